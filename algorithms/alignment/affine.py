"""Affine alignment with known correspondences: y = A x + b by linear least squares."""

from __future__ import annotations

from dataclasses import dataclass
from typing import cast

import numpy as np

from algorithms.core.errors import ConvergenceWarning, DegenerateInputError, warn
from algorithms.core.linalg import RANK_RTOL, homogeneous, numerical_rank
from algorithms.core.pairs import Pairs, flat_error, prepare
from algorithms.core.params import PointsLike, WeightsLike, validate_params
from algorithms.core.types import FloatArray

__all__ = ["AffineResult", "affine"]

#: Newton steps of the symmetric fit before it gives up (it typically needs under 20).
MAX_NEWTON = 50
#: The symmetric fit stops once a step is this small relative to ``A``.
STEP_RTOL = 1e-13


@dataclass(frozen=True, eq=False)
class AffineResult:
    """The affine map ``y ≈ A x + b`` that best aligns ``source`` to ``target``.

    Attributes
    ----------
    transform : (d+1, d+1) float array
        The homogeneous matrix ``[[A, b], [0, 1]]`` that maps source points onto target
        points.
    linear : (d, d) float array
        The linear part ``A``; its determinant may be negative (an affine map may mirror).
    translation : (d,) float array
        The translation ``b`` applied after ``A``.
    rmse : float
        The weighted root-mean-square residual ``sqrt(sum w_i |A x_i + b - y_i|^2 / sum
        w_i)``; with ``symmetric=True`` the root of the mean of that square and the inverse
        one, ``sum w_i |A^-1 (y_i - b) - x_i|^2 / sum w_i``.
    iterations : int
        Newton steps of the symmetric fit; 0 for the closed form (``symmetric=False``).
    converged : bool
        False only when the symmetric fit stopped at its step limit (a
        ``ConvergenceWarning`` is issued too); always True for the closed form.
    """

    transform: FloatArray
    linear: FloatArray
    translation: FloatArray
    rmse: float
    iterations: int
    converged: bool


