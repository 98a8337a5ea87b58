"""Tests for algorithms.core.linalg: Procrustes with the reflection fix, polar decomposition,
determinants, numerical rank, homogeneous matrices; single matrices and stacks; the batched
rotations of ARAP's local step."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import orthogonal_procrustes
from scipy.linalg import polar as scipy_polar
from scipy.spatial.transform import Rotation

from algorithms.core import (
    InvalidInputError,
    Procrustes,
    homogeneous,
    linalg,
    numerical_rank,
    polar,
    procrustes,
)
from algorithms.core.linalg import (
    RANK_RTOL,
    RotationFitter,
    batched_polar,
    batched_rotations,
    det,
)

# --- layer 1: by hand ----------------------------------------------------------------------


def test_hand_procrustes_mirror_2d():
    # C = diag(2, -1/2): U V^T = diag(1, -1) is a reflection. The fix negates the singular
    # vector of sigma = 1/2: R = I, D = diag(1, -1), tr(D Sigma) = 2 - 1/2 = 3/2.
    c = np.diag([2.0, -0.5])
    fit = procrustes(c)
    assert isinstance(fit, Procrustes)
    np.testing.assert_allclose(fit.rotation, np.eye(2), atol=1e-15)
    np.testing.assert_allclose(fit.singular_values, [2.0, 0.5])
    np.testing.assert_array_equal(fit.signs, [1.0, -1.0])
    assert fit.trace == pytest.approx(1.5) and not fit.reflection
    kept = procrustes(c, allow_reflection=True)
    np.testing.assert_allclose(kept.rotation, np.diag([1.0, -1.0]), atol=1e-15)
    np.testing.assert_array_equal(kept.signs, [1.0, 1.0])
    assert kept.trace == pytest.approx(2.5) and bool(kept.reflection)


def test_hand_procrustes_quarter_turn():
    # C = R itself (a rotation): the answer is C, all singular values 1.
    r = np.array([[0.0, -1.0], [1.0, 0.0]])
    fit = procrustes(3.0 * r)
    np.testing.assert_allclose(fit.rotation, r, atol=1e-15)
    np.testing.assert_allclose(fit.singular_values, [3.0, 3.0])
    assert fit.trace == pytest.approx(6.0)


def test_hand_polar():
    # A = R S with R the quarter turn and S = diag(2, 1).
    r = np.array([[0.0, -1.0], [1.0, 0.0]])
    rot, stretch = polar(r @ np.diag([2.0, 1.0]))
    np.testing.assert_allclose(rot, r, atol=1e-15)
    np.testing.assert_allclose(stretch, np.diag([2.0, 1.0]), atol=1e-15)


def test_hand_homogeneous_and_det():
    m = homogeneous([[1.0, 2.0], [3.0, 4.0]], [5.0, 6.0])
    np.testing.assert_array_equal(m, [[1, 2, 5], [3, 4, 6], [0, 0, 1]])
    assert det([[1.0, 2.0], [3.0, 4.0]]) == -2.0
    assert det([[2.0, 0.0, 0.0], [0.0, 3.0, 0.0], [0.0, 0.0, 4.0]]) == 24.0
    assert det([[7.0]]) == 7.0


def test_hand_numerical_rank():
    assert numerical_rank([3.0, 1.0, 0.0]) == 2
    assert numerical_rank([3.0, 1.0, 3.0 * RANK_RTOL]) == 2  # at the tolerance: zero
    assert numerical_rank([3.0, 1.0, 4.0 * RANK_RTOL]) == 3
    assert numerical_rank([0.0, 0.0]) == 0
    assert numerical_rank([]) == 0
    assert numerical_rank([1.0, 1e-3], rtol=1e-2) == 1


# --- layer 2: invariants, stacks -------------------------------------------------------------


@pytest.mark.parametrize("d", [2, 3, 5])
def test_procrustes_is_optimal_and_proper(d):
    rng = np.random.default_rng(d)
    for _ in range(50):
        c = rng.standard_normal((d, d))
        fit = procrustes(c)
        r = fit.rotation
        np.testing.assert_allclose(r @ r.T, np.eye(d), atol=1e-12)
        assert np.linalg.det(r) == pytest.approx(1.0)
        assert np.trace(r.T @ c) == pytest.approx(fit.trace, rel=1e-12)
        np.testing.assert_allclose(fit.u @ fit.vt, r, atol=1e-14)
        # the fixed factors still reproduce C with signed singular values
        np.testing.assert_allclose((fit.u * (fit.signs * fit.singular_values)) @ fit.vt, c,
                                   atol=1e-12)
        # no proper rotation nearby does better
        for _ in range(3):
            k = rng.standard_normal((d, d)) * 1e-3
            q = np.linalg.solve(np.eye(d) - (k - k.T), np.eye(d) + (k - k.T))
            assert np.trace((r @ q).T @ c) <= fit.trace + 1e-12


def test_procrustes_stack_equals_loop():
    rng = np.random.default_rng(0)
    cs = rng.standard_normal((4, 6, 3, 3))
    fit = procrustes(cs)
    assert fit.rotation.shape == (4, 6, 3, 3) and fit.reflection.shape == (4, 6)
    assert fit.trace.shape == (4, 6)
    for i in range(4):
        for j in range(6):
            one = procrustes(cs[i, j])
            np.testing.assert_allclose(fit.rotation[i, j], one.rotation, atol=1e-14)
            assert fit.trace[i, j] == pytest.approx(float(one.trace))
    mixed = procrustes(cs, allow_reflection=True)
    dets = np.linalg.det(mixed.rotation)
    np.testing.assert_array_equal(mixed.reflection, dets < 0)
    assert mixed.reflection.any() and not mixed.reflection.all()


def test_polar_stack_and_proper():
    rng = np.random.default_rng(1)
    a = rng.standard_normal((20, 3, 3))
    rot, stretch = polar(a)
    np.testing.assert_allclose(rot @ stretch, a, atol=1e-12)
    np.testing.assert_allclose(stretch, np.swapaxes(stretch, -1, -2), atol=1e-12)
    assert (np.linalg.eigvalsh(stretch) >= -1e-12).all()
    prot, pstretch = polar(a, proper=True)
    np.testing.assert_allclose(prot @ pstretch, a, atol=1e-12)
    np.testing.assert_allclose(np.linalg.det(prot), 1.0, atol=1e-12)
    negative = np.linalg.det(a) < 0
    assert negative.any()
    # where det A < 0 the stretch has exactly one negative eigenvalue
    assert ((np.linalg.eigvalsh(pstretch[negative]) < 0).sum(axis=1) == 1).all()


@pytest.mark.parametrize("d", [1, 2, 3, 4, 6])
def test_det_closed_forms_match_numpy(d):
    m = np.random.default_rng(d).standard_normal((7, d, d))
    np.testing.assert_allclose(det(m), np.linalg.det(m), rtol=1e-12)
    assert float(det(m[0])) == pytest.approx(np.linalg.det(m[0]), rel=1e-12)


def test_homogeneous_stack():
    rng = np.random.default_rng(2)
    lin, t = rng.standard_normal((5, 3, 3)), rng.standard_normal((5, 3))
    m = homogeneous(lin, t)
    assert m.shape == (5, 4, 4)
    x = rng.standard_normal(3)
    np.testing.assert_allclose((m @ np.r_[x, 1.0])[:, :3], lin @ x + t, atol=1e-14)
    np.testing.assert_array_equal(m[:, 3], np.tile([0, 0, 0, 1.0], (5, 1)))


# --- layer 3: scipy --------------------------------------------------------------------------


def test_agrees_with_scipy_orthogonal_procrustes_and_polar():
    rng = np.random.default_rng(3)
    for _ in range(30):
        a, b = rng.standard_normal((10, 4)), rng.standard_normal((10, 4))
        # scipy: R minimising |a R - b|, i.e. maximising tr(R^T a^T b), reflections allowed.
        r_scipy, _ = orthogonal_procrustes(a, b)
        ours = procrustes(a.T @ b, allow_reflection=True)
        np.testing.assert_allclose(ours.rotation, r_scipy, atol=1e-12)
        m = rng.standard_normal((4, 4))
        u, p = scipy_polar(m)
        rot, stretch = polar(m)
        np.testing.assert_allclose(rot, u, atol=1e-12)
        np.testing.assert_allclose(stretch, p, atol=1e-12)


# --- batched rotations (ARAP's local step) and polar decompositions --------------------
# hand cases, known rotations, and agreement with numpy's SVD (via procrustes/polar) on
# hard stacks


def best_by_svd(S):
    """The proper R maximising tr(R S), from numpy's SVD."""
    return procrustes(np.swapaxes(S, -1, -2)).rotation


