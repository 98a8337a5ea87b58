"""Tests for assignment.bipartite: hand cases (max_cost included), invariants, agreement with
scipy's linear_sum_assignment and with brute force, every error branch."""

from __future__ import annotations

import dataclasses
import itertools

import numpy as np
import pytest
from scipy.optimize import linear_sum_assignment
from scipy.spatial.distance import cdist

from algorithms.assignment import MAX_COST_ENTRIES, BipartiteResult, bipartite
from algorithms.core import InvalidInputError

SEEDS = range(100)
DIMS = (2, 3, 5)


# --- layer 1: computed by hand --------------------------------------------------------------


def test_hand_rectangular():
    # source 0, 1, 10; target 1.2, 0.1: 0-0.1 (0.1) + 1-1.2 (0.2) = 0.3 beats every other
    # matching of two; 10 stays single.
    res = bipartite([[0.0], [1.0], [10.0]], [[1.2], [0.1]])
    assert res.pairs.tolist() == [[0, 1], [1, 0]]
    np.testing.assert_allclose(res.distances, [0.1, 0.2], rtol=1e-12)
    assert res.cost == pytest.approx(0.3, rel=1e-12)
    assert res.rmse == pytest.approx(np.sqrt((0.01 + 0.04) / 2), rel=1e-12)
    assert res.n_pairs == 2
    assert res.unmatched_source.tolist() == [2] and res.unmatched_target.tolist() == []
    assert res.pairs.dtype == np.int64 and res.unmatched_source.dtype == np.int64
    assert res.unmatched_target.dtype == np.int64 and res.unmatched_target.shape == (0,)


def test_hand_metric_changes_the_matching():
    # source (4,3), (2,2); target (2,2), (1,3).
    # euclidean: straight sqrt5 + sqrt2 = 3.650 > crossed 3 + 0 = 3    -> crossed
    # sqeuclidean: straight 5 + 2 = 7 < crossed 9 + 0 = 9              -> straight
    src, dst = [[4.0, 3.0], [2.0, 2.0]], [[2.0, 2.0], [1.0, 3.0]]
    euc = bipartite(src, dst)
    assert euc.pairs.tolist() == [[0, 1], [1, 0]]
    assert euc.cost == pytest.approx(3.0, rel=1e-15)
    sq = bipartite(src, dst, metric="sqeuclidean")
    assert sq.pairs.tolist() == [[0, 0], [1, 1]]
    assert sq.cost == pytest.approx(7.0, rel=1e-15)
    np.testing.assert_allclose(sq.distances, [np.sqrt(5), np.sqrt(2)], rtol=1e-15)


def test_hand_max_cost_drops_a_far_pair():
    # source 0, 3; target 1, 10. Unlimited: 0-1 (1) + 3-10 (7) = 8 < 0-10 + 3-1 = 12.
    # max_cost 5: 3-10 costs 7 > 5, so 3 and 10 stay single; 0-1 saves 4 > 3-1 saves 3.
    full = bipartite([[0.0], [3.0]], [[1.0], [10.0]])
    assert full.pairs.tolist() == [[0, 0], [1, 1]] and full.cost == 8.0
    res = bipartite([[0.0], [3.0]], [[1.0], [10.0]], max_cost=5.0)
    assert res.pairs.tolist() == [[0, 0]]
    assert res.cost == 1.0 and res.n_pairs == 1
    assert res.unmatched_source.tolist() == [1] and res.unmatched_target.tolist() == [1]


def test_hand_max_cost_changes_who_is_matched():
    # source 0, 2; target 1.2, 4.5. Unlimited: 0-1.2 + 2-4.5 = 3.7 < 0-4.5 + 2-1.2 = 5.3.
    # max_cost 2: 2-4.5 (2.5) and 0-4.5 are out; 0-1.2 saves 0.8, 2-1.2 saves 1.2: the
    # second source point takes 1.2 and the first stays single.
    assert bipartite([[0.0], [2.0]], [[1.2], [4.5]]).pairs.tolist() == [[0, 0], [1, 1]]
    res = bipartite([[0.0], [2.0]], [[1.2], [4.5]], max_cost=2.0)
    assert res.pairs.tolist() == [[1, 0]]
    assert res.cost == pytest.approx(0.8, rel=1e-12)
    assert res.unmatched_source.tolist() == [0] and res.unmatched_target.tolist() == [1]


def test_hand_max_cost_keeps_equal_and_may_empty():
    res = bipartite([[0.0]], [[2.0]], max_cost=2.0)  # exactly at the limit: kept
    assert res.pairs.tolist() == [[0, 0]]
    empty = bipartite([[0.0], [5.0]], [[2.0], [9.0]], max_cost=1.5)
    assert empty.n_pairs == 0 and empty.cost == 0.0 and empty.rmse == 0.0
    assert empty.pairs.shape == (0, 2) and empty.pairs.dtype == np.int64
    assert empty.distances.shape == (0,)
    assert empty.unmatched_source.tolist() == [0, 1] and empty.unmatched_target.tolist() == [0, 1]


