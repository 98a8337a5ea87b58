"""Catalog entries of the assignment family (finding correspondences)."""

from __future__ import annotations

from typing import Literal

from pydantic import Field, model_validator

from algorithms.assignment import (
    BipartiteResult,
    ClosestPairResult,
    DistanceResult,
    NearestResult,
    TransportResult,
    bipartite,
    closest_pair,
    distance,
    nearest,
    optimal_transport,
)
from algorithms.assignment._dense import check_cost_size
from algorithms.core.validation import as_weights, same_dim
from service.catalog.base import Params
from service.catalog.inputs import Points, Weights
from service.catalog.registry import Process, registry

_SOURCE = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.1]]
_TARGET = [[0.1, 0.0], [2.0, 0.0]]


class NearestParams(Params):
    source: Points = Field(description="Query points: an (n, d) array.",
                           examples=[[[0.0, 0.0], [1.0, 0.0], [2.0, 0.1]]])
    target: Points = Field(description="Reference points: an (m, d) array, same d.",
                           examples=[[[0.1, 0.0], [2.0, 0.0]]])
    k: int = Field(1, ge=1, description="Neighbours per point.")
    direction: Literal["forward", "backward", "union", "intersection", "both"] = Field(
        "forward",
        description="forward: each source point to its k nearest targets; backward: each "
        "target to its k nearest sources; union / intersection (mutual) of both; both: "
        "forward then backward (the distances sum to the Chamfer distance).",
    )
    max_distance: float | None = Field(None, gt=0, description="Drop pairs farther apart.")


registry.add(Process(
    id="assignment.nearest",
    title="Nearest-neighbour assignment (kd-tree)",
    description="Pairs each point with its k nearest neighbours in the other set, in one or "
    "both directions, optionally within a distance.",
    function=nearest,
    params=NearestParams,
    result=NearestResult,
    reference="Bentley, J. L. (1975). Multidimensional binary search trees used for "
    "associative searching. CACM 18(9).",
    fast_path=True,
    keywords=("nearest neighbour", "kd-tree", "correspondences", "chamfer"),
))


class _TwoSets(Params):
    """Two point sets of the same dimension; their sizes may differ."""

    source: Points = Field(description="The first point set: an (n, d) array.",
                           examples=[_SOURCE])
    target: Points = Field(description="The second point set: an (m, d) array, same d; "
                           "m may differ from n.", examples=[_TARGET])

    @model_validator(mode="after")
    def _same_dimension(self) -> _TwoSets:
        same_dim(self.source, self.target, names=("source", "target"))
        return self


class _DenseSets(_TwoSets):
    """Two point sets whose dense n×m cost matrix is built: its size is bounded."""

    @model_validator(mode="after")
    def _bounded(self) -> _DenseSets:
        check_cost_size(self.source.shape[0], self.target.shape[0])
        return self


class ClosestPairParams(_TwoSets):
    pass


registry.add(Process(
    id="assignment.closest_pair",
    title="Closest pair between two point sets (kd-tree)",
    description="The single pair of points, one from each set, at the smallest distance.",
    function=closest_pair,
    params=ClosestPairParams,
    result=ClosestPairResult,
    reference="Bentley, J. L. (1975). Multidimensional binary search trees used for "
    "associative searching. CACM 18(9).",
    fast_path=True,
    keywords=("closest pair", "kd-tree", "minimum distance", "clearance"),
))


class BipartiteParams(_DenseSets):
    metric: Literal["euclidean", "sqeuclidean"] = Field(
        "euclidean", description="The cost of a pair: the Euclidean distance or its square.")
    max_cost: float | None = Field(
        None, gt=0, description="Largest cost of a pair, in the metric's units: points whose "
        "every partner costs more stay unmatched (leaving a point unmatched costs half of "
        "this). Omitted: every point of the smaller set is matched.")


registry.add(Process(
    id="assignment.bipartite",
    title="Optimal one-to-one matching (linear assignment)",
    description="Matches the points of two sets one to one at the least total cost; sets "
    "may differ in size (the surplus stays unmatched), and max_cost leaves far points "
    "single. At most 16 million pairs n·m.",
    function=bipartite,
    params=BipartiteParams,
    result=BipartiteResult,
    reference="Crouse, D. F. (2016). On implementing 2D rectangular assignment algorithms. "
    "IEEE TAES 52(4), 1679–1696.",
    keywords=("hungarian", "linear assignment", "matching", "correspondences"),
))


class OptimalTransportParams(_DenseSets):
    source_weights: Weights | None = Field(
        None, description="Mass of each source point (non-negative, normalised to sum to "
        "1). Omitted: uniform.")
    target_weights: Weights | None = Field(
        None, description="Mass of each target point (non-negative, normalised to sum to "
        "1). Omitted: uniform.")
    method: Literal["exact", "sinkhorn"] = Field(
        "exact", description="exact: the transport linear program (assignment for uniform "
        "masses on equal-size sets); sinkhorn: entropic regularisation, log-domain "
        "iterations.")
    reg: float = Field(0.05, gt=0, description="Sinkhorn's entropic regularisation ε, in "
                       "cost units; smaller is closer to exact but slower.")
    max_iterations: int = Field(1000, ge=1, description="Sinkhorn's iteration limit.")
    tolerance: float = Field(1e-9, gt=0, description="Sinkhorn stops when the L1 error of "
                             "the plan's marginals is at most this.")
    metric: Literal["sqeuclidean", "euclidean"] = Field(
        "sqeuclidean", description="The cost of moving unit mass: squared distance "
        "(2-Wasserstein) or distance (1-Wasserstein, earth mover's).")

    @model_validator(mode="after")
    def _weights_fit(self) -> OptimalTransportParams:
        as_weights(self.source_weights, self.source.shape[0], name="source_weights")
        as_weights(self.target_weights, self.target.shape[0], name="target_weights")
        return self


registry.add(Process(
    id="assignment.optimal_transport",
    title="Optimal transport between weighted point sets (exact or Sinkhorn)",
    description="The transport plan moving the mass of one weighted point set onto another "
    "at the least cost, returned sparse as (source, target, mass) pairs, with its cost "
    "(Wasserstein distance). Exact linear program, or entropic Sinkhorn in the log domain. "
    "At most 16 million pairs n·m.",
    function=optimal_transport,
    params=OptimalTransportParams,
    result=TransportResult,
    reference="Peyré, G. and Cuturi, M. (2019). Computational optimal transport. "
    "Foundations and Trends in Machine Learning 11(5-6).",
    long=False,
    keywords=("wasserstein", "earth mover", "sinkhorn", "transport plan"),
))


class DistanceParams(_TwoSets):
    pass


registry.add(Process(
    id="assignment.distance",
    title="Chamfer, Hausdorff and RMSE distances between point sets",
    description="How far apart two point sets are, from their nearest-neighbour assignment "
    "in both directions: Chamfer (sum and mean), Hausdorff (and both directed halves), "
    "RMSE, and every point's distance to the other set.",
    function=distance,
    params=DistanceParams,
    result=DistanceResult,
    reference="Huttenlocher, D. P., Klanderman, G. A. and Rucklidge, W. J. (1993). "
    "Comparing images using the Hausdorff distance. IEEE TPAMI 15(9).",
    fast_path=True,
    keywords=("chamfer", "hausdorff", "rmse", "set distance"),
))
