r"""Neighbourhood graphs and their edge weights: the adjacency every Laplacian starts from.

A graph here is a symmetric ``(n, n)`` :class:`scipy.sparse.csr_array` whose stored entries
are its edges. The builders store each edge's *length* (the distance between its end
points) so that :func:`weight` can turn lengths into weights afterwards; zero lengths
(coincident points) are stored explicitly, never dropped, so the structure is always the
edge set.

* :class:`Graph` / :func:`as_graph` — a graph given as data: a node count, an edge list and
  optional edge weights, as JSON delivers it (layouts, Markov clustering);
* :func:`edge_graph` — from an explicit edge list (a mesh's :func:`~algorithms.core.mesh.edges`);
* :func:`knn_graph` — each point to its ``k`` nearest others, symmetrised by union or
  mutual agreement (a kd-tree: :class:`scipy.spatial.cKDTree`);
* :func:`radius_graph` — every pair closer than ``r``;
* :func:`weight` — uniform (1), inverse distance (:math:`1/d`) or heat kernel
  (:math:`e^{-d^2/(2\sigma^2)}`, Belkin & Niyogi 2003);
* :func:`neighbour_graph` — the shared graph parameters of the point-cloud methods
  (clustering, embeddings: ``neighbors``, ``n_neighbors``, ``radius``, ``weighting``,
  ``sigma``) turned into one of the graphs above, weighted; :func:`check_n_neighbors` and
  :func:`check_connected` are its checks, also used on their own.

Then :func:`algorithms.core.laplacian.laplacian` gives ``L = D - W``.
"""

from __future__ import annotations

import typing
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Annotated, Any, Literal

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree
from scipy.spatial.distance import pdist, squareform

from algorithms.core.errors import DegenerateInputError, InvalidInputError
from algorithms.core.params import Ge, Gt
from algorithms.core.types import FloatArray, IntArray, KnnQuery
from algorithms.core.validation import (
    as_choice,
    as_float,
    as_indices,
    as_int,
    as_points,
    as_weights,
    check_keys,
    fmt_shape,
)

__all__ = ["Graph", "as_graph", "edge_graph", "knn_graph", "nearest_sorted", "radius_graph",
           "weight", "graph_from_pairs", "neighbour_graph", "check_neighbour_params",
           "check_neighbour_graph",
           "check_n_neighbors", "check_connected", "Neighbors", "GraphWeighting", "NNeighbors",
           "Radius", "HeatWidth", "NEIGHBORS", "WEIGHTINGS", "MAX_COMPLETE"]

NNeighbors = Annotated[int, Ge(1)]
"""Neighbours per point of a ``"knn"`` graph (at most the number of points minus one: checked
against the data by :func:`check_n_neighbors`)."""
Radius = Annotated[float, Gt(0)]
"""The radius of a ``"radius"`` graph, in the points' units."""
HeatWidth = Annotated[float, Gt(0)]
"""The width σ of the heat kernel exp(-d²/2σ²)."""
Neighbors = Literal["knn", "radius", "all"]
"""How the point-cloud methods build their neighbour graph: each point joined to its
``n_neighbors`` nearest, to every point within ``radius``, or to every point."""
GraphWeighting = Literal["uniform", "distance", "heat"]
"""Edge weights of a neighbour graph: 1, 1/d, or the heat kernel exp(-d²/2σ²)."""
#: Accepted values of ``neighbors`` and ``weighting`` in :func:`neighbour_graph`.
NEIGHBORS: tuple[str, ...] = typing.get_args(Neighbors)
WEIGHTINGS: tuple[str, ...] = typing.get_args(GraphWeighting)

#: Most points for ``neighbors="all"`` (a dense ``n×n`` graph: 10,000 points, 800 MB).
MAX_COMPLETE = 10_000



@dataclass(frozen=True, eq=False)
class Graph:
    """A graph on ``n_nodes`` nodes given by its edges.

    Build one with :func:`as_graph`, which checks it; the constructor does not.

    Attributes
    ----------
    n_nodes : int
        Number of nodes, numbered ``0 .. n_nodes - 1``.
    edges : (e, 2) int array
        One row ``(i, j)`` per edge, in the order and orientation given (``layout.poisson``
        matches its vectors to ``p_i - p_j`` of each row).
    weights : (e,) float array or None
        One non-negative number per edge, or ``None`` for all ones. Spring stiffness in
        ``layout.laplacian`` and ``layout.poisson``; edge length in ``layout.stress``.
    """

    n_nodes: int
    edges: IntArray
    weights: FloatArray | None = None

    def __repr__(self) -> str:
        return f"Graph(n_nodes={self.n_nodes}, n_edges={self.edges.shape[0]})"


