"""Catalog entries of the clustering family (a partition of unlabelled points or of a graph;
labelled points are the classification family's)."""

from __future__ import annotations

from algorithms.clustering import check_markov, check_spectral, markov, spectral
from algorithms.core.params import Le
from service import scenes
from service.catalog.registry import Process, registry

_TWO_GROUPS = [[0, 0], [0, 1], [1, 0], [1, 1], [10, 10], [10, 11], [11, 10], [11, 11]]

registry.add(Process(
    spectral, geometry=scenes.clusters, display=("labels",), check=check_spectral,
    limits={"n_init": Le(1000)},
    examples={"points": _TWO_GROUPS, "n_clusters": 2, "n_neighbors": 3},
    keywords=("spectral clustering", "normalized cut", "k-means", "graph laplacian",
              "clustering")))
registry.add(Process(
    markov, geometry=scenes.clusters, display=("labels",), check=check_markov, long=True,
    examples={"points": _TWO_GROUPS, "n_neighbors": 3},
    limits={"expansion": Le(10), "inflation": Le(20), "max_iterations": Le(10_000)},
    keywords=("mcl", "markov clustering", "graph clustering", "community detection",
              "random walk")))
