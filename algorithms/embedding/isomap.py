r"""Isomap: classical MDS of geodesic (shortest-path) distances along a neighbourhood graph."""

from __future__ import annotations

import heapq
import math
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import Annotated, Any, Literal, cast

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.sparse.csgraph import breadth_first_order, connected_components, dijkstra

from algorithms.core.graphs import (
    Neighbors,
    NNeighbors,
    Radius,
    check_neighbour_params,
    neighbour_graph,
)
from algorithms.core.params import Ge, PointsLike, validate_params
from algorithms.core.threads import block_workers, single_blas_thread
from algorithms.core.types import BoolArray, FloatArray, IntArray
from algorithms.core.validation import as_int, as_points
from algorithms.embedding._quality import trustworthiness
from algorithms.layout.mds import classical_coordinates

__all__ = ["check_isomap", "IsomapResult", "isomap", "MAX_ISOMAP_POINTS", "EdgeLength"]

EdgeLength = Literal["distance", "uniform"]
"""The length of a graph edge in the shortest paths: the distance between its ends, or 1."""

#: Isomap holds the dense ``n×n`` geodesic distances: at 20,000 points 3.2 GB, the whole of
#: its peak (3.2 GiB resident, 38 s on one core for a swiss roll).
MAX_ISOMAP_POINTS = 20_000

#: From this many points the geodesic distances come from Dijkstra on a separator only
#: (:func:`_geodesic_distances`); below, Dijkstra from every point.
_PATCHED_FROM = 1000
#: Points per breadth-first ball that seeds a patch: larger patches mean fewer Dijkstra
#: rows (the separator) but wider boundaries (longer min-plus products); 192 balanced them
#: on the 5,000-point swiss roll (a fifth of the points in the separator).
_PATCH_BALL = 192
#: Patches only for graphs this sparse (mean degree); denser ones have wide boundaries.
_PATCH_MAX_DEGREE = 40
#: A patch is derived from its boundary when ``boundary * columns`` is below this many
#: times ``edges + n log2 n`` (one Dijkstra); else its points join the separator.
_DERIVE_RATIO = 4.0
#: Block Krylov: stop when every wanted Ritz residual is below this times the largest
#: Ritz value in magnitude; at least this many basis vectors before a thick restart; at
#: most this many steps (products with the matrix) before ARPACK takes over.
_KRYLOV_TOLERANCE = 1e-12
_KRYLOV_BASIS = 96
_KRYLOV_STEPS = 60


@dataclass(frozen=True, eq=False)
class IsomapResult:
    """Points in ``k`` dimensions whose distances reproduce the geodesic ones.

    Attributes
    ----------
    embedding : (n, k) float array
        One row per point, centred; column ``c`` is the ``c``-th principal coordinate of
        the geodesic distances, its entry of largest magnitude positive.
    eigenvalues : (k,) float array
        The ``k`` largest eigenvalues of :math:`-\\tfrac12 J G^{(2)} J`, decreasing
        (scikit-learn's ``kernel_pca_.eigenvalues_``).
    trustworthiness : float
        Trustworthiness of the embedding against the input points (1: every embedded
        neighbourhood is a true one).
    """

    embedding: FloatArray
    eigenvalues: FloatArray
    trustworthiness: float


def check_isomap(points: Any, n_components: Any, neighbors: str = "knn",
                 n_neighbors: Any = None, radius: Any = None) -> tuple[FloatArray, int]:
    """Check the inputs of :func:`isomap`: 2 to :data:`MAX_ISOMAP_POINTS` points (the
    geodesic distances are an n×n matrix), neighbour-graph parameters that fit them,
    ``n_components`` at most their number. Returns the points and ``n_components``."""
    x = as_points(points, name="points", min_points=2, max_points=MAX_ISOMAP_POINTS)
    check_neighbour_params(x.shape[0], neighbors, n_neighbors, radius)
    k = as_int(n_components, name="n_components", minimum=1, maximum=x.shape[0],
               reason="the number of `points`")
    return x, k