def as_graph(graph: Any, *, name: str = "graph", max_nodes: int | None = None,
             positive_weights: bool = False) -> Graph:
    """Check a graph and return it as a :class:`Graph`.

    Parameters
    ----------
    graph : Graph or mapping
        A :class:`Graph`, or a mapping with keys ``"nodes"`` (the node count, an integer
        ``>= 1``), ``"edges"`` (``(e, 2)`` node indices) and optionally ``"weights"``
        (``(e,)`` non-negative numbers), as JSON delivers it.
    name : str, default "graph"
        Errors name ``{name}.nodes``, ``{name}.edges`` or ``{name}.weights``.
    max_nodes : int, optional
        Most nodes accepted (the service's size limit).
    positive_weights : bool, default False
        Demand weights ``> 0`` (edge lengths) instead of ``>= 0``.

    Raises
    ------
    InvalidInputError
        Not such a mapping, a node count that is not a positive integer, edges not ``(e, 2)``
        integers in ``[0, nodes)``, an edge joining a node to itself, weights not one
        finite non-negative (positive) number per edge.
    """
    nname, ename, wname = f"{name}.nodes", f"{name}.edges", f"{name}.weights"
    if isinstance(graph, Graph):
        nodes, edges, weights = graph.n_nodes, graph.edges, graph.weights
    elif isinstance(graph, Mapping):
        check_keys(graph, ("nodes", "edges"), ("weights",), name=name,
                   expected="an object with keys 'nodes', 'edges' and optionally 'weights'")
        nodes, edges, weights = graph["nodes"], graph["edges"], graph.get("weights")
    else:
        raise InvalidInputError(
            f"Expected `{name}` to be an object with keys 'nodes', 'edges' and optionally "
            f"'weights', got {type(graph).__name__}.", field=name)
    n = as_int(nodes, name=nname, minimum=1, maximum=max_nodes,
               reason="the service's limit" if max_nodes is not None else "")
    try:
        shape = np.shape(edges)
    except (ValueError, TypeError):
        shape = None
    if shape is not None and not (len(shape) == 2 and shape[1] == 2) and shape != (0,):
        raise InvalidInputError(
            f"Expected `{ename}` to be an (e, 2) array of node indices, got shape "
            f"{fmt_shape(shape)}.", field=ename)
    e = as_indices(edges, n, name=ename, what="node indices").reshape(-1, 2)
    loops = e[:, 0] == e[:, 1]
    if loops.any():
        row = int(np.argmax(loops))
        raise InvalidInputError(
            f"Expected `{ename}` to join two distinct nodes per edge, got {e[row].tolist()} "
            f"at row {row}.", field=ename)
    w: FloatArray | None = None
    if weights is not None:
        try:
            wshape = np.shape(weights)
        except (ValueError, TypeError):
            wshape = None
        if wshape is not None and len(wshape) != 1:
            raise InvalidInputError(
                f"Expected `{wname}` to be a flat list of one number per edge, got shape "
                f"{fmt_shape(wshape)}.", field=wname)
        if e.shape[0] == 0 and wshape == (0,):
            w = np.zeros(0)
        else:
            w = as_weights(weights, e.shape[0], name=wname)
        # w is an array here: as_weights returns None only for weights=None
        if positive_weights and w is not None and (w <= 0).any():
            row = int(np.argmax(w <= 0))
            raise InvalidInputError(
                f"Expected `{wname}` to be positive (edge lengths), got {float(w[row])!r} at "
                f"position {row}.", field=wname)
    return Graph(n, e, w)


