"""Tests for assignment.optimal_transport: hand cases, invariants, agreement with POT (exact
cost against ``ot.emd2``, Sinkhorn against ``ot.sinkhorn2``), every error branch."""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np
import ot  # POT, the peer: a test dependency
import pytest
import scipy.sparse as sp
from scipy.optimize import linear_sum_assignment, linprog
from scipy.spatial.distance import cdist

from algorithms.assignment import MAX_COST_ENTRIES, TransportResult, optimal_transport
from algorithms.core import Cancelled, ConvergenceWarning, InvalidInputError

SEEDS = range(100)
DIMS = (2, 3, 5)


def _module():
    import sys

    return sys.modules["algorithms.assignment.optimal_transport"]


def _dense(res, n, m):
    plan = np.zeros((n, m))
    np.add.at(plan, (res.pairs[:, 0], res.pairs[:, 1]), res.masses)
    return plan


# --- layer 1: computed by hand --------------------------------------------------------------


def test_hand_weighted_line():
    # a = (3/4, 1/4) at 0, 1; b = (1/2, 1/2) at 0, 2; squared costs [[0, 4], [1, 1]].
    # P01 = 3/4 - P00 >= 1/4, cost = 4 P01 + 1/4 is least at P00 = 1/2, P01 = P11 = 1/4.
    res = optimal_transport([[0.0], [1.0]], [[0.0], [2.0]], source_weights=[3, 1])
    assert res.pairs.tolist() == [[0, 0], [0, 1], [1, 1]]
    np.testing.assert_allclose(res.masses, [0.5, 0.25, 0.25], atol=1e-15)
    np.testing.assert_allclose(res.distances, [0.0, 2.0, 1.0], atol=1e-15)
    assert res.cost == pytest.approx(1.25, rel=1e-14)
    assert res.rmse == pytest.approx(np.sqrt(1.25), rel=1e-14)
    assert res.solver == "network_simplex" and res.converged and res.iterations == 0
    assert res.marginal_error < 1e-14
    # earth mover's distance on the same masses: 0.25 * 2 + 0.25 * 1 = 0.75
    emd = optimal_transport([[0.0], [1.0]], [[0.0], [2.0]], source_weights=[3, 1],
                            metric="euclidean")
    assert emd.cost == pytest.approx(0.75, rel=1e-14)


def test_hand_uniform_equal_sizes_is_a_permutation():
    # 0, 1 onto 1.1, 0.2: the crossing-free permutation 0->0.2, 1->1.1, each mass 1/2
    res = optimal_transport([[0.0], [1.0]], [[1.1], [0.2]])
    assert res.solver == "assignment" and res.iterations == 0 and res.converged
    assert res.pairs.tolist() == [[0, 1], [1, 0]]
    assert res.masses.tolist() == [0.5, 0.5]
    assert res.cost == pytest.approx(0.5 * (0.04 + 0.01), rel=1e-12)
    assert res.marginal_error == 0.0


def test_hand_split_mass():
    # one source point of mass 1 onto three targets of masses 1/2, 1/4, 1/4
    res = optimal_transport([[0.0, 0.0]], [[1.0, 0.0], [0.0, 2.0], [0.0, -3.0]],
                            target_weights=[2, 1, 1])
    assert res.pairs.tolist() == [[0, 0], [0, 1], [0, 2]]
    np.testing.assert_allclose(res.masses, [0.5, 0.25, 0.25], rtol=1e-14)
    assert res.cost == pytest.approx(0.5 * 1 + 0.25 * 4 + 0.25 * 9, rel=1e-14)


def test_zero_weights_take_no_part():
    res = optimal_transport([[0.0], [5.0], [1.0]], [[0.1], [1.2]], source_weights=[1, 0, 1])
    assert res.solver == "assignment"  # two points of equal mass on each side
    assert res.pairs.tolist() == [[0, 0], [2, 1]]
    assert 1 not in res.pairs[:, 0]
    sk = optimal_transport([[0.0], [5.0], [1.0]], [[0.1], [1.2]], source_weights=[1, 0, 1],
                           method="sinkhorn", reg=0.01)
    assert 1 not in sk.pairs[:, 0]


def test_weights_are_relative():
    a = optimal_transport([[0.0], [1.0]], [[0.5], [3.0]], source_weights=[1, 3])
    b = optimal_transport([[0.0], [1.0]], [[0.5], [3.0]], source_weights=[1e-3, 3e-3])
    c = optimal_transport([[0.0], [1.0]], [[0.5], [3.0]], source_weights=[1e300, 3e300])
    assert a.cost == pytest.approx(b.cost, rel=1e-14) == pytest.approx(c.cost, rel=1e-14)


