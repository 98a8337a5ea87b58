"""Tests for the ARAP local step (batched best rotations): hand cases, and agreement with the
SVD solution (core.linalg.procrustes, reflection fixed) on hard stacks."""

from __future__ import annotations

import numpy as np
import pytest

from algorithms.core.linalg import procrustes
from algorithms.deformation._rotations import RotationFitter, best_rotations


def svd_best(S: np.ndarray) -> np.ndarray:
    """argmax over proper rotations of tr(R S) = tr(Rᵀ Sᵀ): procrustes of Sᵀ."""
    return procrustes(np.swapaxes(S, -1, -2)).rotation


def trace(R: np.ndarray, S: np.ndarray) -> np.ndarray:
    return np.einsum("nij,nji->n", R, S)


def test_hand_cases_3d():
    # S = Σ e e'ᵀ for e' = R e: the covariance of a rotated frame is C Rᵀ, answer R.
    rz = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])   # 90° about z
    S = np.stack([np.eye(3) @ rz.T,                     # e = unit axes: S = I Rᵀ
                  np.diag([2.0, 1.0, 0.0]) @ rz.T,      # flat ring (rank 2): still determined
                  np.zeros((3, 3)),                     # nothing to fit: identity
                  -np.eye(3)])                          # det S < 0: best proper is a half turn
    R = best_rotations(S)
    np.testing.assert_allclose(R[0], rz, atol=1e-14)
    np.testing.assert_allclose(R[1], rz, atol=1e-14)
    np.testing.assert_allclose(R[2], np.eye(3), atol=1e-15)
    # max tr(-R) over rotations is 1 (a half turn: eigenvalues 1, -1, -1)
    assert trace(R[3:], S[3:])[0] == pytest.approx(1.0, abs=1e-14)
    np.testing.assert_allclose(np.linalg.det(R), 1.0, atol=1e-14)


def test_hand_cases_2d():
    # tr(R S) = cos θ (S00 + S11) + sin θ (S01 - S10): θ = atan2(S01 - S10, S00 + S11)
    S = np.array([[[0.0, 1.0], [-1.0, 0.0]],   # θ = 90°
                  [[1.0, 0.0], [0.0, 1.0]],    # θ = 0
                  [[0.0, 0.0], [0.0, 0.0]]])   # anything: identity
    R = best_rotations(S)
    np.testing.assert_allclose(R[0], [[0, -1], [1, 0]], atol=1e-15)
    np.testing.assert_allclose(R[1], np.eye(2), atol=1e-15)
    np.testing.assert_allclose(R[2], np.eye(2), atol=1e-15)


@pytest.mark.parametrize("seed", range(5))
@pytest.mark.parametrize("kind", ["gaussian", "flat", "thin", "reflected", "near_tie"])
def test_matches_svd_on_hard_stacks(seed, kind):
    rng = np.random.default_rng(seed)
    n = 400
    S = rng.standard_normal((n, 3, 3))
    u = np.linalg.qr(rng.standard_normal((n, 3, 3)))[0]
    w = np.linalg.qr(rng.standard_normal((n, 3, 3)))[0]
    if kind == "flat":            # rank 2, as on a planar one-ring
        S = u @ (np.array([1.0, 0.7, 0.0])[:, None] * w)
    elif kind == "thin":          # rank 1-ish: the slow path and the SVD fallback
        S = u @ (np.array([1.0, 1e-3, 0.0])[:, None] * w)
    elif kind == "reflected":     # det S < 0 everywhere
        S = S * np.sign(np.linalg.det(S))[:, None, None] * -1.0
    elif kind == "near_tie":      # det < 0 with σ2 ≈ σ3: nearly undetermined best rotation
        S = u @ (np.array([1.0, 0.5, -0.5 + 1e-9])[:, None] * w)
    R = best_rotations(S)
    ref = svd_best(S)
    np.testing.assert_allclose(np.swapaxes(R, 1, 2) @ R, np.broadcast_to(np.eye(3), R.shape),
                               atol=1e-13)
    np.testing.assert_allclose(np.linalg.det(R), 1.0, atol=1e-13)
    # the attained maximum equals the SVD optimum (the rotation itself may differ where the
    # optimum is not unique)
    np.testing.assert_allclose(trace(R, S), trace(ref, S), atol=1e-12)
    if kind in ("gaussian", "flat", "reflected"):
        unique = np.linalg.svd(S, compute_uv=False)
        ok = (unique[:, 1] + unique[:, 2] * np.sign(np.linalg.det(S))) > 1e-6
        np.testing.assert_allclose(R[ok], ref[ok], atol=1e-7)


def test_fitter_reuses_its_buffers_and_layout():
    rng = np.random.default_rng(3)
    S = rng.standard_normal((50, 3, 3))
    fit = RotationFitter(50, 3)
    out = fit(np.ascontiguousarray(np.transpose(S, (1, 0, 2))))
    again = fit(np.ascontiguousarray(np.transpose(S, (1, 0, 2))))
    assert out is again is fit.out
    R = np.transpose(out, (1, 2, 0))                       # out[a, r, b] = R_r[b, a]
    np.testing.assert_allclose(trace(R, S), trace(svd_best(S), S), atol=1e-12)
    np.testing.assert_allclose(R, best_rotations(S), atol=0)
