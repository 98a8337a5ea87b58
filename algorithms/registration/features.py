r"""Local shape features of 3-D point sets for global registration: Fast Point Feature
Histograms (FPFH, Rusu et al. 2009), consistently oriented normals, voxel down-sampling and
mutual nearest-neighbour matching in feature space.

Everything is vectorised over points and neighbour pairs (no Python loop per point); the
neighbourhoods come from one :class:`scipy.spatial.cKDTree` per set. The results do not
depend on the number of threads.
"""

from __future__ import annotations

import math
from typing import Any, cast

import numpy as np
from scipy import sparse
from scipy.sparse.csgraph import breadth_first_order, connected_components, minimum_spanning_tree
from scipy.spatial import cKDTree

from algorithms.core.errors import InvalidInputError
from algorithms.core.types import FloatArray, IntArray, KnnQuery
from algorithms.core.validation import as_float, as_int, as_points, check_min_points
from algorithms.registration._normals import estimate_normals, given_normals

__all__ = [
    "FPFH_BINS",
    "fpfh",
    "orient_normals",
    "feature_normals",
    "match_features",
    "voxel_downsample",
    "point_spacing",
]

#: Bins per angular feature; FPFH concatenates three such histograms (33 bins).
BINS = 11
FPFH_BINS = 3 * BINS
#: Each 11-bin histogram of the SPFH and of the weighted neighbour sum is scaled to this
#: total, as Open3D and PCL do, so an FPFH block sums to 200 (100 own + 100 neighbours').
HIST_TOTAL = 100.0
#: Neighbours whose nearest-neighbour rank decides the default length scale.
SPACING_RANK = 4
#: Normals need a neighbourhood of this many points (the point and two others).
MIN_FEATURE_POINTS = 4
#: |n1·d| and |n2·d| closer than this times |d| are a tie in the choice of the source
#: point (see ``_pair_bins``).
TIE_RTOL = 1e-9
#: A minimum spanning tree edge weight may not be zero (scipy reads zero as "no edge").
_TINY_WEIGHT = 1e-12


def point_spacing(points: FloatArray, tree: cKDTree | None = None) -> float:
    r"""The sampling spacing of a point set: the median distance to the 4th nearest neighbour.

    On a surface sampled on a grid of step :math:`h` the 4th neighbour is at :math:`h`; for
    random (Poisson) samples of density :math:`\rho` it is at about
    :math:`\sqrt{4 / (\pi\rho)} \approx 1.13 / \sqrt\rho`: close to the step of a grid of the
    same density either way, so radii given as multiples of it mean the same neighbour
    counts for voxel-filtered scans and for random samples.
    """
    n = points.shape[0]
    if n < 2:
        return 0.0
    tree = cKDTree(points) if tree is None else tree
    k = min(SPACING_RANK, n - 1)
    dist, _ = cast(KnnQuery, tree.query(points, k=k + 1))
    return float(np.median(dist[:, k]))


def voxel_downsample(points: FloatArray, voxel_size: float) -> FloatArray:
    """The centroid of the points in each occupied cube of a grid of step ``voxel_size``
    (Open3D's ``voxel_down_sample``), rows in lexicographic order of the cubes.

    Parameters
    ----------
    points : (n, d) float array
    voxel_size : float
        The grid step, ``> 0``; the grid's origin is the componentwise minimum.

    Returns
    -------
    (k, d) float array
        One point per occupied cube, ``k <= n``.
    """
    voxel_size = as_float(voxel_size, name="voxel_size", minimum=0.0, inclusive=False)
    keys = np.floor((points - points.min(axis=0)) / voxel_size).astype(np.int64)
    extent = keys.max(axis=0) + 1
    if float(np.prod(extent.astype(float))) < 2.0 ** 62:
        # one integer per cube, in the lexicographic order of its index triple: a 1-D
        # unique (a sort of integers) instead of a sort of rows
        flat = np.zeros(keys.shape[0], dtype=np.int64)
        for j in range(keys.shape[1]):
            flat = flat * extent[j] + keys[:, j]
        _, inverse, counts = np.unique(flat, return_inverse=True, return_counts=True)
    else:
        _, inverse, counts = np.unique(keys, axis=0, return_inverse=True, return_counts=True)
    inverse = inverse.reshape(-1)
    out = np.zeros((counts.size, points.shape[1]))
    for j in range(points.shape[1]):  # d columns, not n points
        out[:, j] = np.bincount(inverse, weights=points[:, j], minlength=counts.size)
    return out / counts[:, None]


