"""Multiway registration: several point sets brought into one frame at once, by generalised
Procrustes analysis when the rows correspond (:mod:`~algorithms.registration.procrustes`),
by pairwise ICP and pose-graph optimisation on SE(3) when they do not
(:mod:`~algorithms.registration.pose_graph`)."""

from __future__ import annotations

from typing import Annotated, Any

from algorithms.core.params import ArrayInput, Ge, Gt, Interval, validate_params
from algorithms.core.progress import Progress
from algorithms.core.threads import single_blas_thread
from algorithms.registration._point_sets import (
    MultiwayResult,
    PointSetsLike,
    check_rigid,
    check_sets,
    check_transforms,
)
from algorithms.registration.pose_graph import METRICS, Metric, check_neighbors, pose_graph
from algorithms.registration.procrustes import MODELS, Model, generalized_procrustes

__all__ = ["MultiwayResult", "multiway", "check_multiway", "check_sets", "check_transforms",
           "MODELS", "METRICS"]


def check_multiway(sets: Any, correspondences: bool = True, model: str = "rigid",
                   metric: str = "symmetric", init: Any = None, neighbors: Any = None) -> None:
    """Check the inputs of :func:`multiway` as its two methods do: the sets' count, lengths
    and dimensions (:func:`check_sets`), the starting transforms against them
    (:func:`check_transforms`) and, without correspondences, ``neighbors`` against their
    number."""
    pts = check_sets(sets, correspondences=correspondences, model=model, metric=metric)
    if init is not None:
        check_transforms(init, len(pts), pts[0].shape[1], model)
    if not correspondences:
        check_neighbors(neighbors, len(pts))


