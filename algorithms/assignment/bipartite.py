"""Optimal one-to-one matching between two point sets (linear assignment)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Annotated

import numpy as np
from scipy.optimize import linear_sum_assignment

from algorithms.assignment._dense import (
    MAX_COST_ENTRIES,
    METRICS,
    Metric,
    check_dense,
    cost_matrix,
    pair_distances,
)
from algorithms.core.params import Gt, PointsLike, validate_params
from algorithms.core.types import FloatArray, IntArray

__all__ = ["BipartiteResult", "bipartite", "METRICS", "MAX_COST_ENTRIES"]


@dataclass(frozen=True, eq=False)
class BipartiteResult:
    """The optimal one-to-one matching between ``source`` and ``target``.

    Attributes
    ----------
    pairs : (k, 2) int64 array
        Each row is ``(source_index, target_index)``, sorted by source index. No point
        appears in two pairs.
    distances : (k,) float array
        The Euclidean distance between the two points of each pair, whatever the ``metric``.
    cost : float
        The minimised total, the sum of the ``metric`` cost over the pairs (not counting
        the unmatched points). 0.0 when there are no pairs.
    rmse : float
        The root-mean-square of ``distances``, 0.0 when there are no pairs.
    n_pairs : int
        The number of pairs ``k``: ``min(n, m)`` without ``max_cost``, possibly fewer with it.
    unmatched_source : (n - k,) int64 array
        The rows of ``source`` left without a partner, ascending.
    unmatched_target : (m - k,) int64 array
        The rows of ``target`` left without a partner, ascending.
    """

    pairs: IntArray
    distances: FloatArray
    cost: float
    rmse: float
    n_pairs: int
    unmatched_source: IntArray
    unmatched_target: IntArray


@validate_params
def bipartite(
    source: PointsLike,
    target: PointsLike,
    *,
    metric: Metric = "euclidean",
    max_cost: Annotated[float, Gt(0)] | None = None,
) -> BipartiteResult:
    r"""Optimal one-to-one matching (linear assignment).

    Matches the points of two sets one to one at the least total cost; sets may differ in size (the
    surplus stays unmatched), and max_cost leaves far points single. At most 16 million pairs n·m.

    With :math:`c_{ij}` the ``metric`` cost between :math:`x_i` and :math:`y_j`, this solves
    the (rectangular) linear assignment problem

    .. math::

        \min_{\pi}\ \sum_{(i, j) \in \pi} c_{ij}

    over matchings :math:`\pi` (sets of pairs in which no point appears twice) of size
    :math:`\min(n, m)`: when the sets differ in size, the surplus points of the larger set
    stay unmatched. With ``max_cost`` = :math:`\tau` every point may stay unmatched at a
    price of :math:`\tau / 2`, so a pair is worth making only when it costs less than
    :math:`\tau`:

    .. math::

        \min_{\pi}\ \sum_{(i, j) \in \pi} c_{ij}
        + \frac{\tau}{2}\,\bigl(n + m - 2\lvert\pi\rvert\bigr),
        \qquad c_{ij} \le \tau \ \text{for every}\ (i, j) \in \pi,

    that is, the matching maximises the total saving :math:`\sum_\pi (\tau - c_{ij})`.
    No returned pair costs more than :math:`\tau`.

    Parameters
    ----------
    source : (n, d) float array
        The first point set, any ``d >= 1``, at least one point.
    target : (m, d) float array
        The second point set, same ``d``; its size may differ from ``source`` (the surplus
        of the larger set stays unmatched). At most 16 million pairs ``n·m``
        (``MAX_COST_ENTRIES``).
    metric : {"euclidean", "sqeuclidean"}, default "euclidean"
        The cost of a pair: the distance :math:`\lVert x_i - y_j \rVert`, or its square.
        The squared distance favours many small displacements over a few large ones.
    max_cost : float, optional
        The largest cost of a pair (``> 0``, in the units of ``metric``): leaving a point
        unmatched costs half of it, so points whose every partner costs more stay
        unmatched. Omitted: every point of the smaller set is matched.

    Returns
    -------
    BipartiteResult
        ``pairs``, ``distances``, ``cost``, ``rmse``, ``n_pairs``, ``unmatched_source`` and
        ``unmatched_target``.

    Raises
    ------
    InvalidInputError
        Empty, malformed or non-finite point sets; differing dimensions
        (``field="target"``); unknown ``metric``; ``max_cost <= 0`` or non-finite; more
        than ``MAX_COST_ENTRIES`` (16 million) pairs ``n·m`` (the error names the larger
        set).

    Notes
    -----
    **Solver.** The dense ``n×m`` cost matrix goes to
    :func:`scipy.optimize.linear_sum_assignment` (the shortest augmenting path algorithm
    of Jonker-Volgenant as modified by Crouse, 2016), :math:`O(n^2 m)` for
    :math:`n \le m`. With ``max_cost`` the matrix becomes :math:`\min(c_{ij} - \tau, 0)`:
    a full rectangular assignment of it has the same value as the best partial matching
    (pairs costing :math:`\tau` or more contribute 0, so dropping them afterwards changes
    nothing), which is the formulation above. This is the ``cost_limit`` of the LAPJV
    implementations (dummy rows and columns at :math:`\tau/2`) without enlarging the
    matrix. A pair costing exactly :math:`\tau` neither gains nor loses: it is kept when the
    solver returns it.

    **Ties.** When several matchings have the same least cost, the solver's choice is
    returned; the same input always gives the same answer.

    **Size.** The cost matrix holds ``n·m`` float64 entries; above ``MAX_COST_ENTRIES``
    (16 million, 128 MB, e.g. 4,000 × 4,000 points) the call is refused before any work.

    References
    ----------
    .. [1] H. W. Kuhn, "The Hungarian method for the assignment problem", Naval Research
       Logistics Quarterly 2, 83-97, 1955.
    .. [2] R. Jonker and A. Volgenant, "A shortest augmenting path algorithm for dense and
       sparse linear assignment problems", Computing 38, 325-340, 1987.
    .. [3] D. F. Crouse, "On implementing 2D rectangular assignment algorithms", IEEE
       Transactions on Aerospace and Electronic Systems 52(4), 1679-1696, 2016.

    Examples
    --------
    >>> from algorithms.assignment import bipartite
    >>> res = bipartite([[0.0], [1.0], [10.0]], [[1.2], [0.1]])
    >>> res.pairs.tolist(), round(res.cost, 6), res.unmatched_source.tolist()
    ([[0, 1], [1, 0]], 0.3, [2])
    >>> bipartite([[0.0], [1.0], [10.0]], [[1.2], [0.1], [20.0]], max_cost=5.0).pairs.tolist()
    [[0, 1], [1, 0]]
    """
    src, dst = check_dense(source, target)
    tau = max_cost
    n, m = src.shape[0], dst.shape[0]

    cost = cost_matrix(src, dst, metric)
    if tau is None:
        rows, cols = linear_sum_assignment(cost)
    else:
        saving = cost - tau
        np.minimum(saving, 0.0, out=saving)
        rows, cols = linear_sum_assignment(saving)
        del saving
        keep = cost[rows, cols] <= tau
        rows, cols = rows[keep], cols[keep]
    rows = rows.astype(np.int64, copy=False)
    cols = cols.astype(np.int64, copy=False)

    k = int(rows.shape[0])
    pairs = np.empty((k, 2), dtype=np.int64)
    pairs[:, 0] = rows
    pairs[:, 1] = cols
    if metric == "euclidean":
        distances = np.ascontiguousarray(cost[rows, cols])
    else:
        distances = pair_distances(src, dst, rows, cols)
    total = float(cost[rows, cols].sum()) if k else 0.0
    rmse = float(np.sqrt(np.dot(distances, distances) / k)) if k else 0.0
    matched_s = np.zeros(n, dtype=bool)
    matched_s[rows] = True
    matched_t = np.zeros(m, dtype=bool)
    matched_t[cols] = True
    return BipartiteResult(
        pairs=pairs,
        distances=distances,
        cost=total,
        rmse=rmse,
        n_pairs=k,
        unmatched_source=np.flatnonzero(~matched_s).astype(np.int64),
        unmatched_target=np.flatnonzero(~matched_t).astype(np.int64),
    )
