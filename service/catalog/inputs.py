"""Input types of the catalog's parameter models.

Geometry inputs arrive as JSON arrays and leave validation as numpy arrays, checked by
:mod:`algorithms.core.validation` (the only place input checks live), with a JSON Schema for
the process description. Limits that depend on the service's settings (most points per
input) come through pydantic's validation context: ``{"max_points": N}``.

Meshes arrive as ``{"vertices": [[x, y, z], ...], "faces": [[i, j, k], ...]}`` and leave as
:class:`algorithms.core.mesh.Mesh` (checked by :func:`~algorithms.core.mesh.as_mesh`: errors
name ``mesh.vertices`` / ``mesh.faces`` after the field); handles as ``{"indices": [...],
"positions": [[...], ...]}`` and leave as :class:`algorithms.core.mesh.Handles`, checked for
their own structure here and against the mesh by the process's model validator
(:func:`~algorithms.core.mesh.as_handles` with the mesh).
"""

from __future__ import annotations

from typing import Annotated, Any

import numpy as np
from pydantic import PlainSerializer, PlainValidator, ValidationInfo, WithJsonSchema

from algorithms.core.errors import InvalidInputError
from algorithms.core.graphs import Graph, as_graph
from algorithms.core.mesh import Handles as HandlesData
from algorithms.core.mesh import Mesh, as_handles, as_mesh
from algorithms.core.params import Kind
from algorithms.core.validation import as_points

__all__ = ["max_points", "Points", "Weights", "Labels", "points_schema", "MeshInput", "Handles",
           "HandlesInput", "GraphInput", "mesh_schema", "handles_type", "tolist", "KIND_TYPES"]


def points_schema(description: str, *, dim: int | None = None,
                  min_points: int = 1) -> dict[str, Any]:
    row: dict[str, Any] = {"type": "array", "items": {"type": "number"}, "minItems": dim or 1}
    if dim is not None:
        row["maxItems"] = dim
    return {"type": "array", "items": row, "minItems": min_points, "description": description}


def max_points(info: ValidationInfo) -> int | None:
    """The service's limit of points per input, passed in the validation context."""
    limit = (info.context or {}).get("max_points")
    return None if limit is None else int(limit)


def _validate_points(value: Any, info: ValidationInfo) -> np.ndarray:
    return as_points(value, name=info.field_name or "points", max_points=max_points(info))


def _validate_weights(value: Any, info: ValidationInfo) -> np.ndarray:
    name = info.field_name or "weights"
    try:
        arr = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise InvalidInputError(
            f"Expected `{name}` to be a flat list of numbers, got {type(value).__name__}.",
            field=name) from None
    if arr.ndim != 1:
        raise InvalidInputError(
            f"Expected `{name}` to be a flat list of numbers, got an array of shape "
            f"{arr.shape}.", field=name)
    return arr  # length, sign and finiteness against the paired points: as_weights


def tolist(a: np.ndarray) -> list[Any]:
    values: list[Any] = a.tolist()
    return values


Points = Annotated[
    np.ndarray,
    PlainValidator(_validate_points),
    PlainSerializer(tolist),
    WithJsonSchema(points_schema("An (n, d) array of point coordinates, one row per point.")),
]
"""An (n, d) float array of points, given as a JSON array of rows."""

Weights = Annotated[
    np.ndarray,
    PlainValidator(_validate_weights),
    PlainSerializer(tolist),
    WithJsonSchema({"type": "array", "items": {"type": "number", "minimum": 0},
                    "description": "One non-negative weight per point pair."}),
]
"""A flat float array of per-pair weights."""


_TRIANGLES = ("One row of 3 vertex indices (0-based) per triangle, counter-clockwise seen "
              "from the front.")


def mesh_schema(description: str, *, faces: str = _TRIANGLES,
                corners: tuple[int, int] = (3, 3)) -> dict[str, Any]:
    """A mesh's JSON Schema; ``faces`` describes its faces, of ``corners`` vertices each."""
    return {
        "type": "object",
        "description": description,
        "properties": {
            "vertices": {"type": "array", "minItems": 3, "description": "One row of 2 or 3 "
                         "coordinates per vertex.",
                         "items": {"type": "array", "items": {"type": "number"},
                                   "minItems": 2, "maxItems": 3}},
            "faces": {"type": "array", "minItems": 1, "description": faces,
                      "items": {"type": "array", "items": {"type": "integer", "minimum": 0},
                                "minItems": corners[0], "maxItems": corners[1]}},
        },
        "required": ["vertices", "faces"],
        "additionalProperties": False,
    }


def _object_members(value: Any, name: str, keys: tuple[str, str]) -> tuple[Any, Any]:
    expected = f"an object with keys {keys[0]!r} and {keys[1]!r}"
    if not isinstance(value, dict):
        raise InvalidInputError(f"Expected `{name}` to be {expected}, got "
                                f"{type(value).__name__}.", field=name)
    missing = [k for k in keys if k not in value]
    if missing:
        raise InvalidInputError(f"Expected `{name}` to be {expected}, got no "
                                f"{missing[0]!r}.", field=name)
    extra = sorted(str(k) for k in value if k not in keys)
    if extra:
        raise InvalidInputError(f"Expected `{name}` to be {expected}, got an unknown key "
                                f"{extra[0]!r}.", field=name)
    return value[keys[0]], value[keys[1]]


def _validate_mesh(value: Any, info: ValidationInfo) -> Mesh:
    name = info.field_name or "mesh"
    if isinstance(value, Mesh):
        value = {"vertices": value.vertices, "faces": value.faces}
    vertices, faces = _object_members(value, name, ("vertices", "faces"))
    return as_mesh(vertices, faces, name=name, max_vertices=max_points(info))