def trace(R, S):
    return np.einsum("...ij,...ji->...", R, S)


def assert_rotations(R, atol=1e-12):
    d = R.shape[-1]
    np.testing.assert_allclose(R @ np.swapaxes(R, -1, -2), np.broadcast_to(np.eye(d), R.shape),
                               atol=atol)
    np.testing.assert_allclose(np.linalg.det(R), 1.0, atol=atol)


def planar_stack(b, rng):
    """Covariances of flat neighbourhoods (rank 2), as ARAP meets on planar regions."""
    p = rng.standard_normal((b, 6, 3)) * [1, 1, 0]
    q = rng.standard_normal((b, 6, 3))
    return np.einsum("bki,bkj->bij", p, q)


def test_hand_cases_3d():
    # S = Σ e e'ᵀ for e' = R e: the covariance of a rotated frame is C Rᵀ, answer R.
    rz = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])   # 90° about z
    S = np.stack([np.eye(3) @ rz.T,                     # e = unit axes: S = I Rᵀ
                  np.diag([2.0, 1.0, 0.0]) @ rz.T,      # flat ring (rank 2): still determined
                  np.zeros((3, 3)),                     # nothing to fit: identity
                  -np.eye(3)])                          # det S < 0: best proper is a half turn
    R = batched_rotations(S)
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
    R = batched_rotations(S)
    np.testing.assert_allclose(R[0], [[0, -1], [1, 0]], atol=1e-15)
    np.testing.assert_allclose(R[1], np.eye(2), atol=1e-15)
    np.testing.assert_allclose(R[2], np.eye(2), atol=1e-15)


