"""Catalog entries of the interpolation family (two shapes, or a shape and a transform, in;
frames of the path between them out)."""

from __future__ import annotations

from typing import Annotated, Any, Literal

import numpy as np
from pydantic import (
    Field,
    PlainSerializer,
    PlainValidator,
    ValidationInfo,
    WithJsonSchema,
    model_validator,
)

from algorithms.alignment.affine import affine as fit_affine
from algorithms.alignment.rigid import rigid as fit_rigid
from algorithms.alignment.similarity import similarity as fit_similarity
from algorithms.core.errors import InvalidInputError
from algorithms.core.mesh import Mesh
from algorithms.interpolation import (
    MAX_FRAMES,
    AffineInterpolationResult,
    ArapInterpolationResult,
    PoissonInterpolationResult,
    RigidInterpolationResult,
    affine,
    arap,
    poisson,
    read_pair,
    read_times,
    rigid,
)
from algorithms.interpolation._common import check_frame_count, read_shape
from algorithms.interpolation.rigid import split_similarity
from service.catalog.base import Params
from service.catalog.inputs import Points, points_schema
from service import scenes
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


def _mesh_schema(description: str, *, tets: bool) -> dict[str, Any]:
    per_face = 4 if tets else 3
    what = ("3 vertex indices per triangle or, in 3-D, 4 per tetrahedron" if tets
            else "3 vertex indices per triangle")
    return {
        "type": "object",
        "description": description,
        "properties": {
            "vertices": {"type": "array", "minItems": 3, "description": "One row of 2 or 3 "
                         "coordinates per vertex.",
                         "items": {"type": "array", "items": {"type": "number"},
                                   "minItems": 2, "maxItems": 3}},
            "faces": {"type": "array", "minItems": 1, "description": f"One row of {what} "
                      "(0-based).",
                      "items": {"type": "array", "items": {"type": "integer", "minimum": 0},
                                "minItems": 3, "maxItems": per_face}},
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
    max_points = (info.context or {}).get("max_points")
    v, f = read_shape(value, name=name, max_points=max_points,
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
        "A mesh: vertices and triangles (or tetrahedra in 3-D).", tets=True)],
        "description": "A point set (n, d) or a mesh {vertices, faces}."}),
]
"""A point set or a mesh (triangles, or tetrahedra in 3-D)."""

