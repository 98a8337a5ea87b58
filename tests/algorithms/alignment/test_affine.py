"""Tests for alignment.affine: hand cases, recovery, the symmetric fit, agreement with
numpy.linalg.lstsq."""

from __future__ import annotations

import dataclasses
import sys
import warnings

import numpy as np
import pytest

from algorithms.alignment import AffineResult, affine
from algorithms.core import ConvergenceWarning, DegenerateInputError, InvalidInputError

# The package re-exports the function under the module's name: reach the module itself.
affine_module = sys.modules["algorithms.alignment.affine"]

SEEDS = range(100)

# --- layer 1: by hand ------------------------------------------------------------------------


def test_hand_triangle_shear():
    # A = [[2, 0], [1, 3]], b = (1, -1): (0,0) -> (1,-1); (1,0) -> (3,0); (0,1) -> (1,2).
    res = affine([[0, 0], [1, 0], [0, 1]], [[1, -1], [3, 0], [1, 2]])
    np.testing.assert_allclose(res.linear, [[2, 0], [1, 3]], atol=1e-12)
    np.testing.assert_allclose(res.translation, [1, -1], atol=1e-12)
    np.testing.assert_allclose(res.transform, [[2, 0, 1], [1, 3, -1], [0, 0, 1]], atol=1e-12)
    assert res.rmse < 1e-12 and res.iterations == 0 and res.converged is True


def test_hand_line_regression_1d():
    # x = 0, 1, 2; y = 1, 3, 4. x̄ = 1, ȳ = 8/3, Sxy = 3, Sxx = 2: a = 3/2, b = 8/3 - 3/2 = 7/6.
    # Predictions 7/6, 16/6, 25/6; residuals 1/6, -2/6, 1/6: mean square (6/36)/3 = 1/18.
    res = affine([[0], [1], [2]], [[1], [3], [4]])
    assert res.linear[0, 0] == pytest.approx(1.5, abs=1e-14)
    assert res.translation[0] == pytest.approx(7 / 6, abs=1e-14)
    assert res.rmse == pytest.approx(np.sqrt(1 / 18), abs=1e-14)


def test_hand_weights_and_projection():
    # A flat target is fine one-sided: every point to the x-axis, y = (x1, 0).
    res = affine([[0, 0], [1, 0], [0, 1], [5, 5]], [[0, 0], [1, 0], [0, 0], [9, 9]],
                 weights=[1, 1, 1, 0])
    np.testing.assert_allclose(res.linear, [[1, 0], [0, 0]], atol=1e-14)
    np.testing.assert_allclose(res.translation, [0, 0], atol=1e-14)
    assert res.rmse == pytest.approx(0.0, abs=1e-14)


def test_result_fields():
    names = [f.name for f in dataclasses.fields(AffineResult)]
    assert names == ["transform", "linear", "translation", "rmse", "iterations", "converged"]
    for name in names:
        assert f"\n    {name} : " in AffineResult.__doc__


# --- layer 2: invariants and recovery -------------------------------------------------------


@pytest.mark.parametrize("d", [2, 3, 5])
def test_recovers_random_affine(d):
    for seed in SEEDS:
        rng = np.random.default_rng(seed)
        n = d + 1 + seed % 6
        offset = 1000.0 if seed % 2 else 0.0
        x = rng.standard_normal((n, d)) * 3 + offset
        a = rng.standard_normal((d, d)) * 2
        b = rng.standard_normal(d) * 10
        y = x @ a.T + b
        res = affine(x, y)
        msg = f"seed {seed}"
        np.testing.assert_allclose(res.linear, a, atol=1e-8, err_msg=msg)
        np.testing.assert_allclose(res.translation, b, atol=1e-8 * (1 + offset * 10),
                                   err_msg=msg)
        assert res.rmse < 1e-8 * (1 + offset)
        hom = np.c_[x, np.ones(n)] @ res.transform.T
        np.testing.assert_allclose(hom[:, :d], y, atol=1e-8 * (1 + offset * 10))