def graph_from_pairs(n: int, i: Any, j: Any, data: Any) -> sp.csr_array:
    """A symmetric csr_array with ``data[e]`` at ``(i[e], j[e])`` and ``(j[e], i[e])``.

    Repeated pairs (in either orientation) keep the value of their first occurrence;
    explicit zeros are kept (they are edges of length zero).
    """
    i = np.asarray(i, dtype=np.int64)
    j = np.asarray(j, dtype=np.int64)
    data = np.asarray(data, dtype=np.float64)
    lo, hi = np.minimum(i, j), np.maximum(i, j)
    keys, first = np.unique(lo * n + hi, return_index=True)
    lo, hi, d = keys // n, keys % n, data[first]
    rows = np.concatenate([lo, hi])
    cols = np.concatenate([hi, lo])
    vals = np.concatenate([d, d])
    g = sp.csr_array((vals, (rows, cols)), shape=(n, n))
    g.sum_duplicates()  # no duplicates left: this only sorts the indices
    return g


def edge_graph(n: int, edges: Any, weights: Any = None, *, name: str = "edges") -> sp.csr_array:
    """The symmetric adjacency matrix of an undirected graph given by its edges.

    Parameters
    ----------
    n : int
        Number of vertices.
    edges : (e, 2) int array
        Pairs of distinct vertex indices, either orientation; a pair given twice (in either
        orientation) is one edge.
    weights : (e,) float array, optional
        A finite value per edge (for a repeated edge, its first occurrence counts); 1 for
        every edge when omitted.
    name : str, default "edges"
        Names the edge list in errors (the weights are ``weights``).

    Returns
    -------
    (n, n) csr_array
        Symmetric, zero diagonal.

    Raises
    ------
    InvalidInputError
        ``edges`` not ``(e, 2)`` indices below ``n``, a self-loop, or ``weights`` not ``(e,)``
        finite numbers.

    Examples
    --------
    >>> edge_graph(3, [[0, 1], [1, 2]]).toarray().tolist()
    [[0.0, 1.0, 0.0], [1.0, 0.0, 1.0], [0.0, 1.0, 0.0]]
    """
    n = as_int(n, name="n", minimum=0)
    e = as_indices(edges, n, name=name, what="vertex indices")
    if e.size == 0:
        e = e.reshape(0, 2)
    if e.ndim != 2 or e.shape[1] != 2:
        raise InvalidInputError(
            f"Expected `{name}` to be an (e, 2) array of vertex indices, got shape "
            f"{tuple(e.shape)}.", field=name)
    loop = e[:, 0] == e[:, 1]
    if loop.any():
        row = int(np.argmax(loop))
        raise InvalidInputError(
            f"Expected `{name}` to join two distinct vertices, got {e[row].tolist()} at row "
            f"{row}.", field=name)
    if weights is None:
        w = np.ones(e.shape[0])
    else:
        try:
            w = np.asarray(weights, dtype=np.float64)
        except (TypeError, ValueError):
            raise InvalidInputError(
                f"Expected `weights` to be an ({e.shape[0]},) array of numbers, got "
                f"{type(weights).__name__}.", field="weights") from None
        if w.shape != (e.shape[0],):
            raise InvalidInputError(
                f"Expected `weights` to be an ({e.shape[0]},) array, one per edge, got shape "
                f"{tuple(w.shape)}.", field="weights")
        bad = ~np.isfinite(w)
        if bad.any():
            row = int(np.argmax(bad))
            raise InvalidInputError(
                f"Expected `weights` to hold finite numbers, got {float(w[row])!r} at "
                f"position {row}.",
                field="weights")
    return graph_from_pairs(n, e[:, 0], e[:, 1], w)


