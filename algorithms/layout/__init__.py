"""Layout ("drawing"): positions for the vertices of a mesh or the nodes of a graph with
some of them pinned (``laplacian``, ``poisson``), or for points known only by their pairwise
distances (``mds``, ``stress``).

The checks of the alternative inputs (:func:`mesh_or_graph`, :func:`distance_source`) and
of distance matrices (:func:`as_distance_matrix`, :func:`distance_pairs_matrix`) are public,
so that a caller (the service) can refuse a request before running it with the very checks
and messages of the methods. :class:`~algorithms.core.graphs.Graph`, the graph input of
every layout, is re-exported from :mod:`algorithms.core.graphs`.
"""

from algorithms.core.graphs import Graph
from algorithms.layout._inputs import (
    as_distance_matrix,
    check_distances,
    distance_pairs_matrix,
    distance_source,
    mesh_or_graph,
)
from algorithms.layout.laplacian import LaplacianLayoutResult, check_laplacian, laplacian
from algorithms.layout.mds import MDSResult, mds
from algorithms.layout.poisson import PoissonLayoutResult, check_poisson, poisson
from algorithms.layout.stress import StressResult, check_stress, stress

__all__ = [
    "Graph",
    "LaplacianLayoutResult",
    "laplacian",
    "MDSResult",
    "mds",
    "PoissonLayoutResult",
    "poisson",
    "StressResult",
    "stress",
    "mesh_or_graph",
    "distance_source",
    "as_distance_matrix",
    "distance_pairs_matrix",
    "check_distances",
    "check_laplacian",
    "check_poisson",
    "check_stress",
]