@pytest.mark.parametrize("d", [2, 3])
def test_symmetric_recovers_exact_data_at_once(d):
    for seed in range(30):
        rng = np.random.default_rng(seed)
        x = rng.standard_normal((d + 3, d))
        a = rng.standard_normal((d, d)) + 2 * np.eye(d)
        y = x @ a.T + 1.0
        res = affine(x, y, symmetric=True)
        np.testing.assert_allclose(res.linear, a, atol=1e-9)
        assert res.converged and res.iterations <= 2 and res.rmse < 1e-9


def test_symmetric_is_the_inverse_of_the_swapped_fit_and_a_minimum():
    rng = np.random.default_rng(3)
    x = rng.standard_normal((20, 3))
    a = rng.standard_normal((3, 3)) + 2 * np.eye(3)
    y = x @ a.T + 2 + rng.standard_normal((20, 3)) * 0.3
    w = rng.uniform(0.2, 2.0, 20)
    fwd = affine(x, y, weights=w, symmetric=True)
    back = affine(y, x, weights=w, symmetric=True)
    assert fwd.converged and fwd.iterations > 1
    np.testing.assert_allclose(fwd.transform @ back.transform, np.eye(4), atol=1e-12)
    assert fwd.rmse == pytest.approx(back.rmse, rel=1e-9)

    def objective(v: np.ndarray) -> float:
        m, t = v[:9].reshape(3, 3), v[9:]
        e = x @ m.T + t - y
        g = np.linalg.solve(m, (y - t).T).T - x
        return float(w @ (np.sum(e**2, 1) + np.sum(g**2, 1)) / w.sum())

    best = objective(np.r_[fwd.linear.ravel(), fwd.translation])
    assert fwd.rmse == pytest.approx(np.sqrt(best / 2), rel=1e-12)
    for _ in range(10):
        step = rng.standard_normal(12) * 1e-4
        assert objective(np.r_[fwd.linear.ravel(), fwd.translation] + step) > best
    one_sided = affine(x, y, weights=w)
    assert not np.allclose(one_sided.linear, fwd.linear, atol=1e-6)


def test_symmetric_reports_non_convergence(monkeypatch):
    monkeypatch.setattr(affine_module, "MAX_NEWTON", 1)
    rng = np.random.default_rng(4)
    x = rng.standard_normal((10, 2))
    y = x @ [[2, 1], [0, 1]] + rng.standard_normal((10, 2)) * 0.5
    with pytest.warns(ConvergenceWarning, match="symmetric affine fit stopped after 1 Newton"):
        res = affine(x, y, symmetric=True)
    assert res.converged is False and res.iterations == 1 and np.isfinite(res.rmse)


def test_weights_equal_duplicates_and_scale_free():
    rng = np.random.default_rng(6)
    x = rng.standard_normal((9, 3))
    y = x @ rng.standard_normal((3, 3)).T + rng.standard_normal((9, 3)) * 0.1
    k = rng.integers(1, 4, size=9)
    weighted = affine(x, y, weights=k.astype(float))
    repeated = affine(np.repeat(x, k, axis=0), np.repeat(y, k, axis=0))
    np.testing.assert_allclose(weighted.transform, repeated.transform, atol=1e-12)
    assert weighted.rmse == pytest.approx(repeated.rmse, rel=1e-12)
    scaled = affine(x, y, weights=k * 1e8)
    np.testing.assert_allclose(scaled.transform, weighted.transform, atol=1e-12)


def test_reflections_are_part_of_the_model():
    x = np.random.default_rng(7).standard_normal((6, 2))
    res = affine(x, x * [1, -1])
    np.testing.assert_allclose(res.linear, [[1, 0], [0, -1]], atol=1e-13)


# --- layer 3: numpy.linalg.lstsq -------------------------------------------------------------


