"""Projective alignment with known correspondences: the direct linear transformation (DLT)
with Hartley normalisation, in any dimension."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import cast

import numpy as np

from algorithms.core.errors import DegenerateInputError
from algorithms.core.linalg import RANK_RTOL, homogeneous, numerical_rank
from algorithms.core.pairs import Pairs, flat_error, prepare
from algorithms.core.params import PointsLike, WeightsLike, validate_params
from algorithms.core.types import FloatArray

__all__ = ["HomographyResult", "homography"]


@dataclass(frozen=True, eq=False)
class HomographyResult:
    """The projective map ``y ≈ dehomogenize(P [x; 1])`` that aligns ``source`` to ``target``.

    Attributes
    ----------
    transform : (d+1, d+1) float array
        The projective matrix ``P``, scaled so that ``P[d, d] = 1`` (when that entry is zero
        up to rounding, so that ``|P|_F = 1`` with its largest-magnitude entry positive).
    linear : (d, d) float array
        The block ``P[:d, :d]``; the linear part of the map when ``perspective`` is zero.
    translation : (d,) float array
        The block ``P[:d, d]``; the translation when ``perspective`` is zero.
    perspective : (d,) float array
        The block ``P[d, :d]``: zero for an affine map, else the direction in which points
        are sent towards infinity.
    rmse : float
        The weighted root-mean-square transfer error ``sqrt(sum w_i |dehom(P x_i) - y_i|^2 /
        sum w_i)``; with ``symmetric=True`` the root of the mean of that square and the
        backward transfer error ``sum w_i |dehom(P^-1 y_i) - x_i|^2 / sum w_i``.
    """

    transform: FloatArray
    linear: FloatArray
    translation: FloatArray
    perspective: FloatArray
    rmse: float


@validate_params
def homography(
    source: PointsLike,
    target: PointsLike,
    *,
    weights: WeightsLike | None = None,
    symmetric: bool = False,
) -> HomographyResult:
    r"""Projective alignment (normalised DLT).

    The (d+1)×(d+1) projective matrix P (P[d, d] = 1 when possible) with y ≈ dehomogenize(P [x; 1]),
    by the direct linear transformation on Hartley-normalised points, in any dimension; at least d +
    2 pairs in general position.

    Row ``i`` of ``source`` corresponds to row ``i`` of ``target``. The model is
    :math:`y = \operatorname{dehom}(P\,[x; 1])` with a ``(d+1)×(d+1)`` matrix ``P``
    defined up to scale, where :math:`\operatorname{dehom}(h) = h_{1..d} / h_{d+1}`.
    Writing :math:`p_j` for the rows of ``P`` and :math:`h_i = [x_i; 1]`, each pair gives
    ``d`` equations linear in ``P`` once the scale is multiplied out,

    .. math::

        p_j^\mathsf{T} h_i - y_{ij}\, p_{d+1}^\mathsf{T} h_i = 0, \qquad j = 1, \dots, d,

    stacked into :math:`A\,\operatorname{vec}(P) = 0`. The estimate minimises the
    algebraic error :math:`\sum_i w_i \lVert A_i \operatorname{vec}(P)\rVert^2` subject to
    :math:`\lVert P \rVert_F = 1`: ``vec(P)`` is the right singular vector of the smallest
    singular value of ``A``. Points are first normalised (Hartley): each set is centred at
    its weighted centroid and scaled so that its root-mean-square distance from it is
    :math:`\sqrt d`; the matrix found for the normalised points is mapped back,
    :math:`P = T_y^{-1} \hat P T_x`.

    Parameters
    ----------
    source : (n, d) float array
        The points to move, any ``d >= 1``, at least ``d + 2`` of them in general position.
    target : (n, d) float array
        Where they should land, paired row by row with ``source``.
    weights : (n,) float array, optional
        Non-negative per-pair weights with a positive sum; all equal when omitted. The
        ``d`` DLT rows of pair ``i`` are multiplied by :math:`\sqrt{w_i}` (so they weight the
        algebraic error), and the normalisation uses the weighted centroid and spread.
    symmetric : bool, default False
        Report the forward and backward transfer errors together in ``rmse``. The DLT
        equations of the inverse map are the same equations, so the estimate is unchanged.

    Returns
    -------
    HomographyResult
        ``transform`` (``P``), its blocks ``linear``, ``translation`` and ``perspective``,
        and ``rmse``.

    Raises
    ------
    InvalidInputError
        Fewer than ``d + 2`` points; ``source`` and ``target`` shapes differ
        (``field="target"``); NaN/Inf; malformed ``weights`` (``field="weights"``);
        ``symmetric`` not a bool.
    DegenerateInputError
        A set spans fewer than ``d`` dimensions after centring (coincident, collinear,
        coplanar points); the points are not in general position, so that more than one
        projective map fits (with ``d + 2`` points: ``d + 1`` of them on one hyperplane);
        the best-fitting ``P`` is singular; or it sends a source point of positive weight
        to infinity (``|P[d] · [x; 1]|`` at or below ``RANK_RTOL`` of the size of its
        terms; ``field=None``). The message names the set responsible when one is.

    Notes
    -----
    **General dimension.** ``P`` has :math:`(d+1)^2 - 1` degrees of freedom and each pair
    gives ``d`` equations, hence at least ``d + 2`` pairs (4 in the plane, 5 in space, 3 on
    a line: the Möbius maps :math:`x \mapsto (ax + b)/(cx + e)`). The planar case has
    two rows per pair, a ``2n×9`` system whose solution is the right singular vector of the
    smallest singular value; the same derivation gives ``d`` rows per pair in ``d``
    dimensions. For more
    than :math:`(d+1)^2` rows, ``A`` is first reduced to its ``R`` factor (same singular
    values and right singular vectors), so the SVD is of a :math:`(d+1)^2` square.

    **Normalisation.** Without it the columns of ``A`` differ in size by the square of the
    coordinates (10⁶ for coordinates in the thousands) and the smallest singular vector
    loses that many digits (Hartley 1997). With it, noise-free data is recovered to about
    10⁻¹² relative even with coordinates in the thousands.

    **Not the geometric error.** The DLT minimises the algebraic error, which weights the
    transfer error of pair ``i`` by the square of :math:`p_{d+1}^\mathsf{T} h_i`; for
    noise-free data both vanish and the map is exact, for noisy data it is a good start for
    a nonlinear refinement. ``rmse`` is always the geometric transfer error.

    **Degeneracy tolerance.** Sets whose centred singular values fall at or below
    ``RANK_RTOL = 1e-10`` of the largest are flat; the system is undetermined when its
    second-smallest singular value is at or below ``RANK_RTOL`` of the largest.

    **Cost.** ``O(n d⁵)``: the ``nd × (d+1)²`` system, its QR and one small SVD.

    References
    ----------
    .. [1] R. Hartley and A. Zisserman, Multiple View Geometry in Computer Vision, 2nd ed.,
       §4.1-4.4 (DLT and normalisation), Cambridge University Press, 2004.
    .. [2] R. Hartley, "In defense of the eight-point algorithm", IEEE TPAMI 19(6),
       580-593, 1997.
    .. [3] J. Zaragoza, T.-J. Chin, M. S. Brown and D. Suter, "As-projective-as-possible
       image stitching with moving DLT", CVPR 2013 (the weighted DLT).

    Examples
    --------
    >>> import numpy as np
    >>> from algorithms.alignment import homography
    >>> x = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    >>> y = np.array([[0.0, 0.0], [0.5, 0.0], [0.5, 0.5], [0.0, 1.0]])   # (x, y) / (x + 1)
    >>> res = homography(x, y)
    >>> np.round(res.transform, 12) + 0.0
    array([[1., 0., 0.],
           [0., 1., 0.],
           [1., 0., 1.]])
    """
    pairs = prepare(source, target, weights, min_dim=1, minimum=_minimum)
    d = pairs.d
    for name in ("source", "target"):
        span = pairs.span(name, RANK_RTOL)
        if span < d:
            raise flat_error(name, span, d, f"a projective map needs d + 2 = {d + 2} points "
                             "in general position", weighted=pairs.weighted)

    eye = np.eye(d)
    kx = math.sqrt(d / pairs.mean_square(pairs.xc))
    ky = math.sqrt(d / pairs.mean_square(pairs.yc))
    xn, yn = pairs.xc * kx, pairs.yc * ky
    rows = pairs.sqrt_p()
    vec, sv = _null_vector(_dlt_matrix(xn, yn, rows))
    if not sv[-2] > RANK_RTOL * sv[0]:
        raise _position_error(pairs, xn, yn, rows, "more than one projective map fits")
    normalised = vec.reshape(d + 1, d + 1)
    if numerical_rank(np.linalg.svd(normalised, compute_uv=False), RANK_RTOL) < d + 1:
        raise _position_error(pairs, xn, yn, rows, "the best-fitting projective map is "
                              "singular")
    p = homogeneous(eye / ky, pairs.y_mean) @ normalised @ homogeneous(kx * eye,
                                                                        -kx * pairs.x_mean)
    p = _scaled(p)

    forward = _transfer(p, pairs.source, pairs.target, pairs, "source")
    backward: FloatArray | None = None
    if symmetric:  # inv of float64 is float64 (its stubs say any floating)
        inverse = cast(FloatArray, np.linalg.inv(p))
        backward = _transfer(inverse, pairs.target, pairs.source, pairs, "target")
    return HomographyResult(
        transform=p,
        linear=p[:d, :d].copy(),
        translation=p[:d, d].copy(),
        perspective=p[d, :d].copy(),
        rmse=pairs.rmse(forward, backward),
    )


def _minimum(d: int) -> tuple[int, str]:
    return d + 2, f"d + 2 = {d + 2} in general position for a projective map of {d}-D"


def _dlt_matrix(xn: FloatArray, yn: FloatArray, rows: FloatArray) -> FloatArray:
    """The ``(n d) × (d+1)²`` DLT system, the ``d`` rows of pair ``i`` scaled by ``rows[i]``."""
    n, d = xn.shape
    h = np.c_[xn, np.ones(n)] * rows[:, None]
    a = np.zeros((n, d, d + 1, d + 1))
    j = np.arange(d)
    a[:, j, j, :] = h[:, None, :]
    a[:, :, d, :] = -yn[:, :, None] * h[:, None, :]
    return a.reshape(n * d, (d + 1) ** 2)


def _null_vector(a: FloatArray) -> tuple[FloatArray, FloatArray]:
    """The right singular vector of the smallest singular value, and all ``(d+1)²``
    singular values (zeros appended when there are fewer rows than columns)."""
    k = a.shape[1]
    if a.shape[0] > k:  # the (d+1)² square R factor (numpy's stubs type it as QRResult)
        a = np.asarray(np.linalg.qr(a, mode="r"))
    _, s, vt = np.linalg.svd(a, full_matrices=True)
    return vt[-1], np.concatenate((s, np.zeros(k - s.size)))


def _position_error(
    pairs: Pairs, xn: FloatArray, yn: FloatArray, rows: FloatArray, why: str
) -> DegenerateInputError:
    """Name the set that is not in general position (error path only): a set is to blame
    when even the identity map of it onto itself is not the only projective fit."""
    d = pairs.d
    weighted = " (counting only points with positive weight)" if pairs.weighted else ""
    for name, pts in (("source", xn), ("target", yn)):
        _, sv = _null_vector(_dlt_matrix(pts, pts, rows))
        if not sv[-2] > RANK_RTOL * sv[0]:
            return DegenerateInputError(
                f"Expected `{name}` to hold points in general position{weighted} (with "
                f"d + 2 = {d + 2} points: no {d + 1} of them on one hyperplane), got a "
                f"configuration that leaves the projective map undetermined: {why}.",
                field=name,
            )
    return DegenerateInputError(
        f"Expected `source` and `target` to be related by an invertible projective map, got "
        f"pairs for which {why}.",
        field=None,
    )


def _scaled(p: FloatArray) -> FloatArray:
    """``P / P[d, d]``, or ``P / ±|P|_F`` when that entry vanishes (see ``transform``)."""
    corner: np.float64 = p[-1, -1]
    norm = float(np.linalg.norm(p))
    if abs(corner) > RANK_RTOL * norm:
        return p / corner
    p = p / norm
    return p if p.flat[int(np.argmax(np.abs(p)))] > 0 else -p


def _transfer(
    p: FloatArray, frm: FloatArray, to: FloatArray, pairs: Pairs, name: str
) -> FloatArray:
    """``dehom(P [x; 1]) - y`` for every pair; zero for pairs of weight zero."""
    d = frm.shape[1]
    h = frm @ p[:d, :d].T + p[:d, d]
    w = frm @ p[d, :d] + p[d, d]
    used = np.ones(len(w), dtype=bool) if pairs.p is None else pairs.p > 0
    # |w| at rounding level of its terms: the point lies on the plane sent to infinity.
    size = np.abs(frm) @ np.abs(p[d, :d]) + abs(p[d, d])
    bad = used & ~(np.abs(w) > RANK_RTOL * size)
    if bad.any():
        row = int(np.argmax(bad))
        raise DegenerateInputError(
            f"Expected the fitted projective map to send every point of `{name}` to a "
            f"finite point, got infinity for row {row}: the pairs do not fit one "
            "projective map.",
            field=None,
        )
    with np.errstate(divide="ignore", invalid="ignore"):
        resid = h / w[:, None] - to
    resid[~used] = 0.0
    return resid
