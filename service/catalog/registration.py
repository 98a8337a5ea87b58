"""Catalog entries of the registration family (no correspondences: found with the transform)."""

from __future__ import annotations

from typing import Annotated, Any, Literal

import numpy as np
from pydantic import Field, PlainSerializer, PlainValidator, WithJsonSchema, model_validator

from algorithms.core.validation import as_choice, as_points, same_dim
from algorithms.registration import ICPResult, icp
from algorithms.registration._normals import given_normals
from algorithms.registration.icp import INITS, check_init
from service.catalog.base import Params
from service.catalog.inputs import Points
from service.catalog.registry import Process, registry

# A tetrahedron-like asymmetric set and the same turned by 10° about z and shifted by (0.1, 0, 0)
_SOURCE = [[0, 0, 0], [2, 0, 0], [0, 1, 0], [0, 0, 0.5], [1, 1, 0.2], [0.5, 0.2, 0.4]]
_C, _S = float(np.cos(np.radians(10.0))), float(np.sin(np.radians(10.0)))
_TARGET = [[round(_C * x - _S * y + 0.1, 12), round(_S * x + _C * y, 12), z]
           for x, y, z in _SOURCE]


def _validate_init(value: Any) -> str | np.ndarray:
    if isinstance(value, str):
        return as_choice(value, INITS, name="init")
    return as_points(value, name="init")  # its shape and model: checked by the algorithm


def _init_json(value: str | np.ndarray) -> Any:
    return value if isinstance(value, str) else value.tolist()


InitInput = Annotated[
    Any,
    PlainValidator(_validate_init),
    PlainSerializer(_init_json),
    WithJsonSchema({
        "anyOf": [
            {"type": "string", "enum": list(INITS)},
            {"type": "array", "items": {"type": "array", "items": {"type": "number"}},
             "minItems": 3},
        ],
    }),
]


class ICPParams(Params):
    source: Points = Field(description="Points to move: an (n, d) array, d ≥ 2 (d = 3 for "
                           "the plane metrics).", examples=[_SOURCE])
    target: Points = Field(description="Points to register onto: an (m, d) array, same d, "
                           "any m; no correspondence with source needed.", examples=[_TARGET])
    model: Literal["rigid", "similarity", "affine"] = Field(
        "rigid", description="rigid: rotation + translation; similarity: also a uniform "
        "scale; affine: any linear map + translation.")
    metric: Literal["point_to_point", "point_to_plane", "symmetric"] = Field(
        "point_to_point", description="point_to_point (any d), point_to_plane (3-D, target "
        "normals estimated when not given) or symmetric (3-D, rigid, both sets' normals).")
    init: InitInput = Field(
        "identity", description="The initial transform: 'identity', 'pca' (principal axes, "
        "every proper sign choice tried, the best ICP result kept), or a (d+1)×(d+1) "
        "homogeneous matrix whose linear part belongs to the model.")
    max_iterations: int = Field(30, ge=1, le=10_000, description="Most iterations (per sign "
                                "choice with init=pca).")
    tolerance: float = Field(1e-6, ge=0, description="Stop when the RMSE changes by less "
                             "than this fraction in an iteration; the iterations also stop "
                             "when the correspondences no longer change.")
    max_correspondence_distance: float | None = Field(
        None, gt=0, description="Ignore pairs farther apart than this; also the inlier "
        "bound of fitness. No bound when omitted.")
    overlap: float = Field(1.0, gt=0, le=1, description="Trimmed ICP: keep only this "
                           "fraction of source points, those with the nearest partners.")
    kernel: Literal["none", "huber", "tukey"] = Field(
        "none", description="Robust kernel applied by iteratively reweighted least squares.")
    kernel_scale: float | None = Field(
        None, gt=0, description="The kernel's threshold in the points' units; estimated "
        "each iteration from the median residual when omitted.")
    target_normals: Points | None = Field(
        None, description="Optional (m, 3) normals of the target points for the plane "
        "metrics; estimated by local PCA when omitted.")
    source_normals: Points | None = Field(
        None, description="Optional (n, 3) normals of the source points for "
        "metric=symmetric; estimated by local PCA when omitted.")
    normal_neighbors: int = Field(10, ge=2, le=1000, description="Neighbours per estimated "
                                  "normal.")

    @model_validator(mode="after")
    def _consistent(self) -> ICPParams:
        """What can be checked before the job runs is checked here, so that an asynchronous
        request is refused with 422 at once instead of failing later."""
        same_dim(self.source, self.target, names=("source", "target"))
        for normals, points, name in ((self.target_normals, self.target, "target_normals"),
                                      (self.source_normals, self.source, "source_normals")):
            if normals is not None:
                given_normals(normals, points.shape[0], name=name)
        if not isinstance(self.init, str):
            check_init(self.init, self.source.shape[1], self.model)
        return self


registry.add(Process(
    id="registration.icp",
    title="Iterative closest point (rigid, similarity, affine)",
    description="Registers source onto target without correspondences: nearest-neighbour "
    "pairs (one kd-tree), closed-form or linearised point-to-plane / symmetric fit, repeat "
    "until the pairs stop changing or the RMSE settles; identity, PCA (all sign choices) or "
    "matrix start; distance bound, trimming and Huber/Tukey kernels. Returns fitness and "
    "converged=false with a reason instead of a silent identity.",
    function=icp,
    params=ICPParams,
    result=ICPResult,
    reference="Besl, P. J., McKay, N. D. (1992). A method for registration of 3-D shapes. "
    "IEEE TPAMI 14(2), 239–256; Rusinkiewicz, S. (2019). A symmetric objective function "
    "for ICP. ACM TOG 38(4), 85.",
    long=True,
    keywords=("icp", "registration", "point cloud", "point-to-plane", "trimmed", "robust"),
))
