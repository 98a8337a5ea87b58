"""Optimal transport between two weighted point sets: exact, and entropic (Sinkhorn)."""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import Annotated, Any, Literal, get_args

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
from algorithms.core.errors import ConvergenceWarning, InvalidInputError, warn
from algorithms.core.params import Ge, Gt, PointsLike, WeightsLike, validate_params
from algorithms.core.progress import Progress, as_progress
from algorithms.core.types import FloatArray, IntArray, IntpArray
from algorithms.core.validation import as_weights

__all__ = [
    "TransportResult",
    "optimal_transport",
    "check_transport",
    "TRANSPORT_METHODS",
    "METRICS",
    "MAX_COST_ENTRIES",
]

TransportMethod = Literal["exact", "sinkhorn"]
#: The accepted values of ``method``.
TRANSPORT_METHODS = get_args(TransportMethod)

#: Sinkhorn reports progress (and may be cancelled) every this many iterations.
PROGRESS_EVERY = 50

#: Over-relaxed Sinkhorn (see Notes): the rate of plain iterations is estimated over this
#: many iterations, the relaxation factor is capped at ``SOR_MAX``, and not used when it
#: would be below ``1 + SOR_MIN_GAIN``; relaxed runs check convergence every
#: ``SOR_CHECK_EVERY`` iterations.
SOR_WINDOW = 10
SOR_MAX = 1.9
SOR_MIN_GAIN = 0.05
SOR_CHECK_EVERY = 10
SOR_RENEW_EVERY = 200

#: Sinkhorn plan entries below this fraction of their source point's mass are left out of
#: the returned sparse plan (``cost`` and ``marginal_error`` still count them).
SINKHORN_CUTOFF = 1e-12

#: Exact plan entries at or below this mass (of a total of 1) are solver round-off, dropped.
EXACT_CUTOFF = 1e-15

#: The network simplex's pivot limit: this many per pair, at least ``EMD_MIN_ITERATIONS``
#: (POT's default of 100,000 is too few for a few thousand points a side).
EMD_ITERATIONS_PER_PAIR = 50
EMD_MIN_ITERATIONS = 100_000

#: Exponents below this are clipped before ``exp`` in Sinkhorn's log-sum-exp: their terms
#: (< 4e-44 each, next to a largest term of 1) cannot change a float64 sum, and clipping
#: keeps ``exp`` away from slow subnormal results.
_EXP_FLOOR = -100.0


@dataclass(frozen=True, eq=False)
class TransportResult:
    """A transport plan between two weighted point sets, returned sparse.

    Attributes
    ----------
    pairs : (k, 2) int64 array
        The plan's support: each row is ``(source_index, target_index)`` of a pair that
        carries mass, sorted by source index then target index.
    masses : (k,) float array
        The mass moved along each pair; the masses of both sets are normalised to a total
        of 1, so these sum to 1 (up to the entries Sinkhorn leaves out, see Notes).
    distances : (k,) float array
        The Euclidean distance between the two points of each pair, whatever the ``metric``.
    cost : float
        The transport cost, the sum over the plan of mass times ``metric`` cost: the squared
        2-Wasserstein distance for "sqeuclidean" with the exact method, the
        1-Wasserstein (earth mover's) distance for "euclidean". For Sinkhorn, the cost of the
        entropic plan without the entropy term.
    rmse : float
        The mass-weighted root-mean-square distance ``sqrt(sum mass * distance^2)``; with
        the exact method and "sqeuclidean" it is the 2-Wasserstein distance.
    marginal_error : float
        How far the plan's marginals are from the prescribed masses, in the L1 norm summed
        over both sides: round-off for the exact method, at most ``tolerance`` when
        Sinkhorn converged.
    n_pairs : int
        The number of pairs ``k`` in the returned plan.
    iterations : int
        Sinkhorn iterations; 0 for the exact method.
    converged : bool
        Whether Sinkhorn met ``tolerance`` within ``max_iterations``; always true for the
        exact method.
    solver : str
        Which solver ran: "assignment" (uniform masses on equal-size sets),
        "network_simplex" (the exact method otherwise) or "sinkhorn".
    """

    pairs: IntArray
    masses: FloatArray
    distances: FloatArray
    cost: float
    rmse: float
    marginal_error: float
    n_pairs: int
    iterations: int
    converged: bool
    solver: str


