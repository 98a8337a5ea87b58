"""Alignment without correspondences by principal axes (PCA / correlation alignment)."""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from typing import Literal, cast, get_args

import numpy as np
from scipy.spatial import cKDTree

from algorithms.core.linalg import RANK_RTOL, det, homogeneous, numerical_rank
from algorithms.core.pairs import flat_error
from algorithms.core.params import PointsLike, validate_params
from algorithms.core.types import FloatArray, KnnQuery
from algorithms.core.validation import as_points, same_dim

__all__ = ["PCAResult", "pca", "MODES", "CHOICES", "SCALES"]

Mode = Literal["unoriented", "oriented"]
Choose = Literal["residual", "rotation"]
Scale = Literal["anisotropic", "isotropic", "none"]
#: The accepted values of ``mode``, ``choose`` and ``scale``.
MODES, CHOICES, SCALES = get_args(Mode), get_args(Choose), get_args(Scale)


@dataclass(frozen=True, eq=False)
class PCAResult:
    """The map ``y ≈ A x + t`` that lays the principal axes of ``source`` onto those of
    ``target``.

    Attributes
    ----------
    transform : (d+1, d+1) float array
        The homogeneous matrix ``[[A, t], [0, 1]]`` that maps source points onto target
        points.
    linear : (d, d) float array
        ``A = rotation @ axes @ diag(scale) @ axes.T``: stretch along the source's principal
        axes, then turn them onto the target's.
    rotation : (d, d) float array
        The orthogonal matrix ``R`` sending each source principal axis to its target partner
        (signs as chosen), with determinant +1 unless ``reflection`` is true.
    scale : (d,) float array
        The stretch along each source principal axis: ones (``scale="none"``), the ratio of
        root-mean-square radii (``"isotropic"``), or the ratios of the standard deviations
        along paired axes (``"anisotropic"``).
    axes : (d, d) float array
        The source's principal axes as columns, by decreasing variance, each pointing
        towards the set's skew (positive third moment) times the sign chosen; ``rotation @
        axes`` are the target's, pointing towards its skew.
    translation : (d,) float array
        ``t = ȳ - A x̄``: centroid onto centroid.
    rmse : float
        The root-mean-square distance from each moved source point to its nearest target
        point; with ``symmetric=True`` the root of the mean of that square and the one from
        each target point, moved back by the inverse map, to its nearest source point.
    chamfer : float
        The Chamfer distance between the moved source and the target: the sum of the
        distances from each point to the nearest point of the other set, both ways.
    reflection : bool
        True when ``rotation`` is a reflection (determinant -1), which happens only with
        ``allow_reflection=True``.
    """

    transform: FloatArray
    linear: FloatArray
    rotation: FloatArray
    scale: FloatArray
    axes: FloatArray
    translation: FloatArray
    rmse: float
    chamfer: float
    reflection: bool


