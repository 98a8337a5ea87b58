"""Catalog entries of the registration family (no correspondences: found with the transform)."""

from __future__ import annotations

from functools import partial
from typing import Annotated, Any

import numpy as np
from annotated_types import Le
from pydantic import PlainSerializer, PlainValidator, ValidationInfo, WithJsonSchema

from algorithms.core.errors import InvalidInputError
from algorithms.core.validation import as_choice, as_points, check_point_sets
from algorithms.registration import cpd, given_normals, icp, ransac
from algorithms.registration.cpd import check_sizes
from algorithms.registration.icp import INITS, check_init
from algorithms.registration.multiway import check_multiway, multiway
from algorithms.registration.ransac import check_ransac
from service import scenes
from service.catalog.inputs import max_points, points_schema
from service.catalog.registry import Process, registry

# A tetrahedron-like asymmetric set and the same turned by 10° about z and shifted by (0.1, 0, 0)
_SOURCE: list[list[float]] = [[0, 0, 0], [2, 0, 0], [0, 1, 0], [0, 0, 0.5], [1, 1, 0.2],
                              [0.5, 0.2, 0.4]]
_C, _S = float(np.cos(np.radians(10.0))), float(np.sin(np.radians(10.0)))
_TARGET = [[round(_C * x - _S * y + 0.1, 12), round(_S * x + _C * y, 12), z]
           for x, y, z in _SOURCE]
# The same, scaled by 1.5 as well: rigid CPD with scale recovers all three.
_CPD_TARGET = [[round(1.5 * (_C * x - _S * y) + 0.1, 12), round(1.5 * (_S * x + _C * y), 12),
                round(1.5 * z, 12)] for x, y, z in _SOURCE]
# Turned by 120° about z (beyond any local method), shifted and listed backwards: RANSAC
# finds it from random samples, without a start.
_RC, _RS = float(np.cos(np.radians(120.0))), float(np.sin(np.radians(120.0)))
_RANSAC_TARGET = [[round(_RC * x - _RS * y + 1.0, 12), round(_RS * x + _RC * y - 0.5, 12), z]
                  for x, y, z in _SOURCE[::-1]]
# Three views of an L-shaped set of 5 points, row j the same point in each: the second turned
# by 90° and shifted by (5, 0), the third twice as large and shifted by (0, 3).
_L = [[0, 0], [2, 0], [0, 1], [0, 2], [1, 0]]
_MULTIWAY_SETS = [_L, [[-y + 5, x] for x, y in _L], [[2 * x, 2 * y + 3] for x, y in _L]]


# -- JSON forms of the family's special inputs ----------------------------------------------
def _validate_init(value: Any) -> str | np.ndarray:
    if isinstance(value, str):
        return as_choice(value, INITS, name="init")
    return as_points(value, name="init")  # its shape and model: checked by the algorithm


InitInput = Annotated[
    Any,
    PlainValidator(_validate_init),
    PlainSerializer(lambda v: v if isinstance(v, str) else v.tolist()),
    WithJsonSchema({"anyOf": [
        {"type": "string", "enum": list(INITS)},
        {"type": "array", "items": {"type": "array", "items": {"type": "number"}},
         "minItems": 3},
    ]}),
]
"""ICP's start: a named one or a (d+1)×(d+1) homogeneous matrix."""


def _validate_point_sets(value: Any, info: ValidationInfo) -> list[np.ndarray]:
    name = info.field_name or "sets"
    if isinstance(value, np.ndarray) and value.ndim == 3:
        value = list(value)
    if not isinstance(value, (list, tuple)):
        raise InvalidInputError(f"Expected `{name}` to be a list of (n, d) point arrays, got "
                                f"{type(value).__name__}.", field=name)
    limit = max_points(info)
    return [as_points(v, name=f"{name}[{i}]", max_points=limit)
            for i, v in enumerate(value)]


PointSets = Annotated[
    list,
    PlainValidator(_validate_point_sets),
    PlainSerializer(lambda sets: [a.tolist() for a in sets]),
    WithJsonSchema({"type": "array", "minItems": 2, "description": "A list of point sets.",
                    "items": points_schema("An (n, d) array of point coordinates.")}),
]
"""A list of (n_i, d) float arrays, given as a JSON array of point arrays; errors name the
set (`sets[2]`)."""


