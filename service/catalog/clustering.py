"""Catalog entries of the clustering family (a partition of unlabelled points or of a graph).

The classification family's entries (labelled points) are registered by
:mod:`service.catalog.classification`, imported below.
"""

from __future__ import annotations

from typing import Literal

from pydantic import Field, model_validator

from algorithms.clustering import (
    MarkovClusteringResult,
    SpectralClusteringResult,
    markov,
    spectral,
)
from algorithms.core.errors import InvalidInputError
from algorithms.core.graphs import check_n_neighbors
from service.catalog.base import Params
from service.catalog.inputs import GraphInput, Points
from service import scenes
from service.catalog.registry import Process, registry

_TWO_GROUPS = [[0, 0], [0, 1], [1, 0], [1, 1], [10, 10], [10, 11], [11, 10], [11, 11]]
_NEIGHBORS = ("The neighbour graph: each point joined to its n_neighbors nearest (union of "
              "the two directions), to every point within radius, or to every point.")
_WEIGHTING = ("Edge weights: 1 (uniform), 1/d (distance) or the heat kernel exp(−d²/2σ²).")


class _GraphParams(Params):
    neighbors: Literal["knn", "radius", "all"] = Field("knn", description=_NEIGHBORS)
    n_neighbors: int = Field(10, ge=1, description="Neighbours per point with "
                             "neighbors='knn'; at most the number of points minus one.")
    radius: float | None = Field(None, gt=0, description="The radius with "
                                 "neighbors='radius' (required there).")
    weighting: Literal["uniform", "distance", "heat"] = Field("uniform",
                                                             description=_WEIGHTING)
    sigma: float | None = Field(None, gt=0, description="The heat kernel's width σ; the "
                                "mean edge length by default.")

    def _check_graph(self, n: int) -> None:
        if self.neighbors == "knn":
            check_n_neighbors(n, self.n_neighbors)
        if self.neighbors == "radius" and self.radius is None:
            raise InvalidInputError("Expected `radius` with neighbors='radius', got none.",
                                    field="radius")


# -- clustering.spectral ---------------------------------------------------------------------
class SpectralParams(_GraphParams):
    points: Points = Field(description="The points to cluster, (n, d), n ≥ 2.",
                           examples=[_TWO_GROUPS])
    n_clusters: int = Field(8, ge=1, description="The number of clusters k, at most n.",
                            examples=[2])
    n_neighbors: int = Field(10, ge=1, description="Neighbours per point with "
                             "neighbors='knn'; at most the number of points minus one.",
                             examples=[3])
    n_init: int = Field(10, ge=1, le=1000, description="k-means++ starts; the one with the "
                        "least inertia is kept.")
    seed: int = Field(0, ge=0, description="Seeds k-means++; the same seed gives the same "
                      "labels.")

    @model_validator(mode="after")
    def _sizes(self) -> SpectralParams:
        n = self.points.shape[0]
        if n < 2:
            raise InvalidInputError(f"Expected `points` to hold at least 2 points, got {n}.",
                                    field="points")
        if self.n_clusters > n:
            raise InvalidInputError(f"Expected `n_clusters` to be at most the number of "
                                    f"points ({n}), got {self.n_clusters}.",
                                    field="n_clusters")
        self._check_graph(n)
        return self


registry.add(Process(
    id="clustering.spectral",
    geometry=scenes.clusters,
    title="Spectral clustering (Ng, Jordan, Weiss)",
    description="k-means (k-means++ seeding, seeded) on the bottom eigenvectors of the "
    "symmetric normalised Laplacian of the points' neighbour graph, rows scaled to unit "
    "length. Reports labels, cluster sizes, the embedding and its eigenvalues.",
    function=spectral,
    params=SpectralParams,
    result=SpectralClusteringResult,
    reference="Ng, A. Y., Jordan, M. I., Weiss, Y. (2001). On spectral clustering: analysis "
    "and an algorithm. NIPS 14.",
    keywords=("spectral clustering", "normalized cut", "k-means", "graph laplacian",
              "clustering"),
))


# -- clustering.markov -----------------------------------------------------------------------
class MarkovParams(_GraphParams):
    points: Points | None = Field(None, description="Points whose neighbour graph is "
                                  "clustered, (n, d). Exactly one of points and graph.",
                                  examples=[_TWO_GROUPS])
    graph: GraphInput | None = Field(None, description="A graph {nodes, edges, weights?} "
                                     "clustered as it is (non-negative weights, default 1).")
    n_neighbors: int = Field(10, ge=1, description="Neighbours per point with "
                             "neighbors='knn'; at most the number of points minus one.",
                             examples=[3])
    expansion: int = Field(2, ge=2, le=10, description="The power e of the expansion Mᵉ.")
    inflation: float = Field(2.0, gt=1, le=20, description="The elementwise power r of "
                             "the inflation; larger gives more, smaller clusters.")
    self_loops: float = Field(1.0, ge=0, description="Weight added on the diagonal before "
                              "normalising (0: none).")
    pruning_threshold: float = Field(1e-4, ge=0, lt=1, description="Entries below this are "
                                     "dropped after each inflation.")
    max_iterations: int = Field(100, ge=1, le=10_000, description="Most expansion-inflation "
                                "rounds.")
    tolerance: float = Field(1e-6, ge=0, description="Stop when no entry changes by more "
                             "than this.")

    @model_validator(mode="after")
    def _one_input(self) -> MarkovParams:
        if (self.points is None) == (self.graph is None):
            got = "none" if self.points is None else "both"
            raise InvalidInputError(f"Expected exactly one of `points` and `graph`, got "
                                    f"{got}.", field="points" if self.points is None
                                    else "graph")
        if self.points is not None:
            n = self.points.shape[0]
            if n < 2:
                raise InvalidInputError(f"Expected `points` to hold at least 2 points, got "
                                        f"{n}.", field="points")
            self._check_graph(n)
        return self


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
    params=MarkovParams,
    result=MarkovClusteringResult,
    reference="van Dongen, S. (2000). Graph clustering by flow simulation. PhD thesis, "
    "University of Utrecht.",
    long=True,
    keywords=("mcl", "markov clustering", "graph clustering", "community detection",
              "random walk"),
))
