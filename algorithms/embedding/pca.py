r"""Principal component analysis: the orthogonal projection that keeps the most variance."""

from __future__ import annotations

import contextlib
from dataclasses import dataclass
from typing import Annotated, Any

import numpy as np
import scipy.linalg as la

from algorithms.core.params import Ge, PointsLike, validate_params
from algorithms.core.threads import single_blas_thread
from algorithms.core.types import FloatArray
from algorithms.core.validation import as_int, as_points
from algorithms.embedding._quality import fix_signs, trustworthiness

__all__ = ["check_pca", "PCAResult", "pca", "check_linear_components"]

#: Data of at most this many cells is decomposed with BLAS on one thread (the thread
#: policy of :mod:`algorithms.core.threads`: threads only cost there).
_ONE_THREAD_CELLS = 1 << 18
#: The separation of the kept eigenvalues, relative to the largest, that lets the
#: scatter matrix's eigenvectors stand for the SVD (:func:`_principal_axes`).
_SEPARATED = 1e-4


@dataclass(frozen=True, eq=False)
class PCAResult:
    """The data projected on its ``k`` principal axes.

    Attributes
    ----------
    embedding : (n, k) float array
        The principal scores :math:`(X - \\bar x) V_k`, one row per point.
    components : (k, D) float array
        The principal axes (unit rows, decreasing variance), each one's entry of largest
        magnitude positive (scikit-learn's convention).
    eigenvalues : (k,) float array
        The variance along each axis, :math:`\\sigma_c^2 / (n - 1)` (scikit-learn's
        ``explained_variance_``): the eigenvalues of the covariance matrix.
    explained_variance_ratio : (k,) float array
        Each eigenvalue over the total variance.
    singular_values : (k,) float array
        The singular values :math:`\\sigma_c` of the centred data.
    mean : (D,) float array
        The mean point :math:`\\bar x` that was subtracted.
    trustworthiness : float
        Trustworthiness of the embedding (1: every embedded neighbourhood is a true one).
    """

    embedding: FloatArray
    components: FloatArray
    eigenvalues: FloatArray
    explained_variance_ratio: FloatArray
    singular_values: FloatArray
    mean: FloatArray
    trustworthiness: float


def check_linear_components(n_components: Any, n: int, d: int) -> int:
    """``n_components`` of a linear map of ``n`` points in ``d`` dimensions: ``1 <= k <= d``
    (and ``<= n``)."""
    limit = min(n, d)
    reason = "the dimension of `points`" if d <= n else "the number of `points`"
    return as_int(n_components, name="n_components", minimum=1, maximum=limit, reason=reason)


def check_pca(points: Any, n_components: Any) -> tuple[FloatArray, int]:
    """Check the inputs of :func:`pca`: at least 2 points, ``n_components`` at most their
    dimension and their number (:func:`check_linear_components`). Returns both."""
    x = as_points(points, name="points", min_points=2)
    return x, check_linear_components(n_components, *x.shape)


def _principal_axes(xc: FloatArray, k: int) -> tuple[FloatArray, FloatArray]:
    r"""The singular values of the centred ``xc`` (every one, decreasing) and at least its
    ``k`` leading right singular vectors (rows).

    Tall data (``n >= 4 D``) takes the eigenvectors of the ``D × D`` scatter matrix
    :math:`\tilde X^\mathsf{T} \tilde X`: ``n D²`` operations instead of the SVD's (with
    LAPACK's overheads, 3-5× faster on 1,500 × 64). Squaring halves the relative accuracy
    of small singular values, so it is kept only when the kept eigenvalues are separated
    (:math:`\sigma_k^2 - \sigma_{k+1}^2 \ge 10^{-4} \sigma_1^2`, which bounds the error
    of the axes near :math:`10^4` ulps); else, and for wide data, the thin SVD.
    """
    n, d = xc.shape
    if n >= 4 * d:
        lam, v = la.eigh(xc.T @ xc, check_finite=False, driver="evr")
        lam, v = lam[::-1], v[:, ::-1]
        top = float(lam[0])
        after = float(lam[k]) if k < d else 0.0
        if top > 0 and float(lam[k - 1]) - after >= _SEPARATED * top:
            s = np.sqrt(np.maximum(lam, 0.0))
            s[:k] = np.sqrt(lam[:k])
            return s, np.ascontiguousarray(v.T)
    _, s, vt = la.svd(xc, full_matrices=False, check_finite=False, lapack_driver="gesdd")
    return s, vt