def test_identical_points_cost_nothing():
    pts = [[0.0, 0.0], [1.0, 1.0], [2.0, 0.0]]
    res = optimal_transport(pts, pts, source_weights=[1, 2, 3], target_weights=[1, 2, 3])
    assert res.cost == 0.0 and res.pairs.tolist() == [[0, 0], [1, 1], [2, 2]]
    same = optimal_transport([[1.0], [1.0]], [[1.0], [1.0], [1.0]])  # every cost 0
    assert same.cost == 0.0 and same.masses.sum() == pytest.approx(1.0, rel=1e-15)


def test_result_dataclass():
    names = [f.name for f in dataclasses.fields(TransportResult)]
    assert names == ["pairs", "masses", "distances", "cost", "rmse", "marginal_error",
                     "n_pairs", "iterations", "converged", "solver"]
    for name in names:
        assert f"\n    {name} : " in TransportResult.__doc__
    res = optimal_transport([[0.0]], [[1.0]])
    with pytest.raises(dataclasses.FrozenInstanceError):
        res.cost = 0.0  # type: ignore[misc]
    assert isinstance(res.cost, float) and isinstance(res.n_pairs, int)
    assert isinstance(res.converged, bool) and isinstance(res.iterations, int)


# --- layer 2: invariants -----------------------------------------------------------------------


def _case(seed, d, *, weighted=True):
    rng = np.random.default_rng(seed)
    n, m = (int(v) for v in rng.integers(1, 25, size=2))
    src, dst = rng.random((n, d)), rng.random((m, d))
    wa = rng.random(n) if weighted else None
    wb = rng.random(m) if weighted else None
    return src, dst, wa, wb


@pytest.mark.parametrize("d", DIMS)
def test_exact_plan_is_feasible_and_sparse(d):
    for seed in range(30):
        src, dst, wa, wb = _case(seed, d)
        res = optimal_transport(src, dst, source_weights=wa, target_weights=wb)
        n, m = len(src), len(dst)
        plan = _dense(res, n, m)
        np.testing.assert_allclose(plan.sum(axis=1), wa / wa.sum(), atol=1e-12)
        np.testing.assert_allclose(plan.sum(axis=0), wb / wb.sum(), atol=1e-12)
        assert np.all(res.masses > 0) and res.n_pairs <= n + m - 1  # a basic solution
        assert res.marginal_error < 1e-12
        assert res.cost == pytest.approx(float((plan * cdist(src, dst, "sqeuclidean")).sum()),
                                         rel=1e-12)
        keys = res.pairs[:, 0] * m + res.pairs[:, 1]
        assert np.all(np.diff(keys) > 0)  # sorted, each pair once


def test_network_simplex_agrees_with_assignment_on_uniform_masses():
    simplex = _module()._exact_network_simplex
    for seed in range(20):
        rng = np.random.default_rng(seed)
        n = int(rng.integers(2, 30))
        cost = cdist(rng.random((n, 3)), rng.random((n, 3)), "sqeuclidean")
        u = np.full(n, 1.0 / n)
        rows, cols, mass, _ = simplex(cost, u, u)
        r, c = linear_sum_assignment(cost)
        assert float(mass @ cost[rows, cols]) == pytest.approx(cost[r, c].sum() / n, rel=1e-12)


def _linprog_cost(cost, a, b):
    """The transport LP solved by HiGHS over every pair: a solver independent of POT's."""
    n, m = cost.shape
    rows = np.concatenate([np.repeat(np.arange(n), m), n + np.tile(np.arange(m), n)])
    a_eq = sp.csc_array((np.ones(2 * n * m), (rows, np.tile(np.arange(n * m), 2))),
                        shape=(n + m, n * m))
    res = linprog(cost.ravel(), A_eq=a_eq[:-1], b_eq=np.concatenate([a, b])[:-1],
                  bounds=(0, None), method="highs")
    assert res.status == 0
    return res.fun


def test_exact_cost_equals_an_independent_lp():
    for seed in range(30):
        rng = np.random.default_rng(seed)
        n, m = (int(v) for v in rng.integers(1, 40, size=2))
        src, dst = rng.random((n, 2)), rng.random((m, 2))
        wa, wb = rng.random(n) + 0.01, rng.random(m) + 0.01
        metric = ("sqeuclidean", "euclidean")[seed % 2]
        res = optimal_transport(src, dst, source_weights=wa, target_weights=wb, metric=metric)
        ref = _linprog_cost(cdist(src, dst, metric), wa / wa.sum(), wb / wb.sum())
        assert res.cost == pytest.approx(ref, rel=1e-9, abs=1e-14), seed
        assert res.n_pairs <= n + m - 1  # a basic solution


