"""Reading a parameterization's input mesh and checking that it is a topological disk."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Literal, get_args

import numpy as np
import scipy.sparse as sp

from algorithms.core.errors import DegenerateInputError, InvalidInputError
from algorithms.core.laplacian import mesh_laplacian
from algorithms.core.linsolve import PinnedSystem
from algorithms.core.mesh import Mesh, face_angles, loops_of_edges, pattern_components, read_mesh
from algorithms.core.types import FloatArray, IntArray

__all__ = ["NotADiskError", "Disk", "read_disk", "check_disk", "convex_boundary", "Boundary",
           "BOUNDARIES", "pinned_map"]


class NotADiskError(InvalidInputError):
    """The mesh is well formed but not a topological disk: closed, several boundary loops
    (holes), several connected components, a non-manifold edge or vertex, inconsistently
    oriented faces, or vertices no face uses. A parameterization maps a disk to the plane
    and needs exactly one boundary loop."""


@dataclass(frozen=True, eq=False)
class Disk:
    """A checked disk-like mesh and its boundary loop.

    Attributes
    ----------
    mesh : Mesh
        The mesh, ``(n, 2)`` or ``(n, 3)`` vertices.
    loop : (b,) int array
        The boundary loop in the order of the faces (counter-clockwise around a
        counter-clockwise disk), starting at its smallest vertex index.
    """

    mesh: Mesh
    loop: IntArray


def _fail(message: str, name: str) -> NotADiskError:
    return NotADiskError(f"Expected `{name}` to be a topological disk (one connected, "
                         f"manifold, consistently oriented surface with exactly one boundary "
                         f"loop), got {message}.", field=name)


def check_disk(mesh: Mesh, *, name: str = "mesh") -> IntArray:
    """Check that ``mesh`` is a topological disk and return its boundary loop.

    Checks, in order: every vertex is in a face; no edge is shared by more than two faces
    and no two faces traverse an edge in the same direction (orientable, consistently
    oriented); one connected component; a boundary; no boundary vertex where two fans touch
    (a bow tie); exactly one boundary loop; Euler characteristic ``V - E + F = 1``.

    Returns
    -------
    (b,) int array
        The boundary loop (see :class:`Disk`).

    Raises
    ------
    NotADiskError
        (an :class:`~algorithms.core.errors.InvalidInputError`, field ``name``) naming the
        first failed check with a vertex, edge or count that shows it.
    """
    f = mesh.faces
    n = mesh.n_vertices
    used = np.zeros(n, dtype=bool)
    used[f.ravel()] = True
    if not used.all():
        k = int(np.argmin(used))
        more = int(np.count_nonzero(~used))
        raise _fail(f"vertex {k} in no face" + (f" ({more} such vertices)" if more > 1 else ""),
                    name)
    a = f.ravel()
    b = np.roll(f, -1, axis=1).ravel()           # a[k] -> b[k]: the half-edges, by face
    # each half-edge as twice its undirected edge's key, plus 1 when it runs from the higher
    # vertex to the lower: one sort of integers groups the half-edges of each edge, in order
    # of direction (cheaper than np.unique's argsort, inverse and counts: 2 ms, not 8, for
    # 300,000 half-edges)
    half = np.minimum(a, b)
    half *= n
    half += np.maximum(a, b)
    half <<= 1
    half += a > b
    half.sort()
    key = half >> 1
    start = np.flatnonzero(np.concatenate([[True], key[1:] != key[:-1]]))
    ucount = np.diff(np.append(start, half.shape[0]))
    undirected = key[start]
    if (ucount > 2).any():
        k = int(np.argmax(ucount > 2))
        raise _fail(f"the non-manifold edge ({undirected[k] // n}, {undirected[k] % n}) shared "
                    f"by {int(ucount.max())} faces", name)
    # an edge of two faces is traversed once each way: no two half-edges are equal
    same = half[1:] == half[:-1]
    if same.any():
        h = int(half[np.argmax(same)])
        i, j = divmod(h >> 1, n)
        if h & 1:
            i, j = j, i
        raise _fail(f"edge ({i}, {j}) traversed in the same direction by two "
                    f"faces (inconsistent orientation or a non-manifold edge)", name)
    # the edges sorted by their lower vertex are the upper triangle of the graph, in CSR
    lo, hi = np.divmod(undirected, n)
    indptr = np.concatenate([[0], np.cumsum(np.bincount(lo, minlength=n))])
    count, _ = pattern_components(sp.csr_array((np.ones(hi.shape[0], dtype=np.int8), hi,
                                                indptr), shape=(n, n)))
    if count > 1:
        raise _fail(f"{count} connected components", name)
    once = ucount == 1                           # edges of one half-edge: the boundary
    if not once.any():
        raise _fail("a closed mesh (no boundary); cut it open first", name)
    lo, hi = lo[once], hi[once]
    up = (half[start[once]] & 1) == 0            # runs from the lower vertex to the higher
    bnd_edges = np.stack([np.where(up, lo, hi), np.where(up, hi, lo)], axis=1)
    out_deg = np.bincount(bnd_edges[:, 0], minlength=n)
    if (out_deg > 1).any():
        k = int(np.argmax(out_deg > 1))
        raise _fail(f"the non-manifold vertex {k} where {int(out_deg[k])} fans of faces "
                    f"touch", name)
    loops = loops_of_edges(bnd_edges)
    if len(loops) != 1:
        raise _fail(f"{len(loops)} boundary loops (a surface with "
                    f"{len(loops) - 1} hole{'s' if len(loops) > 2 else ''}); fill or cut the "
                    f"holes first", name)
    chi = n - undirected.shape[0] + f.shape[0]
    if chi != 1:
        raise _fail(f"Euler characteristic V - E + F = {chi} (1 for a disk; a handle lowers it "
                    f"by 2)", name)
    return loops[0]


def read_disk(mesh: Any, *, name: str = "mesh") -> Disk:
    """A :class:`Disk` from a ``Mesh``, a ``(vertices, faces)`` pair or a mapping with those
    keys, checked by :func:`~algorithms.core.mesh.as_mesh` and :func:`check_disk`."""
    m = read_mesh(mesh, name=name)
    return Disk(m, check_disk(m, name=name))


def pinned_map(disk: Disk, values: FloatArray,
               weighting: Literal["uniform", "cotangent", "tangent"],
               laplacian: sp.csr_array | None = None) -> tuple[FloatArray, float]:
    r"""The spring layout of a checked disk with its boundary loop pinned to ``values``
    (``(b, 2)``, in the loop's order), and its energy :math:`u^\mathsf{T} L u`.

    What :func:`algorithms.layout.laplacian` computes with these pins, without checking
    the mesh and the pins again (:func:`read_disk` did) or counting flips (the caller's
    quality figures do). ``laplacian``: the mesh's Laplacian of that ``weighting``, when
    the caller has it already.
    """
    m = disk.mesh
    lap = mesh_laplacian(m.vertices, m.faces, kind=weighting) if laplacian is None \
        else laplacian
    # one connected component (check_disk) and its boundary pinned: L_ff is non-singular
    uv = PinnedSystem(lap, disk.loop, name="mesh", check_components=False).solve(values)
    return uv, max(float(np.einsum("ij,ij->", uv, lap @ uv)), 0.0)


Boundary = Literal["circle", "square"]
#: The accepted values of ``boundary``.
BOUNDARIES = get_args(Boundary)


def convex_boundary(disk: Disk, shape: str) -> FloatArray:
    """Positions for the boundary loop on the unit circle or the square ``[-1, 1]²``,
    counter-clockwise in the loop's order, spaced by the lengths of the boundary edges.

    Circle: vertex ``loop[k]`` at angle ``2π s_k / S`` (``s_k`` the boundary length from
    ``loop[0]``, ``S`` the whole), as ``igl.map_vertices_to_circle``. Square: the four
    corners go to the four boundary vertices with the smallest angle sums (the surface's
    own corners), at least an eighth of the boundary length apart, the first in loop order
    at ``(-1, -1)``; each side's vertices are spaced by length between its corners (as
    CGAL's ``Square_border_arc_length_parameterizer_3``), so every corner is a vertex and
    the polygon is the square itself.
    """
    loop = disk.loop
    p = disk.mesh.vertices[loop]
    seg = np.linalg.norm(np.roll(p, -1, axis=0) - p, axis=1)
    cum = np.concatenate([[0.0], np.cumsum(seg)])               # (b + 1,), closes the loop
    total = cum[-1]
    if shape == "circle":
        angle = 2.0 * np.pi * cum[:-1] / total
        return np.stack([np.cos(angle), np.sin(angle)], axis=1)
    b = loop.shape[0]
    if b < 4:
        raise DegenerateInputError(
            f"Expected `mesh` to have at least 4 boundary vertices for boundary='square' (one "
            f"per corner), got {b}.", field="boundary")
    corners = _square_corners(disk, cum)
    start = corners[0]
    rolled = np.roll(np.arange(b), -start)             # loop positions from the first corner
    rc = np.append(corners - start, b)
    rcum = np.concatenate([cum[start:-1] - cum[start], cum[:start + 1] + total - cum[start]])
    square = np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0], [-1.0, -1.0]])
    out = np.empty((b, 2))
    for side in range(4):
        lo, hi = rc[side], rc[side + 1]
        t = (rcum[lo:hi] - rcum[lo]) / (rcum[hi] - rcum[lo])
        out[rolled[lo:hi]] = square[side] + t[:, None] * (square[side + 1] - square[side])
    return out


def _square_corners(disk: Disk, cum: FloatArray) -> IntArray:
    """Four loop positions for the square's corners, increasing: the boundary vertices with
    the smallest angle sums (the surface's own corners), each at least an eighth of the
    boundary length from the others; arc-length quarters where too few qualify."""
    loop = disk.loop
    b, total = loop.shape[0], cum[-1]
    sums = np.bincount(disk.mesh.faces.ravel(),
                       weights=face_angles(disk.mesh.vertices, disk.mesh.faces).ravel(),
                       minlength=disk.mesh.n_vertices)[loop]
    chosen: list[int] = []
    for k in np.argsort(sums, kind="stable").tolist():
        gaps = [abs(cum[k] - cum[c]) for c in chosen]
        if all(min(g, total - g) >= total / 8 for g in gaps):
            chosen.append(k)
            if len(chosen) == 4:
                break
    if len(chosen) < 4:
        chosen = [int(np.argmin(np.abs(cum[:-1] - q * total))) for q in (0, .25, .5, .75)]
    out = np.unique(chosen)
    if out.shape[0] < 4:                                # tiny loops: spread evenly
        out = np.arange(4) * b // 4
    return out.astype(np.int64)
