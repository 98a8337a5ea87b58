"""RANSAC global registration: a rigid transform from ``source`` to ``target`` without a
start, from sampled correspondences (FPFH feature matches, or random point triples of
each set), refined by ICP."""

from __future__ import annotations

import heapq
import math
import warnings
from dataclasses import dataclass
from typing import Annotated, Any, Literal, cast, get_args

import numpy as np
from scipy.spatial import cKDTree

from algorithms.core.errors import ConvergenceWarning, DegenerateInputError, InvalidInputError, warn
from algorithms.core.linalg import RANK_RTOL, numerical_rank, procrustes
from algorithms.core.params import Ge, Gt, Interval, PointsLike, Seed, validate_params
from algorithms.core.progress import Progress, as_progress
from algorithms.core.threads import SERIAL_BELOW, query_workers, single_blas_thread
from algorithms.core.types import FloatArray, IntArray, KnnQuery
from algorithms.core.validation import as_points, check_min_points, check_span, same_dim
from algorithms.registration._normals import estimate_normals
from algorithms.registration.features import (
    MIN_FEATURE_POINTS,
    _fpfh,
    feature_normals,
    match_features,
    point_spacing,
    voxel_downsample,
)
from algorithms.registration.icp import Metric, icp

__all__ = ["RANSACResult", "ransac", "check_ransac", "check_inputs", "FEATURES"]

Features = Literal["fpfh", "none"]
#: The accepted values of ``features``.
FEATURES = get_args(Features)
#: Open3D's ``CorrespondenceCheckerBasedOnEdgeLength(0.9)``: every edge of the sample and
#: its image may differ by at most this factor.
EDGE_SIMILARITY = 0.9
#: A sample whose smallest relevant singular value is below this fraction of its largest
#: (a sliver triangle, nearly collinear points) fixes the rotation poorly: it is skipped.
FLAT_RTOL = 0.05
#: Hypotheses drawn per vectorised batch. Fixed, so that results never depend on it.
BATCH = 1024
#: Residuals evaluated per block when scoring hypotheses (bounds the memory).
SCORE_BLOCK = 1 << 18
#: Source points used to score a hypothesis without features (a seeded subsample above).
SCORE_POINTS = 2000
#: Source points the ICP refinement uses at most (a seeded subsample above).
REFINE_POINTS = 20000
#: kd-tree queries of this many points or more run on all cores (results are per point).
PARALLEL_FROM = SERIAL_BELOW
#: ICP iterations of the refinement.
REFINE_ITERATIONS = 30
#: Default radii, in units of the length scale (``voxel_size`` or the point spacing), as in
#: Open3D's global registration tutorial.
FEATURE_RADIUS_FACTOR = 5.0
DISTANCE_FACTOR = 1.5
#: Without features or voxels, the default threshold is this fraction of the median distance
#: from a source point to its nearest neighbour.
NEAREST_FACTOR = 0.5
#: Neighbours per estimated normal.
NORMAL_NEIGHBORS = 10
#: Targets of fewer points are refined point-to-point (too few for meaningful normals).
PLANE_MIN_POINTS = 3 * NORMAL_NEIGHBORS
#: Fewer mutual matches than this many samples' worth: use the one-sided matches (Open3D).
MUTUAL_MIN_SAMPLES = 3
#: Neighbours per normal of the features (30 others, 31 points: Open3D's tutorial ``max_nn``
#: of 30 counts the point itself, one fewer; kept as measured): 10 noisy
#: neighbours make poor normals and FPFH built on them mismatch (measured on pyvista's ant:
#: 5-20 % correct mutual matches with 10, 15-55 % with 30).
FEATURE_NORMAL_NEIGHBORS = 30
#: Most points of an FPFH neighbourhood, the point itself counted (Open3D's ``max_nn``).
FEATURE_MAX_NN = 101
#: Without ``voxel_size`` (features): one pass per voxel of these multiples of the source's
#: point spacing, the pass whose transform fits the full sets best wins. The best voxel
#: depends on the noise, which is unknown: 1.5 h suits clean samples (a smooth potato
#: with 1/4 h of noise: 3 h keeps too little of its shape and turns it over), 3 h noisy
#: ones (the pyvista airplane and ant with 2/3 h of noise: 1.5 h matches poorly).
VOXEL_FACTORS = (1.5, 3.0)
#: With features, the stopping rule never stops before this many hypotheses (4 batches):
#: a shape with a near symmetry (an airplane turned over) has a wrong pose of nearly as
#: many matches, which a few dozen hypotheses may not get past.
MIN_HYPOTHESES = 4 * BATCH
#: With features, the hypotheses of least error over the matches kept for re-scoring.
TOP_HYPOTHESES = 100
#: ... of which the best this many distinct ones, re-scored on the (down-sampled) sets, are
#: refined by ICP and compared on the full sets.
REFINE_CANDIDATES = 5
#: ICP iterations of each candidate's refinement (the final one has 30): enough to tell poses apart.
CANDIDATE_ITERATIONS = 10
#: Two hypotheses are the same pose when their rotations differ by less than this
#: (Frobenius norm, about 2°) and their translations by less than the threshold.
SAME_ROTATION = 0.05
#: Poses are compared on the full sets by the truncated squared error at this fraction of
#: ``max_correspondence_distance``: tight enough that a nearly symmetric wrong pose, which
#: keeps many points within the threshold, loses to the right one.
SELECT_FACTOR = 1.0 / 3.0
#: A best hypothesis supported by fewer inliers than this (the sample itself included) is
#: no registration.
MIN_SUPPORT = 6


