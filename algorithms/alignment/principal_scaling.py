"""Principal scaling alignment: the cross-covariance map M = ỸX̃ᵀ = UΣVᵀ."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from algorithms.core.linalg import homogeneous
from algorithms.core.pairs import one_per_dimension, prepare, rotation_fit
from algorithms.core.params import PointsLike, WeightsLike, validate_params
from algorithms.core.types import FloatArray

__all__ = ["PrincipalScalingResult", "principal_scaling"]


@dataclass(frozen=True, eq=False)
class PrincipalScalingResult:
    """The map ``y ≈ U Σ Vᵀ x + t`` with ``U Σ Vᵀ = Σᵢ wᵢ ỹᵢ x̃ᵢᵀ`` (the cross-covariance map).

    Attributes
    ----------
    transform : (d+1, d+1) float array
        The homogeneous matrix ``[[M, t], [0, 1]]`` that maps source points towards target
        points.
    linear : (d, d) float array
        ``M = U D Σ Vᵀ``: the weighted ``sum w_i (y_i - ȳ)(x_i - x̄)^T`` itself, or with the
        reflection fix applied (``D`` flips the singular vector of the smallest singular
        value when ``det(U Vᵀ) = -1`` and reflections are not allowed).
    rotation : (d, d) float array
        ``R = U D Vᵀ``, the orthogonal factor: determinant +1 unless ``reflection`` is true.
    scale : (d,) float array
        ``Σ``, the scale factors along ``axes``, non-negative and decreasing.
    axes : (d, d) float array
        ``V``: column ``k`` is the source direction scaled by ``scale[k]``; ``linear =
        rotation @ axes @ diag(scale) @ axes.T``.
    translation : (d,) float array
        ``t = ȳ - M x̄``, through the weighted centroids.
    rmse : float
        The weighted root-mean-square residual ``sqrt(sum w_i |M x_i + t - y_i|^2 / sum
        w_i)``; with ``symmetric=True`` the root of the mean of that square and the inverse
        one, ``sum w_i |M^-1 (y_i - t) - x_i|^2 / sum w_i``.
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
    reflection: bool


