r"""The neighbourhood graph shared by the graph embeddings (isomap, Laplacian eigenmaps, LPP,
LLE), built from the core builders of :mod:`algorithms.core.graphs`.

Parameters, with the same names in every method and in the service:

* ``neighbors``: ``"knn"`` (each point to its ``n_neighbors`` nearest, symmetrised by union),
  ``"radius"`` (every pair closer than ``radius``) or ``"all"`` (every pair);
* ``weighting``: ``"uniform"`` (1), ``"distance"`` (:math:`1/d`) or ``"heat"``
  (:math:`e^{-d^2/2\sigma^2}`, ``sigma`` the mean edge length unless given).

A graph that falls apart into several connected components is an error that says how many
(:func:`check_connected`): every method here would otherwise return an embedding in which
the components are unrelated (Isomap: infinite distances; spectral methods: one zero
eigenvalue per component).
"""

from __future__ import annotations

from typing import Any

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components
from scipy.spatial.distance import pdist, squareform

from algorithms.core.errors import DegenerateInputError, InvalidInputError
from algorithms.core.graphs import knn_graph, radius_graph, weight
from algorithms.core.types import FloatArray
from algorithms.core.validation import as_choice, as_float, as_int

__all__ = ["NEIGHBORS", "WEIGHTINGS", "distance_graph", "weighted_graph", "check_connected",
           "default_neighbors", "check_components", "resolve_n_neighbors",
           "similarity_graph"]

NEIGHBORS = ("knn", "radius", "all")
WEIGHTINGS = ("uniform", "distance", "heat")


def default_neighbors(n: int) -> int:
    """scikit-learn's SpectralEmbedding default: ``max(n // 10, 1)``."""
    return max(n // 10, 1)


def distance_graph(x: FloatArray, neighbors: str, n_neighbors: int, radius: float | None,
                   *, name: str = "points") -> sp.csr_array:
    """The symmetric graph whose stored entries are the edge lengths ``‖x_i − x_j‖``."""
    as_choice(neighbors, NEIGHBORS, name="neighbors")
    n = x.shape[0]
    if neighbors == "knn":
        k = as_int(n_neighbors, name="n_neighbors", minimum=1, maximum=n - 1,
                   reason=f"the number of `{name}` minus one ({n - 1})")
        return knn_graph(x, k, name=name)
    if neighbors == "radius":
        if radius is None:
            raise InvalidInputError("Expected `radius` with neighbors='radius', got none.",
                                    field="radius")
        r = as_float(radius, name="radius", minimum=0.0, inclusive=False)
        return radius_graph(x, r, name=name)
    d = squareform(pdist(x))
    # keep coincident pairs as explicit zero-length edges (every pair is an edge)
    rows, cols = np.nonzero(~np.eye(n, dtype=bool))
    g = sp.csr_array((d[rows, cols], (rows, cols)), shape=(n, n))
    return g


def weighted_graph(lengths: sp.csr_array, weighting: str, sigma: float | None, *,
                   name: str = "points") -> sp.csr_array:
    """Edge weights from edge lengths (:func:`algorithms.core.graphs.weight`)."""
    as_choice(weighting, WEIGHTINGS, name="weighting")
    return weight(lengths, weighting, sigma=sigma, name=name)  # type: ignore[arg-type]


def check_components(g: sp.csr_array) -> int:
    """The number of connected components of a symmetric graph."""
    count, _ = connected_components(g, directed=False)
    return int(count)


def check_connected(g: sp.csr_array, neighbors: str, *, method: str) -> None:
    """Raise :class:`DegenerateInputError` naming the component count of a split graph."""
    count = check_components(g)
    if count > 1:
        field = {"knn": "n_neighbors", "radius": "radius"}.get(neighbors, "points")
        hint = {"knn": "increase `n_neighbors`", "radius": "increase `radius`"}.get(
            neighbors, "the points")
        raise DegenerateInputError(
            f"Expected a connected neighbourhood graph for {method}, got {count} connected "
            f"components ({hint}, or embed each part on its own).", field=field)


def resolve_n_neighbors(n_neighbors: Any, n: int) -> int:
    """``n_neighbors`` as given, or :func:`default_neighbors` when ``None``."""
    return default_neighbors(n) if n_neighbors is None else n_neighbors


def similarity_graph(x: FloatArray, neighbors: str, n_neighbors: Any, radius: float | None,
                     weighting: str, sigma: float | None, *, method: str) -> sp.csr_array:
    """The connected, weighted neighbourhood graph of the spectral methods (LE, LPP)."""
    n = x.shape[0]
    lengths = distance_graph(x, neighbors, resolve_n_neighbors(n_neighbors, n), radius)
    check_connected(lengths, neighbors, method=method)
    return weighted_graph(lengths, weighting, sigma)