@dataclass(frozen=True, eq=False)
class RANSACResult:
    """The rigid transform RANSAC found from ``source`` to ``target``, and how well it fits.

    Attributes
    ----------
    transform : (d+1, d+1) float array
        The homogeneous matrix ``[[R, t], [0, 1]]`` that maps source points onto the target
        (after the ICP refinement when ``refine`` is true). The identity, labelled
        ``converged=False``, when no sample passed the checks.
    rotation : (d, d) float array
        The rotation ``R`` (determinant +1).
    translation : (d,) float array
        The translation ``t`` applied after the rotation.
    rmse : float
        Root-mean-square distance from the moved source points to their nearest target
        points, over the source points that have one within ``max_correspondence_distance``
        (Open3D's ``inlier_rmse``), on the full input sets; 0.0 when there are none.
    fitness : float
        The fraction of source points with a target point within
        ``max_correspondence_distance`` after the transform (Open3D's fitness), on the full
        input sets.
    inlier_count : int
        The number of those source points (``fitness`` times the source size).
    correspondence_count : int
        The candidate correspondences RANSAC sampled from: the feature matches for
        ``features="fpfh"``; for ``features="none"``, the source times the target size
        (every pair is a candidate).
    iterations : int
        Hypotheses (samples) drawn, those rejected by the checks included (over all
        passes).
    converged : bool
        True when the confidence-based stopping rule was met: the best hypothesis's inlier
        ratio ``w`` made ``log(1 - confidence) / log(1 - w^s)`` samples (``s`` per sample)
        enough before ``max_iterations``, with at least 6 inliers (in the winning pass).
        False otherwise (see ``reason``); a ``ConvergenceWarning`` accompanies False.
    reason : str
        Why the sampling stopped and what the refinement did, in words.
    """

    transform: FloatArray
    rotation: FloatArray
    translation: FloatArray
    rmse: float
    fitness: float
    inlier_count: int
    correspondence_count: int
    iterations: int
    converged: bool
    reason: str


@dataclass
class _Best:
    error: float
    inliers: int
    ratio: float
    rotation: FloatArray
    translation: FloatArray
    number: int  # 1-based number of the hypothesis