@validate_params
def principal_scaling(
    source: PointsLike,
    target: PointsLike,
    *,
    weights: WeightsLike | None = None,
    allow_reflection: bool = False,
    symmetric: bool = False,
) -> PrincipalScalingResult:
    r"""Principal scaling alignment (the cross-covariance map M = Ỹ X̃ᵀ).

    Scale along perpendicular axes, then rotate: y = UΣVᵀx + t with UΣVᵀ = Σ wᵢ ỹᵢ x̃ᵢᵀ. Equals the
    least-squares affine map exactly when the source is whitened (Σ wᵢ x̃ᵢ x̃ᵢᵀ = I); otherwise a
    worse fit.

    Row ``i`` of ``source`` corresponds to row ``i`` of ``target``. The map
    :math:`y = U \Sigma V^\mathsf{T} x + t` (``U``, ``V`` orthonormal, :math:`\Sigma \ge 0`
    diagonal) is taken from the cross-covariance itself,

    .. math::

        M = \sum_{i=1}^{n} w_i \tilde y_i \tilde x_i^\mathsf{T} = \tilde Y \tilde X^\mathsf{T}
          = U \Sigma V^\mathsf{T}, \qquad t = \bar y - M \bar x,

    with weighted centroids :math:`\bar x, \bar y` and centred points :math:`\tilde x_i,
    \tilde y_i`. This function computes exactly that (the weights enter unnormalised, so
    that all-ones weights give :math:`\tilde Y \tilde X^\mathsf{T}`), with the reflection
    fix of :func:`~algorithms.alignment.rigid`. It is **not** a least-squares fit in general;
    see Notes.

    Parameters
    ----------
    source : (n, d) float array
        The points to move, ``d >= 2`` and ``n >= d``.
    target : (n, d) float array
        Where they should land, paired row by row with ``source``.
    weights : (n,) float array, optional
        Non-negative per-pair weights with a positive sum; all ones when omitted. Unlike in
        the other alignment methods their overall size matters: doubling every weight
        doubles ``M``.
    allow_reflection : bool, default False
        Keep :math:`U \Sigma V^\mathsf{T}` when :math:`\det(U V^\mathsf{T}) = -1`. Off: the
        left singular vector of the smallest singular value is negated, so the map never
        mirrors.
    symmetric : bool, default False
        Report the forward and inverse residuals together in ``rmse``. ``M`` is a formula,
        not a minimiser, so the flag changes only the figure (and requires ``M``
        invertible).

    Returns
    -------
    PrincipalScalingResult
        ``transform``, ``linear``, ``rotation``, ``scale``, ``axes``, ``translation``,
        ``rmse`` and ``reflection``.

    Raises
    ------
    InvalidInputError
        ``d < 2``; fewer than ``d`` points; ``source`` and ``target`` shapes differ
        (``field="target"``); NaN/Inf; malformed ``weights`` (``field="weights"``);
        ``allow_reflection`` or ``symmetric`` not a bool.
    DegenerateInputError
        ``M`` has rank below ``d - 1`` (coincident or collinear sets: the rotation and axes
        are undetermined), or below ``d`` with ``allow_reflection=True`` or
        ``symmetric=True``.

    Notes
    -----
    **When M is the least-squares map.** Every ``d×d`` matrix has a singular value
    decomposition, so the model :math:`U \Sigma V^\mathsf{T}` is the general linear map and
    its least-squares fit is the affine one, :math:`A = \tilde Y \tilde X^\mathsf{T}
    (\tilde X \tilde X^\mathsf{T})^{-1}` (:func:`~algorithms.alignment.affine`). ``M``
    equals it exactly when :math:`\tilde X \tilde X^\mathsf{T} = \sum_i w_i \tilde x_i
    \tilde x_i^\mathsf{T} = I`, i.e. for a whitened source (and, without
    ``allow_reflection``, when :math:`\det A \ge 0`). Otherwise ``M`` carries the source's
    second moments along: scaling ``source`` by ``c`` scales ``M`` by ``c`` where the best
    map scales by ``1/c``, and the residual is larger than the affine one. Reading
    :math:`\tilde Y \tilde X^\mathsf{T}` as "divide by X, multiply by Y" misses exactly the
    factor :math:`(\tilde X \tilde X^\mathsf{T})^{-1}`, which whitening makes the identity;
    the tests check both statements (equality when whitened, a larger residual otherwise).

    **Reflection fix** as in :func:`~algorithms.alignment.rigid`
    (:func:`algorithms.core.linalg.procrustes`): with :math:`\det(U V^\mathsf{T}) = -1` the
    returned linear part is :math:`U D \Sigma V^\mathsf{T} \ne M`, the nearest map of the
    model without a mirror.

    **Cost.** ``O(n d²)`` and one ``d×d`` SVD.

    References
    ----------
    .. [1] S. Umeyama, "Least-squares estimation of transformation parameters between two
       point patterns", IEEE TPAMI 13(4), 376-380, 1991: the same cross-covariance, whose
       rotation factor is the rigid fit.

    Examples
    --------
    >>> import numpy as np
    >>> from algorithms.alignment import principal_scaling
    >>> x = np.array([[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]]) / np.sqrt(2)
    >>> y = x @ np.array([[3.0, 0.0], [0.0, 0.5]]).T      # whitened source: M is exact
    >>> res = principal_scaling(x, y)
    >>> np.round(res.linear, 12) + 0.0
    array([[3. , 0. ],
           [0. , 0.5]])
    >>> res.scale.round(12).tolist()
    [3.0, 0.5]
    """
    pairs = prepare(source, target, weights, min_dim=2, minimum=one_per_dimension)
    fit = rotation_fit(pairs, reflect_ok=allow_reflection, invertible=symmetric)
    scale = pairs.total * fit.singular_values  # C is normalised; M = (sum of weights) C
    linear = (fit.u * scale) @ fit.vt
    translation = pairs.y_mean - linear @ pairs.x_mean
    return PrincipalScalingResult(
        transform=homogeneous(linear, translation),
        linear=linear,
        rotation=fit.rotation,
        scale=scale,
        axes=np.ascontiguousarray(fit.vt.T),
        translation=translation,
        rmse=pairs.linear_rmse(linear, symmetric=symmetric),
        reflection=bool(fit.reflection),
    )
