"""Catalog entries of the clustering family (a partition of unlabelled points or of a graph;
labelled points are the classification family's)."""

from __future__ import annotations

from typing import Any

from algorithms.clustering import markov, spectral
from algorithms.core.errors import InvalidInputError
from algorithms.core.graphs import check_neighbour_params
from algorithms.core.params import Le
from algorithms.core.validation import as_int, check_min_points
from service import scenes
from service.catalog.registry import Process, registry

_TWO_GROUPS = [[0, 0], [0, 1], [1, 0], [1, 1], [10, 10], [10, 11], [11, 10], [11, 11]]


def _neighbour_graph(p: Any) -> None:
    """At least 2 points, and neighbour-graph parameters that fit them."""
    check_min_points(p.points, 2, name="points")
    check_neighbour_params(p.points.shape[0], p.neighbors, p.n_neighbors, p.radius)


def _clusters_fit(p: Any) -> None:
    """n_clusters at most the number of points, as for any neighbour graph of them."""
    check_min_points(p.points, 2, name="points")
    as_int(p.n_clusters, name="n_clusters", minimum=1, maximum=p.points.shape[0],
           reason="the number of `points`")
    _neighbour_graph(p)


def _points_or_graph(p: Any) -> None:
    """Exactly one of points and graph; for points, as for any neighbour graph."""
    if (p.points is None) == (p.graph is None):
        got = "none" if p.points is None else "both"
        raise InvalidInputError(f"Expected exactly one of `points` and `graph`, got {got}.",
                                field="points" if p.points is None else "graph")
    if p.points is not None:
        _neighbour_graph(p)


registry.add(Process(
    id="clustering.spectral",
    geometry=scenes.clusters,
    title="Spectral clustering (Ng, Jordan, Weiss)",
    description="k-means (k-means++ seeding, seeded) on the bottom eigenvectors of the "
    "symmetric normalised Laplacian of the points' neighbour graph, rows scaled to unit "
    "length. Reports labels, cluster sizes, the embedding and its eigenvalues.",
    function=spectral,
    examples={"points": _TWO_GROUPS, "n_clusters": 2, "n_neighbors": 3},
    limits={"n_init": Le(1000)},
    check=_clusters_fit,
    keywords=("spectral clustering", "normalized cut", "k-means", "graph laplacian",
              "clustering"),
))

registry.add(Process(
    id="clustering.markov",
    geometry=scenes.clusters,
    title="Markov clustering (MCL)",
    description="Alternates expansion (a matrix power: random-walk steps) and inflation "
    "(elementwise power, columns renormalised) of the column-stochastic matrix of a graph "
    "or of the points' neighbour graph, pruning small entries, until it stops changing; "
    "the attractors name the clusters. The number of clusters follows from the inflation. "
    "Progress per iteration, cancellable.",
    function=markov,
    examples={"points": _TWO_GROUPS, "n_neighbors": 3},
    limits={"expansion": Le(10), "inflation": Le(20), "max_iterations": Le(10_000)},
    check=_points_or_graph,
    long=True,
    keywords=("mcl", "markov clustering", "graph clustering", "community detection",
              "random walk"),
))
