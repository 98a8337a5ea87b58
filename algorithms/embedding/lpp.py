r"""Locality preserving projections: the linear map closest to Laplacian eigenmaps."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp

from algorithms.core.errors import DegenerateInputError
from algorithms.core.laplacian import laplacian as graph_laplacian
from algorithms.core.types import FloatArray
from algorithms.core.validation import as_choice, as_points
from algorithms.embedding._quality import fix_signs, trustworthiness
from algorithms.embedding.laplacian_eigenmaps import LAPLACIANS, similarity_graph
from algorithms.embedding.pca import check_linear_components

__all__ = ["LPPResult", "lpp", "lpp_from_weights"]


@dataclass(frozen=True, eq=False)
class LPPResult:
    """A linear projection that keeps neighbours near.

    Attributes
    ----------
    embedding : (n, k) float array
        :math:`(X - \\mu) A`, one row per point.
    components : (k, D) float array
        The projection :math:`A^\\mathsf{T}`: row ``c`` is the generalized eigenvector of the
        ``c``-th smallest eigenvalue, its entry of largest magnitude positive. New points
        project as ``(x - mean) @ components.T``.
    eigenvalues : (k,) float array
        The generalized eigenvalues, increasing.
    mean : (D,) float array
        The centre :math:`\\mu` subtracted (degree-weighted for ``"random_walk"``).
    trustworthiness : float
        Trustworthiness of the embedding (1: every embedded neighbourhood is a true one).
    """

    embedding: FloatArray
    components: FloatArray
    eigenvalues: FloatArray
    mean: FloatArray
    trustworthiness: float


def lpp_from_weights(x: FloatArray, w: Any, k: int, kind: str = "random_walk"
                     ) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Components ``(k, D)``, eigenvalues and centre of LPP for points ``x`` and symmetric
    weights ``w`` (see :func:`lpp`)."""
    as_choice(kind, LAPLACIANS, name="laplacian")
    w = sp.csr_array(w, dtype=np.float64)
    d = np.asarray(w.sum(axis=1)).ravel()
    lap = graph_laplacian(w)
    if kind == "random_walk":
        mu = (d @ x) / d.sum()
        xc = x - mu
        a = xc.T @ (lap @ xc)
        b = xc.T @ (d[:, None] * xc)
    else:
        mu = x.mean(axis=0)
        xc = x - mu
        if kind == "symmetric":
            s = 1.0 / np.sqrt(d)
            a = xc.T @ (s[:, None] * (lap @ (s[:, None] * xc)))
        else:
            a = xc.T @ (lap @ xc)
        b = xc.T @ xc
    a, b = 0.5 * (a + a.T), 0.5 * (b + b.T)
    ev = la.eigvalsh(b)
    dim = x.shape[1]
    rank = int(np.count_nonzero(ev > ev[-1] * dim * np.finfo(float).eps * 10))
    if rank < dim:
        raise DegenerateInputError(
            f"Expected `points` to span all of their {dim} dimensions (LPP's constraint matrix "
            f"XᵀDX must be invertible), got rank {rank}: project them first (e.g. with "
            f"embedding.pca, n_components={rank}).", field="points")
    vals, vecs = la.eigh(a, b, subset_by_index=[0, k - 1], check_finite=False)
    comps = fix_signs(vecs).T
    return np.ascontiguousarray(comps), np.maximum(vals, 0.0), mu