def nearest_sorted(points: Any, m: int, *, tree: cKDTree | None = None,
                   name: str = "points") -> KnnQuery:
    """Each point's ``m`` nearest points (itself among them), ties broken by index.

    The rows are sorted by distance, and equal distances by index: among points tied at
    the ``m``-th distance the lower indices are kept, whatever the kd-tree's traversal,
    so data with tied distances (integer pixels, grids) gives one graph on every machine.

    scikit-learn has no such rule: which of the tied candidates its heap keeps depends on
    the search (kd-tree, ball tree, brute force), and for brute force on the number of
    threads. Measured on its digits (1,797 points, 11 nearest counting the point): brute
    force with 1 and with 2 threads disagree on 30 neighbour sets, brute force and the
    kd-tree on 32 to 38, ours and each of them on 15 to 34. Isomap's 2-D embedding of the
    digits (10 neighbours) then differs from scikit-learn's by a Procrustes disparity of
    3.0e-5 (its 1-thread run) and 2.3e-4 (2 threads), while its two runs differ by 2.4e-4;
    given the same graph (scikit-learn's ``metric="precomputed"``), the embeddings agree
    to rounding.

    Parameters
    ----------
    points : (n, d) float array
    m : int
        Neighbours per point, counting the point itself; ``1 <= m <= n``.
    tree : cKDTree, optional
        A kd-tree of ``points``, built when omitted.
    name : str, default "points"

    Returns
    -------
    dist, idx : (n, m) float array, (n, m) int array
        Distances and indices of each row's ``m`` nearest, in that order.

    Examples
    --------
    >>> d, i = nearest_sorted([[0.0], [1.0], [-1.0], [3.0]], 2)
    >>> i.tolist()
    [[0, 1], [1, 0], [2, 0], [3, 1]]
    """
    x = as_points(points, name=name)
    n = x.shape[0]
    tree = cKDTree(x) if tree is None else tree
    q = min(m + 1, n)   # one more, to see whether the m-th distance is tied beyond
    dist, idx = typing.cast(KnnQuery, tree.query(x, k=q))
    dist, idx = dist.reshape(n, q), idx.reshape(n, q)
    tied = np.flatnonzero(dist[:, m - 1] == dist[:, m]) if q > m else np.zeros(0, np.intp)
    dist, idx = dist[:, :m], idx[:, :m]
    inner = np.flatnonzero(np.any(dist[:, 1:] == dist[:, :-1], axis=1))  # ties inside
    if inner.size:
        order = np.lexsort((idx[inner], dist[inner]), axis=-1)
        dist[inner] = np.take_along_axis(dist[inner], order, axis=1)
        idx[inner] = np.take_along_axis(idx[inner], order, axis=1)
    if tied.size:  # every point tied at the m-th distance is a candidate: lowest indices win
        reach = np.nextafter(dist[tied, m - 1], np.inf)
        lists = tree.query_ball_point(x[tied], reach)
        for row, cand in zip(tied, lists, strict=True):
            c = np.asarray(cand, dtype=np.intp)
            dc = np.sqrt(np.sum((x[c] - x[row]) ** 2, axis=1))
            pick = np.lexsort((c, dc))[:m]
            dist[row], idx[row] = dc[pick], c[pick]
    return dist, idx


def knn_graph(points: Any, k: int, *, mode: Literal["union", "mutual"] = "union",
              include_self: bool = False, name: str = "points") -> sp.csr_array:
    """The k-nearest-neighbour graph, with distances as edge values.

    Parameters
    ----------
    points : (n, d) float array
    k : int
        Neighbours per point, ``1 <= k <= n - 1``.
    mode : {"union", "mutual"}, default "union"
        ``"union"``: ``i ~ j`` when either is among the other's ``k`` nearest (every point
        keeps at least ``k`` neighbours); ``"mutual"``: when both are (points may end up
        isolated).
    include_self : bool, default False
        Whether the point itself counts among its ``k`` nearest (scikit-learn's
        ``kneighbors_graph(..., include_self=True)``, used by its ``SpectralClustering``
        and ``SpectralEmbedding``): each point then has ``k - 1`` other neighbours. The
        graph never stores the diagonal (no Laplacian counts it). Without it, a point is
        not its own neighbour (scikit-learn's ``include_self=False``, used by ``Isomap``).
    name : str, default "points"

    Returns
    -------
    (n, n) csr_array
        Symmetric; entry ``(i, j)`` is ``‖p_i - p_j‖`` (explicit zeros for coincident points).
        Equals ``sklearn.neighbors.kneighbors_graph(points, k, mode="distance",
        include_self=include_self)`` without its diagonal, symmetrised by maximum (union)
        or minimum of structure (mutual); ties among equidistant neighbours are broken by
        index (:func:`nearest_sorted`), where scikit-learn's choice depends on its search
        and thread count.

    Raises
    ------
    InvalidInputError
        Bad ``points`` (see :func:`~algorithms.core.validation.as_points`), ``k`` outside
        ``[1, n - 1]``, unknown ``mode``.
    """
    x = as_points(points, name=name, min_points=2)
    n = x.shape[0]
    k = as_int(k, name="k", minimum=1, maximum=n - 1, reason=f"the number of `{name}` minus one")
    as_choice(mode, ("union", "mutual"), name="mode")
    m = k if include_self else k + 1
    dist, idx = nearest_sorted(x, m)
    own = idx == np.arange(n)[:, None]
    if not include_self:
        # drop each point itself; where coincident points of lower index hid it, drop the
        # first (nearest) column, as scikit-learn's kneighbors does
        missing = ~own.any(axis=1)
        own[missing, 0] = True
    keep = ~own
    i = np.repeat(np.arange(n), keep.sum(axis=1))
    j = idx[keep]
    d = dist[keep]
    if mode == "union":
        return graph_from_pairs(n, i, j, d)
    keys = i * n + j
    back = j * n + i
    both = np.isin(keys, back)
    return graph_from_pairs(n, i[both], j[both], d[both])