def test_sinkhorn_plan_and_figures():
    rng = np.random.default_rng(1)
    src, dst = rng.random((20, 2)), rng.random((15, 2))
    wb = rng.random(15)
    res = optimal_transport(src, dst, target_weights=wb, method="sinkhorn", reg=0.1)
    assert res.solver == "sinkhorn" and res.converged and res.marginal_error <= 1e-9
    plan = _dense(res, 20, 15)
    np.testing.assert_allclose(plan.sum(axis=1), np.full(20, 1 / 20), atol=1e-9)
    np.testing.assert_allclose(plan.sum(axis=0), wb / wb.sum(), atol=1e-9)
    assert res.n_pairs == 300  # an entropic plan is dense at this regularisation
    assert res.cost == pytest.approx(float((plan * cdist(src, dst, "sqeuclidean")).sum()),
                                     rel=1e-9)
    assert res.rmse == pytest.approx(np.sqrt(res.masses @ res.distances**2), rel=1e-12)


def test_sinkhorn_over_relaxation_same_plan_fewer_iterations():
    mod = _module()
    rng = np.random.default_rng(1)
    src, dst = rng.random((40, 2)), rng.random((40, 2))
    relaxed = optimal_transport(src, dst, method="sinkhorn", reg=0.01)
    old = mod.SOR_MAX
    try:
        mod.SOR_MAX = 1.0  # never relax: plain Sinkhorn
        plain = optimal_transport(src, dst, method="sinkhorn", reg=0.01)
    finally:
        mod.SOR_MAX = old
    assert relaxed.converged and plain.converged
    assert relaxed.iterations < plain.iterations / 2
    assert relaxed.cost == pytest.approx(plain.cost, rel=1e-8)
    np.testing.assert_array_equal(relaxed.pairs, plain.pairs)
    np.testing.assert_allclose(relaxed.masses, plain.masses, atol=1e-9)


def test_sinkhorn_not_converging_warns():
    rng = np.random.default_rng(2)
    src, dst = rng.random((10, 2)), rng.random((12, 2))
    with pytest.warns(ConvergenceWarning, match=r"Sinkhorn stopped after 3 iterations .* "
                      r"raise `max_iterations` or `reg`"):
        res = optimal_transport(src, dst, method="sinkhorn", reg=0.01, max_iterations=3)
    assert not res.converged and res.iterations == 3 and res.marginal_error > 1e-9
    assert np.isfinite(res.cost)


def test_sinkhorn_progress_and_cancel():
    rng = np.random.default_rng(3)
    src, dst = rng.random((10, 2)), rng.random((10, 2))
    seen = []
    with pytest.warns(ConvergenceWarning):
        optimal_transport(src, dst, method="sinkhorn", reg=1e-3, max_iterations=120,
                          tolerance=1e-15, progress=lambda *a: seen.append(a))
    assert [s[:2] for s in seen] == [(50, 120), (100, 120)]
    assert "Sinkhorn iteration 50" in seen[0][2]

    def stop(done, total, message=""):
        raise Cancelled("stop")

    with pytest.raises(Cancelled):
        optimal_transport(src, dst, method="sinkhorn", reg=1e-3, max_iterations=500,
                          tolerance=1e-15, progress=stop)
    with pytest.raises(Cancelled):  # the network simplex path reports before it solves
        optimal_transport(src, dst, source_weights=np.arange(1, 11), progress=stop)


def test_sinkhorn_small_reg_does_not_overflow():
    # reg 1e-3 on unit-scale data: exp(-C/reg) underflows to 0 for most pairs; the log
    # domain never forms it. No overflow, no division by zero, no NaN.
    rng = np.random.default_rng(4)
    src, dst = rng.random((30, 2)), rng.random((25, 2))
    exact = optimal_transport(src, dst).cost
    with np.errstate(over="raise", divide="raise", invalid="raise"), warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        res = optimal_transport(src, dst, method="sinkhorn", reg=1e-3, max_iterations=3000)
    assert np.isfinite(res.cost) and np.all(np.isfinite(res.masses))
    assert res.marginal_error < 1e-4
    assert abs(res.cost - exact) < 1e-3 * np.log(30 * 25) + res.marginal_error * 2


# --- layer 3: agreement with POT -----------------------------------------------------------