def lpp(points: Any, *, n_components: int = 2, neighbors: str = "knn",
        n_neighbors: int | None = None, radius: float | None = None,
        weighting: str = "uniform", sigma: float | None = None,
        laplacian: str = "random_walk", quality_neighbors: int = 5) -> LPPResult:
    r"""Locality preserving projections (He and Niyogi 2003).

    Laplacian eigenmaps restricted to linear maps :math:`y = A^\mathsf{T}(x - \mu)`: with
    the centred data :math:`\tilde X` (rows are points), the graph's :math:`W`, :math:`D`,
    :math:`L = D - W`, the columns of :math:`A` are the generalized eigenvectors of the
    ``k`` smallest eigenvalues of

    * ``"random_walk"`` (default; the paper): :math:`\tilde X^\mathsf{T} L \tilde X a =
      \lambda \tilde X^\mathsf{T} D \tilde X a`, centred at the degree-weighted mean (so
      the constant map is excluded, as the trivial vector in Laplacian eigenmaps);
    * ``"symmetric"`` (the seed document): :math:`\tilde X^\mathsf{T} D^{-1/2} L D^{-1/2}
      \tilde X a = \lambda \tilde X^\mathsf{T} \tilde X a`, i.e. :math:`\min
      \operatorname{tr}(Y^\mathsf{T} D^{-1/2} L D^{-1/2} Y)` subject to
      :math:`Y^\mathsf{T} Y = I`, centred at the mean;
    * ``"unnormalized"``: :math:`\tilde X^\mathsf{T} L \tilde X a = \lambda
      \tilde X^\mathsf{T} \tilde X a`, centred at the mean.

    Parameters
    ----------
    points : (n, D) float array
        Spanning all ``D`` dimensions (else reduce them first, e.g. by PCA).
    n_components : int, default 2
        The dimension ``k``, ``1 <= k <= D``.
    neighbors, n_neighbors, radius, weighting, sigma
        The graph, as in :func:`~algorithms.embedding.laplacian_eigenmaps` (default
        ``n_neighbors = max(n // 10, 1)``, uniform weights).
    laplacian : {"random_walk", "symmetric", "unnormalized"}, default "random_walk"
        The normalisation above.
    quality_neighbors : int, default 5
        The neighbourhood size of the reported trustworthiness.

    Returns
    -------
    LPPResult
        ``embedding``, ``components``, ``eigenvalues``, ``mean``, ``trustworthiness``.

    Raises
    ------
    InvalidInputError
        Bad ``points``; ``n_components`` outside ``[1, min(n, D)]``; ``n_neighbors``
        outside ``[1, n - 1]``; an unknown option.
    DegenerateInputError
        Points that do not span their ``D`` dimensions; a disconnected graph (the message
        says into how many components).

    Notes
    -----
    **The seed document** sets the problem up as :math:`\min A X L_\mathrm{sym} X^\mathsf{T}
    A^\mathsf{T}` subject to :math:`A X X^\mathsf{T} A^\mathsf{T} = I` and notes "some take
    :math:`V = X D^{-1/2}` as X directly", which gives the paper's
    :math:`X L X^\mathsf{T} a = \lambda X D X^\mathsf{T} a`. The default is the paper's
    form, the linear counterpart of the default of ``laplacian_eigenmaps``: when the points
    are affinely independent (``D = n - 1``) every function on them is linear and the two
    methods coincide (tested). ``laplacian="symmetric"`` is the seed's. The seed also
    remarks that the linearity constraint weakens the graph embedding; LPP's gain is a map
    that applies to new points (``components``, ``mean``).

    There is no reference implementation in scikit-learn; the tests check the generalized
    eigen-equations, the reduction to Laplacian eigenmaps above, and invariance under
    rotations and translations of the input.

    References
    ----------
    .. [1] X. He, P. Niyogi, "Locality preserving projections", NIPS 16 (2003).
    .. [2] The seed document, section "Laplacian principal component analysis".

    Examples
    --------
    >>> import numpy as np
    >>> rng = np.random.default_rng(0)
    >>> x = np.c_[np.linspace(0, 10, 40), rng.normal(0, 0.1, 40), rng.normal(0, 0.1, 40)]
    >>> res = lpp(x, n_components=2, n_neighbors=3)
    >>> bool(np.allclose(res.embedding, (x - res.mean) @ res.components.T))
    True
    """
    x = as_points(points, name="points", min_points=3)
    n, dim = x.shape
    k = check_linear_components(n_components, n, dim)
    as_choice(laplacian, LAPLACIANS, name="laplacian")
    w = similarity_graph(x, neighbors, n_neighbors, radius, weighting, sigma,
                         method="locality preserving projections")
    comps, vals, mu = lpp_from_weights(x, w, k, laplacian)
    y = (x - mu) @ comps.T
    return LPPResult(
        embedding=np.ascontiguousarray(y),
        components=comps,
        eigenvalues=vals,
        mean=mu,
        trustworthiness=trustworthiness(x, y, n_neighbors=quality_neighbors),
    )
