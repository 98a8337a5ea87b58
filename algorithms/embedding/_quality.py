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
* ``_nearest_neighbors``: every point's exact ``k`` nearest neighbours (t-SNE's
  affinities and the trustworthiness of inputs in many dimensions share it).
"""

from __future__ import annotations

from typing import Any, cast

import numpy as np
from scipy.spatial import cKDTree

from algorithms.core.errors import InvalidInputError
from algorithms.core.threads import query_workers, single_blas_thread
from algorithms.core.types import FloatArray, IntArray, IntpArray, KnnQuery
from algorithms.core.validation import as_int, as_points
from algorithms.embedding._groups import group_count, partition

__all__ = ["trustworthiness", "fix_signs", "quality_neighbors"]

#: Most rows of input distances computed at once (memory: ``_CHUNK × n`` floats).
_CHUNK = 256
#: Most ball members handled at once (memory: a few arrays of this many).
_BALL_CHUNK = 1 << 22
#: Cells of a block of the list-based count (8 bytes each).
_LIST_CELLS = 4_000_000
#: Cells of a block of the exact neighbour search: its single-precision estimates and
#: their ``argpartition`` (4 + 8 bytes each; 6 MB). t-SNE's peak memory at a few thousand
#: points is this search's (4,000,000 cells: 58 MiB at 2,000 points in 50-D), and the
#: search is no slower for smaller blocks (they stay in the cache; 30,000 points: 1.6 s,
#: against 2.0 s with 4,000,000 cells).
_KNN_CELLS = 500_000
#: Cells of the candidates' coordinate differences of a block (8 bytes each; 1 MB).
_KNN_DIFF_CELLS = 131_072
#: Extra candidates per point of the single-precision neighbour search.
_KNN_MARGIN = 10
#: Most input dimensions for which the neighbour search uses a kd-tree.
_KDTREE_MAX_DIM = 8


def _score(total: float, n: int, k: int) -> float:
    """:math:`T(k)` from the sum of ``max(0, r(i, j) - k)``."""
    return 1.0 - total * 2.0 / (n * k * (2.0 * n - 3.0 * k - 1.0))


def _embedded_neighbours(y: FloatArray, k: int) -> IntpArray:
    """Each point's ``k`` nearest neighbours in the embedding, itself excluded (with
    coincident images it may sit anywhere among the ``k + 1`` found, or not at all)."""
    n: int = y.shape[0]
    _, nbr = cast(KnnQuery, cKDTree(y).query(y, k=k + 1, workers=query_workers(n)))
    nbr = nbr.reshape(n, k + 1)
    own = nbr == np.arange(n)[:, None]
    own[~own.any(axis=1), -1] = True
    others: IntpArray = nbr[~own].reshape(n, k)
    return others


def quality_neighbors(k: int, n: int) -> int:
    """``k`` clipped to the largest neighbourhood trustworthiness is defined for,
    ``k < n / 2`` (0 when ``n < 3``)."""
    return max(0, min(k, (n - 1) // 2))


def trustworthiness(points: Any, embedding: Any, *, n_neighbors: int = 5,
                    input_neighbours: tuple[Any, Any] | None = None) -> float:
    r"""Trustworthiness of an embedding: are its neighbourhoods true ones?

    Parameters
    ----------
    points : (n, D) float array
        The input points.
    embedding : (n, k) float array
        Their images, row ``i`` for point ``i``.
    n_neighbors : int, default 5
        The neighbourhood size ``k``, clipped to ``(n - 1) // 2`` (the formula needs
        ``k < n / 2``). scikit-learn's ``trustworthiness`` refuses such a ``k`` instead
        (a ``ValueError``); here every method reports a trustworthiness for its
        ``quality_neighbors`` whatever the number of points, so the largest ``k`` the
        formula allows is used.
    input_neighbours : ((n, w) float array, (n, w) int array), optional
        The input points' ``w`` nearest neighbours if already known (t-SNE has them):
        squared distances and indices, itself excluded, each row sorted by distance then
        index. With ``w >= k`` the ranks are read off these lists where they can be (the
        same value, without the input's own neighbour search).

    Returns
    -------
    float
        :math:`T(k) \in [0, 1]`; 1 when ``n < 3`` (every neighbourhood is trivially kept).
        Equals ``sklearn.manifold.trustworthiness(points, embedding, n_neighbors=k)`` up to
        ties among equidistant points.

    Raises
    ------
    InvalidInputError
        Bad arrays, different numbers of rows, ``n_neighbors < 1``, neighbour lists of
        the wrong shape.

    Notes
    -----
    Cost (scikit-learn sorts the full :math:`n \times n` distance matrix): up to 8 input
    dimensions, two kd-tree queries, then each embedded neighbour that is not among the
    input's ``k`` nearest has its rank counted among the input points in a kd-tree ball
    of its radius (a few points for a good embedding), or, when the balls would hold more
    than half the rows, :math:`O(n)` each from whole rows of distances in blocks. Above 8
    dimensions, where a kd-tree visits nearly every point, the input's ``k`` nearest come
    from the exact blocked search of :func:`_nearest_neighbors` and the ranks as with
    given lists (100,000 points in 50-D in 20 clusters: 28 s in all, where the kd-tree
    path ran for many minutes).

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
    nbr = _embedded_neighbours(y, k)
    if input_neighbours is not None:
        d2, lists = (np.asarray(a) for a in input_neighbours)
        if d2.shape != lists.shape or d2.ndim != 2 or d2.shape[0] != n:
            raise InvalidInputError(
                f"Expected `input_neighbours` to be two ({n}, w) arrays, got shapes "
                f"{d2.shape} and {lists.shape}.", field="input_neighbours")
        if lists.shape[1] >= k:
            return _score(_outsider_ranks_from_lists(x, nbr, d2, lists, k), n, k)
    if x.shape[1] > _KDTREE_MAX_DIM:
        # in many dimensions a kd-tree visits nearly every point: the input's own k
        # nearest from the exact blocked search instead, then the same count as above
        d2, lists = _nearest_neighbors(x, k)
        return _score(_outsider_ranks_from_lists(x, nbr, d2, lists, k), n, k)
    # only embedded neighbours that are not among the k nearest inputs have rank > k
    tree = cKDTree(x)
    _, true = tree.query(x, k=k + 1, workers=query_workers(n))
    true = true.reshape(n, k + 1)
    member = (nbr[:, :, None] == true[:, None, :]).any(axis=2)
    rows = np.flatnonzero(~member.all(axis=1))
    total = _outsider_ranks_by_tree(x, tree, nbr, member, k, rows.size * n // 2)
    if total is not None:
        return _score(total, n, k)
    sq = np.einsum("ij,ij->i", x, x)
    total = 0.0
    chunk = max(1, min(_CHUNK, 20_000_000 // n))
    with single_blas_thread():  # thin (chunk, D) @ (D, n) products: the thread policy
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
    return _score(total, n, k)


def _outsider_ranks_by_tree(x: FloatArray, tree: cKDTree, nbr: Any, member: Any, k: int,
                            limit: int) -> float | None:
    """The sum of ``max(0, r(i, j) - k)`` over the embedded neighbours ``j`` of ``i`` that
    are not among its ``k`` nearest inputs, each rank counted over the input points inside
    a kd-tree ball of radius ``d(i, j)`` (slightly enlarged: the count itself compares the
    squared differences ``d(i, l)^2 < d(i, j)^2``, computed the same way for both). The
    balls are only counted (in C) unless another point lies within a relative ``1e-9`` of
    ``d(i, j)``; only those near-ties list the ball's members. None when the balls hold
    more than ``limit`` points (bad embeddings: full rows are cheaper)."""
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
    # Counted inside the ball shrunk by the same margin, every point but the centre is
    # closer than j for sure: when j is the only point between the two spheres, the rank
    # is that count (the centre stands for j). Only near-ties need the members' distances.
    inner = tree.query_ball_point(x[oi], np.sqrt(d2) * (1.0 - 1e-9), return_length=True)
    clear = (counts - inner == 1) & (d2 > 0)
    total = float(np.maximum(inner[clear] - k, 0).sum())
    keep = ~clear
    oi, d2, radius, counts = oi[keep], d2[keep], radius[keep], counts[keep]
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


def _outsider_ranks_from_lists(x: FloatArray, emb: IntpArray, input_d2: FloatArray,
                               input_nbr: IntArray, k: int) -> float:
    r"""The sum of ``max(0, r(i, j) - k)`` over the embedded neighbours ``emb`` (``(n, k)``)
    with the input's sorted neighbour lists known (squared distances and indices, at least
    ``k`` wide): a rank :math:`1 + \#\{l : d_{il} < d_{ij}\}` is read off its row of the
    lists when the neighbour is there, and only rows with an embedded neighbour beyond the
    list need their distances to the other points (in blocks of rows, screened by BLAS
    estimates with an error bound, :func:`_screen`), and only to those of the groups of
    a partition (:mod:`~algorithms.embedding._groups`) that may hold a point closer than
    the row's farthest outsider."""
    n = x.shape[0]
    width = input_nbr.shape[1]
    total = 0.0
    # in a sorted row, the entries strictly closer than the one at q: the first q' with
    # the same distance (ties share the rank of the first)
    new = np.ones(input_d2.shape, dtype=bool)
    new[:, 1:] = input_d2[:, 1:] != input_d2[:, :-1]
    first = np.maximum.accumulate(np.where(new, np.arange(width, dtype=np.int32), 0), axis=1)
    ranks = np.zeros((n, k), dtype=np.int64)                           # 0: beyond the list
    step = max(1, _LIST_CELLS // (k * width))
    for s in range(0, n, step):
        e = min(n, s + step)
        hit = emb[s:e, :, None] == input_nbr[s:e, None, :]              # (b, k, width)
        at = np.take_along_axis(first[s:e], hit.argmax(axis=2), axis=1)
        ranks[s:e] = np.where(hit.any(axis=2), at + 1, 0)
    inside = ranks > 0
    total += float(np.maximum(ranks[inside] - k, 0).sum())
    far = np.flatnonzero(~inside.all(axis=1))
    if far.size == 0:
        return total
    # rank = 1 + #{l : d_il < d_ij}, counted on estimates of the distances by BLAS (single
    # precision, with an error bound), group by group of a partition of the points
    # (_groups): only the groups that may hold a point closer than the row's farthest
    # outsider are looked at. One pass over a block keeps the entries below the row's
    # largest threshold (a rank's worth), and only those are compared with each of the
    # row's thresholds; those within the error bound of one are decided by their exact
    # distances (j itself among them: not closer than itself)
    xc = x - x.mean(axis=0)
    sq, x32, sq32, slack = _screen(xc)
    groups = partition(xc, group_count(n))
    far = far[np.argsort(groups.label[far], kind="stable")]
    bounds = np.searchsorted(groups.label[far], np.arange(len(groups) + 1))
    with single_blas_thread():
        for g in range(len(groups)):
            rows = far[bounds[g]:bounds[g + 1]]
            if rows.size == 0:
                continue
            out = ~inside[rows]                                     # (b, k) outsiders
            diff = xc[rows, None, :] - xc[emb[rows]]
            dij = np.einsum("bkd,bkd->bk", diff, diff)
            cols = groups.reach(g, float(dij[out].max()))
            pos = np.searchsorted(cols, rows)
            xcols, sqcols = x32[cols], sq32[cols]
            t = dij - sq[rows, None]                    # on the estimates' scale
            lo = np.where(out, t - slack[rows, None], -np.inf)
            hi = np.where(out, t + slack[rows, None], -np.inf)
            step = max(1, _LIST_CELLS // cols.size)
            for s in range(0, rows.size, step):
                r = rows[s:s + step]
                est = _estimates(x32[r], xcols, sqcols, pos[s:s + step])
                # the row's largest threshold, rounded up to the estimates' precision
                top = np.nextafter(hi[s:s + step].max(axis=1).astype(est.dtype), np.inf)
                flat = np.flatnonzero(est <= top[:, None])
                below = np.zeros((r.size, k), dtype=np.int64)
                if 4 * flat.size > est.size:    # a poor embedding: whole rows per threshold
                    total += _dense_ranks(xc, est, r, cols, lo[s:s + step], hi[s:s + step],
                                          dij[s:s + step], out[s:s + step], k)
                    continue
                owner, at = np.divmod(flat, cols.size)
                vals = est.ravel()[flat].astype(np.float64)
                del est
                for c in range(k):
                    lo_c, hi_c = lo[s + owner, c], hi[s + owner, c]
                    below[:, c] = np.bincount(owner[vals < lo_c], minlength=r.size)
                    near = np.flatnonzero((vals >= lo_c) & (vals <= hi_c))
                    if near.size:                       # estimates within the error bound
                        o, other = owner[near], cols[at[near]]
                        dl = xc[other] - xc[r[o]]
                        closer = np.einsum("ij,ij->i", dl, dl) < dij[s + o, c]
                        below[:, c] += np.bincount(o[closer], minlength=r.size)
                total += float(np.maximum(1 + below[out[s:s + step]] - k, 0).sum())
    return total


def _dense_ranks(xc: FloatArray, est: np.ndarray, r: IntpArray, cols: IntpArray,
                 lo: FloatArray, hi: FloatArray, dij: FloatArray, out: np.ndarray, k: int
                 ) -> float:
    """The sum of ``max(0, r(i, j) - k)`` over the outsiders ``out`` of the rows ``r``,
    from their whole rows of estimates ``est`` over ``cols``: per threshold, the entries
    below ``lo`` (rounded down to the estimates' precision) count, those up to ``hi``
    (rounded up) are decided by their exact distances."""
    total = 0.0
    for c in range(k):
        o = np.flatnonzero(out[:, c])
        if o.size == 0:
            continue
        rows_est = est[o]
        lo_c = np.nextafter(lo[o, c].astype(est.dtype), -np.inf)[:, None]
        hi_c = np.nextafter(hi[o, c].astype(est.dtype), np.inf)[:, None]
        below = np.count_nonzero(rows_est < lo_c, axis=1)
        near_o, near_l = np.nonzero((rows_est >= lo_c) & (rows_est <= hi_c))
        if near_o.size:
            dl = xc[cols[near_l]] - xc[r[o[near_o]]]
            closer = np.einsum("ij,ij->i", dl, dl) < dij[o[near_o], c]
            below += np.bincount(near_o[closer], minlength=o.size)
        total += float(np.maximum(1 + below - k, 0).sum())
    return total


def _screen(xc: FloatArray, single: bool = True
            ) -> tuple[FloatArray, np.ndarray, np.ndarray, FloatArray]:
    r"""For estimates of :math:`e_{ij} = \lVert x_j\rVert^2 - 2 x_i \cdot x_j` (the squared
    distance less :math:`\lVert x_i\rVert^2`, which ranks row ``i``) in single precision:
    ``(|x|² in double, x and |x|² in single, slack)``, ``slack[i]`` bounding the error of
    any estimate in row ``i`` (rounding of the inputs, of the products and of their sums,
    with a factor 4 of safety). Double precision if not ``single`` or if single would
    overflow."""
    sq = np.einsum("ij,ij->i", xc, xc)
    norms = np.sqrt(sq)
    top = float(norms.max()) if norms.size else 0.0
    kind = np.float32 if single and top < 1e18 else np.float64
    slack = 4.0 * (xc.shape[1] + 2) * float(np.finfo(kind).eps) * (norms * top + top * top)
    return sq, xc.astype(kind, copy=False), sq.astype(kind, copy=False), slack


def _estimates(xr: np.ndarray, xcols: np.ndarray, sqcols: np.ndarray, own: IntpArray
               ) -> np.ndarray:
    """The screen's estimates (:func:`_screen`) of the squared distances from the rows
    ``xr`` to the columns ``xcols`` less the rows' own squared norms (constant along a
    row, so they rank alike): ``-2 x_i·x_j + |x_j|²``, in the screen's precision; each
    row's own column ``own[i]`` set to ``+inf`` (a point is not its own neighbour)."""
    est: np.ndarray = xr @ xcols.T
    est *= -2.0
    est += sqcols[None, :]
    est[np.arange(xr.shape[0]), own] = np.inf
    return est


def _nearest_neighbors(x: FloatArray, k: int) -> tuple[FloatArray, IntArray]:
    """The ``k`` nearest neighbours of every point, itself excluded, exactly, each row
    sorted by (squared distance, index); the squared distances are recomputed from the
    differences (no cancellation).

    In a few dimensions a kd-tree; above ``_KDTREE_MAX_DIM`` (where a kd-tree visits
    nearly every point anyway) blocks of rows of the squared distances by one matrix
    product each (BLAS, one thread, single precision: twice as fast) and the
    ``k + _KNN_MARGIN`` smallest of each row by ``argpartition``; the candidates'
    distances are then recomputed exactly, and a row whose exact ``k``-th distance is
    not below the next estimate minus a bound on the single-precision error is redone
    in double precision, so the result is exact (up to the order of exact ties).
    Several times faster than the kd-tree in 50 dimensions.

    From :data:`~algorithms.embedding._groups.GROUPED_FROM` points the rows go group by
    group of a partition (:mod:`~algorithms.embedding._groups`) and the columns are only
    the groups that may hold a neighbour: an upper bound on each row's ``k``-th distance
    comes from the nearest groups, and every group whose gap to the row's group exceeds
    it is left out (exact still; on clustered data most of the ``n × n`` is skipped).

    Returns ``(d2, nbr)``, both ``(n, k)``."""
    n, dim = x.shape
    xc = x - x.mean(axis=0)
    if dim <= _KDTREE_MAX_DIM:
        _, found = cKDTree(xc).query(xc, k=k + 1, workers=query_workers(n))
        found = found.reshape(n, k + 1)
        own = found == np.arange(n)[:, None]
        own[~own.any(axis=1), -1] = True      # coincident points: self not returned
        return _exact_sorted(xc, np.arange(n), found[~own].reshape(n, k))
    screen = _screen(xc)
    groups = partition(xc, group_count(n))
    d2 = np.empty((n, k))
    nbr = np.empty((n, k), dtype=np.intp)
    with single_blas_thread():
        for g in range(len(groups)):
            rows = groups.members(g)
            if len(groups) == 1:
                cols = rows
            else:
                tau = _kth_bound(screen, rows, groups.nearest_groups(g, k + 1), k)
                cols = groups.reach(g, tau)
            _search_block(xc, screen, rows, cols, k, d2, nbr)
    return d2, nbr


def _kth_bound(screen: tuple[FloatArray, Any, Any, FloatArray], rows: IntpArray,
               cols: IntpArray, k: int) -> float:
    """An upper bound on the squared distance of every point of ``rows`` to its ``k``-th
    nearest neighbour: the largest ``k``-th smallest estimate over ``cols`` (which hold
    the rows and at least ``k`` others), plus the estimates' error bound."""
    sq, x32, sq32, slack = screen
    pos = np.searchsorted(cols, rows)
    xcols, sqcols = x32[cols], sq32[cols]
    step = max(1, _KNN_CELLS // cols.size)
    tau = 0.0
    for s in range(0, rows.size, step):
        r = rows[s:s + step]
        block = _estimates(x32[r], xcols, sqcols, pos[s:s + step])
        kth = np.partition(block, k - 1, axis=1)[:, k - 1].astype(np.float64)
        tau = max(tau, float((kth + sq[r] + slack[r]).max()))
    return tau


def _search_block(xc: FloatArray, screen: tuple[FloatArray, Any, Any, FloatArray],
                  rows: IntpArray, cols: IntpArray, k: int, d2: FloatArray,
                  nbr: IntpArray) -> None:
    """The ``k`` nearest of ``cols`` (sorted, holding ``rows``) to each point of ``rows``,
    written to its rows of ``d2`` and ``nbr`` (see :func:`_nearest_neighbors`)."""
    sq, x32, sq32, slack = screen
    n, dim = xc.shape
    m = cols.size
    pos = np.searchsorted(cols, rows)
    xcols, sqcols = x32[cols], sq32[cols]
    wide = min(m - 1, k + _KNN_MARGIN)                  # candidates from single precision
    step = max(1, min(rows.size, _KNN_CELLS // m, _KNN_DIFF_CELLS // max(1, wide * dim)))
    # the candidates' exact k-th distance below every other point's estimate minus the
    # slack proves the k nearest exact; rows without the proof are redone in double
    for s in range(0, rows.size, step):
        r = rows[s:s + step]
        here = np.arange(r.size)
        block = _estimates(x32[r], xcols, sqcols, pos[s:s + step])
        if wide < m - 1:
            part = np.argpartition(block, wide, axis=1)
            beyond = block[here, part[:, wide]].astype(np.float64) + sq[r] - slack[r]
        else:                                       # every other point is a candidate
            part = np.argpartition(block, wide - 1, axis=1)
            beyond = np.full(r.size, np.inf)
        cand = cols[part[:, :wide]]                 # a copy: the block's arrays freed
        del block, part
        dd, pp = _exact_sorted(xc, r, cand)
        d2[r], nbr[r] = dd[:, :k], pp[:, :k]
        redo = np.flatnonzero(~(dd[:, k - 1] < beyond))     # not proven (or NaN)
        if redo.size:
            rr = r[redo]
            block = sq[cols][None, :] - 2.0 * (xc[rr] @ xc[cols].T)
            block[np.arange(rr.size), pos[s:s + step][redo]] = np.inf
            part = np.argpartition(block, k - 1, axis=1)[:, :k]
            d2[rr], nbr[rr] = _exact_sorted(xc, rr, cols[part])


def _exact_sorted(xc: FloatArray, rows: IntArray, part: IntArray
                  ) -> tuple[FloatArray, IntArray]:
    """Squared distances from the points ``rows`` to their candidates ``part`` (one row
    each) from the differences, each row sorted by distance, ties by index."""
    diff = xc[part]
    diff -= xc[rows, None, :]                       # in place: one (b, k, D) array, not two
    return _sorted_rows(np.einsum("bkd,bkd->bk", diff, diff), part)


def _sorted_rows(d2: FloatArray, nbr: IntArray) -> tuple[FloatArray, IntArray]:
    """Each row of ``(d2, nbr)`` sorted by distance, ties by index."""
    order = np.lexsort((nbr, d2), axis=1)
    return np.take_along_axis(d2, order, axis=1), np.take_along_axis(nbr, order, axis=1)
