"""Multiway registration: several point sets brought into one frame at once, by generalised
Procrustes analysis when the rows correspond, by pairwise ICP and pose-graph optimisation on
SE(3) when they do not."""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import breadth_first_order, connected_components, minimum_spanning_tree
from scipy.sparse.linalg import spsolve
from scipy.spatial import cKDTree
from scipy.spatial.transform import Rotation

from algorithms.core.errors import ConvergenceWarning, DegenerateInputError, InvalidInputError
from algorithms.core.linalg import procrustes
from algorithms.core.progress import Progress, as_progress
from algorithms.core.types import BoolArray, FloatArray, IntArray
from algorithms.core.validation import (
    as_bool,
    as_choice,
    as_float,
    as_int,
    as_points,
    check_span,
)
from algorithms.registration.icp import check_init, icp

__all__ = ["MultiwayResult", "multiway", "check_sets", "check_transforms", "MODELS", "METRICS"]

#: The accepted values of ``model`` and ``metric``.
MODELS = ("rigid", "similarity")
METRICS = ("symmetric", "point_to_plane", "point_to_point")

#: Up to this many sets every pair is registered; beyond, each set with its next neighbours.
ALL_PAIRS_UP_TO = 10
#: Neighbours in order per set when there are more than ``ALL_PAIRS_UP_TO`` sets.
DEFAULT_NEIGHBORS = 2
#: The pairwise ICP runs coarse to fine with these multiples of ``max_correspondence_distance``
#: and metrics (None: the ``metric`` asked for): wide bounds pull in a far start, the tight
#: ones remove the bias that pairs reaching past the edge of the overlap put on the wide
#: ones, and the point-to-point polish removes the curvature bias of the plane metrics on
#: sparse samples (a tangent plane at a sample misses the curved surface between samples).
STAGES: tuple[tuple[float, str | None], ...] = (
    (4.0, None), (2.0, None), (1.0, None), (1.0, "point_to_point"))
#: The default ``max_correspondence_distance`` is this multiple of the median point spacing.
SPACING_FACTOR = 2.0
#: Points per set used to estimate the spacing (a random-free, evenly strided subset).
SPACING_SAMPLE = 2000
#: An objective at or below this fraction of the data's squared size is an exact fit.
ROUNDING_RTOL = 1e-24
#: Levenberg-Marquardt gives up when its damping exceeds this (no descent step left).
MAX_DAMPING = 1e16

@dataclass(frozen=True, eq=False)
class MultiwayResult:
    """One transform per set into the frame of set 0, and how well the sets agree there.

    Attributes
    ----------
    transforms : (k, d+1, d+1) float array
        ``transforms[i]`` maps the points of set ``i`` into the frame of set 0 (the
        reference: ``transforms[0]`` is the identity), homogeneous ``[[s R, t], [0, 1]]``.
    rotations : (k, d, d) float array
        The rotation ``R`` of each transform (determinant +1).
    scales : (k,) float array
        The scale ``s`` of each transform: all 1.0 for the rigid model; relative to set 0
        for similarity.
    translations : (k, d) float array
        The translation ``t`` of each transform, applied after ``s R``.
    mean_shape : (n, d) float array or None
        Generalised Procrustes only: the mean shape (consensus), row ``j`` the mean of the
        sets' row ``j`` after their transforms, in the frame (and units) of set 0. Null for
        the pose graph.
    rmse : (k,) float array
        Per set, in set 0's units. Procrustes: the root-mean-square distance of the moved
        set's rows to the mean shape's. Pose graph: the RMS distance from the set's moved
        points to the nearest moved point of the sets it kept an edge with, over the points
        that have one within ``max_correspondence_distance`` (0.0 when none has).
    fitness : (k,) float array
        Pose graph: per set, the fraction of its points with a point of a set it kept an
        edge with within ``max_correspondence_distance`` (Open3D's fitness, over the
        graph). Procrustes: all 1.0 (every row has its partner).
    edges : (m, 2) int array
        Pose graph: the pairs ``(i, j)`` registered by ICP (set ``i`` onto set ``j``), kept
        or not. Procrustes: empty (no pairwise registration).
    edge_fitness : (m,) float array
        Pose graph: the ICP fitness of each edge (share of set ``i``'s points with a
        partner in set ``j`` within ``max_correspondence_distance``). Procrustes: empty.
    edge_kept : (m,) bool array
        Pose graph: whether the edge is in the final graph; dropped for low fitness
        (below ``min_fitness``) or pruned by the line process (a loop closure whose
        confidence fell below ``edge_prune_threshold``). Procrustes: empty.
    iterations : int
        Procrustes: passes of the rotation/scale/mean updates. Pose graph: accepted
        Levenberg-Marquardt steps of both optimisation rounds.
    converged : bool
        True when the relative decrease of the objective fell below ``tolerance`` (or the
        fit is exact); False when ``max_iterations`` ran out. A ``ConvergenceWarning``
        accompanies False.
    reason : str
        Why the iterations stopped, in words.
    """

    transforms: FloatArray
    rotations: FloatArray
    scales: FloatArray
    translations: FloatArray
    mean_shape: FloatArray | None
    rmse: FloatArray
    fitness: FloatArray
    edges: IntArray
    edge_fitness: FloatArray
    edge_kept: BoolArray
    iterations: int
    converged: bool
    reason: str