@validate_params
def isomap(
    points: PointsLike,
    *,
    n_components: Annotated[int, Ge(1)] = 2,
    neighbors: Neighbors = "knn",
    n_neighbors: NNeighbors = 5,
    radius: Radius | None = None,
    weighting: EdgeLength = "distance",
    quality_neighbors: Annotated[int, Ge(1)] = 5,
) -> IsomapResult:
    r"""Isomap.

    Classical MDS of geodesic distances: shortest paths along the neighbourhood graph (Dijkstra),
    then the top eigenvectors of −½JG⁽²⁾J. A disconnected graph is an error that says into how many
    components it falls. Reports eigenvalues and trustworthiness.

    1. A neighbourhood graph on the points (``neighbors``), each edge as long as the
       distance between its ends (``weighting="distance"``) or 1 (``"uniform"``: hops);
    2. the geodesic distances :math:`G`: all-pairs shortest paths (Dijkstra);
    3. classical MDS of :math:`G` (the ``k`` largest eigenpairs of
       :math:`-\tfrac12 J G^{(2)} J`), the code shared with ``layout.mds``.

    Parameters
    ----------
    points : (n, D) float array
        The data, one row per point; at least 2 (and more than ``n_neighbors``) and at
        most 20,000 points (the method keeps the ``n×n`` geodesic distances: 3.2 GB).
    n_components : int, default 2
        The dimension ``k`` of the embedding, ``1 <= k <= n``. It may exceed the dimension
        ``D`` of the points (geodesic distances need not be Euclidean in ``D``), as in
        scikit-learn's ``Isomap``.
    neighbors : {"knn", "radius", "all"}, default "knn"
        The neighbourhood graph: ``"knn"`` joins each point to its ``n_neighbors``
        nearest (either way round), ``"radius"`` every pair at most ``radius`` apart,
        ``"all"`` every pair (then Isomap is plain classical MDS).
    n_neighbors : int, default 5
        Neighbours per point with ``neighbors="knn"`` (the point itself not counted, as
        scikit-learn's ``Isomap``), at most ``n - 1``. Equidistant candidates are taken by
        lower index (scikit-learn's choice among them varies with its search and thread
        count: see :func:`algorithms.core.graphs.nearest_sorted`).
    radius : float, optional
        The radius with ``neighbors="radius"``, required there.
    weighting : {"distance", "uniform"}, default "distance"
        Edge *lengths* for the shortest paths: ``"distance"`` the Euclidean distance
        between the ends, ``"uniform"`` 1 per edge (hop counts). (A heat kernel is a
        similarity, not a length: there is none here.)
    quality_neighbors : int, default 5
        The neighbourhood size of the reported trustworthiness (clipped to
        ``(n - 1) // 2`` when larger).

    Returns
    -------
    IsomapResult
        ``embedding``, ``eigenvalues``, ``trustworthiness``.

    Raises
    ------
    InvalidInputError
        Bad ``points``; ``n_neighbors`` outside ``[1, n - 1]`` (fewer points than
        neighbours); ``radius`` missing or not positive; ``n_components`` outside
        ``[1, n]``; unknown ``neighbors`` or ``weighting``; more than 20,000 points.
    DegenerateInputError
        The graph is disconnected: the message says into how many components
        (``field`` ``n_neighbors`` or ``radius``).

    Notes
    -----
    **Disconnected graphs are an error** here, not repaired:
    scikit-learn ≥ 1.0 joins the components by their closest pairs with a warning
    (PR #20531), which makes the geodesic distances between components straight-line
    jumps and the embedding depend on them; an error naming the component count lets the
    caller choose more neighbours or a larger radius instead.

    **Edge values are lengths, not similarities.** The shortest paths add up edge values,
    so they must be lengths; a Laplacian's weights are similarities (large for near
    points), the inverse notion. ``weighting`` here is therefore a length, and the
    similarities of the spectral methods (``1/d``, the heat kernel) are not offered.

    With ``neighbors="knn"`` and ``weighting="distance"`` the result equals
    ``sklearn.manifold.Isomap(n_neighbors=k, eigen_solver="dense")`` up to the signs of the
    columns (same sign convention here, so equal up to ties of neighbours).

    Cost: :math:`O(n^2)` memory for the geodesic distances. Below 1,000 points, Dijkstra
    from every point, :math:`O(n (e + n \log n))`; from 1,000 (sparse graphs), Dijkstra
    from a separator of graph patches only (a fifth of the points on a swiss roll) and
    every other row by a min-plus product of the boundary rows of its patch, exact up to
    rounding (:func:`_geodesic_distances`). The eigenvectors above 400 points: a block
    Krylov method on :math:`-\tfrac12 J G^{(2)} J` applied without forming it, to Ritz
    residuals below :math:`10^{-12}` of the largest eigenvalue (ARPACK on the explicit
    matrix if that fails); a dense eigendecomposition below.

    References
    ----------
    .. [1] J. B. Tenenbaum, V. de Silva, J. C. Langford, "A global geometric framework for
       nonlinear dimensionality reduction", Science 290 (2000).

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0, np.pi, 20)
    >>> arc = np.c_[np.cos(t), np.sin(t)]             # a half circle of 19 chords
    >>> y = isomap(arc, n_components=1, neighbors="radius", radius=0.2).embedding.ravel()
    >>> chords = 19 * 2 * np.sin(np.pi / 38)          # unrolled to a segment that long
    >>> round(float(y.max() - y.min() - chords), 9)
    0.0
    """
    x, k = check_isomap(points, n_components, neighbors, n_neighbors, radius)
    g = neighbour_graph(x, neighbors=neighbors, n_neighbors=n_neighbors, radius=radius,
                        connected="isomap")
    if weighting == "uniform":
        g.data = np.ones_like(g.data)
    geo = _geodesic_distances(g)
    geo *= geo
    y, eigenvalues = _principal_coordinates(geo, k)
    del geo
    return IsomapResult(
        embedding=y,
        eigenvalues=eigenvalues,
        trustworthiness=trustworthiness(x, y, n_neighbors=quality_neighbors),
    )