def orient_normals(points: FloatArray, normals: FloatArray, neighbors: IntArray) -> FloatArray:
    r"""Flip normals to one consistent side of the surface (Hoppe et al. 1992).

    The signs propagate along the minimum spanning tree of the neighbour graph weighted by
    :math:`1 - |n_i \cdot n_j|` (nearly parallel normals first), so that neighbours agree;
    then each connected part is flipped as a whole so that its normals point, on balance,
    away from its centroid (:math:`\sum_i n_i \cdot (p_i - \bar p) \ge 0`: outwards on a
    closed surface). Both rules turn with the points, so the result is rotation covariant.
    The propagation is vectorised by pointer jumping (the sign of a point is the product of
    the relative signs on its tree path, found in :math:`O(\log \text{depth})` passes).

    Parameters
    ----------
    points : (n, 3) float array
    normals : (n, 3) float array
        Unit normals of arbitrary sign.
    neighbors : (n, k) int array
        Each point's neighbours (rows of ``points``; ``n`` marks a missing one).

    Returns
    -------
    (n, 3) float array
        The normals, each multiplied by +1 or -1.
    """
    n = points.shape[0]
    rows = np.repeat(np.arange(n), neighbors.shape[1])
    cols = neighbors.reshape(-1)
    keep = (cols < n) & (cols != rows)
    rows, cols = rows[keep], cols[keep]
    weight = 1.0 - np.abs(np.einsum("ij,ij->i", normals[rows], normals[cols])) + _TINY_WEIGHT
    graph = sparse.csr_matrix((weight, (rows, cols)), shape=(n, n))
    mst = minimum_spanning_tree(graph)
    n_parts, label = connected_components(mst, directed=False)
    # A virtual root joined to the first point of every part: one traversal for all parts.
    first = np.full(n_parts, n, dtype=np.int64)
    np.minimum.at(first, label, np.arange(n))
    mst_edges = mst.tocoo()
    r = np.concatenate([mst_edges.row, np.full(n_parts, n)])
    c = np.concatenate([mst_edges.col, first])
    w = np.concatenate([mst_edges.data, np.ones(n_parts)])
    full = sparse.csr_matrix((w, (r, c)), shape=(n + 1, n + 1))
    _, parent = breadth_first_order(full, n, directed=False, return_predecessors=True)
    parent = parent[:n].astype(np.int64)
    top = parent == n
    safe = np.where(top, np.arange(n), parent)
    rel = np.where(np.einsum("ij,ij->i", normals, normals[safe]) < 0.0, -1.0, 1.0)
    rel[top] = 1.0
    # pointer jumping: sign[v] = rel[v] * sign[parent[v]], all paths at once
    sign, ptr = rel, safe
    while not np.array_equal(ptr[ptr], ptr):
        sign, ptr = sign * sign[ptr], ptr[ptr]
    out = normals * sign[:, None]
    # each part outwards on balance
    count = np.bincount(label, minlength=n_parts).astype(float)
    centre = np.stack([np.bincount(label, weights=points[:, j], minlength=n_parts)
                       for j in range(3)], axis=1) / count[:, None]
    balance = np.bincount(label, weights=np.einsum("ij,ij->i", out, points - centre[label]),
                          minlength=n_parts)
    flip = np.where(balance < 0.0, -1.0, 1.0)
    return out * flip[label][:, None]


