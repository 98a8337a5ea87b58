"""Similarity alignment with known correspondences (Umeyama 1991): rotation, uniform scale,
translation."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from algorithms.core.errors import DegenerateInputError
from algorithms.core.linalg import homogeneous
from algorithms.core.pairs import Pairs, one_per_dimension, prepare, rotation_fit
from algorithms.core.params import PointsLike, WeightsLike, validate_params
from algorithms.core.types import FloatArray

__all__ = ["SimilarityResult", "similarity"]

#: A best scale at or below this fraction of the largest singular value counts as zero.
SCALE_RTOL = 1e-12


@dataclass(frozen=True, eq=False)
class SimilarityResult:
    """The similarity ``y ≈ s R x + t`` that best aligns ``source`` to ``target``.

    Attributes
    ----------
    transform : (d+1, d+1) float array
        The homogeneous matrix ``[[s R, t], [0, 1]]`` that maps source points onto target
        points.
    linear : (d, d) float array
        The linear part ``s R`` of the transform.
    rotation : (d, d) float array
        The orthogonal matrix ``R``, with determinant +1 unless ``reflection`` is true.
    translation : (d,) float array
        The translation ``t`` applied after scaling and rotating.
    scale : float
        The uniform scale ``s > 0``.
    rmse : float
        The weighted root-mean-square residual ``sqrt(sum w_i |s R x_i + t - y_i|^2 / sum
        w_i)``; with ``symmetric=True`` the root of the mean of that square and the inverse
        one, ``sum w_i |(R^T (y_i - t)) / s - x_i|^2 / sum w_i``.
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
def similarity(
    source: PointsLike,
    target: PointsLike,
    *,
    weights: WeightsLike | None = None,
    allow_reflection: bool = False,
    symmetric: bool = False,
) -> SimilarityResult:
    r"""Similarity alignment (Umeyama).

    The rotation R (det +1 unless reflections are allowed), uniform scale s and translation t
    minimising Σ wᵢ‖s R xᵢ + t − yᵢ‖² for paired points, d ≥ 2; s = tr(DΣ)/σx² with Umeyama's
    reflection-corrected trace.

    Row ``i`` of ``source`` corresponds to row ``i`` of ``target``. The model is
    ``y = s R x + t`` with ``R`` orthogonal and ``s > 0``, solved in closed form (Umeyama
    1991):

    .. math::

        \min_{R^\mathsf{T} R = I,\ \det R = 1,\ s > 0,\ t}\ \sum_{i=1}^{n} w_i
        \lVert s R x_i + t - y_i \rVert^2 .

    With weighted centroids :math:`\bar x, \bar y`, centred points :math:`\tilde x_i,
    \tilde y_i`, normalised weights :math:`p_i = w_i / \sum_j w_j`, the cross-covariance
    :math:`C = \sum_i p_i \tilde y_i \tilde x_i^\mathsf{T} = U \Sigma V^\mathsf{T}` and
    :math:`\sigma_x^2 = \sum_i p_i \lVert \tilde x_i \rVert^2`:

    .. math::

        R = U D V^\mathsf{T}, \qquad
        s = \frac{\operatorname{tr}(D \Sigma)}{\sigma_x^2}, \qquad
        t = \bar y - s R \bar x,

    where :math:`D = \operatorname{diag}(1, \dots, 1, \operatorname{sign}\det(U V^\mathsf{T}))`
    (the identity with ``allow_reflection=True``).

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
        Also consider improper orthogonal matrices (determinant -1).
    symmetric : bool, default False
        Minimise the forward and the inverse residuals together,
        :math:`\sum_i w_i (\lVert s R x_i + t - y_i \rVert^2
        + \lVert s^{-1} R^\mathsf{T}(y_i - t) - x_i \rVert^2)`; see Notes.

    Returns
    -------
    SimilarityResult
        ``transform``, ``linear`` (``s R``), ``rotation``, ``translation``, ``scale``,
        ``rmse`` and ``reflection``.

    Raises
    ------
    InvalidInputError
        ``d < 2``; fewer than ``d`` points; ``source`` and ``target`` shapes differ
        (``field="target"``); NaN/Inf; malformed ``weights`` (``field="weights"``);
        ``allow_reflection`` or ``symmetric`` not a bool.
    DegenerateInputError
        The rotation is undetermined (as for :func:`~algorithms.alignment.rigid`: the
        cross-covariance has rank below ``d - 1``, or below ``d`` with reflections allowed;
        the message names the coincident or collinear set), or the best scale is zero
        (``field=None``): in 2-D, when ``target`` is a mirror image of ``source`` whose
        cross-covariance has two equal singular values, no proper rotation correlates the
        sets at all and collapsing every point onto the centroid fits best.

    Notes
    -----
    **The scale uses the corrected trace.** The scale is often written (e.g. in Horaud's
    course notes) :math:`s = \operatorname{tr}(\Sigma)/\lVert\tilde X\rVert_F^2`. That is right only
    while :math:`\det(U V^\mathsf{T}) = +1`. When the reflection fix flips the singular vector
    of the smallest singular value, the rotation actually used correlates the sets by
    :math:`\operatorname{tr}(R^\mathsf{T} C) = \operatorname{tr}(D\Sigma) = \sigma_1 + \dots +
    \sigma_{d-1} - \sigma_d`, and the least-squares scale for that rotation is
    :math:`\operatorname{tr}(D\Sigma)/\sigma_x^2`, Umeyama's formula (his eq. 42 with the
    matrix ``S``). The plain trace overestimates the scale by :math:`2\sigma_d/\sigma_x^2`
    and gives a larger residual; this implementation follows Umeyama. The shortcut
    :math:`s \approx \lVert\tilde Y\rVert_F / \lVert\tilde X\rVert_F` (the scale
    trimesh's ``procrustes`` uses) is exact only for noise-free data; in general it is the
    larger of the two (Cauchy–Schwarz) and not the least-squares scale.

    **Reflection fix and degeneracy** as in :func:`~algorithms.alignment.rigid`, whose
    rotation this shares (:func:`algorithms.core.linalg.procrustes`).

    **Symmetric.** The inverse residual of pair ``i`` is :math:`-e_i / s` rotated, where
    :math:`e_i = s R x_i + t - y_i`, so the objective is
    :math:`(1 + s^{-2}) \sum_i w_i \lVert e_i \rVert^2`. For every ``s > 0`` the best ``t``
    is still the one through the centroids and the best ``R`` still the Procrustes rotation
    above; the scale then minimises
    :math:`f(s) = (s^2 \sigma_x^2 - 2 s T + \sigma_y^2)(1 + s^{-2})`, with
    :math:`T = \operatorname{tr}(D\Sigma)`, whose stationary points are the positive roots of
    :math:`\sigma_x^2 s^4 - T s^3 + T s - \sigma_y^2 = 0` (there is one at least: the
    polynomial is negative at 0 and positive at infinity). The root of smallest ``f`` is
    taken and polished by Newton steps. For noise-free data it is the true scale, as in the
    one-sided fit.

    **Cost.** As :func:`~algorithms.alignment.rigid`: ``O(n d²)`` and one ``d×d`` SVD.

    References
    ----------
    .. [1] S. Umeyama, "Least-squares estimation of transformation parameters between two
       point patterns", IEEE Transactions on Pattern Analysis and Machine Intelligence
       13(4), 376-380, 1991.
    .. [2] B. K. P. Horn, "Closed-form solution of absolute orientation using unit
       quaternions", Journal of the Optical Society of America A 4(4), 629-642, 1987.

    Examples
    --------
    >>> import numpy as np
    >>> from algorithms.alignment import similarity
    >>> x = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 2.0]])
    >>> y = 2.0 * x @ np.array([[0.0, 1.0], [-1.0, 0.0]]) + [3.0, 4.0]   # 90°, double, shift
    >>> res = similarity(x, y)
    >>> round(res.scale, 12)
    2.0
    >>> np.round(res.linear, 12) + 0.0
    array([[ 0., -2.],
           [ 2.,  0.]])
    """
    pairs = prepare(source, target, weights, min_dim=2, minimum=one_per_dimension)
    fit = rotation_fit(pairs, reflect_ok=allow_reflection)
    var_x = pairs.mean_square(pairs.xc)
    trace = float(fit.trace)
    if not trace > SCALE_RTOL * fit.singular_values[0]:
        raise DegenerateInputError(
            "Expected `source` and `target` to be correlated by some proper rotation, got a "
            "best scale of zero: no similarity with positive scale fits better than "
            "collapsing every point onto the target's centroid (a mirror image with equal "
            "singular values; allow_reflection=true fits it).",
            field=None,
        )
    scale = _symmetric_scale(pairs, var_x, trace) if symmetric else trace / var_x

    rotation = fit.rotation
    linear = scale * rotation
    translation = pairs.y_mean - linear @ pairs.x_mean
    return SimilarityResult(
        transform=homogeneous(linear, translation),
        linear=linear,
        rotation=rotation,
        translation=translation,
        scale=scale,
        rmse=pairs.linear_rmse(linear, symmetric=symmetric),
        reflection=bool(fit.reflection),
    )


