r"""Laplacian (spring) layout of a mesh or graph with pinned vertices; the Tutte embedding
when a mesh's boundary is pinned to a convex polygon."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Literal, cast, get_args

import numpy as np
import scipy.sparse as sp

from algorithms.core.errors import DegenerateInputError
from algorithms.core.graphs import Graph, edge_graph
from algorithms.core.laplacian import laplacian as laplacian_of
from algorithms.core.laplacian import mesh_laplacian
from algorithms.core.linsolve import PinnedSystem
from algorithms.core.mesh import DEGENERATE_RTOL, Handles, Mesh, as_handles, boundary_loops
from algorithms.core.params import GraphLike, HandlesLike, MeshLike, validate_params
from algorithms.core.types import FloatArray, IntArray
from algorithms.layout._inputs import read_mesh_or_graph

__all__ = ["LaplacianLayoutResult", "laplacian", "check_laplacian", "Weighting", "Spacing",
           "WEIGHTINGS", "SPACINGS", "face_orientation"]

Weighting = Literal["uniform", "cotangent", "tangent"]
Spacing = Literal["arc_length", "uniform"]
#: The accepted values of ``weighting`` and ``boundary_spacing``.
WEIGHTINGS, SPACINGS = get_args(Weighting), get_args(Spacing)


@dataclass(frozen=True, eq=False)
class LaplacianLayoutResult:
    """Positions minimising the spring energy with some vertices pinned.

    Attributes
    ----------
    positions : (n, k) float array
        One row per vertex (node); pinned rows equal their pinned positions exactly.
    pinned : (p,) int array
        The pinned vertices: the given pins, or the boundary loop pinned to the circle in
        its order.
    energy : float
        The spring energy :math:`\\sum_{(i,j)} w_{ij} \\lVert p_i - p_j \\rVert^2` of the
        layout, each edge once.
    flipped_faces : int
        For a mesh laid out in 2-D: faces whose orientation is opposite to that of the
        layout as a whole (signed area of the other sign than the sum of all). 0 for a
        graph or a layout in other dimensions.
    degenerate_faces : int
        For a mesh laid out in 2-D: faces collapsed to (near) zero area, doubled area at
        most 1e-12 times the squared longest edge. 0 for a graph or other dimensions.
    """

    positions: FloatArray
    pinned: IntArray
    energy: float
    flipped_faces: int
    degenerate_faces: int


def check_laplacian(mesh: Any = None, graph: Any = None, weighting: str = "uniform",
                    pins: Any = None) -> tuple[Mesh | Graph, Handles | None]:
    """Check the inputs of :func:`laplacian`: one of ``mesh`` and ``graph``
    (:func:`~algorithms.layout.mesh_or_graph`), ``pins`` within its vertices, and pins with
    a graph (it has no boundary to pin by default). Returns the mesh or graph and the
    pins."""
    shape = read_mesh_or_graph(mesh, graph, weighting)
    n = shape.n_vertices if isinstance(shape, Mesh) else shape.n_nodes
    if pins is not None:
        return shape, as_handles(pins, n, name="pins")
    if isinstance(shape, Graph):
        raise DegenerateInputError("Expected `pins` with a `graph` (a graph has no boundary "
                                   "to pin by default), got none.", field="pins")
    return shape, None


@validate_params
def laplacian(
    mesh: MeshLike | None = None,
    *,
    graph: GraphLike | None = None,
    pins: HandlesLike | None = None,
    weighting: Weighting = "uniform",
    boundary_spacing: Spacing = "arc_length",
) -> LaplacianLayoutResult:
    r"""Laplacian (spring) layout; Tutte embedding.

    Places every free vertex at the weighted average of its neighbours, some vertices pinned: L₀₀x =
    −L₀₁c, one factored solve for all coordinates. A mesh's boundary pinned to the unit circle by
    default (Tutte's embedding: with uniform or tangent weights no face flips). Reports the spring
    energy and flipped faces.

    Minimises the spring energy with the pinned positions :math:`c` fixed,

    .. math::

        \min_{p} \sum_{(i,j) \in E} w_{ij} \lVert p_i - p_j \rVert^2
        \quad\text{s.t.}\quad p_P = c
        \qquad\Longleftrightarrow\qquad L_{00}\, x = -L_{01}\, c,

    one solve of the free block of :math:`L = D - W` per coordinate (one factorization):
    every free vertex lands at the weighted average of its neighbours.

    Without ``pins``, a mesh's longest boundary loop is pinned to the unit circle in its
    order (counter-clockwise for counter-clockwise faces), its vertices spaced by the
    lengths of the boundary edges (``boundary_spacing="arc_length"``, as
    ``igl.map_vertices_to_circle``) or evenly (``"uniform"``); this is Tutte's embedding,
    a parameterization of a disk-like surface. By Tutte's spring theorem (Floater's
    generalisation to positive weights), non-negative weights and a boundary on a convex
    polygon give a layout in which no face flips.

    Parameters
    ----------
    mesh : Mesh or mapping, optional
        A triangle mesh, ``{"vertices": (n, 2|3), "faces": (m, 3)}``, whose edges are the
        springs; without ``pins`` its longest boundary loop is pinned to the unit circle
        (Tutte's embedding). Exactly one of ``mesh`` and ``graph``.
    graph : Graph or mapping, optional
        Instead of ``mesh``: a graph ``{"nodes": n, "edges": (e, 2), "weights": (e,)?}``;
        its weights (default 1, non-negative) are the spring stiffnesses. A repeated edge
        counts once (its first weight). Needs ``pins``.
    pins : Handles or mapping, optional
        ``{"indices": (p,), "positions": (p, k)}``: the pinned vertices (nodes) and their
        positions, in any dimension ``k >= 2``, the dimension of the layout; at least one
        in every connected component. Default for a mesh: its boundary on the unit circle
        (then ``k = 2``).
    weighting : {"uniform", "cotangent", "tangent"}, default "uniform"
        Mesh edge weights: ``"uniform"`` 1 (Tutte's barycentric map), ``"cotangent"``
        :math:`(\cot\alpha + \cot\beta)/2` (the harmonic map; negative across edges
        opposite obtuse angles, so faces may flip) or ``"tangent"`` :math:`\sum
        \tan(\theta/2) / \lVert p_i - p_j \rVert` (Floater's mean value weights, never
        negative: no flips). A graph takes only ``"uniform"`` (its own weights).
    boundary_spacing : {"arc_length", "uniform"}, default "arc_length"
        Where the default boundary's vertices go on the circle: ``"arc_length"`` spaced by
        the lengths of the boundary edges, ``"uniform"`` evenly. Unused with ``pins``.

    Returns
    -------
    LaplacianLayoutResult
        ``positions``, ``pinned``, ``energy``, ``flipped_faces``, ``degenerate_faces``.

    Raises
    ------
    InvalidInputError
        Not exactly one of ``mesh`` and ``graph``; a malformed mesh, graph (edges out of
        range, self-loops, negative weights) or pins (indices out of range or repeated,
        positions not one finite row per index); ``weighting`` other than ``"uniform"``
        with a graph; an unknown option.
    DegenerateInputError
        Zero-area faces; a graph without ``pins``; a closed mesh without ``pins`` (no
        boundary to pin); a connected component without a pin (field ``pins``, or
        ``mesh`` when the boundary was pinned by default); a free block that is singular.

    Notes
    -----
    **Tutte's guarantee needs non-negative weights.** With a pin in every connected
    component the free block :math:`L_{00}` is non-singular, so the layout is unique.
    With the pins on a convex polygon and every weight non-negative, it is an embedding:
    no vertex outside the polygon, no crossing edges, no flipped face (Tutte; Floater for
    positive weights). The cotangent weights break the condition: an edge whose opposite
    angles sum to more than :math:`\pi` (a mesh that is not Delaunay, with obtuse
    triangles) gets a negative weight, and faces may flip. The tangent weights are sums
    of :math:`\tan(\theta/2) > 0` over angles :math:`\theta \in (0, \pi)`, never negative,
    so they keep the guarantee on any mesh.
    A boundary pinned to a *non-convex* polygon (given ``pins``) may flip faces: the count
    is reported, not raised.

    Only the longest boundary loop is pinned by default; a mesh with holes keeps its
    holes free (their faces may then overlap: give ``pins`` for every loop).

    References
    ----------
    .. [1] W. T. Tutte, "How to draw a graph", Proc. London Math. Soc. 13 (1963).
    .. [2] M. S. Floater, "Parametrization and smooth approximation of surface
       triangulations", CAGD 14 (1997); "Mean value coordinates", CAGD 20 (2003).

    Examples
    --------
    A square with a centre vertex: the boundary goes to the circle, the centre to its
    middle.

    >>> from algorithms.layout import laplacian
    >>> v = [[0, 0], [1, 0], [1, 1], [0, 1], [0.5, 0.5]]
    >>> f = [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]
    >>> res = laplacian((v, f))
    >>> (res.positions[4].round(12) + 0.0).tolist(), res.flipped_faces
    ([0.0, 0.0], 0)
    """
    shape, h = check_laplacian(mesh, graph, weighting, pins)
    faces: IntArray | None = None
    if isinstance(shape, Mesh):
        faces = shape.faces
        lap = mesh_laplacian(shape.vertices, shape.faces, kind=weighting)
    else:
        lap = graph_laplacian(shape)
    if h is not None:
        pinned, values, pin_name = h.indices, h.positions, "pins"
    else:  # a mesh (check_laplacian refuses a graph without pins)
        pinned, values = circle_boundary(cast(Mesh, shape), boundary_spacing)
        pin_name = "mesh"
    system = PinnedSystem(lap, pinned, name=pin_name)
    x = system.solve(values)
    energy = float(np.einsum("ij,ij->", x, lap @ x))
    flipped = degenerate = 0
    if faces is not None and x.shape[1] == 2:
        flipped, degenerate = face_orientation(x, faces)
    return LaplacianLayoutResult(
        positions=x,
        pinned=pinned,
        energy=max(energy, 0.0),
        flipped_faces=flipped,
        degenerate_faces=degenerate,
    )


def graph_laplacian(g: Graph) -> sp.csr_array:
    """``L = D - W`` of a checked graph (edges of zero weight are no edges)."""
    if g.weights is None:
        w = edge_graph(g.n_nodes, g.edges)
    else:
        w = edge_graph(g.n_nodes, g.edges, g.weights)
        w.eliminate_zeros()
    return laplacian_of(w)


def circle_boundary(mesh: Mesh, spacing: str) -> tuple[IntArray, FloatArray]:
    """The longest boundary loop and its positions on the unit circle, counter-clockwise
    in the loop's order."""
    loops = boundary_loops(mesh.faces)
    if not loops:
        raise DegenerateInputError(
            "Expected `mesh` to have a boundary to pin to the circle, got a closed mesh; "
            "give `pins`.", field="mesh")
    loop = loops[0]
    _, first = np.unique(loop, return_index=True)   # a vertex met twice keeps its first visit
    loop = loop[np.sort(first)]
    if loop.shape[0] < 3:
        raise DegenerateInputError(
            f"Expected the boundary of `mesh` to have at least 3 vertices, got "
            f"{loop.shape[0]}; give `pins`.", field="mesh")
    if spacing == "uniform":
        t = np.arange(loop.shape[0]) / loop.shape[0]
    else:
        p = mesh.vertices[loop]
        seg = np.linalg.norm(np.roll(p, -1, axis=0) - p, axis=1)
        cum = np.concatenate([[0.0], np.cumsum(seg)[:-1]])
        t = cum / seg.sum()
    angle = 2.0 * math.pi * t
    return loop.astype(np.int64), np.stack([np.cos(angle), np.sin(angle)], axis=1)


def face_orientation(x: FloatArray, faces: IntArray) -> tuple[int, int]:
    """Counts of flipped and of degenerate faces of a planar layout ``x`` (n, 2).

    A face is degenerate when its doubled area is at most ``DEGENERATE_RTOL`` times its
    squared longest edge (or all its corners coincide); flipped when, not degenerate, its
    signed area has the sign opposite to the sum of all signed areas.
    """
    f0, f1, f2 = faces[:, 0], faces[:, 1], faces[:, 2]
    u, w = x[:, 0], x[:, 1]          # one coordinate at a time: 1-D gathers
    u0, w0 = u[f0], w[f0]
    ax, ay = u[f1] - u0, w[f1] - w0
    bx, by = u[f2] - u0, w[f2] - w0
    cx, cy = bx - ax, by - ay
    doubled = ax * by - ay * bx
    longest = np.maximum(np.maximum(ax * ax + ay * ay, bx * bx + by * by), cx * cx + cy * cy)
    degenerate = np.abs(doubled) <= DEGENERATE_RTOL * longest
    sign = 1.0 if doubled.sum() >= 0 else -1.0
    flipped = (doubled * sign < 0) & ~degenerate
    return int(np.count_nonzero(flipped)), int(np.count_nonzero(degenerate))
