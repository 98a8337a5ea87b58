"""Dense cost matrices, shared by :mod:`~algorithms.assignment.bipartite` and
:mod:`~algorithms.assignment.optimal_transport`.

Both methods need every pairwise cost, an ``n×m`` float64 matrix. Its size is bounded by
:data:`MAX_COST_ENTRIES` so that a request of two large sets fails at once with a clear
error instead of exhausting a worker's memory.
"""

from __future__ import annotations

from typing import Any, Literal, get_args

import numpy as np
from scipy.spatial.distance import cdist

from algorithms.core.errors import InvalidInputError
from algorithms.core.types import FloatArray
from algorithms.core.validation import check_point_sets

__all__ = ["Metric", "METRICS", "MAX_COST_ENTRIES", "check_cost_size", "check_dense",
           "cost_matrix", "pair_distances"]

Metric = Literal["euclidean", "sqeuclidean"]
#: The accepted values of ``metric``: the ground cost of a pair of points.
METRICS = get_args(Metric)

#: The largest dense cost matrix built, in entries ``n·m`` (16 million: 128 MB of float64,
#: e.g. 4,000 × 4,000 points). Sinkhorn holds two such matrices, the LP path three.
MAX_COST_ENTRIES = 16_000_000


def check_dense(source: Any, target: Any) -> tuple[FloatArray, FloatArray]:
    """Check two point sets of one dimension whose ``n×m`` cost matrix fits
    (:func:`check_cost_size`); returns them as :func:`as_points` reads them."""
    src, dst = check_point_sets(source, target)
    check_cost_size(src.shape[0], dst.shape[0])
    return src, dst


def check_cost_size(n: int, m: int, *, names: tuple[str, str] = ("source", "target")) -> None:
    """Raise unless the ``n×m`` cost matrix stays within :data:`MAX_COST_ENTRIES`.

    The error names the larger set (the second on a tie): it is the one to shrink.
    """
    if n * m <= MAX_COST_ENTRIES:
        return
    first, second = names
    field = first if n > m else second
    raise InvalidInputError(
        f"Expected `{first}` and `{second}` to have at most {MAX_COST_ENTRIES:,} point pairs "
        f"(the entries of the dense n×m cost matrix), got {n:,} × {m:,} = {n * m:,}; "
        "subsample the larger set.",
        field=field,
    )


def cost_matrix(source: FloatArray, target: FloatArray, metric: Metric) -> FloatArray:
    """The ``(n, m)`` matrix of ``metric`` between every source and every target point."""
    return np.ascontiguousarray(cdist(source, target, metric), dtype=np.float64)


def pair_distances(source: FloatArray, target: FloatArray, i: np.ndarray, j: np.ndarray
                   ) -> FloatArray:
    """Euclidean distances ``|source[i] - target[j]|`` of the listed pairs."""
    if i.size == 0:
        return np.zeros(0, dtype=np.float64)
    diff = source[i] - target[j]
    squared: FloatArray = np.einsum("ij,ij->i", diff, diff)
    return np.sqrt(squared)
