r"""A sparse Cholesky factorization of our own, compiled with numba: multifrontal, on
supernodes, after a nested-dissection ordering. It is the default install's fast path for
symmetric positive definite systems (:mod:`algorithms.core.linsolve`, backend
``"multifrontal"``), where the alternatives are SciPy's SuperLU (an LU: twice the work and
memory of a Cholesky, and its supernodal kernels are its own loops) or CHOLMOD (GPL, an
optional extra).

The steps
---------
1. **Ordering** (:func:`nested_dissection`): the graph of the matrix is cut in two by a
   separator, each half cut again, down to parts of :data:`LEAF` vertices; every
   separator is numbered after the two parts it separates. A separator is one level of a
   breadth-first search from a far vertex of the part (the last one a first search
   reached; a half inherits one from its parent's search: the root, or the last vertex
   reached), the narrowest level that leaves at least :data:`BALANCE` of the part on
   each side, less its vertices with no neighbour in the next level (they join the first
   half). On the meshes this package solves (planar-like graphs) this keeps the fill to
   :math:`O(n \log n)`, about that of SuperLU's minimum degree order (1.99M against 2.02M
   entries of ``L`` on ``bench/linsolve.py``'s 50k Laplacian), and puts most of the
   work in a few large dense blocks.
2. **Symbolic**: the elimination tree of the permuted matrix, its postorder (so that each
   subtree's columns are contiguous), the count of each column of :math:`L` (by walking
   each row's subtree), and the supernodes: runs of columns ``j, j + 1`` where ``j + 1``
   is ``j``'s parent and ``L``'s column ``j`` is column ``j + 1`` plus its diagonal,
   then relaxed (a supernode joins its parent when the zeros that adds are few:
   :data:`RELAX`). Each supernode's rows are its columns, then the union of its columns'
   rows in the matrix and its children's rows, sorted.
3. **Numeric**: in postorder, each supernode's *front* (a dense ``m × m`` matrix over its
   ``m`` rows, upper triangle) gets its columns of the matrix and its children's update
   matrices (extend-add), then a blocked dense Cholesky of its ``c`` pivots: within a
   block of :data:`BLOCK` rows, contiguous row operations; the trailing rows updated by
   matrix products (BLAS). What remains of the front, ``m - c`` rows square, is the
   update matrix its parent takes. Fronts are kept on a stack: in postorder a
   supernode's children are the last ones finished.
4. **Solves**: forward and back substitution by supernode, each right-hand side in turn:
   the rows below a supernode's diagonal block scattered (forward) or gathered (back)
   once per supernode.

Measured (``bench/linsolve.py``, the table in :mod:`~algorithms.core.linsolve`): it
factors the 5k-200k systems there 1.1-2.7× faster than SuperLU (1.7-2.7× from 50k
unknowns) and 1.3-1.7× slower than CHOLMOD; it solves 3 right-hand sides 1.0-1.5× slower
than SuperLU, one within 15 % of it. Harmonic deformation and parameterization of the
bench's 50k meshes without CHOLMOD went from 1.2-1.3× libigl's time (with SuperLU) to
0.96-0.98×.

A pivot that is not positive (the matrix is not positive definite, to rounding) stops the
factorization with :class:`NotPositiveDefinite`; :mod:`~algorithms.core.linsolve` then
falls back on SuperLU, as it does for CHOLMOD.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import scipy.sparse as sp
from numba import njit

from algorithms.core.types import FloatArray, IntArray

__all__ = ["NotPositiveDefinite", "SparseCholesky", "nested_dissection"]

#: Parts of at most this many vertices are not cut again (numbered as the search left
#: them).
LEAF = 16

#: A separator is the narrowest search level that leaves at least this fraction of the
#: part on each side.
BALANCE = 0.3

#: Relaxed supernodes: a supernode joins its parent when together they have at most
#: ``RELAX[t, 0]`` columns and at most the fraction ``RELAX[t, 1]`` of their block is
#: zeros the merge adds, for some row ``t`` (CHOLMOD's defaults).
RELAX = np.array([[4, 1.0], [16, 0.8], [48, 0.1], [1 << 62, 0.05]])

#: Columns per block of a front's dense Cholesky: the diagonal block and the panel in
#: loops, the rest of the front updated by one matrix product per block.
BLOCK = 32


class NotPositiveDefinite(ArithmeticError):
    """A pivot of the factorization was not positive."""


# --- ordering -----------------------------------------------------------------------------


@njit(cache=True, nogil=True)
def _bfs(root: int, label: int, part: Any, indptr: Any, indices: Any, level: Any,
         queue: Any) -> tuple[int, int]:  # pragma: no cover - compiled
    """Breadth-first search from ``root`` within the vertices of ``part == label``:
    ``queue[:count]`` in visiting order, ``level`` of each (the caller resets it to -1).
    Returns ``count`` and the number of levels."""
    queue[0] = root
    level[root] = 0
    head, tail = 0, 1
    while head < tail:
        v = queue[head]
        head += 1
        for p in range(indptr[v], indptr[v + 1]):
            w = indices[p]
            if level[w] < 0 and part[w] == label:
                level[w] = level[v] + 1
                queue[tail] = w
                tail += 1
    return tail, level[queue[tail - 1]] + 1


@njit(cache=True, nogil=True)
def _nested_dissection(n: int, indptr: Any, indices: Any,
                       leaf: int) -> Any:  # pragma: no cover - compiled
    order = np.arange(n)
    part = np.zeros(n, np.int64)
    level = np.full(n, -1, np.int64)
    queue = np.empty(n, np.int64)
    side = np.empty(n, np.int8)
    scratch = np.empty(n, np.int64)
    widths = np.zeros(n + 1, np.int64)
    # (start, stop, label, a far vertex or -1) of the parts to cut
    stack = np.empty((2 * n + 2, 4), np.int64)
    stack[0, 0], stack[0, 1], stack[0, 2], stack[0, 3] = 0, n, 0, -1
    top = 1
    labels = 1
    while top > 0:
        top -= 1
        a, b, label, root = stack[top, 0], stack[top, 1], stack[top, 2], stack[top, 3]
        size = b - a
        if size <= leaf:
            continue
        if root < 0:  # two sweeps: the search from the last vertex the first one reached
            count, depth = _bfs(order[a], label, part, indptr, indices, level, queue)
            root = queue[count - 1]
            for t in range(count):
                level[queue[t]] = -1
        count, depth = _bfs(root, label, part, indptr, indices, level, queue)
        if count < size:
            # not connected: what the search reached, and the rest
            for t in range(a, b):
                side[order[t]] = 1
            for t in range(count):
                side[queue[t]] = 0
            for t in range(count):
                level[queue[t]] = -1
            k = 0
            for t in range(count):
                scratch[k] = queue[t]
                k += 1
            for t in range(a, b):
                if side[order[t]] == 1:
                    scratch[k] = order[t]
                    k += 1
            order[a:b] = scratch[:size]
            for t in range(a, a + count):
                part[order[t]] = labels
            for t in range(a + count, b):
                part[order[t]] = labels + 1
            stack[top, 0], stack[top, 1], stack[top, 2], stack[top, 3] = \
                a, a + count, labels, root
            stack[top + 1, 0], stack[top + 1, 1], stack[top + 1, 2], stack[top + 1, 3] = \
                a + count, b, labels + 1, -1
            top += 2
            labels += 2
            continue
        if depth < 3:  # too dense to cut: a leaf
            for t in range(count):
                level[queue[t]] = -1
            continue
        # the narrowest level that leaves at least BALANCE of the part on each side, else
        # the level that halves it
        widths[:depth] = 0
        for t in range(count):
            widths[level[queue[t]]] += 1
        m = -1
        below = widths[0]
        for lv in range(1, depth - 1):
            above = size - below - widths[lv]
            if min(below, above) >= BALANCE * size and (m < 0 or widths[lv] < widths[m]):
                m = lv
            below += widths[lv]
        if m < 0:
            below = widths[0]
            m = 1
            while m < depth - 2 and below + widths[m] < size // 2:
                below += widths[m]
                m += 1
        # 0: first half, 1: second half, 2: separator
        seen = 0
        for t in range(count):
            v = queue[t]
            lv = level[v]
            if lv < m:
                side[v] = 0
            elif lv > m:
                side[v] = 1
            else:
                side[v] = 0
                for p in range(indptr[v], indptr[v + 1]):
                    w = indices[p]
                    if part[w] == label and level[w] == m + 1:
                        side[v] = 2
                        seen += 1
                        break
        for t in range(count):
            level[queue[t]] = -1
        k = 0
        for s in range(3):
            for t in range(a, b):
                if side[order[t]] == s:
                    scratch[k] = order[t]
                    k += 1
        order[a:b] = scratch[:size]
        n1 = 0
        for t in range(a, b):
            if side[order[t]] == 0:
                n1 += 1
        n2 = size - n1 - seen
        for t in range(a, a + n1):
            part[order[t]] = labels
        for t in range(a + n1, a + n1 + n2):
            part[order[t]] = labels + 1
        for t in range(a + n1 + n2, b):
            part[order[t]] = -1
        # far vertices of the halves: the search's root, the last vertex it reached
        stack[top, 0], stack[top, 1], stack[top, 2], stack[top, 3] = a, a + n1, labels, root
        stack[top + 1, 0], stack[top + 1, 1], stack[top + 1, 2], stack[top + 1, 3] = \
            a + n1, a + n1 + n2, labels + 1, queue[count - 1]
        top += 2
        labels += 2
    return order


def nested_dissection(a: Any, leaf: int = LEAF) -> IntArray:
    """A fill-reducing order of the symmetric matrix ``a``'s unknowns (the module's
    step 1; its lower triangle is read): ``order[k]`` is the unknown eliminated
    ``k``-th."""
    g = sp.csc_array(a)
    n = int(g.shape[0])
    ptr, adj = _adjacency(n, g.indptr.astype(np.int64), g.indices.astype(np.int64))
    return np.asarray(_nested_dissection(n, ptr, adj, int(leaf)))


# --- symbolic -----------------------------------------------------------------------------


@njit(cache=True, nogil=True, inline="always")
def _placed(i: int, j: int, inverse: Any) -> tuple[int, int]:  # pragma: no cover - compiled
    """Where the entry ``(i, j)`` of the lower triangle lands in that of ``P A Pᵀ``."""
    r, c = inverse[i], inverse[j]
    return (r, c) if r >= c else (c, r)


@njit(cache=True, nogil=True)
def _permute_lower(n: int, indptr: Any, indices: Any, data: Any,
                   inverse: Any) -> Any:  # pragma: no cover - compiled
    """The lower triangle of ``P A Pᵀ`` from the lower triangle of ``A`` (CSC; entries above
    the diagonal are not read; ``inverse[i]``: the new index of ``i``), by columns (CSC)
    and by rows (CSR: the pattern)."""
    count = np.zeros(n + 1, np.int64)
    rcount = np.zeros(n + 1, np.int64)
    for j in range(n):
        for p in range(indptr[j], indptr[j + 1]):
            if indices[p] >= j:
                r, c = _placed(indices[p], j, inverse)
                count[c + 1] += 1
                rcount[r + 1] += 1
    for j in range(n):
        count[j + 1] += count[j]
        rcount[j + 1] += rcount[j]
    nnz = count[n]
    rows = np.empty(nnz, np.int64)
    vals = np.empty(nnz)
    cols = np.empty(nnz, np.int64)
    fill = count[:n].copy()
    rfill = rcount[:n].copy()
    for j in range(n):
        for p in range(indptr[j], indptr[j + 1]):
            if indices[p] >= j:
                r, c = _placed(indices[p], j, inverse)
                rows[fill[c]] = r
                vals[fill[c]] = data[p]
                fill[c] += 1
                cols[rfill[r]] = c
                rfill[r] += 1
    return count, rows, vals, rcount, cols


@njit(cache=True, nogil=True)
def _adjacency(n: int, indptr: Any, indices: Any) -> Any:  # pragma: no cover - compiled
    """The graph of a symmetric matrix from its lower triangle (CSC): both directions of
    every entry below the diagonal."""
    count = np.zeros(n + 1, np.int64)
    for j in range(n):
        for p in range(indptr[j], indptr[j + 1]):
            i = indices[p]
            if i > j:
                count[i + 1] += 1
                count[j + 1] += 1
    for j in range(n):
        count[j + 1] += count[j]
    adj = np.empty(count[n], np.int64)
    fill = count[:n].copy()
    for j in range(n):
        for p in range(indptr[j], indptr[j + 1]):
            i = indices[p]
            if i > j:
                adj[fill[i]] = j
                fill[i] += 1
                adj[fill[j]] = i
                fill[j] += 1
    return count, adj


@njit(cache=True, nogil=True)
def _etree(n: int, ptr: Any, adj: Any, order: Any,
           inverse: Any) -> Any:  # pragma: no cover - compiled
    """The elimination tree of the matrix whose graph is ``ptr, adj`` (:func:`_adjacency`)
    in the order ``order`` (``inverse`` its inverse), by new indices (-1: a root): row
    ``k`` of the permuted lower triangle is the neighbours of ``order[k]`` that come
    before it."""
    parent = np.full(n, -1, np.int64)
    ancestor = np.full(n, -1, np.int64)
    for k in range(n):
        v = order[k]
        for p in range(ptr[v], ptr[v + 1]):
            i = inverse[adj[p]]
            while i != -1 and i < k:
                nxt = ancestor[i]
                ancestor[i] = k
                if nxt == -1:
                    parent[i] = k
                i = nxt
    return parent


@njit(cache=True, nogil=True)
def _postorder(n: int, parent: Any) -> Any:  # pragma: no cover - compiled
    head = np.full(n, -1, np.int64)
    nxt = np.full(n, -1, np.int64)
    for j in range(n - 1, -1, -1):  # children in increasing order
        if parent[j] != -1:
            nxt[j] = head[parent[j]]
            head[parent[j]] = j
    post = np.empty(n, np.int64)
    stack = np.empty(n, np.int64)
    k = 0
    for root in range(n):
        if parent[root] != -1:
            continue
        top = 0
        stack[0] = root
        while top >= 0:
            v = stack[top]
            c = head[v]
            if c == -1:
                top -= 1
                post[k] = v
                k += 1
            else:
                head[v] = nxt[c]
                top += 1
                stack[top] = c
    return post


@njit(cache=True, nogil=True)
def _symbolic(n: int, cptr: Any, crows: Any, rptr: Any, rcols: Any, parent: Any,
              relax: Any) -> Any:  # pragma: no cover - compiled
    """The supernodes (``first`` column of each, then one past the last), each one's rows
    (``srows[sptr[s]:sptr[s + 1]]``: its own columns first, the others sorted), its parent
    supernode, and the children lists (``head``, ``nxt``) of the supernodal tree."""
    counts = np.ones(n, np.int64)
    mark = np.full(n, -1, np.int64)
    for k in range(n):
        mark[k] = k
        for p in range(rptr[k], rptr[k + 1]):
            i = rcols[p]
            while mark[i] != k:  # row k's subtree: L[k, i] != 0
                mark[i] = k
                counts[i] += 1
                i = parent[i]
    # fundamental supernodes: column j - 1 joins j when L's column j - 1 is column j
    # plus its diagonal
    first = np.empty(n + 1, np.int64)
    ns = 0
    for j in range(n):
        if j == 0 or not (parent[j - 1] == j and counts[j - 1] == counts[j] + 1):
            first[ns] = j
            ns += 1
    first[ns] = n
    # relaxed: a supernode joins its parent when the parent comes right after it (it is
    # the parent's last child) and the zeros that adds are few (RELAX)
    cols = np.empty(ns, np.int64)    # of the group ending at each supernode
    rows = np.empty(ns, np.int64)
    zeros = np.zeros(ns, np.int64)
    cut = np.ones(ns + 1, np.bool_)  # a group starts at supernode s
    for s in range(ns):
        cols[s] = first[s + 1] - first[s]
        rows[s] = counts[first[s]]
    for s in range(ns - 1):
        last = first[s + 1] - 1
        if parent[last] < first[s + 1] or parent[last] >= first[s + 2]:
            continue                  # the parent is not the next supernode
        c2, m2 = cols[s] + cols[s + 1], cols[s] + rows[s + 1]
        z = zeros[s] + zeros[s + 1] + m2 * c2 - rows[s] * cols[s] - rows[s + 1] * cols[s + 1]
        frac = z / (m2 * c2)
        ok = False
        for t in range(relax.shape[0]):
            if c2 <= relax[t, 0] and frac <= relax[t, 1]:
                ok = True
        if ok:
            cut[s + 1] = False
            cols[s + 1], rows[s + 1], zeros[s + 1] = c2, m2, z
    groups = 0
    size = np.empty(ns, np.int64)    # each group's rows: those of its last supernode
    for s in range(ns):
        if cut[s]:
            first[groups] = first[s]
            groups += 1
        size[groups - 1] = rows[s]
    first[groups] = n
    ns = groups
    first = first[:ns + 1].copy()
    owner = np.empty(n, np.int64)
    for s in range(ns):
        owner[first[s]:first[s + 1]] = s
    sparent = np.full(ns, -1, np.int64)
    for s in range(ns):
        p = parent[first[s + 1] - 1]
        if p != -1:
            sparent[s] = owner[p]
    # children lists of the supernodal tree, the last child first (the order the
    # numeric step pops their update matrices in)
    head = np.full(ns, -1, np.int64)
    nxt = np.full(ns, -1, np.int64)
    for s in range(ns):
        if sparent[s] != -1:
            nxt[s] = head[sparent[s]]
            head[sparent[s]] = s
    # each supernode's rows: its columns, its columns' rows in A, its children's rows
    sptr = np.zeros(ns + 1, np.int64)
    for s in range(ns):
        sptr[s + 1] = sptr[s] + size[s]
    srows = np.empty(sptr[ns], np.int64)
    mark[:] = -1
    for s in range(ns):
        f, last = first[s], first[s + 1]
        k = sptr[s]
        for j in range(f, last):
            mark[j] = s
            srows[k] = j
            k += 1
        for j in range(f, last):
            for p in range(cptr[j], cptr[j + 1]):
                r = crows[p]
                if mark[r] != s:
                    mark[r] = s
                    srows[k] = r
                    k += 1
        c = head[s]
        while c != -1:
            for p in range(sptr[c] + first[c + 1] - first[c], sptr[c + 1]):
                r = srows[p]
                if mark[r] != s:
                    mark[r] = s
                    srows[k] = r
                    k += 1
            c = nxt[c]
        if k != sptr[s + 1]:
            raise AssertionError("a supernode's rows are not as many as counted")
        srows[sptr[s] + last - f:k].sort()  # the solves then walk b in order
    return first, sptr, srows, sparent, head, nxt


# --- numeric ------------------------------------------------------------------------------


@njit(cache=True, nogil=True)
def _dense_partial(front: Any, c: int, block: int) -> bool:  # pragma: no cover - compiled
    """Cholesky of the first ``c`` pivots of the symmetric ``front``, whose upper triangle
    is read and written (row ``j`` of it is column ``j`` of the lower one, contiguous): on
    return its first ``c`` rows hold ``Lᵀ``, its trailing block the update matrix. By
    blocks of ``block`` rows: within one, each row scaled by its pivot and taken from the
    rows after it in the block (contiguous row operations); the trailing rows then
    updated by products of the block (BLAS). False if a pivot is not positive."""
    m = front.shape[0]
    for k0 in range(0, c, block):
        k1 = min(k0 + block, c)
        for j in range(k0, k1):
            d = front[j, j]
            if not d > 0.0:
                return False
            d = np.sqrt(d)
            front[j, j] = d
            inv = 1.0 / d
            for i in range(j + 1, m):
                front[j, i] *= inv
            for r in range(j + 1, k1):
                e = front[j, r]
                for i in range(r, m):
                    front[r, i] -= e * front[j, i]
        if k1 < m:  # the trailing upper triangle, by blocks of rows
            panel = np.ascontiguousarray(front[k0:k1, k1:].T)  # (m - k1) × (k1 - k0)
            for b0 in range(0, m - k1, block):
                b1 = min(b0 + block, m - k1)
                front[k1 + b0:k1 + b1, k1 + b0:] -= np.dot(panel[b0:b1], panel[b0:].T)
    return True


@njit(cache=True, nogil=True)
def _numeric(n: int, cptr: Any, crows: Any, cvals: Any, first: Any, sptr: Any, srows: Any,
             head: Any, nxt: Any, block: int) -> Any:  # pragma: no cover - compiled
    """The supernodes' blocks of ``Lᵀ`` (each ``c × m``, row-major, in ``lx`` from
    ``lptr``), or an empty ``lptr`` if a pivot is not positive."""
    ns = first.shape[0] - 1
    lptr = np.zeros(ns + 1, np.int64)
    for s in range(ns):
        lptr[s + 1] = lptr[s] + (sptr[s + 1] - sptr[s]) * (first[s + 1] - first[s])
    lx = np.empty(lptr[ns])
    relpos = np.empty(n, np.int64)
    updates = [np.empty((0, 0))]
    owners = [-1]
    for s in range(ns):
        f, c = first[s], first[s + 1] - first[s]
        m = sptr[s + 1] - sptr[s]
        rows = srows[sptr[s]:sptr[s + 1]]
        for t in range(m):
            relpos[rows[t]] = t
        front = np.zeros((m, m))
        for j in range(f, f + c):  # A's columns, as rows of the upper triangle
            for p in range(cptr[j], cptr[j + 1]):
                front[j - f, relpos[crows[p]]] += cvals[p]
        ch = head[s]
        while ch != -1:  # the children's update matrices: the last ones pushed
            u = updates.pop()
            if owners.pop() != ch:
                raise AssertionError("an update matrix taken out of order")
            cc = first[ch + 1] - first[ch]
            crow = srows[sptr[ch] + cc:sptr[ch + 1]]
            mu = crow.shape[0]
            idx = np.empty(mu, np.int64)
            for t in range(mu):
                idx[t] = relpos[crow[t]]
            for a in range(mu):  # u's upper triangle into front's (rows unsorted)
                ia = idx[a]
                for b in range(a, mu):
                    ib = idx[b]
                    if ia <= ib:
                        front[ia, ib] += u[a, b]
                    else:
                        front[ib, ia] += u[a, b]
            ch = nxt[ch]
        if not _dense_partial(front, c, block):
            return lptr[:0], lx
        lx[lptr[s]:lptr[s + 1]] = front[:c, :].ravel()
        if m > c:
            updates.append(np.ascontiguousarray(front[c:, c:]))
            owners.append(s)
    return lptr, lx


@njit(cache=True, nogil=True)
def _solve(b: Any, first: Any, sptr: Any, srows: Any, lptr: Any,
           lx: Any) -> Any:  # pragma: no cover - compiled
    """``L Lᵀ x = b`` in the permuted order, ``bᵀ`` (k × n) overwritten with ``xᵀ``.

    By supernode: the triangular solve of its diagonal block, and the rows below it
    gathered (backward) or scattered (forward) once, the products in between over
    contiguous rows of the block (a row of ``Lᵀ`` is a column of ``L``)."""
    ns = first.shape[0] - 1
    k = b.shape[0]
    width = 0
    for s in range(ns):
        width = max(width, sptr[s + 1] - sptr[s] - (first[s + 1] - first[s]))
    work = np.empty((k, width))
    for s in range(ns):  # forward: L y = b
        f, c = first[s], first[s + 1] - first[s]
        m = sptr[s + 1] - sptr[s]
        blk = lx[lptr[s]:lptr[s + 1]].reshape((c, m))  # Lᵀ: row j is L's column j
        rows = srows[sptr[s] + c:sptr[s + 1]]
        w = m - c
        work[:, :w] = 0.0
        for q in range(k):
            x = b[q]
            u = work[q]
            for j in range(c):
                y = x[f + j] / blk[j, j]
                x[f + j] = y
                for i in range(j + 1, c):
                    x[f + i] -= blk[j, i] * y
                for i in range(w):
                    u[i] += blk[j, c + i] * y
            for i in range(w):
                x[rows[i]] -= u[i]
    for s in range(ns - 1, -1, -1):  # back: Lᵀ x = y
        f, c = first[s], first[s + 1] - first[s]
        m = sptr[s + 1] - sptr[s]
        blk = lx[lptr[s]:lptr[s + 1]].reshape((c, m))
        rows = srows[sptr[s] + c:sptr[s + 1]]
        w = m - c
        for q in range(k):
            x = b[q]
            u = work[q]
            for i in range(w):
                u[i] = x[rows[i]]
            for j in range(c - 1, -1, -1):
                acc = x[f + j]
                for i in range(j + 1, c):
                    acc -= blk[j, i] * x[f + i]
                for i in range(w):
                    acc -= blk[j, c + i] * u[i]
                x[f + j] = acc / blk[j, j]
    return b


class SparseCholesky:
    """``A = Pᵀ L Lᵀ P`` of a sparse symmetric positive definite ``A`` (its lower triangle
    is read), by the module's steps; :meth:`solve` for any number of right-hand sides.

    Raises :class:`NotPositiveDefinite` when a pivot is not positive.
    """

    def __init__(self, a: Any) -> None:
        a = sp.csc_array(a)
        a.sum_duplicates()
        n = int(a.shape[0])
        self.n = n
        indptr = a.indptr.astype(np.int64)
        indices = a.indices.astype(np.int64)
        data = np.ascontiguousarray(a.data, dtype=np.float64)
        ptr, adj = _adjacency(n, indptr, indices)
        nd = np.asarray(_nested_dissection(n, ptr, adj, LEAF))
        inverse = np.empty(n, np.int64)
        inverse[nd] = np.arange(n)
        tree = _etree(n, ptr, adj, nd, inverse)
        post = _postorder(n, tree)
        self.perm = nd[post]
        # the tree of the postordered matrix is the same tree, relabelled
        rank = np.empty(n, np.int64)
        rank[post] = np.arange(n)
        up = tree[post]
        parent = np.where(up >= 0, rank[np.maximum(up, 0)], -1)
        inverse[self.perm] = np.arange(n)
        cptr, crows, cvals, rptr, rcols = _permute_lower(n, indptr, indices, data, inverse)
        (self._first, self._sptr, self._srows, _, head,
         nxt) = _symbolic(n, cptr, crows, rptr, rcols, parent, RELAX)
        self._lptr, self._lx = _numeric(n, cptr, crows, cvals, self._first, self._sptr,
                                        self._srows, head, nxt, BLOCK)
        if self._lptr.shape[0] == 0:
            raise NotPositiveDefinite("a pivot of the Cholesky factorization was not "
                                      "positive")

    @property
    def nnz(self) -> int:
        """Stored entries of ``L`` (each supernode's diagonal block in full)."""
        return int(self._lx.shape[0])

    def factor(self) -> sp.csc_array:
        """``L`` as a sparse matrix, in the permuted order (``A[perm][:, perm] = L Lᵀ``);
        the explicit zeros of relaxed supernodes dropped."""
        rows, cols, vals = [], [], []
        for s in range(self._first.shape[0] - 1):
            f, c = int(self._first[s]), int(self._first[s + 1] - self._first[s])
            r = self._srows[self._sptr[s]:self._sptr[s + 1]]
            blk = self._lx[self._lptr[s]:self._lptr[s + 1]].reshape(c, r.shape[0]).T
            i, j = np.nonzero(blk)
            keep = r[i] >= f + j                      # the diagonal block's lower triangle
            rows.append(r[i[keep]])
            cols.append(f + j[keep])
            vals.append(blk[i[keep], j[keep]])
        out = sp.csc_array((np.concatenate(vals), (np.concatenate(rows),
                                                   np.concatenate(cols))),
                           shape=(self.n, self.n))
        out.eliminate_zeros()
        return out

    def solve(self, b: FloatArray) -> FloatArray:
        """``x`` with ``A x = b``, ``b`` of shape ``(n,)`` or ``(n, k)``."""
        arr = np.asarray(b, dtype=np.float64)
        cols = arr.reshape(self.n, -1)
        work = np.ascontiguousarray(cols[self.perm].T)  # one contiguous row per column
        _solve(work, self._first, self._sptr, self._srows, self._lptr, self._lx)
        out = np.empty_like(cols)
        out[self.perm] = work.T
        return out.reshape(arr.shape)
