"""Tests for alignment.homography: hand cases, recovery in d = 1, 2, 3, 5 also with
coordinates in the thousands, weights, symmetric transfer error, agreement with an
independent DLT (Hartley & Zisserman, Algorithm 4.2) and with affine."""

from __future__ import annotations

import dataclasses
import sys

import numpy as np
import pytest
from scipy.linalg import null_space

from algorithms.alignment import HomographyResult, affine, homography
from algorithms.core import DegenerateInputError, InvalidInputError

SEEDS = range(100)


def apply(p: np.ndarray, x: np.ndarray) -> np.ndarray:
    h = np.c_[x, np.ones(len(x))] @ p.T
    return h[:, :-1] / h[:, -1:]


def random_problem(seed: int, d: int, *, big: bool):  # noqa: ANN201
    """A random projective map with P[d, d] = 1 and points it sends to finite places; with
    ``big`` the coordinates are in the thousands (500-1500 and their images)."""
    rng = np.random.default_rng(seed)
    n = d + 2 + seed % 5
    scale, offset = (500.0, 1000.0) if big else (1.0, 0.0)
    x = rng.uniform(-1, 1, (n, d)) * scale + offset
    p = np.eye(d + 1)
    p[:d, :d] += rng.standard_normal((d, d)) * 0.3
    p[:d, d] = rng.standard_normal(d) * (offset or 1.0)
    p[d, :d] = rng.standard_normal(d) * 0.05 / (offset or 1.0)
    return x, apply(p, x), p


# --- layer 1: by hand ------------------------------------------------------------------------


def test_hand_unit_square_perspective():
    # P = [[1,0,0],[0,1,0],[1,0,1]]: (x, y) -> (x, y)/(x + 1).
    # (0,0) -> (0,0); (1,0) -> (1/2, 0); (1,1) -> (1/2, 1/2); (0,1) -> (0, 1).
    x = [[0, 0], [1, 0], [1, 1], [0, 1]]
    y = [[0, 0], [0.5, 0], [0.5, 0.5], [0, 1]]
    res = homography(x, y)
    np.testing.assert_allclose(res.transform, [[1, 0, 0], [0, 1, 0], [1, 0, 1]], atol=1e-14)
    np.testing.assert_allclose(res.linear, np.eye(2), atol=1e-14)
    np.testing.assert_allclose(res.translation, [0, 0], atol=1e-14)
    np.testing.assert_allclose(res.perspective, [1, 0], atol=1e-14)
    assert res.rmse < 1e-14


def test_hand_moebius_1d():
    # x -> (2x + 1)/(x + 1): 0 -> 1, 1 -> 3/2, 2 -> 5/3. P = [[2, 1], [1, 1]].
    res = homography([[0], [1], [2]], [[1], [1.5], [5 / 3]])
    np.testing.assert_allclose(res.transform, [[2, 1], [1, 1]], atol=1e-13)


def test_hand_corner_zero_is_scaled_by_norm():
    # P = [[0,0,1],[0,1,0],[1,0,0]]: (x, y) -> (1/x, y/x); the origin goes to infinity, so
    # P[2, 2] = 0 and the matrix is scaled to unit norm, largest entry positive: P/√3.
    x = np.array([[1, 0], [2, 1], [1, 3], [4, 2], [-3, -1]], dtype=float)
    y = np.c_[1 / x[:, 0], x[:, 1] / x[:, 0]]
    res = homography(x, y)
    expected = np.array([[0, 0, 1], [0, 1, 0], [1, 0, 0]]) / np.sqrt(3)
    np.testing.assert_allclose(res.transform, expected, atol=1e-13)
    assert res.rmse < 1e-13


def test_result_fields():
    names = [f.name for f in dataclasses.fields(HomographyResult)]
    assert names == ["transform", "linear", "translation", "perspective", "rmse"]
    for name in names:
        assert f"\n    {name} : " in HomographyResult.__doc__


# --- layer 2: recovery and invariants ---------------------------------------------------------


@pytest.mark.parametrize("big", [False, True], ids=["unit", "thousands"])
@pytest.mark.parametrize("d", [1, 2, 3, 5])
def test_recovers_random_homography(d, big):
    for seed in SEEDS:
        x, y, p = random_problem(seed, d, big=big)
        res = homography(x, y)
        msg = f"seed {seed}"
        np.testing.assert_allclose(res.transform, p, rtol=1e-8, atol=1e-8, err_msg=msg)
        assert res.transform[d, d] == 1.0
        np.testing.assert_allclose(apply(res.transform, x), y, rtol=1e-8, atol=1e-8, err_msg=msg)
        assert res.rmse < 1e-8 * (1 + 1000 * big)


