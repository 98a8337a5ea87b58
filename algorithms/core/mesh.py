r"""Triangle meshes: the validated :class:`Mesh` and :class:`Handles` inputs and the
combinatorial and metric quantities every mesh method needs (edges, boundary, areas,
normals, corner angles, connected components).

Everything here is vectorised over faces (no Python loop over faces or vertices); the only
loop walks boundary loops vertex by vertex, which is cheap (a boundary has
:math:`O(\sqrt{n})` vertices on a disk-like mesh).

Conventions
-----------
* ``faces`` is an ``(m, 3)`` int64 array of vertex indices; corner ``k`` of face ``f`` is
  ``faces[f, k]`` and the edge *opposite* corner ``k`` joins corners ``k + 1`` and
  ``k + 2`` (mod 3), as in libigl.
* ``vertices`` is ``(n, 2)`` (a planar mesh) or ``(n, 3)``. Vertices no face references are
  allowed; they are isolated in the graph and form components of their own.
* Undirected edges are rows ``(i, j)`` with ``i < j``, sorted lexicographically.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from algorithms.core.errors import DegenerateInputError, InvalidInputError
from algorithms.core.types import FloatArray, IntArray
from algorithms.core.validation import as_indices, as_points, check_keys

__all__ = [
    "Mesh",
    "Handles",
    "as_mesh",
    "as_handles",
    "read_mesh",
    "edges",
    "boundary_edges",
    "boundary_loops",
    "cross_norm",
    "corner_edges",
    "pattern_components",
    "edge_geometry",
    "loops_of_edges",
    "face_areas",
    "signed_areas",
    "face_normals",
    "face_angles",
    "components",
    "DEGENERATE_RTOL",
    "FACE_BLOCK",
    "degenerate_faces",
]

#: A face is degenerate (zero area) when its doubled area is at most this fraction of its
#: longest squared edge, i.e. its height is below ``DEGENERATE_RTOL`` times its longest edge
#: (collinear corners in floating point land near 1e-16).
DEGENERATE_RTOL = 1e-12

#: Faces per block of per-face geometry (:func:`degenerate_faces`, the Laplacians'
#: weights): a block's temporaries (about twenty arrays of this length) stay in a core's L2
#: cache. On a 400k-face mesh this runs 2-3x faster than whole-mesh arrays (the check of
#: :func:`degenerate_faces`: 2.1x at 100k faces, 2.8x at 400k), with bit-identical results.
FACE_BLOCK = 8192


@dataclass(frozen=True, eq=False)
class Mesh:
    """A triangle mesh in the plane or in space.

    Build one with :func:`as_mesh`, which checks it; the constructor does not.

    Attributes
    ----------
    vertices : (n, d) float array
        Vertex coordinates, one row per vertex, ``d`` = 2 or 3.
    faces : (m, 3) int array
        Triangles as rows of three vertex indices (counter-clockwise seen from the front).
    """

    vertices: FloatArray
    faces: IntArray

    @property
    def n_vertices(self) -> int:
        return int(self.vertices.shape[0])

    @property
    def n_faces(self) -> int:
        return int(self.faces.shape[0])

    @property
    def dim(self) -> int:
        return int(self.vertices.shape[1])

    @property
    def nbytes(self) -> int:
        """Bytes held by the arrays (the service sizes jobs by it)."""
        return int(self.vertices.nbytes + self.faces.nbytes)

    def __repr__(self) -> str:
        return f"Mesh(n_vertices={self.n_vertices}, n_faces={self.n_faces}, dim={self.dim})"


@dataclass(frozen=True, eq=False)
class Handles:
    """Vertices constrained to given positions (deformation handles, pinned boundary).

    Build one with :func:`as_handles`, which checks it against its mesh.

    Attributes
    ----------
    indices : (p,) int array
        Distinct vertex indices.
    positions : (p, d) float array
        Where each of those vertices must go; row ``i`` belongs to ``indices[i]``.
    """

    indices: IntArray
    positions: FloatArray

    @property
    def nbytes(self) -> int:
        """Bytes held by the arrays (the service sizes jobs by it)."""
        return int(self.indices.nbytes + self.positions.nbytes)

    def __repr__(self) -> str:
        return f"Handles(p={self.indices.shape[0]}, dim={self.positions.shape[1]})"


def _fmt_shape(shape: tuple[int, ...]) -> str:
    return "(" + ", ".join(str(s) for s in shape) + ("," if len(shape) == 1 else "") + ")"


def _shape_of(x: Any) -> tuple[int, ...] | None:
    try:
        shape: tuple[int, ...] = np.shape(x)
    except (ValueError, TypeError):  # ragged: as_indices/as_points word the error
        return None
    return shape


def edge_geometry(vertices: Any, faces: Any) -> tuple[FloatArray, FloatArray]:
    """Squared lengths of the edges opposite each corner, ``(3, m)`` (row ``k``: the edge
    opposite corner ``k``), and doubled face areas ``(m,)``.

    Works one coordinate at a time on 1-D gathers (contiguous, cache-friendly), which is
    several times faster than gathering ``(m, 3)`` rows and calling ``np.cross``.
    """
    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces, dtype=np.int64)
    f0, f1, f2 = f[:, 0], f[:, 1], f[:, 2]
    d = v.shape[1]
    sq = np.zeros((3, f.shape[0]))
    e1s, e2s = [], []
    for k in range(d):  # 2 or 3 coordinates, each vectorised over all faces
        x = v[:, k]
        a, b, c = x[f0], x[f1], x[f2]
        e0, e1, e2 = c - b, a - c, b - a
        sq[0] += e0 * e0
        sq[1] += e1 * e1
        sq[2] += e2 * e2
        e1s.append(e1)
        e2s.append(e2)
    return sq, cross_norm(e1s, e2s)


def degenerate_faces(vertices: Any, faces: Any) -> np.ndarray:
    """``(m,)`` bool: the faces of zero area, whose doubled area is at most
    :data:`DEGENERATE_RTOL` times their longest squared edge (computed in blocks of
    :data:`FACE_BLOCK` faces)."""
    f = np.asarray(faces, dtype=np.int64)
    bad = np.empty(f.shape[0], dtype=bool)
    for s in range(0, f.shape[0], FACE_BLOCK):
        sq, dbl = edge_geometry(vertices, f[s:s + FACE_BLOCK])
        np.less_equal(dbl, DEGENERATE_RTOL * sq.max(axis=0), out=bad[s:s + FACE_BLOCK])
    return bad


def corner_edges(vertices: Any, faces: Any) -> tuple[list[FloatArray], list[FloatArray]]:
    """Each face's edges from its corner 0, ``p1 - p0`` and ``p2 - p0``, one ``(m,)`` array
    per coordinate (1-D gathers: several times faster than ``(m, 3)`` rows)."""
    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces, dtype=np.int64)
    e1, e2 = [], []
    for k in range(v.shape[1]):
        x = v[:, k]
        x0 = x[f[:, 0]]
        e1.append(x[f[:, 1]] - x0)
        e2.append(x[f[:, 2]] - x0)
    return e1, e2


def cross_norm(a: list[FloatArray], b: list[FloatArray]) -> FloatArray:
    """``|a × b|`` of vectors given one coordinate per array (2 or 3 of them, each
    ``(m,)``): the absolute determinant in 2-D."""
    if len(a) == 2:
        return np.abs(a[0] * b[1] - a[1] * b[0])
    cx = a[1] * b[2] - a[2] * b[1]
    cy = a[2] * b[0] - a[0] * b[2]
    cz = a[0] * b[1] - a[1] * b[0]
    out: FloatArray = np.sqrt(cx * cx + cy * cy + cz * cz)
    return out


def _cross_norm(a: FloatArray, b: FloatArray) -> FloatArray:
    if a.shape[1] == 2:
        return np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])
    norm: FloatArray = np.linalg.norm(np.cross(a, b), axis=1)
    return norm


def as_mesh(
    vertices: Any,
    faces: Any,
    *,
    name: str = "mesh",
    max_vertices: int | None = None,
    allow_degenerate: bool = False,
) -> Mesh:
    """Check a triangle mesh and return it as a :class:`Mesh`.

    Parameters
    ----------
    vertices : array_like, (n, d)
        Vertex coordinates, ``d`` = 2 or 3, finite.
    faces : array_like, (m, 3)
        Vertex indices, integers (integral floats accepted, as JSON may deliver them) in
        ``[0, n)``, three distinct ones per face; ``m >= 1``.
    name : str, default "mesh"
        The input's name: errors name ``{name}.vertices`` or ``{name}.faces``.
    max_vertices : int, optional
        Most vertices accepted (the service's size limit).
    allow_degenerate : bool, default False
        Accept zero-area faces (their cotangent weights are infinite: only the uniform
        Laplacian and purely combinatorial functions make sense on them).

    Returns
    -------
    Mesh
        ``vertices`` as C-contiguous float64, ``faces`` as C-contiguous int64 (the inputs
        themselves when they already are; do not write into them).

    Raises
    ------
    InvalidInputError
        Wrong shapes, NaN/Inf coordinates, non-integral or out-of-range indices, a face that
        repeats a vertex; the message names the first bad row.
    DegenerateInputError
        (a subclass of :class:`InvalidInputError`) a zero-area face, unless
        ``allow_degenerate``; the message names the first one.

    Examples
    --------
    >>> m = as_mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
    >>> m.n_vertices, m.n_faces
    (3, 1)
    """
    vname, fname = f"{name}.vertices", f"{name}.faces"
    v = as_points(vertices, name=vname, min_dim=2, max_points=max_vertices)
    if v.shape[1] not in (2, 3):
        raise InvalidInputError(
            f"Expected `{vname}` to be an (n, 2) or (n, 3) array of finite numbers, got shape "
            f"{_fmt_shape(v.shape)}.", field=vname)
    n = v.shape[0]
    shape = _shape_of(faces)
    if shape is not None and (len(shape) != 2 or shape[1] != 3):
        raise InvalidInputError(
            f"Expected `{fname}` to be an (m, 3) array of vertex indices, got shape "
            f"{_fmt_shape(shape)}.", field=fname)
    f = as_indices(faces, n, name=fname, what="vertex indices")
    if f.ndim != 2 or f.shape[1] != 3:  # ragged input that numpy read after all
        raise InvalidInputError(
            f"Expected `{fname}` to be an (m, 3) array of vertex indices, got shape "
            f"{_fmt_shape(f.shape)}.", field=fname)
    if f.shape[0] == 0:
        raise InvalidInputError(f"Expected `{fname}` to hold at least 1 face, got 0.",
                                field=fname)
    repeated = (f[:, 0] == f[:, 1]) | (f[:, 1] == f[:, 2]) | (f[:, 2] == f[:, 0])
    if repeated.any():
        row = int(np.argmax(repeated))
        raise InvalidInputError(
            f"Expected `{fname}` to hold three distinct vertex indices per face, got "
            f"{f[row].tolist()} at row {row}.", field=fname)
    if not allow_degenerate:
        bad = degenerate_faces(v, f)
        if bad.any():
            row = int(np.argmax(bad))
            count = int(np.count_nonzero(bad))
            more = f" ({count} degenerate faces in all)" if count > 1 else ""
            raise DegenerateInputError(
                f"Expected `{fname}` to have non-zero area, got a degenerate (zero-area) face "
                f"{f[row].tolist()} at row {row}{more}.", field=fname)
    return Mesh(v, f)


def read_mesh(mesh: Any, *, name: str = "mesh") -> Mesh:
    """A checked :class:`Mesh` from a ``Mesh``, a mapping with the keys ``vertices`` and
    ``faces`` (as JSON delivers it) or a ``(vertices, faces)`` pair; checked by
    :func:`as_mesh` (a ``Mesh`` is checked again: its constructor does not check)."""
    if isinstance(mesh, Mesh):
        return as_mesh(mesh.vertices, mesh.faces, name=name)
    if isinstance(mesh, Mapping):
        check_keys(mesh, ("vertices", "faces"), name=name,
                   expected="an object with keys 'vertices' and 'faces'")
        return as_mesh(mesh["vertices"], mesh["faces"], name=name)
    if isinstance(mesh, (tuple, list)) and len(mesh) == 2:
        return as_mesh(mesh[0], mesh[1], name=name)
    raise InvalidInputError(
        f"Expected `{name}` to be a mesh (vertices and faces), got {type(mesh).__name__}.",
        field=name)


def as_handles(handles: Any, mesh: Mesh | int | None, *, name: str = "handles") -> Handles:
    """Check handles (vertex indices and their target positions) against a mesh.

    Parameters
    ----------
    handles : Handles or mapping
        A :class:`Handles`, or a mapping with keys ``"indices"`` (``(p,)`` integers) and
        ``"positions"`` (``(p, d)`` finite numbers), as JSON delivers it.
    mesh : Mesh or int or None
        The mesh the indices point into (its vertex count bounds them and its dimension
        fixes ``d``), a vertex count alone, or ``None`` to check the handles' own structure
        only (what the service does before it has the mesh).
    name : str, default "handles"
        Errors name ``{name}.indices`` or ``{name}.positions`` (``{name}`` itself when it is
        not a mapping).

    Returns
    -------
    Handles

    Raises
    ------
    InvalidInputError
        Not a mapping with those two keys, indices not a flat list of integers in range,
        a repeated index, positions not ``(p, d)`` with the mesh's ``d``, NaN/Inf, or a
        count of positions that differs from the count of indices.
    """
    iname, pname = f"{name}.indices", f"{name}.positions"
    if isinstance(handles, Handles):
        indices, positions = handles.indices, handles.positions
    elif isinstance(handles, Mapping):
        check_keys(handles, ("indices", "positions"), name=name,
                   expected="an object with keys 'indices' and 'positions'")
        indices, positions = handles["indices"], handles["positions"]
    else:
        raise InvalidInputError(
            f"Expected `{name}` to be an object with keys 'indices' and 'positions', got "
            f"{type(handles).__name__}.", field=name)
    if isinstance(mesh, Mesh):
        n, dim = mesh.n_vertices, mesh.dim
    elif mesh is None:
        n, dim = np.iinfo(np.int64).max, None
    else:
        n, dim = int(mesh), None
    shape = _shape_of(indices)
    if shape is not None and len(shape) != 1:
        raise InvalidInputError(
            f"Expected `{iname}` to be a flat list of vertex indices, got shape "
            f"{_fmt_shape(shape)}.", field=iname)
    idx = as_indices(indices, n, name=iname, what="vertex indices")
    if idx.ndim != 1:
        raise InvalidInputError(
            f"Expected `{iname}` to be a flat list of vertex indices, got shape "
            f"{_fmt_shape(idx.shape)}.", field=iname)
    if idx.shape[0] == 0:
        raise InvalidInputError(f"Expected `{iname}` to hold at least 1 index, got 0.",
                                field=iname)
    order = np.argsort(idx, kind="stable")
    dup = np.flatnonzero(idx[order][1:] == idx[order][:-1])
    if dup.size:
        first, second = sorted((int(order[dup[0]]), int(order[dup[0] + 1])))
        raise InvalidInputError(
            f"Expected `{iname}` to be unique, got {int(idx[first])} twice (positions "
            f"{first} and {second}).", field=iname)
    pos = as_points(positions, name=pname, dim=dim, min_dim=2)
    if pos.shape[0] != idx.shape[0]:
        raise InvalidInputError(
            f"Expected `{pname}` to hold one row per index ({idx.shape[0]}), got "
            f"{pos.shape[0]}.", field=pname)
    return Handles(idx, pos)


def _undirected_keys(faces: IntArray) -> tuple[IntArray, IntArray, IntArray, int]:
    """Half-edges ``(a -> b)`` of every face (corner k to k+1) and their undirected keys."""
    f = np.asarray(faces, dtype=np.int64)
    a = f.ravel()                                # face-major: (f0,f1), (f1,f2), (f2,f0)
    b = f[:, [1, 2, 0]].ravel()
    n = int(f.max()) + 1 if f.size else 0
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    return a, b, lo * n + hi, n


def edges(faces: Any) -> IntArray:
    """The unique undirected edges of a triangle mesh.

    Parameters
    ----------
    faces : (m, 3) int array

    Returns
    -------
    (e, 2) int array
        Rows ``(i, j)`` with ``i < j``, sorted lexicographically.

    Examples
    --------
    >>> edges([[0, 1, 2], [2, 1, 3]]).tolist()
    [[0, 1], [0, 2], [1, 2], [1, 3], [2, 3]]
    """
    _, _, keys, n = _undirected_keys(np.asarray(faces))
    if n == 0:
        return np.zeros((0, 2), dtype=np.int64)
    u = np.unique(keys)
    return np.stack([u // n, u % n], axis=1)


def boundary_edges(faces: Any) -> IntArray:
    """Edges that belong to exactly one face, oriented as in that face.

    Returns
    -------
    (b, 2) int array
        Rows ``(i, j)``: ``j`` follows ``i`` in the face's corner order, so the boundary of
        a counter-clockwise disk runs counter-clockwise. Edges shared by three or more faces
        (non-manifold) are not boundary edges.
    """
    a, b, keys, n = _undirected_keys(np.asarray(faces))
    if n == 0:
        return np.zeros((0, 2), dtype=np.int64)
    _, inverse, counts = np.unique(keys, return_inverse=True, return_counts=True)
    once = counts[inverse] == 1
    return np.stack([a[once], b[once]], axis=1)


def boundary_loops(faces: Any) -> list[IntArray]:
    """The boundary of a mesh as closed loops of vertices.

    Returns
    -------
    list of (k,) int arrays
        One array per loop, its vertices in the order of the boundary edges (counter-clockwise
        around a counter-clockwise disk), starting at its smallest vertex index; longest
        loop first, ties by that starting vertex. Empty for a closed mesh.

    Notes
    -----
    Where a vertex has two outgoing boundary edges (two fans touching at one vertex) the
    walk takes the first unused one, so such a vertex may appear twice in one loop.
    """
    return loops_of_edges(boundary_edges(faces))


def loops_of_edges(edges: Any) -> list[IntArray]:
    """Walk directed boundary edges into closed loops, as :func:`boundary_loops` does with
    those of :func:`boundary_edges` (for a caller that has them already).

    Parameters
    ----------
    edges : (b, 2) int array
        Rows ``(i, j)``: a boundary edge from ``i`` to ``j``.

    Returns
    -------
    list of (k,) int arrays
        As :func:`boundary_loops`.
    """
    be = np.asarray(edges, dtype=np.int64).reshape(-1, 2)
    if be.shape[0] == 0:
        return []
    order = np.argsort(be[:, 0], kind="stable")      # outgoing edges grouped by start vertex
    starts = be[order, 0]
    uniq, at, cnt = np.unique(starts, return_index=True, return_counts=True)
    first = dict(zip(uniq.tolist(), at.tolist()))
    count = dict(zip(uniq.tolist(), cnt.tolist()))
    used = np.zeros(be.shape[0], dtype=bool)
    ends = be[:, 1].tolist()
    order_l = order.tolist()
    loops: list[IntArray] = []
    for e0 in range(be.shape[0]):
        if used[e0]:
            continue
        loop, e = [], e0
        while not used[e]:
            used[e] = True
            loop.append(int(be[e, 0]))
            v = ends[e]
            if v not in first:
                break  # an open chain (inconsistently oriented faces): stop here
            nxt = None
            for k in range(first[v], first[v] + count[v]):
                if not used[order_l[k]]:
                    nxt = order_l[k]
                    break
            if nxt is None:
                break
            e = nxt
        arr = np.asarray(loop, dtype=np.int64)
        loops.append(np.roll(arr, -int(np.argmin(arr))))
    loops.sort(key=lambda lp: (-lp.shape[0], int(lp[0])))
    return loops


def _corners(vertices: Any, faces: Any) -> tuple[FloatArray, ...]:
    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces, dtype=np.int64)
    return v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]


def face_areas(vertices: Any, faces: Any) -> FloatArray:
    """Area of each face (non-negative), for planar or spatial meshes.

    Returns
    -------
    (m,) float array
    """
    out = cross_norm(*corner_edges(vertices, faces))  # 2.5x faster than rows and np.cross
    out *= 0.5
    return out


def signed_areas(vertices: Any, faces: Any) -> FloatArray:
    """Signed area of each face of a planar mesh: positive when its corners run
    counter-clockwise, negative when the face is flipped.

    Parameters
    ----------
    vertices : (n, 2) float array

    Returns
    -------
    (m,) float array
    """
    p0, p1, p2 = _corners(vertices, faces)
    if p0.shape[1] != 2:
        raise InvalidInputError(
            f"Expected `vertices` to be an (n, 2) array for signed areas, got shape "
            f"{_fmt_shape(np.shape(vertices))}.", field="vertices")
    a, b = p1 - p0, p2 - p0
    return 0.5 * (a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])


def face_normals(vertices: Any, faces: Any) -> FloatArray:
    """Unit normal of each face, by the right-hand rule on its corner order.

    Planar meshes are taken as lying in ``z = 0`` (normals ``(0, 0, ±1)``). A zero-area
    face gets the zero vector rather than NaN.

    Returns
    -------
    (m, 3) float array
    """
    p0, p1, p2 = _corners(vertices, faces)
    if p0.shape[1] == 2:
        pad = np.zeros((p0.shape[0], 1))
        p0, p1, p2 = (np.hstack([p, pad]) for p in (p0, p1, p2))
    c = np.cross(p1 - p0, p2 - p0)
    norm = np.linalg.norm(c, axis=1, keepdims=True)
    unit: FloatArray = np.divide(c, norm, out=np.zeros_like(c), where=norm > 0)
    return unit


def face_angles(vertices: Any, faces: Any) -> FloatArray:
    """Interior angle at each corner of each face, in radians.

    Computed as ``atan2(|a × b|, a · b)``, accurate for angles near 0 and π (unlike
    ``arccos``).

    Returns
    -------
    (m, 3) float array
        Column ``k`` is the angle at corner ``k`` (vertex ``faces[:, k]``); each row sums
        to π.
    """
    p = _corners(vertices, faces)
    out = np.empty((p[0].shape[0], 3))
    for k in range(3):  # three corners, each vectorised over all faces
        a, b = p[(k + 1) % 3] - p[k], p[(k + 2) % 3] - p[k]
        out[:, k] = np.arctan2(_cross_norm(a, b), np.einsum("ij,ij->i", a, b))
    return out


def components(n: int, edges: Any) -> tuple[int, IntArray]:
    """Connected components of the graph with ``n`` vertices and the given edges.

    Parameters
    ----------
    n : int
        Number of vertices; vertices no edge touches are components of their own.
    edges : (e, 2) int array
        Undirected edges (either orientation; repeats allowed).

    Returns
    -------
    count : int
    labels : (n,) int array
        Component of each vertex, ``0 .. count - 1``, numbered in order of each component's
        smallest vertex.
    """
    e = np.asarray(edges, dtype=np.int64).reshape(-1, 2)
    return pattern_components(
        sp.coo_array((np.ones(e.shape[0], dtype=np.int8), (e[:, 0], e[:, 1])), shape=(n, n)))


def pattern_components(a: Any) -> tuple[int, IntArray]:
    """Connected components of the graph whose edges are the stored entries of a square
    sparse matrix (its sparsity pattern, explicit zeros included, either direction): the
    components of a mesh from its Laplacian, with no edge list to build.

    Returns
    -------
    count : int
    labels : (n,) int array
        As :func:`components`.
    """
    c = sp.csr_array(a)
    g = sp.csr_array((np.ones(c.indices.shape[0], dtype=np.int8), c.indices, c.indptr),
                     shape=c.shape)
    count, labels = connected_components(g, directed=True, connection="weak")
    _, first = np.unique(labels, return_index=True)   # first vertex of each scipy label
    rank = np.empty(count, dtype=np.int64)
    rank[np.argsort(first, kind="stable")] = np.arange(count)
    return int(count), rank[labels]
