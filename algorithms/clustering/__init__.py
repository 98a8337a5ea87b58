"""Clustering: unlabelled points (or a graph) in, a partition out.

* :func:`spectral` — k-means on the normalised-Laplacian embedding (Ng, Jordan, Weiss);
* :func:`markov` — Markov clustering (MCL) by expansion and inflation.

Both build the neighbour graph of the points with the parameters of
:func:`algorithms.core.graphs.neighbour_graph`, declared alike in both signatures:
``neighbors`` (:data:`~algorithms.core.graphs.Neighbors`: knn, radius, all),
``n_neighbors``, ``radius``, ``weighting``
(:data:`~algorithms.core.graphs.GraphWeighting`: uniform, distance, heat) and
``sigma``.
"""

from algorithms.clustering.markov import MarkovClusteringResult, check_markov, markov
from algorithms.clustering.spectral import SpectralClusteringResult, check_spectral, spectral

__all__ = ["MarkovClusteringResult", "markov", "check_markov", "SpectralClusteringResult",
           "spectral", "check_spectral"]