@validate_params
def pca(
    source: PointsLike,
    target: PointsLike,
    *,
    mode: Mode = "unoriented",
    choose: Choose = "residual",
    scale: Scale = "anisotropic",
    allow_reflection: bool = False,
    symmetric: bool = False,
) -> PCAResult:
    r"""Principal-axis alignment (no correspondences).

    Lays the principal axes of the source onto those of the target (sets of any sizes): A = E′ S K
    Eᵀ with signs S from skewness (oriented) or the best of the proper sign choices (unoriented),
    scale K none, isotropic or anisotropic √(D′D⁻¹).

    Each set is centred and its covariance diagonalised,
    :math:`\frac1n \tilde X^\mathsf{T} \tilde X = E D E^\mathsf{T}` and
    :math:`\frac1m \tilde Y^\mathsf{T} \tilde Y = E' D' E'^\mathsf{T}`, eigenvalues in
    decreasing order. The axes are paired by that order and the map is

    .. math::

        A = E' S K E^\mathsf{T}, \qquad t = \bar y - A \bar x,

    with :math:`S = \operatorname{diag}(\pm 1)` the chosen signs and ``K`` the scale:
    ``"anisotropic"`` :math:`K = \sqrt{D' D^{-1}}`, ``"isotropic"``
    :math:`K = \sqrt{\operatorname{tr} D' / \operatorname{tr} D}\, I`, ``"none"``
    :math:`K = I`. ``rotation`` is :math:`R = E' S E^\mathsf{T}`.

    The signs of eigenvectors are arbitrary; ``mode`` fixes them:

    - ``"oriented"``: each axis points where the set's third moment along it is positive
      (towards its long tail: the skewness), in both sets; then, if :math:`\det R = -1` and
      reflections are not allowed, the axis of the smallest eigenvalue is flipped (of all
      single flips, it increases the residual least).
    - ``"unoriented"``: every sign choice is tried, the :math:`2^{d-1}` proper ones
      (:math:`2^d` with ``allow_reflection``), and ``choose`` picks one: ``"residual"``
      (default) the one of smallest Chamfer distance between the moved source and the
      target (kd-tree), ``"rotation"`` the one of smallest rotation angle, i.e. largest
      :math:`\operatorname{tr} R`.

    Parameters
    ----------
    source : (n, d) float array
        The points to move, ``d >= 2``, ``n >= 2``.
    target : (m, d) float array
        The points to align to; same ``d``, any ``m >= 2``.
    mode : {"unoriented", "oriented"}, default "unoriented"
        How the signs of the axes are fixed: ``"unoriented"`` tries every proper sign
        choice of the principal axes and keeps the one ``choose`` prefers; ``"oriented"``
        points each axis towards its set's skew (third moment) and pairs the axes in order
        of variance.
    choose : {"residual", "rotation"}, default "residual"
        With ``mode="unoriented"``, which sign choice is kept: ``"residual"`` the one of
        least Chamfer distance, ``"rotation"`` the one of smallest rotation angle (largest
        trace). Ignored when oriented.
    scale : {"anisotropic", "isotropic", "none"}, default "anisotropic"
        How the source is stretched: ``"anisotropic"`` each principal axis by the ratio of
        the two sets' standard deviations along it, ``"isotropic"`` by one factor, the ratio
        of RMS radii, ``"none"`` not at all (rotate only).
    allow_reflection : bool, default False
        Let ``rotation`` be a reflection when that pairs the axes better.
    symmetric : bool, default False
        Count the inverse residuals in ``rmse`` too (target moved back onto the source).
        The Chamfer distance that ``choose="residual"`` minimises already counts both ways.

    Returns
    -------
    PCAResult
        ``transform``, ``linear``, ``rotation``, ``scale``, ``axes``, ``translation``,
        ``rmse``, ``chamfer`` and ``reflection``.

    Raises
    ------
    InvalidInputError
        ``d < 2``; fewer than 2 points in a set; differing dimensions
        (``field="target"``); NaN/Inf; an unknown ``mode``, ``choose`` or ``scale``; a flag
        that is not a bool.
    DegenerateInputError
        A set spans fewer than ``d - 1`` dimensions after centring (coincident points, or
        collinear points in 3-D and up: some axes are undetermined); or fewer than ``d``
        with ``scale="anisotropic"`` (a zero variance has no ratio), with
        ``allow_reflection=True`` (a flat set fits its mirror image equally well), or with
        ``symmetric=True`` (the map must be invertible).

    Notes
    -----
    **The smallest rotation has the largest trace.** The angle :math:`\theta` of a rotation
    satisfies :math:`\operatorname{tr} R = 1 + 2\cos\theta` in 3-D (:math:`2\cos\theta` in
    2-D; in general the trace falls as the rotation grows). A rule that keeps "the
    rotation of smallest angle, i.e. of smallest trace" contradicts itself: the smallest
    angle is the **largest** trace, and that is what ``choose="rotation"`` keeps.

    **Normalised covariances.** Each covariance is a mean over its own set's points. The
    unnormalised :math:`\tilde X^\mathsf{T} \tilde X` would make the anisotropic scale
    :math:`\sqrt{D'D^{-1}}` of sets of ``n`` and ``m`` points off by :math:`\sqrt{m/n}`.

    **Isotropic and no scale** give a similarity or a rigid motion, as ``model`` does in
    :func:`~algorithms.registration.icp`.

    **Ambiguity.** Equal eigenvalues (a set symmetric under some rotation, e.g. a disc)
    leave the axes, and so the answer, undetermined; no error is raised, as a slightly
    perturbed set is determined. An axis along which a set is symmetric has no third
    moment and the oriented mode cannot orient it: use ``mode="unoriented"``, which is
    the default for that reason. The residual rule is the robust choice; the rotation rule
    suits sets that are already roughly aligned.

    **Cost.** Two ``O(n d²)`` covariances and ``d×d`` eigendecompositions; the residual rule
    adds, per sign choice, a kd-tree of the moved source and two queries:
    :math:`O(2^{d-1} (n + m) \log(n + m))`.

    References
    ----------
    .. [1] T. Ju, "CSE 554 Lecture 7: Alignment", Washington University in St. Louis
       (principal-axis alignment and the sign ambiguity).

    Examples
    --------
    >>> import numpy as np
    >>> from algorithms.alignment import pca
    >>> rng = np.random.default_rng(0)
    >>> x = rng.gamma(2.0, size=(200, 2)) * [3.0, 1.0]      # skewed, elongated
    >>> turn = np.array([[0.0, -1.0], [1.0, 0.0]])           # 90 degrees
    >>> y = 2.0 * x[::-1] @ turn.T + [5.0, 5.0]              # reordered, scaled, moved
    >>> res = pca(x, y, mode="oriented", scale="isotropic")
    >>> np.round(res.linear, 8) + 0.0
    array([[ 0., -2.],
           [ 2.,  0.]])
    """
    src = as_points(source, name="source", min_dim=2, min_points=2)
    dst = as_points(target, name="target", min_points=2)
    same_dim(src, dst, names=("source", "target"))
    d = src.shape[1]

    full = scale == "anisotropic" or allow_reflection or symmetric
    if scale == "anisotropic":
        why = "the anisotropic scale divides by every variance"
    elif allow_reflection:
        why = "a reflection across the flat they span fits equally well"
    else:
        why = "the inverse map that `symmetric=true` needs does not exist"
    x_mean, xc, x_axes, x_var = _principal(src, "source", d if full else d - 1, why)
    y_mean, yc, y_axes, y_var = _principal(dst, "target", d if full else d - 1, why)

    if scale == "anisotropic":
        factors = np.sqrt(y_var / x_var)
    elif scale == "isotropic":
        factors = np.full(d, math.sqrt(y_var.sum() / x_var.sum()))
    else:
        factors = np.ones(d)

    # Both sets' axes point towards their skew: the oriented pairing is the sign choice of
    # all ones, and the first candidate of the unoriented search (ties go to it).
    x_axes = x_axes * _skew_signs(xc, x_axes)
    y_axes = y_axes * _skew_signs(yc, y_axes)
    det_pair = det(y_axes) * det(x_axes)
    if mode == "oriented":
        signs = np.ones(d)
        if not allow_reflection and det_pair < 0:
            signs[-1] = -1.0  # the smallest variance: the residual grows least
        candidates = [signs]
    else:
        candidates = _sign_choices(d, det_pair, allow_reflection)

    def linear_of(signs: FloatArray) -> FloatArray:
        return (y_axes * (signs * factors)) @ x_axes.T

    tree = cKDTree(dst)
    if len(candidates) > 1 and choose == "rotation":
        overlap = np.einsum("ik,ik->k", y_axes, x_axes)  # tr(E' S Eᵀ) = Σₖ sₖ (e'ₖ · eₖ)
        best = max(candidates, key=lambda s: float(s @ overlap))
    else:
        best = min(candidates, key=lambda s: _chamfer(xc @ linear_of(s).T + y_mean, dst, tree))
    linear = linear_of(best)
    rotation = (y_axes * best) @ x_axes.T
    translation = y_mean - linear @ x_mean
    moved = xc @ linear.T + y_mean  # = A x + t, from centred data

    forward, _ = cast(KnnQuery, tree.query(moved))
    mean_sq = float(forward @ forward) / len(forward)
    if symmetric:
        back = np.linalg.solve(linear, yc.T).T + x_mean
        inverse, _ = cast(KnnQuery, cKDTree(src).query(back))
        mean_sq = 0.5 * (mean_sq + float(inverse @ inverse) / len(inverse))
    return PCAResult(
        transform=homogeneous(linear, translation),
        linear=linear,
        rotation=rotation,
        scale=factors,
        axes=x_axes * best,
        translation=translation,
        rmse=math.sqrt(mean_sq),
        chamfer=_chamfer(moved, dst, tree),
        reflection=bool(det(rotation) < 0),
    )


