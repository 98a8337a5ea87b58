"""algorithms.interpolation._faces, the per-face machinery of arap and poisson: with area
weights the gradient operator's normal matrix is the cotangent Laplacian (libigl's
cotmatrix, triangles and tetrahedra), and rotation angles are unwrapped across faces."""

from __future__ import annotations

import igl
import numpy as np
import pytest

from algorithms.core.laplacian import cotangent_laplacian
from algorithms.interpolation._faces import (
    face_adjacency,
    face_measures,
    gradient_operator,
    unwrap_rotations,
)
from tests.algorithms.interpolation.interp_meshes import bar, strip3, tet_bar


@pytest.mark.parametrize("kind", ["bar", "strip", "tets"])
def test_area_weighted_gradient_normal_matrix_is_the_cotangent_laplacian(kind: str) -> None:
    v, f = {"bar": bar, "strip": strip3, "tets": tet_bar}[kind](nx=5)
    rng = np.random.default_rng(0)
    v = v + rng.uniform(-0.1, 0.1, v.shape)
    g = gradient_operator(v, f)
    d = v.shape[1]
    lap = (g.T @ (np.repeat(face_measures(v, f), d)[:, None] * g)).toarray()
    np.testing.assert_allclose(lap, -igl.cotmatrix(v, f).toarray(), atol=1e-12)
    if kind != "tets":
        np.testing.assert_allclose(lap, cotangent_laplacian(v, f).toarray(), atol=1e-12)


def test_unwrap_by_hand_on_a_chain() -> None:
    # three faces in a row with angles 3.0, -3.0, -2.9 (a turn past π): unwrapped from the
    # smallest |angle| (face 2: -2.9) the chain becomes -2.9, -3.0, -3.0 - (2π - 6.0)
    f = np.array([[0, 1, 2], [1, 2, 3], [2, 3, 4]])
    w = np.array([[3.0], [-3.0], [-2.9]])
    out = unwrap_rotations(w, face_adjacency(f))
    np.testing.assert_allclose(out.ravel(), [3.0 - 2 * np.pi, -3.0, -2.9])
    # in 3-D: the same about an axis (a vector of length θ, its alternatives θ + 2πk)
    axis = np.array([0.0, 0.6, 0.8])
    out3 = unwrap_rotations(w * axis, face_adjacency(f))
    np.testing.assert_allclose(out3, out * axis, atol=1e-12)
