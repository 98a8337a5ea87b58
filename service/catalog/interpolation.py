"""Catalog entries of the interpolation family (two shapes, or a shape and a transform, in;
frames of the path between them out)."""

from __future__ import annotations

from functools import partial
from typing import Annotated, Any

import numpy as np
from pydantic import PlainSerializer, PlainValidator, ValidationInfo, WithJsonSchema

from algorithms.core.errors import InvalidInputError
from algorithms.core.mesh import Mesh
from algorithms.interpolation import (
    MAX_FRAMES,
    affine,
    arap,
    check_anchored,
    poisson,
    read_shape,
    read_times,
    rigid,
)
from algorithms.interpolation.affine import check_affine
from algorithms.interpolation.rigid import check_rigid
from service import scenes
from service.catalog.inputs import Points, max_points, mesh_schema, points_schema
from service.catalog.registry import Process, registry

# A 4 × 1 strip in the plane (ten vertices, eight triangles) ...
_STRIP_V = [[0.0, -0.5], [1.0, -0.5], [2.0, -0.5], [3.0, -0.5], [4.0, -0.5],
            [0.0, 0.5], [1.0, 0.5], [2.0, 0.5], [3.0, 0.5], [4.0, 0.5]]
_STRIP_F = [[0, 1, 6], [0, 6, 5], [1, 2, 7], [1, 7, 6], [2, 3, 8], [2, 8, 7], [3, 4, 9],
            [3, 9, 8]]
# ... bent into a quarter circle (its centre line keeps its length)
_BENT_V = [[0.0, -0.5], [1.165837, -0.268101], [2.154186, 0.392293], [2.81458, 1.380642],
           [3.046479, 2.546479], [0.0, 0.5], [0.783154, 0.655779], [1.447079, 1.0994],
           [1.8907, 1.763325], [2.046479, 2.546479]]
_STRIP = {"vertices": _STRIP_V, "faces": _STRIP_F}
_BENT = {"vertices": _BENT_V, "faces": _STRIP_F}
# a unit square turned by a quarter turn, stretched along x and moved
_SQUARE = [[0, 0], [1, 0], [1, 1], [0, 1]]
_AFFINE = [[0.0, -1.0, 2.0], [2.0, 0.0, 1.0], [0.0, 0.0, 1.0]]
_QUARTER = [[0.0, -1.0, 2.0], [1.0, 0.0, 1.0], [0.0, 0.0, 1.0]]
_TIMES = [0.0, 0.25, 0.5, 0.75, 1.0]


_SOLIDS = "One row of 3 vertex indices per triangle or, in 3-D, 4 per tetrahedron (0-based)."
_MESH = mesh_schema("A mesh: vertices and triangles (or tetrahedra in 3-D).", faces=_SOLIDS,
                    corners=(3, 4))


def _shape(value: Any, info: ValidationInfo, need_faces: bool) -> Mesh | np.ndarray:
    name = info.field_name or "source"
    if isinstance(value, Mesh):
        value = {"vertices": value.vertices, "faces": value.faces}
    if value is not None and not isinstance(value, dict) and need_faces:
        raise InvalidInputError(
            f"Expected `{name}` to be a mesh {{vertices, faces}}, got "
            f"{type(value).__name__}.", field=name)
    v, f = read_shape(value, name=name, max_points=max_points(info),
                      allow_degenerate=name != "source")
    if isinstance(value, dict):
        return Mesh(v, f)
    return v


def _validate_shape(value: Any, info: ValidationInfo) -> Mesh | np.ndarray:
    return _shape(value, info, need_faces=False)


def _validate_mesh(value: Any, info: ValidationInfo) -> Mesh | np.ndarray:
    return _shape(value, info, need_faces=info.field_name == "source")


def _shape_json(value: Mesh | np.ndarray) -> Any:
    if isinstance(value, Mesh):
        return {"vertices": value.vertices.tolist(), "faces": value.faces.tolist()}
    return value.tolist()


def _validate_times(value: Any, info: ValidationInfo) -> np.ndarray:
    return read_times(value, name=info.field_name or "times")


_POINTS = points_schema("An (n, d) point set, d = 2 or 3.", min_points=1)

ShapeInput = Annotated[
    Any,
    PlainValidator(_validate_shape),
    PlainSerializer(_shape_json),
    WithJsonSchema({"anyOf": [_POINTS, _MESH],
                    "description": "A point set (n, d) or a mesh {vertices, faces}."}),
]
"""A point set or a mesh (triangles, or tetrahedra in 3-D)."""

MeshShapeInput = Annotated[
    Any,
    PlainValidator(_validate_mesh),
    PlainSerializer(_shape_json),
    WithJsonSchema({"anyOf": [_MESH, _POINTS], "description": "A mesh {vertices, faces} "
                    "(the target may also be its vertices alone)."}),
]
"""A mesh (the source); the target may be given as its vertices alone."""

TimesInput = Annotated[
    np.ndarray,
    PlainValidator(_validate_times),
    PlainSerializer(lambda a: a.tolist()),
    WithJsonSchema({"type": "array", "items": {"type": "number", "minimum": 0, "maximum": 1},
                    "minItems": 1, "maxItems": MAX_FRAMES,
                    "description": "Strictly increasing times in [0, 1]."}),
]
"""Strictly increasing times in [0, 1]."""

_SHAPES = {"source": ShapeInput, "target": ShapeInput | None, "transform": Points | None,
           "times": TimesInput | None}
_MESHES = {**_SHAPES, "source": MeshShapeInput, "target": MeshShapeInput | None}


_whole = partial(Process, geometry=scenes.animation, inputs=_SHAPES, fast_path=True)
_per_face = partial(Process, geometry=scenes.animation, inputs=_MESHES, check=check_anchored,
                    examples={"source": _STRIP, "target": _BENT, "times": _TIMES}, long=True)

registry.add(_whole(affine, check=check_affine,
                    examples={"source": _SQUARE, "transform": _AFFINE, "times": _TIMES},
                    keywords=("interpolation", "homotopy", "polar decomposition", "slerp",
                              "animation")))
registry.add(_whole(rigid, check=check_rigid,
                    examples={"source": _SQUARE, "transform": _QUARTER, "times": _TIMES},
                    keywords=("interpolation", "rigid", "similarity", "slerp", "animation")))
registry.add(_per_face(arap, keywords=("interpolation", "morphing", "arap", "homotopy",
                                       "animation")))
registry.add(_per_face(poisson, keywords=("interpolation", "morphing", "poisson",
                                          "gradient field", "animation")))