def test_symmetric_reports_forward_and_backward_transfer_error():
    rng = np.random.default_rng(3)
    x, y, _ = random_problem(3, 2, big=False)
    x = np.r_[x, rng.uniform(-1, 1, (6, 2))]
    y = np.r_[y, rng.uniform(-1, 1, (6, 2))]  # pairs that fit no map
    w = rng.uniform(0.5, 2.0, len(x))
    fwd = homography(x, y, weights=w)
    sym = homography(x, y, weights=w, symmetric=True)
    np.testing.assert_array_equal(sym.transform, fwd.transform)  # the DLT does not change
    forward = np.sum((apply(fwd.transform, x) - y) ** 2, 1)
    backward = np.sum((apply(np.linalg.inv(fwd.transform), y) - x) ** 2, 1)
    assert fwd.rmse == pytest.approx(np.sqrt(w @ forward / w.sum()), rel=1e-12)
    assert sym.rmse == pytest.approx(np.sqrt((w @ forward + w @ backward) / (2 * w.sum())),
                                     rel=1e-12)


@pytest.mark.parametrize("d", [2, 3])
def test_zero_weight_outliers_and_duplicates(d):
    for seed in range(30):
        x, y, p = random_problem(seed, d, big=bool(seed % 2))
        rng = np.random.default_rng(seed)
        x = np.r_[x, x[:2] + 0.1]
        y = np.r_[y, y[:2] + rng.standard_normal((2, d)) * 100]  # outliers
        w = np.r_[np.ones(len(x) - 2), 0.0, 0.0]
        res = homography(x, y, weights=w)
        np.testing.assert_allclose(res.transform, p, rtol=1e-8, atol=1e-8)
    rng = np.random.default_rng(0)
    x, y, _ = random_problem(0, 2, big=False)
    y = y + rng.standard_normal(y.shape) * 0.01
    k = rng.integers(1, 4, size=len(x))
    weighted = homography(x, y, weights=k.astype(float))
    repeated = homography(np.repeat(x, k, axis=0), np.repeat(y, k, axis=0))
    np.testing.assert_allclose(weighted.transform, repeated.transform, atol=1e-12)


def test_invariant_under_projective_change_of_target_frame_for_exact_data():
    x, y, p = random_problem(7, 2, big=False)
    q = np.array([[1.0, 0.2, 0.1], [0.0, 0.9, -0.3], [0.05, 0.0, 1.0]])
    res = homography(x, apply(q, y))
    composed = q @ p
    np.testing.assert_allclose(res.transform, composed / composed[2, 2], atol=1e-10)


# --- layer 3: peers ---------------------------------------------------------------------------