@pytest.mark.parametrize("d", [2, 3])
def test_matches_svd_on_random_stacks(d):
    rng = np.random.default_rng(0)
    S = rng.standard_normal((2000, d, d))
    R = batched_rotations(S)
    assert R.shape == S.shape
    assert_rotations(R)
    np.testing.assert_allclose(R, best_by_svd(S), atol=1e-10)


def test_matches_svd_on_flat_neighbourhoods():
    S = planar_stack(1000, np.random.default_rng(1))
    R = batched_rotations(S)
    assert_rotations(R)
    np.testing.assert_allclose(R, best_by_svd(S), atol=1e-10)


@pytest.mark.parametrize("seed", range(100))
def test_recovers_the_rotation_of_an_arap_neighbourhood(seed):
    # S = Σ w e e'ᵀ with e' = R e: the best rotation is R itself (maximum tr(R S) = Σ w ‖e‖²)
    rng = np.random.default_rng(seed)
    R_true = Rotation.random(rng=rng).as_matrix()
    e = rng.standard_normal((7, 3))
    w = rng.uniform(0.1, 2.0, 7)
    S = np.einsum("k,ki,kj->ij", w, e, e @ R_true.T)
    np.testing.assert_allclose(batched_rotations(S[None])[0], R_true, atol=1e-11)


def test_reflection_fix_flips_the_smallest_direction():
    # S = diag(3, 2, -1): the best proper R is diag(1, 1, 1) with trace 3 + 2 - 1 = 4, not the
    # reflection diag(1, 1, -1) (trace 6, improper)
    S = np.diag([3.0, 2.0, -1.0])[None]
    np.testing.assert_allclose(batched_rotations(S)[0], np.eye(3), atol=1e-15)
    R, P = batched_polar(S, proper=False)
    np.testing.assert_allclose(R[0], np.diag([1.0, 1.0, -1.0]), atol=1e-15)
    np.testing.assert_allclose(P[0], np.diag([3.0, 2.0, 1.0]), atol=1e-15)


def test_never_worse_than_svd_even_where_not_unique():
    rng = np.random.default_rng(5)
    rank1 = np.einsum("bi,bj->bij", rng.standard_normal((200, 3)), rng.standard_normal((200, 3)))
    special = np.stack([np.zeros((3, 3)), np.eye(3), -np.eye(3), np.diag([2.0, 2.0, 0.0]),
                        np.diag([1.0, 1.0, 1.0 - 1e-17])])
    S = np.concatenate([rank1, special])
    R = batched_rotations(S)
    assert_rotations(R)
    assert (trace(R, S) >= trace(best_by_svd(S), S) - 1e-12).all()
    np.testing.assert_array_equal(R[200], np.eye(3))            # S = 0 gives the identity


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
    R = batched_rotations(S)
    ref = best_by_svd(S)
    assert_rotations(R, atol=1e-13)
    # the attained maximum equals the SVD optimum (the rotation itself may differ where the
    # optimum is not unique)
    np.testing.assert_allclose(trace(R, S), trace(ref, S), atol=1e-12)
    if kind in ("gaussian", "flat", "reflected"):
        unique = np.linalg.svd(S, compute_uv=False)
        ok = (unique[:, 1] + unique[:, 2] * np.sign(np.linalg.det(S))) > 1e-6
        np.testing.assert_allclose(R[ok], ref[ok], atol=1e-7)


