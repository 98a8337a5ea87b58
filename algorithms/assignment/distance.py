"""Distances between two point sets from their nearest-neighbour assignment: Chamfer,
Hausdorff, RMSE."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from algorithms.assignment.nearest import Workers, check_workers
from algorithms.core.params import PointsLike, validate_params
from algorithms.core.threads import query_workers
from algorithms.core.types import FloatArray
from algorithms.core.validation import check_point_sets

__all__ = ["DistanceResult", "distance"]


@dataclass(frozen=True, eq=False)
class DistanceResult:
    """How far apart two point sets are, by every usual measure at once.

    Attributes
    ----------
    chamfer : float
        The Chamfer distance, the sum of every point's distance to the nearest point of the
        other set, both directions: ``sum(forward_distances) + sum(backward_distances)``.
    chamfer_mean : float
        The size-normalised Chamfer distance, ``mean(forward_distances) +
        mean(backward_distances)``.
    hausdorff : float
        The Hausdorff distance, the larger of the two directed ones: no point of either set
        is farther than this from the other set.
    hausdorff_forward : float
        The directed Hausdorff distance from source to target, ``max(forward_distances)``.
    hausdorff_backward : float
        The directed Hausdorff distance from target to source, ``max(backward_distances)``.
    rmse : float
        The root-mean-square of all ``n + m`` nearest-neighbour distances, both directions.
    rmse_forward : float
        The root-mean-square of ``forward_distances`` (source to target).
    rmse_backward : float
        The root-mean-square of ``backward_distances`` (target to source).
    forward_distances : (n,) float array
        For each source point, the distance to its nearest target point.
    backward_distances : (m,) float array
        For each target point, the distance to its nearest source point.
    """

    chamfer: float
    chamfer_mean: float
    hausdorff: float
    hausdorff_forward: float
    hausdorff_backward: float
    rmse: float
    rmse_forward: float
    rmse_backward: float
    forward_distances: FloatArray
    backward_distances: FloatArray


@validate_params
def distance(source: PointsLike, target: PointsLike, *, workers: Workers = -1
             ) -> DistanceResult:
    r"""Chamfer, Hausdorff and RMSE distances between point sets.

    How far apart two point sets are, from their nearest-neighbour assignment in both directions:
    Chamfer (sum and mean), Hausdorff (and both directed halves), RMSE, and every point's distance
    to the other set.

    With the nearest-neighbour distances :math:`d_i = \min_j \lVert x_i - y_j \rVert`
    (forward, one per source point) and :math:`e_j = \min_i \lVert x_i - y_j \rVert`
    (backward, one per target point):

    .. math::

        \text{chamfer} &= \sum_i d_i + \sum_j e_j, \qquad
        \text{chamfer\_mean} = \tfrac{1}{n}\sum_i d_i + \tfrac{1}{m}\sum_j e_j, \\
        \text{hausdorff} &= \max\bigl(\max_i d_i,\ \max_j e_j\bigr), \qquad
        \text{rmse} = \sqrt{\frac{\sum_i d_i^2 + \sum_j e_j^2}{n + m}} .

    ``chamfer`` measures the difference of two sets by a sum of distances (Barrow et al.
    1977 [1]_); it equals the sum of the distances of :func:`nearest` with
    ``direction="both"``.

    Parameters
    ----------
    source : (n, d) float array
        The first point set, any ``d >= 1``, at least one point.
    target : (m, d) float array
        The second point set, same ``d``; its size may differ from ``source``.
    workers : int, default -1
        Threads for the kd-tree queries; -1 uses every core, except that a query of fewer
        than ``SERIAL_BELOW`` (8192) points runs on one thread. The result never depends on
        ``workers``.

    Returns
    -------
    DistanceResult
        ``chamfer``, ``chamfer_mean``, ``hausdorff`` (and its two directed halves),
        ``rmse`` (and its two directed halves), ``forward_distances`` and
        ``backward_distances``.

    Raises
    ------
    InvalidInputError
        Empty, malformed or non-finite point sets; differing dimensions
        (``field="target"``); ``workers`` 0 or below -1.

    Notes
    -----
    **One result, every measure.** The measures share the two nearest-neighbour queries,
    so they are returned together rather than chosen by an option. All are symmetric in
    ``source`` and ``target`` except the directed ones, which swap. All are 0 exactly when
    the two sets hold the same points (as sets; multiplicities do not count).

    **Other conventions.** Some libraries (PyTorch3D's ``chamfer_distance``) call the
    mean of *squared* distances the Chamfer distance; it is
    ``rmse_forward**2 + rmse_backward**2``. The directed Hausdorff distances equal
    :func:`scipy.spatial.distance.directed_hausdorff`'s.

    **Cost.** Two :class:`scipy.spatial.cKDTree` builds and two batched queries,
    :math:`O((n + m) \log(n + m))` expected for small ``d``; no ``n×m`` matrix is formed.

    References
    ----------
    .. [1] H. G. Barrow, J. M. Tenenbaum, R. C. Bolles and H. C. Wolf, "Parametric
       correspondence and chamfer matching: two new techniques for image matching",
       IJCAI 1977, 659-663.
    .. [2] D. P. Huttenlocher, G. A. Klanderman and W. J. Rucklidge, "Comparing images
       using the Hausdorff distance", IEEE TPAMI 15(9), 850-863, 1993.

    Examples
    --------
    >>> from algorithms.assignment import distance
    >>> res = distance([[0.0], [2.0], [7.0]], [[1.5], [6.0], [10.0]])
    >>> res.forward_distances.tolist(), res.backward_distances.tolist()
    ([1.5, 0.5, 1.0], [0.5, 1.0, 3.0])
    >>> res.chamfer, res.hausdorff, res.hausdorff_forward
    (7.5, 3.0, 1.5)
    """
    src, dst = check_point_sets(source, target)
    workers = check_workers(workers)
    fwd = _nearest_distances(dst, src, workers)
    bwd = _nearest_distances(src, dst, workers)
    n, m = fwd.shape[0], bwd.shape[0]
    sq_f, sq_b = float(np.dot(fwd, fwd)), float(np.dot(bwd, bwd))
    h_f, h_b = float(fwd.max()), float(bwd.max())
    return DistanceResult(
        chamfer=float(fwd.sum() + bwd.sum()),
        chamfer_mean=float(fwd.mean() + bwd.mean()),
        hausdorff=max(h_f, h_b),
        hausdorff_forward=h_f,
        hausdorff_backward=h_b,
        rmse=float(np.sqrt((sq_f + sq_b) / (n + m))),
        rmse_forward=float(np.sqrt(sq_f / n)),
        rmse_backward=float(np.sqrt(sq_b / m)),
        forward_distances=fwd,
        backward_distances=bwd,
    )


def _nearest_distances(tree_points: FloatArray, query_points: FloatArray, workers: int
                       ) -> FloatArray:
    """Distance from every query point to its nearest tree point."""
    if workers == -1:
        workers = query_workers(query_points.shape[0])
    dist, _ = cKDTree(tree_points).query(query_points, k=1, workers=workers)
    return np.ascontiguousarray(dist, dtype=np.float64)
