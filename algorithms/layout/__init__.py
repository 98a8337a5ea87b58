"""Layout ("drawing"): positions for the vertices of a mesh or the nodes of a graph with
some of them pinned (``laplacian``, ``poisson``), or for points known only by their pairwise
distances (``mds``, ``stress``)."""

from algorithms.core.graphs import Graph, as_graph
from algorithms.layout.laplacian import LaplacianLayoutResult, laplacian
from algorithms.layout.mds import MDSResult, mds
from algorithms.layout.poisson import PoissonLayoutResult, poisson
from algorithms.layout.stress import StressResult, stress

__all__ = [
    "Graph",
    "as_graph",
    "LaplacianLayoutResult",
    "laplacian",
    "MDSResult",
    "mds",
    "PoissonLayoutResult",
    "poisson",
    "StressResult",
    "stress",
]