@pytest.mark.parametrize("d", [2, 3])
def test_fitter_reuses_its_buffers_and_layout(d):
    rng = np.random.default_rng(3)
    S = rng.standard_normal((50, d, d))
    fit = RotationFitter(50, d)
    out = fit(np.ascontiguousarray(np.transpose(S, (1, 0, 2))))
    again = fit(np.ascontiguousarray(np.transpose(S, (1, 0, 2))))
    assert out is again is fit.out
    R = np.transpose(out, (1, 2, 0))                       # out[a, r, b] = R_r[b, a]
    np.testing.assert_allclose(trace(R, S), trace(best_by_svd(S), S), atol=1e-12)
    np.testing.assert_allclose(R, batched_rotations(S), atol=0)



def test_fitter_in_blocks_equals_one_pass(monkeypatch):
    # 5 blocks of 64 and a partial one; the thin (slow path, SVD fallback) and zero
    # matrices sit in later blocks, so every block's slow indices are offsets within it
    rng = np.random.default_rng(8)
    n = 5 * 64 + 37
    u = np.linalg.qr(rng.standard_normal((n, 3, 3)))[0]
    w = np.linalg.qr(rng.standard_normal((n, 3, 3)))[0]
    S = rng.standard_normal((n, 3, 3))
    thin = np.arange(150, n, 7)
    S[thin] = u[thin] @ (np.array([1.0, 1e-3, 0.0])[:, None] * w[thin])
    S[[200, n - 1]] = 0.0
    layout = np.ascontiguousarray(np.transpose(S, (1, 0, 2)))
    whole = RotationFitter(n, 3)(layout).copy()
    monkeypatch.setattr(linalg, "_BLOCK", 64)
    blocked = RotationFitter(n, 3)
    assert blocked._a.shape == (10, 64)                     # buffers for one block only
    out = blocked(layout)
    np.testing.assert_array_equal(out, whole)
    R = np.transpose(out, (1, 2, 0))
    assert_rotations(R, atol=1e-13)
    np.testing.assert_allclose(trace(R, S), trace(best_by_svd(S), S), atol=1e-12)
    np.testing.assert_array_equal(R[[200, n - 1]], np.broadcast_to(np.eye(3), (2, 3, 3)))

def test_empty_stack():
    assert batched_rotations(np.zeros((0, 3, 3))).shape == (0, 3, 3)
    R, P = batched_polar(np.zeros((0, 2, 2)), proper=False)
    assert R.shape == P.shape == (0, 2, 2)


def test_single_matrix_and_leading_dimensions():
    rng = np.random.default_rng(2)
    S = rng.standard_normal((4, 5, 3, 3))
    R = batched_rotations(S)
    np.testing.assert_allclose(R, best_by_svd(S), atol=1e-10)
    np.testing.assert_allclose(batched_rotations(S[0, 0]), R[0, 0], atol=1e-14)


def test_other_dimensions_fall_back_to_svd():
    rng = np.random.default_rng(3)
    S = rng.standard_normal((50, 4, 4))
    np.testing.assert_allclose(batched_rotations(S), best_by_svd(S), atol=1e-12)
    assert batched_rotations(np.full((3, 1, 1), -2.0)).ravel().tolist() == [1.0, 1.0, 1.0]


@pytest.mark.parametrize("d", [2, 3])
@pytest.mark.parametrize("proper", [True, False])
def test_polar_matches_svd_polar(d, proper):
    rng = np.random.default_rng(4)
    A = rng.standard_normal((500, d, d))
    R, P = batched_polar(A, proper=proper)
    R_ref, P_ref = polar(A, proper=proper)
    np.testing.assert_allclose(R, R_ref, atol=1e-10)
    np.testing.assert_allclose(P, P_ref, atol=1e-10)
    np.testing.assert_allclose(R @ P, A, atol=1e-12)
    np.testing.assert_allclose(P, np.swapaxes(P, -1, -2), atol=0)
    dets = np.linalg.det(R)
    if proper:
        np.testing.assert_allclose(dets, 1.0, atol=1e-12)
    else:
        np.testing.assert_allclose(dets, np.sign(np.linalg.det(A)), atol=1e-12)
        assert (np.linalg.eigvalsh(P) >= -1e-12).all()


def test_rejects_non_square_stacks():
    with pytest.raises(InvalidInputError, match=r"`S` to be a stack of square matrices "
                       r"\(\.\.\., d, d\), got shape \(5, 3, 2\)\.") as info:
        batched_rotations(np.zeros((5, 3, 2)))
    assert info.value.field == "S"
    with pytest.raises(InvalidInputError, match=r"`A` to be a stack of square matrices"):
        batched_polar(np.zeros(3))
    with pytest.raises(InvalidInputError, match=r"dimension `d` to be 2 or 3, got 4\.") as info:
        RotationFitter(10, 4)
    assert info.value.field == "d"
