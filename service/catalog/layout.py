"""Catalog entries of the layout family (positions for a mesh's vertices or a graph's nodes
with pins, or for points known by their pairwise distances)."""

from __future__ import annotations

from typing import Annotated, Any

import numpy as np
from pydantic import PlainSerializer, PlainValidator, ValidationInfo, WithJsonSchema

from algorithms.core.errors import DegenerateInputError, InvalidInputError
from algorithms.core.mesh import Handles, as_handles
from algorithms.core.mesh import edges as mesh_edges
from algorithms.core.params import Le
from algorithms.core.validation import MAX_DENSE_POINTS, as_int, as_points, as_weights
from algorithms.layout import (
    as_distance_matrix,
    distance_pairs_matrix,
    distance_source,
    laplacian,
    mds,
    mesh_or_graph,
    poisson,
    stress,
)
from service import scenes
from service.catalog.inputs import Points, max_points
from service.catalog.registry import Process, registry


# -- input types -----------------------------------------------------------------------------
def _validate_pins(value: Any, info: ValidationInfo) -> Handles:
    name = info.field_name or "pins"
    if not isinstance(value, (Handles, dict)):
        raise InvalidInputError(f"Expected `{name}` to be an object with keys 'indices' and "
                                f"'positions', got {type(value).__name__}.", field=name)
    return as_handles(value, None, name=name)  # against the mesh or graph: the entry's check


def _pins_json(h: Handles) -> dict[str, Any]:
    return {"indices": h.indices.tolist(), "positions": h.positions.tolist()}


PinsInput = Annotated[
    Handles,
    PlainValidator(_validate_pins),
    PlainSerializer(_pins_json),
    WithJsonSchema({
        "type": "object",
        "description": "Vertices (nodes) held at given positions: their indices and "
        "positions, in the layout's dimension.",
        "properties": {
            "indices": {"type": "array", "minItems": 1, "description": "Distinct vertex "
                        "(node) indices, 0-based.", "items": {"type": "integer", "minimum": 0}},
            "positions": {"type": "array", "minItems": 1, "description": "The position of "
                          "each, row i for indices[i]; k ≥ 2 coordinates.",
                          "items": {"type": "array", "items": {"type": "number"},
                                    "minItems": 2}},
        },
        "required": ["indices", "positions"],
        "additionalProperties": False,
    }),
]
"""Pinned vertices ``{"indices": [...], "positions": [[...], ...]}`` in any dimension
``k >= 2`` (the general ``Handles`` input has 2 or 3), validated into
:class:`algorithms.core.mesh.Handles` (structure only)."""


def _max_dense(info: ValidationInfo) -> int:
    limit = max_points(info)
    return MAX_DENSE_POINTS if limit is None else min(MAX_DENSE_POINTS, limit)


def _validate_distances(value: Any, info: ValidationInfo) -> np.ndarray:
    return as_distance_matrix(value, name=info.field_name or "distances",
                              max_points=_max_dense(info))


def _validate_pairs(value: Any, info: ValidationInfo) -> np.ndarray:
    name = info.field_name or "distance_pairs"
    return as_points(value, name=name, dim=3, max_points=_max_dense(info) ** 2)


def _nullable_list(a: np.ndarray) -> list[Any]:
    return [[None if np.isnan(x) else float(x) for x in row] for row in a]


def _tolist(a: np.ndarray) -> list[Any]:
    values: list[Any] = a.tolist()
    return values


DistanceMatrix = Annotated[
    np.ndarray,
    PlainValidator(_validate_distances),
    PlainSerializer(_nullable_list),
    WithJsonSchema({
        "type": "array",
        "description": "An (n, n) matrix of pairwise distances: non-negative, zero diagonal; "
        "null marks an unknown distance.",
        "items": {"type": "array", "items": {"type": ["number", "null"], "minimum": 0}},
        "minItems": 2,
    }),
]
"""An ``(n, n)`` distance matrix, ``null`` (NaN) for unknown entries."""

DistancePairs = Annotated[
    np.ndarray,
    PlainValidator(_validate_pairs),
    PlainSerializer(_tolist),
    WithJsonSchema({
        "type": "array",
        "description": "Known distances as rows (i, j, d): points i and j (0-based) are d "
        "apart.",
        "items": {"type": "array", "items": {"type": "number"}, "minItems": 3, "maxItems": 3},
        "minItems": 1,
    }),
]
"""Known distances as ``(m, 3)`` rows ``(i, j, d)``."""

_DISTANCE_INPUTS = {"distances": DistanceMatrix | None, "distance_pairs": DistancePairs | None}


# -- checks across inputs --------------------------------------------------------------------
def _nodes(p: Any) -> int:
    """The vertex (node) count of the one mesh or graph given (a graph: uniform weighting)."""
    if mesh_or_graph(p.mesh, p.graph, p.weighting) == "mesh":
        return int(p.mesh.n_vertices)
    return int(p.graph.n_nodes)


def _pinned(p: Any) -> None:
    """One of mesh and graph; pins within its vertices; a graph comes with pins."""
    n = _nodes(p)
    if p.pins is not None:
        as_handles(p.pins, n, name="pins")
    elif p.graph is not None:
        raise DegenerateInputError("Expected `pins` with a `graph` (a graph has no boundary "
                                   "to pin by default), got none.", field="pins")