# --- input checks (shared with the catalog) -------------------------------------------------


def check_sets(sets: Any, *, correspondences: bool, model: str = "rigid",
               metric: str = "symmetric", max_points: int | None = None
               ) -> list[FloatArray]:
    """Check the list of point sets for :func:`multiway` and return them as float arrays.

    At least two sets, each an ``(n_i, d)`` array of finite numbers with the same ``d``;
    with ``correspondences`` all of the same length ``n`` (row ``j`` of each is the same
    point) and spread enough to determine their rotation (and scale); without, 3-D and
    enough points for the pairwise ICP. Errors name the set: ``field="sets[2]"``.
    """
    if isinstance(sets, np.ndarray) and sets.ndim == 3:
        sets = list(sets)
    if isinstance(sets, (str, bytes)) or not isinstance(sets, (Sequence, np.ndarray)):
        raise InvalidInputError(f"Expected `sets` to be a list of (n, d) point arrays, got "
                                f"{type(sets).__name__}.", field="sets")
    if len(sets) < 2:
        raise InvalidInputError(f"Expected `sets` to hold at least 2 point sets, got "
                                f"{len(sets)}.", field="sets")
    out = [as_points(s, name=f"sets[{i}]", max_points=max_points) for i, s in enumerate(sets)]
    n, d = out[0].shape
    for i, s in enumerate(out[1:], start=1):
        if s.shape[1] != d:
            raise InvalidInputError(
                f"Expected `sets[{i}]` to have the dimension of `sets[0]` ({d}), got shape "
                f"({s.shape[0]}, {s.shape[1]}).", field=f"sets[{i}]")
        if correspondences and s.shape[0] != n:
            raise InvalidInputError(
                f"Expected `sets[{i}]` to hold as many points as `sets[0]` ({n}, paired row "
                f"by row since correspondences=true), got {s.shape[0]}; give "
                "correspondences=false for sets without known correspondences.",
                field=f"sets[{i}]")
    if correspondences:
        need = max(d - 1, 1 if model == "similarity" else 0)
        why = "its rotation is undetermined" if need == d - 1 and d > 1 else \
            "its scale is undetermined"
        for i, s in enumerate(out):
            check_span(s, f"sets[{i}]", need, why)
        return out
    if d != 3:
        raise InvalidInputError(
            f"Expected 3-D point sets for correspondences=false (the pose graph is on "
            f"SE(3)), got d = {d}; give correspondences=true (generalised Procrustes, any "
            "d) for sets whose rows correspond.", field="sets")
    if model != "rigid":
        raise InvalidInputError(
            f"Expected model='rigid' with correspondences=false (the pose graph is on "
            f"SE(3)), got {model!r}.", field="model")
    fewest = 3 if metric == "point_to_point" else 6
    for i, s in enumerate(out):
        if s.shape[0] < fewest:
            raise InvalidInputError(
                f"Expected `sets[{i}]` to hold at least {fewest} points (pairwise {metric} "
                f"ICP), got {s.shape[0]}.", field=f"sets[{i}]")
        check_span(s, f"sets[{i}]", 2, "the rotation of its pairwise ICP is undetermined")
    return out


def check_transforms(init: Any, k: int, d: int, model: str) -> FloatArray:
    """Check ``init``: ``k`` homogeneous ``(d+1, d+1)`` matrices of the model (rotations
    for rigid, positive multiples of rotations for similarity); ``field="init"``."""
    try:
        arr = np.asarray(init, dtype=np.float64)
    except (TypeError, ValueError):
        raise InvalidInputError(f"Expected `init` to be a ({k}, {d + 1}, {d + 1}) array of "
                                "homogeneous matrices, got one numpy cannot read.",
                                field="init") from None
    if arr.shape != (k, d + 1, d + 1):
        raise InvalidInputError(
            f"Expected `init` to be a ({k}, {d + 1}, {d + 1}) array: one homogeneous matrix "
            f"per set, got shape {tuple(arr.shape)}.", field="init")
    out = np.empty_like(arr)
    for i in range(k):
        try:
            out[i] = check_init(arr[i], d, model)
        except InvalidInputError as err:
            raise InvalidInputError(f"init[{i}]: {err.message}", field="init") from None
    return out