def check_transport(source: Any, target: Any, source_weights: Any = None,
                    target_weights: Any = None
                    ) -> tuple[FloatArray, FloatArray, FloatArray | None, FloatArray | None]:
    """Check the inputs of :func:`optimal_transport`: two point sets as :func:`check_dense`
    takes them, and one mass per point where masses are given. Returns them checked."""
    src, dst = check_dense(source, target)
    wa = as_weights(source_weights, src.shape[0], name="source_weights")
    wb = as_weights(target_weights, dst.shape[0], name="target_weights")
    return src, dst, wa, wb


@validate_params
def optimal_transport(
    source: PointsLike,
    target: PointsLike,
    *,
    source_weights: WeightsLike | None = None,
    target_weights: WeightsLike | None = None,
    method: TransportMethod = "exact",
    reg: Annotated[float, Gt(0)] = 0.05,
    max_iterations: Annotated[int, Ge(1)] = 1000,
    tolerance: Annotated[float, Gt(0)] = 1e-9,
    metric: Metric = "sqeuclidean",
    progress: Progress | None = None,
) -> TransportResult:
    r"""Optimal transport between weighted point sets (exact or Sinkhorn).

    The transport plan moving the mass of one weighted point set onto another at the least cost,
    returned sparse as (source, target, mass) pairs, with its cost (Wasserstein distance). Exact
    linear program, or entropic Sinkhorn in the log domain. At most 16 million pairs n·m.

    With masses :math:`a \in \mathbb{R}^n_{\ge 0}`, :math:`b \in \mathbb{R}^m_{\ge 0}`
    (each summing to 1) and the ``metric`` cost :math:`C_{ij}` between :math:`x_i` and
    :math:`y_j`, the exact method solves the Kantorovich problem

    .. math::

        \min_{P \ge 0}\ \langle C, P \rangle = \sum_{ij} C_{ij} P_{ij}
        \quad\text{subject to}\quad P \mathbf{1} = a,\ \ P^\mathsf{T} \mathbf{1} = b,

    and ``method="sinkhorn"`` its entropic regularisation (Cuturi 2013)

    .. math::

        \min_{P \ge 0,\ P \mathbf{1} = a,\ P^\mathsf{T} \mathbf{1} = b}\
        \langle C, P \rangle - \varepsilon H(P), \qquad
        H(P) = -\sum_{ij} P_{ij} (\log P_{ij} - 1),

    whose solution :math:`P_{ij} = \exp((f_i + g_j - C_{ij})/\varepsilon)` is found by
    alternating the dual updates, in the log domain,

    .. math::

        f_i \leftarrow \varepsilon \log a_i
            - \varepsilon \operatorname{LSE}_j \bigl((g_j - C_{ij})/\varepsilon\bigr), \qquad
        g_j \leftarrow \varepsilon \log b_j
            - \varepsilon \operatorname{LSE}_i \bigl((f_i - C_{ij})/\varepsilon\bigr).

    Parameters
    ----------
    source : (n, d) float array
        The points mass leaves from, any ``d >= 1``, at least one point.
    target : (m, d) float array
        The points mass arrives at, same ``d``; its size may differ from ``source``. At
        most 16 million pairs ``n·m`` (``MAX_COST_ENTRIES``).
    source_weights : (n,) float array, optional
        Non-negative masses of the source points with a positive sum; uniform when omitted.
        They are relative: normalised to sum to 1 (so the totals of the two sets never
        disagree). Points of mass 0 take no part.
    target_weights : (m,) float array, optional
        Non-negative masses of the target points with a positive sum, normalised to sum
        to 1; uniform when omitted. Points of mass 0 take no part.
    method : {"exact", "sinkhorn"}, default "exact"
        ``"exact"``: the transport linear program (an assignment when the masses are
        uniform on sets of equal size, else the network simplex); ``"sinkhorn"``: its
        entropic regularisation, solved by log-domain Sinkhorn iterations (faster on
        large sets, a blurred plan).
    reg : float, default 0.05
        Sinkhorn's :math:`\varepsilon` (``> 0``), in the units of the cost (absolute, as in
        POT): smaller is closer to the exact plan but needs more iterations. Checked but
        unused by the exact method.
    max_iterations : int, default 1000
        Sinkhorn's iteration limit (``>= 1``); one iteration updates both potentials.
    tolerance : float, default 1e-9
        Sinkhorn stops when the L1 error of the plan's marginals is at most this (``> 0``),
        checked every iteration. POT's ``sinkhorn`` has the same default (``stopThr=1e-9``)
        but checks the L2 norm of the column marginals' error every 10 iterations, so it
        may run a few iterations more; the L1 rule bounds the mass misplaced, which is what
        the plan's users read.
    metric : {"sqeuclidean", "euclidean"}, default "sqeuclidean"
        The cost of moving unit mass from :math:`x_i` to :math:`y_j`:
        :math:`\lVert x_i - y_j \rVert^2` (2-Wasserstein) or :math:`\lVert x_i - y_j \rVert`
        (1-Wasserstein, earth mover's distance).
    progress : callable, optional
        ``progress(done, total, message)``; Sinkhorn calls it every ``PROGRESS_EVERY`` (50)
        iterations with ``total = max_iterations``, the exact method once before it
        solves. It may raise :class:`~algorithms.core.errors.Cancelled`.

    Returns
    -------
    TransportResult
        The sparse plan (``pairs``, ``masses``, ``distances``) with ``cost``, ``rmse``,
        ``marginal_error``, ``n_pairs``, ``iterations``, ``converged`` and ``solver``.

    Raises
    ------
    InvalidInputError
        Empty, malformed or non-finite point sets; differing dimensions
        (``field="target"``); malformed weights (wrong length, negative, NaN/Inf, all
        zero; ``field="source_weights"`` or ``"target_weights"``); unknown ``method`` or
        ``metric``; ``reg <= 0``, ``tolerance <= 0`` or ``max_iterations < 1``; more than
        ``MAX_COST_ENTRIES`` (16 million) pairs ``n·m`` (the error names the larger set).

    Warns
    -----
    ConvergenceWarning
        Sinkhorn reached ``max_iterations`` before ``tolerance``; the result then has
        ``converged=False`` and its plan's marginals are off by ``marginal_error``.

    Notes
    -----
    **Exact solvers.** When both sets have the same number of points of positive mass and
    the masses are uniform, an optimal plan is a permutation (the vertices of the Birkhoff
    polytope are permutation matrices, Birkhoff 1946 [6]), found by
    :func:`scipy.optimize.linear_sum_assignment`: ``solver="assignment"``, each pair
    carrying :math:`1/n`. Otherwise the transport problem is solved by the network simplex
    of POT (``ot.lp.emd``, Bonneel et al. 2011 [4]; ``solver="network_simplex"``), the
    fastest exact solver installable from wheels: on 1,000 × 1,000 points with random
    masses it takes about 0.2 s where column generation over HiGHS' dual simplex took 1.6 s
    and the full LP in :func:`scipy.optimize.linprog` about 30 times longer (see
    ``bench/assignment.py``). The target masses are rescaled so both totals agree to the
    last bit. The plan is a basic solution: at most :math:`n + m - 1` pairs. The network
    simplex runs to its end without progress reports, so it cannot be cancelled midway.

    **Sinkhorn in the log domain.** The updates above use the log-sum-exp trick (subtract
    each row's largest exponent before ``exp``), so nothing overflows however small
    :math:`\varepsilon` is relative to the costs; the kernel :math:`e^{-C/\varepsilon}`,
    which underflows to 0 for :math:`\varepsilon = 10^{-3}` on unit-scale data, is never
    formed. The iteration stops when the column sums of the plan :math:`(f, g)` (its row
    sums are exact right after an :math:`f` update) are within ``tolerance`` in L1. The
    converged entropic plan's cost exceeds the exact cost by at most
    :math:`\varepsilon \log(nm)`: comparing its objective with the exact plan's bounds
    the difference by :math:`\varepsilon` times a difference of two entropies
    :math:`-\sum P \log P`, both in :math:`[0, \log(nm)]`. The returned sparse plan leaves
    out entries below ``SINKHORN_CUTOFF`` (1e-12) times the mass of their source
    point; ``cost`` and ``marginal_error`` are computed on the full plan.

    **Over-relaxation.** Plain Sinkhorn converges linearly at a rate that approaches 1 as
    :math:`\varepsilon` shrinks. Every ``SOR_WINDOW`` (10) plain iterations the observed
    rate :math:`\theta` of the marginal error (while it decreases) sets the relaxation
    :math:`\omega = \min(1.9,\ 2 / (1 + \sqrt{1 - \theta}))` (the optimal SOR factor
    for a Gauss-Seidel rate :math:`\theta`), and the updates become
    :math:`f \leftarrow (1 - \omega) f + \omega f^{\text{Sinkhorn}}` (Thibault, Chizat,
    Dossal & Papadakis 2021), which has the same fixed point. Every ``SOR_CHECK_EVERY``
    (10) iterations one plain update measures the error; if it grew, :math:`\omega` is
    halved towards 1, and below 1.05 plain Sinkhorn resumes for good. Every
    ``SOR_RENEW_EVERY`` (200) relaxed iterations a plain window re-estimates :math:`\theta`,
    which early iterations tend to underestimate. On unit-scale data at
    :math:`\varepsilon \le 0.05` this divides the iteration count by about 2 to 10 (the
    slowest inputs gain most). At :math:`\varepsilon = 10^{-3}` tens of thousands of
    iterations may still be needed on some inputs (the error then decays sublinearly for
    long stretches); the result then says ``converged=False`` and a
    :class:`ConvergenceWarning` is issued.

    **Memory.** Both methods build the dense ``n×m`` cost matrix; above ``MAX_COST_ENTRIES``
    (16 million entries, 128 MB) the call is refused before any work. Sinkhorn needs two
    such matrices, the network simplex two (the cost and the dense plan).

    References
    ----------
    .. [1] L. Kantorovich, "On the translocation of masses", Doklady Akademii Nauk SSSR 37,
       199-201, 1942.
    .. [2] M. Cuturi, "Sinkhorn distances: lightspeed computation of optimal transport",
       NeurIPS 26, 2013.
    .. [3] G. Peyré and M. Cuturi, "Computational optimal transport", Foundations and
       Trends in Machine Learning 11(5-6), 355-607, 2019 (sections 3 and 4.4, the
       log-domain Sinkhorn).
    .. [4] N. Bonneel, M. van de Panne, S. Paris and W. Heidrich, "Displacement
       interpolation using Lagrangian mass transport", ACM Transactions on Graphics 30(6),
       158, 2011 (the network simplex POT implements).
    .. [5] A. Thibault, L. Chizat, C. Dossal and N. Papadakis, "Overrelaxed Sinkhorn-Knopp
       algorithm for regularized optimal transport", Algorithms 14(5), 143, 2021.
    .. [6] G. Birkhoff, "Tres observaciones sobre el algebra lineal", Universidad Nacional
       de Tucumán Revista, Serie A 5, 147-151, 1946.

    Examples
    --------
    >>> from algorithms.assignment import optimal_transport
    >>> res = optimal_transport([[0.0], [1.0]], [[0.0], [2.0]], source_weights=[3, 1])
    >>> res.pairs.tolist(), res.masses.tolist(), res.cost
    ([[0, 0], [0, 1], [1, 1]], [0.5, 0.25, 0.25], 1.25)
    """
    src, dst, wa, wb = check_transport(source, target, source_weights, target_weights)
    n, m = src.shape[0], dst.shape[0]
    report = as_progress(progress)

    a = _masses(wa, n)
    b = _masses(wb, m)
    si = np.flatnonzero(a > 0)  # points of mass 0 take no part
    ti = np.flatnonzero(b > 0)
    a, b = a[si], b[ti]
    cost = cost_matrix(src[si], dst[ti], metric)

    iterations, converged = 0, True
    if method == "exact":
        if a.shape[0] == b.shape[0] and a.min() == a.max() and b.min() == b.max():
            solver = "assignment"
            rows, cols = linear_sum_assignment(cost)
            mass = np.full(rows.shape[0], 1.0 / rows.shape[0])
        else:
            solver = "network_simplex"
            report(0, 1, "exact transport: network simplex")
            rows, cols, mass, iterations = _exact_network_simplex(cost, a, b)
        total = float(np.dot(mass, cost[rows, cols]))
        err = _marginal_error(rows, cols, mass, a, b)
    else:
        solver = "sinkhorn"
        with np.errstate(over="ignore"):
            too_small = not np.isfinite(cost.max() / reg)
        if too_small:
            raise InvalidInputError(
                f"Expected `reg` to be large enough that cost / reg is finite, got {reg!r} "
                f"with a largest cost of {cost.max()!r}.",
                field="reg",
            )
        rows, cols, mass, total, err, iterations, converged = _sinkhorn(
            cost, a, b, reg, max_iterations, tolerance, report
        )
        if not converged:
            warn(
                f"Sinkhorn stopped after {iterations} iterations with a marginal error of "
                f"{err:.3g}, above the tolerance {tolerance:.3g}; raise `max_iterations` or "
                "`reg`.",
                ConvergenceWarning,
            )
    del cost

    i = si[rows].astype(np.int64, copy=False)
    j = ti[cols].astype(np.int64, copy=False)
    order = np.lexsort((j, i))
    i, j, mass = i[order], j[order], np.ascontiguousarray(mass[order], dtype=np.float64)
    k = int(i.shape[0])
    pairs = np.empty((k, 2), dtype=np.int64)
    pairs[:, 0] = i
    pairs[:, 1] = j
    distances = pair_distances(src, dst, i, j)
    rmse = float(np.sqrt(max(np.dot(mass, distances * distances), 0.0))) if k else 0.0
    return TransportResult(
        pairs=pairs,
        masses=mass,
        distances=distances,
        cost=total,
        rmse=rmse,
        marginal_error=float(err),
        n_pairs=k,
        iterations=int(iterations),
        converged=bool(converged),
        solver=solver,
    )