def test_max_cost_in_squared_units():
    # sqeuclidean: the pair 0-1.5 costs 2.25, within 2.5 but not within 2.0
    assert bipartite([[0.0]], [[1.5]], metric="sqeuclidean", max_cost=2.5).n_pairs == 1
    assert bipartite([[0.0]], [[1.5]], metric="sqeuclidean", max_cost=2.0).n_pairs == 0


def test_result_dataclass():
    names = [f.name for f in dataclasses.fields(BipartiteResult)]
    assert names == ["pairs", "distances", "cost", "rmse", "n_pairs", "unmatched_source",
                     "unmatched_target"]
    for name in names:
        assert f"\n    {name} : " in BipartiteResult.__doc__
    res = bipartite([[0.0]], [[1.0]])
    with pytest.raises(dataclasses.FrozenInstanceError):
        res.cost = 0.0  # type: ignore[misc]
    assert isinstance(res.cost, float) and isinstance(res.n_pairs, int)


# --- layer 2: invariants -----------------------------------------------------------------------


def _check_matching(res, n, m):
    s, t = res.pairs[:, 0], res.pairs[:, 1]
    assert len(set(s.tolist())) == len(s) and len(set(t.tolist())) == len(t)
    assert np.all(np.diff(s) > 0)  # sorted by source index
    assert sorted(s.tolist() + res.unmatched_source.tolist()) == list(range(n))
    assert sorted(t.tolist() + res.unmatched_target.tolist()) == list(range(m))
    assert res.n_pairs == len(s)


@pytest.mark.parametrize("d", DIMS)
def test_invariants(d):
    for seed in range(30):
        rng = np.random.default_rng(seed)
        n, m = (int(v) for v in rng.integers(1, 15, size=2))
        src, dst = rng.random((n, d)), rng.random((m, d))
        res = bipartite(src, dst)
        _check_matching(res, n, m)
        assert res.n_pairs == min(n, m)
        np.testing.assert_allclose(
            res.distances, np.linalg.norm(src[res.pairs[:, 0]] - dst[res.pairs[:, 1]], axis=1),
            rtol=1e-12)
        # permuting the target permutes the answer, not the cost
        perm = rng.permutation(m)
        assert bipartite(src, dst[perm]).cost == pytest.approx(res.cost, rel=1e-12)
        # swapping the sets swaps the pairs' roles, not the cost
        assert bipartite(dst, src).cost == pytest.approx(res.cost, rel=1e-12)
        # a translation of both sets changes nothing
        shifted = bipartite(src + 3.0, dst + 3.0)
        assert shifted.cost == pytest.approx(res.cost, rel=1e-9)
        # no limit binds above the largest cost; none is left below the smallest
        big = bipartite(src, dst, max_cost=float(cdist(src, dst).max()) * 2)
        np.testing.assert_array_equal(big.pairs, res.pairs)
        small = bipartite(src, dst, max_cost=float(cdist(src, dst).min()) / 2)
        assert small.n_pairs == 0


# --- layer 3: agreement with scipy and brute force ----------------------------------------


@pytest.mark.parametrize("metric", ["euclidean", "sqeuclidean"])
@pytest.mark.parametrize("d", DIMS)
def test_cost_equals_linear_sum_assignment(d, metric):
    for seed in SEEDS:
        rng = np.random.default_rng(seed)
        n, m = (int(v) for v in rng.integers(1, 30, size=2))
        src, dst = rng.standard_normal((n, d)), rng.standard_normal((m, d))
        res = bipartite(src, dst, metric=metric)
        cost = cdist(src, dst, metric)
        rows, cols = linear_sum_assignment(cost)
        assert res.cost == pytest.approx(cost[rows, cols].sum(), rel=1e-12), seed
        assert res.cost == pytest.approx(cost[res.pairs[:, 0], res.pairs[:, 1]].sum(), rel=1e-12)
        _check_matching(res, n, m)


def _lapjv_cost_limit(cost, tau):
    """The cost_limit construction of the LAPJV implementations: dummy rows and columns
    at tau/2, pairs above tau forbidden. Returns the optimal objective."""
    n, m = cost.shape
    big = np.full((n + m, m + n), np.inf)
    big[:n, :m] = np.where(cost <= tau, cost, np.inf)
    big[:n, m:][np.diag_indices(n)] = tau / 2
    big[n:, :m][np.diag_indices(m)] = tau / 2
    big[n:, m:] = 0.0
    r, c = linear_sum_assignment(big)
    return float(big[r, c].sum())