@validate_params
def ransac(
    source: PointsLike,
    target: PointsLike,
    *,
    features: Features = "fpfh",
    voxel_size: Annotated[float, Gt(0)] | None = None,
    feature_radius: Annotated[float, Gt(0)] | None = None,
    max_correspondence_distance: Annotated[float, Gt(0)] | None = None,
    max_iterations: Annotated[int, Ge(1)] = 100_000,
    confidence: Annotated[float, Interval(gt=0, le=1)] = 0.999,
    mutual_filter: bool = True,
    refine: bool = True,
    seed: Seed = 0,
    progress: Progress | None = None,
) -> RANSACResult:
    r"""RANSAC global registration (FPFH features or random triples) + ICP.

    Registers source onto target rigidly without a start: candidate pairs from mutually matched FPFH
    features (or, for small sets, random point triples of each set), seeded random samples of 3
    pairs checked by edge lengths, Kabsch fits scored by truncated squared error, confidence-based
    stopping. Without voxel_size: two down-sampling passes (1.5 and 3 × the point spacing), the best
    hypotheses re-scored and ICP-checked on the point sets, a robust (Tukey) ICP refinement against
    the full target; with voxel_size: Open3D's single pass, then point-to-plane ICP. The same seed
    gives the same result; converged=false with a reason instead of a silent identity.

    1. **Down-sampling**: with ``voxel_size`` each set is replaced by the centroids of its
       points in each occupied voxel. With features and no ``voxel_size``, two passes of
       steps 1-4 run, at 1.5 and 3 × the source's point spacing :math:`h` (those that leave
       enough points; none: one pass without down-sampling), and the pass whose pose has
       the least truncated error :math:`\sum_i \min(r_i^2, \tau_s^2)` of the full source
       against the full target wins (:math:`r_i` the distance to the nearest target
       point, :math:`\tau_s = \tau / 3` of the smaller voxel).
    2. **Candidates.** ``features="fpfh"`` (3-D): FPFH descriptors of both sets
       (:func:`~algorithms.registration.fpfh`, radius ``feature_radius``), matched by
       nearest neighbour in feature space, mutually with ``mutual_filter``.
       ``features="none"``: every (source point, target point) pair is a candidate and
       samples are drawn from each set independently (see Notes).
    3. **Hypotheses.** Each draws :math:`s = \max(3, d)` candidate pairs with the generator
       seeded by ``seed`` and is skipped unless every edge of the sample and of its image agree
       within a factor 0.9 (Open3D's edge-length checker) and the sample is not nearly
       collinear; the rest get the Kabsch fit :math:`(R, t)` of their pairs, are skipped
       unless every sampled pair then lies within ``max_correspondence_distance``
       (Open3D's distance checker), and are scored by the truncated squared error
       (MSAC, Torr & Zisserman 2000)

       .. math::

           E(R, t) = \sum_i \min\big(\lVert R x_i + t - y_i \rVert^2, \tau^2\big)

       over the candidate pairs (features) or over the source points and their nearest
       target points (no features), :math:`\tau` = ``max_correspondence_distance``. The
       hypothesis of least error is kept; its inliers (residual :math:`\le\tau`) give the
       inlier ratio :math:`w` of the candidates.
    4. **Stopping**: after :math:`N = \log(1 - c) / \log(1 - w^s)` hypotheses for the
       ``confidence`` :math:`c` (the number after which an all-inlier sample has been
       drawn with probability :math:`c`), or ``max_iterations``. With features and no
       ``voxel_size``, never before 4096 hypotheses; then the 100 of least error are
       re-scored by the truncated error of the down-sampled source against the
       down-sampled target (threshold :math:`\tau`), the best 5 distinct poses refined
       by 10 ICP iterations (``refine``) and compared on the full sets
       (threshold :math:`\tau_s`): the pose with the most matches is not always the one
       that fits (an airplane turned over on its back shares most of its features).
    5. **Refinement** (``refine``): ICP from the RANSAC transform
       (:func:`~algorithms.registration.icp`, point-to-plane against the (down-sampled)
       target with its normals in 3-D when it has at least 30 points and is not flat, else
       point-to-point; at most 20,000 source points, pairs within
       ``max_correspondence_distance``); kept only when it lowers the truncated error
       :math:`\sum_i \min(r_i^2, \tau^2)` of its metric (plane or point distances).
       With features and no ``voxel_size``: against the full target (normals of 10
       neighbours) with Tukey's kernel (its scale from the median residual, so that the
       points outside the overlap do not pull the pose; a plain threshold of
       :math:`1.5 h` left 1-3° on the pyvista ant and airplane crops, the kernel
       0.2-1°), kept when it lowers the truncated point error at :math:`\tau_s`.

    Parameters
    ----------
    source : (n, d) float array
        The points to move; ``d = 3`` with features, any ``d >= 2`` without.
    target : (m, d) float array
        The points to register onto, same ``d``, any size ``m``; the overlap may be
        partial. No correspondence with ``source`` and no start are needed.
    features : {"fpfh", "none"}, default "fpfh"
        Where candidate pairs come from: ``"fpfh"`` (3-D) from Fast Point Feature
        Histograms matched between the sets; ``"none"`` every pair of a source and a target
        point, samples of point triples drawn from each set at random. ``"none"`` needs no
        local structure but finds an all-inlier sample with probability about
        :math:`(k/nm)^3` per hypothesis (``k`` overlapping points): it is for small sets,
        tens of points.
    voxel_size : float, optional
        Down-sample both sets on a grid of this step first (``> 0``); also the length
        scale of the default radii; one pass of Open3D's pipeline (normals of 10
        neighbours). Noisy scans need a voxel several times the noise. When omitted with
        features: two passes, at 1.5 and 3 × the source's point spacing (median distance
        to the 4th nearest neighbour, :func:`~.features.point_spacing`), with normals of
        30 neighbours, and the best-fitting pose wins; without features: no
        down-sampling, the scale is the point spacing.
    feature_radius : float, optional
        FPFH neighbourhood radius (``> 0``). Omitted: 5 × the length scale, the voxel step
        of the pass (``voxel_size`` or a default pass's) or, without down-sampling, the
        source's point spacing.
    max_correspondence_distance : float, optional
        The inlier threshold :math:`\tau` (``> 0``) of scoring, checking, refinement and
        the reported ``fitness``. Omitted: 1.5 × the length scale (the voxel step, or the
        source's point spacing without down-sampling), except with
        ``features="none"`` and no ``voxel_size``: half the median distance from a source
        point to its nearest neighbour (so that a point's partner is unambiguous).
    max_iterations : int, default 100000
        Most hypotheses (samples) to draw, ``>= 1``; the default is Open3D's.
    confidence : float, default 0.999
        Stop once an all-inlier sample has been drawn with this probability (estimated
        from the best inlier ratio), ``0 < confidence <= 1``; 1 never stops early.
    mutual_filter : bool, default True
        Keep only mutual nearest neighbours in feature space; falls back to the one-sided
        matches when fewer than 9 remain (as Open3D). False: each point's nearest
        neighbour in feature space, from both sets (each pair once).
    refine : bool, default True
        Refine the RANSAC transform with ICP (point-to-plane in 3-D when the target has
        enough points, else point-to-point), kept only when it lowers the truncated
        error.
    seed : int or numpy.random.Generator, default 0
        Seeds the sampling; the same seed gives the same result, bit for bit (no step
        depends on the number of threads).
    progress : callable, optional
        ``progress(done, total, message)`` after every 1024 hypotheses and after the
        refinement (``total`` = passes × ``max_iterations`` + 1); it may raise
        :class:`~algorithms.core.errors.Cancelled`.

    Returns
    -------
    RANSACResult
        ``transform``, ``rotation``, ``translation``, ``rmse``, ``fitness``,
        ``inlier_count``, ``correspondence_count``, ``iterations``, ``converged``,
        ``reason``.

    Raises
    ------
    InvalidInputError
        Malformed or non-finite points; differing dimensions (``field="target"``); fewer
        than ``max(3, d)`` points (4 with features); ``features="fpfh"`` with points that
        are not 3-D (``field="features"``); a ``voxel_size`` that leaves too few points
        (``field="voxel_size"``); an unknown option or a parameter out of range.
    DegenerateInputError
        A set whose points are all coincident or (in 3-D) collinear: the rotation about
        their line is undetermined.

    Warns
    -----
    ConvergenceWarning
        Whenever ``converged`` is False.

    Notes
    -----
    **RANSAC without features.** ``features="none"`` is RANSAC in its plainest form for
    registration: pick ``s`` points of each set at random, take them to correspond in
    order, fit the rigid motion, measure the error of the moved source against the target,
    and keep the least error over many draws, a random search of the :math:`O(n^3 m^3)`
    pairs of triples. Two things are added: the error is truncated at :math:`\tau` (so
    that points outside the overlap cannot dominate it: MSAC), and the edge-length and
    distance checks reject most non-congruent samples before any scoring. On real scans
    that search is hopeless, so candidates come from local features instead, as in Open3D
    (``features="fpfh"``).

    **Never a silent identity.** When no hypothesis passes the checks, when the best has
    fewer than 6 inliers, or when the confidence was not reached within
    ``max_iterations``, ``converged`` is False and ``reason`` says which; the transform is
    then the best found (the identity when none was), and ``fitness`` shows the overlap.

    **The default on real scans.** Issue #4's trial (the pyvista airplane and ant, 6000
    surface points, two crops sharing 70 %, 0.5 % noise, any rotation, seeds 0-19) was
    registered to < 2° in 1 and 2 of 20 trials with a voxel of the point spacing, 15 and
    12 with the best single voxel (0.02 of the diagonal): normals of 10 noisy neighbours
    make few correct matches, the pose of least match error is often the airplane on its
    back, and a threshold of 1.5 voxels lets ICP drift by 2°. With the two passes,
    30-neighbour normals, the re-scoring of the best hypotheses on the sets and the
    Tukey refinement it is 20 of 20 for both (and the six-fold, two-sided nut lands on one
    of its symmetric poses 20 times in 20).

    **Reproducibility.** Hypotheses are drawn and scored in fixed batches of 1024 and taken
    in their drawing order, and the stopping rule is applied after each one as if they
    were processed one by one; kd-tree queries are per point. The same input and ``seed``
    therefore give the same bits (Open3D's parallel RANSAC does not, Open3D #7475).

    References
    ----------
    .. [1] M. A. Fischler and R. C. Bolles, "Random sample consensus", Comm. ACM 24(6),
       381-395, 1981.
    .. [2] P. H. S. Torr and A. Zisserman, "MLESAC: a new robust estimator with
       application to estimating image geometry", CVIU 78(1), 138-156, 2000 (MSAC).
    .. [3] R. B. Rusu, N. Blodow and M. Beetz, "Fast Point Feature Histograms (FPFH) for
       3D registration", ICRA 2009.
    .. [4] Q.-Y. Zhou, J. Park and V. Koltun, "Open3D: a modern library for 3D data
       processing", arXiv:1801.09847, 2018 (checkers, fitness, stopping rule).

    Examples
    --------
    >>> import numpy as np
    >>> from algorithms.registration import ransac
    >>> src = np.array([[0, 0, 0], [2, 0, 0], [0, 1, 0], [0, 0, 0.5], [1, 1, 0.2],
    ...                 [0.5, 0.2, 0.4]])
    >>> c, s = np.cos(2.0), np.sin(2.0)
    >>> dst = src[::-1] @ np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]]).T + [3, 0, 1]
    >>> res = ransac(src, dst, features="none", max_correspondence_distance=0.05)
    >>> res.converged, res.fitness
    (True, 1.0)
    >>> bool(np.allclose(res.rotation, [[c, -s, 0], [s, c, 0], [0, 0, 1]]))
    True
    """
    report = as_progress(progress)
    src, dst, (s, need) = check_ransac(source, target, features)
    d = src.shape[1]
    voxel, radius, tau = voxel_size, feature_radius, max_correspondence_distance
    rng = np.random.default_rng(seed)

    # 1. down-sampling and scales
    if features == "fpfh":
        if voxel is not None:
            voxels: list[float | None] = [voxel]
        else:
            spacing = point_spacing(src)
            voxels = [f * spacing for f in VOXEL_FACTORS if spacing > 0.0 and min(
                voxel_downsample(src, f * spacing).shape[0],
                voxel_downsample(dst, f * spacing).shape[0]) >= need]
            voxels = voxels or [None]
    else:
        voxels = [voxel]
    total = len(voxels) * max_iterations + 1
    dst_tree = cKDTree(dst, balanced_tree=False, compact_nodes=False)
    robust = features == "fpfh" and voxel is None
    runs = [_pass(src, dst, dst_tree, v, features, radius, tau, mutual_filter, refine, robust,
                  s, need, rng, max_iterations, confidence, report, k * max_iterations, total)
            for k, v in enumerate(voxels)]

    # the pass whose transform fits the full sets best
    pts = _subsample(src)
    tau_sel = SELECT_FACTOR * min(r.tau for r in runs)
    chosen = runs[0]
    if len(runs) > 1:
        errors = [_truncated(pts, dst_tree, r.transform, tau_sel) for r in runs]
        chosen = runs[int(np.argmin(errors))]
    best, tau, transform, search = chosen.best, chosen.tau, chosen.transform, chosen.search
    drawn = sum(r.drawn for r in runs)
    candidates = search.count
    converged = best is not None and best.inliers >= MIN_SUPPORT and \
        _needed(best.ratio, confidence, s) <= chosen.drawn
    if best is None:
        reason = (f"no hypothesis of {drawn} passed the checks (edge lengths within "
                  f"{EDGE_SIMILARITY:g}, every sampled pair within max_correspondence_distance "
                  f"= {tau:.6g}) among {candidates} candidate correspondences: no transform "
                  "found, the identity is returned")
    elif best.inliers < MIN_SUPPORT:
        reason = (f"the best hypothesis is supported by only {best.inliers} candidate "
                  f"correspondences within max_correspondence_distance = {tau:.6g} (at least "
                  f"{MIN_SUPPORT} needed) after {chosen.drawn} hypotheses")
    elif converged:
        reason = (f"confidence {confidence:g} reached after {chosen.drawn} hypotheses (inlier "
                  f"ratio {best.ratio:.3g} of {candidates} candidates)")
    else:
        reason = (f"max_iterations = {max_iterations} reached before confidence "
                  f"{confidence:g} (the best inlier ratio {best.ratio:.3g} of {candidates} "
                  f"candidates needs {_needed(best.ratio, confidence, s):.3g} hypotheses)")
    if voxel is None and chosen.voxel is not None:
        tried = ", ".join(f"{v:.4g}" for v in voxels if v is not None)
        reason = (f"{reason}; voxel_size {chosen.voxel:.4g} of those tried ({tried}, "
                  f"{' and '.join(f'{f:g}' for f in VOXEL_FACTORS)} × the point spacing)")
    if chosen.note:
        reason = f"{reason}; {chosen.note}"

    # 5. refinement
    if refine and best is not None:
        with single_blas_thread():  # ICP's sums over all pairs: the same bits on any machine
            if robust:
                transform, note = _polish(pts, dst, dst_tree, transform, tau, tau_sel)
            else:
                transform, note = _refine(src, chosen.t_pts, chosen.t_normals, transform, tau,
                                          rng)
        reason = f"{reason}; {note}"
    report(total, total, "RANSAC finished")

    # per-point queries: threads change the speed, never the result
    workers = query_workers(src.shape[0])
    dist, _ = cast(KnnQuery, dst_tree.query(
        src @ transform[:d, :d].T + transform[:d, d], distance_upper_bound=tau * (1 + 1e-9),
        workers=workers))
    inl = dist[dist <= tau]
    rmse = math.sqrt(float(inl @ inl) / inl.size) if inl.size else 0.0
    if not converged:
        warn(f"RANSAC did not converge: {reason}.", ConvergenceWarning)
    return RANSACResult(
        transform=transform,
        rotation=transform[:d, :d].copy(),
        translation=transform[:d, d].copy(),
        rmse=rmse,
        fitness=inl.size / src.shape[0],
        inlier_count=int(inl.size),
        correspondence_count=int(candidates),
        iterations=int(drawn),
        converged=bool(converged),
        reason=reason,
    )


