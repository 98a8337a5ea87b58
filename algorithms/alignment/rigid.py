"""Rigid alignment with known correspondences (Kabsch / orthogonal Procrustes)."""

from __future__ import annotations

from dataclasses import dataclass

from algorithms.core.linalg import RANK_RTOL as RANK_RTOL  # re-exported: documented below
from algorithms.core.linalg import homogeneous
from algorithms.core.pairs import one_per_dimension, prepare, rotation_fit
from algorithms.core.params import PointsLike, WeightsLike, validate_params
from algorithms.core.types import FloatArray

__all__ = ["RigidResult", "rigid"]


@dataclass(frozen=True, eq=False)
class RigidResult:
    """The rigid transform ``y ≈ R x + t`` that best aligns ``source`` to ``target``.

    Attributes
    ----------
    transform : (d+1, d+1) float array
        The homogeneous matrix ``[[R, t], [0, 1]]`` that maps source points onto target points.
    linear : (d, d) float array
        The linear part of the transform, here equal to ``rotation`` (``scale`` is 1).
    rotation : (d, d) float array
        The orthogonal matrix ``R``, with determinant +1 unless ``reflection`` is true.
    translation : (d,) float array
        The translation ``t`` applied after the rotation.
    scale : float
        Always 1.0 for a rigid transform; present so every alignment result has the field.
    rmse : float
        The weighted root-mean-square residual ``sqrt(sum w_i |R x_i + t - y_i|^2 / sum w_i)``.
    reflection : bool
        True when the returned ``rotation`` is a reflection (determinant -1), which happens
        only with ``allow_reflection=True``.
    """

    transform: FloatArray
    linear: FloatArray
    rotation: FloatArray
    translation: FloatArray
    scale: float
    rmse: float
    reflection: bool