def radius_graph(points: Any, r: float, *, name: str = "points") -> sp.csr_array:
    """Every pair of points at distance at most ``r``, with distances as edge values.

    Parameters
    ----------
    points : (n, d) float array
    r : float
        The radius, ``r > 0``.
    name : str, default "points"

    Returns
    -------
    (n, n) csr_array
        Symmetric, zero diagonal; explicit zeros for coincident points. Equals
        ``sklearn.neighbors.radius_neighbors_graph(points, r, mode="distance")``.

    Raises
    ------
    InvalidInputError
        Bad ``points`` or ``r`` not a positive number.
    """
    x = as_points(points, name=name)
    r = as_float(r, name="r", minimum=0.0, inclusive=False)
    n = x.shape[0]
    pairs = cKDTree(x).query_pairs(r, output_type="ndarray")
    if pairs.size == 0:
        return sp.csr_array((n, n), dtype=np.float64)
    d = np.linalg.norm(x[pairs[:, 0]] - x[pairs[:, 1]], axis=1)
    return graph_from_pairs(n, pairs[:, 0], pairs[:, 1], d)


def weight(adjacency: Any, kind: Literal["uniform", "distance", "heat"] = "uniform", *,
           sigma: float | None = None, name: str = "points") -> sp.csr_array:
    r"""Turn edge lengths into edge weights.

    Parameters
    ----------
    adjacency : (n, n) sparse array
        A graph whose stored entries are edge lengths (:func:`knn_graph`,
        :func:`radius_graph`, or :func:`edge_graph` with lengths).
    kind : {"uniform", "distance", "heat"}, default "uniform"
        ``"uniform"``: :math:`w = 1`; ``"distance"``: :math:`w = 1/d` (inverse distance:
        near neighbours pull harder); ``"heat"``: :math:`w = e^{-d^2 / (2\sigma^2)}`.
    sigma : float, optional
        The heat kernel's width, ``> 0``; the mean edge length when omitted.
    name : str, default "points"
        The input to blame for a zero length with ``"distance"``.

    Returns
    -------
    (n, n) csr_array
        Same structure as ``adjacency``, new values.

    Raises
    ------
    InvalidInputError
        Unknown ``kind``; ``sigma`` not positive; a negative or non-finite length.
    DegenerateInputError
        A zero length with ``kind="distance"`` (coincident points: infinite weight).

    Examples
    --------
    >>> g = edge_graph(3, [[0, 1], [1, 2]], [2.0, 4.0])
    >>> weight(g, "distance").toarray()[1].tolist()
    [0.5, 0.0, 0.25]
    """
    as_choice(kind, ("uniform", "distance", "heat"), name="kind")
    g = sp.csr_array(adjacency, dtype=np.float64, copy=True)
    d = g.data
    bad = ~np.isfinite(d) | (d < 0)
    if bad.any():
        at = int(np.argmax(bad))
        raise InvalidInputError(
            f"Expected `adjacency` to hold finite non-negative edge lengths, got {float(d[at])!r}.",
            field="adjacency")
    if kind == "uniform":
        g.data = np.ones_like(d)
    elif kind == "distance":
        zero = d == 0
        if zero.any():
            row = np.repeat(np.arange(g.shape[0]), np.diff(g.indptr))
            at = int(np.argmax(zero))
            raise DegenerateInputError(
                f"Expected distinct `{name}` for inverse-distance weights, got points "
                f"{int(row[at])} and {int(g.indices[at])} at distance 0.", field=name)
        g.data = 1.0 / d
    else:
        if sigma is None:
            s = float(d.mean()) if d.size else 1.0
            s = s if s > 0 else 1.0
        else:
            s = as_float(sigma, name="sigma", minimum=0.0, inclusive=False)
        g.data = np.exp(-(d * d) / (2.0 * s * s))
    return g