@dataclass
class _Run:
    """One pass of RANSAC at one voxel size: its sets, threshold, search, best hypothesis
    and the transform it proposes (before the final refinement)."""

    voxel: float | None
    tau: float
    t_pts: FloatArray
    t_normals: FloatArray | None
    search: _Search
    best: _Best | None
    drawn: int
    transform: FloatArray
    note: str


def _pass(src: FloatArray, dst: FloatArray, dst_tree: cKDTree, voxel: float | None, features: str,
          radius: float | None, tau: float | None, mutual_filter: bool, refine: bool,
          robust: bool, s: int, need: int, rng: np.random.Generator, max_iterations: int,
          confidence: float, report: Progress, offset: int, total: int) -> _Run:
    """Steps 1-4 at one voxel size (``None``: no down-sampling). ``robust`` (features
    without a given ``voxel_size``): normals of 30 neighbours, at least ``MIN_HYPOTHESES``
    hypotheses, and the best few distinct ones re-scored on the sets (ICP-refined when
    ``refine``); else Open3D's single pass (normals of 10 neighbours)."""
    d = src.shape[1]
    s_pts, t_pts = src, dst
    if voxel is not None:
        s_pts, t_pts = voxel_downsample(src, voxel), voxel_downsample(dst, voxel)
        for pts, name in ((s_pts, "source"), (t_pts, "target")):
            if pts.shape[0] < need:
                raise InvalidInputError(
                    f"Expected `voxel_size` to leave at least {need} `{name}` points, got "
                    f"{pts.shape[0]} with voxel_size = {voxel:g}; use a smaller voxel.",
                    field="voxel_size")
    s_tree, t_tree = cKDTree(s_pts), cKDTree(t_pts)
    scale = voxel if voxel is not None else point_spacing(s_pts, s_tree)
    if not scale > 0.0:  # most points repeated: fall back to a fraction of the size
        centred = s_pts - s_pts.mean(axis=0)
        scale = 1e-2 * math.sqrt(float(np.einsum("ij,ij->", centred, centred)) / len(s_pts))
    if tau is None and features == "none" and voxel is None:
        # small sets: half the typical gap to the nearest point, so that an inlier is
        # unambiguous (a radius of several gaps would let wrong samples score as well)
        nearest, _ = cast(KnnQuery, s_tree.query(s_pts, k=2))
        gap = float(np.median(nearest[:, 1]))
        tau = NEAREST_FACTOR * gap if gap > 0.0 else DISTANCE_FACTOR * scale
    tau = DISTANCE_FACTOR * scale if tau is None else tau
    radius = FEATURE_RADIUS_FACTOR * scale if radius is None else radius

    # 2. candidates
    t_normals = None
    if features == "fpfh":
        k = FEATURE_NORMAL_NEIGHBORS if robust else NORMAL_NEIGHBORS
        s_normals = feature_normals(s_pts, s_tree, k)
        t_normals = feature_normals(t_pts, t_tree, k)
        # at most 100 neighbours besides the point (Open3D's max_nn = 101): on the bench's
        # scan pair (bench/_reg_ransac.py) Open3D's tutorial max_nn = 100 left RANSAC 8.6°
        # off before refinement, against 6.0° with 101 (both 0.05° after ICP)
        fs = _fpfh(s_pts, s_normals, s_tree, radius, FEATURE_MAX_NN)
        ft = _fpfh(t_pts, t_normals, t_tree, radius, FEATURE_MAX_NN)
        cs, ct = _matches(fs, ft, mutual_filter, s)
        search: _Search = _FeatureSearch(s_pts[cs], t_pts[ct], tau, s)
    else:
        search = _PointSearch(s_pts, t_pts, t_tree, tau, s, rng)

    # 3-4. hypotheses (small products: one BLAS thread, the same bits on any machine)
    top: list[Any] = []
    with single_blas_thread():
        best, drawn, _ = _sample(
            search, rng, max_iterations, confidence, report, offset=offset, total=total,
            min_hypotheses=MIN_HYPOTHESES if robust else 0, top=top if robust else None)
    transform = np.eye(d + 1)
    if best is not None:
        transform[:d, :d], transform[:d, d] = best.rotation, best.translation
    note = ""
    if top:
        with single_blas_thread():
            transform, note = _rescore(top, s_pts, t_pts, t_tree, t_normals, tau, src,
                                       dst_tree, refine)
    return _Run(voxel, tau, t_pts, t_normals, search, best, drawn, transform, note)


