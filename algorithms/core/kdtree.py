r"""A kd-tree compiled with numba for the nearest-point searches of the iterative methods:
the two nearest points within a bound, one query point at a time, from code that is
itself compiled (ICP's search, :mod:`algorithms.registration.icp`).

Why not :class:`scipy.spatial.cKDTree` there: its queries are general (any ``k``, any
``p``-norm, a heap per query, the query points passed in from Python), and ICP asks
millions of the same small question: for each moved source point, its nearest and second
nearest target points within the correspondence bound. Asked here of the same tree layout
(sliding midpoint splits, leaves of :data:`LEAF` points), one query point at a time inside
a compiled loop that also does ICP's test for keeping the previous partner, the search
takes 0.4-0.6 of cKDTree's time on one thread (the bench's 10,000-point ICP pair, every
source point queried: 3.7 against 8.8 ms at the first pose, 2.8 against 5.1 ms at the
last; the same answers, distances equal to the bit), and needs no numpy call per
iteration besides.

The answers
-----------
``nearest2`` gives the smallest and the second smallest squared distance (equal when two
points tie) and the index of the nearest point; among equally near points, the smallest
index (a rule that holds on every tree and in every thread; cKDTree's own pick among
equals depends on its tree). Only points strictly closer than the bound count; when none
is, the index is ``n`` and both distances are the squared bound. A squared distance is
summed over the coordinates in order, ``(x0 - p0)² + (x1 - p1)² + ...``, as cKDTree sums
it: the same bits.

The search descends to the leaf of the query point, then visits the other sides of the
splits on its way back whose cell lies at most the second smallest distance found so far
from the query point (at most, not below: a point at exactly that distance may still be
the lowest-indexed one of a tie). A cell's distance is summed from the offsets of the
query point from the split planes that bound the cell, one per coordinate; each offset is
at most the coordinate's difference to any point in the cell, and rounding is monotonic
with terms that are not negative, so the sum is a lower bound of every such point's
squared distance in floating point too: no point that counts is ever skipped.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numba import njit

from algorithms.core.types import FloatArray, IntArray

__all__ = ["KdTree", "LEAF", "nearest2", "nearest2_any", "search"]

#: Points per leaf: 32 against 8 and 16 made the queries of the bench's 100,000-point ICP
#: pair 1.5x and 1.15x faster (fewer nodes to descend, leaves scanned in one contiguous
#: run; measured on the first version of the search, which pruned by split planes only).
LEAF = 32


@njit(cache=True, nogil=True)
def _build(points: Any, leaf: int) -> Any:  # pragma: no cover - compiled
    n, d = points.shape
    perm = np.arange(n)
    cap = 2 * n + 1
    dim = np.full(cap, -1, np.int64)
    split = np.zeros(cap)
    left = np.zeros(cap, np.int64)
    right = np.zeros(cap, np.int64)
    lo = np.zeros(cap, np.int64)
    hi = np.zeros(cap, np.int64)
    todo = np.empty(cap, np.int64)
    level = np.zeros(cap, np.int64)
    depth = 0
    mn = np.empty(d)
    mx = np.empty(d)
    count = 1
    hi[0] = n
    todo[0] = 0
    top = 1
    while top > 0:
        top -= 1
        node = todo[top]
        a, b = lo[node], hi[node]
        if b - a <= leaf:
            continue
        for c in range(d):
            mn[c] = np.inf
            mx[c] = -np.inf
        for t in range(a, b):
            for c in range(d):
                v = points[perm[t], c]
                mn[c] = min(mn[c], v)
                mx[c] = max(mx[c], v)
        axis, width = 0, mx[0] - mn[0]
        for c in range(1, d):
            if mx[c] - mn[c] > width:
                axis, width = c, mx[c] - mn[c]
        if width == 0.0:          # every point of the node at one place: a leaf
            continue
        s = 0.5 * (mn[axis] + mx[axis])
        i, j = a, b - 1
        while i <= j:             # below the midpoint to the left, the rest to the right
            if points[perm[i], axis] < s:
                i += 1
            else:
                perm[i], perm[j] = perm[j], perm[i]
                j -= 1
        m = i
        if m == a or m == b:      # one side empty: slide the split to the nearest point
            k = a
            for t in range(a + 1, b):
                v, w = points[perm[t], axis], points[perm[k], axis]
                if (m == a and v < w) or (m == b and v > w):
                    k = t
            end = a if m == a else b - 1
            perm[end], perm[k] = perm[k], perm[end]
            s = points[perm[end], axis]
            m = a + 1 if m == a else b - 1
        dim[node], split[node] = axis, s
        left[node], right[node] = count, count + 1
        lo[count], hi[count], lo[count + 1], hi[count + 1] = a, m, m, b
        level[count] = level[count + 1] = level[node] + 1
        depth = max(depth, level[node] + 1)
        todo[top], todo[top + 1] = count, count + 1
        top += 2
        count += 2
    return (perm, dim[:count].copy(), split[:count].copy(), left[:count].copy(),
            right[:count].copy(), lo[:count].copy(), hi[:count].copy(), depth)


class KdTree:
    """The target side of the searches: a kd-tree over ``points`` (``(n, d)``, float64),
    its arrays ready for :func:`nearest2`.

    Attributes
    ----------
    data : (n, d) float array
        The points, in their order.
    sorted : (n, d) float array
        The points in leaf order (each leaf a contiguous run).
    perm : (n,) int array
        ``sorted[t] = data[perm[t]]``.
    dim, split, left, right, lo, hi : (nodes,) arrays
        Per node: the split coordinate (-1 for a leaf), the split value, the two children,
        and the run ``lo:hi`` of ``sorted`` it holds.
    stack : int
        The entries a search stack needs: the tree's depth plus one (each level of the
        path a search is on holds at most one node waiting). Sliding midpoint splits keep
        real data shallow; a degenerate set (one point split off at a time) can be deep.
    """

    def __init__(self, points: FloatArray, leaf: int = LEAF) -> None:
        data = np.ascontiguousarray(points, dtype=np.float64)
        # writable: compiled code is specialised on read-only arrays apart (another compile)
        self.data = data if data.flags.writeable else data.copy()
        self.n = int(self.data.shape[0])
        (self.perm, self.dim, self.split, self.left, self.right, self.lo,
         self.hi, depth) = _build(self.data, leaf)
        self.stack = int(depth) + 1
        self.sorted = np.ascontiguousarray(self.data[self.perm])

    @property
    def wide(self) -> int | None:
        """What :func:`search` takes to pick the search for the tree's dimension: ``None``
        for points of 2 or 3 coordinates (:func:`nearest2`), else their number
        (:func:`nearest2_any`)."""
        d = int(self.data.shape[1])
        return None if d in (2, 3) else d

    def nodes(self) -> tuple[Any, ...]:
        """The arguments :func:`nearest2` takes after the query point."""
        return (self.sorted, self.perm, self.dim, self.split, self.left, self.right,
                self.lo, self.hi)

    def query2(self, x: FloatArray, bound: float = np.inf) -> tuple[FloatArray, FloatArray,
                                                                     IntArray]:
        """For each row of ``x``: the distances of its nearest and second nearest points
        strictly within ``bound`` (inf where there is none) and the nearest one's index
        (``n`` where there is none). A plain loop over :func:`nearest2`, for tests and
        callers outside compiled code."""
        x = np.ascontiguousarray(x, dtype=np.float64)
        d1, d2, idx = _query_rows(self.wide, x, float(bound) ** 2, self.stack,
                                  *self.nodes())
        return d1, d2, idx


@njit(cache=True, nogil=True, inline="always")
def _offer(s: float, p: int, best1: float, best2: float, found: int
           ) -> tuple[float, float, int]:  # pragma: no cover - compiled
    """The two smallest squared distances and the nearest's index after the point ``p`` at
    ``s`` is seen: among equals the smallest index is the nearest, and a tie leaves the
    second smallest equal to the smallest."""
    if s < best1 or (s == best1 and p < found):
        return s, best1, p
    if s < best2:
        return best1, s, found
    return best1, best2, found


@njit(cache=True, nogil=True)
def nearest2_any(x: Any, b2: float, stack_node: Any, stack_box: Any, data: Any, perm: Any,
                  dim: Any, split: Any, left: Any, right: Any, lo: Any, hi: Any
                  ) -> tuple[float, float, int]:  # pragma: no cover - compiled
    """:func:`nearest2` in any dimension ``d`` (``stack_box`` with ``d + 1`` columns): a
    loop over the coordinates where :func:`nearest2` spells out two or three (calling
    this from there made the 3-D search a third slower: the caller chooses)."""
    d = x.shape[0]
    n = perm.shape[0]
    off = np.empty(d)
    best1, best2, found = b2, b2, n
    stack_node[0] = 0
    stack_box[0, :d + 1] = 0.0
    top = 1
    while top > 0:
        top -= 1
        if stack_box[top, 0] > best2:
            continue
        node = stack_node[top]
        off[:] = stack_box[top, 1:d + 1]
        while dim[node] >= 0:
            c = dim[node]
            gap = x[c] - split[node]
            if gap < 0.0:
                near, far = left[node], right[node]
                gap = -gap
            else:
                near, far = right[node], left[node]
            box = 0.0
            for k in range(d):
                f = gap if k == c else off[k]
                box += f * f
            if box <= best2:
                stack_node[top] = far
                stack_box[top, 0] = box
                stack_box[top, 1:d + 1] = off
                stack_box[top, 1 + c] = gap
                top += 1
            node = near
        for t in range(lo[node], hi[node]):
            s = 0.0
            for k in range(d):
                e = x[k] - data[t, k]
                s += e * e
            if s <= best2 and s < b2:
                best1, best2, found = _offer(s, perm[t], best1, best2, found)
    return best1, best2, found


@njit(cache=True, nogil=True)
def nearest2(x: Any, b2: float, stack_node: Any, stack_box: Any, data: Any, perm: Any,
             dim: Any, split: Any, left: Any, right: Any, lo: Any, hi: Any
             ) -> tuple[float, float, int]:  # pragma: no cover - compiled
    """The smallest and second smallest squared distances from the point ``x`` (2 or 3
    coordinates; :func:`nearest2_any` for others) to the tree's points strictly below
    ``b2`` (``b2`` where there are not two), and the index of the nearest (``len(perm)``
    where there is none; the smallest index among equals). ``stack_node`` (int) and
    ``stack_box`` (float, ``max(4, d + 1)`` columns) are the caller's scratch arrays of at
    least :attr:`KdTree.stack` rows."""
    d = x.shape[0]
    n = perm.shape[0]
    x0, x1 = x[0], x[1]
    x2 = x[2] if d == 3 else 0.0
    best1, best2, found = b2, b2, n
    # a node waits with the squared distance from x to its cell and the three offsets
    # from x to the cell's sides along each coordinate that make it up
    stack_node[0] = 0
    stack_box[0, 0] = stack_box[0, 1] = stack_box[0, 2] = stack_box[0, 3] = 0.0
    top = 1
    while top > 0:
        top -= 1
        if stack_box[top, 0] > best2:
            continue
        node = stack_node[top]
        o0, o1, o2 = stack_box[top, 1], stack_box[top, 2], stack_box[top, 3]
        while dim[node] >= 0:
            c = dim[node]
            gap = (x0 if c == 0 else x1 if c == 1 else x2) - split[node]
            if gap < 0.0:
                near, far = left[node], right[node]
                gap = -gap
            else:
                near, far = right[node], left[node]
            f0 = gap if c == 0 else o0
            f1 = gap if c == 1 else o1
            f2 = gap if c == 2 else o2
            box = f0 * f0 + f1 * f1 + f2 * f2
            if box <= best2:
                stack_node[top] = far
                stack_box[top, 0], stack_box[top, 1] = box, f0
                stack_box[top, 2], stack_box[top, 3] = f1, f2
                top += 1
            node = near
        for t in range(lo[node], hi[node]):
            e0, e1 = x0 - data[t, 0], x1 - data[t, 1]
            s = e0 * e0 + e1 * e1
            if d == 3:
                e2 = x2 - data[t, 2]
                s += e2 * e2
            if s <= best2 and s < b2:
                best1, best2, found = _offer(s, perm[t], best1, best2, found)
    return best1, best2, found


@njit(cache=True, nogil=True)
def search(wide: int | None, x: Any, b2: float, stack_node: Any, stack_box: Any, data: Any,
           perm: Any, dim: Any, split: Any, left: Any, right: Any, lo: Any, hi: Any
           ) -> tuple[float, float, int]:  # pragma: no cover - compiled
    """:func:`nearest2` if ``wide`` is None (points of 2 or 3 coordinates:
    :attr:`KdTree.wide`), else :func:`nearest2_any`: the one way compiled callers pick the
    search.

    Compiled apart for ``None`` and for an integer, each with the other branch pruned
    (numba decides ``is None`` from the argument's type), so a 3-D caller holds only
    :func:`nearest2`: a boolean flag, with both branches in the loop, made the 10,000-point
    ICP pair 13 % slower.

    Why not the search itself as an argument (as callers did): a compiled function cached
    on disk whose signature holds another compiled function keeps that one in its cache
    index by a weak reference, restored from the file as a new object that nothing else
    holds. Once numba lets it go (it keeps the last 128 it restored), the next compile of
    the caller in that process, for a signature not yet in the index, fails to write the
    index back (``ReferenceError: underlying object has vanished``): a multiway job on a
    Dask worker failed so."""
    if wide is None:
        return nearest2(x, b2, stack_node, stack_box, data, perm, dim, split, left, right,
                        lo, hi)
    return nearest2_any(x, b2, stack_node, stack_box, data, perm, dim, split, left, right,
                        lo, hi)


@njit(cache=True, nogil=True)
def _query_rows(wide: int | None, x: Any, b2: float, stack: int, data: Any, perm: Any, dim: Any,
                split: Any, left: Any, right: Any, lo: Any,
                hi: Any) -> Any:  # pragma: no cover - compiled
    m = x.shape[0]
    n = perm.shape[0]
    d1 = np.empty(m)
    d2 = np.empty(m)
    idx = np.empty(m, np.int64)
    stack_node = np.empty(stack, np.int64)
    stack_box = np.empty((stack, max(4, x.shape[1] + 1)))
    for i in range(m):
        s1, s2, k = search(wide, x[i], b2, stack_node, stack_box, data, perm, dim, split,
                           left, right, lo, hi)
        d1[i] = np.sqrt(s1) if k < n else np.inf
        d2[i] = np.sqrt(s2) if s2 < b2 else np.inf
        idx[i] = k
    return d1, d2, idx
