"""The single closest pair between two point sets (kd-tree on the smaller set)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import cast

import numpy as np
from scipy.spatial import cKDTree

from algorithms.assignment.nearest import Workers, check_workers
from algorithms.core.params import PointsLike, validate_params
from algorithms.core.threads import query_workers
from algorithms.core.types import FloatArray, IntArray, KnnQuery
from algorithms.core.validation import check_point_sets

__all__ = ["ClosestPairResult", "closest_pair"]


@dataclass(frozen=True, eq=False)
class ClosestPairResult:
    """The closest pair of points, one from ``source`` and one from ``target``.

    Attributes
    ----------
    source_index : int
        The row of ``source`` that belongs to the closest pair.
    target_index : int
        The row of ``target`` that belongs to the closest pair.
    distance : float
        The Euclidean distance between the two points, the smallest over all pairs.
    pairs : (1, 2) int64 array
        The same pair as a one-row table ``[[source_index, target_index]]``, laid out like
        the ``pairs`` of every other assignment result.
    distances : (1,) float array
        The same distance as a one-element array, aligned with ``pairs``.
    """

    source_index: int
    target_index: int
    distance: float
    pairs: IntArray
    distances: FloatArray


@validate_params
def closest_pair(source: PointsLike, target: PointsLike, *, workers: Workers = -1
                 ) -> ClosestPairResult:
    r"""Closest pair between two point sets (kd-tree).

    The single pair of points, one from each set, at the smallest distance.

    .. math::

        (i^\ast, j^\ast) = \operatorname*{arg\,min}_{i, j}\ \lVert x_i - y_j \rVert

    Parameters
    ----------
    source : (n, d) float array
        The first point set, any ``d >= 1``, at least one point.
    target : (m, d) float array
        The second point set, same ``d``; its size may differ from ``source``.
    workers : int, default -1
        Threads for the kd-tree query; -1 uses every core, except that a query of fewer
        than ``SERIAL_BELOW`` (8192) points runs on one thread. The result never depends on
        ``workers``.

    Returns
    -------
    ClosestPairResult
        ``source_index``, ``target_index``, ``distance``, and the same pair as ``pairs`` and
        ``distances``.

    Raises
    ------
    InvalidInputError
        Empty, malformed or non-finite point sets; differing dimensions
        (``field="target"``); ``workers`` 0 or below -1.

    Notes
    -----
    **Algorithm.** A :class:`scipy.spatial.cKDTree` is built on the smaller set and every
    point of the larger set queries its nearest neighbour in it, in one batched call; the
    smallest of those distances is the answer. :math:`O((n + m) \log \min(n, m))` expected
    for small ``d``; no ``n×m`` matrix is formed.

    **Ties.** When several pairs share the smallest distance, the one whose point of the
    larger set (``source`` when the sizes are equal) has the lowest index is returned; its
    partner is the one the kd-tree finds. The same input always gives the same answer.
    The pair is symmetric in the sense that swapping ``source`` and ``target`` returns the
    swapped indices with the same ``distance``, up to this tie-breaking.

    References
    ----------
    .. [1] J. L. Bentley, "Multidimensional binary search trees used for associative
       searching", Communications of the ACM 18(9), 509-517, 1975.

    Examples
    --------
    >>> from algorithms.assignment import closest_pair
    >>> res = closest_pair([[0.0, 0.0], [5.0, 5.0]], [[1.0, 1.0], [4.0, 4.5], [9.0, 9.0]])
    >>> res.source_index, res.target_index, round(res.distance, 6)
    (1, 1, 1.118034)
    >>> res.pairs.tolist()
    [[1, 1]]
    """
    src, dst = check_point_sets(source, target)
    workers = check_workers(workers)
    tree_is_source = src.shape[0] < dst.shape[0]
    tree_points, query_points = (src, dst) if tree_is_source else (dst, src)
    if workers == -1:
        workers = query_workers(query_points.shape[0])
    dist, idx = cast(KnnQuery, cKDTree(tree_points).query(query_points, k=1, workers=workers))
    q = int(np.argmin(dist))
    t = int(idx[q])
    i, j = (t, q) if tree_is_source else (q, t)
    d = float(dist[q])
    return ClosestPairResult(
        source_index=i,
        target_index=j,
        distance=d,
        pairs=np.array([[i, j]], dtype=np.int64),
        distances=np.array([d], dtype=np.float64),
    )