def _masses(w: FloatArray | None, n: int) -> FloatArray:
    """Weights (already checked) normalised to sum to 1; uniform when ``None``."""
    if w is None:
        return np.full(n, 1.0 / n)
    scaled: FloatArray = w / w.max()  # no overflow in the sum of huge weights
    total: float = scaled.sum()
    return scaled / total


def _marginal_error(rows: np.ndarray, cols: np.ndarray, mass: FloatArray,
                    a: FloatArray, b: FloatArray) -> float:
    row_sums = np.bincount(rows, weights=mass, minlength=a.shape[0])
    col_sums = np.bincount(cols, weights=mass, minlength=b.shape[0])
    return float(np.abs(row_sums - a).sum() + np.abs(col_sums - b).sum())


# -- exact: POT's network simplex ----------------------------------------------------------


def _exact_network_simplex(cost: FloatArray, a: FloatArray, b: FloatArray
                           ) -> tuple[IntpArray, IntpArray, FloatArray, int]:
    """Exact transport by POT's network simplex; returns (rows, cols, masses, 0)."""
    # Imported on first use: `import ot` costs about a second (it imports its optional
    # backends), which processes that never transport should not pay.
    from ot.lp import emd

    b = b * (a.sum() / b.sum())  # totals equal to the last bit, as the simplex requires
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # reported through the log instead
        plan, log = emd(a, b, cost, numItermax=max(EMD_MIN_ITERATIONS, EMD_ITERATIONS_PER_PAIR
                                                   * cost.size), log=True)
    if log.get("warning"):  # cannot happen for a feasible, bounded problem within the limit
        raise RuntimeError(f"POT's network simplex stopped: {log['warning']}")
    rows, cols = np.nonzero(plan > EXACT_CUTOFF)
    return rows, cols, plan[rows, cols], 0