@validate_params
def pca(
    points: PointsLike,
    *,
    n_components: Annotated[int, Ge(1)] = 2,
    quality_neighbors: Annotated[int, Ge(1)] = 5,
) -> PCAResult:
    r"""Principal component analysis.

    Projects the centred data on its k principal axes (thin SVD): the orthogonal projection keeping
    the most variance. Reports the axes, the variance along each (eigenvalues), their share, and
    trustworthiness; signs fixed (each axis's largest entry positive).

    With :math:`\tilde X = X - \bar x = U \Sigma V^\mathsf{T}` (thin SVD), the embedding is
    :math:`\tilde X V_k = U_k \Sigma_k`, the projection on the ``k`` right singular vectors
    of largest singular value: of all orthogonal projections to ``k`` dimensions it keeps
    the most variance (equivalently, the sum of squared projection distances is least).

    Parameters
    ----------
    points : (n, D) float array
        The data, one row per point; at least 2 points.
    n_components : int, default 2
        The dimension ``k`` of the embedding, ``1 <= k <= min(n, D)``.
    quality_neighbors : int, default 5
        The neighbourhood size of the reported trustworthiness (clipped to
        ``(n - 1) // 2`` when larger).

    Returns
    -------
    PCAResult
        ``embedding``, ``components``, ``eigenvalues``, ``explained_variance_ratio``,
        ``singular_values``, ``mean``, ``trustworthiness``.

    Raises
    ------
    InvalidInputError
        Bad ``points`` (fewer than 2, NaN/Inf), ``n_components`` outside ``[1, min(n, D)]``.

    Notes
    -----
    Classical MDS of the Euclidean distances gives the
    same embedding (:func:`~algorithms.embedding.mds`). Signs: each axis's entry of largest
    magnitude is positive, as in ``sklearn.decomposition.PCA`` (scikit-learn ≥ 1.5), so the
    scores equal scikit-learn's.

    Cost: one thin SVD, :math:`O(n D \min(n, D))`; for ``n >= 4 D`` the eigenvectors of
    the ``D × D`` scatter matrix instead when the kept eigenvalues are well separated
    (the same axes to about 1e-12), :math:`O(n D^2)` with a smaller constant.

    References
    ----------
    .. [1] K. Pearson, "On lines and planes of closest fit to systems of points in space",
       Philosophical Magazine 2 (1901).

    Examples
    --------
    >>> import numpy as np
    >>> x = [[0, 0], [2, 2], [4, 4], [1, 3], [3, 1]]
    >>> res = pca(x, n_components=1)
    >>> np.round(res.components, 6).tolist()
    [[0.707107, 0.707107]]
    >>> np.round(res.embedding.ravel() ** 2, 6).tolist()
    [8.0, 0.0, 8.0, 0.0, 0.0]
    """
    x, k = check_pca(points, n_components)
    n, d = x.shape
    mean = x.mean(axis=0)
    xc = x - mean
    with single_blas_thread() if x.size <= _ONE_THREAD_CELLS else contextlib.nullcontext():
        s, vt = _principal_axes(xc, k)
    comps = fix_signs(vt[:k].T).T
    y = xc @ comps.T
    var = s * s / (n - 1)
    total = float(var.sum())
    ratio = var[:k] / total if total > 0 else np.zeros(k)
    return PCAResult(
        embedding=np.ascontiguousarray(y),
        components=np.ascontiguousarray(comps),
        eigenvalues=var[:k].copy(),
        explained_variance_ratio=ratio,
        singular_values=s[:k].copy(),
        mean=mean,
        trustworthiness=trustworthiness(x, y, n_neighbors=quality_neighbors),
    )