def _principal(
    pts: FloatArray, name: str, need: int, why: str
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Centroid, centred points, principal axes (columns, decreasing variance) and
    variances of a set."""
    mean = pts.mean(axis=0)
    centred = pts - mean
    var, axes = np.linalg.eigh(centred.T @ centred / len(pts))
    var, axes = np.maximum(var[::-1], 0.0), axes[:, ::-1]
    # Variances are squared extents: RANK_RTOL on them is 1e-5 on the extents, the
    # tolerance rigid alignment applies to each set.
    span = numerical_rank(var, RANK_RTOL)
    if span < need:
        reason = "the principal axes are undetermined" if span < pts.shape[1] - 1 else why
        raise flat_error(name, span, need, reason)
    return mean, centred, axes, var


def _skew_signs(centred: FloatArray, axes: FloatArray) -> FloatArray:
    """+1 where the third moment along an axis is non-negative, else -1."""
    third = np.mean((centred @ axes) ** 3, axis=0)
    return np.where(third < 0, -1.0, 1.0)


def _sign_choices(d: int, det_pair: float, reflect_ok: bool) -> list[FloatArray]:
    """Every sign vector, or only those giving ``det(E' S Eᵀ) = +1``."""
    out = [np.array(s, dtype=float) for s in itertools.product((1.0, -1.0), repeat=d)]
    if reflect_ok:
        return out
    return [s for s in out if det_pair * np.prod(s) > 0]


def _chamfer(moved: FloatArray, target: FloatArray, target_tree: cKDTree) -> float:
    """The Chamfer distance: nearest-point distances summed both ways."""
    forward, _ = cast(KnnQuery, target_tree.query(moved))
    backward, _ = cast(KnnQuery, cKDTree(moved).query(target))
    return float(forward.sum() + backward.sum())
