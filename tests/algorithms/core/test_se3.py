"""Tests for core.se3: hand cases of every map (a quarter turn, a pure translation), the
invariants of the group and its algebra (exp(log T) = T, R Rᵀ = I, det R = 1, the adjoint
identity, the inverse), and agreement with scipy's rotation vectors and matrix exponential."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.linalg import expm, logm
from scipy.spatial.transform import Rotation

from algorithms.core import se3


def _twist_matrix(xi: np.ndarray) -> np.ndarray:
    """The 4×4 Lie algebra element of the twist (ω, v)."""
    out = np.zeros((4, 4))
    out[:3, :3] = se3.hat(xi[:3])
    out[:3, 3] = xi[3:]
    return out


def _random_motion(rng: np.random.Generator, angle: float | None = None) -> np.ndarray:
    axis = rng.normal(size=3)
    theta = rng.uniform(0.0, math.pi) if angle is None else angle
    out = np.eye(4)
    out[:3, :3] = Rotation.from_rotvec(theta * axis / np.linalg.norm(axis)).as_matrix()
    out[:3, 3] = rng.normal(size=3)
    return out


ANGLES = (0.0, 1e-9, 1e-4, 5e-3, 0.0099, 0.0101, 0.05, 0.0999, 0.1001, 1.0, 3.0,
          math.pi - 0.011, math.pi - 0.009, math.pi)


# --- layer 1: computed by hand --------------------------------------------------------------


def test_hat_is_the_cross_product():
    w, x = np.array([1.0, 2.0, 3.0]), np.array([-2.0, 0.5, 4.0])
    np.testing.assert_array_equal(se3.hat(w), [[0, -3, 2], [3, 0, -1], [-2, 1, 0]])
    np.testing.assert_array_equal(se3.hat(w) @ x, np.cross(w, x))


def test_exp_of_a_quarter_turn_about_z_with_a_shift_along_it():
    # ω = (0, 0, π/2), v = (0, 0, 1): a screw motion; the rotation is the quarter turn
    # [[0, -1, 0], [1, 0, 0], [0, 0, 1]] and the translation (along the axis) is v itself,
    # since V v = v for v parallel to ω.
    t = se3.exp(np.array([0.0, 0.0, math.pi / 2, 0.0, 0.0, 1.0]))
    np.testing.assert_allclose(t, [[0, -1, 0, 0], [1, 0, 0, 0], [0, 0, 1, 1], [0, 0, 0, 1]],
                               atol=1e-15)


def test_exp_of_a_half_turn_about_z_moving_along_x():
    # ω = (0, 0, π), v = (1, 0, 0): V = I + (2/π²) W + ((π - 0)/π³) W², W = π [e_z]×, so
    # V e_x = e_x + (2/π) e_y - e_x = (0, 2/π, 0).
    t = se3.exp(np.array([0.0, 0.0, math.pi, 1.0, 0.0, 0.0]))
    np.testing.assert_allclose(t[:3, :3], np.diag([-1.0, -1.0, 1.0]), atol=1e-15)
    np.testing.assert_allclose(t[:3, 3], [0.0, 2.0 / math.pi, 0.0], atol=1e-15)


def test_pure_translation():
    t = np.eye(4)
    t[:3, 3] = [1.0, -2.0, 3.0]
    np.testing.assert_array_equal(se3.exp(np.r_[0.0, 0.0, 0.0, 1.0, -2.0, 3.0]), t)
    np.testing.assert_array_equal(se3.log(t), [0, 0, 0, 1, -2, 3])
    np.testing.assert_array_equal(se3.inverse(t)[:3, 3], [-1.0, 2.0, -3.0])


def test_identity():
    np.testing.assert_array_equal(se3.exp(np.zeros(6)), np.eye(4))
    np.testing.assert_array_equal(se3.log(np.eye(4)), np.zeros(6))
    np.testing.assert_array_equal(se3.adjoint(np.eye(4)), np.eye(6))
    np.testing.assert_array_equal(se3.left_jacobian_inverse(np.zeros(6)), np.eye(6))


def test_adjoint_and_ad_blocks():
    t = np.eye(4)
    t[:3, 3] = [1.0, 0.0, 0.0]                     # a shift along x, no rotation
    ad_t = se3.adjoint(t)
    np.testing.assert_array_equal(ad_t[:3, :3], np.eye(3))
    np.testing.assert_array_equal(ad_t[:3, 3:], np.zeros((3, 3)))
    np.testing.assert_array_equal(ad_t[3:, :3], se3.hat([1.0, 0.0, 0.0]))
    xi = np.array([1.0, 2.0, 3.0, 4.0, 5.0, 6.0])
    a = se3.ad(xi)
    np.testing.assert_array_equal(a[:3, :3], se3.hat(xi[:3]))
    np.testing.assert_array_equal(a[3:, 3:], se3.hat(xi[:3]))
    np.testing.assert_array_equal(a[3:, :3], se3.hat(xi[3:]))
    np.testing.assert_array_equal(a[:3, 3:], np.zeros((3, 3)))


# --- layer 2: invariants ----------------------------------------------------------------------


@pytest.mark.parametrize("angle", ANGLES)
def test_exp_gives_a_rotation(angle):
    rng = np.random.default_rng(0)
    axis = rng.normal(size=3)
    xi = np.r_[angle * axis / np.linalg.norm(axis), rng.normal(size=3)]
    t = se3.exp(xi)
    r = t[:3, :3]
    np.testing.assert_allclose(r @ r.T, np.eye(3), atol=1e-15)
    assert np.linalg.det(r) == pytest.approx(1.0, abs=1e-15)
    np.testing.assert_array_equal(t[3], [0, 0, 0, 1])


@pytest.mark.parametrize("angle", ANGLES)
def test_exp_and_log_are_inverse(angle):
    rng = np.random.default_rng(1)
    for _ in range(5):
        axis = rng.normal(size=3)
        xi = np.r_[angle * axis / np.linalg.norm(axis), rng.normal(size=3)]
        t = se3.exp(xi)
        np.testing.assert_allclose(t[:3, :3], Rotation.from_rotvec(xi[:3]).as_matrix(),
                                   atol=1e-15)
        if angle < math.pi:   # at a half turn ω and -ω are the same motion
            np.testing.assert_allclose(se3.log(t), xi, atol=1e-12)
        np.testing.assert_allclose(se3.exp(se3.log(t)), t, atol=1e-12)


@pytest.mark.parametrize("seed", range(20))
def test_exp_log_round_trip_of_random_motions(seed):
    t = _random_motion(np.random.default_rng(seed))
    np.testing.assert_allclose(se3.exp(se3.log(t)), t, atol=1e-12)
    assert np.linalg.norm(se3.log(t)[:3]) <= math.pi + 1e-12


@pytest.mark.parametrize("seed", range(10))
def test_inverse_composes_to_the_identity(seed):
    t = _random_motion(np.random.default_rng(seed))
    np.testing.assert_allclose(se3.inverse(t) @ t, np.eye(4), atol=1e-14)
    np.testing.assert_allclose(t @ se3.inverse(t), np.eye(4), atol=1e-14)
    np.testing.assert_allclose(se3.inverse(t), np.linalg.inv(t), atol=1e-14)


@pytest.mark.parametrize("seed", range(10))
def test_log_of_the_inverse_and_of_powers(seed):
    # log(T⁻¹) = -log(T); log(exp(ξ)²) = 2ξ while the angle stays below π.
    rng = np.random.default_rng(seed)
    xi = np.r_[rng.uniform(-0.5, 0.5, 3), rng.normal(size=3)]
    t = se3.exp(xi)
    np.testing.assert_allclose(se3.log(se3.inverse(t)), -xi, atol=1e-13)
    np.testing.assert_allclose(se3.log(t @ t), 2 * xi, atol=1e-12)


@pytest.mark.parametrize("seed", range(10))
def test_adjoint_moves_twists_between_frames(seed):
    # exp(Ad_T ξ) = T exp(ξ) T⁻¹, and Ad is a homomorphism: Ad(T S) = Ad(T) Ad(S).
    rng = np.random.default_rng(seed)
    t, s = _random_motion(rng), _random_motion(rng)
    xi = rng.normal(size=6) * 0.3
    np.testing.assert_allclose(se3.exp(se3.adjoint(t) @ xi),
                               t @ se3.exp(xi) @ se3.inverse(t), atol=1e-12)
    np.testing.assert_allclose(se3.adjoint(t @ s), se3.adjoint(t) @ se3.adjoint(s),
                               atol=1e-12)
    np.testing.assert_allclose(se3.adjoint(se3.inverse(t)), np.linalg.inv(se3.adjoint(t)),
                               atol=1e-12)


@pytest.mark.parametrize("seed", range(5))
def test_ad_is_the_lie_bracket(seed):
    # ad_ξ η is the twist of the commutator [ξ̂, η̂] = ξ̂ η̂ - η̂ ξ̂.
    rng = np.random.default_rng(seed)
    xi, eta = rng.normal(size=6), rng.normal(size=6)
    a, b = _twist_matrix(xi), _twist_matrix(eta)
    np.testing.assert_allclose(_twist_matrix(se3.ad(xi) @ eta), a @ b - b @ a, atol=1e-13)


@pytest.mark.parametrize("seed", range(5))
def test_left_jacobian_inverse_is_the_derivative_of_log(seed):
    # log(exp(δ) exp(ξ)) ≈ ξ + J_l⁻¹(ξ) δ: central differences, for the small residual
    # twists where the second-order series is accurate (its error is O(|ξ|⁴)).
    rng = np.random.default_rng(seed)
    xi = rng.normal(size=6) * 0.05
    h = 1e-6
    numeric = np.empty((6, 6))
    for k in range(6):
        d = np.zeros(6)
        d[k] = h
        numeric[:, k] = (se3.log(se3.exp(d) @ se3.exp(xi))
                         - se3.log(se3.exp(-d) @ se3.exp(xi))) / (2 * h)
    np.testing.assert_allclose(se3.left_jacobian_inverse(xi), numeric, atol=1e-6)


# --- layer 3: agreement with scipy ------------------------------------------------------------


@pytest.mark.parametrize("seed", range(10))
def test_exp_and_log_agree_with_the_matrix_exponential(seed):
    rng = np.random.default_rng(seed)
    xi = np.r_[rng.uniform(-1.5, 1.5, 3), rng.normal(size=3)]
    np.testing.assert_allclose(se3.exp(xi), expm(_twist_matrix(xi)), atol=1e-13)
    t = se3.exp(xi)
    np.testing.assert_allclose(_twist_matrix(se3.log(t)), np.real(logm(t)), atol=1e-10)