def _neighbour_pairs(tree: cKDTree, points: FloatArray, radius: float, max_neighbors: int
                     ) -> tuple[IntArray, IntArray, FloatArray, IntArray, IntArray]:
    """The neighbourhoods of Open3D's hybrid search (at most ``max_neighbors`` nearest other
    points closer than ``radius``), as unordered pairs and directed entries.

    Returns ``(i, j, length, rows, pair)``: the unordered pairs ``i < j`` used by some
    neighbourhood with their distances, and for each directed entry (point ``rows[e]`` has
    the neighbour of pair ``pair[e]``) the pair's index. Coincident points (distance 0)
    are left out: they carry no direction. A pair exactly ``radius`` apart is left out too,
    as Open3D's ``SearchHybrid`` leaves it (squared distance strictly below the squared
    radius). One dual-tree search finds every pair once.
    """
    found = tree.query_pairs(radius * (1 + 1e-9), output_type="ndarray").astype(np.int64)
    i, j = found[:, 0], found[:, 1]
    diff = points[i] - points[j]
    d2 = np.einsum("ij,ij->i", diff, diff)
    keep = (d2 > 0.0) & (d2 < radius * radius)
    i, j, length = i[keep], j[keep], np.sqrt(d2[keep])
    m = i.size
    rows = np.concatenate([i, j])
    pair = np.concatenate([np.arange(m), np.arange(m)])
    count = np.bincount(rows, minlength=points.shape[0])
    if count.size and count.max() > max_neighbors:   # keep each point's nearest only
        # entries of over-full points, by point and nearest first: one stable sort of a
        # float key (point + distance / 2r); the other entries are all kept
        over = np.flatnonzero(count[rows] > max_neighbors)
        order = over[np.argsort(rows[over] + length[pair[over]] / (2.0 * radius),
                                kind="stable")]
        over_count = np.where(count > max_neighbors, count, 0)
        start = np.cumsum(over_count) - over_count
        rank = np.arange(order.size) - start[rows[order]]
        sel = np.concatenate([np.flatnonzero(count[rows] <= max_neighbors),
                              order[rank < max_neighbors]])
        rows, pair = rows[sel], pair[sel]
        used = np.zeros(m, dtype=bool)
        used[pair] = True
        remap = np.cumsum(used) - 1
        i, j, length, pair = i[used], j[used], length[used], remap[pair]
    return i, j, length, rows, pair