@pytest.mark.parametrize("d", DIMS)
def test_exact_cost_equals_pot_emd2(d):
    for seed in SEEDS:
        src, dst, wa, wb = _case(seed, d)
        if seed % 10 == 0:
            wa[0] = 0.0  # a point without mass
        res = optimal_transport(src, dst, source_weights=wa, target_weights=wb)
        ref = ot.emd2(wa / wa.sum(), wb / wb.sum(), cdist(src, dst, "sqeuclidean"))
        assert res.cost == pytest.approx(ref, rel=1e-10, abs=1e-14), seed


def test_exact_larger_sets_equal_pot_emd2():
    for seed in range(12):
        rng = np.random.default_rng(seed)
        d = DIMS[seed % 3]
        n, m = (int(v) for v in rng.integers(50, 90, size=2))
        src, dst = rng.random((n, d)), rng.random((m, d))
        wa, wb = rng.random(n), rng.random(m)
        res = optimal_transport(src, dst, source_weights=wa, target_weights=wb,
                                metric=("sqeuclidean", "euclidean")[seed % 2])
        ref = ot.emd2(wa / wa.sum(), wb / wb.sum(),
                      cdist(src, dst, ("sqeuclidean", "euclidean")[seed % 2]))
        assert res.cost == pytest.approx(ref, rel=1e-10), seed
        assert res.solver == "network_simplex" and res.n_pairs <= n + m - 1


@pytest.mark.parametrize("d", DIMS)
def test_exact_uniform_cost_equals_pot_emd2(d):
    for seed in SEEDS:
        rng = np.random.default_rng(seed)
        n = int(rng.integers(1, 40))
        m = n if seed % 2 else int(rng.integers(1, 40))  # assignment, and network simplex
        src, dst = rng.standard_normal((n, d)), rng.standard_normal((m, d))
        res = optimal_transport(src, dst, metric="euclidean")
        ref = ot.emd2(np.full(n, 1 / n), np.full(m, 1 / m), cdist(src, dst))
        assert res.cost == pytest.approx(ref, rel=1e-10), seed
        assert res.solver == ("assignment" if n == m else "network_simplex")


@pytest.mark.parametrize("d", DIMS)
def test_sinkhorn_equals_pot_sinkhorn2(d):
    for seed in range(20):
        src, dst, wa, wb = _case(seed, d)
        a, b = wa / wa.sum(), wb / wb.sum()
        res = optimal_transport(src, dst, source_weights=wa, target_weights=wb,
                                method="sinkhorn", reg=0.2, tolerance=1e-11,
                                max_iterations=20000)
        assert res.converged, seed
        ref = ot.sinkhorn2(a, b, cdist(src, dst, "sqeuclidean"), 0.2, method="sinkhorn_log",
                           stopThr=1e-12, numItermax=20000)
        assert res.cost == pytest.approx(float(ref), rel=1e-7), seed


@pytest.mark.parametrize("d", DIMS)
def test_sinkhorn_approaches_exact_as_reg_shrinks(d):
    # 0 <= cost(P_eps) - OT <= eps log(nm) for the converged entropic plan (the entropies
    # of both plans lie in [0, log nm]), so the gap shrinks with eps.
    for seed in range(25):
        rng = np.random.default_rng(seed)
        n, m = (int(v) for v in rng.integers(5, 15, size=2))
        src, dst = rng.random((n, d)), rng.random((m, d))
        exact = optimal_transport(src, dst).cost
        gaps = []
        for reg in (0.3, 0.1, 0.03):
            res = optimal_transport(src, dst, method="sinkhorn", reg=reg, tolerance=1e-10,
                                    max_iterations=50000)
            assert res.converged, (seed, reg)
            gap = res.cost - exact
            assert -1e-9 <= gap <= reg * np.log(n * m), (seed, reg, gap)
            gaps.append(gap)
        assert gaps[0] > gaps[1] > gaps[2] or gaps[2] < 1e-12, (seed, gaps)


# --- errors ----------------------------------------------------------------------------------

SRC = [[0.0, 0.0], [1.0, 0.0]]
DST = [[0.0, 1.0], [1.0, 1.0], [2.0, 1.0]]


def test_error_too_few_points():
    with pytest.raises(InvalidInputError, match=r"`source` to hold at least 1 point, got 0") as info:
        optimal_transport(np.zeros((0, 2)), DST)
    assert info.value.field == "source"
    with pytest.raises(InvalidInputError, match=r"`target` to hold at least 1 point, got 0") as info:
        optimal_transport(SRC, np.zeros((0, 2)))
    assert info.value.field == "target"


