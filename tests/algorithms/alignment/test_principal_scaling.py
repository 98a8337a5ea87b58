"""Tests for alignment.principal_scaling: the cross-covariance map M = ỸX̃ᵀ, exactly when it equals the
least-squares affine map (whitened source) and when it does not (a larger residual)."""

from __future__ import annotations

import dataclasses
import sys

import numpy as np
import pytest

from algorithms.alignment import PrincipalScalingResult, affine, principal_scaling
from algorithms.core import DegenerateInputError, InvalidInputError

SEEDS = range(100)


def whitened(rng: np.random.Generator, n: int, d: int, w: np.ndarray | None = None,
             offset: float = 0.0) -> np.ndarray:
    """``n`` points with Σ wᵢ x̃ᵢx̃ᵢᵀ = I about their weighted centroid."""
    w = np.ones(n) if w is None else w
    x = rng.standard_normal((n, d)) * rng.uniform(0.5, 3.0, d)
    xc = x - (w @ x) / w.sum()
    chol = np.linalg.cholesky((xc * w[:, None]).T @ xc)
    return np.linalg.solve(chol, xc.T).T + offset


def random_proper(rng: np.random.Generator, d: int) -> np.ndarray:
    a = rng.standard_normal((d, d)) * 2
    if np.linalg.det(a) < 0:
        a[:, 0] = -a[:, 0]
    return a


# --- layer 1: by hand ------------------------------------------------------------------------


def test_hand_whitened_square_is_exact():
    # Corners (±1/2, ±1/2): Σ x̃x̃ᵀ = 4 · diag(1/4, 1/4) = I. y = diag(3, 1/2) x + (1, 1).
    x = np.array([[0.5, 0.5], [-0.5, 0.5], [-0.5, -0.5], [0.5, -0.5]])
    y = x * [3.0, 0.5] + 1.0
    res = principal_scaling(x, y)
    np.testing.assert_allclose(res.linear, np.diag([3.0, 0.5]), atol=1e-15)
    np.testing.assert_allclose(res.translation, [1, 1], atol=1e-15)
    np.testing.assert_allclose(res.scale, [3.0, 0.5], atol=1e-15)
    np.testing.assert_allclose(np.abs(res.axes), np.eye(2), atol=1e-15)
    np.testing.assert_allclose(res.rotation, np.eye(2), atol=1e-15)
    assert res.rmse < 1e-15 and res.reflection is False


def test_hand_unwhitened_cross_is_off_by_its_second_moment():
    # x = (±1, 0), (0, ±1): Σ x̃x̃ᵀ = 2I. y = diag(3, 1/2) x, so M = Σ y xᵀ = diag(6, 1),
    # twice the true map. Residuals M x - y = diag(3, 1/2) x: (±3, 0), (0, ±1/2); mean square
    # (9 + 9 + 1/4 + 1/4)/4 = 4.625. The affine fit is exact.
    x = np.array([[1, 0], [-1, 0], [0, 1], [0, -1]], dtype=float)
    y = x * [3.0, 0.5]
    res = principal_scaling(x, y)
    np.testing.assert_allclose(res.linear, np.diag([6.0, 1.0]), atol=1e-15)
    assert res.rmse == pytest.approx(np.sqrt(4.625), abs=1e-14)
    assert affine(x, y).rmse < 1e-15


def test_hand_weights_enter_unnormalised():
    # Weight 1/2 on each of the four points of the previous case: Σ wᵢ x̃ᵢx̃ᵢᵀ = I, exact.
    x = np.array([[1, 0], [-1, 0], [0, 1], [0, -1]], dtype=float)
    y = x * [3.0, 0.5]
    res = principal_scaling(x, y, weights=[0.5] * 4)
    np.testing.assert_allclose(res.linear, np.diag([3.0, 0.5]), atol=1e-15)
    doubled = principal_scaling(x, y, weights=[1.0] * 4)
    np.testing.assert_allclose(doubled.linear, 2 * res.linear, atol=1e-15)


def test_result_fields():
    names = [f.name for f in dataclasses.fields(PrincipalScalingResult)]
    assert names == ["transform", "linear", "rotation", "scale", "axes", "translation",
                     "rmse", "reflection"]
    for name in names:
        assert f"\n    {name} : " in PrincipalScalingResult.__doc__


# --- layer 2: when it is the least-squares map, and when not ---------------------------------


@pytest.mark.parametrize("d", [2, 3, 5])
def test_equals_affine_exactly_for_a_whitened_source(d):
    # X̃X̃ᵀ = I: M = ỸX̃ᵀ = ỸX̃ᵀ(X̃X̃ᵀ)⁻¹ = A, for noisy targets too, weighted or not.
    for seed in SEEDS:
        rng = np.random.default_rng(seed)
        n = d + 2 + seed % 5
        w = rng.uniform(0.2, 2.0, n) if seed % 2 else None
        x = whitened(rng, n, d, w, offset=100.0 * (seed % 3))
        a = random_proper(rng, d)
        y = x @ a.T + rng.standard_normal(d) + rng.standard_normal((n, d)) * 0.05
        ours = principal_scaling(x, y, weights=w)
        best = affine(x, y, weights=w)
        if np.linalg.det(best.linear) < 0:  # noise flipped it: only the mirror-free map left
            continue
        np.testing.assert_allclose(ours.linear, best.linear, atol=1e-9, err_msg=f"seed {seed}")
        np.testing.assert_allclose(ours.translation, best.translation, atol=1e-7)
        assert ours.rmse == pytest.approx(best.rmse, rel=1e-7, abs=1e-12)
        # noise-free: the map is recovered
        exact = principal_scaling(x, x @ a.T, weights=w)
        np.testing.assert_allclose(exact.linear, a, atol=1e-8)


