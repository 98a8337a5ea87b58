"""Catalog entries of the interpolation family (two shapes, or a shape and a transform, in;
frames of the path between them out)."""

from __future__ import annotations

from typing import Annotated, Any

import numpy as np
from pydantic import PlainSerializer, PlainValidator, ValidationInfo, WithJsonSchema

from algorithms.alignment import affine as fit_affine
from algorithms.alignment import rigid as fit_rigid
from algorithms.alignment import similarity as fit_similarity
from algorithms.core.errors import InvalidInputError
from algorithms.core.mesh import Mesh
from algorithms.interpolation import (
    MAX_FRAMES,
    Pair,
    affine,
    arap,
    check_frame_count,
    poisson,
    read_pair,
    read_shape,
    read_times,
    rigid,
)
from algorithms.interpolation.rigid import split_similarity
from service import scenes
from service.catalog.inputs import Points, max_points, points_schema
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


def _mesh_schema(description: str) -> dict[str, Any]:
    return {
        "type": "object",
        "description": description,
        "properties": {
            "vertices": {"type": "array", "minItems": 3, "description": "One row of 2 or 3 "
                         "coordinates per vertex.",
                         "items": {"type": "array", "items": {"type": "number"},
                                   "minItems": 2, "maxItems": 3}},
            "faces": {"type": "array", "minItems": 1, "description": "One row of 3 vertex "
                      "indices per triangle or, in 3-D, 4 per tetrahedron (0-based).",
                      "items": {"type": "array", "items": {"type": "integer", "minimum": 0},
                                "minItems": 3, "maxItems": 4}},
        },
        "required": ["vertices", "faces"],
        "additionalProperties": False,
    }


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
    WithJsonSchema({"anyOf": [_POINTS, _mesh_schema(
        "A mesh: vertices and triangles (or tetrahedra in 3-D).")],
        "description": "A point set (n, d) or a mesh {vertices, faces}."}),
]
"""A point set or a mesh (triangles, or tetrahedra in 3-D)."""

MeshShapeInput = Annotated[
    Any,
    PlainValidator(_validate_mesh),
    PlainSerializer(_shape_json),
    WithJsonSchema({"anyOf": [_mesh_schema(
        "A mesh: vertices and triangles (or tetrahedra in 3-D)."), _POINTS],
        "description": "A mesh {vertices, faces} (the target may also be its vertices "
        "alone)."}),
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


def _pair(p: Any) -> Pair:
    """The end shape (target or transform) fits the source; the frames fit the output cap."""
    pair = read_pair(p.source, p.target, p.transform)
    check_frame_count(pair.n, pair.dim, p.times if p.times is not None else read_times(None))
    return pair


def _keeps_orientation(p: Any) -> None:
    """As _pair, and the map (given, or the fit the job would make) mirrors only with flip."""
    pair = _pair(p)
    d = pair.dim
    if pair.transform is not None:
        a, field = pair.transform[:d, :d], "transform"
    else:  # the fit the job would make: a flat source is refused now (422)
        a, field = fit_affine(pair.source, pair.target).linear, "target"
    if p.reflection == "refuse" and np.linalg.det(a) < 0:
        raise InvalidInputError(
            f"Expected the map to `{field}` to keep orientation (det A > 0), got a "
            f"reflection; pass reflection='flip' to pass through a flattened shape once.",
            field=field)


def _is_rigid(p: Any) -> None:
    """As _pair, and the transform is a rigid motion (a similarity with scale), or fits one."""
    pair = _pair(p)
    d = pair.dim
    if pair.transform is not None:
        split_similarity(pair.transform[:d, :d], p.scale)
    elif p.scale:  # the fit the job would make: degenerate sources refused now
        fit_similarity(pair.source, pair.target)
    else:
        fit_rigid(pair.source, pair.target)


def _anchored(p: Any) -> None:
    """As _pair, and the anchor is a vertex of the source."""
    pair = _pair(p)
    if p.anchor >= pair.n:
        raise InvalidInputError(
            f"Expected `anchor` to be a vertex index of `source` (below {pair.n}), got "
            f"{p.anchor}.", field="anchor")


registry.add(Process(
    id="interpolation.affine",
    geometry=scenes.animation,
    title="Affine interpolation by polar decomposition",
    description="A = R S (polar decomposition); R turns along the shortest arc (slerp), S "
    "and the translation move linearly, so det A(t) > 0 all along the path. The map is "
    "given or fitted to the target (its residual blended in, so t = 1 is the target).",
    function=affine,
    examples={"source": _SQUARE, "transform": _AFFINE, "times": _TIMES},
    inputs=_SHAPES,
    check=_keeps_orientation,
    fast_path=True,
    keywords=("interpolation", "homotopy", "polar decomposition", "slerp", "animation"),
))

registry.add(Process(
    id="interpolation.rigid",
    geometry=scenes.animation,
    title="Rigid (or similarity) motion interpolation",
    description="Fits a rigid motion (Kabsch) or similarity (Umeyama) to the target, or "
    "takes the one given, and moves the shape along it: rotation by slerp (shortest arc), "
    "pivot on a straight line, scale geometric (s^t).",
    function=rigid,
    examples={"source": _SQUARE, "transform": _QUARTER, "times": _TIMES},
    inputs=_SHAPES,
    check=_is_rigid,
    fast_path=True,
    keywords=("interpolation", "rigid", "similarity", "slerp", "animation"),
))

registry.add(Process(
    id="interpolation.arap",
    geometry=scenes.animation,
    title="As-rigid-as-possible shape interpolation",
    description="Per face, A_f = R_f S_f interpolated as slerp(R_f) lerp(I, S_f); the "
    "vertices of each frame solve min Σ_f ‖B_f(x) − A_f(t)‖² with one vertex on its "
    "straight path (one factored sparse system, one solve per frame).",
    function=arap,
    examples={"source": _STRIP, "target": _BENT, "times": _TIMES},
    inputs=_MESHES,
    check=_anchored,
    long=True,
    keywords=("interpolation", "morphing", "arap", "homotopy", "animation"),
))

registry.add(Process(
    id="interpolation.poisson",
    geometry=scenes.animation,
    title="Poisson shape interpolation",
    description="Per-face gradients interpolated (rotations made continuous across the "
    "mesh then slerped, stretches lerped) and each frame recovered by a Poisson solve "
    "L x = div(gradients) with the prefactored cotangent Laplacian.",
    function=poisson,
    examples={"source": _STRIP, "target": _BENT, "times": _TIMES},
    inputs=_MESHES,
    check=_anchored,
    long=True,
    keywords=("interpolation", "morphing", "poisson", "gradient field", "animation"),
))