def test_error_nonfinite():
    with pytest.raises(InvalidInputError, match=r"`source` to hold finite numbers, got nan at row 1"):
        optimal_transport([[0.0, 0.0], [np.nan, 0.0]], DST)
    with pytest.raises(InvalidInputError, match=r"`target` to hold finite numbers, got inf at row 2"):
        optimal_transport(SRC, [[0.0, 1.0], [1.0, 1.0], [np.inf, 1.0]])


def test_error_dimensions_differ():
    with pytest.raises(
        InvalidInputError, match=r"Expected `target` to have the same dimension as `source` \(2\)"
    ) as info:
        optimal_transport(SRC, [[0.0, 1.0, 2.0]])
    assert info.value.field == "target"


@pytest.mark.parametrize(
    ("name", "value", "message"),
    [
        ("source_weights", [1.0, 2.0, 3.0], r"`source_weights` to be an \(2,\) array of finite "
         r"non-negative numbers, got shape \(3,\)"),
        ("source_weights", [1.0, -1.0], r"`source_weights` to be non-negative, got -1.0 at "
         r"position 1"),
        ("source_weights", [0.0, 0.0], r"`source_weights` to have a positive sum, got all zeros"),
        ("source_weights", [1.0, np.nan], r"`source_weights` to hold finite numbers, got nan"),
        ("target_weights", [1.0, 1.0], r"`target_weights` to be an \(3,\) array"),
        ("target_weights", [1.0, np.inf, 1.0], r"`target_weights` to hold finite numbers, got inf"),
        ("target_weights", [[1.0, 1.0, 1.0]], r"`target_weights` to be an \(3,\) array .* "
         r"got shape \(1, 3\)"),
        ("target_weights", ["a", "b", "c"], r"`target_weights` to be an \(3,\) array .* dtype"),
    ],
)
def test_error_weights(name, value, message):
    with pytest.raises(InvalidInputError, match=message) as info:
        optimal_transport(SRC, DST, **{name: value})
    assert info.value.field == name


@pytest.mark.parametrize(
    ("value", "message"),
    [
        (0.0, r"`reg` to be a number > 0, got 0.0"),
        (-0.1, r"`reg` to be a number > 0, got -0.1"),
        (float("nan"), r"`reg` to be a finite number, got nan"),
        ("0.1", r"`reg` to be a number, got '0.1'"),
    ],
)
def test_error_reg(value, message):
    with pytest.raises(InvalidInputError, match=message) as info:
        optimal_transport(SRC, DST, method="sinkhorn", reg=value)
    assert info.value.field == "reg"


def test_error_reg_too_small_for_the_costs():
    with pytest.raises(InvalidInputError, match=r"`reg` to be large enough that cost / reg is "
                       r"finite, got 1e-300") as info:
        optimal_transport([[0.0]], [[1e10]], method="sinkhorn", reg=1e-300)
    assert info.value.field == "reg"


@pytest.mark.parametrize(
    ("kwargs", "field", "message"),
    [
        ({"max_iterations": 0}, "max_iterations", r"`max_iterations` to be an integer >= 1, got 0"),
        ({"max_iterations": 2.5}, "max_iterations", r"`max_iterations` to be an integer, got 2.5"),
        ({"tolerance": 0.0}, "tolerance", r"`tolerance` to be a number > 0, got 0.0"),
        ({"tolerance": -1e-9}, "tolerance", r"`tolerance` to be a number > 0"),
        ({"method": "simplex"}, "method", r"`method` to be one of 'exact', 'sinkhorn', got "
         r"'simplex'"),
        ({"metric": "cosine"}, "metric", r"`metric` to be one of 'euclidean', 'sqeuclidean', "
         r"got 'cosine'"),
    ],
)
def test_error_options(kwargs, field, message):
    with pytest.raises(InvalidInputError, match=message) as info:
        optimal_transport(SRC, DST, **kwargs)
    assert info.value.field == field


def test_error_cost_matrix_too_large():
    m = MAX_COST_ENTRIES // 2000 + 1
    with pytest.raises(InvalidInputError, match=r"at most 16,000,000 point pairs .* got 2,000 × "
                       r"8,001 = 16,002,000") as info:
        optimal_transport(np.zeros((2000, 1)), np.broadcast_to(np.zeros(1), (m, 1)))
    assert info.value.field == "target"


def test_docstring_examples_run():
    import doctest

    assert doctest.testmod(_module(), raise_on_error=False).failed == 0