@validate_params
def rigid(
    source: PointsLike,
    target: PointsLike,
    *,
    weights: WeightsLike | None = None,
    allow_reflection: bool = False,
) -> RigidResult:
    r"""Rigid alignment (Kabsch / Umeyama without scale).

    The rotation R (det +1 unless reflections are allowed) and translation t minimising Σ wᵢ‖R xᵢ +
    t − yᵢ‖² for paired points in any dimension d ≥ 2.

    Row ``i`` of ``source`` corresponds to row ``i`` of ``target``. The model is
    ``y = R x + t`` with ``R`` orthogonal, solved in closed form (Kabsch 1976; Umeyama 1991
    without the scale):

    .. math::

        \min_{R^\mathsf{T} R = I,\ \det R = 1,\ t}\ \sum_{i=1}^{n} w_i
        \lVert R x_i + t - y_i \rVert^2

    With :math:`\bar x = \sum_i w_i x_i / \sum_i w_i` and :math:`\bar y` likewise, the
    weighted cross-covariance :math:`C = \sum_i w_i (y_i - \bar y)(x_i - \bar x)^\mathsf{T}
    = U \Sigma V^\mathsf{T}` gives :math:`R = U D V^\mathsf{T}` with
    :math:`D = \operatorname{diag}(1, \dots, 1, \operatorname{sign}\det(U V^\mathsf{T}))`
    and :math:`t = \bar y - R \bar x`.

    Parameters
    ----------
    source : (n, d) float array
        The points to move, ``d >= 2`` and ``n >= d``.
    target : (n, d) float array
        Where they should land, paired row by row with ``source``.
    weights : (n,) float array, optional
        Non-negative per-pair weights with a positive sum; all equal when omitted. Pairs of
        weight zero are ignored, but the pairs left must still determine the rotation.
    allow_reflection : bool, default False
        Also consider improper orthogonal matrices (determinant -1), i.e. solve the plain
        orthogonal Procrustes problem without the constraint :math:`\det R = 1`.

    Returns
    -------
    RigidResult
        ``transform``, ``linear``, ``rotation``, ``translation``, ``scale`` (1.0), ``rmse``
        and ``reflection``.

    Raises
    ------
    InvalidInputError
        ``d < 2``; fewer than ``d`` points; ``source`` and ``target`` shapes differ
        (``field="target"``); NaN/Inf; malformed ``weights`` (wrong length, negative, NaN,
        all zero; ``field="weights"``); ``allow_reflection`` not a bool.
    DegenerateInputError
        The rotation is undetermined: the weighted cross-covariance has rank below ``d - 1``
        (coincident points, or all points collinear when ``d >= 3``), or below ``d`` with
        ``allow_reflection=True`` (then the reflection across the flat the points span fits
        equally well).

    Notes
    -----
    **Reflection fix.** The unconstrained minimiser :math:`U V^\mathsf{T}` may have
    determinant -1. The best *proper* rotation is then obtained by flipping the sign of the
    singular vector that belongs to the smallest singular value (equivalently, negating that
    singular value): of all sign choices it lowers :math:`\operatorname{tr}(D\Sigma)`, which
    the objective subtracts twice, by the least amount, :math:`2\sigma_d` (Umeyama 1991,
    the matrix ``S`` of his lemma). With ``allow_reflection=True`` the
    determinant is left as it comes and ``reflection`` reports it. Kabsch's 1976 solution
    ranges over all orthogonal matrices and so may return a reflection; his 1978 note added
    the sign correction, and Umeyama proves the corrected solution optimal. Since
    :math:`R = U D V^\mathsf{T}` does not contain the singular values, negating the
    smallest one is done by negating its singular vector, left or right (the same
    rotation). When a reflection fits best
    and the two smallest singular values are equal, the best proper rotation is not unique;
    one of the minimisers is returned.

    **Degeneracy tolerance.** Singular values of :math:`C` at or below
    ``RANK_RTOL = 1e-10`` times the largest count as zero. Rounding leaves the singular
    values of exactly collinear or coplanar data at about machine epsilon times the ratio of
    the points' distance from the origin to their extent, so this relative tolerance flags
    such data even when it lies 10⁴ extents or more away from the origin. The singular
    values of :math:`C` are roughly products of the two sets' extents along matching
    directions; when ``target`` is a moved copy of ``source``, point sets thinner than about
    10⁻⁵ of their extent in some direction are therefore treated as flat. In 2-D, collinear
    points are fine: the rotation is determined (rank ``d - 1 = 1``) unless reflections are
    allowed.

    **No** ``symmetric`` **option.** The other alignment methods can also count the inverse
    residuals :math:`R^\mathsf{T}(y_i - t) - x_i`; for a rigid motion they have the same
    lengths as the forward ones, so the answer and ``rmse`` would not change.

    **Cost.** Two centrings, one ``d×d`` product accumulation over the ``n`` points, one
    ``d×d`` SVD, and one pass for the residual: ``O(n d²)`` time, no loop over points.

    References
    ----------
    .. [1] W. Kabsch, "A solution for the best rotation to relate two sets of vectors",
       Acta Crystallographica A 32(5), 922-923, 1976; and "A discussion of the solution for
       the best rotation to relate two sets of vectors", Acta Cryst. A 34(5), 827-828, 1978.
    .. [2] S. Umeyama, "Least-squares estimation of transformation parameters between two
       point patterns", IEEE Transactions on Pattern Analysis and Machine Intelligence
       13(4), 376-380, 1991.

    Examples
    --------
    >>> import numpy as np
    >>> from algorithms.alignment import rigid
    >>> x = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 2.0]])
    >>> y = x @ np.array([[0.0, 1.0], [-1.0, 0.0]]) + [3.0, 4.0]   # 90° turn, then shift
    >>> res = rigid(x, y)
    >>> np.round(res.rotation, 12) + 0.0
    array([[ 0., -1.],
           [ 1.,  0.]])
    >>> np.round(res.translation, 12) + 0.0
    array([3., 4.])
    """
    pairs = prepare(source, target, weights, min_dim=2, minimum=one_per_dimension)
    fit = rotation_fit(pairs, reflect_ok=allow_reflection)
    rotation = fit.rotation
    translation = pairs.y_mean - rotation @ pairs.x_mean
    return RigidResult(
        transform=homogeneous(rotation, translation),
        linear=rotation.copy(),
        rotation=rotation,
        translation=translation,
        scale=1.0,
        rmse=pairs.linear_rmse(rotation),  # from centred data, for accuracy
        reflection=bool(fit.reflection),
    )
