r"""Quality figures every embedding reports, and the deterministic sign convention.

* :func:`trustworthiness` (Venna and Kaski 2001; the definition of
  ``sklearn.manifold.trustworthiness``): how many of each point's ``k`` nearest neighbours
  in the embedding were not among its ``k`` nearest in the input, weighted by how far down
  the input ranking they were,

  .. math::

     T(k) = 1 - \frac{2}{n k (2n - 3k - 1)} \sum_{i=1}^n \sum_{j \in N^Y_k(i)}
            \max(0,\ r(i, j) - k),

  :math:`r(i, j)` the rank of :math:`j` among :math:`i`'s neighbours in the input (1 for the
  nearest). 1 means every embedded neighbourhood is a true one.
* :func:`fix_signs`: each column's entry of largest magnitude positive (the convention of
  scikit-learn's ``svd_flip``), so eigenvectors do not change sign between runs or
  platforms.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from scipy.spatial import cKDTree

from algorithms.core.types import FloatArray
from algorithms.core.validation import as_int, as_points

__all__ = ["trustworthiness", "fix_signs", "quality_neighbors"]

#: Most rows of input distances computed at once (memory: ``_CHUNK × n`` floats).
_CHUNK = 256
#: Inputs of at most this many dimensions count the outsiders' ranks from kd-tree balls.
_BALL_DIMENSIONS = 16
#: Most ball members handled at once (memory: a few arrays of this many).
_BALL_CHUNK = 1 << 22


def quality_neighbors(k: int, n: int) -> int:
    """``k`` clipped to the largest neighbourhood trustworthiness is defined for,
    ``k < n / 2`` (0 when ``n < 3``)."""
    return max(0, min(k, (n - 1) // 2))


def trustworthiness(points: Any, embedding: Any, *, n_neighbors: int = 5) -> float:
    r"""Trustworthiness of an embedding: are its neighbourhoods true ones?

    Parameters
    ----------
    points : (n, D) float array
        The input points.
    embedding : (n, k) float array
        Their images, row ``i`` for point ``i``.
    n_neighbors : int, default 5
        The neighbourhood size ``k``, clipped to ``(n - 1) // 2`` (the formula needs
        ``k < n / 2``).

    Returns
    -------
    float
        :math:`T(k) \in [0, 1]`; 1 when ``n < 3`` (every neighbourhood is trivially kept).
        Equals ``sklearn.manifold.trustworthiness(points, embedding, n_neighbors=k)`` up to
        ties among equidistant points.

    Raises
    ------
    InvalidInputError
        Bad arrays, different numbers of rows, ``n_neighbors < 1``.

    Notes
    -----
    Cost: two kd-tree queries, then :math:`O(n)` per embedded neighbour that is not an
    input neighbour (its rank is counted), in blocks of rows; scikit-learn sorts the full
    :math:`n \times n` distance matrix. Inputs of at most 16 dimensions count such a rank
    among the input points in a kd-tree ball of that neighbour's radius instead (a few
    points for a good embedding), unless the balls hold more than half the rows would.

    References
    ----------
    .. [1] J. Venna, S. Kaski, "Neighborhood preservation in nonlinear projection methods:
       an experimental study", ICANN (2001).

    Examples
    --------
    >>> import numpy as np
    >>> x = np.arange(10.0)[:, None] * [1.0, 2.0]
    >>> trustworthiness(x, x[:, :1], n_neighbors=3)
    1.0
    """
    x = as_points(points, name="points")
    y = as_points(embedding, name="embedding", min_points=x.shape[0], max_points=x.shape[0])
    n = x.shape[0]
    k = quality_neighbors(as_int(n_neighbors, name="n_neighbors", minimum=1), n)
    if k < 1:
        return 1.0
    _, nbr = cKDTree(y).query(y, k=k + 1)
    nbr = nbr.reshape(n, k + 1)
    own = nbr == np.arange(n)[:, None]
    # drop each point itself (with coincident images it may sit anywhere among k + 1)
    missing = ~own.any(axis=1)
    own[missing, -1] = True
    nbr = nbr[~own].reshape(n, k)
    # only embedded neighbours that are not among the k nearest inputs have rank > k
    tree = cKDTree(x)
    _, true = tree.query(x, k=k + 1)
    true = true.reshape(n, k + 1)
    member = (nbr[:, :, None] == true[:, None, :]).any(axis=2)
    rows = np.flatnonzero(~member.all(axis=1))
    if x.shape[1] <= _BALL_DIMENSIONS:
        total = _outsider_ranks_by_tree(x, tree, nbr, member, k, rows.size * n // 2)
        if total is not None:
            return 1.0 - total * 2.0 / (n * k * (2.0 * n - 3.0 * k - 1.0))
    sq = np.einsum("ij,ij->i", x, x)
    total = 0.0
    chunk = max(1, min(_CHUNK, 20_000_000 // n))
    for start in range(0, rows.size, chunk):
        r = rows[start:start + chunk]
        d = sq[r, None] - 2.0 * (x[r] @ x.T) + sq[None, :]
        d[np.arange(r.size), r] = np.inf  # a point is not its own neighbour
        dn = np.take_along_axis(d, nbr[r], axis=1)  # (m, k)
        # rank r(i, j) = 1 + #{l : d(i, l) < d(i, j)}, for the outsiders only
        for c in range(k):
            out = ~member[r, c]
            if out.any():
                ranks = 1 + (d[out] < dn[out, c][:, None]).sum(axis=1)
                total += float(np.maximum(ranks - k, 0).sum())
    return 1.0 - total * 2.0 / (n * k * (2.0 * n - 3.0 * k - 1.0))


def _outsider_ranks_by_tree(x: FloatArray, tree: cKDTree, nbr: Any, member: Any, k: int,
                            limit: int) -> float | None:
    """The sum of ``max(0, r(i, j) - k)`` over the embedded neighbours ``j`` of ``i`` that
    are not among its ``k`` nearest inputs, each rank counted over the input points inside
    a kd-tree ball of radius ``d(i, j)`` (slightly enlarged: the count itself compares the
    squared differences ``d(i, l)^2 < d(i, j)^2``, computed the same way for both). None
    when the balls hold more than ``limit`` points (bad embeddings: full rows are
    cheaper)."""
    oi, oc = np.nonzero(~member)
    if oi.size == 0:
        return 0.0
    oj = nbr[oi, oc]
    diff = x[oi] - x[oj]
    d2 = np.einsum("ij,ij->i", diff, diff)
    radius = np.sqrt(d2) * (1.0 + 1e-9)
    every = max(1, oi.size // 256)  # a sample first: a bad embedding stops here cheaply
    sample = tree.query_ball_point(x[oi[::every]], radius[::every], return_length=True)
    if int(sample.sum()) * every > 2 * limit:
        return None
    counts = tree.query_ball_point(x[oi], radius, return_length=True)
    if int(counts.sum()) > limit:
        return None
    total = 0.0
    ends = np.cumsum(counts)
    start = 0
    while start < oi.size:
        stop = max(start + 1, int(np.searchsorted(ends, ends[start] - counts[start]
                                                  + _BALL_CHUNK, side="right")))
        balls = tree.query_ball_point(x[oi[start:stop]], radius[start:stop])
        lens = np.fromiter((len(b) for b in balls), dtype=np.int64, count=len(balls))
        inside = (np.concatenate([np.asarray(b, dtype=np.int64) for b in balls])
                  if lens.sum() else np.zeros(0, dtype=np.int64))
        owner = np.repeat(np.arange(stop - start), lens)
        centre = oi[start:stop][owner]
        diff = x[centre] - x[inside]
        closer = (np.einsum("ij,ij->i", diff, diff) < d2[start:stop][owner]) & (inside != centre)
        ranks = 1 + np.bincount(owner, weights=closer, minlength=stop - start)
        total += float(np.maximum(ranks - k, 0).sum())
        start = stop
    return total


def fix_signs(vectors: FloatArray) -> FloatArray:
    """Flip columns so that each one's entry of largest magnitude is positive (in place
    on a copy)."""
    v = np.array(vectors, dtype=np.float64, copy=True)
    if v.size == 0:
        return v
    at = np.argmax(np.abs(v), axis=0)
    signs = np.sign(v[at, np.arange(v.shape[1])])
    signs[signs == 0] = 1.0
    v *= signs
    return v