def _matches(fs: FloatArray, ft: FloatArray, mutual: bool, s: int) -> tuple[IntArray, IntArray]:
    """Candidate pairs from features: mutual nearest neighbours (the one-sided matches below
    when fewer than 3 samples' worth), or every point's nearest feature in the other set in
    both directions (their union, each pair once, sorted)."""
    if mutual:
        cs, ct = match_features(fs, ft, mutual=True)
        if cs.size >= MUTUAL_MIN_SAMPLES * s:
            return cs, ct
    a, b = match_features(fs, ft, mutual=False)
    bb, aa = match_features(ft, fs, mutual=False)
    pairs = np.unique(np.concatenate([np.stack([a, b], axis=1), np.stack([aa, bb], axis=1)]),
                      axis=0)
    return pairs[:, 0], pairs[:, 1]


def _truncated(pts: FloatArray, tree: cKDTree, transform: FloatArray, tau: float) -> float:
    """Sum over ``pts`` of min(r², τ²), r the distance of the moved point to the nearest
    point of ``tree``."""
    d = pts.shape[1]
    workers = query_workers(pts.shape[0])
    dist, _ = tree.query(pts @ transform[:d, :d].T + transform[:d, d],
                         distance_upper_bound=tau * (1 + 1e-9), workers=workers)
    r = np.minimum(dist, tau)
    return float(r @ r)