def _validate_handles(value: Any, info: ValidationInfo) -> HandlesData:
    name = info.field_name or "handles"
    if not isinstance(value, HandlesData):
        _object_members(value, name, ("indices", "positions"))
    return as_handles(value, None, name=name)  # against the mesh: the model's validator


def _mesh_json(m: Mesh) -> dict[str, Any]:
    return {"vertices": m.vertices.tolist(), "faces": m.faces.tolist()}


def _handles_json(h: HandlesData) -> dict[str, Any]:
    return {"indices": h.indices.tolist(), "positions": h.positions.tolist()}


def handles_type(description: str, *, indices: str = "Distinct vertex indices (0-based).",
                 positions: str = "Target position of each handle, row i for indices[i], "
                 "same dimension as the mesh.", max_dim: int | None = 3) -> Any:
    """The input type of vertices held at positions, ``{"indices": [...], "positions":
    [[...], ...]}``, validated into :class:`algorithms.core.mesh.Handles` (structure only:
    the process's check holds them against its mesh or graph); positions of 2 to
    ``max_dim`` coordinates (no upper bound when None)."""
    row: dict[str, Any] = {"type": "array", "items": {"type": "number"}, "minItems": 2}
    if max_dim is not None:
        row["maxItems"] = max_dim
    return Annotated[HandlesData, PlainValidator(_validate_handles),
                     PlainSerializer(_handles_json), WithJsonSchema({
                         "type": "object", "description": description,
                         "properties": {
                             "indices": {"type": "array", "minItems": 1,
                                         "description": indices,
                                         "items": {"type": "integer", "minimum": 0}},
                             "positions": {"type": "array", "minItems": 1,
                                           "description": positions, "items": row}},
                         "required": ["indices", "positions"],
                         "additionalProperties": False})]


MeshInput = Annotated[
    Mesh,
    PlainValidator(_validate_mesh),
    PlainSerializer(_mesh_json),
    WithJsonSchema(mesh_schema("A triangle mesh: vertex coordinates and triangles.")),
]
"""A triangle mesh, given as ``{"vertices": [[x, y, z], ...], "faces": [[i, j, k], ...]}``;
validated into :class:`algorithms.core.mesh.Mesh`."""

Handles = handles_type("Vertices to move and where: their indices and target positions.")
"""Deformation handles, given as ``{"indices": [...], "positions": [[...], ...]}``; validated
into :class:`algorithms.core.mesh.Handles` (structure only: check them against the mesh with
``as_handles(handles, mesh)`` in a model validator)."""

HandlesInput = Handles
"""Alias of :data:`Handles` that does not shadow the dataclass's name."""


def _graph_schema(description: str) -> dict[str, Any]:
    return {
        "type": "object",
        "description": description,
        "properties": {
            "nodes": {"type": "integer", "minimum": 1, "description": "The number of nodes, "
                      "numbered 0 .. nodes - 1."},
            "edges": {"type": "array", "description": "One row (i, j) of node indices per "
                      "edge.", "items": {"type": "array", "items": {"type": "integer",
                                                                      "minimum": 0},
                                         "minItems": 2, "maxItems": 2}},
            "weights": {"type": ["array", "null"], "items": {"type": "number", "minimum": 0},
                        "description": "Optional: one non-negative number per edge (left "
                        "out or null: every edge weighs 1)."},
        },
        "required": ["nodes", "edges"],
        "additionalProperties": False,
    }


def _validate_graph(value: Any, info: ValidationInfo) -> Graph:
    return as_graph(value, name=info.field_name or "graph", max_nodes=max_points(info))


def _graph_json(g: Graph) -> dict[str, Any]:
    out: dict[str, Any] = {"nodes": g.n_nodes, "edges": g.edges.tolist()}
    if g.weights is not None:
        out["weights"] = g.weights.tolist()
    return out


GraphInput = Annotated[
    Graph,
    PlainValidator(_validate_graph),
    PlainSerializer(_graph_json),
    WithJsonSchema(_graph_schema("A graph: its node count, edges and optional edge weights.")),
]
"""A graph ``{"nodes": n, "edges": [[i, j], ...], "weights": [...]?}`` validated into
:class:`algorithms.layout.Graph`."""


def _validate_labels(value: Any, info: ValidationInfo) -> np.ndarray:
    name = info.field_name or "labels"
    if not isinstance(value, (list, np.ndarray)) or any(
            isinstance(v, (bool, float, dict, list)) or v is None for v in value):
        raise InvalidInputError(f"Expected `{name}` to be a flat list of class labels, all "
                                "integers or all strings.", field=name)
    kinds = {type(v) for v in value}
    if len(kinds) > 1:
        raise InvalidInputError(f"Expected `{name}` to be all integers or all strings, got "
                                "a mix.", field=name)
    return np.asarray(value)  # the length against the points: the function (or a check)


Labels = Annotated[
    np.ndarray,
    PlainValidator(_validate_labels),
    PlainSerializer(tolist),
    WithJsonSchema({"type": "array", "items": {"type": ["integer", "string"]},
                    "minItems": 1, "description": "One class label per point: integers or "
                    "strings."}),
]
"""One class label per point (integers or strings), as a 1-D numpy array."""


KIND_TYPES: dict[Kind, Any] = {
    Kind.POINTS: Points,
    Kind.WEIGHTS: Weights,
    Kind.LABELS: Labels,
    Kind.MESH: MeshInput,
    Kind.HANDLES: Handles,
    Kind.GRAPH: GraphInput,
}
"""The JSON input type of each declared kind that has one general form. Inputs of the other
kinds (shapes, other arrays) name their type in their catalog entry."""