@pytest.mark.parametrize("d", [1, 2, 3, 5])
def test_agrees_with_numpy_lstsq(d):
    for seed in SEEDS:
        rng = np.random.default_rng(seed)
        n = 3 * d + 4
        x = rng.standard_normal((n, d)) * 2 + 5
        y = x @ rng.standard_normal((d, d)).T + rng.standard_normal((n, d))
        w = rng.uniform(0.1, 3.0, n) if seed % 2 else None
        hom = np.c_[x, np.ones(n)]
        sw = np.ones(n) if w is None else np.sqrt(w)
        sol, *_ = np.linalg.lstsq(hom * sw[:, None], y * sw[:, None], rcond=None)
        res = affine(x, y, weights=w)
        np.testing.assert_allclose(res.linear, sol[:d].T, atol=1e-10)
        np.testing.assert_allclose(res.translation, sol[d], atol=1e-10)
        resid = hom @ sol - y
        ww = np.ones(n) if w is None else w
        assert res.rmse == pytest.approx(np.sqrt(ww @ np.sum(resid**2, 1) / ww.sum()), rel=1e-9)


# --- errors ----------------------------------------------------------------------------------


def test_error_too_few_points():
    with pytest.raises(InvalidInputError, match=r"`source` to hold at least 4 points \(d \+ 1 = "
                       r"4 affinely independent points for an affine map of 3-D\), got 3\."):
        affine(np.eye(3), np.eye(3))


def test_error_mismatched_and_nonfinite():
    with pytest.raises(InvalidInputError, match=r"`target` to hold as many points") as info:
        affine(np.eye(4, 3), np.eye(5, 3))
    assert info.value.field == "target"
    x = np.eye(4, 3)
    bad = x.copy()
    bad[3, 0] = np.inf
    with pytest.raises(InvalidInputError, match=r"`target` to hold finite numbers, got inf at "
                       r"row 3") as info:
        affine(x, bad)
    assert info.value.field == "target"
    with pytest.raises(InvalidInputError, match=r"`weights` to have a positive sum"):
        affine(x, x, weights=[0, 0, 0, 0])
    with pytest.raises(InvalidInputError, match=r"`symmetric` to be true or false"):
        affine(x, x, symmetric=None)


def test_degenerate_collinear_and_coplanar_even_far_from_origin():
    t = np.linspace(0.0, 1.0, 6)[:, None]
    for offset in (0.0, 1e4):
        line = offset + t * [1.0, 2.0, 3.0]
        with pytest.raises(DegenerateInputError, match=r"`source` to span at least 3 dimensions"
                           r" after centring, got 1: the points are collinear and the affine "
                           r"map is undetermined") as info:
            affine(line, np.random.default_rng(0).standard_normal((6, 3)))
        assert info.value.field == "source"
        rng = np.random.default_rng(1)
        plane = offset + np.c_[rng.standard_normal((6, 2)), np.zeros(6)] @ np.linalg.qr(
            rng.standard_normal((3, 3)))[0]
        with pytest.raises(DegenerateInputError, match=r"got 2: the points are coplanar"):
            affine(plane, rng.standard_normal((6, 3)))


def test_degenerate_coincident_and_zero_weights():
    with pytest.raises(DegenerateInputError, match=r"coincident"):
        affine(np.ones((4, 2)), np.eye(4, 2))
    x = [[0, 0], [1, 0], [0, 1], [2, 0]]
    with pytest.raises(DegenerateInputError, match=r"collinear \(counting only points with "
                       r"positive weight\)"):
        affine(x, x, weights=[1, 1, 0, 1])


def test_degenerate_symmetric_needs_an_invertible_map():
    x = np.array([[0, 0], [1, 0], [0, 1], [1, 1]], dtype=float)
    with pytest.raises(DegenerateInputError, match=r"`target` .* collinear .* no inverse, which "
                       r"`symmetric=true` needs") as info:
        affine(x, x * [1, 0], symmetric=True)
    assert info.value.field == "target"
    # Each set is a unit square, but y2 (0, 1, 1, 0) is uncorrelated with both x1 (0, 1, 0, 1)
    # and x2 (0, 0, 1, 1): A = [[1, 0], [0, 0]] has rank 1.
    y = np.array([[0, 0], [1, 1], [0, 1], [1, 0]], dtype=float)
    with pytest.raises(DegenerateInputError, match=r"affine map to be invertible, got rank 1") \
            as info:
        affine(x, y, symmetric=True)
    assert info.value.field is None


def test_docstring_examples_run():
    import doctest

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert doctest.testmod(affine_module).failed == 0
