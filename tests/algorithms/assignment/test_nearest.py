"""Tests for assignment.nearest: a hand case, brute-force agreement, every error branch."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from scipy.spatial.distance import cdist

from algorithms.assignment import DIRECTIONS, NearestResult, nearest
from algorithms.core import InvalidInputError

SEEDS = range(100)

# Points on a line: source 0, 2, 7; target 1.5, 6, 10.
SOURCE = [[0.0], [2.0], [7.0]]
TARGET = [[1.5], [6.0], [10.0]]


# --- layer 1: computed by hand --------------------------------------------------------------


def test_hand_forward():
    # 0 -> 1.5 (1.5); 2 -> 1.5 (0.5); 7 -> 6 (1.0)
    res = nearest(SOURCE, TARGET)
    assert res.pairs.tolist() == [[0, 0], [1, 0], [2, 1]]
    assert res.distances.tolist() == [1.5, 0.5, 1.0]
    assert res.n_pairs == 3
    assert res.rmse == pytest.approx(np.sqrt((2.25 + 0.25 + 1.0) / 3), rel=1e-15)
    assert res.pairs.dtype == np.int64 and res.pairs.shape == (3, 2)
    assert res.distances.dtype == np.float64


def test_hand_backward():
    # target 1.5 -> source 2 (0.5); 6 -> 7 (1.0); 10 -> 7 (3.0); pairs stay (source, target)
    res = nearest(SOURCE, TARGET, direction="backward")
    assert res.pairs.tolist() == [[1, 0], [2, 1], [2, 2]]
    assert res.distances.tolist() == [0.5, 1.0, 3.0]


def test_hand_union_intersection_both():
    union = nearest(SOURCE, TARGET, direction="union")
    assert union.pairs.tolist() == [[0, 0], [1, 0], [2, 1], [2, 2]]
    assert union.distances.tolist() == [1.5, 0.5, 1.0, 3.0]
    mutual = nearest(SOURCE, TARGET, direction="intersection")
    assert mutual.pairs.tolist() == [[1, 0], [2, 1]]
    assert mutual.distances.tolist() == [0.5, 1.0]
    both = nearest(SOURCE, TARGET, direction="both")
    assert both.pairs.tolist() == [[0, 0], [1, 0], [2, 1], [1, 0], [2, 1], [2, 2]]
    # Chamfer: forward 1.5 + 0.5 + 1.0 = 3.0, backward 0.5 + 1.0 + 3.0 = 4.5
    assert both.distances.sum() == pytest.approx(7.5, abs=1e-15)
    assert both.n_pairs == 6


def test_hand_k2():
    # 0 -> 1.5 (1.5), 6 (6); 2 -> 1.5 (0.5), 6 (4); 7 -> 6 (1), 10 (3)
    res = nearest(SOURCE, TARGET, k=2)
    assert res.pairs.tolist() == [[0, 0], [0, 1], [1, 0], [1, 1], [2, 1], [2, 2]]
    assert res.distances.tolist() == [1.5, 6.0, 0.5, 4.0, 1.0, 3.0]


def test_hand_max_distance_keeps_equal_and_may_empty():
    res = nearest(SOURCE, TARGET, max_distance=1.0)
    assert res.pairs.tolist() == [[1, 0], [2, 1]]  # 1.0 itself is kept, 1.5 dropped
    assert res.distances.tolist() == [0.5, 1.0]
    empty = nearest(SOURCE, TARGET, max_distance=0.1, direction="union")
    assert empty.n_pairs == 0 and empty.rmse == 0.0
    assert empty.pairs.shape == (0, 2) and empty.pairs.dtype == np.int64
    assert empty.distances.shape == (0,)


def test_ties_give_a_valid_deterministic_answer():
    # 0.5 is equally far from 0 and 1: either index is correct; the same call agrees with itself.
    first = nearest([[0.5]], [[0.0], [1.0]])
    assert first.distances.tolist() == [0.5]
    assert first.pairs[0, 1] in (0, 1)
    for _ in range(3):
        np.testing.assert_array_equal(nearest([[0.5]], [[0.0], [1.0]]).pairs, first.pairs)


def test_result_dataclass():
    names = [f.name for f in dataclasses.fields(NearestResult)]
    assert names == ["pairs", "distances", "rmse", "n_pairs"]
    for name in names:
        assert f"\n    {name} : " in NearestResult.__doc__
    res = nearest(SOURCE, TARGET)
    with pytest.raises(dataclasses.FrozenInstanceError):
        res.n_pairs = 0  # type: ignore[misc]
    assert isinstance(res.rmse, float) and isinstance(res.n_pairs, int)


# --- layer 2/3: agreement with brute force (cdist + argsort) ----------------------------------


def brute_force(src, dst, k, direction, max_distance=None):
    dist = cdist(src, dst)
    order_f = np.argsort(dist, axis=1, kind="stable")[:, :k]
    order_b = np.argsort(dist.T, axis=1, kind="stable")[:, :k]
    fwd = [(i, int(j)) for i in range(len(src)) for j in order_f[i]]
    bwd = [(int(i), j) for j in range(len(dst)) for i in order_b[j]]
    if max_distance is not None:
        fwd = [p for p in fwd if dist[p] <= max_distance]
        bwd = [p for p in bwd if dist[p] <= max_distance]
    pairs = {
        "forward": fwd,
        "backward": bwd,
        "both": fwd + bwd,
        "union": sorted(set(fwd) | set(bwd)),
        "intersection": sorted(set(fwd) & set(bwd)),
    }[direction]
    pairs_arr = np.array(pairs, dtype=np.int64).reshape(-1, 2)
    return pairs_arr, dist[pairs_arr[:, 0], pairs_arr[:, 1]]


@pytest.mark.parametrize("d", [1, 2, 3, 5])
@pytest.mark.parametrize("k", [1, 3])
@pytest.mark.parametrize("direction", DIRECTIONS)
def test_agrees_with_brute_force(direction, k, d):
    for seed in SEEDS:
        rng = np.random.default_rng(seed)
        src = rng.standard_normal((int(rng.integers(3, 25)), d))
        dst = rng.standard_normal((int(rng.integers(3, 25)), d)) + 0.3
        res = nearest(src, dst, k=k, direction=direction)
        pairs, dist = brute_force(src, dst, k, direction)
        np.testing.assert_array_equal(res.pairs, pairs, err_msg=f"seed {seed}")
        np.testing.assert_allclose(res.distances, dist, rtol=1e-12, atol=1e-14)
        assert res.n_pairs == len(pairs)
        assert res.rmse == pytest.approx(np.sqrt(np.mean(dist**2)), rel=1e-12)


@pytest.mark.parametrize("direction", DIRECTIONS)
def test_max_distance_agrees_with_brute_force(direction):
    for seed in SEEDS:
        rng = np.random.default_rng(seed)
        d = 1 + seed % 4
        src = rng.standard_normal((15, d))
        dst = rng.standard_normal((12, d))
        radius = float(np.median(cdist(src, dst).min(axis=1)))
        res = nearest(src, dst, k=2, direction=direction, max_distance=radius)
        pairs, dist = brute_force(src, dst, 2, direction, max_distance=radius)
        np.testing.assert_array_equal(res.pairs, pairs, err_msg=f"seed {seed}")
        np.testing.assert_allclose(res.distances, dist, rtol=1e-12, atol=1e-14)
        assert np.all(res.distances <= radius)


def test_chamfer_sum_and_workers():
    rng = np.random.default_rng(0)
    src, dst = rng.standard_normal((40, 3)), rng.standard_normal((30, 3))
    dist = cdist(src, dst)
    chamfer = dist.min(axis=1).sum() + dist.min(axis=0).sum()
    res = nearest(src, dst, direction="both", workers=1)
    assert res.distances.sum() == pytest.approx(chamfer, rel=1e-12)
    again = nearest(src, dst, direction="both", workers=2)
    np.testing.assert_array_equal(again.pairs, res.pairs)


def test_k_equal_to_set_size_and_accepts_lists_and_ints():
    res = nearest([[0, 0], [5, 5]], np.array([[1, 1], [4, 4], [10, 10]], dtype=np.int32), k=3)
    assert res.n_pairs == 6
    assert res.pairs[:3, 1].tolist() == [0, 1, 2] and res.pairs[3:, 1].tolist() == [1, 0, 2]


# --- errors ----------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("direction", "message"),
    [
        ("forward", r"<= 3 \(the number of `target` points\), got 4\."),
        ("backward", r"<= 2 \(the number of `source` points\), got 4\."),
        ("union", r"<= 2 \(the size of the smaller point set, `source`\), got 4\."),
        ("intersection", r"<= 2 \(the size of the smaller point set, `source`\), got 4\."),
        ("both", r"<= 2 \(the size of the smaller point set, `source`\), got 4\."),
    ],
)
def test_error_k_too_large(direction, message):
    with pytest.raises(InvalidInputError, match=r"^Expected `k` to be an integer >= 1 and " + message) as info:
        nearest([[0.0], [1.0]], [[0.0], [1.0], [2.0]], k=4, direction=direction)
    assert info.value.field == "k"


@pytest.mark.parametrize("k", [0, -1])
def test_error_k_too_small(k):
    with pytest.raises(InvalidInputError, match=rf"Expected `k` to be an integer >= 1.*got {k}\."):
        nearest(SOURCE, TARGET, k=k)


@pytest.mark.parametrize("k", [1.5, True, "2", None])
def test_error_k_not_integer(k):
    with pytest.raises(InvalidInputError, match=r"^Expected `k` to be an integer, got"):
        nearest(SOURCE, TARGET, k=k)


def test_error_direction():
    with pytest.raises(
        InvalidInputError,
        match=r"Expected `direction` to be one of 'forward', 'backward', 'union', "
        r"'intersection', 'both', got 'sideways'\.",
    ) as info:
        nearest(SOURCE, TARGET, direction="sideways")
    assert info.value.field == "direction"


@pytest.mark.parametrize(
    ("value", "message"),
    [
        (0.0, r"`max_distance` to be a number > 0, got 0.0"),
        (-1, r"`max_distance` to be a number > 0, got -1.0"),
        (float("nan"), r"`max_distance` to be a finite number, got nan"),
        (float("inf"), r"`max_distance` to be a finite number, got inf"),
        ("1", r"`max_distance` to be a number, got '1'"),
    ],
)
def test_error_max_distance(value, message):
    with pytest.raises(InvalidInputError, match=message) as info:
        nearest(SOURCE, TARGET, max_distance=value)
    assert info.value.field == "max_distance"


@pytest.mark.parametrize(
    ("value", "message"),
    [
        (0, r"`workers` to be -1 \(every core\) or a positive integer, got 0\."),
        (-2, r"`workers` to be an integer >= -1, got -2\."),
        (1.5, r"`workers` to be an integer, got 1.5"),
    ],
)
def test_error_workers(value, message):
    with pytest.raises(InvalidInputError, match=message) as info:
        nearest(SOURCE, TARGET, workers=value)
    assert info.value.field == "workers"


def test_error_dimensions_differ():
    with pytest.raises(
        InvalidInputError, match=r"Expected `target` to have the same dimension as `source` \(1\)"
    ) as info:
        nearest(SOURCE, [[0.0, 1.0]])
    assert info.value.field == "target"


def test_error_empty_and_1d_and_nonfinite():
    with pytest.raises(InvalidInputError, match=r"`target` to hold at least 1 point, got 0"):
        nearest(SOURCE, np.zeros((0, 1)))
    with pytest.raises(InvalidInputError, match=r"`source` to be an \(n, d\) array .* got shape \(3,\)"):
        nearest([0.0, 2.0, 7.0], TARGET)
    with pytest.raises(InvalidInputError, match=r"`source` to hold finite numbers, got nan at row 1"):
        nearest([[0.0], [np.nan]], TARGET)
    with pytest.raises(InvalidInputError, match=r"`target` to hold finite numbers, got -inf at row 2"):
        nearest(SOURCE, [[0.0], [1.0], [-np.inf]])


def test_threaded_query_matches_serial():
    rng = np.random.default_rng(1)
    src, dst = rng.standard_normal((9000, 3)), rng.standard_normal((500, 3))
    threaded = nearest(src, dst, k=2, workers=-1)  # above SERIAL_BELOW: really threaded
    serial = nearest(src, dst, k=2, workers=1)
    np.testing.assert_array_equal(threaded.pairs, serial.pairs)
    np.testing.assert_array_equal(threaded.distances, serial.distances)


def test_docstring_examples_run():
    import doctest
    import sys

    module = sys.modules["algorithms.assignment.nearest"]
    assert doctest.testmod(module, raise_on_error=False).failed == 0
