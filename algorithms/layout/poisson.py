r"""Poisson layout: positions whose edge vectors best match given ones, with soft anchors
and hard pins."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from algorithms.core.errors import InvalidInputError
from algorithms.core.graphs import Graph
from algorithms.core.laplacian import cotangent_weights, tangent_weights
from algorithms.core.linsolve import PinnedSystem
from algorithms.core.mesh import Handles, Mesh, as_handles
from algorithms.core.mesh import edges as mesh_edges
from algorithms.core.params import (
    ArrayInput,
    GraphLike,
    HandlesLike,
    MeshLike,
    WeightsLike,
    validate_params,
)
from algorithms.core.types import FloatArray, IntArray
from algorithms.core.validation import as_points, as_weights
from algorithms.layout._inputs import read_mesh_or_graph
from algorithms.layout.laplacian import Weighting

__all__ = ["PoissonLayoutResult", "poisson", "check_poisson"]


@dataclass(frozen=True, eq=False)
class PoissonLayoutResult:
    """Positions whose edge vectors best match the given ones.

    Attributes
    ----------
    positions : (n, k) float array
        One row per vertex (node); pinned rows equal their pins exactly.
    energy : float
        The minimised objective :math:`\\sum w_{ij} \\lVert (p_i - p_j) - v_{ij}
        \\rVert^2 + \\sum u_i \\lVert p_i - z_i \\rVert^2`.
    edge_rmse : float
        Root mean square over the edges of :math:`\\lVert (p_i - p_j) - v_{ij} \\rVert`
        (unweighted): 0 when the vectors are consistent (the differences of some
        positions) and nothing pulls against them.
    anchor_rmse : float
        Root mean square over the anchors of :math:`\\lVert p_i - z_i \\rVert`; 0 without
        anchors.
    free_components : int
        Connected components with neither an anchor of positive weight nor a pin: their
        position is undetermined and each is centred at the origin.
    """

    positions: FloatArray
    energy: float
    edge_rmse: float
    anchor_rmse: float
    free_components: int


def check_poisson(vectors: Any, mesh: Any = None, graph: Any = None,
                  weighting: str = "cotangent", anchors: Any = None,
                  anchor_weights: Any = None, pins: Any = None
                  ) -> tuple[Mesh | Graph, IntArray, FloatArray, Handles | None,
                             FloatArray | None, Handles | None]:
    """Check the inputs of :func:`poisson`: one of ``mesh`` and ``graph``, one vector per
    edge, anchors and pins within its vertices and of the vectors' dimension, anchor
    weights only with anchors, one per anchor. Returns the mesh or graph, its edges, the
    vectors, the anchors, their weights and the pins."""
    shape = read_mesh_or_graph(mesh, graph, weighting)
    if isinstance(shape, Mesh):
        n, e = shape.n_vertices, mesh_edges(shape.faces)
        where = f"one row per edge of `mesh` ({e.shape[0]}, its unique edges i < j sorted)"
    else:
        n, e = shape.n_nodes, shape.edges
        where = f"one row per edge of `graph` ({e.shape[0]})"
    v = as_points(vectors, name="vectors", min_dim=2, min_points=0)
    if v.shape[0] != e.shape[0]:
        raise InvalidInputError(f"Expected `vectors` to hold {where}, got {v.shape[0]}.",
                                field="vectors")
    held = []
    for name, given in (("anchors", anchors), ("pins", pins)):
        h = None if given is None else as_handles(given, n, name=name)
        if h is not None:
            _same_dim(h.positions, v.shape[1], f"{name}.positions")
        held.append(h)
    a, p = held
    u = None
    if anchor_weights is not None:
        if a is None:
            raise InvalidInputError("Expected `anchor_weights` only together with "
                                    "`anchors`, got weights without anchors.",
                                    field="anchor_weights")
        u = as_weights(anchor_weights, a.indices.shape[0], name="anchor_weights")
    return shape, e, v, a, u, p


@validate_params
def poisson(
    mesh: MeshLike | None = None,
    *,
    graph: GraphLike | None = None,
    vectors: ArrayInput,
    anchors: HandlesLike | None = None,
    anchor_weights: WeightsLike | None = None,
    pins: HandlesLike | None = None,
    weighting: Weighting = "uniform",
) -> PoissonLayoutResult:
    r"""Poisson layout (edge vectors to match, soft anchors).

    Positions whose edge differences best match given vectors, pulled towards anchors and held at
    pins: min Σ wᵢⱼ‖(pᵢ − pⱼ) − vᵢⱼ‖² + Σ uᵢ‖pᵢ − zᵢ‖², solved as (DᵀWD + U)x = DᵀWv + Uz with one
    sparse factorization.

    .. math::

        \min_x \sum_{(i,j)} w_{ij} \lVert (p_i - p_j) - v_{ij} \rVert^2
            + \sum_i u_i \lVert p_i - z_i \rVert^2
        \;=\; \min_x (Dx - v)^\mathsf{T} W (Dx - v) + (x - z)^\mathsf{T} U (x - z)

    with :math:`D` the ``e×n`` difference matrix (row ``(i, j)``: +1 at ``i``, −1 at
    ``j``), so that

    .. math:: (D^\mathsf{T} W D + U)\, x = D^\mathsf{T} W v + U z ,

    solved once for all ``k`` coordinates (one sparse Cholesky factorization). With
    ``pins`` the pinned rows are fixed and the system is split as in
    :func:`~algorithms.layout.laplacian`.

    Parameters
    ----------
    mesh : Mesh or mapping, optional
        A triangle mesh ``{"vertices": (n, 2|3), "faces": (m, 3)}``; its edges, in the
        order of ``vectors``, are its unique edges ``(i, j)``, ``i < j``, sorted
        lexicographically. Exactly one of ``mesh`` and ``graph``.
    graph : Graph or mapping, optional
        Instead of ``mesh``: a graph ``{"nodes": n, "edges": (e, 2), "weights": (e,)?}``;
        edges in their given order and orientation, weights ``w`` (default 1,
        non-negative).
    vectors : (e, k) array_like
        The target of :math:`p_i - p_j` for each edge row ``(i, j)``, in the order of the
        edges; ``k >= 2`` is the dimension of the layout.
    anchors : Handles or mapping, optional
        ``{"indices": (a,), "positions": (a, k)}``: soft targets :math:`z_i`, the term
        :math:`\sum_i u_i \lVert p_i - z_i \rVert^2`. A connected component with neither
        anchors nor pins is centred at the origin.
    anchor_weights : (a,) array_like, optional
        The weight :math:`u_i \ge 0` of each anchor, in the order of ``anchors.indices``;
        all 1 when omitted. Only together with ``anchors``.
    pins : Handles or mapping, optional
        ``{"indices": (p,), "positions": (p, k)}``: vertices (nodes) held at these
        positions exactly.
    weighting : {"uniform", "cotangent", "tangent"}, default "uniform"
        Mesh edge weights ``w``: ``"uniform"`` 1, ``"cotangent"``
        :math:`(\cot\alpha + \cot\beta)/2` (negative across edges opposite obtuse
        angles) or ``"tangent"`` (Floater's mean value weights, never negative). A graph
        takes only ``"uniform"`` (its own weights).

    Returns
    -------
    PoissonLayoutResult
        ``positions``, ``energy``, ``edge_rmse``, ``anchor_rmse``, ``free_components``.

    Raises
    ------
    InvalidInputError
        Not exactly one of ``mesh`` and ``graph``; a malformed mesh or graph; ``vectors``
        not one finite row per edge; anchors or pins out of range, repeated, NaN, or of
        another dimension than ``vectors``; ``anchor_weights`` not one non-negative number
        per anchor; ``weighting`` other than ``"uniform"`` with a graph.
    DegenerateInputError
        Zero-area faces; a singular system (cotangent weights that are not positive
        semidefinite on the free vertices).

    Notes
    -----
    **Components without anchors.** Where no anchor of positive weight and no pin holds
    a connected component, the objective does not change when the component is
    translated, and the normal equations are singular there. Such a component is solved
    with its lowest-numbered vertex held at the origin and then centred at the origin
    (of all minimisers, the one of least norm), and counted in ``free_components``.

    References
    ----------
    .. [1] P. Pérez, M. Gangnet, A. Blake, "Poisson image editing", ACM TOG 22(3) (2003).

    Examples
    --------
    A path 0 - 1 - 2 asked for steps of +1 along x (``p_j - p_i`` = 1, so ``v = -1``),
    node 0 anchored at the origin:

    >>> from algorithms.layout import poisson
    >>> g = {"nodes": 3, "edges": [[0, 1], [1, 2]]}
    >>> res = poisson(graph=g, vectors=[[-1.0, 0.0], [-1.0, 0.0]],
    ...               anchors={"indices": [0], "positions": [[0.0, 0.0]]})
    >>> res.positions.round(12).tolist()
    [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]
    """
    shape, e, v, a, u, h = check_poisson(vectors, mesh, graph, weighting, anchors,
                                         anchor_weights, pins)
    if isinstance(shape, Mesh):
        n = shape.n_vertices
        if weighting == "uniform":
            w = np.ones(e.shape[0])
        else:
            wm = (cotangent_weights if weighting == "cotangent" else tangent_weights)(
                shape.vertices, shape.faces)
            w = np.asarray(wm[e[:, 0], e[:, 1]]).ravel()
    else:
        n = shape.n_nodes
        w = np.ones(e.shape[0]) if shape.weights is None else shape.weights
    k = v.shape[1]

    u_full = np.zeros(n)
    z_full = np.zeros((n, k))
    anchor_idx = np.zeros(0, dtype=np.int64)
    if a is not None:
        anchor_idx, anchor_pos = a.indices, a.positions
        u_full[anchor_idx] = np.ones(a.indices.shape[0]) if u is None else u
        z_full[anchor_idx] = anchor_pos
    pinned = np.zeros(0, dtype=np.int64)
    pin_pos = np.zeros((0, k))
    if h is not None:
        pinned, pin_pos = h.indices, h.positions

    diff = sp.csr_array(
        (np.concatenate([np.ones(e.shape[0]), -np.ones(e.shape[0])]),
         (np.concatenate([np.arange(e.shape[0])] * 2), np.concatenate([e[:, 0], e[:, 1]]))),
        shape=(e.shape[0], n))
    dtw = diff.T.multiply(w).tocsr() if e.shape[0] else sp.csr_array((n, 0))
    system = (dtw @ diff + sp.diags_array(u_full)).tocsr()
    rhs = dtw @ v + u_full[:, None] * z_full

    # Components anchored by nothing: hold their smallest vertex at 0, centre them after.
    active = w != 0
    adj = sp.csr_array((np.ones(int(active.sum())), (e[active, 0], e[active, 1])), shape=(n, n))
    count, labels = connected_components(adj, directed=False)
    held = np.zeros(count, dtype=bool)
    held[labels[anchor_idx[u_full[anchor_idx] > 0]]] = True
    held[labels[pinned]] = True
    loose = np.flatnonzero(~held)
    first = np.full(count, n, dtype=np.int64)
    np.minimum.at(first, labels, np.arange(n))
    extra = first[loose]
    all_pins = np.concatenate([pinned, extra])
    values = np.concatenate([pin_pos, np.zeros((extra.shape[0], k))])
    x = PinnedSystem(system, all_pins, name="pins", check_components=False).solve(values, rhs)
    if loose.size:
        is_loose = np.zeros(count, dtype=bool)
        is_loose[loose] = True
        sel = is_loose[labels]
        sums = np.zeros((count, k))
        np.add.at(sums, labels[sel], x[sel])
        x[sel] -= (sums / np.bincount(labels, minlength=count)[:, None])[labels[sel]]

    residual = diff @ x - v
    anchor_res = x[anchor_idx] - z_full[anchor_idx]
    energy = float(np.einsum("i,ij,ij->", w, residual, residual)
                   + np.einsum("i,ij,ij->", u_full[anchor_idx], anchor_res, anchor_res))
    edge_rmse = math.sqrt(float(np.einsum("ij,ij->", residual, residual)) / e.shape[0]) \
        if e.shape[0] else 0.0
    anchor_rmse = math.sqrt(float(np.einsum("ij,ij->", anchor_res, anchor_res))
                            / anchor_idx.shape[0]) if anchor_idx.shape[0] else 0.0
    return PoissonLayoutResult(
        positions=x,
        energy=energy,
        edge_rmse=edge_rmse,
        anchor_rmse=anchor_rmse,
        free_components=int(loose.shape[0]),
    )


def _same_dim(positions: FloatArray, k: int, name: str) -> None:
    if positions.shape[1] != k:
        raise InvalidInputError(
            f"Expected `{name}` to have the dimension of `vectors` ({k}), got shape "
            f"({positions.shape[0]}, {positions.shape[1]}).", field=name)
