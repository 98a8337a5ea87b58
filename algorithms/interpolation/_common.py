r"""What every interpolation method shares: reading the two shapes (or a shape and a
transform) and the times, rotation logarithms and exponentials (the slerp of a rotation
from the identity), and the per-frame quality measures.

Inputs
------
``source`` is a point set ``(n, d)`` or a mesh (a :class:`~algorithms.core.mesh.Mesh`, a
mapping ``{"vertices", "faces"}``); the mesh methods also take tetrahedra
(``faces`` of shape ``(m, 4)`` in 3-D). The end shape is either ``target`` (points
``(n, d)`` or a mesh *with the same faces*: vertex ``i`` of the source goes to vertex ``i``
of the target) or ``transform``, a homogeneous ``(d+1, d+1)`` matrix applied to the source.

Times
-----
``times`` is a strictly increasing list of numbers in ``[0, 1]`` (default: 11 evenly
spaced). Extrapolation (``t < 0`` or ``t > 1``) is refused: ``(1 - t) I + t S`` stops
being positive definite for ``t > 1 / (1 - λ_min(S))`` when the stretch ``S`` shrinks
somewhere, so volume could collapse outside the interval, and a rotation angle beyond
``π`` would no longer be the shortest arc.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, cast

import numpy as np
from scipy.spatial import cKDTree
from scipy.spatial.transform import Rotation

from algorithms.core.errors import DegenerateInputError, InvalidInputError
from algorithms.core.mesh import DEGENERATE_RTOL, Mesh, as_mesh
from algorithms.core.types import FloatArray, IntArray, KnnQuery
from algorithms.core.validation import MAX_COORDINATE, as_indices, as_int, as_points, check_keys

__all__ = [
    "DEFAULT_TIMES",
    "MAX_FRAMES",
    "MAX_FRAME_VALUES",
    "Pair",
    "read_times",
    "read_shape",
    "read_transform",
    "read_pair",
    "check_frame_count",
    "check_pair",
    "check_anchor",
    "check_anchored",
    "rotation_log",
    "rotation_exp",
    "edges_of",
    "edge_errors",
    "pivot_of",
    "surface_triangles",
    "row_keys",
]

#: Frames when ``times`` is omitted: t = 0, 0.1, ..., 1.
DEFAULT_TIMES = 11
#: Most frames one request may ask for.
MAX_FRAMES = 1001
#: Most numbers the ``frames`` output may hold (frames × vertices × dimension).
MAX_FRAME_VALUES = 20_000_000


@dataclass(frozen=True, eq=False)
class Pair:
    """The two shapes to interpolate between, checked.

    Attributes
    ----------
    source : (n, d) float array
        The shape at ``t = 0``.
    target : (n, d) float array
        The shape at ``t = 1`` (the source moved by ``transform`` when that was given).
    faces : (m, k) int array
        Triangles (``k = 3``) or tetrahedra (``k = 4``); ``(0, 3)`` for point sets.
    transform : (d+1, d+1) float array or None
        The homogeneous transform given instead of a target.
    """

    source: FloatArray
    target: FloatArray
    faces: IntArray
    transform: FloatArray | None

    @property
    def n(self) -> int:
        return int(self.source.shape[0])

    @property
    def dim(self) -> int:
        return int(self.source.shape[1])


def read_times(times: Any, *, name: str = "times") -> FloatArray:
    """``times`` as a strictly increasing float array in ``[0, 1]`` (11 evenly spaced values
    when ``None``).

    Raises
    ------
    InvalidInputError
        Not a flat non-empty list of finite numbers, more than :data:`MAX_FRAMES` values, a
        value outside ``[0, 1]`` or not strictly increasing (the message names the first
        offending position).
    """
    if times is None:
        return np.linspace(0.0, 1.0, DEFAULT_TIMES)
    try:
        arr = np.asarray(times)
    except (TypeError, ValueError):
        arr = np.asarray(None)
    if arr.dtype.kind not in "iuf" or arr.ndim != 1:
        what = (f"shape {arr.shape}" if arr.dtype.kind in "iuf" else
                f"{type(times).__name__}" if arr.ndim == 0 else "non-numeric values")
        raise InvalidInputError(
            f"Expected `{name}` to be a flat list of numbers in [0, 1], got {what}.",
            field=name)
    t = arr.astype(np.float64)
    if t.shape[0] == 0:
        raise InvalidInputError(f"Expected `{name}` to hold at least 1 time, got 0.",
                                field=name)
    if t.shape[0] > MAX_FRAMES:
        raise InvalidInputError(
            f"Expected `{name}` to hold at most {MAX_FRAMES} times, got {t.shape[0]}.",
            field=name)
    bad = ~np.isfinite(t) | (t < 0) | (t > 1)
    if bad.any():
        i = int(np.argmax(bad))
        raise InvalidInputError(
            f"Expected `{name}` to lie in [0, 1] (extrapolation is not offered), got "
            f"{float(t[i])!r} at position {i}.", field=name)
    if t.shape[0] > 1:
        step = np.diff(t)
        if (step <= 0).any():
            i = int(np.argmax(step <= 0)) + 1
            raise InvalidInputError(
                f"Expected `{name}` to be strictly increasing, got {float(t[i])!r} at position "
                f"{i} after {float(t[i - 1])!r}.", field=name)
    return t


def _check_cells(v: FloatArray, cells: Any, name: str, allow_degenerate: bool) -> IntArray:
    """Tetrahedra ``(m, 4)`` of a 3-D vertex array: indices in range, distinct, non-zero
    volume."""
    fname = f"{name}.faces"
    f = as_indices(cells, v.shape[0], name=fname, what="vertex indices")
    if f.ndim != 2 or f.shape[1] != 4 or f.shape[0] == 0 or v.shape[1] != 3:
        raise InvalidInputError(
            f"Expected `{fname}` to be an (m, 3) array of triangles or, with (n, 3) vertices, "
            f"an (m, 4) array of tetrahedra, got shape {tuple(f.shape)}.", field=fname)
    srt = np.sort(f, axis=1)
    repeated = (srt[:, 1:] == srt[:, :-1]).any(axis=1)
    if repeated.any():
        row = int(np.argmax(repeated))
        raise InvalidInputError(
            f"Expected `{fname}` to hold four distinct vertex indices per tetrahedron, got "
            f"{f[row].tolist()} at row {row}.", field=fname)
    if allow_degenerate:
        return np.ascontiguousarray(f, dtype=np.int64)
    p = v[f]
    e = p[:, 1:] - p[:, :1]
    vol6 = np.abs(np.linalg.det(e))
    longest = np.max([np.einsum("ij,ij->i", a - b, a - b)
                      for a, b in ((p[:, i], p[:, j]) for i in range(4) for j in range(i))],
                     axis=0)
    bad = vol6 <= DEGENERATE_RTOL * longest ** 1.5
    if bad.any():
        row = int(np.argmax(bad))
        raise DegenerateInputError(
            f"Expected `{fname}` to have non-zero volume, got a degenerate tetrahedron "
            f"{f[row].tolist()} at row {row}.", field=fname)
    return np.ascontiguousarray(f, dtype=np.int64)


def read_shape(shape: Any, *, name: str, need_faces: bool = False,
               max_points: int | None = None, allow_degenerate: bool = False
               ) -> tuple[FloatArray, IntArray]:
    """Vertices and faces of a point set (faces ``(0, 3)``) or a mesh (triangles; in 3-D
    tetrahedra too); ``allow_degenerate`` accepts zero-area faces (a target may flatten).

    Raises
    ------
    InvalidInputError
        Malformed points or mesh (the field names ``name``, ``name.vertices`` or
        ``name.faces``); a point set where ``need_faces``.
    """
    if isinstance(shape, Mesh):
        shape = {"vertices": shape.vertices, "faces": shape.faces}
    if isinstance(shape, Mapping):
        check_keys(shape, ("vertices", "faces"), name=name,
                   expected="an object with keys 'vertices' and 'faces'")
        faces = shape["faces"]
        try:
            width = np.shape(faces)[1] if np.ndim(faces) == 2 else None
        except (TypeError, ValueError):
            width = None
        if width == 4:
            v = as_points(shape["vertices"], name=f"{name}.vertices", dim=3,
                          max_points=max_points)
            return v, _check_cells(v, faces, name, allow_degenerate)
        m = as_mesh(shape["vertices"], faces, name=name, max_vertices=max_points,
                    allow_degenerate=allow_degenerate)
        return m.vertices, m.faces
    if need_faces:
        raise InvalidInputError(
            f"Expected `{name}` to be a mesh {{vertices, faces}} (this method interpolates "
            f"per face), got {type(shape).__name__}.", field=name)
    v = as_points(shape, name=name, min_dim=2, max_points=max_points)
    if v.shape[1] not in (2, 3):
        raise InvalidInputError(
            f"Expected `{name}` to be an (n, 2) or (n, 3) array of finite numbers, got shape "
            f"{v.shape}.", field=name)
    return v, np.zeros((0, 3), dtype=np.int64)


def read_transform(transform: Any, d: int, *, name: str = "transform") -> FloatArray:
    """A homogeneous ``(d+1, d+1)`` matrix with last row ``(0, ..., 0, 1)``."""
    t = as_points(transform, name=name)
    if t.shape != (d + 1, d + 1):
        raise InvalidInputError(
            f"Expected `{name}` to be a homogeneous ({d + 1}, {d + 1}) matrix for "
            f"{d}-D shapes, got shape {t.shape}.", field=name)
    last = np.zeros(d + 1)
    last[d] = 1.0
    if not np.array_equal(t[d], last):
        raise InvalidInputError(
            f"Expected the last row of `{name}` to be {last.tolist()} (an affine map), got "
            f"{t[d].tolist()}.", field=name)
    return t


def read_pair(source: Any, target: Any = None, transform: Any = None, *,
              need_faces: bool = False, max_points: int | None = None) -> Pair:
    """Check the start shape and the end shape (``target`` or ``transform``, exactly one).

    Raises
    ------
    InvalidInputError
        Malformed inputs; neither or both of ``target`` and ``transform`` (field
        ``target`` / ``transform``); a target whose shape differs from the source's
        (``target`` / ``target.vertices``) or a target mesh with other faces
        (``target.faces``: the methods need the same connectivity).
    """
    v, f = read_shape(source, name="source", need_faces=need_faces, max_points=max_points)
    n, d = v.shape
    if target is None and transform is None:
        raise InvalidInputError(
            "Expected `target` (the end shape) or `transform` (a homogeneous matrix), got "
            "neither.", field="target")
    if target is not None and transform is not None:
        raise InvalidInputError(
            "Expected either `target` or `transform`, got both.", field="transform")
    if transform is not None:
        t = read_transform(transform, d)
        with np.errstate(all="ignore"):
            w = v @ t[:d, :d].T + t[:d, d]
        if not (np.isfinite(w).all() and np.abs(w).max(initial=0.0) <= MAX_COORDINATE):
            raise InvalidInputError(
                f"Expected `transform` to map the source to coordinates of magnitude at most "
                f"{MAX_COORDINATE:g}, got {np.abs(w).max():.3g}.", field="transform")
        return Pair(v, np.ascontiguousarray(w), f, t)
    if isinstance(target, (Mesh, Mapping)):
        if not isinstance(source, (Mesh, Mapping)):
            raise InvalidInputError(
                "Expected `target` to be a point set like `source`, got a mesh.",
                field="target")
        w, g = read_shape(target, name="target", max_points=max_points,
                          allow_degenerate=True)
        if w.shape != (n, d):
            raise InvalidInputError(
                f"Expected `target.vertices` to have the shape of `source.vertices` "
                f"({n}, {d}), got {w.shape}.", field="target.vertices")
        if g.shape != f.shape or not np.array_equal(g, f):
            if g.shape != f.shape:
                what = f"{g.shape[0]} faces of {g.shape[1]} vertices"
            else:
                row = int(np.argmax((g != f).any(axis=1)))
                what = f"{g[row].tolist()} at row {row} where the source has {f[row].tolist()}"
            raise InvalidInputError(
                f"Expected `target.faces` to equal `source.faces` (the same connectivity, "
                f"{f.shape[0]} faces), got {what}.", field="target.faces")
        return Pair(v, w, f, None)
    w = as_points(target, name="target", max_points=max_points)
    if w.shape != (n, d):
        raise InvalidInputError(
            f"Expected `target` to have the shape of the source ({n}, {d}): one row per "
            f"source {'vertex' if f.shape[0] else 'point'}, got {w.shape}.", field="target")
    return Pair(v, w, f, None)


def check_frame_count(n: int, d: int, times: FloatArray) -> None:
    """Refuse requests whose ``frames`` output would hold more than
    :data:`MAX_FRAME_VALUES` numbers (field ``times``)."""
    if times.shape[0] * n * d > MAX_FRAME_VALUES:
        raise InvalidInputError(
            f"Expected `times` to ask for at most {MAX_FRAME_VALUES // max(n * d, 1)} frames "
            f"of this {n}-vertex shape ({MAX_FRAME_VALUES:,} numbers in all), got "
            f"{times.shape[0]}.", field="times")


# --- rotations: logarithm and exponential -------------------------------------------------
def rotation_log(R: FloatArray) -> FloatArray:
    r"""The rotation vector of each rotation of a stack: ``(..., 1)`` angles in
    :math:`(-\pi, \pi]` for ``d = 2``, ``(..., 3)`` axis-angle vectors of length at most
    :math:`\pi` for ``d = 3`` (the shortest arc; at exactly :math:`\pi` one of the two)."""
    d = R.shape[-1]
    if d == 2:
        return np.arctan2(R[..., 1, 0], R[..., 0, 0])[..., None]
    flat = R.reshape(-1, 3, 3)
    w = Rotation.from_matrix(flat).as_rotvec() if flat.shape[0] else np.zeros((0, 3))
    return w.reshape(R.shape[:-2] + (3,))


def rotation_exp(w: FloatArray, d: int) -> FloatArray:
    """The rotations of rotation vectors (:func:`rotation_log`'s inverse; any length)."""
    if d == 2:
        c, s = np.cos(w[..., 0]), np.sin(w[..., 0])
        return np.stack([np.stack([c, -s], -1), np.stack([s, c], -1)], -2)
    flat = w.reshape(-1, 3)
    r = Rotation.from_rotvec(flat).as_matrix() if flat.shape[0] else np.zeros((0, 3, 3))
    return r.reshape(w.shape[:-1] + (3, 3))


# --- quality ------------------------------------------------------------------------------
def edges_of(source: FloatArray, faces: IntArray) -> IntArray:
    """The undirected edges of the faces (every pair of corners, so tetrahedra give six);
    for a point set, each point and its nearest other point in the source."""
    if faces.shape[0] == 0:
        n = source.shape[0]
        if n < 2:
            return np.zeros((0, 2), dtype=np.int64)
        _, nn = cast(KnnQuery, cKDTree(source).query(source, k=2))
        e = np.stack([np.arange(n), nn[:, 1]], axis=1)
    else:
        k = faces.shape[1]
        e = np.concatenate([faces[:, [i, j]] for i in range(k) for j in range(i + 1, k)])
    e = np.sort(e, axis=1)
    _, first = np.unique(row_keys(e, source.shape[0]), return_index=True)
    return np.ascontiguousarray(e[first], dtype=np.int64)


def row_keys(rows: IntArray, n: int) -> IntArray:
    """One int64 per row of ``rows`` (values in ``[0, n)``), equal exactly for equal rows:
    the row read as a number in base ``n`` when that fits, else the ``np.unique`` index."""
    k = rows.shape[1]
    if k == 0 or float(n) ** k < 2.0 ** 62:
        key = np.zeros(rows.shape[0], dtype=np.int64)
        for c in range(k):
            key = key * n + rows[:, c]
        return key
    return np.unique(rows, axis=0, return_inverse=True)[1].ravel().astype(np.int64)


def edge_errors(frames: FloatArray, times: FloatArray, source: FloatArray,
                target: FloatArray, edges: IntArray) -> FloatArray:
    r"""Per frame, the largest relative deviation of an edge length from the lengths
    interpolated linearly: :math:`\max_e |\ell_e(t) - \bar\ell_e(t)| / \bar\ell_e(t)` with
    :math:`\bar\ell_e(t) = (1 - t)\,\ell_e(0) + t\,\ell_e(1)`. Zero for a path that bends
    a bar at constant curvature; a linear blend of the positions shortens it."""
    if edges.shape[0] == 0:
        return np.zeros(times.shape[0])

    def lengths(p: FloatArray) -> FloatArray:
        diff = p[..., edges[:, 1], :] - p[..., edges[:, 0], :]
        squared: FloatArray = np.einsum("...ij,...ij->...i", diff, diff)
        return np.sqrt(squared)

    l0, l1 = lengths(source), lengths(target)
    ref = (1.0 - times)[:, None] * l0 + times[:, None] * l1
    got = lengths(frames)
    err = np.abs(got - ref)
    rel = np.divide(err, ref, out=np.where(err > 0, np.inf, 0.0), where=ref > 0)
    rel[~np.isfinite(rel)] = np.finfo(np.float64).max  # an edge of zero length that grew
    worst: FloatArray = rel.max(axis=1)
    return worst


def pivot_of(source: FloatArray, pivot: str) -> FloatArray:
    """The point the linear part acts about: the source's centroid or the origin."""
    if pivot == "centroid":
        centroid: FloatArray = source.mean(axis=0)
        return centroid
    return np.zeros(source.shape[1])


def surface_triangles(vertices: FloatArray, faces: IntArray) -> IntArray | None:
    """Triangles to draw a frame with: the faces themselves for a triangle mesh, the
    boundary triangles of a tetrahedral mesh (oriented outwards, as ``igl.boundary_facets``
    gives them for positively oriented tetrahedra), ``None`` for a point set (what a glTF
    writer needs to animate ``frames``)."""
    if faces.shape[0] == 0:
        return None
    if faces.shape[1] == 3:
        return faces
    a, b, c, d = faces.T
    tris = np.concatenate([np.stack(s, axis=1) for s in
                           ((b, c, d), (a, d, c), (a, b, d), (a, c, b))])
    p = vertices[faces]
    negative = np.linalg.det(p[:, 1:] - p[:, :1]) < 0
    flip = np.tile(negative, 4)
    tris[flip] = tris[flip][:, ::-1]
    _, inv, counts = np.unique(row_keys(np.sort(tris, axis=1), vertices.shape[0]),
                               return_inverse=True, return_counts=True)
    return np.ascontiguousarray(tris[counts[inv.ravel()] == 1])


def check_pair(source: Any, target: Any = None, transform: Any = None, times: Any = None, *,
               need_faces: bool = False) -> tuple[Pair, FloatArray]:
    """Check what every interpolation takes: the start and end shapes (:func:`read_pair`)
    and ``times`` (:func:`read_times`), their frames within :data:`MAX_FRAME_VALUES`.
    Returns the pair and the times."""
    pair = read_pair(source, target, transform, need_faces=need_faces)
    t = read_times(times)
    check_frame_count(pair.n, pair.dim, t)
    return pair, t


def check_anchor(anchor: Any, n: int) -> int:
    """``anchor``, the vertex held on its straight path: a vertex index of the source's
    ``n``."""
    return as_int(anchor, name="anchor", minimum=0, maximum=n - 1,
                  reason="a vertex index of `source`")


def check_anchored(source: Any, target: Any = None, transform: Any = None, times: Any = None,
                   anchor: Any = 0) -> tuple[Pair, FloatArray]:
    """Check the inputs of the per-face interpolations (``arap``, ``poisson``): meshes as
    :func:`check_pair` takes them and an ``anchor`` among the source's vertices (:func:
    `check_anchor`). Returns the pair and the times."""
    pair, t = check_pair(source, target, transform, times, need_faces=True)
    check_anchor(anchor, pair.n)
    return pair, t
