"""Tests for deformation.laplacian_editing: the rest shape with the handles at rest,
similarities reproduced, agreement with a dense brute-force implementation of Sorkine et
al.'s least squares (per-vertex fits by numpy.linalg.lstsq in a loop)."""

from __future__ import annotations

import numpy as np
import pytest

from algorithms.core import DegenerateInputError, InvalidInputError
from algorithms.core.mesh import edges
from algorithms.deformation import LaplacianEditingResult, laplacian_editing
from tests.algorithms.deformation.deformation_meshes import blob, bumpy_sheet, grid


def brute_force(v, f, idx, pos):
    """Dense reference: residual r(x) = T_i(x) δ_i - L(x)_i with T_i fitted by lstsq per
    vertex, uniform row-normalised Laplacian; r is linear in x, so its Jacobian is read off
    column by column, then the constrained least squares is solved densely."""
    n, d = v.shape
    nbrs = [[] for _ in range(n)]
    for i, j in edges(f):
        nbrs[i].append(j)
        nbrs[j].append(i)

    def lap(x):
        return np.array([x[i] - x[nbrs[i]].mean(axis=0) for i in range(n)])

    delta = lap(v)

    def block(p):
        if d == 2:
            return np.array([[p[0], -p[1], 1, 0], [p[1], p[0], 0, 1]])
        x, y, z = p
        return np.array([[x, 0, z, -y, 1, 0, 0], [y, -z, 0, x, 0, 1, 0],
                         [z, y, -x, 0, 0, 0, 1]])

    def residual(xflat):
        x = xflat.reshape(n, d)
        lx = lap(x)
        out = []
        for i in range(n):
            ring = [i] + nbrs[i]
            A = np.vstack([block(v[j]) for j in ring])
            theta = np.linalg.lstsq(A, x[ring].ravel(), rcond=None)[0]
            D = block(delta[i])
            D[:, -d:] = 0
            out.append(D @ theta - lx[i])
        return np.concatenate(out)

    r0 = residual(np.zeros(n * d))
    J = np.column_stack([residual(e) - r0 for e in np.eye(n * d)])
    pinned = (np.asarray(idx)[:, None] * d + np.arange(d)).ravel()
    free = np.setdiff1d(np.arange(n * d), pinned)
    c = np.asarray(pos, float).ravel()
    xf = np.linalg.lstsq(J[:, free], -(J[:, pinned] @ c) - r0, rcond=None)[0]
    x = np.empty(n * d)
    x[free], x[pinned] = xf, c
    return x.reshape(n, d)


@pytest.mark.parametrize("weights", ["uniform", "cotangent"])
def test_handles_at_rest_give_the_rest_shape(weights):
    v, f = blob(2)
    idx = np.array([0, 9, 33, 100])
    res = laplacian_editing((v, f), {"indices": idx, "positions": v[idx]}, weights=weights)
    assert isinstance(res, LaplacianEditingResult)
    np.testing.assert_allclose(res.mesh.vertices, v, atol=1e-9)
    assert res.energy[0] < 1e-18 and res.handle_residual == 0.0


@pytest.mark.parametrize("seed", range(5))
def test_2d_similarity_is_reproduced_exactly(seed):
    # in the plane the linearised similarity [[s, -w], [w, s]] is every rotation and scale
    rng = np.random.default_rng(seed)
    v, f = grid(6, 5, jitter=0.2, seed=seed)
    angle, scale, shift = rng.uniform(-3, 3), rng.uniform(0.5, 2), rng.normal(size=2)
    R = scale * np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
    idx = rng.choice(len(v), size=2, replace=False)
    res = laplacian_editing((v, f), {"indices": idx, "positions": v[idx] @ R.T + shift})
    np.testing.assert_allclose(res.mesh.vertices, v @ R.T + shift, atol=1e-9)
    assert res.energy[0] < 1e-18


def test_3d_scaling_is_reproduced_exactly():
    v, f = bumpy_sheet()
    idx = np.array([0, 8, 62])
    target = 1.7 * v + [0.5, -1.0, 2.0]
    res = laplacian_editing((v, f), {"indices": idx, "positions": target[idx]})
    np.testing.assert_allclose(res.mesh.vertices, target, atol=1e-9)


@pytest.mark.parametrize("mesh", ["2d", "3d"])
def test_matches_brute_force(mesh):
    rng = np.random.default_rng(7)
    if mesh == "2d":
        v, f = grid(5, 4, jitter=0.2)
        idx = np.array([0, 4, 19])
    else:
        v, f = bumpy_sheet(5, 4)
        idx = np.array([0, 4, 15, 19])
    pos = v[idx] + rng.normal(scale=0.5, size=(len(idx), v.shape[1]))
    ref = brute_force(v, f, idx, pos)
    res = laplacian_editing((v, f), {"indices": idx, "positions": pos})
    np.testing.assert_allclose(res.mesh.vertices, ref, atol=1e-9)
    # rotating the handles of a 3-D sheet keeps the details better than plain Laplacian
    # deformation would: the energy is the residual of that very least squares
    assert res.energy[0] >= 0


def test_errors():
    v, f = bumpy_sheet(5, 4)
    with pytest.raises(DegenerateInputError, match="three handles not on one line") as info:
        laplacian_editing((v, f), {"indices": [0, 1], "positions": v[[0, 1]]})
    assert info.value.field == "handles"
    v2, f2 = grid(3, 3)
    with pytest.raises(DegenerateInputError, match="two distinct handles"):
        laplacian_editing((v2, f2), {"indices": [4], "positions": v2[[4]]})
    with pytest.raises(InvalidInputError, match="'uniform'") as info:
        laplacian_editing((v2, f2), {"indices": [0, 8], "positions": v2[[0, 8]]},
                          weights="tangent")
    assert info.value.field == "weights"
    two = np.vstack([v2, v2 + 10])
    with pytest.raises(DegenerateInputError, match="component of 9 vertices") as info:
        laplacian_editing((two, np.vstack([f2, f2 + 9])),
                          {"indices": [0, 8], "positions": v2[[0, 8]]})
    assert info.value.field == "handles"


def test_ring_pairs_do_not_overflow_on_large_meshes():
    # (i, j) keys are i * n + j: with int32 sparse indices that overflows once n > 46,340
    import scipy.sparse as sp

    from algorithms.deformation.laplacian_editing import _ring_pairs

    n = 60_000
    indptr = np.zeros(n + 1, dtype=np.int32)
    indptr[2:] = 1
    indptr[-1] = 2
    L = sp.csr_array((np.ones(2), np.array([59_999, 1], dtype=np.int32), indptr), shape=(n, n))
    assert sp.coo_array(L).row.dtype == np.int32      # what the sparse code hands over
    ri, rj = _ring_pairs(n, L)
    assert ri.shape[0] == n + 2 and np.all(np.diff(ri) >= 0)
    assert (59_999, 1) in set(zip(ri.tolist(), rj.tolist()))