def _induced(g: sp.csr_array, idx: IntArray) -> sp.csr_array:
    """The subgraph of ``g`` on the vertices ``idx`` (in that order), explicit zero-length
    edges kept (scipy's csgraph reads them as edges)."""
    pos = np.full(g.shape[0], -1, dtype=np.int64)
    pos[idx] = np.arange(idx.size)
    starts = g.indptr[idx].astype(np.int64)
    lens = g.indptr[idx + 1] - starts
    total = int(lens.sum())
    take = np.repeat(starts - np.cumsum(lens) + lens, lens) + np.arange(total)
    rows = np.repeat(np.arange(idx.size), lens)
    cols = pos[g.indices[take]]
    keep = cols >= 0
    return sp.csr_array((g.data[take][keep], (rows[keep], cols[keep])),
                        shape=(idx.size, idx.size))


def _patches(g: sp.csr_array, ball: int) -> NDArray[np.int32]:
    """A label per vertex: graph Voronoi cells (by edge length) of seeds chosen greedily,
    each seed the first vertex not yet within the first ``ball`` vertices of the
    breadth-first order from an earlier seed."""
    n = g.shape[0]
    covered = np.zeros(n, dtype=bool)
    seeds = []
    v = 0
    while v < n:
        if not covered[v]:
            seeds.append(v)
            covered[breadth_first_order(g, v, directed=True,
                                        return_predecessors=False)[:ball]] = True
        v += 1
    _, _, labels = dijkstra(g, directed=True, indices=np.asarray(seeds), min_only=True,
                            return_predecessors=True)
    return labels


def _cover(n: int, rows: IntArray, cols: NDArray[np.integer], cut: BoolArray) -> BoolArray:
    """A vertex cover of the edges ``rows[cut] - cols[cut]`` (both directions listed):
    greedily the vertex on the most uncovered edges first. A boolean mask."""
    r, c = rows[cut], cols[cut]
    cover = np.zeros(n, dtype=bool)
    if r.size == 0:
        return cover
    order = np.argsort(r, kind="stable")
    r, c = r[order], c[order]
    start = np.searchsorted(r, np.arange(n + 1))
    degree = np.diff(start)
    heap = [(-int(degree[v]), int(v)) for v in np.flatnonzero(degree)]
    heapq.heapify(heap)
    while heap:
        d, v = heapq.heappop(heap)
        if cover[v] or degree[v] == 0:
            continue
        if -d != degree[v]:  # stale entry: push back with the current degree
            heapq.heappush(heap, (-int(degree[v]), v))
            continue
        cover[v] = True
        degree[v] = 0
        for u in c[start[v]:start[v + 1]]:
            if not cover[u]:
                degree[u] -= 1
    return cover


