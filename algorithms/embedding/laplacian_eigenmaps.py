r"""Laplacian eigenmaps: the bottom non-trivial eigenvectors of a neighbourhood graph's
Laplacian."""

from __future__ import annotations

import typing
from dataclasses import dataclass
from typing import Annotated, Any, Literal

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
from scipy.sparse.linalg import LinearOperator, eigsh

from algorithms.core.graphs import (
    GraphWeighting,
    HeatWidth,
    Neighbors,
    NNeighbors,
    Radius,
    check_neighbour_graph,
    neighbour_graph,
)
from algorithms.core.laplacian import laplacian as graph_laplacian
from algorithms.core.linsolve import Factor
from algorithms.core.params import Ge, PointsLike, validate_params
from algorithms.core.types import FloatArray
from algorithms.core.validation import as_choice, as_int
from algorithms.embedding._quality import fix_signs, trustworthiness

__all__ = ["LaplacianEigenmapsResult", "laplacian_eigenmaps", "check_laplacian_eigenmaps",
           "Normalization", "LAPLACIANS", "spectral_embedding", "similarity_graph"]

Normalization = Literal["random_walk", "symmetric", "unnormalized"]
r"""How a spectral embedding normalises the graph Laplacian :math:`L = D - W`:
:math:`L v = \lambda D v`, :math:`D^{-1/2} L D^{-1/2} y = \lambda y` or
:math:`L y = \lambda y`."""
#: The accepted values of ``laplacian``.
LAPLACIANS: tuple[str, ...] = typing.get_args(Normalization)

#: Up to this many points the eigenproblem is solved densely (LAPACK); above, by
#: shift-invert Lanczos (ARPACK) on the sparse Laplacian.
_DENSE_BELOW = 1000


