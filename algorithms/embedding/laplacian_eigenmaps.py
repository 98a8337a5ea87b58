r"""Laplacian eigenmaps: the bottom non-trivial eigenvectors of a neighbourhood graph's
Laplacian."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
from scipy.sparse.linalg import eigsh

from algorithms.core.graphs import neighbour_graph
from algorithms.core.laplacian import laplacian as graph_laplacian
from algorithms.core.types import FloatArray
from algorithms.core.validation import as_choice, as_int, as_points
from algorithms.embedding._quality import fix_signs, trustworthiness

__all__ = ["LaplacianEigenmapsResult", "laplacian_eigenmaps", "LAPLACIANS",
           "spectral_embedding", "similarity_graph"]

#: The accepted values of ``laplacian``.
LAPLACIANS = ("random_walk", "symmetric", "unnormalized")

#: Up to this many points the eigenproblem is solved densely (LAPACK); above, by
#: shift-invert Lanczos (ARPACK) on the sparse Laplacian.
_DENSE_BELOW = 1000


def similarity_graph(x: FloatArray, neighbors: str, n_neighbors: Any, radius: float | None,
                     weighting: str, sigma: float | None, *, method: str) -> sp.csr_array:
    """The connected, weighted neighbourhood graph of the spectral embeddings (LE, LPP).

    :func:`algorithms.core.graphs.neighbour_graph` with ``connected=method``; ``n_neighbors``
    omitted is scikit-learn's ``SpectralEmbedding`` default, ``max(n // 10, 1)``.
    """
    if n_neighbors is None:
        n_neighbors = max(x.shape[0] // 10, 1)
    return neighbour_graph(x, neighbors=neighbors, n_neighbors=n_neighbors, radius=radius,
                           weighting=weighting, sigma=sigma, connected=method)


@dataclass(frozen=True, eq=False)
class LaplacianEigenmapsResult:
    """The bottom non-trivial eigenvectors of a neighbourhood graph's Laplacian.

    Attributes
    ----------
    embedding : (n, k) float array
        Column ``c`` is the eigenvector of the ``(c + 2)``-th smallest eigenvalue (the
        first, trivial one skipped), its entry of largest magnitude positive. With
        ``laplacian="random_walk"``: :math:`L v = \\lambda D v`, :math:`v^\\mathsf{T} D v = 1`.
    eigenvalues : (k,) float array
        The matching eigenvalues, increasing (in :math:`[0, 2]` for the normalised
        Laplacians).
    trustworthiness : float
        Trustworthiness of the embedding (1: every embedded neighbourhood is a true one).
    """

    embedding: FloatArray
    eigenvalues: FloatArray
    trustworthiness: float


def _smallest(m: sp.csr_array, count: int, scale: float) -> tuple[FloatArray, FloatArray]:
    """The ``count`` smallest eigenpairs of the symmetric PSD ``m`` (increasing)."""
    n = m.shape[0]
    if n <= _DENSE_BELOW or count >= n // 2:
        w, v = la.eigh(m.toarray(), subset_by_index=[0, count - 1], check_finite=False)
        return w, v
    v0 = np.ones(n) + 0.1 * np.cos(np.arange(n))  # deterministic start
    # shift-invert just below 0: the wanted eigenvalues are the ones nearest the shift
    w, v = eigsh(m.tocsc(), k=count, sigma=-1e-6 * scale, which="LM", v0=v0, tol=0.0)
    order = np.argsort(w)
    return w[order], v[:, order]


def spectral_embedding(w: Any, k: int, kind: str = "random_walk"
                       ) -> tuple[FloatArray, FloatArray]:
    """Bottom ``k`` non-trivial eigenvectors of the Laplacian of the connected weights ``w``.

    Returns the ``(n, k)`` vectors (signs fixed) and their eigenvalues; see
    :func:`laplacian_eigenmaps`.
    """
    as_choice(kind, LAPLACIANS, name="laplacian")
    w = sp.csr_array(w, dtype=np.float64)
    lap = graph_laplacian(w)
    d = np.asarray(w.sum(axis=1)).ravel()
    if kind == "unnormalized":
        vals, vecs = _smallest(lap, k + 1, float(d.max()))
    else:
        s = sp.diags_array(1.0 / np.sqrt(d), format="csr")
        sym = (s @ lap @ s).tocsr()
        sym = ((sym + sym.T) * 0.5).tocsr()
        vals, vecs = _smallest(sym, k + 1, 1.0)
        if kind == "random_walk":
            vecs = vecs / np.sqrt(d)[:, None]  # v = D^-1/2 y: L v = λ D v, vᵀDv = 1
    return fix_signs(vecs[:, 1:]), np.maximum(vals[1:], 0.0)


def laplacian_eigenmaps(points: Any, *, n_components: int = 2, neighbors: str = "knn",
                        n_neighbors: int | None = None, radius: float | None = None,
                        weighting: str = "uniform", sigma: float | None = None,
                        laplacian: str = "random_walk", quality_neighbors: int = 5
                        ) -> LaplacianEigenmapsResult:
    r"""Laplacian eigenmaps (Belkin and Niyogi 2003).

    On a neighbourhood graph with weights :math:`W`, degrees :math:`D` and Laplacian
    :math:`L = D - W`, the embedding minimises :math:`\sum_{ij} w_{ij} \lVert y_i - y_j
    \rVert^2 = \operatorname{tr}(Y^\mathsf{T} L Y)` under a normalisation, which the
    trivial constant solution is excluded from:

    * ``"random_walk"`` (default; the paper, scikit-learn): :math:`L v = \lambda D v`
      with :math:`v^\mathsf{T} D v = 1`, i.e. the eigenvectors of :math:`D^{-1} L`;
    * ``"symmetric"`` (the seed document): :math:`D^{-1/2} L D^{-1/2} y = \lambda y`,
      :math:`\lVert y \rVert = 1` (:math:`y = D^{1/2} v`);
    * ``"unnormalized"``: :math:`L y = \lambda y`, :math:`\lVert y \rVert = 1`.

    Parameters
    ----------
    points : (n, D) float array
    n_components : int, default 2
        The dimension ``k``, ``1 <= k <= n - 2``.
    neighbors : {"knn", "radius", "all"}, default "knn"
        The graph: each point's ``n_neighbors`` nearest (union), every pair within
        ``radius``, or every pair.
    n_neighbors : int, optional
        Default ``max(n // 10, 1)`` (scikit-learn's).
    radius : float, optional
        For ``neighbors="radius"``.
    weighting : {"uniform", "distance", "heat"}, default "uniform"
        Edge weights: 1, :math:`1/d` or :math:`e^{-d^2/2\sigma^2}`.
    sigma : float, optional
        Heat kernel width; default the mean edge length.
    laplacian : {"random_walk", "symmetric", "unnormalized"}, default "random_walk"
        The normalisation above.
    quality_neighbors : int, default 5
        The neighbourhood size of the reported trustworthiness.

    Returns
    -------
    LaplacianEigenmapsResult
        ``embedding``, ``eigenvalues``, ``trustworthiness``.

    Raises
    ------
    InvalidInputError
        Bad ``points``; ``n_neighbors`` outside ``[1, n - 1]`` (fewer points than
        neighbours); ``radius`` missing or not positive; ``n_components`` outside
        ``[1, n - 2]``; an unknown option.
    DegenerateInputError
        The graph is disconnected (the message says into how many components; each one
        would add a zero eigenvalue whose eigenvector only labels the components);
        coincident points with ``weighting="distance"``.

    Notes
    -----
    **The seed document** derives the method from :math:`\min y^\mathsf{T} D^{-1/2} L
    D^{-1/2} y`, substitutes :math:`v = D^{-1/2} y` to reach :math:`L v = \lambda D v`,
    and then turns ``v`` back into ``y`` ("also some take v directly as the answer"): that
    is ``laplacian="symmetric"``. The default returns ``v`` as the paper and
    scikit-learn do, so that the result agrees with ``sklearn.manifold.SpectralEmbedding``
    (affinity ``"precomputed"`` on the same weights) up to an orthogonal transform (exactly
    when the eigenvalues are distinct: same signs convention).

    Disconnected graphs are an error naming the component count; scikit-learn only warns.

    Cost: the graph (kd-tree), then a dense ``eigh`` up to 1,000 points, above that
    shift-invert Lanczos with one sparse LU of :math:`L + \epsilon I`.

    References
    ----------
    .. [1] M. Belkin, P. Niyogi, "Laplacian eigenmaps for dimensionality reduction and
       data representation", Neural Computation 15 (2003).
    .. [2] The seed document, section "graph Laplacian analysis".

    Examples
    --------
    >>> import numpy as np
    >>> x = np.c_[np.arange(6.0), np.zeros(6)]            # a path graph
    >>> res = laplacian_eigenmaps(x, n_components=1, n_neighbors=1)
    >>> bool(np.all(np.diff(res.embedding[:, 0]) < 0) or np.all(np.diff(res.embedding[:, 0]) > 0))
    True
    """
    x = as_points(points, name="points", min_points=3)
    n = x.shape[0]
    k = as_int(n_components, name="n_components", minimum=1, maximum=n - 2,
               reason=f"the number of `points` minus two ({n - 2})")
    as_choice(laplacian, LAPLACIANS, name="laplacian")
    w = similarity_graph(x, neighbors, n_neighbors, radius, weighting, sigma,
                         method="Laplacian eigenmaps")
    y, vals = spectral_embedding(w, k, laplacian)
    return LaplacianEigenmapsResult(
        embedding=np.ascontiguousarray(y),
        eigenvalues=vals,
        trustworthiness=trustworthiness(x, y, n_neighbors=quality_neighbors),
    )
