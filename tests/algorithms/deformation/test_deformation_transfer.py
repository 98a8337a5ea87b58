"""Tests for deformation.deformation_transfer: hand cases (maps carried over exactly), the
identity, agreement with a dense brute-force implementation of Sumner & Popović's least
squares (a loop over faces, numpy.linalg.lstsq)."""

from __future__ import annotations

import numpy as np
import pytest

from algorithms.core import DegenerateInputError, InvalidInputError
from algorithms.deformation import DeformationTransferResult, deformation_transfer
from tests.algorithms.deformation.deformation_meshes import blob, bumpy_sheet, grid, random_rotation


def frame(p, tri):
    a, b, c = p[tri]
    e1, e2 = b - a, c - a
    if p.shape[1] == 2:
        return np.column_stack([e1, e2])
    nrm = np.cross(e1, e2)
    return np.column_stack([e1, e2, nrm / np.sqrt(np.linalg.norm(nrm))])


def brute_force(tgt, f, src, dst, idx, pos):
    n, d = tgt.shape
    m = len(f)
    size = n + (m if d == 3 else 0)
    rows, rhs = [], []
    for c, tri in enumerate(f):
        Q = frame(dst, tri) @ np.linalg.inv(frame(src, tri))
        W = np.linalg.inv(frame(tgt, tri))
        nodes = list(tri) + ([n + c] if d == 3 else [])
        for col in range(d):
            row = np.zeros(size)
            for k in range(d):       # column k of the frame: node k+1 minus node 0
                row[nodes[k + 1]] += W[k, col]
                row[nodes[0]] -= W[k, col]
            rows.append(row)
            rhs.append(Q[:, col])
    A, Y = np.array(rows), np.array(rhs)          # T[r, col] = A[c*d+col] @ x[:, r]
    free = np.setdiff1d(np.arange(size), idx)
    xf = np.linalg.lstsq(A[:, free], Y - A[:, idx] @ pos, rcond=None)[0]
    x = np.empty((size, d))
    x[free], x[idx] = xf, pos
    return x[:n]


def test_hand_2d_shear_carries_over():
    src = np.array([[0, 0], [1, 0], [0, 1], [1, 1]], float)
    f = np.array([[0, 1, 3], [0, 3, 2]])
    tgt = np.array([[0, 0], [3, 0], [0, 2], [3, 2]], float)
    shear = np.array([[1.0, 0.5], [0.0, 1.0]])
    res = deformation_transfer((tgt, f), {"indices": [0], "positions": [[1.0, 1.0]]},
                               source=src, source_deformed=src @ shear.T)
    assert isinstance(res, DeformationTransferResult)
    np.testing.assert_allclose(res.mesh.vertices, tgt @ shear.T + 1.0, atol=1e-12)
    assert res.energy[0] < 1e-24


@pytest.mark.parametrize("seed", range(5))
def test_3d_similarity_carries_over(seed):
    rng = np.random.default_rng(seed)
    src, f = bumpy_sheet(seed=seed)
    tgt = src * [1.0, 1.3, 0.7] + rng.normal(scale=0.05, size=src.shape)   # another shape
    R, s, t = random_rotation(rng), rng.uniform(0.5, 2.0), rng.normal(size=3)
    res = deformation_transfer((tgt, f), {"indices": [5], "positions": [s * R @ tgt[5] + t]},
                               source=src, source_deformed=s * src @ R.T + t)
    np.testing.assert_allclose(res.mesh.vertices, s * tgt @ R.T + t, atol=1e-9)


def test_identity_leaves_the_target_alone():
    src, f = blob(2)
    tgt = src * 1.1
    res = deformation_transfer((tgt, f), {"indices": [0], "positions": tgt[[0]]},
                               source=src, source_deformed=src)
    np.testing.assert_allclose(res.mesh.vertices, tgt, atol=1e-10)
    assert res.handle_residual == 0.0


@pytest.mark.parametrize("dim", [2, 3])
def test_matches_brute_force(dim):
    rng = np.random.default_rng(dim)
    if dim == 2:
        src, f = grid(5, 4, jitter=0.2)
        tgt = src * [1.5, 1.0] + rng.normal(scale=0.05, size=src.shape)
    else:
        src, f = bumpy_sheet(6, 5)
        tgt = src + rng.normal(scale=0.05, size=src.shape)
    dst = src + rng.normal(scale=0.2, size=src.shape)            # a non-rigid deformation
    idx = np.array([0, 3])
    pos = tgt[idx] + rng.normal(scale=0.1, size=(2, dim))
    ref = brute_force(tgt, f, src, dst, idx, pos)
    res = deformation_transfer((tgt, f), {"indices": idx, "positions": pos}, source=src,
                               source_deformed=dst)
    np.testing.assert_allclose(res.mesh.vertices, ref, atol=1e-9)


def test_errors():
    src, f = grid(3, 3)
    with pytest.raises(InvalidInputError, match="one row per vertex") as info:
        deformation_transfer((src, f), {"indices": [0], "positions": [[0, 0]]},
                             source=src[:5], source_deformed=src)
    assert info.value.field == "source"
    with pytest.raises(InvalidInputError, match=r"\(n, 2\)") as info:
        deformation_transfer((src, f), {"indices": [0], "positions": [[0, 0]]},
                             source=src, source_deformed=np.column_stack([src, src[:, 0]]))
    assert info.value.field == "source_deformed"
    flat = src.copy()
    flat[:, 1] = 0.0                                   # every source face collapsed
    with pytest.raises(DegenerateInputError, match="degenerate face") as info:
        deformation_transfer((src, f), {"indices": [0], "positions": [[0, 0]]},
                             source=flat, source_deformed=src)
    assert info.value.field == "source"
    two_v, two_f = np.vstack([src, src + 5]), np.vstack([f, f + 9])
    with pytest.raises(DegenerateInputError, match="component of 9 vertices") as info:
        deformation_transfer((two_v, two_f), {"indices": [0], "positions": [[0, 0]]},
                             source=two_v, source_deformed=two_v)
    assert info.value.field == "handles"
