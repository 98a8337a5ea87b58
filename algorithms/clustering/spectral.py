r"""Spectral clustering (Ng, Jordan and Weiss): k-means on the bottom eigenvectors of the
normalised graph Laplacian."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Annotated, Any

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components
from scipy.sparse.linalg import eigsh

from algorithms.clustering._kmeans import kmeans
from algorithms.core.errors import InvalidInputError, warn
from algorithms.core.graphs import (
    GraphWeighting,
    HeatWidth,
    Neighbors,
    NNeighbors,
    Radius,
    check_neighbour_graph,
    neighbour_graph,
)
from algorithms.core.laplacian import normalized_laplacian
from algorithms.core.params import Ge, PointsLike, Seed, validate_params
from algorithms.core.types import FloatArray, IntArray
from algorithms.core.validation import as_int

__all__ = ["SpectralClusteringResult", "spectral", "check_spectral", "DENSE_BELOW"]

#: Below this many points the eigenvectors come from a dense symmetric eigensolver.
DENSE_BELOW = 2500


@dataclass(frozen=True, eq=False)
class SpectralClusteringResult:
    """A partition of the points into ``n_clusters`` groups, and the embedding it came from.

    Attributes
    ----------
    labels : (n,) int array
        The cluster of each point, ``0 .. n_clusters - 1``, numbered in order of first
        appearance (point 0 is in cluster 0).
    sizes : (n_clusters,) int array
        The number of points in each cluster.
    embedding : (n, n_clusters) float array
        The spectral embedding k-means ran on: the bottom eigenvectors of the symmetric
        normalised Laplacian, each row scaled to unit length; each column's largest entry
        (in absolute value) is positive.
    eigenvalues : (n_clusters,) float array
        The matching eigenvalues of :math:`I - D^{-1/2} W D^{-1/2}`, ascending, in [0, 2].
    inertia : float
        The k-means objective: the sum of squared distances of the embedded points to their
        cluster centre.
    graph_components : int
        The number of connected components of the neighbour graph (a component is never
        split across fewer clusters than it would need; more components than clusters is
        reported with a warning).
    """

    labels: IntArray
    sizes: IntArray
    embedding: FloatArray
    eigenvalues: FloatArray
    inertia: float
    graph_components: int


def check_spectral(points: Any, n_clusters: Any, neighbors: str = "knn",
                   n_neighbors: Any = None, radius: Any = None) -> tuple[FloatArray, int]:
    """Check the inputs of :func:`spectral`: points for a neighbour graph
    (:func:`~algorithms.core.graphs.check_neighbour_graph`) and ``n_clusters`` at most
    their number. Returns the points and the number of clusters."""
    x = check_neighbour_graph(points, neighbors, n_neighbors, radius)
    k = as_int(n_clusters, name="n_clusters", minimum=1, maximum=x.shape[0],
               reason="the number of `points`")
    return x, k


@validate_params
def spectral(
    points: PointsLike,
    *,
    n_clusters: Annotated[int, Ge(1)] = 8,
    neighbors: Neighbors = "knn",
    n_neighbors: NNeighbors = 10,
    radius: Radius | None = None,
    weighting: GraphWeighting = "uniform",
    sigma: HeatWidth | None = None,
    n_init: Annotated[int, Ge(1)] = 10,
    seed: Seed = 0,
) -> SpectralClusteringResult:
    r"""Spectral clustering (Ng, Jordan, Weiss).

    k-means (k-means++ seeding, seeded) on the bottom eigenvectors of the symmetric normalised
    Laplacian of the points' neighbour graph, rows scaled to unit length. Reports labels, cluster
    sizes, the embedding and its eigenvalues.

    With :math:`W` the weights of the neighbour graph and :math:`D` its degrees, the
    embedding is made of the eigenvectors :math:`u_1, \dots, u_k` of the ``k = n_clusters``
    smallest eigenvalues of the symmetric normalised Laplacian

    .. math:: L_\mathrm{sym} = D^{-1/2} (D - W) D^{-1/2} = I - D^{-1/2} W D^{-1/2},

    its rows scaled to unit length (Ng, Jordan and Weiss); k-means with k-means++ seeding
    (``n_init`` starts, the best kept) then groups the rows.

    Parameters
    ----------
    points : (n, d) float array
        The points to cluster, ``n >= 2``.
    n_clusters : int, default 8
        The number of clusters ``k``, at most the number of points.
    neighbors : {"knn", "radius", "all"}, default "knn"
        The neighbour graph: ``"knn"`` joins each point to its ``n_neighbors`` nearest
        (the union of the two directions), ``"radius"`` to every point within ``radius``,
        ``"all"`` to every point (at most 10,000 points).
    n_neighbors : int, default 10
        Neighbours per point with ``neighbors="knn"``, the point itself counted among them
        as scikit-learn's ``SpectralClustering`` counts it (``n_neighbors - 1`` other
        points; ties by lower index); at most the number of points minus one.
    radius : float, optional
        The radius with ``neighbors="radius"``, required there.
    weighting : {"uniform", "distance", "heat"}, default "uniform"
        Edge weights from the edge lengths :math:`d`: ``"uniform"`` 1 (scikit-learn's
        ``affinity="nearest_neighbors"``), ``"distance"`` :math:`1/d`, or ``"heat"`` the
        heat kernel :math:`\exp(-d^2/2\sigma^2)`.
    sigma : float, optional
        The heat kernel's width :math:`\sigma`; the mean edge length when omitted.
    n_init : int, default 10
        k-means++ starts; the one with the least inertia is kept.
    seed : int or numpy Generator, default 0
        Seeds k-means++; the same seed gives the same labels.

    Returns
    -------
    SpectralClusteringResult
        ``labels``, ``sizes``, ``embedding``, ``eigenvalues``, ``inertia``,
        ``graph_components``.

    Raises
    ------
    InvalidInputError
        Bad ``points``; ``n_clusters`` outside ``[1, n]``; ``n_neighbors`` outside
        ``[1, n - 1]``; ``neighbors="radius"`` without ``radius``; an unknown option.
    DegenerateInputError
        Coincident points with ``weighting="distance"`` (infinite weight).

    Warns
    -----
    UserWarning
        The neighbour graph has more connected components than ``n_clusters``: some
        clusters then hold several components (as scikit-learn, which warns too). Fewer
        components than clusters is the normal case; isolated points (no neighbour within
        ``radius``) embed at the origin and join the cluster nearest to it.

    Notes
    -----
    **An embedding, then k-means; no exact cut.** The method reshapes the data by the
    eigenvectors of a graph Laplacian and then runs k-means on them. It is often said to
    solve a relaxation of a (normalised) cut problem exactly; it does not produce a cut.
    Cut indicators are 0/1 vectors and the eigenvectors are not, so the eigenvectors are
    only a relaxed embedding of the points, and the k-means step is what makes the
    partition discrete, with no guarantee that it is the best cut.

    Eigenvectors: a dense symmetric eigensolver below ``DENSE_BELOW`` points; above, the
    Lanczos solver (ARPACK) on :math:`I + D^{-1/2} W D^{-1/2}` (eigenvalues in [0, 2],
    the wanted ones largest). scikit-learn's ``SpectralClustering`` differs in three
    details: it averages the two directions of the kNN relation (weight ½ for one-sided
    neighbours), embeds :math:`D^{-1/2} u` without row normalisation, and seeds ARPACK
    randomly; its labels agree with ours on well-separated data (tests compare adjusted
    Rand indices).

    References
    ----------
    .. [1] A. Y. Ng, M. I. Jordan, Y. Weiss, "On spectral clustering: analysis and an
       algorithm", NIPS 2001.
    .. [2] U. von Luxburg, "A tutorial on spectral clustering", Statistics and Computing
       17(4), 2007.
    .. [3] D. Arthur, S. Vassilvitskii, "k-means++: the advantages of careful seeding",
       SODA 2007.

    Examples
    --------
    >>> pts = [[0, 0], [0, 1], [1, 0], [10, 10], [10, 11], [11, 10]]
    >>> res = spectral(pts, n_clusters=2, n_neighbors=2)
    >>> res.labels.tolist(), res.sizes.tolist()
    ([0, 0, 0, 1, 1, 1], [3, 3])
    """
    x, k = check_spectral(points, n_clusters, neighbors, n_neighbors, radius)
    w = neighbour_graph(x, neighbors=neighbors, n_neighbors=n_neighbors, radius=radius,
                        weighting=weighting, sigma=sigma, include_self=True)
    ncomp = int(connected_components(w, directed=False)[0])
    if ncomp > k:
        warn(f"The neighbour graph of `points` has {ncomp} connected components, "
             f"more than n_clusters={k}: some clusters hold several components.",
             UserWarning)
    vals, vecs = _bottom_eigenvectors(w, k)
    # deterministic signs: each column's largest entry positive
    big = np.argmax(np.abs(vecs), axis=0)
    vecs *= np.where(vecs[big, np.arange(k)] < 0, -1.0, 1.0)
    norms = np.linalg.norm(vecs, axis=1, keepdims=True)
    emb = np.divide(vecs, norms, out=np.zeros_like(vecs), where=norms > 1e-300)
    fit = kmeans(emb, k, n_init=n_init, seed=seed)
    sizes = np.bincount(fit.labels, minlength=k)
    return SpectralClusteringResult(
        labels=fit.labels,
        sizes=sizes.astype(np.int64),
        embedding=emb,
        eigenvalues=vals,
        inertia=fit.inertia,
        graph_components=ncomp,
    )


def _bottom_eigenvectors(w: sp.csr_array, k: int) -> tuple[FloatArray, FloatArray]:
    """The ``k`` smallest eigenpairs of the symmetric normalised Laplacian of ``w``."""
    lap = normalized_laplacian(w, kind="symmetric")
    n = lap.shape[0]
    deg = np.asarray(w.sum(axis=1)).ravel()
    isolated = deg <= 0
    if isolated.any():  # their rows are zero: eigenvalue 0, to keep them out of the way
        lap = (lap + sp.diags_array(np.where(isolated, 1.0, 0.0))).tocsr()
    if n < DENSE_BELOW or k >= n - 1:
        vals, vecs = la.eigh(lap.toarray(), subset_by_index=(0, k - 1))
    else:
        shifted = (2.0 * sp.eye_array(n, format="csr") - lap).tocsr()
        v0 = np.sqrt(np.maximum(deg, 1e-12))  # the bottom eigenvector: deterministic start
        try:
            vals, vecs = eigsh(shifted, k=k, which="LA", v0=v0 / np.linalg.norm(v0),
                               tol=1e-10, maxiter=max(1000, 20 * n))
        except Exception as exc:  # noqa: BLE001  (ARPACK non-convergence)
            raise InvalidInputError(
                f"The eigenvectors of the neighbour graph of `points` did not converge "
                f"({exc}); try more `n_neighbors`.", field="points") from None
        vals = 2.0 - vals
        order = np.argsort(vals, kind="stable")
        vals, vecs = vals[order], vecs[:, order]
    vals = np.clip(vals, 0.0, 2.0)
    return np.ascontiguousarray(vals), np.ascontiguousarray(vecs)
