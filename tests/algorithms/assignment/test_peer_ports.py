"""Cases ported from the peers' own tests: scipy's linear_sum_assignment
(scipy/optimize/tests/test_linear_assignment.py, whose cases live in
scipy/sparse/csgraph/tests/test_matching.py) and POT's exact transport
(POT test/test_ot.py). Each test names the original.

``bipartite`` and ``optimal_transport`` take point sets, not cost matrices; a cost matrix
``C`` (n x m, n <= m) is given as the points ``x_i = -C[i] / 2`` in R^m and ``y_j = e_j``,
whose squared distances are ``C[i, j] + |x_i|² + 1``: a constant per row, and every row is
matched, so the optimal matching is ``C``'s (for n > m, the transpose)."""

from __future__ import annotations

import numpy as np
import ot
import pytest
from ot.datasets import make_1D_gauss

from algorithms.assignment import bipartite, optimal_transport
from algorithms.core.errors import InvalidInputError


def _solve(cost: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """scipy's (row_ind, col_ind) for ``cost`` by our bipartite, rows ascending."""
    c = np.asarray(cost, float)
    flip = c.shape[0] > c.shape[1]
    if flip:
        c = c.T
    res = bipartite(-c / 2.0, np.eye(c.shape[1]), metric="sqeuclidean")
    rows, cols = res.pairs[:, 0], res.pairs[:, 1]
    if flip:
        rows, cols = cols, rows
    order = np.argsort(rows)
    return rows[order], cols[order]


# scipy: sparse/csgraph/tests/test_matching.py::linear_sum_assignment_test_cases
CASES = [
    ([[400, 150, 400], [400, 450, 600], [300, 225, 300]], [150, 400, 300]),
    ([[400, 150, 400, 1], [400, 450, 600, 2], [300, 225, 300, 3]], [150, 2, 300]),
    ([[10, 10, 8], [9, 8, 1], [9, 7, 4]], [10, 1, 7]),
    ([[10, 10, 8, 11], [9, 8, 1, 1], [9, 7, 4, 10]], [10, 1, 4]),
]


# scipy: optimize/tests/test_linear_assignment.py::test_linear_sum_assignment_small_inputs
# (sign -1: scipy maximises the negated matrix, which is minimising the negation of it)
@pytest.mark.parametrize("sign", [-1, 1])
@pytest.mark.parametrize("case", range(len(CASES)))
def test_linear_sum_assignment_small_inputs(sign: int, case: int) -> None:
    cost, expected = CASES[case]
    c = sign * np.array(cost, float)
    want = sign * np.array(expected, float)
    rows, cols = _solve(sign * c)  # maximising c is minimising -c
    np.testing.assert_array_equal(c[rows, cols], want)
    rows, cols = _solve(sign * c.T)
    np.testing.assert_array_equal(np.sort(c.T[rows, cols]), np.sort(want))


# scipy's fifth case holds infinite costs (forbidden pairs); our costs come from finite
# points, so the documented difference is that such input is refused, naming the field
def test_infinite_costs_are_refused() -> None:
    with pytest.raises(InvalidInputError, match="finite") as err:
        bipartite([[np.inf, 0.0]], [[0.0, 0.0]])
    assert err.value.field == "source"


# scipy: optimize/tests/test_linear_assignment.py::test_constant_cost_matrix (its answer,
# the identity, is one of the optimal matchings; any perfect matching is optimal)
def test_constant_cost_matrix() -> None:
    rows, cols = _solve(np.ones((8, 8)))
    np.testing.assert_array_equal(rows, np.arange(8))
    np.testing.assert_array_equal(np.sort(cols), np.arange(8))


# scipy: test_linear_assignment.py::test_two_methods_give_same_result_on_many_sparse_inputs,
# here against scipy's linear_sum_assignment on dense random integer costs
def test_same_cost_as_scipy_on_random_inputs() -> None:
    from scipy.optimize import linear_sum_assignment

    rng = np.random.default_rng(1234)
    for _ in range(20):
        c = rng.integers(1, 100, size=(12, 15)).astype(float)
        r_ref, c_ref = linear_sum_assignment(c)
        rows, cols = _solve(c)
        assert c[rows, cols].sum() == c[r_ref, c_ref].sum()


# POT: test/test_ot.py::test_emd_emd2 (the transport of a set onto itself is the identity)
def test_emd_emd2() -> None:
    rng = np.random.RandomState(0)
    x = rng.randn(100, 2)
    res = optimal_transport(x, x)
    plan = np.zeros((100, 100))
    plan[res.pairs[:, 0], res.pairs[:, 1]] = res.masses
    np.testing.assert_allclose(plan, np.eye(100) / 100)
    np.testing.assert_allclose(plan.sum(axis=1), np.full(100, 0.01))
    np.testing.assert_allclose(plan.sum(axis=0), np.full(100, 0.01))
    np.testing.assert_allclose(res.cost, 0.0, atol=1e-15)


# POT: test/test_ot.py::test_dual_variables (1-D Gaussians on bins, cost |x - y|: the
# exact cost is the distance of the means; symmetric in the two sides)
def test_dual_variables_closed_form_and_symmetry() -> None:
    n, m, mean1, mean2 = 500, 600, 300, 400
    x = np.arange(n, dtype=float)[:, None]
    y = np.arange(m, dtype=float)[:, None]
    a = make_1D_gauss(n, m=mean1, s=5)
    b = make_1D_gauss(m, m=mean2, s=10)
    res = optimal_transport(x, y, source_weights=a, target_weights=b, metric="euclidean")
    np.testing.assert_almost_equal(res.cost, abs(mean1 - mean2), decimal=5)
    back = optimal_transport(y, x, source_weights=b, target_weights=a, metric="euclidean")
    np.testing.assert_array_almost_equal(res.cost, back.cost)
    m_cost = ot.dist(x, y, metric="euclidean")
    np.testing.assert_almost_equal(res.cost, ot.emd2(a, b, m_cost), decimal=7)


# POT: test/test_ot.py::test_emd_dimension_and_mass_mismatch (POT asserts; we raise a typed
# error naming the field)
def test_emd_dimension_mismatch() -> None:
    x = np.random.RandomState(0).randn(100, 2)
    with pytest.raises(InvalidInputError) as err:
        optimal_transport(x, x, source_weights=np.full(101, 1 / 101))
    assert err.value.field == "source_weights"


# POT: test/test_bregman.py::test_sinkhorn (the marginals of the plan are the weights)
def test_sinkhorn_marginals() -> None:
    rng = np.random.RandomState(0)
    x = rng.randn(50, 2)
    res = optimal_transport(x, x, method="sinkhorn", reg=1.0)  # POT: reg 1
    plan = np.zeros((50, 50))
    plan[res.pairs[:, 0], res.pairs[:, 1]] = res.masses
    np.testing.assert_allclose(plan.sum(axis=0), np.full(50, 0.02), atol=1e-5)  # POT: 1e-5
    np.testing.assert_allclose(plan.sum(axis=1), np.full(50, 0.02), atol=1e-5)  # POT: 1e-5
    assert res.converged