def _pair_bins(dp: FloatArray, n1: FloatArray, n2: FloatArray, length: FloatArray
               ) -> tuple[IntArray, IntArray, IntArray]:
    r"""The three angular features of point pairs, as bin indices ``0..10`` each.

    For the pair :math:`(p_s, n_s), (p_t, n_t)` (the source is the point whose normal makes
    the smaller angle with the line joining them), the Darboux frame :math:`u = n_s`,
    :math:`v = (p_t - p_s) \times u / \lVert\cdot\rVert`, :math:`w = u \times v` gives
    :math:`\alpha = v \cdot n_t`, :math:`\phi = u \cdot (p_t - p_s) / \lVert p_t - p_s
    \rVert` and :math:`\theta = \operatorname{atan2}(w \cdot n_t, u \cdot n_t)` (Open3D's
    and PCL's ``ComputePairFeatures``). All three are computed from four scalars,
    :math:`n_1 \cdot d`, :math:`n_2 \cdot d`, :math:`n_1 \cdot n_2` and the triple product
    :math:`d \cdot (n_1 \times n_2)` (which the choice of source does not change), column
    by column: no 3-vector temporaries. The features do not change when the pair is taken
    in the other order, so each unordered pair is computed once. A pair whose line is
    parallel to the source normal has no frame: its three features are 0, as in Open3D.

    ``dp``, ``n1``, ``n2`` are ``(3, m)`` (component rows); ``dp = p_2 - p_1``.
    """
    dx, dy, dz = dp
    ax, ay, az = n1
    bx, by, bz = n2
    e1 = ax * dx + ay * dy + az * dz
    e2 = bx * dx + by * dy + bz * dz
    c = ax * bx + ay * by + az * bz
    triple = dx * (ay * bz - az * by) + dy * (az * bx - ax * bz) + dz * (ax * by - ay * bx)
    # acos|e1| > acos|e2|: point 2 is the source. In a tie (equal normals: two points with
    # the same neighbours have the same PCA normal) the source is the end that makes phi
    # the larger, which does not depend on the order of the points nor on rounding.
    tie = np.abs(np.abs(e1) - np.abs(e2)) <= TIE_RTOL * length
    swap = np.where(tie, -e2 > e1, np.abs(e1) < np.abs(e2))
    a = np.where(swap, -e2, e1)             # u · d_source
    b = np.where(swap, -e1, e2)             # n_t · d_source
    vn = np.sqrt(np.maximum(length * length - a * a, 0.0))   # |d × u|
    frame = vn > 1e-12 * length
    safe = np.where(frame, vn, 1.0)
    alpha = np.where(frame, triple / safe, 0.0)
    theta = np.where(frame, np.arctan2(b - a * c, c * vn), 0.0)
    phi = np.where(frame, a / length, 0.0)

    def bins(x: FloatArray, low: float, high: float) -> IntArray:
        out = np.floor(BINS * (x - low) / (high - low)).astype(np.int64)
        return np.clip(out, 0, BINS - 1)

    return bins(theta, -math.pi, math.pi), bins(alpha, -1.0, 1.0), bins(phi, -1.0, 1.0)


