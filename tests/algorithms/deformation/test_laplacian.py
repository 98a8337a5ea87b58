"""Tests for deformation.laplacian (Laplacian-preserving deformation): the rest shape with the
handles at rest, hand cases, agreement with igl.min_quad_with_fixed on -igl.cotmatrix."""

from __future__ import annotations

import igl
import numpy as np
import pytest
import scipy.sparse as sp

from algorithms.core import DegenerateInputError, InvalidInputError
from algorithms.core.laplacian import mesh_laplacian
from algorithms.deformation import LaplacianResult, laplacian
from tests.algorithms.deformation.deformation_meshes import blob, bumpy_sheet, grid


@pytest.mark.parametrize("weights", ["cotangent", "uniform", "tangent"])
@pytest.mark.parametrize("mesh", ["blob", "sheet"])
def test_handles_at_rest_give_the_rest_shape(weights, mesh):
    v, f = blob(2) if mesh == "blob" else bumpy_sheet()
    idx = np.array([0, 7, 30])
    res = laplacian((v, f), {"indices": idx, "positions": v[idx]}, weights=weights)
    assert isinstance(res, LaplacianResult)
    np.testing.assert_allclose(res.mesh.vertices, v, atol=1e-12)
    assert abs(res.energy[0]) < 1e-20 and res.handle_residual == 0.0


def test_hand_path_keeps_its_edge_vectors():
    # a strip of 3 × 2 vertices, uniform weights: translate the left column only... the
    # right column (free) follows rigidly because every edge vector is kept.
    v, f = grid(3, 2)
    res = laplacian((v, f), {"indices": [0, 3], "positions": [[1.0, 1.0], [1.0, 2.0]]},
                    weights="uniform")
    np.testing.assert_allclose(res.mesh.vertices, v + [1.0, 1.0], atol=1e-12)
    # pulling one end apart stretches edges: energy = Σ w |Δ(edge)|² by hand
    # two vertices of a single triangle pinned 1 apart more than at rest; the third follows
    tri = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    res = laplacian((tri, [[0, 1, 2]]), {"indices": [0, 1], "positions": [[0, 0], [2, 0]]},
                    weights="uniform")
    # free vertex 2 minimises |p2 - (0,1)|² + |p2 - (2,0) - (-1,1)|² -> p2 = (0.5, 1)
    np.testing.assert_allclose(res.mesh.vertices[2], [0.5, 1.0], atol=1e-14)
    # Δe01 = (1,0): 1; Δe02 = (0.5, 0): 0.25; Δe12 = (-0.5, 0): 0.25
    assert res.energy[0] == pytest.approx(1.5, abs=1e-14)


@pytest.mark.parametrize("weights", ["cotangent", "uniform"])
def test_matches_igl_min_quad_with_fixed(weights):
    v, f = blob(3)
    rng = np.random.default_rng(4)
    idx = np.flatnonzero((v[:, 2] > 1.3) | (v[:, 2] < -1.3))
    pos = v[idx] + (v[idx, 2:3] > 0) * rng.normal(size=3)
    if weights == "cotangent":
        L = -igl.cotmatrix(v, f)
    else:
        A = igl.adjacency_matrix(f).astype(float)
        L = sp.csc_matrix(np.diag(np.asarray(A.sum(axis=1)).ravel()) - A.toarray())
    # min ½ xᵀ L x - xᵀ (L v)  s.t. x[idx] = pos
    ref = igl.min_quad_with_fixed(L.tocsc(), -(L @ v), idx, pos)
    res = laplacian((v, f), {"indices": idx, "positions": pos}, weights=weights)
    np.testing.assert_allclose(res.mesh.vertices, ref, atol=1e-9, rtol=0)


def test_energy_is_the_weighted_edge_change():
    v, f = bumpy_sheet()
    idx = np.array([0, 8, 54, 62])
    pos = v[idx] + [[0, 0, 0], [0, 0, 1], [0, 0, 0], [1, 1, 1]]
    res = laplacian((v, f), {"indices": idx, "positions": pos}, weights="tangent")
    W = -mesh_laplacian(v, f, kind="tangent").tocoo()
    u = res.mesh.vertices - v
    keep = W.row < W.col
    i, j, w = W.row[keep], W.col[keep], W.data[keep]
    by_hand = float(np.sum(w * np.sum((u[i] - u[j]) ** 2, axis=1)))
    assert res.energy[0] == pytest.approx(by_hand, rel=1e-10)


def test_errors():
    v = np.array([[0, 0], [1, 0], [0, 1], [5, 0], [6, 0], [5, 1]], float)
    f = np.array([[0, 1, 2], [3, 4, 5]])
    with pytest.raises(DegenerateInputError, match="component of 3 vertices") as info:
        laplacian((v, f), {"indices": [2], "positions": [[0, 1]]})
    assert info.value.field == "handles"
    with pytest.raises(InvalidInputError, match="'cotangent'") as info:
        laplacian((v, f), {"indices": [2, 3], "positions": v[[2, 3]]}, weights="mean")
    assert info.value.field == "weights"
    with pytest.raises(InvalidInputError, match="three distinct") as info:
        laplacian((v, [[0, 1, 1], [3, 4, 5]]), {"indices": [2, 3], "positions": v[[2, 3]]})
    assert info.value.field == "mesh.faces"