# --- the public function ------------------------------------------------------------------


def multiway(
    sets: Any,
    *,
    correspondences: bool = True,
    model: str = "rigid",
    init: Any = None,
    max_iterations: int = 100,
    tolerance: float = 1e-9,
    max_correspondence_distance: float | None = None,
    metric: str = "symmetric",
    neighbors: int | None = None,
    min_fitness: float = 0.3,
    edge_prune_threshold: float = 0.25,
    preference_loop_closure: float = 1.0,
    icp_max_iterations: int = 30,
    progress: Progress | None = None,
) -> MultiwayResult:
    r"""Register ``k >= 2`` point sets at once; one transform per set into set 0's frame.

    **With correspondences** (row ``j`` of every set is the same point): generalised
    Procrustes analysis (Gower 1975). With the sets centred, :math:`\tilde X_i`, it solves

    .. math::

        \min_{R_i,\ s_i,\ M}\ \sum_{i=1}^{k} \lVert s_i \tilde X_i R_i^\mathsf{T} - M
        \rVert_F^2, \qquad \det R_i = 1,\quad
        \textstyle\sum_i s_i^2 \lVert \tilde X_i \rVert_F^2 = \sum_i \lVert \tilde X_i
        \rVert_F^2

    (:math:`s_i = 1` and no constraint for ``model="rigid"``) by block-coordinate descent
    from :math:`M = \tilde X_0`: each pass rotates every set onto the current mean
    (:func:`~algorithms.core.linalg.procrustes` of :math:`M^\mathsf{T} \tilde X_i`, the
    reflection fixed), then, for similarity, sets the scales to ten Berge's (1977) optimum
    for those rotations, :math:`s_i = \phi_i \sqrt{\sum_j \lVert \tilde X_j \rVert^2} /
    \lVert \tilde X_i \rVert` with :math:`\phi` the top eigenvector of the sets'
    correlation matrix :math:`\Phi_{ij} = \langle Z_i, Z_j \rangle / (\lVert Z_i \rVert
    \lVert Z_j \rVert)`, :math:`Z_i = \tilde X_i R_i^\mathsf{T}`, then takes the mean. The
    objective never increases; the iterations stop when it falls by less than
    ``tolerance`` (relatively). The gauge is then fixed to set 0: every working transform
    is composed with the inverse of set 0's, and the mean shape moved into set 0's frame.

    **Without correspondences** (``correspondences=False``, 3-D): pairwise ICP and
    pose-graph optimisation on SE(3), as Open3D's multiway registration with
    ``global_optimization`` and ``GlobalOptimizationLevenbergMarquardt`` (Choi, Zhou &
    Koltun 2015):

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
       rotation first),

       .. math::

           \min_{P_1..P_{k-1}} \sum_{\text{odometry}} r_{ij}^\mathsf{T} \Lambda_{ij} r_{ij}
           + \sum_{\text{loop closures}} \frac{\mu\, r_{ij}^\mathsf{T} \Lambda_{ij} r_{ij}}
           {\mu + r_{ij}^\mathsf{T} \Lambda_{ij} r_{ij}},

       odometry edges being ``(i, i+1)`` and every other edge a loop closure. The second
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
    sets : sequence of (n_i, d) float arrays
        At least two point sets of the same dimension ``d``; with correspondences all of
        the same length ``n`` (any ``d >= 1``), without them 3-D of any sizes.
    correspondences : bool, default True
        Whether row ``j`` of every set is the same point (generalised Procrustes) or the
        correspondences are unknown (pairwise ICP + pose graph).
    model : {"rigid", "similarity"}, default "rigid"
        Rotation and translation per set, or also a uniform scale (Procrustes only).
    init : (k, d+1, d+1) float array, optional
        A start transform per set into a common frame (rigid, or similarity for the
        Procrustes model); only their relative transforms matter. Procrustes starts its
        mean from the moved sets; the pose graph starts each pairwise ICP from them.
    max_iterations : int, default 100
        Most Procrustes passes, or Levenberg-Marquardt iterations per optimisation round.
    tolerance : float, default 1e-9
        Stop when the objective decreases by less than this fraction in an iteration.
    max_correspondence_distance : float, optional
        Pose graph: the pairs' distance bound of the fine ICP, of the information matrices
        and of ``fitness``; also sets :math:`\mu`. Default: 2 × the median distance
        between nearest neighbours within the sets.
    metric : {"symmetric", "point_to_plane", "point_to_point"}, default "symmetric"
        Pose graph: the metric of the coarse-to-fine pairwise ICP stages (the last stage is
        always point-to-point, see Notes). Normals are estimated from neighbours; a pair
        whose target is flat (the plane metrics undetermined) falls back to point-to-point.
    neighbors : int, optional
        Pose graph: register each set with its next ``neighbors`` sets in order (1 gives a
        chain of odometry edges). Default: every pair up to 10 sets, 2 beyond.
    min_fitness : float, default 0.3
        Pose graph: drop edges whose ICP fitness is below this (they overlap too little
        to be trusted), ``0 <= min_fitness <= 1``.
    edge_prune_threshold : float, default 0.25
        Pose graph: prune loop closures whose line-process weight falls below this after
        the first optimisation (Open3D's default), ``0 <= ... < 1``.
    preference_loop_closure : float, default 1.0
        Pose graph: the weight of loop closures in :math:`\mu` (Open3D's option); larger
        keeps more loop closures.
    icp_max_iterations : int, default 30
        Pose graph: most iterations per pairwise ICP stage (four stages per pair).
    progress : callable, optional
        ``progress(done, total, message)`` after every pass, pairwise ICP iteration and
        optimisation step; it may raise :class:`~algorithms.core.errors.Cancelled`, which
        propagates.

    Returns
    -------
    MultiwayResult
        ``transforms``, ``rotations``, ``scales``, ``translations``, ``mean_shape``,
        ``rmse``, ``fitness``, ``edges``, ``edge_fitness``, ``edge_kept``, ``iterations``,
        ``converged`` and ``reason``.

    Raises
    ------
    InvalidInputError
        Fewer than 2 sets (``field="sets"``); a malformed or non-finite set, another
        dimension than ``sets[0]``'s, or (with correspondences) another length
        (``field="sets[i]"``); no correspondences and ``d != 3`` (``field="sets"``) or
        ``model="similarity"`` (``field="model"``); a malformed ``init``; an option out of
        range.
    DegenerateInputError
        A set too flat to determine its rotation (coincident points; collinear in 3-D;
        coplanar ones for pairwise ICP) or, for similarity, its scale
        (``field="sets[i]"``); without correspondences, a graph left disconnected by the
        edges of sufficient fitness (``field="max_correspondence_distance"``).

    Warns
    -----
    ConvergenceWarning
        Whenever ``converged`` is False.

    Notes
    -----
    **The seed.** The seed document names "optimal registration: assembling several sets"
    (多堆數據的組裝) as an advanced problem of alignment and stops there; the methods here
    are the standard answers to it, Gower's generalised Procrustes analysis for known
    correspondences and the pose graph of Choi et al. without.

    **The scale constraint.** Without one, all scales would shrink to zero. ten Berge's
    constraint (above) and Dryden & Mardia's unit size of the mean give the same
    transforms up to one common scale, which the gauge removes: the scale of the
    consensus minimising :math:`\sum_i \lVert s_i Z_i - M \rVert^2` with
    :math:`\lVert M \rVert` fixed is :math:`s_i \propto \langle \hat Z_i, u \rangle /
    \lVert Z_i \rVert` with :math:`u` the top eigenvector of :math:`\sum_i \hat Z_i \hat
    Z_i^\mathsf{T}`, the same :math:`\phi_i / \lVert Z_i \rVert` as ten Berge's. For two
    sets the relative scale is the ratio of their sizes, :math:`\lVert \tilde X_0 \rVert
    / \lVert \tilde X_1 \rVert`, symmetric in the sets, unlike the one-sided Umeyama scale
    that :func:`scipy.spatial.procrustes` applies; the rotations agree.

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

    **The gauge.** Only the relative transforms are determined; fixing set 0 as the
    reference (Open3D's ``reference_node=0``) makes ``transforms[0]`` the identity and
    expresses ``mean_shape`` and ``rmse`` in set 0's units.

    **The residual's frame.** Open3D writes the edge residual as
    :math:`Z^{-1} P_j^{-1} P_i` (a twist in set ``i``'s frame) but builds the information
    matrix from the target points (set ``j``'s frame); here both are in set ``j``'s frame,
    :math:`r = \log(P_j^{-1} P_i Z^{-1})`, so that :math:`r^\mathsf{T}\Lambda r` is the
    second-order change of the pair's point-to-point cost. The inverse left Jacobian is
    used to second order, :math:`J_l^{-1}(r) \approx I - \tfrac12 \operatorname{ad}_r +
    \tfrac1{12} \operatorname{ad}_r^2`.

    **Cost.** Procrustes: :math:`O(k n d^2)` per pass. Pose graph: the pairwise ICP runs
    dominate (``k(k-1)/2`` of them up to 10 sets, about ``neighbors · k`` beyond); the
    optimisation solves a ``6(k-1)`` sparse system per iteration.

    References
    ----------
    .. [1] J. C. Gower, "Generalized Procrustes analysis", Psychometrika 40(1), 33-51,
       1975.
    .. [2] J. M. F. ten Berge, "Orthogonal Procrustes rotation for two or more matrices",
       Psychometrika 42(2), 267-276, 1977.
    .. [3] I. L. Dryden and K. V. Mardia, *Statistical Shape Analysis*, 2nd ed., Wiley,
       2016, chapter 7.
    .. [4] S. Choi, Q.-Y. Zhou and V. Koltun, "Robust reconstruction of indoor scenes",
       CVPR 2015 (line processes for loop closures).
    .. [5] R. Kümmerle et al., "g2o: a general framework for graph optimization", ICRA
       2011.
    .. [6] Q.-Y. Zhou, J. Park and V. Koltun, "Open3D: a modern library for 3D data
       processing", arXiv:1801.09847, 2018 (multiway registration).
    .. [7] S. Rusinkiewicz, "A symmetric objective function for ICP", ACM TOG 38(4), 85,
       2019.

    Examples
    --------
    >>> import numpy as np
    >>> from algorithms.registration import multiway
    >>> x = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 1.0]])
    >>> turned = x @ np.array([[0.0, -1.0], [1.0, 0.0]]).T + [5.0, 0.0]   # 90°, shifted
    >>> res = multiway([x, turned, x + 1.0])
    >>> res.converged, [float(r) for r in np.round(res.rmse, 12)]
    (True, [0.0, 0.0, 0.0])
    >>> np.round(res.transforms[1], 12) + 0.0
    array([[ 0.,  1.,  0.],
           [-1.,  0.,  5.],
           [ 0.,  0.,  1.]])
    """
    report = as_progress(progress)
    correspondences = as_bool(correspondences, name="correspondences")
    model = as_choice(model, MODELS, name="model")
    metric = as_choice(metric, METRICS, name="metric")
    max_iterations = as_int(max_iterations, name="max_iterations", minimum=1)
    tolerance = as_float(tolerance, name="tolerance", minimum=0.0)
    pts = check_sets(sets, correspondences=correspondences, model=model, metric=metric)
    k, d = len(pts), pts[0].shape[1]
    start = None if init is None else check_transforms(init, k, d, model)
    if correspondences:
        return _procrustes(pts, model, start, max_iterations, tolerance, report)
    max_dist = None
    if max_correspondence_distance is not None:
        max_dist = as_float(max_correspondence_distance, name="max_correspondence_distance",
                            minimum=0.0, inclusive=False)
    if neighbors is not None:
        neighbors = as_int(neighbors, name="neighbors", minimum=1, maximum=k - 1,
                           reason="the number of other sets")
    opts = _GraphOptions(
        max_dist=max_dist if max_dist is not None else _default_distance(pts),
        metric=metric,
        neighbors=neighbors,
        min_fitness=as_float(min_fitness, name="min_fitness", minimum=0.0, maximum=1.0),
        prune=as_float(edge_prune_threshold, name="edge_prune_threshold", minimum=0.0,
                       maximum=1.0, inclusive=(True, False)),
        preference=as_float(preference_loop_closure, name="preference_loop_closure",
                            minimum=0.0, inclusive=False),
        icp_iterations=as_int(icp_max_iterations, name="icp_max_iterations", minimum=1),
        max_iterations=max_iterations,
        tolerance=tolerance,
    )
    return _pose_graph(pts, start, opts, report)