@pytest.mark.parametrize("d", [2, 3, 5])
def test_larger_residual_than_affine_otherwise(d):
    for seed in SEEDS:
        rng = np.random.default_rng(seed)
        n = 3 * d
        x = rng.standard_normal((n, d)) * rng.uniform(0.5, 3.0, d)
        a = random_proper(rng, d)
        y = x @ a.T + 1.0
        ours = principal_scaling(x, y)
        assert ours.rmse > affine(x, y).rmse + 1e-3, f"seed {seed}"
        # not scale-consistent: scaling the source by c scales M by c (the best map by 1/c)
        scaled = principal_scaling(2.0 * x, y)
        np.testing.assert_allclose(scaled.linear, 2.0 * ours.linear, atol=1e-10)


@pytest.mark.parametrize("d", [2, 3, 5])
def test_decomposition_and_reflections(d):
    for seed in range(30):
        rng = np.random.default_rng(seed)
        x = whitened(rng, 2 * d + 1, d)
        mirror = random_proper(rng, d) @ np.diag([1.0] * (d - 1) + [-1.0])
        y = x @ mirror.T
        proper = principal_scaling(x, y)
        assert proper.reflection is False
        assert np.linalg.det(proper.rotation) == pytest.approx(1.0)
        assert np.linalg.det(proper.linear) > 0
        kept = principal_scaling(x, y, allow_reflection=True)
        assert kept.reflection is True
        np.testing.assert_allclose(kept.linear, mirror, atol=1e-9)  # whitened: exact
        for res in (proper, kept):
            v = res.axes
            np.testing.assert_allclose(v.T @ v, np.eye(d), atol=1e-12)
            np.testing.assert_allclose(res.rotation @ v @ np.diag(res.scale) @ v.T, res.linear,
                                       atol=1e-10)
            assert (np.diff(res.scale) <= 0).all() and (res.scale >= 0).all()
            np.testing.assert_allclose(res.transform[:d, :d], res.linear)


def test_symmetric_counts_the_inverse_residuals():
    rng = np.random.default_rng(2)
    x = rng.standard_normal((12, 3))
    y = x @ random_proper(rng, 3).T
    fwd = principal_scaling(x, y)
    sym = principal_scaling(x, y, symmetric=True)
    np.testing.assert_array_equal(sym.transform, fwd.transform)  # the map does not change
    e = x @ fwd.linear.T + fwd.translation - y
    g = np.linalg.solve(fwd.linear, (y - fwd.translation).T).T - x
    expected = np.sqrt((np.mean(np.sum(e**2, 1)) + np.mean(np.sum(g**2, 1))) / 2)
    assert sym.rmse == pytest.approx(expected, rel=1e-12)


# --- layer 3: numpy ---------------------------------------------------------------------------


def test_agrees_with_numpy_svd_of_the_cross_covariance():
    for seed in range(30):
        rng = np.random.default_rng(seed)
        x, y = rng.standard_normal((10, 3)), rng.standard_normal((10, 3))
        m = (y - y.mean(0)).T @ (x - x.mean(0))
        res = principal_scaling(x, y, allow_reflection=True)
        np.testing.assert_allclose(res.linear, m, atol=1e-12)
        np.testing.assert_allclose(res.scale, np.linalg.svd(m, compute_uv=False), atol=1e-12)


# --- errors ----------------------------------------------------------------------------------


def test_error_inputs():
    with pytest.raises(InvalidInputError, match=r"`source` to hold at least 3 points"):
        principal_scaling(np.eye(2, 3), np.eye(2, 3))
    with pytest.raises(InvalidInputError, match=r"`target` to hold as many points") as info:
        principal_scaling(np.eye(3), np.eye(4, 3))
    assert info.value.field == "target"
    bad = np.eye(3)
    bad[1, 1] = np.nan
    with pytest.raises(InvalidInputError, match=r"`source` to hold finite numbers, got nan at "
                       r"row 1"):
        principal_scaling(bad, np.eye(3))


def test_degenerate_sets():
    rng = np.random.default_rng(0)
    with pytest.raises(DegenerateInputError, match=r"`source` .* coincident .* undetermined") \
            as info:
        principal_scaling(np.zeros((4, 3)), rng.standard_normal((4, 3)))
    assert info.value.field == "source"
    x = np.array([[0, 0], [1, 1], [2, 2]], dtype=float)
    assert principal_scaling(x, x).rmse > 0  # rank d - 1 is enough one-sided
    with pytest.raises(DegenerateInputError, match=r"collinear .* no inverse, which "
                       r"`symmetric=true` needs"):
        principal_scaling(x, x, symmetric=True)
    with pytest.raises(DegenerateInputError, match=r"collinear .* reflection .* equally well"):
        principal_scaling(x, x, allow_reflection=True)


def test_docstring_examples_run():
    import doctest

    assert doctest.testmod(sys.modules["algorithms.alignment.principal_scaling"]).failed == 0