def _edge_vectors(p: Any) -> None:
    """One of mesh and graph; one vector per edge; anchors and pins within its vertices and
    of the vectors' dimension; anchor weights only with anchors, one per anchor."""
    n = _nodes(p)
    if p.mesh is not None:
        e = mesh_edges(p.mesh.faces).shape[0]
        where = f"one row per edge of `mesh` ({e}, its unique edges i < j sorted)"
    else:
        e = p.graph.edges.shape[0]
        where = f"one row per edge of `graph` ({e})"
    if p.vectors.shape[0] != e:
        raise InvalidInputError(f"Expected `vectors` to hold {where}, got "
                                f"{p.vectors.shape[0]}.", field="vectors")
    k = p.vectors.shape[1]
    for name in ("anchors", "pins"):
        h = getattr(p, name)
        if h is not None:
            as_handles(h, n, name=name)
            if h.positions.shape[1] != k:
                raise InvalidInputError(
                    f"Expected `{name}.positions` to have the dimension of `vectors` ({k}), "
                    f"got shape ({h.positions.shape[0]}, {h.positions.shape[1]}).",
                    field=f"{name}.positions")
    if p.anchor_weights is not None:
        if p.anchors is None:
            raise InvalidInputError("Expected `anchor_weights` only together with `anchors`, "
                                    "got weights without anchors.", field="anchor_weights")
        as_weights(p.anchor_weights, p.anchors.indices.shape[0], name="anchor_weights")


def _distances(p: Any) -> None:
    """One of distances, distance_pairs and graph (n_points only with the pairs);
    n_components at most the number of points."""
    given = distance_source(p.distances, p.distance_pairs, p.n_points, p.graph)
    if given == "distance_pairs":
        n = distance_pairs_matrix(p.distance_pairs, p.n_points).shape[0]
    else:
        n = p.distances.shape[0] if given == "distances" else p.graph.n_nodes
    as_int(p.n_components, name="n_components", minimum=1, maximum=n,
           reason="the number of points")


def _distances_and_start(p: Any) -> None:
    """As for mds; a starting layout with n_components columns."""
    _distances(p)
    if p.initial_positions is not None:
        as_points(p.initial_positions, name="initial_positions", dim=p.n_components)


_SQUARE = {"vertices": [[0, 0], [1, 0], [1, 1], [0, 1], [0.5, 0.5]],
           "faces": [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]}
_PATH = {"nodes": 3, "edges": [[0, 1], [1, 2]]}
_TRIANGLE = [[0, 3, 4], [3, 0, 5], [4, 5, 0]]
_SQUARE_DISTANCES = [[0, 1, 1.4142135623730951, 1], [1, 0, 1, None],
                     [1.4142135623730951, 1, 0, 1], [1, None, 1, 0]]

registry.add(Process(
    id="layout.laplacian",
    geometry=scenes.layout,
    title="Laplacian (spring) layout; Tutte embedding",
    description="Places every free vertex at the weighted average of its neighbours, some "
    "vertices pinned: L₀₀x = −L₀₁c, one factored solve for all coordinates. A mesh's boundary "
    "pinned to the unit circle by default (Tutte's embedding: with uniform or tangent weights "
    "no face flips). Reports the spring energy and flipped faces.",
    function=laplacian,
    examples={"mesh": _SQUARE},
    inputs={"pins": PinsInput | None},
    check=_pinned,
    fast_path=True,
    keywords=("tutte embedding", "spring layout", "parameterization", "graph drawing",
              "harmonic map"),
))

registry.add(Process(
    id="layout.poisson",
    geometry=scenes.layout,
    title="Poisson layout (edge vectors to match, soft anchors)",
    description="Positions whose edge differences best match given vectors, pulled towards "
    "anchors and held at pins: min Σ wᵢⱼ‖(pᵢ − pⱼ) − vᵢⱼ‖² + Σ uᵢ‖pᵢ − zᵢ‖², solved as "
    "(DᵀWD + U)x = DᵀWv + Uz with one sparse factorization.",
    function=poisson,
    examples={"graph": _PATH, "vectors": [[-1.0, 0.0], [-1.0, 0.0]],
              "anchors": {"indices": [0], "positions": [[0.0, 0.0]]}},
    inputs={"vectors": Points, "anchors": PinsInput | None, "pins": PinsInput | None},
    check=_edge_vectors,
    fast_path=True,
    keywords=("poisson", "gradient domain", "least squares", "integration", "anchors"),
))

registry.add(Process(
    id="layout.mds",
    geometry=scenes.layout,
    title="Classical multidimensional scaling (with completion of missing distances)",
    description="Coordinates from the top eigenvectors of the double-centred squared "
    "distances −½JD⁽²⁾J. Missing distances are completed first: rank-(k+2) truncation of "
    "the squared distances (Drineas et al.'s one-shot estimate), refined by alternating "
    "projections. Reports the stress over the known pairs.",
    function=mds,
    examples={"distances": _TRIANGLE},
    inputs=_DISTANCE_INPUTS,
    limits={"max_iterations": Le(100_000)},
    check=_distances,
    keywords=("mds", "torgerson", "principal coordinates", "matrix completion",
              "localization"),
))

registry.add(Process(
    id="layout.stress",
    geometry=scenes.layout,
    title="Stress majorization (SMACOF)",
    description="The layout minimising the weighted stress Σ wᵢⱼ(‖xᵢ − xⱼ‖ − dᵢⱼ)² over the "
    "known pairs by Guttman transforms (never increasing), from classical MDS; distances "
    "from a matrix, a list of pairs, or a graph's shortest paths. Progress per iteration, "
    "cancellable; reports the stress history.",
    function=stress,
    examples={"distances": _SQUARE_DISTANCES},
    inputs=_DISTANCE_INPUTS,
    limits={"max_iterations": Le(100_000)},
    check=_distances_and_start,
    long=True,
    keywords=("smacof", "stress majorization", "metric mds", "graph drawing",
              "kamada-kawai"),
))