def fpfh(
    points: Any,
    *,
    radius: float | None = None,
    max_neighbors: int = 100,
    normals: Any = None,
    normal_neighbors: int = 10,
) -> FloatArray:
    r"""Fast Point Feature Histograms: a 33-number description of each point's neighbourhood
    that does not change when the set is rotated or moved.

    1. **Normals**: the given ``normals``, or local PCA of the ``normal_neighbors`` nearest
       points, oriented consistently by :func:`orient_normals`.
    2. **SPFH** (simplified point feature histogram): for every neighbour :math:`p_j` of
       :math:`p_i` within ``radius`` (at most ``max_neighbors - 1``), the angles
       :math:`(\theta, \alpha, \phi)` of the Darboux frame of the pair (Notes) are
       binned into three 11-bin histograms, each scaled to sum 100.
    3. **FPFH**: :math:`F(p_i) = S(p_i) + \operatorname{norm}\big(\sum_j w_{ij}
       S(p_j)\big)` over the same neighbours with :math:`w_{ij} = 1/\lVert p_i -
       p_j\rVert^2`, each 11-bin block of the sum scaled to 100 (Open3D's
       ``ComputeFPFHFeature``).

    Parameters
    ----------
    points : (n, 3) float array
        ``n >= 4`` points.
    radius : float, optional
        Neighbourhood radius, ``> 0``: the neighbours are the points strictly closer than
        it, as in Open3D's ``KDTreeSearchParamHybrid(radius, max_nn)`` (a point exactly
        ``radius`` away is not one: on a grid of step ``h`` with ``radius = h`` no point
        has a neighbour). 5 × :func:`point_spacing` when omitted (about 80 neighbours on a
        surface, Open3D's tutorial choice of 5 voxels).
    max_neighbors : int, default 100
        At most this many nearest points within ``radius``, the point itself counted
        among them, as Open3D's ``KDTreeSearchParamHybrid(radius, max_nn)`` counts it
        (its hybrid search returns the query point first and FPFH skips it): at most
        ``max_neighbors - 1`` neighbours enter the histograms.
    normals : (n, 3) float array, optional
        Normals of the points (normalised here). Their signs matter: give them oriented
        consistently (outwards, say), or omit them.
    normal_neighbors : int, default 10
        Neighbours per estimated normal, ``>= 2``: the point and this many others (Open3D's
        ``KDTreeSearchParamKNN(knn)`` counts the point, so this is its ``knn - 1``; Open3D's
        default ``knn=30`` smooths more: pass 29 for its normals).

    Returns
    -------
    (n, 33) float array
        Non-negative histograms; each 11-bin block sums to 200 where the point has a
        neighbour within ``radius`` and to 0 where it has none.

    Raises
    ------
    InvalidInputError
        Points not 3-D or fewer than 4; a parameter out of range; normals of the wrong
        shape or of zero length.

    Notes
    -----
    For a pair :math:`(p_s, n_s), (p_t, n_t)`, the source being the point whose normal
    makes the smaller angle with the line joining them, the Darboux frame :math:`u = n_s`,
    :math:`v = (p_t - p_s) \times u / \lVert\cdot\rVert`, :math:`w = u \times v` gives
    :math:`\alpha = v \cdot n_t \in [-1, 1]`, :math:`\phi = u \cdot (p_t - p_s) /
    \lVert p_t - p_s \rVert \in [-1, 1]` and :math:`\theta = \operatorname{atan2}(w \cdot
    n_t, u \cdot n_t) \in [-\pi, \pi]`, each binned into 11 equal bins.

    The neighbour sum is weighted by the inverse *squared* distance, as in Open3D and PCL
    (both weight by what their kd-trees return, squared distances); the paper writes
    :math:`1/\omega_k` with :math:`\omega_k` the distance. Cost: one kd-tree,
    :math:`O(n k)` pair features for ``k`` neighbours, one sparse product.

    References
    ----------
    .. [1] R. B. Rusu, N. Blodow and M. Beetz, "Fast Point Feature Histograms (FPFH) for 3D
       registration", ICRA 2009, 3212-3217.
    .. [2] H. Hoppe, T. DeRose, T. Duchamp, J. McDonald and W. Stuetzle, "Surface
       reconstruction from unorganized points", SIGGRAPH 1992 (normal orientation).

    Examples
    --------
    >>> import numpy as np
    >>> from algorithms.registration import fpfh
    >>> u = np.random.default_rng(0).standard_normal((500, 3))
    >>> sphere = u / np.linalg.norm(u, axis=1, keepdims=True)
    >>> f = fpfh(sphere, radius=0.5)
    >>> f.shape, bool(np.allclose(f.reshape(500, 3, 11).sum(axis=2), 200.0))
    ((500, 33), True)
    """
    pts = as_points(points, name="points", dim=3)
    check_min_points(pts, MIN_FEATURE_POINTS, name="points",
                     reason="a normal needs a point and at least 2 neighbours")
    max_neighbors = as_int(max_neighbors, name="max_neighbors", minimum=1)
    normal_neighbors = as_int(normal_neighbors, name="normal_neighbors", minimum=2)
    tree = cKDTree(pts)
    if radius is None:
        radius = 5.0 * point_spacing(pts, tree)
        if not radius > 0.0:
            raise InvalidInputError("Expected `points` to hold distinct points, got (nearly) "
                                    "all coincident.", field="points")
    radius = as_float(radius, name="radius", minimum=0.0, inclusive=False)
    if normals is None:
        nrm = feature_normals(pts, tree, normal_neighbors)
    else:
        nrm = given_normals(normals, pts.shape[0], name="normals")
    return _fpfh(pts, nrm, tree, radius, max_neighbors)


def feature_normals(points: FloatArray, tree: cKDTree, k: int) -> FloatArray:
    """Normals by local PCA of ``k`` neighbours, consistently oriented (:func:`orient_normals`)."""
    normals, _ = estimate_normals(points, tree, k, 1)
    kk = min(k, points.shape[0] - 1)
    _, idx = cast(KnnQuery, tree.query(points, k=kk + 1))
    return orient_normals(points, normals, idx.astype(np.int64))