MeshShapeInput = Annotated[
    Any,
    PlainValidator(_validate_mesh),
    PlainSerializer(_shape_json),
    WithJsonSchema({"anyOf": [_mesh_schema(
        "A mesh: vertices and triangles (or tetrahedra in 3-D).", tets=True), _POINTS],
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

_SOURCE = ("The shape at t = 0: a point set (n, d) or a mesh {vertices: (n, d), faces: "
           "(m, 3) triangles or, in 3-D, (m, 4) tetrahedra}; d = 2 or 3.")
_SOURCE_MESH = ("The mesh at t = 0: {vertices: (n, d), faces: (m, 3) triangles (d = 2 or 3) "
                "or (m, 4) tetrahedra (d = 3)}, no zero-area faces.")
_TARGET = ("The shape at t = 1, point i for source point i: points (n, d), or a mesh with "
           "exactly the source's faces (same connectivity). Give this or transform.")
_TRANSFORM = ("A homogeneous (d+1) × (d+1) matrix [[A, b], [0, 1]] applied to the source "
              "instead of a target.")
_TIMES_DESC = ("Strictly increasing times in [0, 1] (no extrapolation), one frame each; "
               "11 evenly spaced (0, 0.1, ..., 1) when omitted.")
_ANCHOR = ("The vertex that moves on a straight line from its source to its target "
           "position (fixes the free translation); other connected components use their "
           "lowest-numbered vertex.")


class _InterpolationParams(Params):
    source: ShapeInput = Field(description=_SOURCE, examples=[_SQUARE])
    target: ShapeInput | None = Field(None, description=_TARGET)
    transform: Points | None = Field(None, description=_TRANSFORM, examples=[_AFFINE])
    times: TimesInput | None = Field(None, description=_TIMES_DESC, examples=[_TIMES])

    @model_validator(mode="after")
    def _end_shape(self) -> _InterpolationParams:
        pair = read_pair(self.source, self.target, self.transform)
        times = self.times if self.times is not None else read_times(None)
        check_frame_count(pair.n, pair.dim, times)
        self._check(pair)
        return self

    def _check(self, pair: Any) -> None:
        """Checks of one process against the shapes."""


class AffineParams(_InterpolationParams):
    reflection: Literal["refuse", "flip"] = Field(
        "refuse", description="A map that mirrors (det A < 0) cannot be reached without "
        "flattening the shape: refuse it, or flip (the seed's treatment: a rotation and a "
        "stretch with one negative eigenvalue; the path flattens once).")
    pivot: Literal["centroid", "origin"] = Field(
        "centroid", description="The point the linear part acts about: the source's "
        "centroid (which moves on a straight line) or the origin (b(t) = t b).")

    def _check(self, pair: Any) -> None:
        d = pair.dim
        if pair.transform is not None:
            a, field = pair.transform[:d, :d], "transform"
        else:  # the fit the job would make: a flat source is refused now (422)
            a, field = fit_affine(pair.source, pair.target).linear, "target"
        if self.reflection == "refuse" and np.linalg.det(a) < 0:
            raise InvalidInputError(
                f"Expected the map to `{field}` to keep orientation (det A > 0), got a "
                f"reflection; pass reflection='flip' to pass through a flattened shape once.",
                field=field)


class RigidParams(_InterpolationParams):
    transform: Points | None = Field(None, description="A homogeneous (d+1) × (d+1) rigid "
                                     "motion [[R, b], [0, 1]] (a similarity [[sR, b], [0, 1]] "
                                     "with scale=true) instead of a target.",
                                     examples=[_QUARTER])
    scale: bool = Field(False, description="Fit and interpolate a uniform scale too "
                        "(geometrically: s^t).")
    pivot: Literal["centroid", "origin"] = Field(
        "centroid", description="The point the rotation turns about: the source's centroid "
        "(which moves on a straight line) or the origin.")

    def _check(self, pair: Any) -> None:
        d = pair.dim
        if pair.transform is not None:
            split_similarity(pair.transform[:d, :d], self.scale)
        elif self.scale:  # the fit the job would make: degenerate sources refused now
            fit_similarity(pair.source, pair.target)
        else:
            fit_rigid(pair.source, pair.target)


class _MeshInterpolationParams(_InterpolationParams):
    source: MeshShapeInput = Field(description=_SOURCE_MESH, examples=[_STRIP])
    target: MeshShapeInput | None = Field(None, description=_TARGET, examples=[_BENT])
    transform: Points | None = Field(None, description=_TRANSFORM)
    anchor: int = Field(0, ge=0, description=_ANCHOR)

    def _check(self, pair: Any) -> None:
        if self.anchor >= pair.n:
            raise InvalidInputError(
                f"Expected `anchor` to be a vertex index of `source` (below {pair.n}), got "
                f"{self.anchor}.", field="anchor")


class ArapParams(_MeshInterpolationParams):
    pass


class PoissonParams(_MeshInterpolationParams):
    pass


registry.add(Process(
    id="interpolation.affine",
    geometry=scenes.animation,
    title="Affine interpolation by polar decomposition",
    description="A = R S (polar decomposition); R turns along the shortest arc (slerp), S "
    "and the translation move linearly, so det A(t) > 0 all along the path. The map is "
    "given or fitted to the target (its residual blended in, so t = 1 is the target).",
    function=affine,
    params=AffineParams,
    result=AffineInterpolationResult,
    reference="Shoemake, K., Duff, T. (1992). Matrix animation and polar decomposition. "
    "Graphics Interface '92, 258–264.",
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
    params=RigidParams,
    result=RigidInterpolationResult,
    reference="Shoemake, K. (1985). Animating rotation with quaternion curves. SIGGRAPH "
    "1985, 245–254.",
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
    params=ArapParams,
    result=ArapInterpolationResult,
    reference="Alexa, M., Cohen-Or, D., Levin, D. (2000). As-rigid-as-possible shape "
    "interpolation. SIGGRAPH 2000, 157–164.",
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
    params=PoissonParams,
    result=PoissonInterpolationResult,
    reference="Xu, D., Zhang, H., Wang, Q., Bao, H. (2005). Poisson shape interpolation. "
    "ACM Symposium on Solid and Physical Modeling 2005, 267–274.",
    long=True,
    keywords=("interpolation", "morphing", "poisson", "gradient field", "animation"),
))