def _symmetric_scale(pairs: Pairs, var_x: float, trace: float) -> float:
    """The ``s > 0`` minimising ``(s² σx² − 2 s T + σy²)(1 + s⁻²)`` (see Notes)."""
    var_y = pairs.mean_square(pairs.yc)
    c = trace / var_x
    roots = np.roots([1.0, -c, 0.0, c, -var_y / var_x])
    real = roots.real[(np.abs(roots.imag) <= 1e-6 * np.abs(roots)) & (roots.real > 0)]

    def f(s: float) -> float:
        return (s * s * var_x - 2.0 * s * trace + var_y) * (1.0 + 1.0 / (s * s))

    def g(s: float) -> tuple[float, float]:  # the quartic and its derivative
        return (var_x * s**4 - trace * s**3 + trace * s - var_y,
                4.0 * var_x * s**3 - 3.0 * trace * s**2 + trace)

    # At least one root is real and positive (see Notes); should rounding hide it, start
    # Newton from the one-sided scale.
    best = min((float(r) for r in real), key=f, default=trace / var_x)
    for _ in range(3):  # Newton polish: the companion-matrix roots carry ~1e-15 relative error
        value, slope = g(best)
        if slope == 0.0:
            break
        step = value / slope
        if not 0.0 < best - step:
            break
        best -= step
    return best