@validate_params
def affine(
    source: PointsLike,
    target: PointsLike,
    *,
    weights: WeightsLike | None = None,
    symmetric: bool = False,
) -> AffineResult:
    r"""Affine alignment (linear least squares).

    The matrix A and translation b minimising Σ wᵢ‖A xᵢ + b − yᵢ‖² for paired points in any
    dimension: A = Ỹ X̃⁺ by least squares, b through the centroids.

    Row ``i`` of ``source`` corresponds to row ``i`` of ``target``. The model is
    ``y = A x + b`` with any ``d×d`` matrix ``A``:

    .. math::

        \min_{A,\ b}\ \sum_{i=1}^{n} w_i \lVert A x_i + b - y_i \rVert^2 .

    With weighted centroids :math:`\bar x, \bar y` and centred points stacked as the columns
    of :math:`\tilde X, \tilde Y` (each scaled by :math:`\sqrt{w_i}`), the solution is

    .. math::

        A = \tilde Y \tilde X^{+} = \tilde Y \tilde X^\mathsf{T}
            (\tilde X \tilde X^\mathsf{T})^{-1}, \qquad b = \bar y - A \bar x,

    computed by :func:`numpy.linalg.lstsq` on :math:`\tilde X^\mathsf{T} A^\mathsf{T} =
    \tilde Y^\mathsf{T}` (an SVD of the ``n×d`` data), never by forming the inverse.

    Parameters
    ----------
    source : (n, d) float array
        The points to move, any ``d >= 1``, at least ``d + 1`` of them affinely independent.
    target : (n, d) float array
        Where they should land, paired row by row with ``source``.
    weights : (n,) float array, optional
        Non-negative per-pair weights with a positive sum; all equal when omitted. Pairs of
        weight zero are ignored, but the pairs left must still span ``d`` dimensions.
    symmetric : bool, default False
        Minimise the forward and the inverse residuals together,
        :math:`\sum_i w_i (\lVert A x_i + b - y_i \rVert^2
        + \lVert A^{-1}(y_i - b) - x_i \rVert^2)`; iterative, see Notes.

    Returns
    -------
    AffineResult
        ``transform``, ``linear``, ``translation``, ``rmse``, ``iterations`` and
        ``converged``.

    Raises
    ------
    InvalidInputError
        Fewer than ``d + 1`` points; ``source`` and ``target`` shapes differ
        (``field="target"``); NaN/Inf; malformed ``weights`` (``field="weights"``);
        ``symmetric`` not a bool.
    DegenerateInputError
        ``source`` (counting only pairs of positive weight) spans fewer than ``d``
        dimensions after centring: coincident, collinear or coplanar points leave ``A``
        undetermined. With ``symmetric=True`` also when ``target`` does, or when the forward
        solution is singular (no inverse to start from); ``field=None`` for the latter.

    Notes
    -----
    **Least squares without the normal equations.** The minimiser is often written
    :math:`A = \tilde Y \tilde X^\mathsf{T} (\tilde X \tilde X^\mathsf{T})^{-1}` on the
    centred points; forming :math:`\tilde X \tilde X^\mathsf{T}` squares the condition
    number, so the same minimiser is computed by ``lstsq`` (the pseudo-inverse of
    :math:`\tilde X`) instead. Centring first keeps the numbers small for data far from the
    origin and separates the translation exactly.

    **Degeneracy tolerance.** Singular values of the weighted, centred source at or below
    ``RANK_RTOL = 1e-10`` times the largest count as zero (this is also ``lstsq``'s
    ``rcond``). Exactly coplanar data is flagged even 10⁴ extents away from the origin.
    ``target`` may be flat for the one-sided fit (``A`` is then singular: a projection).

    **Symmetric.** The inverse residual of pair ``i`` is :math:`-A^{-1} e_i`, where
    :math:`e_i = A x_i + b - y_i`, so the best ``b`` still passes through the centroids;
    the objective in ``A`` is no longer quadratic. With :math:`B = A^{-1}` and the weighted
    moments :math:`S_{xx} = \sum_i p_i \tilde x_i \tilde x_i^\mathsf{T}`, :math:`S_{yy}`,
    :math:`S_{yx} = \sum_i p_i \tilde y_i \tilde x_i^\mathsf{T}` it reads

    .. math::

        \operatorname{tr}(A S_{xx} A^\mathsf{T}) - 2 \operatorname{tr}(A S_{yx}^\mathsf{T})
        + \operatorname{tr}(B S_{yy} B^\mathsf{T}) - 2 \operatorname{tr}(B S_{yx})
        + \operatorname{tr} S_{xx} + \operatorname{tr} S_{yy},

    so after one ``O(n d²)`` pass the points are not needed again. It is minimised by
    Newton's method with the exact gradient and Hessian (from
    :math:`\partial B = -B\,\partial A\,B`), damped where the Hessian is not positive
    definite or a step does not descend, from the one-sided solution; it stops when a step
    is below ``STEP_RTOL = 1e-13`` of ``A`` (quadratic convergence near the minimum:
    typically under 20 steps, and none for noise-free data). The answer is the local
    minimum nearest to that start.

    **Reflections.** No rotation is estimated, so there is no ``allow_reflection``: ``A`` is
    whatever fits best, mirror images included. Use ``similarity`` or ``rigid`` for proper
    motions.

    **Cost.** ``O(n d²)`` for the closed form (one thin SVD of the ``n×d`` centred source).
    The symmetric fit adds the moments, ``O(n d²)``, and a few Newton steps of ``O(d⁶)``.

    References
    ----------
    .. [1] S. Schaefer, T. McPhail and J. Warren, "Image deformation using moving least
       squares", ACM Transactions on Graphics 25(3), 533-540, 2006 (the affine case).
    .. [2] G. H. Golub and C. F. Van Loan, Matrix Computations, 4th ed., §5.5 (least squares
       by the SVD), 2013.

    Examples
    --------
    >>> import numpy as np
    >>> from algorithms.alignment import affine
    >>> x = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    >>> y = x @ np.array([[2.0, 0.0], [1.0, 3.0]]).T + [1.0, -1.0]   # shear and stretch
    >>> res = affine(x, y)
    >>> np.round(res.linear, 12) + 0.0
    array([[2., 0.],
           [1., 3.]])
    >>> np.round(res.translation, 12) + 0.0
    array([ 1., -1.])
    """
    pairs = prepare(source, target, weights, min_dim=1, minimum=_minimum)
    d = pairs.d

    sp = pairs.sqrt_p()[:, None]
    xs, ys = pairs.xc * sp, pairs.yc * sp
    solution, _, rank, _ = np.linalg.lstsq(xs, ys, rcond=RANK_RTOL)
    if rank < d:
        raise flat_error("source", int(rank), d, "the affine map is undetermined",
                         weighted=pairs.weighted)
    linear = np.ascontiguousarray(solution.T)

    iterations, converged = 0, True
    if symmetric:
        linear, iterations, converged = _symmetric_fit(pairs, xs, ys, linear)
    translation = pairs.y_mean - linear @ pairs.x_mean
    return AffineResult(
        transform=homogeneous(linear, translation),
        linear=linear,
        translation=translation,
        rmse=pairs.linear_rmse(linear, symmetric=symmetric),
        iterations=iterations,
        converged=converged,
    )


def _minimum(d: int) -> tuple[int, str]:
    return d + 1, f"d + 1 = {d + 1} affinely independent points for an affine map of {d}-D"


