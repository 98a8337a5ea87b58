"""Catalog entries of the registration family (no correspondences: found with the transform)."""

from __future__ import annotations

from typing import Annotated, Any

import numpy as np
from annotated_types import Le
from pydantic import PlainSerializer, PlainValidator, ValidationInfo, WithJsonSchema

from algorithms.core.errors import InvalidInputError
from algorithms.core.validation import as_choice, as_points, same_dim
from algorithms.registration import cpd, given_normals, icp, ransac
from algorithms.registration.cpd import check_sizes
from algorithms.registration.icp import INITS, check_init
from algorithms.registration.multiway import check_sets, check_transforms, multiway
from algorithms.registration.pose_graph import check_neighbors
from algorithms.registration.ransac import check_inputs
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
def _icp_inputs(p: Any) -> None:
    """Same dimension; normals one per point; a matrix start of the right size and model."""
    same_dim(p.source, p.target, names=("source", "target"))
    for normals, points, name in ((p.target_normals, p.target, "target_normals"),
                                  (p.source_normals, p.source, "source_normals")):
        if normals is not None:
            given_normals(normals, points.shape[0], name=name)
    if not isinstance(p.init, str):
        check_init(p.init, p.source.shape[1], p.model)


def _cpd_inputs(p: Any) -> None:
    """Same dimension; enough points for the model and the kernel asked for."""
    same_dim(p.source, p.target, names=("source", "target"))
    check_sizes(p.source, p.target, p.model, p.low_rank)


def _ransac_inputs(p: Any) -> None:
    """Same dimension; 3-D for features; enough points, not collinear."""
    same_dim(p.source, p.target, names=("source", "target"))
    check_inputs(p.source, p.target, p.features)


def _multiway_inputs(p: Any) -> None:
    """Counts, lengths, dimensions and flat sets; init and neighbors against the sets."""
    sets = check_sets(p.sets, correspondences=p.correspondences, model=p.model,
                      metric=p.metric)
    k, d = len(sets), sets[0].shape[1]
    if p.init is not None:
        check_transforms(p.init, k, d, p.model)
    if not p.correspondences:
        check_neighbors(p.neighbors, k)


_ITERATIONS = {"max_iterations": Le(10_000)}

registry.add(Process(
    id="registration.icp",
    geometry=scenes.moved_source,
    title="Iterative closest point (rigid, similarity, affine)",
    description="Registers source onto target without correspondences: nearest-neighbour "
    "pairs (one kd-tree), closed-form or linearised point-to-plane / symmetric fit, repeat "
    "until the pairs stop changing or the RMSE settles; identity, PCA (all sign choices) or "
    "matrix start; distance bound, trimming and Huber/Tukey kernels. Returns fitness and "
    "converged=false with a reason instead of a silent identity.",
    function=icp,
    examples={"source": _SOURCE, "target": _TARGET},
    inputs={"init": InitInput},
    limits={**_ITERATIONS, "normal_neighbors": Le(1000)},
    check=_icp_inputs,
    long=True,
    keywords=("icp", "registration", "point cloud", "point-to-plane", "trimmed", "robust"),
))

registry.add(Process(
    id="registration.cpd",
    geometry=scenes.moved_source,
    title="Coherent point drift (rigid with scale, affine, nonrigid)",
    description="Registers source onto target without correspondences as a Gaussian mixture "
    "fitted by EM: soft correspondences from every pair, closed-form rigid (optionally "
    "scaled) or affine M-steps, or a smooth nonrigid displacement with the motion coherence "
    "regulariser (exact or low-rank kernel); a uniform component of weight w absorbs "
    "outliers. Memory bounded: the M×N posterior is summed in blocks, never stored, so "
    "20,000 × 20,000 points need about 330 MB. Any dimension.",
    function=cpd,
    examples={"source": _SOURCE, "target": _CPD_TARGET},
    limits=_ITERATIONS,
    check=_cpd_inputs,
    long=True,
    keywords=("cpd", "coherent point drift", "registration", "point cloud", "nonrigid",
              "gmm", "em"),
))

registry.add(Process(
    id="registration.ransac",
    geometry=scenes.moved_source,
    title="RANSAC global registration (FPFH features or random triples) + ICP",
    description="Registers source onto target rigidly without a start: candidate pairs from "
    "mutually matched FPFH features (or, for small sets, random point triples of each set), "
    "seeded random samples of 3 pairs checked by edge lengths, Kabsch fits scored by "
    "truncated squared error, confidence-based stopping. Without voxel_size: two "
    "down-sampling passes (1.5 and 3 × the point spacing), the best hypotheses re-scored and "
    "ICP-checked on the point sets, a robust (Tukey) ICP refinement against the full target; "
    "with voxel_size: Open3D's single pass, then point-to-plane ICP. The same seed gives the "
    "same result; converged=false with a reason instead of a silent identity.",
    function=ransac,
    examples={"source": _SOURCE, "target": _RANSAC_TARGET, "features": "none",
              "max_correspondence_distance": 0.05},
    limits={"max_iterations": Le(10_000_000)},
    check=_ransac_inputs,
    long=True,
    keywords=("ransac", "global registration", "fpfh", "features", "registration",
              "point cloud", "no initial guess"),
))

registry.add(Process(
    id="registration.multiway",
    geometry=scenes.moved_sets,
    title="Multiway registration: generalised Procrustes or pose graph",
    description="Registers several point sets at once into the frame of set 0. With "
    "correspondences: generalised Procrustes analysis (rigid or similarity, any dimension), "
    "iterated to the mean shape. Without: pairwise ICP (coarse to fine, symmetric metric, "
    "point-to-point polish) with information matrices, then pose-graph optimisation on "
    "SE(3) by Levenberg-Marquardt with line processes for loop closures, low-fitness and "
    "inconsistent edges pruned (as Open3D's multiway registration).",
    function=multiway,
    examples={"sets": _MULTIWAY_SETS},
    inputs={"sets": PointSets, "init": Transforms | None},
    limits={**_ITERATIONS, "icp_max_iterations": Le(10_000)},
    check=_multiway_inputs,
    long=True,
    keywords=("multiway", "generalized procrustes", "gpa", "pose graph", "registration",
              "point cloud", "loop closure"),
))