def hz_dlt(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Hartley & Zisserman, Algorithm 4.2 (normalised DLT, 2-D), written from the book with
    the two independent rows per correspondence of eq. (4.3) and the same RMS-√2
    normalisation; independent of the code under test."""

    def normaliser(p: np.ndarray) -> np.ndarray:
        c = p.mean(0)
        s = np.sqrt(2 / np.mean(np.sum((p - c) ** 2, 1)))
        return np.array([[s, 0, -s * c[0]], [0, s, -s * c[1]], [0, 0, 1]])

    tx, ty = normaliser(x), normaliser(y)
    xh = np.c_[x, np.ones(len(x))] @ tx.T
    yh = np.c_[y, np.ones(len(y))] @ ty.T
    rows = []
    for a, (u, v, w) in zip(xh, yh, strict=True):
        rows.append(np.r_[np.zeros(3), -w * a, v * a])
        rows.append(np.r_[w * a, np.zeros(3), -u * a])
    h = np.linalg.svd(np.array(rows))[2][-1].reshape(3, 3)
    h = np.linalg.inv(ty) @ h @ tx
    return h / h[2, 2]


def test_agrees_with_hartley_zisserman_dlt_on_noisy_data():
    for seed in range(50):
        rng = np.random.default_rng(seed)
        x, y, _ = random_problem(seed, 2, big=bool(seed % 2))
        x = np.r_[x, rng.uniform(-1, 1, (10, 2)) * x.std() + x.mean(0)]
        y = np.r_[y, rng.uniform(-1, 1, (10, 2)) * y.std() + y.mean(0)]
        np.testing.assert_allclose(homography(x, y).transform, hz_dlt(x, y), rtol=1e-9,
                                   atol=1e-9)


def test_agrees_with_plain_null_space_on_exact_small_data():
    # Unnormalised DLT via scipy.linalg.null_space is fine for small exact coordinates.
    for seed in range(30):
        x, y, p = random_problem(seed, 3, big=False)
        n, d = x.shape
        rows = []
        for xi, yi in zip(x, y, strict=True):
            h = np.r_[xi, 1.0]
            for j in range(d):
                r = np.zeros((d + 1, d + 1))
                r[j], r[d] = h, -yi[j] * h
                rows.append(r.ravel())
        v = null_space(np.array(rows))[:, 0].reshape(d + 1, d + 1)
        np.testing.assert_allclose(homography(x, y).transform, v / v[d, d], atol=1e-9)


def test_affine_data_gives_the_affine_map():
    rng = np.random.default_rng(5)
    x = rng.standard_normal((10, 3)) * 100 + 2000
    y = x @ rng.standard_normal((3, 3)).T + 50
    res = homography(x, y)
    np.testing.assert_allclose(res.perspective, 0, atol=1e-12)
    np.testing.assert_allclose(res.transform, affine(x, y).transform, rtol=1e-9, atol=1e-9)


# --- errors ----------------------------------------------------------------------------------


def test_error_too_few_points():
    with pytest.raises(InvalidInputError, match=r"`source` to hold at least 4 points \(d \+ 2 = 4 "
                       r"in general position for a projective map of 2-D\), got 3\.") as info:
        homography(np.eye(3, 2), np.eye(3, 2))
    assert info.value.field == "source"


def test_error_mismatched_nonfinite_weights():
    x = [[0, 0], [1, 0], [1, 1], [0, 1]]
    with pytest.raises(InvalidInputError, match=r"`target` to hold as many points") as info:
        homography(x, x[:3] + [[2, 2], [3, 3]])
    assert info.value.field == "target"
    with pytest.raises(InvalidInputError, match=r"`target` to hold finite numbers, got -inf at "
                       r"row 2"):
        homography(x, [[0, 0], [1, 0], [-np.inf, 1], [0, 1]])
    with pytest.raises(InvalidInputError, match=r"`weights` to be an \(4,\) array"):
        homography(x, x, weights=[1, 1])


def test_degenerate_collinear_set():
    line = [[0, 0], [1, 1], [2, 2], [3, 3], [4, 4]]
    square = [[0, 0], [1, 0], [1, 1], [0, 1], [2, 3]]
    with pytest.raises(DegenerateInputError, match=r"`source` to span at least 2 dimensions .* "
                       r"collinear and a projective map needs d \+ 2 = 4") as info:
        homography(line, square)
    assert info.value.field == "source"
    with pytest.raises(DegenerateInputError, match=r"`target` .* collinear") as info:
        homography(square, line)
    assert info.value.field == "target"


def test_degenerate_not_in_general_position():
    # Three of four source points on one line: more than one map sends them onto a square
    # ... or none; either way the set is to blame.
    bad = [[0, 0], [1, 0], [2, 0], [0, 1]]
    good = [[0, 0], [1, 0], [1, 1], [0, 1]]
    with pytest.raises(DegenerateInputError, match=r"`source` to hold points in general "
                       r"position \(with d \+ 2 = 4 points: no 3 of them on one hyperplane\)") \
            as info:
        homography(bad, good)
    assert info.value.field == "source"
    with pytest.raises(DegenerateInputError, match=r"`target` to hold points in general") \
            as info:
        homography(good, bad)
    assert info.value.field == "target"
    with pytest.raises(DegenerateInputError, match=r"`source` .* general position \(counting "
                       r"only points with positive weight\)"):
        homography(bad + [[5, 5]], good + [[3, 2]], weights=[1, 1, 1, 1, 0])


def test_degenerate_point_sent_to_infinity():
    # Four pairs fix P = [[1,0,0],[0,1,0],[1,0,1]]; a fifth source point on the line x = -1
    # (sent to infinity), weighted 1e-30 so that it does not move the fit.
    x = [[0, 0], [1, 0], [1, 1], [0, 1], [-1, 2]]
    y = [[0, 0], [0.5, 0], [0.5, 0.5], [0, 1], [7, 7]]
    with pytest.raises(DegenerateInputError, match=r"send every point of `source` to a finite "
                       r"point, got infinity for row 4") as info:
        homography(x, y, weights=[1, 1, 1, 1, 1e-30])
    assert info.value.field is None


def test_docstring_examples_run():
    import doctest

    assert doctest.testmod(sys.modules["algorithms.alignment.homography"]).failed == 0