def _geodesic_distances(g: sp.csr_array, *, patched_from: int = _PATCHED_FROM,
                        ball: int = _PATCH_BALL) -> FloatArray:
    r"""All-pairs shortest path lengths of the symmetric graph ``g``, Dijkstra from a
    separator only.

    The graph is cut into patches (:func:`_patches`); the separator :math:`S` is a vertex
    cover of the edges between patches (:func:`_cover`), so that the other vertices fall
    into components :math:`C` (within one patch each) whose outside neighbours, the
    boundary :math:`B(C)`, are all in :math:`S`. Dijkstra gives the rows of :math:`S`; a shortest
    path from :math:`v \in C` either stays in :math:`C` or leaves it first at some
    :math:`b \in B(C)`, so

    .. math::

       G_{vu} = \min\Bigl(d_C(v, u),\ \min_{b \in B(C)} d_C(v, b) + G_{bu}\Bigr),

    :math:`d_C` the distances inside the small graph on :math:`C \cup B(C)` (:math:`\infty`
    for :math:`u \notin C`): a min-plus product, :math:`|B|` times :math:`n` per row
    instead of a Dijkstra. The columns of :math:`S` come from symmetry. Equal to Dijkstra
    from every vertex up to rounding (sums in another order); a component whose boundary
    is too wide to pay off joins :math:`S`.
    """
    n = g.shape[0]
    e = g.nnz
    if n < patched_from or e > _PATCH_MAX_DEGREE * n:
        return dijkstra(g, directed=True)  # g is symmetric
    labels = _patches(g, ball)
    rows = np.repeat(np.arange(n), np.diff(g.indptr))
    cols = g.indices
    sep = _cover(n, rows, cols, labels[rows] != labels[cols])
    inner = np.flatnonzero(~sep)
    ncomp, comp = connected_components(_induced(g, inner), directed=True, connection="weak")
    comp_of = np.full(n, -1, dtype=np.int64)
    comp_of[inner] = comp
    # each component's boundary: its vertices' neighbours in the separator
    pairs = np.unique(comp_of[rows] * n + cols)
    pairs = pairs[(pairs >= 0)]
    pairs = pairs[sep[pairs % n]]
    bcomp, bvert = pairs // n, pairs % n
    bstart = np.searchsorted(bcomp, np.arange(ncomp + 1))
    # derive a component when |B| * columns beats one Dijkstra per vertex
    budget = _DERIVE_RATIO * (e + n * math.log2(n))
    width = np.diff(bstart)
    derive = width * inner.size <= budget
    sep[inner[~derive[comp]]] = True
    inner = np.flatnonzero(~sep)
    sources = np.flatnonzero(sep)
    geo = np.empty((n, n))
    for start in range(0, sources.size, 256):
        chunk = sources[start:start + 256]
        geo[chunk] = dijkstra(g, directed=True, indices=chunk)
    if inner.size == 0:
        return geo
    for start in range(0, sources.size, 256):  # the separator's columns: by symmetry
        chunk = sources[start:start + 256]
        geo[np.ix_(inner, chunk)] = geo[np.ix_(chunk, inner)].T
    local = np.full(n, -1, dtype=np.int64)
    local[inner] = np.arange(inner.size)
    members = inner[np.argsort(comp_of[inner], kind="stable")]
    mstart = np.searchsorted(comp_of[members], np.arange(ncomp + 1))
    m = inner.size

    def fill(c: int) -> None:  # the rows of component c (its own rows of geo only)
        part = members[mstart[c]:mstart[c + 1]]
        bnd = bvert[bstart[c]:bstart[c + 1]]
        inside = dijkstra(_induced(g, np.concatenate([part, bnd])), directed=True,
                          indices=np.arange(part.size))
        out = np.empty((part.size, m))
        if bnd.size:
            _min_plus(inside[:, part.size:], geo[np.ix_(bnd, inner)], out)
        else:
            out.fill(np.inf)
        cc = local[part]
        out[:, cc] = np.minimum(out[:, cc], inside[:, :part.size])
        geo[np.ix_(part, inner)] = out

    derived = np.flatnonzero(derive)
    sizes = np.diff(mstart)[derived]
    order = derived.tolist()
    # the min-plus products release the GIL: the components go to threads when they are
    # large (each writes its own rows; the results do not depend on the threads)
    workers = block_workers(int(np.median(sizes)) * m if sizes.size else 0,
                            int(np.dot(sizes, width[derived])) * m, 2)
    if workers > 1:
        with ThreadPoolExecutor(workers) as pool:
            list(pool.map(fill, order))
    else:
        for c in order:
            fill(c)
    return geo


def _min_plus(a: FloatArray, b: FloatArray, out: FloatArray) -> None:
    """``out[i, j] = min_k a[i, k] + b[k, j]``: the min-plus product, one ``k`` at a time
    over the whole of ``out`` (exact: the same sums, and a minimum does not round). On
    the 5,000-point swiss roll's patches (68 rows, 36 boundary vertices, 4,042 columns)
    1.6-1.7 ns per sum against 1.9-2.2 row by row; column blocks that stay in the cache
    were slower still (numpy's strided loops), so the sums are not blocked."""
    out.fill(np.inf)
    tmp = np.empty_like(out)
    for k in range(a.shape[1]):
        np.add(a[:, k:k + 1], b[k], out=tmp)
        np.minimum(out, tmp, out=out)