# --- generalised Procrustes ---------------------------------------------------------------


def _procrustes(pts: list[FloatArray], model: str, start: FloatArray | None,
                max_iterations: int, tolerance: float, report: Progress) -> MultiwayResult:
    k = len(pts)
    n, d = pts[0].shape
    centres = np.stack([p.mean(axis=0) for p in pts])                  # (k, d)
    x = np.stack(pts) - centres[:, None, :]                             # (k, n, d)
    sq = np.einsum("knd,knd->k", x, x)                                  # ‖X̃_i‖²
    total = float(sq.sum())
    scales = np.ones(k)
    if start is None:
        mean = x[0].copy()
    else:  # the mean of the sets as the start moves them (the linear parts suffice)
        mean = np.einsum("kij,knj->ni", start[:, :d, :d], x) / k
    objective = math.inf
    converged, reason, it = False, "", 0
    for it in range(1, max_iterations + 1):
        rot = procrustes(np.einsum("nd,kne->kde", mean, x)).rotation      # (k, d, d)
        z = np.einsum("kij,knj->kni", rot, x)                           # Z_i = X̃_i R_iᵀ
        if model == "similarity":
            scales = _ten_berge(z, sq, total)
        y = z * scales[:, None, None]
        mean = y.mean(axis=0)
        diff = y - mean
        new = float(np.einsum("knd,knd->", diff, diff))
        report(it, max_iterations, f"Procrustes pass {it}: objective {new:.6g}")
        if new <= ROUNDING_RTOL * total:
            converged, reason = True, "objective at rounding level (exact fit)"
            break
        if math.isfinite(objective) and objective - new <= tolerance * objective:
            change = (objective - new) / objective
            converged, reason = True, (f"relative objective change {change:.3g} below "
                                       f"tolerance {tolerance:g}")
            break
        objective = new
    else:
        reason = f"max_iterations = {max_iterations} reached before the tolerance was met"
    # Gauge: compose every working map W_i(x) = s_i R_i (x - c_i) with W_0⁻¹.
    rel_scale = scales / scales[0]
    rotations = np.einsum("ji,kjl->kil", rot[0], rot)                   # R_0ᵀ R_i
    linear = rotations * rel_scale[:, None, None]
    translations = centres[0] - np.einsum("kij,kj->ki", linear, centres)
    rotations[0] = np.eye(d)
    translations[0] = 0.0
    linear[0] = np.eye(d)
    mean_shape = mean @ rot[0] / scales[0] + centres[0]
    rmse = np.sqrt(np.einsum("knd,knd->k", diff, diff) / n) / scales[0]
    if not converged:
        warnings.warn(f"Generalised Procrustes did not converge: {reason}.",
                      ConvergenceWarning, stacklevel=3)
    return MultiwayResult(
        transforms=_homogeneous(linear, translations),
        rotations=rotations,
        scales=rel_scale if model == "similarity" else np.ones(k),
        translations=translations,
        mean_shape=mean_shape,
        rmse=rmse,
        fitness=np.ones(k),
        edges=np.zeros((0, 2), dtype=np.int64),
        edge_fitness=np.zeros(0),
        edge_kept=np.zeros(0, dtype=bool),
        iterations=it,
        converged=converged,
        reason=reason,
    )