def check_neighbour_params(n: int, neighbors: str, n_neighbors: Any, radius: Any, *,
                           name: str = "points") -> None:
    """What a ``"knn"`` or ``"radius"`` graph of ``n`` points needs from its parameters:
    ``n_neighbors`` that fits them (when given: some methods choose it themselves), and a
    ``radius``. The one check of :func:`neighbour_graph`, the methods that build their own
    graphs, and the service's checks before a job is queued."""
    if neighbors == "knn" and n_neighbors is not None:
        check_n_neighbors(n, n_neighbors, name=name)
    if neighbors == "radius" and radius is None:
        raise InvalidInputError("Expected `radius` with neighbors='radius', got none.",
                                field="radius")


def check_neighbour_graph(points: Any, neighbors: str = "knn", n_neighbors: Any = None,
                          radius: Any = None, *, min_points: int = 2) -> FloatArray:
    """Points for a neighbour graph: at least ``min_points`` of them (:func:`as_points`)
    and graph parameters that fit them (:func:`check_neighbour_params`). Returns the
    points."""
    x = as_points(points, name="points", min_points=min_points)
    check_neighbour_params(x.shape[0], neighbors, n_neighbors, radius)
    return x


def check_n_neighbors(n: int, n_neighbors: Any, *, name: str = "points") -> int:
    """Check ``n_neighbors`` for a kNN graph of ``n`` points and return it as an ``int``.

    Parameters
    ----------
    n : int
        The number of points.
    n_neighbors : int
        Neighbours per point, ``1 <= n_neighbors <= n - 1`` (a point is not its own
        neighbour).
    name : str, default "points"
        Names the points in the error.

    Returns
    -------
    int

    Raises
    ------
    InvalidInputError
        ``n_neighbors`` not an integer, below 1 or above ``n - 1`` (field ``n_neighbors``).

    Examples
    --------
    >>> check_n_neighbors(6, 5.0)
    5
    """
    k = as_int(n_neighbors, name="n_neighbors", minimum=1)
    if k > n - 1:
        raise InvalidInputError(
            f"Expected `n_neighbors` to be an integer <= {n - 1}, at most the number of "
            f"`{name}` minus one, got {k}; give more points or fewer neighbours.",
            field="n_neighbors")
    return k


def check_connected(graph: Any, *, neighbors: str, method: str) -> None:
    """Raise unless a symmetric graph is connected, naming its number of components.

    Every neighbourhood-graph embedding (Isomap, Laplacian eigenmaps, LPP, LLE) would
    otherwise return unrelated pieces: Isomap infinite geodesic distances, the spectral
    methods one zero eigenvalue per component.

    Parameters
    ----------
    graph : (n, n) sparse array
        Symmetric; its stored entries (explicit zeros included) are the edges.
    neighbors : {"knn", "radius", "all"}
        How the graph was built: the error names the parameter to increase
        (``n_neighbors``, ``radius``; ``points`` otherwise).
    method : str
        The method named in the error, e.g. ``"isomap"``.

    Raises
    ------
    DegenerateInputError
        More than one connected component.

    Examples
    --------
    >>> check_connected(edge_graph(3, [[0, 1], [1, 2]]), neighbors="knn", method="isomap")
    """
    count = int(connected_components(graph, directed=False)[0])
    if count > 1:
        field = {"knn": "n_neighbors", "radius": "radius"}.get(neighbors, "points")
        hint = {"knn": "increase `n_neighbors`", "radius": "increase `radius`"}.get(
            neighbors, "the points")
        raise DegenerateInputError(
            f"Expected a connected neighbourhood graph for {method}, got {count} connected "
            f"components ({hint}, or embed each part on its own).", field=field)


