r"""Markov clustering (MCL): alternate expansion and inflation of a column-stochastic
matrix until it stops changing; its attractors name the clusters."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Annotated, Any

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from algorithms.clustering._kmeans import canonical_labels
from algorithms.core.errors import ConvergenceWarning, InvalidInputError, warn
from algorithms.core.graphs import (
    GraphWeighting,
    HeatWidth,
    Neighbors,
    NNeighbors,
    Radius,
    as_graph,
    check_neighbour_graph,
    edge_graph,
    neighbour_graph,
)
from algorithms.core.params import Ge, GraphLike, Gt, Interval, PointsLike, validate_params
from algorithms.core.progress import Progress, as_progress
from algorithms.core.types import FloatArray, IntArray

__all__ = ["MarkovClusteringResult", "markov", "check_markov"]


@dataclass(frozen=True, eq=False)
class MarkovClusteringResult:
    """The partition MCL converged to.

    Attributes
    ----------
    labels : (n,) int array
        The cluster of each point (node), numbered in order of first appearance.
    sizes : (n_clusters,) int array
        The number of points in each cluster.
    n_clusters : int
        The number of clusters found (MCL chooses it; ``inflation`` steers it).
    attractors : (a,) int array
        The points whose row keeps mass at convergence (non-zero diagonal), ascending.
    iterations : int
        Expansion-inflation rounds run.
    converged : bool
        False when ``max_iterations`` ran out before the matrix changed by less than
        ``tolerance`` (a ``ConvergenceWarning`` is issued; the labels are then read from
        the last matrix).
    """

    labels: IntArray
    sizes: IntArray
    n_clusters: int
    attractors: IntArray
    iterations: int
    converged: bool


@validate_params
def markov(
    points: PointsLike | None = None,
    *,
    graph: GraphLike | None = None,
    neighbors: Neighbors = "knn",
    n_neighbors: NNeighbors = 10,
    radius: Radius | None = None,
    weighting: GraphWeighting = "uniform",
    sigma: HeatWidth | None = None,
    expansion: Annotated[int, Ge(2)] = 2,
    inflation: Annotated[float, Gt(1)] = 2.0,
    self_loops: Annotated[float, Ge(0)] = 1.0,
    pruning_threshold: Annotated[float, Interval(ge=0, lt=1)] = 1e-4,
    max_iterations: Annotated[int, Ge(1)] = 100,
    tolerance: Annotated[float, Ge(0)] = 1e-6,
    progress: Progress | None = None,
) -> MarkovClusteringResult:
    r"""Markov clustering (MCL).

    Alternates expansion (a matrix power: random-walk steps) and inflation (elementwise power,
    columns renormalised) of the column-stochastic matrix of a graph or of the points' neighbour
    graph, pruning small entries, until it stops changing; the attractors name the clusters. The
    number of clusters follows from the inflation. Progress per iteration, cancellable.

    From the weighted adjacency :math:`A` with self-loops added, the column-stochastic
    matrix :math:`M = A D^{-1}` (a random walk's transition probabilities) is iterated:

    * expansion :math:`M \leftarrow M^e` (``e`` steps of the walk at once);
    * inflation :math:`m_{ij} \leftarrow m_{ij}^r / \sum_i m_{ij}^r` (strong transitions
      get stronger, weak ones fade);
    * pruning: entries below ``pruning_threshold`` are dropped (and each column
      renormalised), which keeps :math:`M` sparse;

    until :math:`\max_{ij} |M_t - M_{t-1}| <` ``tolerance``. The limit is idempotent: the
    rows with mass on the diagonal are the *attractors*, and every column puts its mass on
    the attractors of its cluster. Each point joins the attractor holding most of its
    column (lowest index on ties); attractors that share mass form one cluster.

    Parameters
    ----------
    points : (n, d) float array, optional
        Points whose neighbour graph is clustered, ``n >= 2``. Exactly one of ``points``
        and ``graph``.
    graph : Graph or mapping, optional
        Instead of ``points``: a graph ``{"nodes": n, "edges": (e, 2), "weights"?: (e,)}``
        with non-negative weights (default 1), clustered as it is.
    neighbors : {"knn", "radius", "all"}, default "knn"
        The neighbour graph of ``points``: ``"knn"`` joins each point to its
        ``n_neighbors`` nearest (the union of the two directions), ``"radius"`` to every
        point within ``radius``, ``"all"`` to every point (at most 10,000 points).
    n_neighbors : int, default 10
        Neighbours per point with ``neighbors="knn"``, other points only (MCL adds its own
        self-loops; its reference implementations take a graph, not points, so there is
        no peer count to follow, unlike :func:`spectral`'s); at most the number of points
        minus one.
    radius : float, optional
        The radius with ``neighbors="radius"``, required there.
    weighting : {"uniform", "distance", "heat"}, default "uniform"
        Edge weights of the neighbour graph from the edge lengths :math:`d`: ``"uniform"``
        1, ``"distance"`` :math:`1/d`, or ``"heat"`` the heat kernel
        :math:`\exp(-d^2/2\sigma^2)`, which suits MCL best where distances vary.
    sigma : float, optional
        The heat kernel's width :math:`\sigma`; the mean edge length when omitted.
    expansion : int, default 2
        The power ``e >= 2`` of the expansion, the walk's steps per round.
    inflation : float, default 2.0
        The elementwise power ``r > 1`` of the inflation; larger gives more, smaller
        clusters.
    self_loops : float, default 1.0
        Weight added on the diagonal of :math:`A` before normalising (van Dongen's
        recommendation; avoids parity oscillations). 0 adds none.
    pruning_threshold : float, default 1e-4
        Entries of :math:`M` below this are set to zero after each inflation (a column's
        largest entry is always kept), in ``[0, 1)``.
    max_iterations : int, default 100
        Most expansion-inflation rounds.
    tolerance : float, default 1e-6
        Stop when no entry of :math:`M` changes by ``tolerance`` or more in a round.
    progress : callable, optional
        ``progress(iteration, max_iterations, message)`` after each iteration; may raise
        :class:`~algorithms.core.errors.Cancelled`.

    Returns
    -------
    MarkovClusteringResult
        ``labels``, ``sizes``, ``n_clusters``, ``attractors``, ``iterations``,
        ``converged``.

    Raises
    ------
    InvalidInputError
        Neither or both of ``points`` and ``graph``; a malformed graph; bad points or
        neighbour parameters (``n_neighbors`` above ``n - 1``); ``expansion < 2``;
        ``inflation <= 1``; a negative ``self_loops``; a node without any edge and
        ``self_loops=0`` (its column cannot be normalised).
    Cancelled
        Raised by ``progress``.

    Notes
    -----
    **Inflation is what clusters.** MCL is sometimes read as the adjacency matrix raised
    to an infinite power, the final distribution of a random walk of infinitely many
    steps. Pure powers converge to the stationary distribution of each connected
    component: one cluster per component, whatever its structure. Inflation is what
    keeps the walk from mixing across weakly joined groups; the clusters are read from
    the attractors of that limit.

    Disconnected graphs need no special handling: no mass ever crosses between components,
    so each component is clustered on its own.

    Cost per iteration: one sparse matrix product (the expansion) on the pruned matrix.

    References
    ----------
    .. [1] S. van Dongen, "Graph clustering by flow simulation", PhD thesis, University of
       Utrecht, 2000.
    .. [2] A. J. Enright, S. van Dongen, C. A. Ouzounis, "An efficient algorithm for
       large-scale detection of protein families", Nucleic Acids Research 30(7), 2002.

    Examples
    --------
    >>> g = {"nodes": 6, "edges": [[0, 1], [1, 2], [0, 2], [3, 4], [4, 5], [3, 5], [2, 3]]}
    >>> res = markov(graph=g)
    >>> res.labels.tolist(), res.sizes.tolist()
    ([0, 0, 0, 1, 1, 1], [3, 3])
    """
    report = as_progress(progress)
    a = _adjacency(points, graph, neighbors=neighbors, n_neighbors=n_neighbors, radius=radius,
                   weighting=weighting, sigma=sigma)
    name = "points" if graph is None else "graph"
    n = a.shape[0]
    if self_loops > 0:
        a = (a + self_loops * sp.eye_array(n, format="csr")).tocsr()
    col = np.asarray(a.sum(axis=0)).ravel()
    if (col <= 0).any():
        i = int(np.argmax(col <= 0))
        raise InvalidInputError(
            f"Expected every node of `{name}` to have an edge when self_loops=0, got node {i} "
            "without any; give self_loops > 0.", field=name)
    m = _normalise(a)
    converged = False
    it = 0
    while it < max_iterations:
        prev = m
        for _ in range(expansion - 1):
            m = (m @ prev).tocsc()
        m = _inflate(m, inflation, pruning_threshold)
        it += 1
        delta = abs(m - prev).max() if m.nnz or prev.nnz else 0.0
        report(it, max_iterations, f"change {delta:.3g}, {m.nnz} non-zeros")
        if delta < tolerance:
            converged = True
            break
    if not converged:
        warn(f"Markov clustering stopped after {it} iterations before the matrix "
             f"changed by less than {tolerance:g}; labels are read from the last matrix.",
             ConvergenceWarning)
    labels, attractors = _read_clusters(m.tocsc())
    labels, _ = canonical_labels(labels)
    sizes = np.bincount(labels)
    return MarkovClusteringResult(
        labels=labels,
        sizes=sizes.astype(np.int64),
        n_clusters=int(sizes.shape[0]),
        attractors=attractors,
        iterations=it,
        converged=converged,
    )


def check_markov(points: Any = None, graph: Any = None, neighbors: str = "knn",
                 n_neighbors: Any = None, radius: Any = None) -> FloatArray | None:
    """Check the inputs of :func:`markov`: exactly one of ``points`` and ``graph``; points
    for a neighbour graph (:func:`~algorithms.core.graphs.check_neighbour_graph`). Returns
    the points, or None for a graph."""
    if (points is None) == (graph is None):
        got = "none" if points is None else "both"
        raise InvalidInputError(f"Expected exactly one of `points` and `graph`, got {got}.",
                                field="points" if points is None else "graph")
    if points is None:
        return None
    return check_neighbour_graph(points, neighbors, n_neighbors, radius)


def _adjacency(points: Any, graph: Any, **kw: Any) -> sp.csr_array:
    x = check_markov(points, graph, kw["neighbors"], kw.get("n_neighbors"), kw.get("radius"))
    if x is not None:
        return neighbour_graph(x, **kw)

    g = as_graph(graph, name="graph")
    w = None if g.weights is None else g.weights
    return edge_graph(g.n_nodes, g.edges.reshape(-1, 2), w, name="graph.edges")


def _normalise(m: sp.sparray) -> sp.csc_array:
    a = sp.csc_array(m, dtype=np.float64)
    s: FloatArray = np.asarray(a.sum(axis=0)).ravel()
    inv = np.divide(1.0, s, out=np.zeros_like(s), where=s > 0)
    normalised: sp.csc_array = (a @ sp.diags_array(inv)).tocsc()
    return normalised


def _inflate(m: sp.csc_array, r: float, prune: float) -> sp.csc_array:
    m = m.copy()
    np.power(m.data, r, out=m.data)
    m = _normalise(m)
    if prune > 0:
        # never prune a column's largest entry (a column must keep some mass)
        keep = m.data >= prune
        cols = np.repeat(np.arange(m.shape[1]), np.diff(m.indptr))
        top = np.zeros(m.shape[1])
        np.maximum.at(top, cols, m.data)
        keep |= m.data >= top[cols]
        if not keep.all():
            m.data[~keep] = 0.0
            m.eliminate_zeros()
            m = _normalise(m)
    return m


def _read_clusters(m: sp.csc_array) -> tuple[IntArray, IntArray]:
    """Each column joins the row holding most of its mass; attractors sharing mass merge."""
    n = m.shape[0]
    diag = m.diagonal()
    attractors = np.flatnonzero(diag > 0)
    cols = np.repeat(np.arange(n), np.diff(m.indptr))
    # argmax per column, lowest row on ties (values rounded so equal masses compare equal)
    vals = np.round(m.data, 9)
    order = np.lexsort((m.indices, -vals, cols))
    first = np.ones(order.shape[0], dtype=bool)
    first[1:] = cols[order][1:] != cols[order][:-1]
    owner = np.arange(n)
    owner[cols[order][first]] = m.indices[order][first]
    # link each node to its owner, and attractors that hold mass in each other's columns
    is_att = np.zeros(n, dtype=bool)
    is_att[attractors] = True
    both = is_att[m.indices] & is_att[cols]
    rows = np.concatenate([np.arange(n), m.indices[both]])
    cc = np.concatenate([owner, cols[both]])
    link = sp.csr_array((np.ones(rows.shape[0]), (rows, cc)), shape=(n, n))
    _, labels = connected_components(link, directed=False)
    return labels.astype(np.int64), attractors.astype(np.int64)
