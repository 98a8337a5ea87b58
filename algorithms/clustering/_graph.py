"""The shared graph parameters of §8 (``neighbors``, ``n_neighbors``, ``radius``,
``weighting``, ``sigma``) turned into a weighted adjacency matrix by the core builders."""

from __future__ import annotations

from typing import Any

import numpy as np
import scipy.sparse as sp
from scipy.spatial.distance import pdist, squareform

from algorithms.core.errors import InvalidInputError
from algorithms.core.graphs import knn_graph, radius_graph, weight
from algorithms.core.types import FloatArray
from algorithms.core.validation import as_choice, as_float, as_int

__all__ = ["NEIGHBORS", "WEIGHTINGS", "neighbour_graph", "check_neighbours"]

#: Accepted values of ``neighbors`` and ``weighting``.
NEIGHBORS = ("knn", "radius", "all")
WEIGHTINGS = ("uniform", "distance", "heat")

#: Most points for ``neighbors="all"`` (a dense n×n graph).
MAX_COMPLETE = 10_000


def check_neighbours(n: int, n_neighbors: Any, *, name: str = "points") -> int:
    """``n_neighbors`` as an int in ``[1, n - 1]``, the error naming ``n_neighbors``."""
    k = as_int(n_neighbors, name="n_neighbors", minimum=1)
    if k > n - 1:
        raise InvalidInputError(
            f"Expected `n_neighbors` to be at most the number of `{name}` minus one ({n - 1}), "
            f"got {k}; give more points or fewer neighbours.", field="n_neighbors")
    return k


def neighbour_graph(x: FloatArray, *, neighbors: str, n_neighbors: Any, radius: Any,
                    weighting: str, sigma: Any, name: str = "points") -> sp.csr_array:
    """The symmetric weighted adjacency (zero diagonal) of ``x`` for the shared parameters.

    ``knn``: union of the ``n_neighbors`` nearest; ``radius``: every pair within ``radius``;
    ``all``: every pair. Weights: 1, ``1/d`` or ``exp(-d²/2σ²)`` (σ the mean edge length by
    default).
    """
    neighbors = as_choice(neighbors, NEIGHBORS, name="neighbors")
    weighting = as_choice(weighting, WEIGHTINGS, name="weighting")
    if sigma is not None:
        sigma = as_float(sigma, name="sigma", minimum=0.0, inclusive=False)
    n = x.shape[0]
    if neighbors == "knn":
        k = check_neighbours(n, n_neighbors, name=name)
        g = knn_graph(x, k, name=name)
    elif neighbors == "radius":
        if radius is None:
            raise InvalidInputError("Expected `radius` with neighbors='radius', got none.",
                                    field="radius")
        r = as_float(radius, name="radius", minimum=0.0, inclusive=False)
        g = radius_graph(x, r, name=name)
    else:
        if n > MAX_COMPLETE:
            raise InvalidInputError(
                f"Expected at most {MAX_COMPLETE:,} `{name}` with neighbors='all' (a dense n×n "
                f"graph), got {n:,}; use neighbors='knn'.", field="neighbors")
        d = squareform(pdist(x)) if n > 1 else np.zeros((n, n))
        iu = np.triu_indices(n, 1)
        vals = d[iu]
        rows = np.concatenate([iu[0], iu[1]])
        cols = np.concatenate([iu[1], iu[0]])
        g = sp.csr_array((np.concatenate([vals, vals]), (rows, cols)), shape=(n, n))
        g.sort_indices()
    return weight(g, weighting, sigma=sigma, name=name)
