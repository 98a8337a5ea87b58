"""Multiway registration without correspondences: pairwise ICP between the sets, then
pose-graph optimisation on SE(3) with line processes for the loop closures (as Open3D's
multiway registration)."""

from __future__ import annotations

import functools
import math
import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Annotated, Literal, cast, get_args

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.sparse.csgraph import breadth_first_order, connected_components, minimum_spanning_tree
from scipy.sparse.linalg import spsolve
from scipy.spatial import cKDTree

from algorithms.core.errors import ConvergenceWarning, DegenerateInputError, warn
from algorithms.core.parallel import task_map
from algorithms.core.params import ArrayInput, Ge, Gt, Interval, validate_params
from algorithms.core.progress import Progress, as_progress
from algorithms.core.se3 import adjoint, exp, hat, inverse, left_jacobian_inverse, log
from algorithms.core.threads import query_workers
from algorithms.core.types import FloatArray, IntArray, KnnQuery
from algorithms.core.validation import as_int
from algorithms.registration._normals import reuse_normals
from algorithms.registration._point_sets import (
    MultiwayResult,
    PointSetsLike,
    check_sets,
    check_transforms,
)
from algorithms.registration.icp import icp

__all__ = ["pose_graph", "check_neighbors", "METRICS", "Metric"]

Metric = Literal["symmetric", "point_to_plane", "point_to_point"]
#: The accepted values of ``metric``.
METRICS = get_args(Metric)

#: Up to this many sets every pair is registered; beyond, each set with its next neighbours.
ALL_PAIRS_UP_TO = 10
#: Neighbours in order per set when there are more than ``ALL_PAIRS_UP_TO`` sets.
DEFAULT_NEIGHBORS = 2
#: The pairwise ICP runs coarse to fine with these multiples of ``max_correspondence_distance``
#: and metrics (None: the ``metric`` asked for): wide bounds pull in a far start, the tight
#: ones remove the bias that pairs reaching past the edge of the overlap put on the wide
#: ones, and the point-to-point polish removes the curvature bias of the plane metrics on
#: sparse samples (a tangent plane at a sample misses the curved surface between samples).
STAGES: tuple[tuple[float, Metric | None], ...] = (
    (4.0, None), (2.0, None), (1.0, None), (1.0, "point_to_point"))
#: The default ``max_correspondence_distance`` is this multiple of the median point spacing.
SPACING_FACTOR = 2.0
#: Points per set used to estimate the spacing (a random-free, evenly strided subset).
SPACING_SAMPLE = 2000
#: Levenberg-Marquardt gives up when its damping exceeds this (no descent step left).
MAX_DAMPING = 1e16


