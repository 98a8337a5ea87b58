"""Tests for assignment.closest_pair: a hand case, brute-force agreement, every error branch."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from scipy.spatial.distance import cdist

from algorithms.assignment import ClosestPairResult, closest_pair
from algorithms.core import InvalidInputError

SEEDS = range(100)


# --- layer 1: computed by hand --------------------------------------------------------------


def test_hand_case():
    # source (0,0), (5,5); target (1,1), (4,4.5), (9,9): the closest pair is (5,5)-(4,4.5),
    # at sqrt(1 + 0.25); (0,0)-(1,1) is sqrt(2).
    res = closest_pair([[0.0, 0.0], [5.0, 5.0]], [[1.0, 1.0], [4.0, 4.5], [9.0, 9.0]])
    assert (res.source_index, res.target_index) == (1, 1)
    assert res.distance == pytest.approx(np.sqrt(1.25), rel=1e-15)
    assert res.pairs.tolist() == [[1, 1]] and res.pairs.dtype == np.int64
    assert res.distances.tolist() == [res.distance] and res.distances.dtype == np.float64
    assert isinstance(res.source_index, int) and isinstance(res.distance, float)


def test_hand_case_larger_source_and_single_points():
    # the tree goes on the smaller set (here target); indices still read (source, target)
    res = closest_pair([[10.0], [3.0], [7.0], [-1.0]], [[2.5]])
    assert (res.source_index, res.target_index, res.distance) == (1, 0, 0.5)
    one = closest_pair([[1.0, 2.0, 3.0]], [[1.0, 2.0, 5.0]])
    assert (one.source_index, one.target_index, one.distance) == (0, 0, 2.0)


def test_shared_point_gives_zero():
    res = closest_pair([[0.0, 0.0], [3.0, 4.0]], [[9.0, 9.0], [3.0, 4.0]])
    assert (res.source_index, res.target_index, res.distance) == (1, 1, 0.0)


def test_ties_are_deterministic():
    # (0) and (2) are both 1 away from (1): one of them, the same every time
    first = closest_pair([[0.0], [2.0]], [[1.0]])
    assert first.distance == 1.0 and first.source_index in (0, 1)
    for _ in range(3):
        assert closest_pair([[0.0], [2.0]], [[1.0]]).source_index == first.source_index


def test_result_dataclass():
    names = [f.name for f in dataclasses.fields(ClosestPairResult)]
    assert names == ["source_index", "target_index", "distance", "pairs", "distances"]
    for name in names:
        assert f"\n    {name} : " in ClosestPairResult.__doc__
    res = closest_pair([[0.0]], [[1.0]])
    with pytest.raises(dataclasses.FrozenInstanceError):
        res.distance = 0.0  # type: ignore[misc]


# --- layer 2/3: invariants and agreement with brute force (cdist) ----------------------------


@pytest.mark.parametrize("d", [1, 2, 3, 5])
def test_agrees_with_brute_force(d):
    for seed in SEEDS:
        rng = np.random.default_rng(seed)
        src = rng.standard_normal((int(rng.integers(1, 40)), d))
        dst = rng.standard_normal((int(rng.integers(1, 40)), d)) + 0.5
        res = closest_pair(src, dst)
        dist = cdist(src, dst)
        i, j = np.unravel_index(np.argmin(dist), dist.shape)
        assert res.distance == pytest.approx(dist[i, j], rel=1e-12, abs=1e-15), seed
        assert (res.source_index, res.target_index) == (i, j), seed  # no ties in random data
        assert res.distance == pytest.approx(
            np.linalg.norm(src[res.source_index] - dst[res.target_index]), rel=1e-12)


def test_swapping_sets_swaps_the_pair():
    for seed in range(20):
        rng = np.random.default_rng(seed)
        src, dst = rng.random((30, 3)), rng.random((17, 3))
        ab, ba = closest_pair(src, dst), closest_pair(dst, src)
        assert (ab.source_index, ab.target_index) == (ba.target_index, ba.source_index)
        assert ab.distance == ba.distance


def test_threaded_query_matches_serial():
    rng = np.random.default_rng(3)
    src, dst = rng.standard_normal((9000, 3)), rng.standard_normal((300, 3))
    threaded = closest_pair(src, dst, workers=-1)
    serial = closest_pair(src, dst, workers=1)
    assert (threaded.source_index, threaded.target_index, threaded.distance) == \
        (serial.source_index, serial.target_index, serial.distance)


# --- errors ----------------------------------------------------------------------------------


def test_error_too_few_points():
    with pytest.raises(InvalidInputError, match=r"`source` to hold at least 1 point, got 0") as info:
        closest_pair(np.zeros((0, 2)), [[0.0, 0.0]])
    assert info.value.field == "source"
    with pytest.raises(InvalidInputError, match=r"`target` to hold at least 1 point, got 0") as info:
        closest_pair([[0.0, 0.0]], np.zeros((0, 2)))
    assert info.value.field == "target"


def test_error_nonfinite():
    with pytest.raises(InvalidInputError, match=r"`source` to hold finite numbers, got nan at row 1"):
        closest_pair([[0.0], [np.nan]], [[1.0]])
    with pytest.raises(InvalidInputError, match=r"`target` to hold finite numbers, got inf at row 0"):
        closest_pair([[0.0]], [[np.inf]])


def test_error_dimensions_differ():
    with pytest.raises(
        InvalidInputError, match=r"Expected `target` to have the same dimension as `source` \(2\)"
    ) as info:
        closest_pair([[0.0, 0.0]], [[0.0, 0.0, 0.0]])
    assert info.value.field == "target"


def test_error_not_2d():
    with pytest.raises(InvalidInputError, match=r"`source` to be an \(n, d\) array .* got shape \(3,\)"):
        closest_pair([0.0, 1.0, 2.0], [[0.0]])


@pytest.mark.parametrize(
    ("value", "message"),
    [
        (0, r"`workers` to be -1 \(every core\) or a positive integer, got 0\."),
        (-3, r"`workers` to be an integer >= -1, got -3\."),
        (2.5, r"`workers` to be an integer, got 2.5"),
    ],
)
def test_error_workers(value, message):
    with pytest.raises(InvalidInputError, match=message) as info:
        closest_pair([[0.0]], [[1.0]], workers=value)
    assert info.value.field == "workers"


def test_docstring_examples_run():
    import doctest
    import sys

    module = sys.modules["algorithms.assignment.closest_pair"]
    assert doctest.testmod(module, raise_on_error=False).failed == 0
