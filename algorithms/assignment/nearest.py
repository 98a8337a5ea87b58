"""Nearest-neighbour assignment between two point sets (kd-tree)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Annotated, Literal, cast, get_args

import numpy as np
from scipy.spatial import cKDTree

from algorithms.core.errors import InvalidInputError
from algorithms.core.params import Ge, Gt, PointsLike, validate_params
from algorithms.core.threads import query_workers
from algorithms.core.types import FloatArray, IntArray, KnnQuery
from algorithms.core.validation import as_int, check_point_sets

__all__ = ["NearestResult", "nearest", "Direction", "DIRECTIONS", "Workers", "check_workers"]

Direction = Literal["forward", "backward", "union", "intersection", "both"]
#: The accepted values of ``direction``.
DIRECTIONS = get_args(Direction)

Workers = Annotated[int, Ge(-1)]
"""Threads of the kd-tree queries: -1 (every core) or a positive count; 0 is refused by
:func:`check_workers`."""


@dataclass(frozen=True, eq=False)
class NearestResult:
    """Pairs of nearest points between ``source`` and ``target``.

    Attributes
    ----------
    pairs : (m, 2) int64 array
        Each row is ``(source_index, target_index)``, in the order documented by
        :func:`nearest` for the chosen ``direction``.
    distances : (m,) float array
        The Euclidean distance between the two points of each pair.
    rmse : float
        The root-mean-square of ``distances``, 0.0 when there are no pairs.
    n_pairs : int
        The number of pairs ``m``, which may be 0 when ``max_distance`` drops them all.
    """

    pairs: IntArray
    distances: FloatArray
    rmse: float
    n_pairs: int


def check_workers(workers: int) -> int:
    """``workers`` (already an integer >= -1) unless it is 0, which starts no thread."""
    if workers == 0:
        raise InvalidInputError(
            "Expected `workers` to be -1 (every core) or a positive integer, got 0.",
            field="workers",
        )
    return workers


@validate_params
def nearest(
    source: PointsLike,
    target: PointsLike,
    *,
    k: Annotated[int, Ge(1)] = 1,
    direction: Direction = "forward",
    max_distance: Annotated[float, Gt(0)] | None = None,
    workers: Workers = -1,
) -> NearestResult:
    r"""Nearest-neighbour assignment (kd-tree).

    Pairs each point with its k nearest neighbours in the other set, in one or both directions,
    optionally within a distance.

    For ``direction="forward"`` every source point :math:`x_i` is paired with the ``k``
    target points closest to it,

    .. math::

        \mathcal{P}_\to = \{(i, j) : y_j \in \operatorname{kNN}_k(x_i; Y)\},

    and ``"backward"`` does the same from the target side,
    :math:`\mathcal{P}_\leftarrow = \{(i, j) : x_i \in \operatorname{kNN}_k(y_j; X)\}`.
    ``"union"`` is :math:`\mathcal{P}_\to \cup \mathcal{P}_\leftarrow`, ``"intersection"``
    is :math:`\mathcal{P}_\to \cap \mathcal{P}_\leftarrow` (mutual nearest neighbours), and
    ``"both"`` is the forward list followed by the backward list without removing
    duplicates, so that with ``k=1`` the sum of ``distances`` is the Chamfer distance

    .. math::

        \sum_i \min_j \lVert x_i - y_j \rVert + \sum_j \min_i \lVert x_i - y_j \rVert .

    Parameters
    ----------
    source : (n, d) float array
        The first point set, any ``d >= 1``.
    target : (m, d) float array
        The second point set, same ``d``; its size may differ from ``source``.
    k : int, default 1
        Neighbours per query point, ``1 <= k <=`` the size of the set searched: ``target``
        for forward, ``source`` for backward, the smaller of the two otherwise.
    direction : {"forward", "backward", "union", "intersection", "both"}, default "forward"
        Which pairs to return: ``"forward"`` each source point with its ``k`` nearest
        target points; ``"backward"`` each target point with its ``k`` nearest source
        points; ``"union"`` the pairs found in either direction, ``"intersection"`` those
        found in both (mutual nearest neighbours), each pair once; ``"both"`` the forward
        list followed by the backward one, duplicates kept (with ``k=1`` its distances sum
        to the Chamfer distance).
    max_distance : float, optional
        Drop pairs farther apart than this (``> 0``, in the points' units); pairs at exactly
        this distance are kept. Applied in each direction before union or intersection.
        Omitted: no pair is dropped.
    workers : int, default -1
        Threads for the kd-tree queries; -1 uses every core, except that a query of fewer
        than ``SERIAL_BELOW`` (8192) points runs on one thread, where starting threads costs
        more than it saves. The result never depends on ``workers``.

    Returns
    -------
    NearestResult
        ``pairs``, ``distances``, ``rmse`` and ``n_pairs``. An empty result (every pair
        beyond ``max_distance``) is not an error: ``n_pairs == 0`` and ``rmse == 0.0``.

    Raises
    ------
    InvalidInputError
        Empty, malformed or non-finite point sets; differing dimensions
        (``field="target"``); unknown ``direction``; ``k`` out of range (``field="k"``);
        ``max_distance <= 0`` or non-finite; ``workers`` 0 or below -1.

    Notes
    -----
    **Order of the pairs** (deterministic): ``"forward"`` by source index, then by rank
    (nearest first); ``"backward"`` by target index, then by rank; ``"both"`` the forward
    list then the backward list; ``"union"`` and ``"intersection"`` sorted
    lexicographically by ``(source_index, target_index)``, each pair once.

    **Ties.** When several points are at exactly the same distance, which of them the
    kd-tree returns (and their order within a row for ``k > 1``) is decided by the tree
    traversal: the same input always gives the same answer, but it is not necessarily the
    lowest index. ``"intersection"`` inherits those choices. Distances themselves are
    unaffected.

    **Cost.** One :class:`scipy.spatial.cKDTree` build and one batched query per direction
    (two for union, intersection and both); :math:`O((n + m) \log(n + m))` expected for
    small ``d``, no loop over points. Union and intersection add a sort of the pair keys.

    References
    ----------
    .. [1] J. L. Bentley, "Multidimensional binary search trees used for associative
       searching", Communications of the ACM 18(9), 509-517, 1975.
    .. [2] S. Maneewongvatana and D. M. Mount, "Analysis of approximate nearest neighbor
       searching with clustered point sets", arXiv:cs/9901013, 1999 (the sliding-midpoint
       kd-tree of scipy's ``cKDTree``).

    Examples
    --------
    >>> from algorithms.assignment import nearest
    >>> res = nearest([[0.0], [2.0], [7.0]], [[1.5], [6.0]], direction="both")
    >>> res.pairs.tolist()
    [[0, 0], [1, 0], [2, 1], [1, 0], [2, 1]]
    >>> res.distances.tolist()
    [1.5, 0.5, 1.0, 0.5, 1.0]
    """
    src, dst = check_point_sets(source, target)
    n_s, n_t = src.shape[0], dst.shape[0]
    if direction == "forward":
        limit, why = n_t, "the number of `target` points"
    elif direction == "backward":
        limit, why = n_s, "the number of `source` points"
    else:
        limit = min(n_s, n_t)
        why = f"the size of the smaller point set, `{'source' if n_s <= n_t else 'target'}`"
    k = as_int(k, name="k", minimum=1, maximum=limit, reason=why)
    bound = max_distance
    workers = check_workers(workers)

    if direction == "forward":
        s, t, dist = _query(dst, src, k, bound, workers)
        return _result(s, t, dist)
    if direction == "backward":
        t, s, dist = _query(src, dst, k, bound, workers)
        return _result(s, t, dist)

    fs, ft, fd = _query(dst, src, k, bound, workers)
    bt, bs, bd = _query(src, dst, k, bound, workers)
    if direction == "both":
        return _result(np.concatenate([fs, bs]), np.concatenate([ft, bt]), np.concatenate([fd, bd]))

    # Encode (s, t) as one int64 key; sorting keys sorts pairs lexicographically.
    fkey = fs * n_t + ft
    bkey = bs * n_t + bt
    if direction == "union":
        key, first = np.unique(np.concatenate([fkey, bkey]), return_index=True)
        dist = np.concatenate([fd, bd])[first]
    else:  # intersection; keys are unique within each direction (k distinct neighbours)
        key, in_f, _ = np.intersect1d(fkey, bkey, assume_unique=True, return_indices=True)
        dist = fd[in_f]
    s, t = np.divmod(key, n_t)
    return _result(s, t, dist)


def _query(
    tree_points: FloatArray,
    query_points: FloatArray,
    k: int,
    bound: float | None,
    workers: int,
) -> tuple[IntArray, IntArray, FloatArray]:
    """k nearest ``tree_points`` of every query point: (query index, tree index, distance),
    flattened query-major, nearest first, pairs beyond ``bound`` dropped."""
    tree = cKDTree(tree_points)
    if workers == -1:
        workers = query_workers(query_points.shape[0])
    if bound is None:
        dist, idx = cast(KnnQuery, tree.query(query_points, k=k, workers=workers))
    else:
        # The tree's own cut-off compares rounded squared distances; search a hair wider
        # and cut on the returned distances so that "<= max_distance" holds exactly.
        dist, idx = cast(KnnQuery, tree.query(
            query_points, k=k, distance_upper_bound=bound * (1.0 + 1e-9), workers=workers
        ))
    n_q = query_points.shape[0]
    q = np.arange(n_q, dtype=np.int64)
    if k > 1:
        q = np.repeat(q, k)
        dist = dist.ravel()
        idx = idx.ravel()
    t = idx.astype(np.int64, copy=False)
    if bound is not None:
        keep = dist <= bound
        if not keep.all():
            q, t, dist = q[keep], t[keep], dist[keep]
    return q, t, np.ascontiguousarray(dist, dtype=np.float64)


def _result(s: IntArray, t: IntArray, dist: FloatArray) -> NearestResult:
    m = int(dist.shape[0])
    pairs = np.empty((m, 2), dtype=np.int64)
    pairs[:, 0] = s
    pairs[:, 1] = t
    rmse = float(np.sqrt(np.dot(dist, dist) / m)) if m else 0.0
    return NearestResult(pairs=pairs, distances=dist, rmse=rmse, n_pairs=m)