@validate_params
def multiway(
    sets: PointSetsLike,
    *,
    correspondences: bool = True,
    model: Model = "rigid",
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
    r"""Multiway registration: generalised Procrustes or pose graph.

    Registers several point sets at once into the frame of set 0. With correspondences: generalised
    Procrustes analysis (rigid or similarity, any dimension), iterated to the mean shape. Without:
    pairwise ICP (coarse to fine, symmetric metric, point-to-point polish) with information
    matrices, then pose-graph optimisation on SE(3) by Levenberg-Marquardt with line processes for
    loop closures, low-fitness and inconsistent edges pruned (as Open3D's multiway registration).

    **With correspondences** (row ``j`` of every set is the same point): generalised
    Procrustes analysis (Gower 1975), :func:`~algorithms.registration.generalized_procrustes`:
    every set is rotated (and, for similarity, scaled) onto the mean shape of the moved
    sets, and the mean recomputed, until the sum of squared distances to the mean stops
    decreasing; any dimension.

    **Without correspondences** (``correspondences=False``, 3-D):
    :func:`~algorithms.registration.pose_graph`, as Open3D's multiway registration (Choi,
    Zhou & Koltun 2015): every pair of sets (or each with its next ``neighbors``) is
    registered by coarse-to-fine ICP, the pairwise results weighted by their information
    matrices, then the poses optimised on SE(3) by Levenberg-Marquardt with line processes
    that switch off inconsistent loop closures.

    The options of the other method are ignored: ``max_correspondence_distance``,
    ``metric``, ``neighbors``, ``min_fitness``, ``edge_prune_threshold``,
    ``preference_loop_closure`` and ``icp_max_iterations`` are the pose graph's.

    Parameters
    ----------
    sets : sequence of (n_i, d) float arrays
        At least two point sets, ``(n_i, d)`` arrays of the same dimension ``d``. With
        correspondences: all of the same length ``n``, row ``j`` of each the same point, any
        ``d >= 1``. Without: 3-D, of any sizes (at least 6 points each, 3 with
        ``metric="point_to_point"``).
    correspondences : bool, default True
        True: row ``j`` of every set is the same point (generalised Procrustes). False:
        the correspondences are unknown (pairwise ICP and pose-graph optimisation on
        SE(3), 3-D only).
    model : {"rigid", "similarity"}, default "rigid"
        ``"rigid"``: a rotation and a translation per set; ``"similarity"``: also a
        uniform scale, relative to set 0's (generalised Procrustes only).
    init : (k, d+1, d+1) float array, optional
        A start transform per set into a common frame (rigid; similarity allowed for
        Procrustes); only their relative transforms matter. Procrustes starts its mean
        from the sets as they move them; the pose graph starts each pairwise ICP from
        them. Omitted: Procrustes starts from set 0, the pose graph from the identity (the
        sets taken as roughly aligned, as by a scanner).
    max_iterations : int, default 100
        Most Procrustes passes, or Levenberg-Marquardt iterations per pose-graph
        optimisation round (two rounds), ``>= 1``.
    tolerance : float, default 1e-9
        Stop when the objective decreases by less than this fraction of its value in an
        iteration, ``>= 0`` (tighter than Open3D's pose-graph criteria, 1e-6: the
        iterations are cheap at the sizes of a multiway problem).
    max_correspondence_distance : float, optional
        Pose graph: the pairs' distance bound (``> 0``, in the points' units) of the fine
        pairwise ICP (the coarse stages use 4 and 2 × it), of the edges' information
        matrices and of ``fitness``; it also scales the line process's loop-closure
        weight. Omitted: 2 × the median distance between nearest neighbours within the
        sets.
    metric : {"symmetric", "point_to_plane", "point_to_point"}, default "symmetric"
        Pose graph: the metric of the coarse-to-fine pairwise ICP stages, followed by a
        point-to-point polish: ``"symmetric"`` uses both sets' normals (Rusinkiewicz
        2019), ``"point_to_plane"`` the target's, ``"point_to_point"`` plain distances.
        Normals are estimated from 10 neighbours; a pair whose target is flat (the plane
        metrics undetermined) falls back to point-to-point.
    neighbors : int, optional
        Pose graph: register each set with its next ``neighbors`` sets in order, ``1 <=
        neighbors <= k - 1`` (1 gives a chain); consecutive pairs then count as trusted
        odometry. Omitted: every pair up to 10 sets (no odometry), 2 beyond.
    min_fitness : float, default 0.3
        Pose graph: drop pairwise edges whose ICP fitness (the share of points with a
        partner within ``max_correspondence_distance``) is below this, ``0 <= min_fitness
        <= 1``: they overlap too little to be trusted.
    edge_prune_threshold : float, default 0.25
        Pose graph: prune the loop closures whose line-process weight falls below this
        after the first optimisation round (Open3D's default), ``0 <= ... < 1``.
    preference_loop_closure : float, default 1.0
        Pose graph: the weight of loop closures in the line process (Open3D's option),
        ``> 0``; larger keeps more loop closures.
    icp_max_iterations : int, default 30
        Pose graph: most iterations per pairwise ICP stage (four stages per pair),
        ``>= 1``.
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
    **Why all sets at once.** Registering every set to set 0 alone lets that one set's noise
    and overlap decide every pose, and chaining pairwise registrations (1 onto 0, 2 onto
    1, ...) accumulates their errors. Both methods use every set at once: Procrustes
    aligns each to the mean of all, the pose graph weighs every pairwise registration by
    its information and distributes the inconsistency of loops over their edges. Only the
    relative transforms are determined; set 0 is the reference of both
    (``transforms[0]`` is the identity).

    References
    ----------
    .. [1] J. C. Gower, "Generalized Procrustes analysis", Psychometrika 40(1), 33-51,
       1975.
    .. [2] S. Choi, Q.-Y. Zhou and V. Koltun, "Robust reconstruction of indoor scenes",
       CVPR 2015.

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
    if correspondences:
        # the thread policy (algorithms.core.threads): thin (n, d) products, one BLAS thread;
        # without correspondences, each pairwise ICP applies it itself
        with single_blas_thread():
            return generalized_procrustes(sets, model=model, init=init,
                                          max_iterations=max_iterations, tolerance=tolerance,
                                          progress=progress)
    check_rigid(model)
    return pose_graph(sets, init=init, max_iterations=max_iterations, tolerance=tolerance,
                      max_correspondence_distance=max_correspondence_distance, metric=metric,
                      neighbors=neighbors, min_fitness=min_fitness,
                      edge_prune_threshold=edge_prune_threshold,
                      preference_loop_closure=preference_loop_closure,
                      icp_max_iterations=icp_max_iterations, progress=progress)