def _ten_berge(z: FloatArray, sq: FloatArray, total: float) -> FloatArray:
    """The optimal scales for rotated sets ``z`` under ``Σ s_i² ‖X_i‖² = Σ ‖X_i‖²``."""
    norms = np.sqrt(sq)
    gram = np.einsum("knd,lnd->kl", z, z) / np.outer(norms, norms)
    _, vecs = np.linalg.eigh(gram)
    phi = vecs[:, -1] * (1.0 if vecs[:, -1].sum() >= 0 else -1.0)
    if not (phi > 0).all():
        i = int(np.argmin(phi))
        raise DegenerateInputError(
            f"Expected every set to correlate positively with the consensus, got `sets[{i}]` "
            "opposed to it: no positive scale fits it (its shape does not match the "
            "others').", field=f"sets[{i}]")
    return phi * math.sqrt(total) / norms


# --- pose graph ---------------------------------------------------------------------------


@dataclass(frozen=True)
class _GraphOptions:
    max_dist: float
    metric: str
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


def _default_distance(pts: list[FloatArray]) -> float:
    spacings = []
    for p in pts:
        sample = p[:: max(1, len(p) // SPACING_SAMPLE)]
        dist, _ = cKDTree(p).query(sample, k=2)
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
    for stage, (factor, stage_metric) in enumerate(STAGES):
        bound = factor * opts.max_dist
        metric = stage_metric or opts.metric
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
    info[:3, 3:] = _hat(s)
    info[3:, :3] = _hat(s).T
    info[3:, 3:] = len(q) * np.eye(3)
    return info


def _pose_graph(pts: list[FloatArray], start: FloatArray | None, opts: _GraphOptions,
                report: Progress) -> MultiwayResult:
    k = len(pts)
    pairs = _pairs(k, opts.neighbors)
    # Consecutive sets are odometry (trusted, as scans in acquisition order) only when the
    # pairs follow the order; among all pairs the order may mean nothing.
    sequential = opts.neighbors is not None or k > ALL_PAIRS_UP_TO
    trees = [cKDTree(p) for p in pts]
    icp_work = len(STAGES) * opts.icp_iterations
    total = len(pairs) * icp_work + 2 * opts.max_iterations

    def scaled(base: float) -> Progress:
        def inner(done: float, _total: float, message: str = "") -> None:
            report(base + done, total, message)
        return inner

    if start is not None:
        start = np.einsum("ij,kjl->kil", np.linalg.inv(start[0]), start)
    edges: list[_Edge] = []
    for e, (i, j) in enumerate(pairs):
        guess = np.eye(4) if start is None else np.linalg.inv(start[j]) @ start[i]
        z, fitness = _register_pair(pts[i], pts[j], guess, opts, scaled(e * icp_work))
        moved = pts[i] @ z[:3, :3].T + z[:3, 3]
        dist, idx = trees[j].query(moved, distance_upper_bound=opts.max_dist)
        idx = idx[np.isfinite(dist)]
        edges.append(_Edge(i, j, z, _information(pts[j][idx]), fitness, int(idx.size),
                           odometry=sequential and j == i + 1,
                           kept=fitness >= opts.min_fitness))
        report((e + 1) * icp_work, total, f"pair {i}→{j}: fitness {fitness:.3g}")
    _check_connected(k, edges, opts)
    poses = _spanning_tree_poses(k, [e for e in edges if e.kept])
    used = [e for e in edges if e.kept]
    mu = opts.preference * opts.max_dist ** 2 * float(np.mean([e.pairs for e in used]))
    base = len(pairs) * icp_work
    poses, its1, conv, reason = _levenberg_marquardt(poses, used, mu, opts, report, base,
                                                     total)
    # Prune the loop closures the line process turned (nearly) off, then optimise again
    # (unless pruning would disconnect the graph).
    weak = [e for e in used if not e.odometry and
            _confidence(_residual(poses, e), e.info, mu) < opts.prune]
    if weak and _components(k, [e for e in used if e not in weak]) == 1:
        for e in weak:
            e.kept = False
        used = [e for e in edges if e.kept]
        poses, its2, conv, reason = _levenberg_marquardt(poses, used, mu, opts, report,
                                                         base + opts.max_iterations, total)
        reason += f"; {len(weak)} loop closure{'s' if len(weak) > 1 else ''} pruned"
    else:
        its2 = 0
    rmse, fitness = _agreement(pts, trees, poses, used, opts.max_dist)
    if not conv:
        warnings.warn(f"Pose-graph optimisation did not converge: {reason}.",
                      ConvergenceWarning, stacklevel=3)
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


def _labels(k: int, edges: list[_Edge]) -> tuple[int, IntArray]:
    graph = sp.coo_matrix((np.ones(len(edges)), ([e.i for e in edges], [e.j for e in edges])),
                          shape=(k, k))
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
    weight = {}
    for e in edges:  # keep the best edge per unordered pair
        key = (e.i, e.j)
        if key not in weight or e.fitness > weight[key].fitness:
            weight[key] = e
    rows = [e.i for e in weight.values()]
    cols = [e.j for e in weight.values()]
    cost = [2.0 - e.fitness for e in weight.values()]   # > 0: zero means "no edge"
    tree = minimum_spanning_tree(sp.coo_matrix((cost, (rows, cols)), shape=(k, k)))
    order, parent = breadth_first_order(tree + tree.T, 0, directed=False)
    poses = np.tile(np.eye(4), (k, 1, 1))
    for child in order[1:]:
        p = int(parent[child])
        if (child, p) in weight:                 # Z maps child into parent: P_c = P_p Z
            poses[child] = poses[p] @ weight[child, p].z
        else:                                    # Z maps parent into child: P_c = P_p Z⁻¹
            poses[child] = poses[p] @ _inverse(weight[p, child].z)
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
                candidate[node] = _exp(xi[node - 1]) @ poses[node]
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
    return _log(_inverse(poses[e.j]) @ poses[e.i] @ _inverse(e.z))


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
        jac = _left_jacobian_inverse(r) @ _adjoint(_inverse(poses[e.j]))
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


def _agreement(pts: list[FloatArray], trees: list[cKDTree], poses: FloatArray,
               edges: list[_Edge], max_dist: float) -> tuple[FloatArray, FloatArray]:
    k = len(pts)
    partners: list[set[int]] = [set() for _ in range(k)]
    for e in edges:
        partners[e.i].add(e.j)
        partners[e.j].add(e.i)
    rmse, fitness = np.zeros(k), np.zeros(k)
    for i in range(k):
        best = np.full(len(pts[i]), np.inf)
        for j in sorted(partners[i]):
            rel = _inverse(poses[j]) @ poses[i]
            moved = pts[i] @ rel[:3, :3].T + rel[:3, 3]
            dist, _ = trees[j].query(moved, distance_upper_bound=max_dist)
            np.minimum(best, dist, out=best)
        inside = best[np.isfinite(best)]
        fitness[i] = inside.size / len(pts[i])
        rmse[i] = math.sqrt(float(inside @ inside) / inside.size) if inside.size else 0.0
    return rmse, fitness


# --- SE(3) --------------------------------------------------------------------------------


def _hat(w: FloatArray) -> FloatArray:
    return np.array([[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]])


def _inverse(t: FloatArray) -> FloatArray:
    out = np.eye(4)
    out[:3, :3] = t[:3, :3].T
    out[:3, 3] = -t[:3, :3].T @ t[:3, 3]
    return out


def _adjoint(t: FloatArray) -> FloatArray:
    """``Ad_T`` for twists ``(ω, v)``: ``exp(Ad_T ξ) = T exp(ξ) T⁻¹``."""
    r = t[:3, :3]
    out = np.zeros((6, 6))
    out[:3, :3] = r
    out[3:, 3:] = r
    out[3:, :3] = _hat(t[:3, 3]) @ r
    return out


def _left_jacobian_inverse(xi: FloatArray) -> FloatArray:
    """``J_l⁻¹(ξ) ≈ I - ad_ξ / 2 + ad_ξ² / 12`` (second order; residuals are small)."""
    ad = np.zeros((6, 6))
    wx = _hat(xi[:3])
    ad[:3, :3] = wx
    ad[3:, 3:] = wx
    ad[3:, :3] = _hat(xi[3:])
    return np.eye(6) - 0.5 * ad + ad @ ad / 12.0


def _exp(xi: FloatArray) -> FloatArray:
    """The rigid motion of the twist ``(ω, v)`` (Rodrigues, and the left Jacobian for ``t``)."""
    w, v = xi[:3], xi[3:]
    theta = math.sqrt(float(w @ w))
    wx = _hat(w)
    if theta < 1e-2:  # series: the closed forms cancel catastrophically near zero
        t2 = theta * theta
        sin_c = 1.0 - t2 / 6.0 + t2 * t2 / 120.0
        a = 0.5 - t2 / 24.0 + t2 * t2 / 720.0
        b = 1.0 / 6.0 - t2 / 120.0 + t2 * t2 / 5040.0
    else:
        sin_c = math.sin(theta) / theta
        a = (1.0 - math.cos(theta)) / theta ** 2
        b = (theta - math.sin(theta)) / theta ** 3
    wx2 = wx @ wx
    out = np.eye(4)
    out[:3, :3] = np.eye(3) + sin_c * wx + a * wx2
    out[:3, 3] = (np.eye(3) + a * wx + b * wx2) @ v
    return out


def _log(t: FloatArray) -> FloatArray:
    """The twist ``(ω, v)`` of a rigid motion (inverse of :func:`_exp`)."""
    r = t[:3, :3]
    skew = np.array([r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]]) / 2.0
    sin = math.sqrt(float(skew @ skew))
    theta = math.atan2(sin, (float(np.trace(r)) - 1.0) / 2.0)
    if theta < 1e-2:
        w = skew * (1.0 + theta ** 2 / 6.0 + 7.0 * theta ** 4 / 360.0)
    elif theta < math.pi - 1e-2:
        w = skew * (theta / sin)
    else:  # near a half turn the skew part vanishes: take the axis from the matrix
        w = Rotation.from_matrix(r).as_rotvec()
        theta = float(np.linalg.norm(w))
    wx = _hat(w)
    if theta < 1e-1:  # series: the closed form cancels catastrophically near zero
        t2 = theta * theta
        c = 1.0 / 12.0 + t2 / 720.0 + t2 * t2 / 30240.0 + t2 ** 3 / 1209600.0
    else:
        c = (1.0 - theta * math.sin(theta) / (2.0 * (1.0 - math.cos(theta)))) / theta ** 2
    v = (np.eye(3) - 0.5 * wx + c * wx @ wx) @ t[:3, 3]
    return np.concatenate([w, v])


def _homogeneous(linear: FloatArray, translation: FloatArray) -> FloatArray:
    k, d = translation.shape
    out = np.zeros((k, d + 1, d + 1))
    out[:, :d, :d] = linear
    out[:, :d, d] = translation
    out[:, d, d] = 1.0
    return out