@pytest.mark.parametrize("d", DIMS)
def test_max_cost_agrees_with_dummy_construction(d):
    for seed in SEEDS:
        rng = np.random.default_rng(seed)
        n, m = (int(v) for v in rng.integers(1, 20, size=2))
        src, dst = rng.random((n, d)), rng.random((m, d))
        cost = cdist(src, dst)
        tau = float(np.quantile(cost, rng.uniform(0.05, 0.6)))
        res = bipartite(src, dst, max_cost=tau)
        objective = res.cost + tau / 2 * (n + m - 2 * res.n_pairs)
        assert objective == pytest.approx(_lapjv_cost_limit(cost, tau), rel=1e-12), seed
        assert np.all(res.distances <= tau)
        _check_matching(res, n, m)


def _brute_force_partial(cost, tau):
    """Least sum of (c - tau) over partial matchings using only pairs with c <= tau."""
    n, m = cost.shape
    best = 0.0
    for k in range(1, min(n, m) + 1):
        for rows in itertools.combinations(range(n), k):
            for cols in itertools.permutations(range(m), k):
                c = cost[list(rows), list(cols)]
                if np.all(c <= tau):
                    best = min(best, float((c - tau).sum()))
    return best


def test_max_cost_agrees_with_brute_force():
    for seed in range(40):
        rng = np.random.default_rng(seed)
        n, m = (int(v) for v in rng.integers(1, 5, size=2))
        src, dst = rng.random((n, 2)), rng.random((m, 2))
        cost = cdist(src, dst)
        tau = float(np.median(cost))
        res = bipartite(src, dst, max_cost=tau)
        assert res.cost - tau * res.n_pairs == pytest.approx(
            _brute_force_partial(cost, tau), rel=1e-12, abs=1e-15), seed


# --- errors ----------------------------------------------------------------------------------


def test_error_too_few_points():
    with pytest.raises(InvalidInputError, match=r"`source` to hold at least 1 point, got 0") as info:
        bipartite(np.zeros((0, 2)), [[0.0, 0.0]])
    assert info.value.field == "source"
    with pytest.raises(InvalidInputError, match=r"`target` to hold at least 1 point, got 0") as info:
        bipartite([[0.0, 0.0]], np.zeros((0, 2)))
    assert info.value.field == "target"


def test_error_nonfinite():
    with pytest.raises(InvalidInputError, match=r"`source` to hold finite numbers, got nan at row 0"):
        bipartite([[np.nan, 0.0]], [[1.0, 0.0]])
    with pytest.raises(InvalidInputError, match=r"`target` to hold finite numbers, got -inf at row 1"):
        bipartite([[0.0, 0.0]], [[1.0, 0.0], [-np.inf, 0.0]])


def test_error_dimensions_differ():
    with pytest.raises(
        InvalidInputError, match=r"Expected `target` to have the same dimension as `source` \(3\)"
    ) as info:
        bipartite([[0.0, 0.0, 0.0]], [[0.0, 0.0]])
    assert info.value.field == "target"


def test_error_metric():
    with pytest.raises(
        InvalidInputError,
        match=r"Expected `metric` to be one of 'euclidean', 'sqeuclidean', got 'cityblock'\.",
    ) as info:
        bipartite([[0.0]], [[1.0]], metric="cityblock")
    assert info.value.field == "metric"


@pytest.mark.parametrize(
    ("value", "message"),
    [
        (0.0, r"`max_cost` to be a number > 0, got 0.0"),
        (-2, r"`max_cost` to be a number > 0, got -2.0"),
        (float("nan"), r"`max_cost` to be a finite number, got nan"),
        (float("inf"), r"`max_cost` to be a finite number, got inf"),
        ("1", r"`max_cost` to be a number, got '1'"),
    ],
)
def test_error_max_cost(value, message):
    with pytest.raises(InvalidInputError, match=message) as info:
        bipartite([[0.0]], [[1.0]], max_cost=value)
    assert info.value.field == "max_cost"


def test_error_cost_matrix_too_large():
    # checked before any work: broadcast views cost no memory
    n = MAX_COST_ENTRIES // 1000 + 1
    src = np.broadcast_to(np.zeros(1), (n, 1))
    dst = np.zeros((1000, 1))
    with pytest.raises(
        InvalidInputError,
        match=r"Expected `source` and `target` to have at most 16,000,000 point pairs .*"
        r"got 16,001 × 1,000 = 16,001,000",
    ) as info:
        bipartite(src, dst)
    assert info.value.field == "source"  # the larger set


def test_docstring_examples_run():
    import doctest
    import sys

    module = sys.modules["algorithms.assignment.bipartite"]
    assert doctest.testmod(module, raise_on_error=False).failed == 0