@validate_params
def pose_graph(
    sets: PointSetsLike,
    *,
    init: ArrayInput | None = None,
    max_iterations: Annotated[int, Ge(1)] = 100,
    tolerance: Annotated[float, Ge(0)] = 1e-9,
    max_correspondence_distance: Annotated[float, Gt(0)] | None = None,
    metric: Metric = "symmetric",
    neighbors: Annotated[int, Ge(1)] | None = None,
    min_fitness: Annotated[float, Interval(ge=0, le=1)] = 0.3,
    edge_prune_threshold: Annotated[float, Interval(ge=0, lt=1)] = 0.25,
    preference_loop_closure: Annotated[float, Gt(0)] = 1.0,
    icp_max_iterations: Annotated[int, Ge(1)] = 30,
    progress: Progress | None = None,
) -> MultiwayResult:
    r"""Register ``k >= 2`` 3-D point sets without known correspondences rigidly into set 0's
    frame: pairwise ICP, then pose-graph optimisation on SE(3).

    As Open3D's multiway registration with ``global_optimization`` and
    ``GlobalOptimizationLevenbergMarquardt`` (Choi, Zhou & Koltun 2015):

    1. **Edges.** Every pair ``i < j`` when ``k <= 10``, else each set with its next
       ``neighbors`` sets in order. Set ``i`` is registered onto set ``j`` by
       :func:`~algorithms.registration.icp` (rigid; ``metric`` with 4, 2 and 1 ×
       ``max_correspondence_distance``, then a point-to-point polish with 1 ×), started at
       :math:`P_j^{-1} P_i` from ``init`` (identity when omitted: the sets are taken as
       roughly aligned, as by a scanner). The result :math:`Z_{ij}` gets the information
       matrix of its correspondences :math:`q` (in set ``j``'s frame),
       :math:`\Lambda_{ij} = \sum_q [-[q]_\times \mid I]^\mathsf{T} [-[q]_\times \mid I]`,
       so that :math:`r^\mathsf{T} \Lambda r` approximates the change of the squared
       point-to-point residual under a small twist ``r``. Edges of fitness below
       ``min_fitness`` are dropped.
    2. **Start.** Poses :math:`P_i` (set ``i`` into set 0's frame, :math:`P_0 = I`)
       composed along the spanning tree of highest fitness.
    3. **Optimisation.** With :math:`r_{ij} = \log(P_j^{-1} P_i Z_{ij}^{-1})` (a twist,
       rotation first, :mod:`algorithms.core.se3`),

       .. math::

           \min_{P_1..P_{k-1}} \sum_{\text{odometry}} r_{ij}^\mathsf{T} \Lambda_{ij} r_{ij}
           + \sum_{\text{loop closures}} \frac{\mu\, r_{ij}^\mathsf{T} \Lambda_{ij} r_{ij}}
           {\mu + r_{ij}^\mathsf{T} \Lambda_{ij} r_{ij}},

       odometry edges being ``(i, i+1)`` when the pairs follow the order (``neighbors``
       given, or more than 10 sets) and every other edge a loop closure. The second
       sum is the line process of Choi et al. minimised over its line variables
       :math:`l_{ij} = (\mu / (\mu + r^\mathsf{T}\Lambda r))^2` in closed form (a
       Geman-McClure kernel), with :math:`\mu` = ``preference_loop_closure`` ×
       ``max_correspondence_distance``\ ² × the mean number of correspondences per edge
       (Open3D's choice). Levenberg-Marquardt on the Lie algebra: left increments
       :math:`P_i \leftarrow \exp(\xi_i) P_i`, Jacobians :math:`\pm J_l^{-1}(r)
       \operatorname{Ad}(P_j^{-1})`, the sparse normal equations solved by
       ``scipy.sparse``. Then loop closures with :math:`l_{ij}` below
       ``edge_prune_threshold`` are pruned (unless that disconnects the graph) and the
       graph optimised again.

    Parameters
    ----------
    sets : sequence of (n_i, 3) float arrays
        At least two 3-D point sets of any sizes (at least 6 points each, 3 with
        ``metric="point_to_point"``), not collinear.
    init : (k, 4, 4) float array, optional
        A rigid start transform per set into a common frame; only their relative
        transforms matter: each pairwise ICP starts from them. Omitted: the identity (the
        sets are taken as roughly aligned, as by a scanner).
    max_iterations : int, default 100
        Most Levenberg-Marquardt iterations per optimisation round (two rounds), ``>= 1``.
    tolerance : float, default 1e-9
        Stop an optimisation round when the objective decreases by less than this fraction
        of its value in an iteration, ``>= 0``. (Open3D's
        ``GlobalOptimizationConvergenceCriteria`` stops at a relative increment of 1e-6;
        the tighter default costs a few cheap iterations on graphs of tens of nodes.)
    max_correspondence_distance : float, optional
        The pairs' distance bound (``> 0``, in the points' units) of the fine pairwise ICP
        (the coarse stages use 4 and 2 × it), of the information matrices and of
        ``fitness``; it also sets the loop closures' :math:`\mu`. Omitted: 2 × the median
        distance between nearest neighbours within the sets.
    metric : {"symmetric", "point_to_plane", "point_to_point"}, default "symmetric"
        The metric of the coarse-to-fine pairwise ICP stages (the last stage is always
        point-to-point): ``"symmetric"`` both sets' normals (Rusinkiewicz 2019),
        ``"point_to_plane"`` the target's normals, ``"point_to_point"`` plain distances.
        Normals are estimated from 10 neighbours; a pair whose target is flat (the plane
        metrics undetermined) falls back to point-to-point.
    neighbors : int, optional
        Register each set with its next ``neighbors`` sets in order, ``1 <= neighbors <=
        k - 1`` (1 gives a chain); consecutive pairs then count as trusted odometry.
        Omitted: every pair up to 10 sets (no odometry), 2 beyond.
    min_fitness : float, default 0.3
        Drop pairwise edges whose ICP fitness (the share of points with a partner within
        ``max_correspondence_distance``) is below this: they overlap too little to be
        trusted; ``0 <= min_fitness <= 1``.
    edge_prune_threshold : float, default 0.25
        Prune the loop closures whose line-process weight :math:`l_{ij}` falls below this
        after the first optimisation round (Open3D's default), ``0 <= ... < 1``.
    preference_loop_closure : float, default 1.0
        The weight of loop closures in :math:`\mu` (Open3D's option), ``> 0``; larger keeps
        more loop closures.
    icp_max_iterations : int, default 30
        Most iterations per pairwise ICP stage (four stages per pair), ``>= 1``.
    progress : callable, optional
        ``progress(done, total, message)`` after every pairwise ICP iteration and
        optimisation step; it may raise :class:`~algorithms.core.errors.Cancelled`, which
        propagates.

    Returns
    -------
    MultiwayResult
        ``transforms``, ``rotations``, ``scales`` (all 1.0), ``translations``, ``rmse``
        and ``fitness`` per set over its kept edges, ``edges``, ``edge_fitness``,
        ``edge_kept``, ``iterations``, ``converged`` and ``reason``; no ``mean_shape``.

    Raises
    ------
    InvalidInputError
        Fewer than 2 sets or ``d != 3`` (``field="sets"``); a malformed or non-finite set,
        another dimension than ``sets[0]``'s or too few points (``field="sets[i]"``); a
        malformed ``init``; ``neighbors > k - 1``; an option out of range.
    DegenerateInputError
        A set too flat for its pairwise ICP (coincident, collinear or, for the plane
        metrics of a pair, coplanar points) (``field="sets[i]"``); a graph left
        disconnected by the edges of sufficient fitness, or sets without distinct points
        to estimate ``max_correspondence_distance`` from
        (``field="max_correspondence_distance"``).

    Warns
    -----
    ConvergenceWarning
        Whenever ``converged`` is False.

    Notes
    -----
    **Pairwise ICP: symmetric, then point-to-point.** Measured on five noisy (1 % of the
    size) partial (70 %) views of generated shapes, ten seeds each: point-to-plane stages
    alone (Open3D's multiway example) left pose errors up to 1.9° on a bent bar (stuck
    in a sliding minimum at the wide bounds) and 0.3-0.8° on a smooth blob (the tangent
    planes of sparse samples are biased on a curved surface); the symmetric metric
    (Rusinkiewicz 2019) for the coarse-to-fine stages and a point-to-point polish at the
    tight bound left at most 0.25° on both, as fast.

    **Odometry.** Open3D trusts the edges between consecutive sets (odometry: no line
    process, never pruned). Here that holds only when the pairs follow the order
    (``neighbors`` given, or more than 10 sets); among all pairs the input order may mean
    nothing, and a consecutive pair stuck in a wrong ICP minimum would otherwise pull the
    whole graph (measured: 2° errors where the robust graph has 0.2°).

    **The gauge.** Only the relative transforms are determined; set 0 is the reference
    (Open3D's ``reference_node=0``): ``transforms[0]`` is the identity.

    **The residual's frame.** Open3D writes the edge residual as
    :math:`Z^{-1} P_j^{-1} P_i` (a twist in set ``i``'s frame) but builds the information
    matrix from the target points (set ``j``'s frame); here both are in set ``j``'s frame,
    :math:`r = \log(P_j^{-1} P_i Z^{-1})`, so that :math:`r^\mathsf{T}\Lambda r` is the
    second-order change of the pair's point-to-point cost. The inverse left Jacobian is
    used to second order, :math:`J_l^{-1}(r) \approx I - \tfrac12 \operatorname{ad}_r +
    \tfrac1{12} \operatorname{ad}_r^2`.

    **Cost.** The pairwise ICP runs dominate (``k(k-1)/2`` of them up to 10 sets, about
    ``neighbors · k`` beyond); the optimisation solves a ``6(k-1)`` sparse system per
    iteration. The pairwise runs are independent and go through
    :func:`~algorithms.core.parallel.task_map`: one after the other here, as tasks across
    the cluster in a job of the service; each result is the same either way. The plane
    stages need normals, a function of a set alone: run here, each set's are estimated
    once for all its pairs; as tasks, once per pair (a task gets its two sets only), not
    once per stage. At 12 views of 2,100 points (``bench/multiway.py``'s data) that
    halves the call, 1.46 s → 0.71 s, with the same transforms to the bit.

    References
    ----------
    .. [1] S. Choi, Q.-Y. Zhou and V. Koltun, "Robust reconstruction of indoor scenes",
       CVPR 2015 (line processes for loop closures).
    .. [2] R. Kümmerle et al., "g2o: a general framework for graph optimization", ICRA
       2011.
    .. [3] Q.-Y. Zhou, J. Park and V. Koltun, "Open3D: a modern library for 3D data
       processing", arXiv:1801.09847, 2018 (multiway registration).
    .. [4] S. Rusinkiewicz, "A symmetric objective function for ICP", ACM TOG 38(4), 85,
       2019.
    """
    report = as_progress(progress)
    pts = check_sets(sets, correspondences=False, metric=metric)
    k = len(pts)
    start = None if init is None else check_transforms(init, k, 3, "rigid")
    check_neighbors(neighbors, k)
    trees = [cKDTree(p) for p in pts]
    opts = _GraphOptions(
        max_dist=(max_correspondence_distance if max_correspondence_distance is not None
                  else _default_distance(pts, trees)),
        metric=metric,
        neighbors=neighbors,
        min_fitness=min_fitness,
        prune=edge_prune_threshold,
        preference=preference_loop_closure,
        icp_iterations=icp_max_iterations,
        max_iterations=max_iterations,
        tolerance=tolerance,
    )
    result = _pose_graph(pts, trees, start, opts, report)
    if not result.converged:
        warn(f"Pose-graph optimisation did not converge: {result.reason}.",
             ConvergenceWarning)
    return result


