"""Tests for assignment.distance: a hand case, invariants, agreement with brute force and
scipy's directed_hausdorff, every error branch."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from scipy.spatial.distance import cdist, directed_hausdorff

from algorithms.assignment import DistanceResult, distance, nearest
from algorithms.core import InvalidInputError

SEEDS = range(100)

# Points on a line: source 0, 2, 7; target 1.5, 6, 10.
SOURCE = [[0.0], [2.0], [7.0]]
TARGET = [[1.5], [6.0], [10.0]]


# --- layer 1: computed by hand --------------------------------------------------------------


def test_hand_case():
    # forward: 0 -> 1.5 (1.5), 2 -> 1.5 (0.5), 7 -> 6 (1.0)
    # backward: 1.5 -> 2 (0.5), 6 -> 7 (1.0), 10 -> 7 (3.0)
    res = distance(SOURCE, TARGET)
    assert res.forward_distances.tolist() == [1.5, 0.5, 1.0]
    assert res.backward_distances.tolist() == [0.5, 1.0, 3.0]
    assert res.chamfer == 7.5
    assert res.chamfer_mean == pytest.approx(3.0 / 3 + 4.5 / 3, rel=1e-15)
    assert (res.hausdorff, res.hausdorff_forward, res.hausdorff_backward) == (3.0, 1.5, 3.0)
    assert res.rmse_forward == pytest.approx(np.sqrt((2.25 + 0.25 + 1.0) / 3), rel=1e-15)
    assert res.rmse_backward == pytest.approx(np.sqrt((0.25 + 1.0 + 9.0) / 3), rel=1e-15)
    assert res.rmse == pytest.approx(np.sqrt((3.5 + 10.25) / 6), rel=1e-15)
    assert res.forward_distances.dtype == np.float64
    for name in ("chamfer", "chamfer_mean", "hausdorff", "rmse", "rmse_forward"):
        assert isinstance(getattr(res, name), float)


def test_hand_different_sizes_2d():
    # one source point at the origin, targets at distance 3 and 5 (a 3-4-5 triangle)
    res = distance([[0.0, 0.0]], [[3.0, 0.0], [3.0, 4.0]])
    assert res.forward_distances.tolist() == [3.0]
    assert res.backward_distances.tolist() == [3.0, 5.0]
    assert res.chamfer == 11.0 and res.chamfer_mean == 3.0 + 4.0
    assert res.hausdorff == 5.0 and res.hausdorff_forward == 3.0
    assert res.rmse == pytest.approx(np.sqrt((9 + 9 + 25) / 3), rel=1e-15)


def test_identical_sets_are_at_zero():
    pts = np.random.default_rng(0).random((20, 3))
    res = distance(pts, pts[::-1])
    assert res.chamfer == res.hausdorff == res.rmse == 0.0
    # multiplicities do not count: a set and the same set with repeats are at 0 too
    assert distance(pts, np.concatenate([pts, pts[:5]])).hausdorff == 0.0


def test_result_dataclass():
    names = [f.name for f in dataclasses.fields(DistanceResult)]
    assert names == ["chamfer", "chamfer_mean", "hausdorff", "hausdorff_forward",
                     "hausdorff_backward", "rmse", "rmse_forward", "rmse_backward",
                     "forward_distances", "backward_distances"]
    for name in names:
        assert f"\n    {name} : " in DistanceResult.__doc__
    res = distance(SOURCE, TARGET)
    with pytest.raises(dataclasses.FrozenInstanceError):
        res.chamfer = 0.0  # type: ignore[misc]


# --- layer 2: invariants -----------------------------------------------------------------------


def test_symmetry_and_agreement_with_nearest():
    for seed in range(20):
        rng = np.random.default_rng(seed)
        src, dst = rng.random((25, 3)), rng.random((14, 3))
        ab, ba = distance(src, dst), distance(dst, src)
        for name in ("chamfer", "chamfer_mean", "hausdorff", "rmse"):
            assert getattr(ab, name) == pytest.approx(getattr(ba, name), rel=1e-14)
        assert ab.hausdorff_forward == ba.hausdorff_backward
        np.testing.assert_array_equal(ab.forward_distances, ba.backward_distances)
        both = nearest(src, dst, direction="both")
        assert ab.chamfer == pytest.approx(both.distances.sum(), rel=1e-13)
        assert ab.rmse == pytest.approx(both.rmse, rel=1e-13)
        assert ab.rmse_forward == pytest.approx(nearest(src, dst).rmse, rel=1e-13)


def test_triangle_inequality_of_hausdorff():
    for seed in range(20):
        rng = np.random.default_rng(seed)
        a, b, c = rng.random((10, 2)), rng.random((12, 2)) + 0.2, rng.random((8, 2)) - 0.3
        assert distance(a, c).hausdorff <= distance(a, b).hausdorff + distance(b, c).hausdorff \
            + 1e-12


# --- layer 3: agreement with brute force and scipy ---------------------------------------


@pytest.mark.parametrize("d", [1, 2, 3, 5])
def test_agrees_with_brute_force(d):
    for seed in SEEDS:
        rng = np.random.default_rng(seed)
        src = rng.standard_normal((int(rng.integers(1, 30)), d))
        dst = rng.standard_normal((int(rng.integers(1, 30)), d)) + 0.4
        res = distance(src, dst)
        full = cdist(src, dst)
        fwd, bwd = full.min(axis=1), full.min(axis=0)
        np.testing.assert_allclose(res.forward_distances, fwd, rtol=1e-12, atol=1e-15)
        np.testing.assert_allclose(res.backward_distances, bwd, rtol=1e-12, atol=1e-15)
        assert res.chamfer == pytest.approx(fwd.sum() + bwd.sum(), rel=1e-12)
        assert res.chamfer_mean == pytest.approx(fwd.mean() + bwd.mean(), rel=1e-12)
        assert res.hausdorff == pytest.approx(max(fwd.max(), bwd.max()), rel=1e-12)
        assert res.hausdorff_forward == pytest.approx(directed_hausdorff(src, dst)[0], rel=1e-12)
        assert res.hausdorff_backward == pytest.approx(directed_hausdorff(dst, src)[0], rel=1e-12)
        assert res.rmse == pytest.approx(np.sqrt(np.mean(np.r_[fwd, bwd] ** 2)), rel=1e-12)


def test_threaded_query_matches_serial():
    rng = np.random.default_rng(5)
    src, dst = rng.standard_normal((9000, 3)), rng.standard_normal((9500, 3))
    threaded, serial = distance(src, dst, workers=-1), distance(src, dst, workers=1)
    np.testing.assert_array_equal(threaded.forward_distances, serial.forward_distances)
    assert threaded.chamfer == serial.chamfer


# --- errors ----------------------------------------------------------------------------------


def test_error_too_few_points():
    with pytest.raises(InvalidInputError, match=r"`source` to hold at least 1 point, got 0") as info:
        distance(np.zeros((0, 1)), TARGET)
    assert info.value.field == "source"
    with pytest.raises(InvalidInputError, match=r"`target` to hold at least 1 point, got 0") as info:
        distance(SOURCE, np.zeros((0, 1)))
    assert info.value.field == "target"


def test_error_nonfinite():
    with pytest.raises(InvalidInputError, match=r"`source` to hold finite numbers, got nan at row 2"):
        distance([[0.0], [1.0], [np.nan]], TARGET)
    with pytest.raises(InvalidInputError, match=r"`target` to hold finite numbers, got inf at row 0"):
        distance(SOURCE, [[np.inf]])


def test_error_dimensions_differ():
    with pytest.raises(
        InvalidInputError, match=r"Expected `target` to have the same dimension as `source` \(1\)"
    ) as info:
        distance(SOURCE, [[0.0, 1.0]])
    assert info.value.field == "target"


@pytest.mark.parametrize(
    ("value", "message"),
    [
        (0, r"`workers` to be -1 \(every core\) or a positive integer, got 0\."),
        (-2, r"`workers` to be an integer >= -1, got -2\."),
    ],
)
def test_error_workers(value, message):
    with pytest.raises(InvalidInputError, match=message) as info:
        distance(SOURCE, TARGET, workers=value)
    assert info.value.field == "workers"


def test_docstring_examples_run():
    import doctest
    import sys

    module = sys.modules["algorithms.assignment.distance"]
    assert doctest.testmod(module, raise_on_error=False).failed == 0
