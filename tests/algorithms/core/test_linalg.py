"""Tests for algorithms.core.linalg: Procrustes with the reflection fix, polar decomposition,
determinants, numerical rank, homogeneous matrices; single matrices and stacks."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import orthogonal_procrustes
from scipy.linalg import polar as scipy_polar

from algorithms.core import Procrustes, homogeneous, numerical_rank, polar, procrustes
from algorithms.core.linalg import RANK_RTOL, det

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