def check_neighbors(neighbors: int | None, k: int) -> None:
    """``neighbors``, when given, is at most the number of other sets, ``k - 1``
    (``field="neighbors"``)."""
    if neighbors is not None:
        as_int(neighbors, name="neighbors", minimum=1, maximum=k - 1,
               reason="the number of other sets")


@dataclass(frozen=True)
class _GraphOptions:
    max_dist: float
    metric: Metric
    neighbors: int | None
    min_fitness: float
    prune: float
    preference: float
    icp_iterations: int
    max_iterations: int
    tolerance: float


@dataclass
class _Edge:
    i: int
    j: int
    z: FloatArray            # ICP: maps set i into set j's frame
    info: FloatArray         # 6×6 information matrix (rotation first)
    fitness: float
    pairs: int               # correspondences within the bound
    odometry: bool
    kept: bool = True


def _default_distance(pts: list[FloatArray], trees: Sequence[cKDTree]) -> float:
    spacings = []
    for p, tree in zip(pts, trees, strict=True):
        sample = p[:: max(1, len(p) // SPACING_SAMPLE)]
        dist, _ = cast(KnnQuery, tree.query(sample, k=2))
        spacings.append(float(np.median(dist[:, 1])))
    value = SPACING_FACTOR * float(np.median(spacings))
    if not value > 0:
        raise DegenerateInputError(
            "Expected the sets to hold distinct points to estimate "
            "max_correspondence_distance from their spacing, got a median spacing of 0; "
            "give max_correspondence_distance.", field="max_correspondence_distance")
    return value


def _pairs(k: int, neighbors: int | None) -> list[tuple[int, int]]:
    if neighbors is None:
        neighbors = k - 1 if k <= ALL_PAIRS_UP_TO else DEFAULT_NEIGHBORS
    return [(i, j) for i in range(k) for j in range(i + 1, min(k, i + neighbors + 1))]


def _register_pair(src: FloatArray, dst: FloatArray, start: FloatArray, opts: _GraphOptions,
                   report: Progress) -> tuple[FloatArray, float]:
    """ICP of ``src`` onto ``dst`` by the :data:`STAGES`; returns the transform and fitness."""
    transform = start
    fitness = 0.0
    with reuse_normals():  # the plane stages estimate the two sets' normals once, not each
        for stage, (factor, stage_metric) in enumerate(STAGES):
            bound = factor * opts.max_dist
            metric: Metric = stage_metric or opts.metric
            for attempt in range(2):
                try:
                    with warnings.catch_warnings():
                        warnings.simplefilter("ignore", ConvergenceWarning)
                        res = icp(src, dst, metric=metric, init=transform,
                                  max_iterations=opts.icp_iterations,
                                  max_correspondence_distance=bound,
                                  progress=_offset(report, stage * opts.icp_iterations))
                    break
                except DegenerateInputError:
                    if metric == "point_to_point" or attempt:
                        raise
                    metric = "point_to_point"   # a flat target: point-to-plane is undetermined
            transform, fitness = res.transform, res.fitness
            if res.fitness == 0.0:
                break
    return transform, fitness


def _pair_call(call: tuple[int, int, int, FloatArray, FloatArray, FloatArray],
               report: Progress, *, opts: _GraphOptions, icp_work: int, work: int
               ) -> tuple[FloatArray, float, FloatArray, int]:
    """One pair's registration, a call of :func:`~algorithms.core.parallel.task_map`:
    ``call`` is ``(number, i, j, set i, set j, start)``; reports in the graph's units.
    Returns the edge's transform, fitness, information matrix (of the target points paired
    within the bound under the transform) and count of those pairs: all the edge needs of
    the two sets, computed where the sets are."""
    number, i, j, src, dst, guess = call

    def scaled(done: float, total: float, message: str = "") -> None:  # total: ICP's own
        report(number * icp_work + done, work, message)

    z, fit = _register_pair(src, dst, guess, opts, scaled)
    moved = src @ z[:3, :3].T + z[:3, 3]
    dist, idx = cast(KnnQuery, cKDTree(dst).query(moved, distance_upper_bound=opts.max_dist))
    idx = idx[np.isfinite(dist)]
    report((number + 1) * icp_work, work, f"pair {i}→{j}: fitness {fit:.3g}")
    return z, fit, _information(dst[idx]), int(idx.size)


def _offset(report: Progress, base: int) -> Progress:
    """``report`` with ``base`` added to ``done`` (the caller's wrapper knows the total)."""
    def inner(done: float, total: float, message: str = "") -> None:
        report(base + done, total, message)
    return inner


def _information(q: FloatArray) -> FloatArray:
    """``Σ [-[q]× | I]ᵀ [-[q]× | I]`` over the rows ``q``."""
    info = np.zeros((6, 6))
    s = q.sum(axis=0)
    info[:3, :3] = float(np.einsum("ij,ij->", q, q)) * np.eye(3) - q.T @ q
    info[:3, 3:] = hat(s)
    info[3:, :3] = hat(s).T
    info[3:, 3:] = len(q) * np.eye(3)
    return info


def _pose_graph(pts: list[FloatArray], trees: Sequence[cKDTree], start: FloatArray | None,
                opts: _GraphOptions, report: Progress) -> MultiwayResult:
    k = len(pts)
    pairs = _pairs(k, opts.neighbors)
    # Consecutive sets are odometry (trusted, as scans in acquisition order) only when the
    # pairs follow the order; among all pairs the order may mean nothing.
    sequential = opts.neighbors is not None or k > ALL_PAIRS_UP_TO
    icp_work = len(STAGES) * opts.icp_iterations
    work = len(pairs) * icp_work + 2 * opts.max_iterations

    if start is not None:
        start = np.einsum("ij,kjl->kil", np.linalg.inv(start[0]), start)
    # The pairwise registrations are independent: the installed mapper may run them
    # elsewhere (the service: as Dask tasks), each sent only its two sets.
    calls = [(number, i, j, pts[i], pts[j],
              np.eye(4) if start is None else np.linalg.inv(start[j]) @ start[i])
             for number, (i, j) in enumerate(pairs)]
    with reuse_normals():  # run here, the pairs estimate each set's normals once in all
        registered = task_map(functools.partial(_pair_call, opts=opts, icp_work=icp_work,
                                                work=work), calls, report)
    edges = [_Edge(i, j, z, info, fit, count, odometry=sequential and j == i + 1,
                   kept=fit >= opts.min_fitness)
             for (i, j), (z, fit, info, count) in zip(pairs, registered, strict=True)]
    _check_connected(k, edges, opts)
    poses = _spanning_tree_poses(k, [e for e in edges if e.kept])
    used = [e for e in edges if e.kept]
    mu = opts.preference * opts.max_dist ** 2 * float(np.mean([e.pairs for e in used]))
    base = len(pairs) * icp_work
    poses, its1, conv, reason = _levenberg_marquardt(poses, used, mu, opts, report, base,
                                                     work)
    # Prune the loop closures the line process turned (nearly) off, then optimise again
    # (unless pruning would disconnect the graph).
    weak = [e for e in used if not e.odometry and
            _confidence(_residual(poses, e), e.info, mu) < opts.prune]
    if weak and _components(k, [e for e in used if e not in weak]) == 1:
        for e in weak:
            e.kept = False
        used = [e for e in edges if e.kept]
        poses, its2, conv, reason = _levenberg_marquardt(poses, used, mu, opts, report,
                                                         base + opts.max_iterations, work)
        reason += f"; {len(weak)} loop closure{'s' if len(weak) > 1 else ''} pruned"
    else:
        its2 = 0
    rmse, fitness = _agreement(pts, trees, poses, used, opts.max_dist)
    return MultiwayResult(
        transforms=poses,
        rotations=poses[:, :3, :3].copy(),
        scales=np.ones(k),
        translations=poses[:, :3, 3].copy(),
        mean_shape=None,
        rmse=rmse,
        fitness=fitness,
        edges=np.array([(e.i, e.j) for e in edges], dtype=np.int64).reshape(-1, 2),
        edge_fitness=np.array([e.fitness for e in edges], dtype=np.float64),
        edge_kept=np.array([e.kept for e in edges], dtype=bool),
        iterations=its1 + its2,
        converged=conv,
        reason=reason,
    )


def _labels(k: int, edges: list[_Edge]) -> tuple[int, NDArray[np.int32]]:
    rows = np.array([e.i for e in edges], dtype=np.int64)
    cols = np.array([e.j for e in edges], dtype=np.int64)
    graph = sp.coo_matrix((np.ones(len(edges)), (rows, cols)), shape=(k, k))
    count, labels = connected_components(graph, directed=False)
    return int(count), labels


def _components(k: int, edges: list[_Edge]) -> int:
    return _labels(k, edges)[0]


def _check_connected(k: int, edges: list[_Edge], opts: _GraphOptions) -> None:
    count, labels = _labels(k, [e for e in edges if e.kept])
    if count > 1:
        apart = [int(i) for i in np.flatnonzero(labels != labels[0])]
        listed = ", ".join(str(i) for i in apart[:10]) + (" ..." if len(apart) > 10 else "")
        raise DegenerateInputError(
            f"Expected every set to overlap another with ICP fitness >= min_fitness = "
            f"{opts.min_fitness:g} within max_correspondence_distance = {opts.max_dist:g}, "
            f"got sets {listed} not connected to set 0 by such an edge: their poses are "
            "undetermined. Give a larger max_correspondence_distance, a closer `init`, "
            "more `neighbors` or a lower min_fitness.", field="max_correspondence_distance")


def _spanning_tree_poses(k: int, edges: list[_Edge]) -> FloatArray:
    """Poses composed along the spanning tree of highest fitness, rooted at set 0."""
    weight: dict[tuple[int, int], _Edge] = {}
    for e in edges:  # keep the best edge per unordered pair
        key = (e.i, e.j)
        if key not in weight or e.fitness > weight[key].fitness:
            weight[key] = e
    rows = np.array([e.i for e in weight.values()], dtype=np.int64)
    cols = np.array([e.j for e in weight.values()], dtype=np.int64)
    cost = np.array([2.0 - e.fitness for e in weight.values()])  # > 0: zero means "no edge"
    tree = minimum_spanning_tree(sp.coo_matrix((cost, (rows, cols)), shape=(k, k)))
    order, parent = breadth_first_order(tree + tree.T, 0, directed=False)
    poses = np.tile(np.eye(4), (k, 1, 1))
    for child in order[1:]:
        p = int(parent[child])
        if (child, p) in weight:                 # Z maps child into parent: P_c = P_p Z
            poses[child] = poses[p] @ weight[child, p].z
        else:                                    # Z maps parent into child: P_c = P_p Z⁻¹
            poses[child] = poses[p] @ inverse(weight[p, child].z)
    return poses


def _levenberg_marquardt(poses: FloatArray, edges: list[_Edge], mu: float,
                         opts: _GraphOptions, report: Progress, base: float, total: float
                         ) -> tuple[FloatArray, int, bool, str]:
    k = poses.shape[0]
    cost = _cost(poses, edges, mu)
    lam = 1e-5                     # Marquardt damping, relative to the diagonal of H
    accepted = 0
    for it in range(1, opts.max_iterations + 1):
        h, g = _normal_equations(poses, edges, mu, k)
        if not np.abs(g).max(initial=0.0) > 0:
            return poses, accepted, True, "gradient zero (graph consistent to rounding)"
        diag = h.diagonal()
        while True:
            damped = (h + sp.diags(lam * np.maximum(diag, 1e-12 * diag.max()))).tocsc()
            step = spsolve(damped, -g)
            xi = step.reshape(-1, 6)
            candidate = poses.copy()
            for node in range(1, k):
                candidate[node] = exp(xi[node - 1]) @ poses[node]
            new = _cost(candidate, edges, mu)
            if new < cost:
                break
            lam *= 4.0
            if lam > MAX_DAMPING:
                return poses, accepted, True, ("no step decreases the objective (a minimum "
                                               "to rounding)")
        lam = max(lam / 3.0, 1e-12)
        change = (cost - new) / cost if cost > 0 else 0.0
        poses, cost = candidate, new
        accepted += 1
        report(base + it, total, f"pose graph iteration {accepted}: objective {cost:.6g}")
        if change < opts.tolerance:
            return poses, accepted, True, (f"relative objective change {change:.3g} below "
                                           f"tolerance {opts.tolerance:g}")
        if float(np.abs(step).max()) < 1e-15:
            return poses, accepted, True, "step at rounding level"
    return poses, accepted, False, (f"max_iterations = {opts.max_iterations} reached before "
                                    "the tolerance was met")


def _residual(poses: FloatArray, e: _Edge) -> FloatArray:
    return log(inverse(poses[e.j]) @ poses[e.i] @ inverse(e.z))


def _confidence(r: FloatArray, info: FloatArray, mu: float) -> float:
    s = float(r @ info @ r)
    return (mu / (mu + s)) ** 2


def _cost(poses: FloatArray, edges: list[_Edge], mu: float) -> float:
    total = 0.0
    for e in edges:
        r = _residual(poses, e)
        s = float(r @ e.info @ r)
        total += s if e.odometry else mu * s / (mu + s)
    return total


def _normal_equations(poses: FloatArray, edges: list[_Edge], mu: float, k: int
                      ) -> tuple[sp.csr_matrix, FloatArray]:
    """``H = Σ w Jᵀ Λ J`` and ``g = Σ w Jᵀ Λ r`` over the free poses 1..k-1 (sparse)."""
    size = 6 * (k - 1)
    rows: list[IntArray] = []
    cols: list[IntArray] = []
    vals: list[FloatArray] = []
    g = np.zeros(size)
    block = np.arange(6)
    for e in edges:
        r = _residual(poses, e)
        w = 1.0 if e.odometry else _confidence(r, e.info, mu)
        jac = left_jacobian_inverse(r) @ adjoint(inverse(poses[e.j]))
        parts = [(e.i, jac), (e.j, -jac)]
        for a, ja in parts:
            if a == 0:
                continue
            g[6 * (a - 1):6 * a] += w * ja.T @ (e.info @ r)
            for b, jb in parts:
                if b == 0:
                    continue
                rows.append(np.repeat(6 * (a - 1) + block, 6))
                cols.append(np.tile(6 * (b - 1) + block, 6))
                vals.append((w * ja.T @ e.info @ jb).ravel())
    if not vals:
        return sp.csr_matrix((size, size)), g
    h = sp.coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                      shape=(size, size)).tocsr()
    return h, g


def _agreement(pts: list[FloatArray], trees: Sequence[cKDTree], poses: FloatArray,
               edges: list[_Edge], max_dist: float) -> tuple[FloatArray, FloatArray]:
    k = len(pts)
    partners: list[set[int]] = [set() for _ in range(k)]
    for e in edges:
        partners[e.i].add(e.j)
        partners[e.j].add(e.i)
    # each tree queried once, for all the sets paired with it (enough points at once for
    # the query's threads); each set keeps its nearest distance over its partners
    best = [np.full(len(p), np.inf) for p in pts]
    for j in range(k):
        sources = sorted(partners[j])
        if not sources:
            continue
        rel = inverse(poses[j]) @ poses[sources]           # set i's frame into set j's
        moved = np.concatenate([pts[i] @ r[:3, :3].T + r[:3, 3]
                                for i, r in zip(sources, rel, strict=True)])
        dist, _ = trees[j].query(moved, distance_upper_bound=max_dist,
                                 workers=query_workers(len(moved)))
        ends = np.cumsum([len(pts[i]) for i in sources])
        for i, part in zip(sources, np.split(dist, ends[:-1]), strict=True):
            np.minimum(best[i], part, out=best[i])
    rmse, fitness = np.zeros(k), np.zeros(k)
    for i in range(k):
        inside = best[i][np.isfinite(best[i])]
        fitness[i] = inside.size / len(pts[i])
        rmse[i] = math.sqrt(float(inside @ inside) / inside.size) if inside.size else 0.0
    return rmse, fitness