def _rescore(top: list[Any], s_pts: FloatArray, t_pts: FloatArray, t_tree: cKDTree,
             t_normals: FloatArray | None, tau: float, src: FloatArray, dst_tree: cKDTree,
             refine: bool) -> tuple[FloatArray, str]:
    """The kept hypotheses (least error over the matches) re-scored by the truncated error
    of the (down-sampled) source against the target; the best ``REFINE_CANDIDATES``
    distinct poses ICP-refined on those sets (``refine``) and compared by the truncated
    error at ``SELECT_FACTOR`` × τ of the full source (at most 20,000 points) against the
    full target. Returns the winner and a note."""
    top = sorted(top, key=lambda item: (-item[0], -item[1]))     # least error, then first
    errors = [_truncated(s_pts, t_tree, _homogeneous(r, t), tau) for _, _, r, t in top]
    poses: list[tuple[FloatArray, FloatArray]] = []
    for k in np.argsort(errors, kind="stable"):
        r, t = top[k][2], top[k][3]
        if any(np.linalg.norm(r - r2) < SAME_ROTATION and np.linalg.norm(t - t2) < tau
               for r2, t2 in poses):
            continue
        poses.append((r, t))
        if len(poses) == REFINE_CANDIDATES:
            break
    pts = _subsample(src)
    tau_sel = SELECT_FACTOR * tau
    found = []
    for r, t in poses:
        transform = _homogeneous(r, t)
        if refine:
            transform, _ = _refine(s_pts, t_pts, t_normals, transform, tau,
                                   np.random.default_rng(0), CANDIDATE_ITERATIONS)
        found.append((_truncated(pts, dst_tree, transform, tau_sel), transform))
    k = min(range(len(found)), key=lambda i: found[i][0])
    return found[k][1], (f"{len(found)} distinct poses of the {len(top)} best hypotheses "
                         "compared on the sets")


