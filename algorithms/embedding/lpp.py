r"""Locality preserving projections: the linear map closest to Laplacian eigenmaps."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Annotated, Any

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp

from algorithms.core.errors import DegenerateInputError
from algorithms.core.graphs import (
    GraphWeighting,
    HeatWidth,
    Neighbors,
    NNeighbors,
    Radius,
    check_neighbour_graph,
)
from algorithms.core.laplacian import laplacian as graph_laplacian
from algorithms.core.params import Ge, PointsLike, validate_params
from algorithms.core.types import FloatArray
from algorithms.core.validation import as_choice
from algorithms.embedding._quality import fix_signs, trustworthiness
from algorithms.embedding.laplacian_eigenmaps import LAPLACIANS, Normalization, similarity_graph
from algorithms.embedding.pca import check_linear_components

__all__ = ["check_lpp", "LPPResult", "lpp", "lpp_from_weights"]


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


def check_lpp(points: Any, n_components: Any, neighbors: str = "knn", n_neighbors: Any = None,
              radius: Any = None) -> tuple[FloatArray, int]:
    """Check the inputs of :func:`lpp`: at least 3 points, neighbour-graph parameters that
    fit them, ``n_components`` at most their dimension and number. Returns both."""
    x = check_neighbour_graph(points, neighbors, n_neighbors, radius, min_points=3)
    return x, check_linear_components(n_components, *x.shape)


@validate_params
def lpp(
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
) -> LPPResult:
    r"""Locality preserving projections.

    The linear map closest to Laplacian eigenmaps: generalized eigenvectors of XᵀLXa = λXᵀDXa on the
    centred data. Reports the projection (applies to new points), eigenvalues and trustworthiness.

    Laplacian eigenmaps restricted to linear maps :math:`y = A^\mathsf{T}(x - \mu)`: with
    the centred data :math:`\tilde X` (rows are points), the graph's :math:`W`, :math:`D`,
    :math:`L = D - W`, the columns of :math:`A` are the generalized eigenvectors of the
    ``k`` smallest eigenvalues of

    * ``"random_walk"`` (default; the paper): :math:`\tilde X^\mathsf{T} L \tilde X a =
      \lambda \tilde X^\mathsf{T} D \tilde X a`, centred at the degree-weighted mean (so
      the constant map is excluded, as the trivial vector in Laplacian eigenmaps);
    * ``"symmetric"``: :math:`\tilde X^\mathsf{T} D^{-1/2} L D^{-1/2}
      \tilde X a = \lambda \tilde X^\mathsf{T} \tilde X a`, i.e. :math:`\min
      \operatorname{tr}(Y^\mathsf{T} D^{-1/2} L D^{-1/2} Y)` subject to
      :math:`Y^\mathsf{T} Y = I`, centred at the mean;
    * ``"unnormalized"``: :math:`\tilde X^\mathsf{T} L \tilde X a = \lambda
      \tilde X^\mathsf{T} \tilde X a`, centred at the mean.

    Parameters
    ----------
    points : (n, D) float array
        The data, one row per point; at least 3 points, spanning all ``D`` dimensions
        (else reduce them first, e.g. by PCA).
    n_components : int, default 2
        The dimension ``k`` of the embedding, ``1 <= k <= min(n, D)``.
    neighbors : {"knn", "radius", "all"}, default "knn"
        The neighbourhood graph: ``"knn"`` joins each point to its ``n_neighbors``
        nearest (either way round), ``"radius"`` every pair at most ``radius`` apart,
        ``"all"`` every pair.
    n_neighbors : int, optional
        Neighbours per point with ``neighbors="knn"``, the point itself counted among them
        (``n_neighbors - 1`` other points), the graph of :func:`laplacian_eigenmaps` and
        scikit-learn's ``SpectralEmbedding``; at most ``n - 1``; ``max(n // 10, 2)`` when
        omitted.
    radius : float, optional
        The radius with ``neighbors="radius"``, required there.
    weighting : {"uniform", "distance", "heat"}, default "uniform"
        Edge weights from the edge lengths :math:`d`: ``"uniform"`` 1, ``"distance"``
        :math:`1/d`, ``"heat"`` the heat kernel :math:`\exp(-d^2/2\sigma^2)`.
        Every edge of the symmetrised graph weighs the same, whichever side found it (not
        half for one side, as scikit-learn's ``SpectralEmbedding``; see
        :func:`~algorithms.embedding.laplacian_eigenmaps`).
    sigma : float, optional
        The heat kernel's width :math:`\sigma`; the mean edge length when omitted.
    laplacian : {"random_walk", "symmetric", "unnormalized"}, default "random_walk"
        The generalized eigenproblem for the directions :math:`a`, with :math:`X` the
        centred data and :math:`L = D - W`: ``"random_walk"`` :math:`X^\mathsf{T} L X a =
        \lambda X^\mathsf{T} D X a` (the paper; centred at the degree-weighted mean);
        ``"symmetric"`` the symmetric normalised Laplacian in place of :math:`L` and
        :math:`X^\mathsf{T} X` on the right; ``"unnormalized"`` :math:`X^\mathsf{T} L X a =
        \lambda X^\mathsf{T} X a`.
    quality_neighbors : int, default 5
        The neighbourhood size of the reported trustworthiness (clipped to
        ``(n - 1) // 2`` when larger).

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
    **Two normalisations.** Set up with the normalised Laplacian, the problem is
    :math:`\min \operatorname{tr}(A^\mathsf{T} \tilde X^\mathsf{T} L_\mathrm{sym} \tilde X
    A)` subject to :math:`A^\mathsf{T} \tilde X^\mathsf{T} \tilde X A = I`, with
    :math:`L_\mathrm{sym} = D^{-1/2} L D^{-1/2}` (``"symmetric"``). Replacing the data
    :math:`\tilde X` by :math:`D^{1/2} \tilde X` in it gives the paper's
    :math:`\tilde X^\mathsf{T} L \tilde X a = \lambda \tilde X^\mathsf{T} D \tilde X a`:
    the same substitution that turns the symmetric eigenproblem of Laplacian eigenmaps
    into :math:`L v = \lambda D v`, but here the two are different problems, since the
    map must be linear in the data. The default is the paper's form, the linear
    counterpart of the default of ``laplacian_eigenmaps``: when the points are affinely
    independent (``D = n - 1``) every function on them is linear and the two methods
    coincide (tested). The linearity constraint can only raise the graph objective
    compared with Laplacian eigenmaps; LPP's gain is a map that applies to new points
    (``components``, ``mean``).

    There is no reference implementation in scikit-learn; the tests check the generalized
    eigen-equations, the reduction to Laplacian eigenmaps above, and invariance under
    rotations and translations of the input.

    References
    ----------
    .. [1] X. He, P. Niyogi, "Locality preserving projections", NIPS 16 (2003).

    Examples
    --------
    >>> import numpy as np
    >>> rng = np.random.default_rng(0)
    >>> x = np.c_[np.linspace(0, 10, 40), rng.normal(0, 0.1, 40), rng.normal(0, 0.1, 40)]
    >>> res = lpp(x, n_components=2, n_neighbors=3)
    >>> bool(np.allclose(res.embedding, (x - res.mean) @ res.components.T))
    True
    """
    x, k = check_lpp(points, n_components, neighbors, n_neighbors, radius)
    n, dim = x.shape
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
