"""Tests for deformation.biharmonic: hand cases, invariants, agreement with igl.harmonic
(k = 2 and 3) on the handle displacements."""

from __future__ import annotations

import igl
import numpy as np
import pytest

from algorithms.core import DegenerateInputError, InvalidInputError
from algorithms.deformation import BiharmonicResult, biharmonic, harmonic
from tests.algorithms.deformation.deformation_meshes import blob, bumpy_sheet, grid, tube


def two_rings(v, nx, ny):
    """Boundary vertices and the ring inside them."""
    x, y = v[:, 0], v[:, 1]
    return np.flatnonzero((x < 1.5) | (x > nx - 2.5) | (y < 1.5) | (y > ny - 2.5))


@pytest.mark.parametrize("seed", range(5))
def test_affine_data_on_two_rings_is_reproduced_inside(seed):
    # L p = 0 at interior vertices of a planar mesh for affine p (linear precision); with the
    # two outer rings pinned, every free vertex's L M⁻¹ L row sees interior rows only, so an
    # affine map of the two rings extends exactly.
    rng = np.random.default_rng(seed)
    v, f = grid(9, 8, jitter=0.25, seed=seed)
    A, t = rng.normal(size=(2, 2)), rng.normal(size=2)
    idx = two_rings(grid(9, 8)[0], 9, 8)          # pick rings on the unjittered layout
    res = biharmonic((v, f), {"indices": idx, "positions": v[idx] @ A.T + t})
    assert isinstance(res, BiharmonicResult)
    np.testing.assert_allclose(res.mesh.vertices, v @ A.T + t, atol=1e-9)


def test_smoother_than_harmonic_at_a_point_handle():
    # A single pulled vertex: harmonic makes a spike (the displacement's Laplacian is
    # concentrated there), biharmonic a smooth bump with a smaller maximum slope.
    v, f = grid(11, 11)
    v3 = np.column_stack([v, np.zeros(len(v))])
    rim = np.flatnonzero((v[:, 0] == 0) | (v[:, 0] == 10) | (v[:, 1] == 0) | (v[:, 1] == 10))
    idx = np.concatenate([rim, [60]])
    pos = v3[idx].copy()
    pos[-1, 2] = 1.0
    h = harmonic((v3, f), {"indices": idx, "positions": pos}).mesh.vertices[:, 2]
    b = biharmonic((v3, f), {"indices": idx, "positions": pos}).mesh.vertices[:, 2]
    neighbours = [49, 59, 61, 71]
    assert np.all(b[neighbours] > h[neighbours])    # the bump is rounder at its top
    assert np.all(b[neighbours] < 1.0)


def test_rest_and_translation():
    v, f = bumpy_sheet()
    idx = np.array([0, 10, 40, 62])
    rest = biharmonic((v, f), {"indices": idx, "positions": v[idx]})
    np.testing.assert_array_equal(rest.mesh.vertices, v)
    assert rest.energy == [0.0] and rest.handle_residual == 0.0
    moved = biharmonic((v, f), {"indices": idx, "positions": v[idx] + [1.0, -2.0, 0.5]},
                       order=3)
    np.testing.assert_allclose(moved.mesh.vertices, v + [1.0, -2.0, 0.5], atol=1e-9)


@pytest.mark.parametrize("order", [2, 3])
@pytest.mark.parametrize("mesh", ["blob", "tube", "sheet"])
def test_matches_igl_harmonic(order, mesh):
    v, f = {"blob": lambda: blob(3), "tube": tube, "sheet": bumpy_sheet}[mesh]()
    rng = np.random.default_rng(1)
    top = v[:, 2] > np.quantile(v[:, 2], 0.85)
    bottom = v[:, 2] < np.quantile(v[:, 2], 0.15)
    idx = np.flatnonzero(top | bottom)
    pos = v[idx] + top[idx, None] * rng.normal(size=3)
    ref = v + igl.harmonic(v, f, idx, pos - v[idx], order)
    res = biharmonic((v, f), {"indices": idx, "positions": pos}, order=order)
    np.testing.assert_allclose(res.mesh.vertices, ref, atol=1e-8, rtol=0)
    np.testing.assert_array_equal(res.mesh.vertices[idx], pos)
    # the reported energy is uᵀ Q u with libigl's own operators
    L = -igl.cotmatrix(v, f)
    minv = 1.0 / igl.massmatrix(v, f, igl.MASSMATRIX_TYPE_VORONOI).diagonal()
    u = ref - v
    Qu = L @ u
    for _ in range(order - 1):
        Qu = L @ (minv[:, None] * Qu)
    assert res.energy[0] == pytest.approx(float(np.sum(u * Qu)), rel=1e-6)


def test_unused_vertices_stay_put():
    v, f = grid(5, 5)
    v = np.vstack([v, [[9.0, 9.0]]])
    res = biharmonic((v, f), {"indices": [0, 4, 20, 24], "positions": v[[0, 4, 20, 24]] * 2})
    np.testing.assert_array_equal(res.mesh.vertices[-1], [9.0, 9.0])
    assert np.all(np.isfinite(res.mesh.vertices))


def test_errors():
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [5, 0, 0], [6, 0, 0], [5, 1, 0]], float)
    f = np.array([[0, 1, 2], [3, 4, 5]])
    with pytest.raises(DegenerateInputError, match="component of 3 vertices") as info:
        biharmonic((v, f), {"indices": [4], "positions": [[0, 0, 1]]})
    assert info.value.field == "handles"
    with pytest.raises(InvalidInputError, match="order") as info:
        biharmonic((v, f), {"indices": [1, 3], "positions": v[[1, 3]]}, order=1)
    assert info.value.field == "order"
    with pytest.raises(InvalidInputError, match="non-negative") as info:
        biharmonic((v, [[0, 1, 2], [3, 4, -1]]), {"indices": [1, 3], "positions": v[[1, 3]]})
    assert info.value.field == "mesh.faces"
