"""Assignment: correspondences between two point sets (who pairs with whom)."""

from algorithms.assignment._dense import MAX_COST_ENTRIES, METRICS, check_cost_size, check_dense
from algorithms.assignment.bipartite import BipartiteResult, bipartite
from algorithms.assignment.closest_pair import ClosestPairResult, closest_pair
from algorithms.assignment.distance import DistanceResult, distance
from algorithms.assignment.nearest import DIRECTIONS, NearestResult, nearest
from algorithms.assignment.optimal_transport import (
    TRANSPORT_METHODS,
    TransportResult,
    check_transport,
    optimal_transport,
)

__all__ = [
    "DIRECTIONS",
    "MAX_COST_ENTRIES",
    "METRICS",
    "TRANSPORT_METHODS",
    "BipartiteResult",
    "ClosestPairResult",
    "DistanceResult",
    "NearestResult",
    "TransportResult",
    "bipartite",
    "check_cost_size",
    "check_dense",
    "check_transport",
    "closest_pair",
    "distance",
    "nearest",
    "optimal_transport",
]
