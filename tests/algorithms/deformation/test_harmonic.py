"""Tests for deformation.harmonic: hand cases (linear precision on planar meshes), invariants,
agreement with igl.harmonic (k = 1) on the handle displacements."""

from __future__ import annotations

import igl
import numpy as np
import pytest

from algorithms.core import DegenerateInputError, InvalidInputError
from algorithms.deformation import HarmonicResult, harmonic, laplacian
from tests.algorithms.deformation.deformation_meshes import blob, bumpy_sheet, grid, tube


def boundary(v, nx, ny):
    return np.flatnonzero((v[:, 0] == 0) | (v[:, 0] == nx - 1) | (v[:, 1] == 0)
                          | (v[:, 1] == ny - 1))


def test_hand_strip_moves_half_way():
    # 3 × 2 grid, left column fixed, right column lifted by 1: by symmetry of the cotangent
    # weights on right triangles (diagonals weigh 0) the middle column rises by 1/2.
    v, f = grid(3, 2)
    res = harmonic((v, f), {"indices": [0, 3, 2, 5], "positions": [[0, 0], [0, 1], [2, 1],
                                                                    [2, 2]]})
    assert isinstance(res, HarmonicResult)
    np.testing.assert_allclose(res.mesh.vertices[[1, 4]], [[1, 0.5], [1, 1.5]], atol=1e-14)
    # energy = Σ_c u_cᵀ L u_c with L = -igl.cotmatrix
    u = res.mesh.vertices - v
    L = -igl.cotmatrix(v, f)
    assert res.energy[0] == pytest.approx(float(np.sum(u * (L @ u))), rel=1e-14)


@pytest.mark.parametrize("seed", range(5))
def test_affine_boundary_data_is_reproduced_inside(seed):
    # cotangent weights have linear precision on planar meshes: an affine map on the
    # boundary extends to the same affine map inside, whatever the (valid) triangulation
    rng = np.random.default_rng(seed)
    v, f = grid(7, 6, jitter=0.3, seed=seed)
    A, t = rng.normal(size=(2, 2)), rng.normal(size=2)
    idx = boundary(v, 7, 6)
    res = harmonic((v, f), {"indices": idx, "positions": v[idx] @ A.T + t})
    np.testing.assert_allclose(res.mesh.vertices, v @ A.T + t, atol=1e-10)


def test_rest_and_translation():
    v, f = bumpy_sheet()
    idx = np.array([0, 10, 40, 62])
    rest = harmonic((v, f), {"indices": idx, "positions": v[idx]})
    np.testing.assert_array_equal(rest.mesh.vertices, v)
    assert rest.energy == [0.0] and rest.handle_residual == 0.0
    moved = harmonic((v, f), {"indices": idx, "positions": v[idx] + [1.0, -2.0, 0.5]})
    np.testing.assert_allclose(moved.mesh.vertices, v + [1.0, -2.0, 0.5], atol=1e-12)
    assert abs(moved.energy[0]) < 1e-10


def test_same_as_laplacian_with_cotangent_weights():
    v, f = tube()
    idx = np.flatnonzero((v[:, 2] == 0) | (v[:, 2] == 5.0))
    pos = v[idx] + np.where(v[idx, 2:3] > 0, [[1.0, 0.0, 0.5]], [[0.0, 0.0, 0.0]])
    a = harmonic((v, f), {"indices": idx, "positions": pos})
    b = laplacian((v, f), {"indices": idx, "positions": pos}, weights="cotangent")
    np.testing.assert_allclose(a.mesh.vertices, b.mesh.vertices, atol=1e-10)
    assert a.energy[0] == pytest.approx(b.energy[0], rel=1e-9)


@pytest.mark.parametrize("mesh", ["blob", "tube", "sheet"])
def test_matches_igl_harmonic(mesh):
    v, f = {"blob": lambda: blob(3), "tube": tube, "sheet": bumpy_sheet}[mesh]()
    rng = np.random.default_rng(0)
    top = v[:, 2] > np.quantile(v[:, 2], 0.9)
    bottom = v[:, 2] < np.quantile(v[:, 2], 0.1)
    idx = np.flatnonzero(top | bottom)
    pos = v[idx] + top[idx, None] * rng.normal(size=3)
    ref = v + igl.harmonic(v, f, idx, pos - v[idx], 1)
    res = harmonic((v, f), {"indices": idx, "positions": pos})
    np.testing.assert_allclose(res.mesh.vertices, ref, atol=1e-8, rtol=0)
    np.testing.assert_array_equal(res.mesh.vertices[idx], pos)


def test_errors():
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [5, 0, 0], [6, 0, 0], [5, 1, 0]], float)
    f = np.array([[0, 1, 2], [3, 4, 5]])
    with pytest.raises(DegenerateInputError, match="component of 3 vertices") as info:
        harmonic((v, f), {"indices": [1], "positions": [[0, 0, 1]]})
    assert info.value.field == "handles"
    with pytest.raises(InvalidInputError, match="below 6, got 7") as info:
        harmonic((v, [[0, 1, 2], [3, 4, 7]]), {"indices": [1, 3], "positions": v[[1, 3]]})
    assert info.value.field == "mesh.faces"
    with pytest.raises(DegenerateInputError, match="degenerate") as info:
        harmonic((np.vstack([v, [[7, 0, 0]]]), [[0, 1, 2], [3, 4, 6]]),   # 3, 4, 6 on a line
                 {"indices": [1, 3], "positions": v[[1, 3]]})
    assert info.value.field == "mesh.faces"
    with pytest.raises(InvalidInputError, match="keys 'indices' and 'positions'") as info:
        harmonic((v, f), {"indices": [1, 3]})
    assert info.value.field == "handles"