def _validate_transforms(value: Any, info: ValidationInfo) -> np.ndarray:
    name = info.field_name or "init"
    try:
        arr = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise InvalidInputError(f"Expected `{name}` to be an array of (d+1)×(d+1) "
                                "homogeneous matrices, one per set.", field=name) from None
    if arr.ndim != 3:
        raise InvalidInputError(f"Expected `{name}` to be a (k, d+1, d+1) array of "
                                f"homogeneous matrices, got shape {tuple(arr.shape)}.",
                                field=name)
    return arr  # count, size, finiteness and model: check_transforms against the sets


Transforms = Annotated[
    np.ndarray,
    PlainValidator(_validate_transforms),
    PlainSerializer(lambda a: a.tolist()),
    WithJsonSchema({"type": "array", "description": "One (d+1)×(d+1) homogeneous matrix per "
                    "set.", "items": {"type": "array", "items": {"type": "array", "items":
                                                                 {"type": "number"}}}}),
]


# -- checks across inputs, before a job is queued -------------------------------------------
def _icp_inputs(source: Any, target: Any, source_normals: Any, target_normals: Any,
                init: Any, model: str) -> None:
    """Same dimension; normals one per point; a matrix start of the right size and model."""
    check_point_sets(source, target)
    for normals, points, name in ((target_normals, target, "target_normals"),
                                  (source_normals, source, "source_normals")):
        if normals is not None:
            given_normals(normals, points.shape[0], name=name)
    if not isinstance(init, str):
        check_init(init, source.shape[1], model)


def _cpd_inputs(source: Any, target: Any, model: str, low_rank: int | None) -> None:
    """Same dimension; enough points for the model and the kernel asked for."""
    check_sizes(*check_point_sets(source, target), model, low_rank)


_ITERATIONS = {"max_iterations": Le(10_000)}

_moved = partial(Process, geometry=scenes.moved_source, limits=_ITERATIONS, long=True)

# icp and cpd keep their texts here: their docstrings open with the mathematics
registry.add(_moved(
    icp, title="Iterative closest point (rigid, similarity, affine)",
    description="Registers source onto target without correspondences: nearest-neighbour "
    "pairs (one kd-tree), closed-form or linearised point-to-plane / symmetric fit, repeat "
    "until the pairs stop changing or the RMSE settles; identity, PCA (all sign choices) or "
    "matrix start; distance bound, trimming and Huber/Tukey kernels. Returns fitness and "
    "converged=false with a reason instead of a silent identity.",
    examples={"source": _SOURCE, "target": _TARGET}, inputs={"init": InitInput},
    limits={**_ITERATIONS, "normal_neighbors": Le(1000)}, check=_icp_inputs,
    keywords=("icp", "registration", "point cloud", "point-to-plane", "trimmed", "robust")))
registry.add(_moved(
    cpd, title="Coherent point drift (rigid with scale, affine, nonrigid)",
    description="Registers source onto target without correspondences as a Gaussian mixture "
    "fitted by EM: soft correspondences from every pair, closed-form rigid (optionally "
    "scaled) or affine M-steps, or a smooth nonrigid displacement with the motion coherence "
    "regulariser (exact or low-rank kernel); a uniform component of weight w absorbs "
    "outliers. Memory bounded: the M×N posterior is summed in blocks, never stored, so "
    "20,000 × 20,000 points need about 330 MB. Any dimension.",
    examples={"source": _SOURCE, "target": _CPD_TARGET}, check=_cpd_inputs,
    keywords=("cpd", "coherent point drift", "registration", "point cloud", "nonrigid",
              "gmm", "em")))
registry.add(_moved(
    ransac, check=check_ransac, limits={"max_iterations": Le(10_000_000)},
    examples={"source": _SOURCE, "target": _RANSAC_TARGET, "features": "none",
              "max_correspondence_distance": 0.05},
    keywords=("ransac", "global registration", "fpfh", "features", "registration",
              "point cloud", "no initial guess")))
registry.add(_moved(
    multiway, geometry=scenes.moved_sets, check=check_multiway,
    examples={"sets": _MULTIWAY_SETS}, inputs={"sets": PointSets, "init": Transforms | None},
    limits={**_ITERATIONS, "icp_max_iterations": Le(10_000)},
    keywords=("multiway", "generalized procrustes", "gpa", "pose graph", "registration",
              "point cloud", "loop closure")))