def _subsample(src: FloatArray) -> FloatArray:
    """At most ``REFINE_POINTS`` source points, evenly strided (no random draw)."""
    n = src.shape[0]
    return src if n <= REFINE_POINTS else src[::-(-n // REFINE_POINTS)]


def _homogeneous(rot: FloatArray, shift: FloatArray) -> FloatArray:
    d = rot.shape[0]
    out = np.eye(d + 1)
    out[:d, :d], out[:d, d] = rot, shift
    return out


def _polish(pts: FloatArray, dst: FloatArray, tree: cKDTree, start: FloatArray, tau: float,
            tau_sel: float) -> tuple[FloatArray, str]:
    """The final refinement with features: point-to-plane ICP of ``pts`` onto the full
    target (normals by local PCA of 10 neighbours; point-to-point when it is flat or has
    fewer than 30 points) with Tukey's kernel (scale from the residuals' median), so that
    the points outside the overlap, and the noise, do not pull the pose; kept when it
    lowers the truncated point error at ``tau_sel``."""
    metric: Metric = "point_to_point"
    normals = None
    if dst.shape[0] >= PLANE_MIN_POINTS:
        centred = dst - dst.mean(axis=0)
        var = np.linalg.eigvalsh(centred.T @ centred / len(dst))[::-1]
        if numerical_rank(np.maximum(var, 0.0), RANK_RTOL) == 3:
            metric = "point_to_plane"
            workers = query_workers(dst.shape[0])
            normals, _ = estimate_normals(dst, tree, NORMAL_NEIGHBORS, workers)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ConvergenceWarning)
            res = icp(pts, dst, metric=metric, init=start, max_iterations=REFINE_ITERATIONS,
                      max_correspondence_distance=tau, kernel="tukey",
                      target_normals=normals)
    except DegenerateInputError as err:
        return start, f"ICP refinement skipped: {str(err).rstrip('.')}"
    if res.iterations == 0:
        return start, f"{metric} ICP refinement stopped at once ({res.reason})"
    if _truncated(pts, tree, res.transform, tau_sel) <= _truncated(pts, tree, start, tau_sel):
        return res.transform, (f"refined by {metric} ICP ({res.iterations} iterations, "
                               f"{res.reason})")
    return start, (f"{metric} ICP refinement ({res.reason}) raised the truncated error: the "
                   "RANSAC transform is kept")


def check_ransac(source: Any, target: Any, features: str = "fpfh"
                 ) -> tuple[FloatArray, FloatArray, tuple[int, int]]:
    """Check the inputs of :func:`ransac`: two point sets of one dimension (at least 2),
    then as :func:`check_inputs`. Returns both sets and the sample size with the points it
    needs."""
    src = as_points(source, name="source", min_dim=2)
    dst = as_points(target, name="target")
    same_dim(src, dst, names=("source", "target"))
    return src, dst, check_inputs(src, dst, features)


def check_inputs(src: FloatArray, dst: FloatArray, features: str) -> tuple[int, int]:
    """What :func:`ransac` demands of checked point sets of the same dimension ``d``: 3-D
    for features, enough points, not all collinear. Returns the sample size ``max(3, d)``
    and the fewest points a set may have."""
    d = src.shape[1]
    if features == "fpfh" and d != 3:
        raise InvalidInputError(
            f"Expected 3-D points for features='fpfh' (FPFH is defined in 3-D), got d = {d}; "
            "use features='none' in other dimensions.", field="features")
    s = max(3, d)
    need = max(s, MIN_FEATURE_POINTS) if features == "fpfh" else s
    why = ("a normal needs a point and at least 2 neighbours" if features == "fpfh"
           else f"a sample has {s} points in {d}-D")
    check_min_points(src, need, name="source", reason=why)
    check_min_points(dst, need, name="target", reason=why)
    check_span(src, "source", d - 1, "the rotation is undetermined")
    check_span(dst, "target", d - 1, "the rotation is undetermined")
    return s, need


# --- the two kinds of candidates ------------------------------------------------------------


class _Search:
    """How samples are drawn and hypotheses scored: ``count`` candidate pairs, samples of
    ``s`` pairs, inlier threshold ``tau``."""

    count: int
    s: int
    tau: float

    def draw(self, rng: np.random.Generator, b: int) -> tuple[FloatArray, FloatArray, Any]:
        """``b`` samples: source points, target points (``(b, s, d)`` each), and a validity
        mask (samples that repeat a point are invalid)."""
        raise NotImplementedError

    def score(self, rot: FloatArray, shift: FloatArray) -> tuple[FloatArray, IntArray]:
        """Truncated squared errors and inlier counts of ``h`` hypotheses."""
        raise NotImplementedError

    def ratio(self, rot: FloatArray, shift: FloatArray, inliers: int) -> float:
        """The inlier ratio of the candidates under one hypothesis."""
        raise NotImplementedError


def _distinct(idx: IntArray) -> Any:
    s = idx.shape[1]
    ok = np.ones(idx.shape[0], dtype=bool)
    for a in range(s):
        for b in range(a + 1, s):
            ok &= idx[:, a] != idx[:, b]
    return ok


class _FeatureSearch(_Search):
    r"""Candidates are feature matches ``ps[k] ↔ pt[k]``. A hypothesis's squared residuals
    over all of them come from one matrix product: with the sets centred (``p``, ``q``),
    :math:`\lVert R p + t - q\rVert^2 = |p|^2 + |q - t|^2 + 2 p \cdot R^\mathsf{T} t
    - 2 \operatorname{vec}(q p^\mathsf{T}) \cdot \operatorname{vec}(R)`, so ``h``
    hypotheses cost an ``(M, 9) @ (9, h)`` product (BLAS on one thread: the same bits on any
    machine) instead of ``h`` transforms of ``M`` points."""

    def __init__(self, ps: FloatArray, pt: FloatArray, tau: float, s: int) -> None:
        self.ps, self.pt, self.tau, self.tau2, self.s = ps, pt, tau, tau * tau, s
        self.count = ps.shape[0]
        self.cs = ps.mean(axis=0) if self.count else np.zeros(3)
        self.ct = pt.mean(axis=0) if self.count else np.zeros(3)
        p, q = ps - self.cs, pt - self.ct
        self.p, self.q = p, q
        self.pp = np.einsum("ij,ij->i", p, p)
        self.qq = np.einsum("ij,ij->i", q, q)
        self.qp = np.einsum("mi,mj->mij", q, p).reshape(-1, 9)    # vec(q pᵀ), row-major

    def draw(self, rng: np.random.Generator, b: int) -> tuple[FloatArray, FloatArray, Any]:
        if self.count == 0:
            return np.zeros((b, self.s, 3)), np.zeros((b, self.s, 3)), np.zeros(b, bool)
        idx = rng.integers(0, self.count, size=(b, self.s))
        return self.ps[idx], self.pt[idx], _distinct(idx)

    def score(self, rot: FloatArray, shift: FloatArray) -> tuple[FloatArray, IntArray]:
        h, m = rot.shape[0], self.count
        err, inl = np.empty(h), np.empty(h, dtype=np.int64)
        step = max(1, SCORE_BLOCK // max(m, 1))
        for a in range(0, h, step):  # the caller limits BLAS to one thread
            r, t = rot[a:a + step], shift[a:a + step]
            t = t + np.einsum("hij,j->hi", r, self.cs) - self.ct    # in centred frames
            rtt = np.einsum("hij,hi->hj", r, t)                      # Rᵀ t
            r2 = (self.pp[:, None] + self.qq[:, None] + np.einsum("hi,hi->h", t, t)
                  - 2.0 * (self.q @ t.T) + 2.0 * (self.p @ rtt.T)
                  - 2.0 * (self.qp @ r.reshape(-1, 9).T))          # (M, h)
            inl[a:a + step] = np.count_nonzero(r2 <= self.tau2, axis=0)
            err[a:a + step] = np.minimum(r2, self.tau2).sum(axis=0)
        return err, inl

    def ratio(self, rot: FloatArray, shift: FloatArray, inliers: int) -> float:
        return inliers / self.count


class _PointSearch(_Search):
    def __init__(self, s_pts: FloatArray, t_pts: FloatArray, t_tree: cKDTree, tau: float,
                 s: int, rng: np.random.Generator) -> None:
        self.s_pts, self.t_pts, self.tree, self.tau, self.s = s_pts, t_pts, t_tree, tau, s
        n = s_pts.shape[0]
        self.count = n * t_pts.shape[0]
        self.scored = s_pts if n <= SCORE_POINTS else \
            s_pts[np.sort(rng.choice(n, SCORE_POINTS, replace=False))]

    def draw(self, rng: np.random.Generator, b: int) -> tuple[FloatArray, FloatArray, Any]:
        ia = rng.integers(0, self.s_pts.shape[0], size=(b, self.s))
        ib = rng.integers(0, self.t_pts.shape[0], size=(b, self.s))
        return self.s_pts[ia], self.t_pts[ib], _distinct(ia) & _distinct(ib)

    def score(self, rot: FloatArray, shift: FloatArray) -> tuple[FloatArray, IntArray]:
        h, k = rot.shape[0], self.scored.shape[0]
        moved = np.einsum("hij,mj->hmi", rot, self.scored) + shift[:, None, :]
        dist, _ = cast(KnnQuery, self.tree.query(moved.reshape(h * k, -1),
                                                 distance_upper_bound=self.tau * (1 + 1e-9)))
        dist = dist.reshape(h, k)
        inside = dist <= self.tau
        err = np.where(inside, dist * dist, self.tau * self.tau).sum(axis=1)
        return err, np.count_nonzero(inside, axis=1)

    def ratio(self, rot: FloatArray, shift: FloatArray, inliers: int) -> float:
        moved = self.scored @ rot.T + shift
        pairs = self.tree.query_ball_point(moved, self.tau, return_length=True).sum()
        candidates: int = self.scored.shape[0] * self.t_pts.shape[0]
        return float(pairs) / candidates


# --- sampling -------------------------------------------------------------------------------


def _needed(ratio: float, confidence: float, s: int) -> float:
    """Hypotheses after which an all-inlier sample was drawn with probability ``confidence``."""
    p = ratio ** s
    if p >= 1.0:
        return 0.0
    if p <= 0.0 or confidence >= 1.0:
        return math.inf
    return math.log1p(-confidence) / math.log1p(-p)


def _kabsch(a: FloatArray, b: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Best rotations and translations ``b ≈ R a + t`` of a stack of samples ``(h, s, d)``."""
    ca, cb = a.mean(axis=1), b.mean(axis=1)
    cov = np.einsum("hki,hkj->hij", b - cb[:, None, :], a - ca[:, None, :])
    rot = procrustes(cov).rotation
    return rot, cb - np.einsum("hij,hj->hi", rot, ca)


def _checks(a: FloatArray, b: FloatArray) -> Any:
    """Open3D's edge-length check, and no (nearly) collinear samples."""
    s, d = a.shape[1], a.shape[2]
    ok = np.ones(a.shape[0], dtype=bool)
    for i in range(s):
        for j in range(i + 1, s):
            la = np.linalg.norm(a[:, i] - a[:, j], axis=1)
            lb = np.linalg.norm(b[:, i] - b[:, j], axis=1)
            ok &= (la >= EDGE_SIMILARITY * lb) & (lb >= EDGE_SIMILARITY * la) & (la > 0)
    idx = np.flatnonzero(ok)
    if idx.size:
        centred = a[idx] - a[idx].mean(axis=1, keepdims=True)
        sv = np.linalg.svd(centred, compute_uv=False)          # (h, min(s, d))
        ok[idx] = sv[:, d - 2] > FLAT_RTOL * sv[:, 0]
    return ok


def _sample(search: _Search, rng: np.random.Generator, max_iterations: int,
            confidence: float, report: Progress, *, offset: int = 0, total: int | None = None,
            min_hypotheses: int = 0, top: list[Any] | None = None
            ) -> tuple[_Best | None, int, int]:
    """Draw, check, fit and score hypotheses batch by batch; apply the stopping rule after
    each hypothesis in drawing order, never before ``min_hypotheses``. ``top`` (a list)
    collects the ``TOP_HYPOTHESES`` of least error as a heap of ``(-error, -number,
    rotation, translation)``. Progress is ``offset + drawn`` of ``total``. Returns the best,
    the number drawn and the limit."""
    total = max_iterations + 1 if total is None else total
    tau = search.tau
    best: _Best | None = None
    drawn, limit = 0, max_iterations
    while drawn < limit:
        b = min(BATCH, max_iterations - drawn)
        a, t, ok = search.draw(rng, b)
        ok &= _checks(a, t)
        cand = np.flatnonzero(ok)
        if cand.size:
            rot, shift = _kabsch(a[cand], t[cand])
            moved = np.einsum("hij,hkj->hki", rot, a[cand]) + shift[:, None, :]
            res = np.linalg.norm(moved - t[cand], axis=2).max(axis=1)
            keep = res <= tau
            cand, rot, shift = cand[keep], rot[keep], shift[keep]
        if cand.size:
            err, inl = search.score(rot, shift)
            for k in range(cand.size):
                number = drawn + int(cand[k]) + 1
                if number > limit:
                    break
                if top is not None:
                    item = (-float(err[k]), -number, rot[k], shift[k])
                    if len(top) < TOP_HYPOTHESES:
                        heapq.heappush(top, item)
                    elif item[:2] > top[0][:2]:
                        heapq.heapreplace(top, item)
                if best is None or err[k] < best.error:
                    ratio = search.ratio(rot[k], shift[k], int(inl[k]))
                    best = _Best(float(err[k]), int(inl[k]), ratio, rot[k], shift[k], number)
                    needed = _needed(ratio, confidence, search.s)
                    if best.inliers >= MIN_SUPPORT and needed < max_iterations:
                        limit = min(max_iterations,
                                    max(number, math.ceil(needed), min_hypotheses))
        drawn = min(drawn + b, limit)
        report(offset + drawn, total, f"RANSAC: {drawn} hypotheses" + (
            "" if best is None else f", best inlier ratio {best.ratio:.3g}"))
    return best, drawn, limit


# --- refinement -----------------------------------------------------------------------------


def _refine(src: FloatArray, t_pts: FloatArray, t_normals: FloatArray | None,
            start: FloatArray, tau: float, rng: np.random.Generator,
            iterations: int = REFINE_ITERATIONS) -> tuple[FloatArray, str]:
    """ICP from ``start``; the refined transform only when it lowers the truncated error of
    the refinement's metric (``cost``) over the source points used."""
    d = src.shape[1]
    pts = src if src.shape[0] <= REFINE_POINTS else \
        src[np.sort(rng.choice(src.shape[0], REFINE_POINTS, replace=False))]
    metric: Metric = "point_to_point"
    if d == 3 and pts.shape[0] >= 6 and t_pts.shape[0] >= PLANE_MIN_POINTS:
        centred = t_pts - t_pts.mean(axis=0)
        var = np.linalg.eigvalsh(centred.T @ centred / len(t_pts))[::-1]
        if numerical_rank(np.maximum(var, 0.0), RANK_RTOL) == 3:
            metric = "point_to_plane"
    tree = cKDTree(t_pts)
    workers = query_workers(pts.shape[0])
    normals = t_normals if metric == "point_to_plane" else None
    if metric == "point_to_plane" and normals is None:
        normals = feature_normals(t_pts, tree, NORMAL_NEIGHBORS)

    def cost(transform: FloatArray) -> float:
        """The truncated error of the refinement's own metric: sum over the source points of
        min(r², τ²), r the distance (or plane distance) to the nearest target point."""
        moved = pts @ transform[:d, :d].T + transform[:d, d]
        dist, idx = cast(KnnQuery, tree.query(moved, distance_upper_bound=tau * (1 + 1e-9),
                                              workers=workers))
        near = dist <= tau
        r = dist[near]
        if normals is not None:
            k = idx[near]
            r = np.einsum("ij,ij->i", moved[near] - t_pts[k], normals[k])
        n_pts: int = pts.shape[0]
        return float(r @ r) + tau * tau * (n_pts - r.size)

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ConvergenceWarning)
            res = icp(pts, t_pts, metric=metric, init=start, max_iterations=iterations,
                      max_correspondence_distance=tau, target_normals=normals)
    except DegenerateInputError as err:
        return start, f"ICP refinement skipped: {str(err).rstrip('.')}"
    if res.iterations == 0:
        return start, f"{metric} ICP refinement stopped at once ({res.reason})"
    if cost(res.transform) <= cost(start):
        return res.transform, (f"refined by {metric} ICP ({res.iterations} iterations, "
                               f"{res.reason})")
    return start, (f"{metric} ICP refinement ({res.reason}) raised the truncated error: the "
                   "RANSAC transform is kept")