def _symmetric_fit(
    pairs: Pairs, xs: FloatArray, ys: FloatArray, start: FloatArray
) -> tuple[FloatArray, int, bool]:
    """Damped Newton on the symmetric objective from ``start`` (see Notes of :func:`affine`).

    With ``B = A⁻¹`` and the weighted moments ``Sxx = Σ pᵢ x̃ᵢx̃ᵢᵀ``, ``Syy``, ``Syx = Σ pᵢ
    ỹᵢx̃ᵢᵀ``, the objective is ``tr(A Sxx Aᵀ) − 2 tr(A Syxᵀ) + tr(Syy) + tr(B Syy Bᵀ) −
    2 tr(B Syx) + tr(Sxx)``: the points enter only through the moments.
    """
    d = pairs.d
    why = "the affine map has no inverse, which `symmetric=true` needs"
    span = pairs.span("target", RANK_RTOL)
    if span < d:
        raise flat_error("target", span, d, why, weighted=pairs.weighted)
    rank = numerical_rank(np.linalg.svd(start, compute_uv=False), RANK_RTOL)
    if rank < d:
        raise DegenerateInputError(
            f"Expected the least-squares affine map to be invertible, got rank {rank} of "
            f"{d}: `source` and `target` are uncorrelated along some direction and {why}.",
            field=None,
        )
    moments = _Moments(xs.T @ xs, ys.T @ ys, ys.T @ xs)
    a = start
    f = moments.objective(a)
    for iteration in range(1, MAX_NEWTON + 1):
        b = cast(FloatArray, np.linalg.inv(a))  # float64 in (the stubs say any floating)
        g = moments.gradient(a, b).ravel()
        h = moments.hessian(b)
        step, f_new = _damped_step(moments, a, f, g, h)
        if step is None:  # no descent left at rounding level: a minimum
            return a, iteration - 1, True
        a = a + step.reshape(d, d)
        f = f_new
        if np.linalg.norm(step) <= STEP_RTOL * np.linalg.norm(a):
            return a, iteration, True
    warn(
        f"The symmetric affine fit stopped after {MAX_NEWTON} Newton steps without meeting "
        "its tolerance; the result is the best map found.",
        ConvergenceWarning,
    )
    return a, MAX_NEWTON, False


@dataclass(frozen=True)
class _Moments:
    sxx: FloatArray
    syy: FloatArray
    syx: FloatArray

    def objective(self, a: FloatArray) -> float:
        b = np.linalg.inv(a)
        forward = np.vdot(a @ self.sxx, a) - 2.0 * np.vdot(a, self.syx) + np.trace(self.syy)
        inverse = np.vdot(b @ self.syy, b) - 2.0 * np.vdot(b, self.syx.T) + np.trace(self.sxx)
        return float(forward + inverse)

    def gradient(self, a: FloatArray, b: FloatArray) -> FloatArray:
        # d/dA of the inverse part: -Bᵀ G Bᵀ with G = 2 (B Syy - Sxy), from dB = -B dA B.
        g_b = 2.0 * (b @ self.syy - self.syx.T)
        return 2.0 * (a @ self.sxx - self.syx) - b.T @ g_b @ b.T

    def hessian(self, b: FloatArray) -> FloatArray:
        """The ``d² × d²`` Hessian, column ``(k, l)`` the derivative along ``E = e_k e_lᵀ``."""
        d = b.shape[0]
        g_b = 2.0 * (b @ self.syy - self.syx.T)
        cols = np.empty((d * d, d * d))
        for k in range(d):
            for m in range(d):
                e = np.zeros((d, d))
                e[k, m] = 1.0
                db = -b @ e @ b
                dg = 2.0 * db @ self.syy
                d_inv = db.T @ g_b @ b.T + b.T @ dg @ b.T + b.T @ g_b @ db.T
                cols[:, k * d + m] = (2.0 * e @ self.sxx - d_inv).ravel()
        return 0.5 * (cols + cols.T)


def _damped_step(
    moments: _Moments, a: FloatArray, f: float, g: FloatArray, h: FloatArray
) -> tuple[FloatArray | None, float]:
    """A Newton step, damped (``H + μI``) until ``H`` is positive definite and the step
    descends; ``None`` when no step descends by more than rounding."""
    d = a.shape[0]
    slack = 1e-14 * abs(f)
    scale = float(np.abs(h).max()) or 1.0
    mu = 0.0
    while mu <= 1e12 * scale:
        try:
            chol = np.linalg.cholesky(h + mu * np.eye(h.shape[0]))
        except np.linalg.LinAlgError:
            mu = max(10.0 * mu, 1e-10 * scale)
            continue
        step = -np.linalg.solve(chol.T, np.linalg.solve(chol, g))
        trial = a + step.reshape(d, d)
        if np.linalg.cond(trial) < 1e12:
            f_new = moments.objective(trial)
            if f_new <= f + slack:
                return step, f_new
        mu = max(10.0 * mu, 1e-10 * scale)
    return None, f