def similarity_graph(x: FloatArray, neighbors: str, n_neighbors: Any, radius: float | None,
                     weighting: str, sigma: float | None, *, method: str) -> sp.csr_array:
    """The connected, weighted neighbourhood graph of the spectral embeddings (LE, LPP).

    :func:`algorithms.core.graphs.neighbour_graph` with ``connected=method``, each point
    counted among its own ``n_neighbors`` as in scikit-learn's ``SpectralEmbedding``
    (``kneighbors_graph(..., include_self=True)``); ``n_neighbors`` omitted is
    ``max(n // 10, 2)``: scikit-learn's ``max(n // 10, 1)`` except below 20 points, where
    1 would count the point alone and leave no edge.
    """
    if n_neighbors is None:
        n_neighbors = max(x.shape[0] // 10, 2)
    return neighbour_graph(x, neighbors=neighbors, n_neighbors=n_neighbors, radius=radius,
                           weighting=weighting, sigma=sigma, connected=method,
                           include_self=True)


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
    # shift-invert just below 0: the wanted eigenvalues are the ones nearest the shift.
    # The shift must sit well below them, not only below 0: LLE's are tiny (20,000-point
    # swiss roll: 8e-12 and 3e-10 of the largest diagonal entry), and a shift of 1e-6
    # maps them all near 1e6, where Lanczos took 3,973 solves against 21 at 1e-12.
    # m - σI is positive definite there, so a sparse Cholesky with a fill-reducing
    # ordering factors it (ARPACK's own LU, with a column ordering, fills in 2-4× more:
    # 5,000-point LLE, 0.24 s against 0.05-0.09 s for the whole solve)
    sigma = -1e-12 * scale
    factor = Factor(m - sigma * sp.eye_array(n, format="csr"), name="the Laplacian")
    op = LinearOperator((n, n), matvec=factor.solve, dtype=np.float64)
    w, v = eigsh(m.tocsc(), k=count, sigma=sigma, which="LM", v0=v0, tol=0.0, OPinv=op)
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


def check_laplacian_eigenmaps(points: Any, n_components: Any, neighbors: str = "knn",
                              n_neighbors: Any = None, radius: Any = None
                              ) -> tuple[FloatArray, int]:
    """Check the inputs of :func:`laplacian_eigenmaps`: at least 3 points, neighbour-graph
    parameters that fit them, ``n_components`` at most their number minus 2 (the eigenvectors after
    the trivial one, and fewer than all). Returns the points and ``n_components``."""
    x = check_neighbour_graph(points, neighbors, n_neighbors, radius, min_points=3)
    k = as_int(n_components, name="n_components", minimum=1, maximum=x.shape[0] - 2,
               reason="the number of `points` minus two")
    return x, k


@validate_params
def laplacian_eigenmaps(
    points: PointsLike,
    *,
    n_components: Annotated[int, Ge(1)] = 2,
    neighbors: Neighbors = "knn",
    n_neighbors: NNeighbors | None = None,
    radius: Radius | None = None,
    weighting: GraphWeighting = "uniform",
    sigma: HeatWidth | None = None,
    laplacian: Normalization = "random_walk",
    quality_neighbors: Annotated[int, Ge(1)] = 5,
) -> LaplacianEigenmapsResult:
    r"""Laplacian eigenmaps (spectral embedding).

    The eigenvectors of the smallest non-trivial eigenvalues of the neighbourhood graph's Laplacian,
    Lv = λDv by default. A disconnected graph is an error that says into how many components it
    falls. Reports eigenvalues and trustworthiness.

    On a neighbourhood graph with weights :math:`W`, degrees :math:`D` and Laplacian
    :math:`L = D - W`, the embedding minimises :math:`\sum_{ij} w_{ij} \lVert y_i - y_j
    \rVert^2 = \operatorname{tr}(Y^\mathsf{T} L Y)` under a normalisation, which the
    trivial constant solution is excluded from:

    * ``"random_walk"`` (default; the paper, scikit-learn): :math:`L v = \lambda D v`
      with :math:`v^\mathsf{T} D v = 1`, i.e. the eigenvectors of :math:`D^{-1} L`;
    * ``"symmetric"``: :math:`D^{-1/2} L D^{-1/2} y = \lambda y`,
      :math:`\lVert y \rVert = 1` (:math:`y = D^{1/2} v`);
    * ``"unnormalized"``: :math:`L y = \lambda y`, :math:`\lVert y \rVert = 1`.

    Parameters
    ----------
    points : (n, D) float array
        The data, one row per point; at least 3 points.
    n_components : int, default 2
        The dimension ``k`` of the embedding, ``1 <= k <= n - 2``. It may exceed the
        dimension ``D`` of the points, as in scikit-learn's ``SpectralEmbedding``.
    neighbors : {"knn", "radius", "all"}, default "knn"
        The neighbourhood graph: ``"knn"`` joins each point to its ``n_neighbors``
        nearest (either way round), ``"radius"`` every pair at most ``radius`` apart,
        ``"all"`` every pair.
    n_neighbors : int, optional
        Neighbours per point with ``neighbors="knn"``, the point itself counted among them
        as in scikit-learn's ``SpectralEmbedding`` (``n_neighbors - 1`` other points; ties
        by lower index), at most ``n - 1``; ``max(n // 10, 2)`` when omitted
        (scikit-learn's ``max(n // 10, 1)``, except that below 20 points 1 would leave
        each point alone).
    radius : float, optional
        The radius with ``neighbors="radius"``, required there.
    weighting : {"uniform", "distance", "heat"}, default "uniform"
        Edge weights from the edge lengths :math:`d`: ``"uniform"`` 1, ``"distance"``
        :math:`1/d`, ``"heat"`` the heat kernel :math:`\exp(-d^2/2\sigma^2)`.
        Every edge of the symmetrised graph (``i`` among ``j``'s neighbours or ``j`` among
        ``i``'s) weighs the same: scikit-learn's ``SpectralEmbedding`` gives an edge found
        from one side only half the weight (``(A + Aᵀ)/2``), which moves the embedding
        slightly (a Procrustes disparity of 3.7e-3 on a 400-point swiss roll, k = 10;
        ``affinity="precomputed"`` on our graph agrees to 1e-28). Weight 1 keeps the graph
        the same whichever side found an edge, as spectral clustering here does.
    sigma : float, optional
        The heat kernel's width :math:`\sigma`; the mean edge length when omitted.
    laplacian : {"random_walk", "symmetric", "unnormalized"}, default "random_walk"
        The normalisation of :math:`L = D - W`: ``"random_walk"`` solves
        :math:`L v = \lambda D v` (the paper, scikit-learn); ``"symmetric"`` returns instead
        the unit eigenvectors :math:`y = \sqrt{D}\, v` of the symmetric normalised
        Laplacian; ``"unnormalized"`` solves :math:`L y = \lambda y`.
    quality_neighbors : int, default 5
        The neighbourhood size of the reported trustworthiness (clipped to
        ``(n - 1) // 2`` when larger).

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
    **Which vector is the embedding.** The normalised problem :math:`\min y^\mathsf{T}
    D^{-1/2} L D^{-1/2} y` with :math:`\lVert y \rVert = 1` becomes, by the substitution
    :math:`v = D^{-1/2} y`, the paper's :math:`L v = \lambda D v` with
    :math:`v^\mathsf{T} D v = 1`: the same eigenvalues, but the two eigenvectors differ by
    the factor :math:`D^{1/2}` row by row, so returning :math:`y` (``"symmetric"``) or
    :math:`v` gives different embeddings wherever degrees differ. The default returns
    :math:`v`, as the paper and scikit-learn do, so that the result agrees with
    ``sklearn.manifold.SpectralEmbedding`` (affinity ``"precomputed"`` on the same weights)
    up to an orthogonal transform (exactly when the eigenvalues are distinct: same signs
    convention).

    Disconnected graphs are an error naming the component count; scikit-learn only warns.

    Cost: the graph (kd-tree), then a dense ``eigh`` up to 1,000 points, above that
    shift-invert Lanczos with one sparse Cholesky factorization of :math:`L + \epsilon I`
    (:class:`~algorithms.core.linsolve.Factor`).

    References
    ----------
    .. [1] M. Belkin, P. Niyogi, "Laplacian eigenmaps for dimensionality reduction and
       data representation", Neural Computation 15 (2003).

    Examples
    --------
    >>> import numpy as np
    >>> x = np.c_[np.arange(6.0), np.zeros(6)]            # a path graph
    >>> res = laplacian_eigenmaps(x, n_components=1, n_neighbors=2)
    >>> bool(np.all(np.diff(res.embedding[:, 0]) < 0) or np.all(np.diff(res.embedding[:, 0]) > 0))
    True
    """
    x, k = check_laplacian_eigenmaps(points, n_components, neighbors, n_neighbors, radius)
    w = similarity_graph(x, neighbors, n_neighbors, radius, weighting, sigma,
                         method="Laplacian eigenmaps")
    y, vals = spectral_embedding(w, k, laplacian)
    return LaplacianEigenmapsResult(
        embedding=np.ascontiguousarray(y),
        eigenvalues=vals,
        trustworthiness=trustworthiness(x, y, n_neighbors=quality_neighbors),
    )