def neighbour_graph(points: Any, *, neighbors: str, n_neighbors: Any = None,
                    radius: Any = None, weighting: str | None = None, sigma: Any = None,
                    connected: str | None = None, include_self: bool = False,
                    name: str = "points") -> sp.csr_array:
    r"""The symmetric neighbourhood graph of a point cloud for the shared graph parameters.

    The parameters have the same names in every point-cloud method (spectral and Markov
    clustering, Isomap, Laplacian eigenmaps, LPP) and in the service.

    Parameters
    ----------
    points : (n, d) float array
    neighbors : {"knn", "radius", "all"}
        ``"knn"``: each point to its ``n_neighbors`` nearest, symmetrised by union
        (:func:`knn_graph`); ``"radius"``: every pair within ``radius``
        (:func:`radius_graph`); ``"all"``: every pair (at most :data:`MAX_COMPLETE` points).
    n_neighbors : int, optional
        Required with ``"knn"``: ``1 <= n_neighbors <= n - 1`` (:func:`check_n_neighbors`).
    radius : float, optional
        Required with ``"radius"``: ``radius > 0``.
    weighting : {"uniform", "distance", "heat"}, optional
        The edge weights (:func:`weight`): :math:`1`, :math:`1/d` or
        :math:`e^{-d^2/(2\sigma^2)}`. Omitted: the edge lengths :math:`d` themselves.
    sigma : float, optional
        The heat kernel's width, ``> 0``; the mean edge length when omitted. Checked
        whatever the ``weighting``.
    connected : str, optional
        Require a connected graph (:func:`check_connected`, checked before weighting),
        naming this method in the error; no check when omitted.
    include_self : bool, default False
        With ``"knn"``: whether each point counts among its own ``n_neighbors`` nearest
        (:func:`knn_graph`), as scikit-learn's spectral methods count it.
    name : str, default "points"
        Names the points in errors.

    Returns
    -------
    (n, n) csr_array
        Symmetric, zero diagonal, sorted indices; coincident points are joined by explicit
        zero-length edges when ``weighting`` is omitted.

    Raises
    ------
    InvalidInputError
        Unknown ``neighbors`` or ``weighting``; ``n_neighbors``, ``radius`` or ``sigma``
        missing or out of range; more than :data:`MAX_COMPLETE` points with ``"all"``.
    DegenerateInputError
        A split graph when ``connected`` is given; coincident points with
        ``weighting="distance"``.

    Examples
    --------
    >>> g = neighbour_graph([[0, 0], [1, 0], [3, 0]], neighbors="knn", n_neighbors=1)
    >>> g.toarray().tolist()
    [[0.0, 1.0, 0.0], [1.0, 0.0, 2.0], [0.0, 2.0, 0.0]]
    >>> neighbour_graph([[0, 0], [1, 0], [3, 0]], neighbors="all",
    ...                 weighting="distance").toarray()[0].tolist()
    [0.0, 1.0, 0.3333333333333333]
    """
    neighbors = as_choice(neighbors, NEIGHBORS, name="neighbors")
    if weighting is not None:
        weighting = as_choice(weighting, WEIGHTINGS, name="weighting")
    if sigma is not None:
        sigma = as_float(sigma, name="sigma", minimum=0.0, inclusive=False)
    x = as_points(points, name=name)
    n = x.shape[0]
    if neighbors == "knn":
        g = knn_graph(x, check_n_neighbors(n, n_neighbors, name=name),
                      include_self=include_self, name=name)
    elif neighbors == "radius":
        check_neighbour_params(n, neighbors, n_neighbors, radius, name=name)
        g = radius_graph(x, as_float(radius, name="radius", minimum=0.0, inclusive=False),
                         name=name)
    else:
        if n > MAX_COMPLETE:
            raise InvalidInputError(
                f"Expected at most {MAX_COMPLETE:,} `{name}` with neighbors='all' (a dense n×n "
                f"graph), got {n:,}; use neighbors='knn'.", field="neighbors")
        d = squareform(pdist(x)) if n > 1 else np.zeros((n, n))
        iu = np.triu_indices(n, 1)
        vals = d[iu]
        del d
        # every pair is an edge: coincident pairs stay as explicit zero lengths
        g = sp.csr_array((np.concatenate([vals, vals]),
                          (np.concatenate([iu[0], iu[1]]), np.concatenate([iu[1], iu[0]]))),
                         shape=(n, n))
        g.sort_indices()
    if connected is not None:
        check_connected(g, neighbors=neighbors, method=connected)
    if weighting is None:
        return g
    # checked against WEIGHTINGS above (as_choice returns it as a plain str)
    return weight(g, typing.cast(GraphWeighting, weighting), sigma=sigma, name=name)