def _principal_coordinates(squared: FloatArray, k: int) -> tuple[FloatArray, FloatArray]:
    r"""Classical MDS of the squared distances ``squared`` (read only), as
    :func:`~algorithms.layout.mds.classical_coordinates`, by a block Krylov (block Lanczos
    with full reorthogonalisation) method on the operator :math:`B = -\tfrac12 J G J`
    applied without forming :math:`B`.

    The basis is kept centred, so :math:`B Q = -\tfrac12 J (G Q)`: one pass over :math:`G`
    (a BLAS-3 product with a block of :math:`k + 6` vectors) per step. Each step:
    Rayleigh-Ritz on the whole basis; stop when every wanted residual
    :math:`\lVert B u - \theta u \rVert` is below ``1e-12`` times the largest Ritz value
    in magnitude; else extend the basis by the next Krylov block (:math:`B` times the last
    block, orthogonalised). When the basis is full, a thick restart: keep the leading half
    of the Ritz vectors (no product lost) and go on from the residuals of the leading
    :math:`k + 6`. Not converged after a budget of steps (or a basis that cannot grow):
    ARPACK on the explicit matrix. Small problems and large ``k`` (over about ``n / 6``) go
    to :func:`~algorithms.layout.mds.classical_coordinates`.
    """
    with single_blas_thread():  # thin products over a large matrix: memory-bound
        return _block_krylov(squared, k)


def _block_krylov(squared: FloatArray, k: int) -> tuple[FloatArray, FloatArray]:
    """:func:`_principal_coordinates` without the thread limit."""
    n = squared.shape[0]
    b = k + 6
    limit = min(max(_KRYLOV_BASIS, 6 * b), n // 2)
    if n < 400 or 3 * b > limit:
        return classical_coordinates(squared, k)
    idx = np.arange(1, n + 1, dtype=np.float64)
    q = np.cos(np.outer(idx, np.arange(1, b + 1) * 0.6180339887498949))  # deterministic
    q -= q.mean(axis=0)
    v = cast(FloatArray, la.qr(q, mode="economic")[0])  # float64 (stubs: any floating)
    av = _centred_product(squared, v)
    last = b
    for _ in range(_KRYLOV_STEPS):
        t = v.T @ av
        theta, y = la.eigh(0.5 * (t + t.T))
        order = np.argsort(theta)[::-1]
        theta, y = theta[order], y[:, order]
        u, au = v @ y[:, :b], av @ y[:, :b]
        resid = au - u * theta[:b]
        scale = max(float(np.abs(theta).max()), np.finfo(float).tiny)
        if np.linalg.norm(resid[:, :k], axis=0).max() <= _KRYLOV_TOLERANCE * scale:
            u, theta = u[:, :k], theta[:k]
            biggest = np.argmax(np.abs(u), axis=0)
            signs = np.sign(u[biggest, np.arange(k)])
            signs[signs == 0] = 1.0
            u = u * signs
            return np.ascontiguousarray(u * np.sqrt(np.maximum(theta, 0.0))), theta
        w = av[:, -last:]  # the next Krylov block: B times the last one
        if v.shape[1] + b > limit:  # thick restart on the leading Ritz vectors
            keep = limit // 2
            v, av = v @ y[:, :keep], av @ y[:, :keep]
            w = resid  # continues their Krylov space
        size = max(float(np.linalg.norm(w, axis=0).max()), np.finfo(float).tiny)
        for _ in range(2):  # classical Gram-Schmidt, twice
            w = w - v @ (v.T @ w)
        w -= w.mean(axis=0)
        q, r = la.qr(w, mode="economic")
        # directions that are mostly rounding (the Krylov space is nearly invariant) would
        # spoil the orthonormality of the basis: drop them
        fresh = np.abs(np.diag(r)) > 1e-12 * size
        if not fresh.any():
            break
        q = q[:, fresh]
        q -= v @ (v.T @ q)
        q = cast(FloatArray, la.qr(q, mode="economic")[0])
        last = q.shape[1]
        v = np.hstack([v, q])
        av = np.hstack([av, _centred_product(squared, q)])
    return classical_coordinates(squared, k)  # not converged: ARPACK on the explicit B


def _centred_product(squared: FloatArray, q: FloatArray) -> FloatArray:
    """:math:`-\\tfrac12 J G q` for a centred block ``q`` (so that :math:`Jq = q`), ``G``
    symmetric: computed as :math:`(q^T G)^T`, which OpenBLAS does about twice as fast as
    :math:`G q` for a few columns."""
    p = (np.ascontiguousarray(q.T) @ squared).T
    p -= p.mean(axis=0)
    p *= -0.5
    return p
