r"""Isomap: classical MDS of geodesic (shortest-path) distances along a neighbourhood graph."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.sparse.csgraph import shortest_path

from algorithms.core.graphs import neighbour_graph
from algorithms.core.threads import single_blas_thread
from algorithms.core.types import FloatArray
from algorithms.core.validation import as_choice, as_int, as_points
from algorithms.embedding._quality import trustworthiness
from algorithms.layout.mds import classical_coordinates

__all__ = ["IsomapResult", "isomap", "MAX_ISOMAP_POINTS"]

#: Isomap holds the dense ``n×n`` geodesic distances (10,000 points: 800 MB).
MAX_ISOMAP_POINTS = 10_000


@dataclass(frozen=True, eq=False)
class IsomapResult:
    """Points in ``k`` dimensions whose distances reproduce the geodesic ones.

    Attributes
    ----------
    embedding : (n, k) float array
        One row per point, centred; column ``c`` is the ``c``-th principal coordinate of
        the geodesic distances, its entry of largest magnitude positive.
    eigenvalues : (k,) float array
        The ``k`` largest eigenvalues of :math:`-\\tfrac12 J G^{(2)} J`, decreasing
        (scikit-learn's ``kernel_pca_.eigenvalues_``).
    trustworthiness : float
        Trustworthiness of the embedding against the input points (1: every embedded
        neighbourhood is a true one).
    """

    embedding: FloatArray
    eigenvalues: FloatArray
    trustworthiness: float


def isomap(points: Any, *, n_components: int = 2, neighbors: str = "knn",
           n_neighbors: int = 5, radius: float | None = None, weighting: str = "distance",
           quality_neighbors: int = 5) -> IsomapResult:
    r"""Isomap (Tenenbaum, de Silva and Langford 2000).

    1. A neighbourhood graph on the points (``neighbors``), each edge as long as the
       distance between its ends (``weighting="distance"``) or 1 (``"uniform"``: hops);
    2. the geodesic distances :math:`G`: all-pairs shortest paths (Dijkstra);
    3. classical MDS of :math:`G` (the ``k`` largest eigenpairs of
       :math:`-\tfrac12 J G^{(2)} J`), the code shared with ``layout.mds``.

    Parameters
    ----------
    points : (n, D) float array
        At least ``n_neighbors + 1`` and at most 10,000 points.
    n_components : int, default 2
        The dimension ``k``, ``1 <= k <= n``.
    neighbors : {"knn", "radius", "all"}, default "knn"
        ``"knn"``: each point joined to its ``n_neighbors`` nearest (union); ``"radius"``:
        every pair closer than ``radius``; ``"all"``: every pair (plain classical MDS).
    n_neighbors : int, default 5
        Neighbours per point for ``"knn"``, ``1 <= n_neighbors <= n - 1``.
    radius : float, optional
        The radius for ``"radius"``.
    weighting : {"distance", "uniform"}, default "distance"
        Edge *lengths* for the shortest paths: the Euclidean distance, or 1 per edge.
        (The heat kernel is a similarity, not a length: it is refused.)
    quality_neighbors : int, default 5
        The neighbourhood size of the reported trustworthiness.

    Returns
    -------
    IsomapResult
        ``embedding``, ``eigenvalues``, ``trustworthiness``.

    Raises
    ------
    InvalidInputError
        Bad ``points``; ``n_neighbors`` outside ``[1, n - 1]`` (fewer points than
        neighbours); ``radius`` missing or not positive; ``n_components`` outside
        ``[1, n]``; unknown ``neighbors`` or ``weighting``; more than 10,000 points.
    DegenerateInputError
        The graph is disconnected: the message says into how many components
        (``field`` ``n_neighbors`` or ``radius``).

    Notes
    -----
    **Disconnected graphs are an error** here (ALGORITHMS.md), not repaired:
    scikit-learn ≥ 1.0 joins the components by their closest pairs with a warning
    (PR #20531), which makes the geodesic distances between components straight-line
    jumps and the embedding depend on them; an error naming the component count lets the
    caller choose more neighbours or a larger radius instead.

    The seed document describes the three steps as above ("adjacency matrix: pick
    neighbours, set weights; all-pairs shortest paths with those weights; multidimensional
    scaling"); as its graph-Laplacian section says weights must be inverted for Laplacians
    (similarities), here the edge values are lengths, so ``weighting`` is a length.
    With ``neighbors="knn"`` and ``weighting="distance"`` the result equals
    ``sklearn.manifold.Isomap(n_neighbors=k, eigen_solver="dense")`` up to the signs of the
    columns (same sign convention here, so equal up to ties of neighbours).

    Cost: Dijkstra from every point, :math:`O(n (e + n \log n))`; :math:`O(n^2)` memory for
    the geodesic distances; the eigenvectors by Lanczos (ARPACK) above 400 points.

    References
    ----------
    .. [1] J. B. Tenenbaum, V. de Silva, J. C. Langford, "A global geometric framework for
       nonlinear dimensionality reduction", Science 290 (2000).
    .. [2] The seed document, section "isomap".

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0, np.pi, 20)
    >>> arc = np.c_[np.cos(t), np.sin(t)]             # a half circle of 19 chords
    >>> y = isomap(arc, n_components=1, neighbors="radius", radius=0.2).embedding.ravel()
    >>> chords = 19 * 2 * np.sin(np.pi / 38)          # unrolled to a segment that long
    >>> round(float(y.max() - y.min() - chords), 9)
    0.0
    """
    x = as_points(points, name="points", min_points=2, max_points=MAX_ISOMAP_POINTS)
    n = x.shape[0]
    k = as_int(n_components, name="n_components", minimum=1, maximum=n,
               reason=f"the number of `points` ({n})")
    as_choice(weighting, ("distance", "uniform"), name="weighting")
    g = neighbour_graph(x, neighbors=neighbors, n_neighbors=n_neighbors, radius=radius,
                        connected="isomap")
    if weighting == "uniform":
        g.data = np.ones_like(g.data)
    geo = shortest_path(g, method="D", directed=True)  # g is symmetric
    geo *= geo
    with single_blas_thread():
        y, eigenvalues = classical_coordinates(geo, k)
    del geo
    return IsomapResult(
        embedding=y,
        eigenvalues=eigenvalues,
        trustworthiness=trustworthiness(x, y, n_neighbors=quality_neighbors),
    )