# -- entropic: log-domain Sinkhorn ----------------------------------------------------------


def _sinkhorn(cost: FloatArray, a: FloatArray, b: FloatArray, reg: float,
              max_iterations: int, tolerance: float, report: Progress
              ) -> tuple[IntpArray, IntpArray, FloatArray, float, float, int, bool]:
    """Log-domain Sinkhorn; returns (rows, cols, masses, cost, marginal error, iterations,
    converged) with the plan already cut to its significant entries. Overwrites ``cost``."""
    n, m = cost.shape
    scaled = np.divide(cost, reg, out=cost)  # C / eps, in place; potentials are f/eps, g/eps
    buf = np.empty((n, m))
    log_a, log_b = np.log(a), np.log(b)

    def lse_rows(g: FloatArray) -> FloatArray:  # LSE_j (g_j - scaled_ij)
        np.subtract(g[None, :], scaled, out=buf)
        top: FloatArray = buf.max(axis=1)
        np.subtract(buf, top[:, None], out=buf)
        np.maximum(buf, _EXP_FLOOR, out=buf)
        np.exp(buf, out=buf)
        sums: FloatArray = buf.sum(axis=1)
        return top + np.log(sums)

    def lse_cols(f: FloatArray) -> FloatArray:  # LSE_i (f_i - scaled_ij)
        np.subtract(f[:, None], scaled, out=buf)
        top: FloatArray = buf.max(axis=0)
        np.subtract(buf, top[None, :], out=buf)
        np.maximum(buf, _EXP_FLOOR, out=buf)
        np.exp(buf, out=buf)
        sums: FloatArray = buf.sum(axis=0)
        return top + np.log(sums)

    f = np.zeros(n)
    g = np.zeros(m)
    omega = 1.0  # over-relaxation; 1 is plain Sinkhorn
    adapt = True
    errors: list[float] = []  # every iteration's error while plain, for the rate estimate
    last_check = np.inf
    relaxed_at = 0
    converged = False
    err = np.inf
    iterations = 0
    for it in range(1, max_iterations + 1):
        iterations = it
        f_plain = log_a - lse_rows(g)
        check = omega == 1.0 or it % SOR_CHECK_EVERY == 0
        f = f_plain if check else f + omega * (f_plain - f)
        col_lse = lse_cols(f)
        if check:
            # the plan of (f, g) has exact row sums; its column sums are exp(g + col_lse)
            err = float(np.abs(np.exp(g + col_lse) - b).sum())
            if err <= tolerance:
                converged = True
                break
            if omega == 1.0 and adapt:
                errors.append(err)
                if len(errors) > SOR_WINDOW:
                    rate = (errors[-1] / errors[-1 - SOR_WINDOW]) ** (1.0 / SOR_WINDOW)
                    errors.clear()
                    if rate < 1.0:
                        omega = min(SOR_MAX, 2.0 / (1.0 + np.sqrt(1.0 - rate)))
                        omega = omega if omega > 1.0 + SOR_MIN_GAIN else 1.0
                        relaxed_at = it
            elif omega > 1.0 and err > last_check:  # diverging: back towards plain
                omega = 1.0 + 0.5 * (omega - 1.0)
                if omega < 1.0 + SOR_MIN_GAIN:
                    omega, adapt = 1.0, False
            elif omega > 1.0 and it - relaxed_at >= SOR_RENEW_EVERY:
                omega = 1.0  # a plain window again, to re-estimate the rate
            last_check = err
        g_plain = log_b - col_lse
        g = g_plain if omega == 1.0 else g + omega * (g_plain - g)
        if it % PROGRESS_EVERY == 0:
            report(it, max_iterations, f"Sinkhorn iteration {it}, marginal error {err:.3g}")
    if not check:  # stopped on a relaxed step: end on a plain one (exact row sums)
        f = log_a - lse_rows(g)

    # The plan of the current potentials; its marginal error is measured afresh.
    np.add(f[:, None], g[None, :], out=buf)
    buf -= scaled
    np.exp(buf, out=buf)
    plan = buf
    total = float(np.einsum("ij,ij->", plan, scaled) * reg)
    err = float(np.abs(plan.sum(axis=1) - a).sum() + np.abs(plan.sum(axis=0) - b).sum())
    keep = plan >= (SINKHORN_CUTOFF * a)[:, None]
    rows, cols = np.nonzero(keep)
    mass = plan[rows, cols]
    return rows, cols, mass, total, err, iterations, converged