def _fpfh(pts: FloatArray, nrm: FloatArray, tree: cKDTree, radius: float,
          max_neighbors: int) -> FloatArray:
    n = pts.shape[0]
    # Open3D's max_nn counts the query point itself: max_neighbors - 1 others
    i, j, length, rows, pair = _neighbour_pairs(tree, pts, radius, max_neighbors - 1)
    pt, nt = np.ascontiguousarray(pts.T), np.ascontiguousarray(nrm.T)
    b1, b2, b3 = _pair_bins(pt[:, j] - pt[:, i], nt[:, i], nt[:, j], length)
    count = np.bincount(rows, minlength=n).astype(float)
    incr = np.divide(HIST_TOTAL, count, out=np.zeros(n), where=count > 0)[rows]
    base = rows * FPFH_BINS
    flat = np.concatenate([base + b1[pair], base + BINS + b2[pair],
                           base + 2 * BINS + b3[pair]])
    spfh = np.bincount(flat, weights=np.tile(incr, 3), minlength=n * FPFH_BINS)
    spfh = spfh.reshape(n, FPFH_BINS)
    cols = np.where(i[pair] == rows, j[pair], i[pair])
    weight = sparse.coo_matrix((1.0 / length[pair] ** 2, (rows, cols)), shape=(n, n))
    total = np.asarray(weight @ spfh).reshape(n, 3, BINS)              # Σ_j w_ij S(p_j)
    block = total.sum(axis=2)
    scale = np.divide(HIST_TOTAL, block, out=np.zeros_like(block), where=block > 0)
    out = (total * scale[:, :, None]).reshape(n, FPFH_BINS) + spfh
    return np.ascontiguousarray(out)


def match_features(source_features: Any, target_features: Any, *, mutual: bool = True
                   ) -> tuple[IntArray, IntArray]:
    """Pairs of points whose features are nearest neighbours (Euclidean, in feature space).

    Parameters
    ----------
    source_features : (n, f) float array
    target_features : (m, f) float array
    mutual : bool, default True
        Keep only mutual nearest neighbours: ``j`` is the nearest target feature of source
        ``i`` *and* ``i`` the nearest source feature of ``j`` (Open3D's ``mutual_filter``).

    Returns
    -------
    source_index, target_index : (k,) int arrays
        Row ``i`` of each forms one pair, in increasing ``source_index``; rows whose
        features are all zero (no neighbourhood) take no part.

    Examples
    --------
    >>> import numpy as np
    >>> a = np.array([[1.0, 0.0], [2.0, 0.0], [5.0, 5.0]])
    >>> match_features(a, a[[2, 0]] + 0.1)
    (array([0, 2]), array([1, 0]))
    """
    fa = as_points(source_features, name="source_features")
    fb = as_points(target_features, name="target_features", dim=fa.shape[1])
    ia = np.flatnonzero(np.abs(fa).sum(axis=1) > 0)
    ib = np.flatnonzero(np.abs(fb).sum(axis=1) > 0)
    if ia.size == 0 or ib.size == 0:
        return np.zeros(0, np.int64), np.zeros(0, np.int64)
    _, fwd = cKDTree(fb[ib]).query(fa[ia])
    fwd = np.asarray(fwd, dtype=np.int64).reshape(-1)
    if mutual:
        _, bwd = cKDTree(fa[ia]).query(fb[ib])
        bwd = np.asarray(bwd, dtype=np.int64).reshape(-1)
        keep = bwd[fwd] == np.arange(ia.size)
        return ia[keep].astype(np.int64), ib[fwd[keep]].astype(np.int64)
    return ia.astype(np.int64), ib[fwd].astype(np.int64)
