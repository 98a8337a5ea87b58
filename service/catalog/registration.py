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
from service import scenes
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
    geometry=scenes.moved_source,
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


# --- registration.cpd -------------------------------------------------------------------------

from algorithms.registration.cpd import CPDResult, check_sizes, cpd  # noqa: E402

# The ICP example's source, scaled by 1.5 as well: rigid CPD with scale recovers all three.
_CPD_TARGET = [[round(1.5 * (_C * x - _S * y) + 0.1, 12), round(1.5 * (_S * x + _C * y), 12),
                round(1.5 * z, 12)] for x, y, z in _SOURCE]


class CPDParams(Params):
    source: Points = Field(description="Points to move (the mixture's centroids): an (M, d) "
                           "array, d ≥ 2.", examples=[_SOURCE])
    target: Points = Field(description="Points to register onto: an (N, d) array, same d, "
                           "any N; no correspondence with source needed.",
                           examples=[_CPD_TARGET])
    model: Literal["rigid", "affine", "nonrigid"] = Field(
        "rigid", description="rigid: rotation, translation and (with scale) a uniform scale; "
        "affine: any linear map + translation; nonrigid: a smooth displacement field "
        "(Gaussian kernel, motion coherence).")
    scale: bool = Field(True, description="Rigid only: estimate a uniform scale as well.")
    w: float = Field(0.0, ge=0, lt=1, description="Weight of the uniform outlier component, "
                     "in [0, 1): raise it for noise and points missing from one set.")
    beta: float = Field(2.0, gt=0, description="Nonrigid: width of the Gaussian kernel "
                        "(larger is smoother), in normalised units when normalize is true.")
    alpha: float = Field(2.0, gt=0, description="Nonrigid: regularisation weight (the "
                         "paper's lambda); larger keeps the motion more coherent.")
    low_rank: int | None = Field(
        None, ge=1, description="Nonrigid: number of leading eigenpairs of the kernel (the "
        "paper's fast version). Default: exact up to 1000 source points, else ceil(sqrt(M)); "
        "a value ≥ M asks for the exact kernel (up to 4000 source points).")
    normalize: bool = Field(True, description="Nonrigid: centre each set and scale it to unit "
                            "RMS radius first (as the authors' code), so beta and alpha are "
                            "unit-free; rigid and affine do not depend on it.")
    sigma2: float | None = Field(None, gt=0, description="Initial variance of the mixture in "
                                 "squared target units; by default the mean squared distance "
                                 "of all pairs per dimension.")
    max_iterations: int = Field(100, ge=1, le=10_000, description="Most EM iterations.")
    tolerance: float = Field(1e-5, ge=0, description="Stop when the negative log-likelihood "
                             "changes by less than this fraction in an iteration.")

    @model_validator(mode="after")
    def _consistent(self) -> CPDParams:
        """Dimensions and point counts are checked before the job runs (422 at once)."""
        same_dim(self.source, self.target, names=("source", "target"))
        check_sizes(self.source, self.target, self.model, self.low_rank)
        return self


registry.add(Process(
    id="registration.cpd",
    geometry=scenes.moved_source,
    title="Coherent point drift (rigid with scale, affine, nonrigid)",
    description="Registers source onto target without correspondences as a Gaussian mixture "
    "fitted by EM: soft correspondences from every pair, closed-form rigid (optionally "
    "scaled) or affine M-steps, or a smooth nonrigid displacement with the motion coherence "
    "regulariser (exact or low-rank kernel); a uniform component of weight w absorbs "
    "outliers. Memory bounded: the M×N posterior is summed in blocks, never stored, so "
    "20,000 × 20,000 points need about 260 MB. Any dimension.",
    function=cpd,
    params=CPDParams,
    result=CPDResult,
    reference="Myronenko, A., Song, X. (2010). Point set registration: coherent point drift. "
    "IEEE TPAMI 32(12), 2262–2275.",
    long=True,
    keywords=("cpd", "coherent point drift", "registration", "point cloud", "nonrigid",
              "gmm", "em"),
))


# --- registration.ransac ----------------------------------------------------------------------

from algorithms.registration.ransac import RANSACResult, check_inputs, ransac  # noqa: E402

# The ICP example's source turned by 120° about z (beyond any local method), shifted and
# listed backwards: RANSAC finds it from random samples, without a start.
_RC, _RS = float(np.cos(np.radians(120.0))), float(np.sin(np.radians(120.0)))
_RANSAC_TARGET = [[round(_RC * x - _RS * y + 1.0, 12), round(_RS * x + _RC * y - 0.5, 12), z]
                  for x, y, z in _SOURCE[::-1]]


class RANSACParams(Params):
    source: Points = Field(description="Points to move: an (n, 3) array (any (n, d), d ≥ 2, "
                           "with features=none).", examples=[_SOURCE])
    target: Points = Field(description="Points to register onto: an (m, d) array, same d, "
                           "any m, partial overlap allowed; no correspondence with source "
                           "needed and no start.", examples=[_RANSAC_TARGET])
    features: Literal["fpfh", "none"] = Field(
        "fpfh", description="fpfh: candidate pairs from matched Fast Point Feature Histograms "
        "(3-D); none: the seed's random sampling of point triples from each set, for small "
        "sets (tens of points).", examples=["none"])
    voxel_size: float | None = Field(
        None, gt=0, description="Down-sample both sets on a voxel grid of this step first; "
        "also the length scale of the default radii (one pass). When omitted with features: "
        "two passes at 1.5 and 3 × the source's point spacing, the best-fitting pose wins "
        "(without features: no down-sampling, the point spacing as the scale). Noisy scans "
        "need a voxel several times the noise.")
    feature_radius: float | None = Field(
        None, gt=0, description="FPFH neighbourhood radius; 5 × the length scale when "
        "omitted.")
    max_correspondence_distance: float | None = Field(
        None, gt=0, description="Inlier threshold of scoring, checking, ICP refinement and "
        "fitness; 1.5 × the length scale when omitted.", examples=[0.05])
    max_iterations: int = Field(100_000, ge=1, le=10_000_000, description="Most hypotheses "
                                "(samples) to draw.")
    confidence: float = Field(0.999, gt=0, le=1, description="Stop once an all-inlier sample "
                              "has been drawn with this probability (estimated from the best "
                              "inlier ratio); 1 never stops early.")
    mutual_filter: bool = Field(True, description="Keep only mutual nearest neighbours in "
                                "feature space (false: each point's nearest feature in the "
                                "other set, both ways).")
    refine: bool = Field(True, description="Refine the RANSAC transform with ICP "
                         "(point-to-plane in 3-D).")
    seed: int = Field(0, ge=0, description="Seeds the sampling; the same seed gives the same "
                      "result, bit for bit.")

    @model_validator(mode="after")
    def _consistent(self) -> RANSACParams:
        """Dimensions, point counts and collinear sets are refused before the job runs."""
        same_dim(self.source, self.target, names=("source", "target"))
        check_inputs(self.source, self.target, self.features)
        return self


registry.add(Process(
    id="registration.ransac",
    geometry=scenes.moved_source,
    title="RANSAC global registration (FPFH features or random triples) + ICP",
    description="Registers source onto target rigidly without a start: candidate pairs from "
    "mutually matched FPFH features (or, for small sets, the seed's random point triples), "
    "seeded random samples of 3 pairs checked by edge lengths, Kabsch fits scored by "
    "truncated squared error, confidence-based stopping. Without voxel_size: two "
    "down-sampling passes (1.5 and 3 × the point spacing), the best hypotheses re-scored and "
    "ICP-checked on the point sets, a robust (Tukey) ICP refinement against the full target; "
    "with voxel_size: Open3D's single pass, then point-to-plane ICP. The same seed gives the "
    "same result; converged=false with a reason instead of a silent identity.",
    function=ransac,
    params=RANSACParams,
    result=RANSACResult,
    reference="Fischler, M. A., Bolles, R. C. (1981). Random sample consensus. Comm. ACM "
    "24(6), 381–395; Rusu, R. B., Blodow, N., Beetz, M. (2009). Fast Point Feature Histograms "
    "(FPFH) for 3D registration. ICRA 2009.",
    long=True,
    keywords=("ransac", "global registration", "fpfh", "features", "registration",
              "point cloud", "no initial guess"),
))

# --- registration.multiway --------------------------------------------------------------------

from pydantic import ValidationInfo  # noqa: E402

from algorithms.core.errors import InvalidInputError  # noqa: E402
from algorithms.registration.multiway import (  # noqa: E402
    MultiwayResult,
    check_sets,
    check_transforms,
    multiway,
)
from service.catalog.inputs import points_schema  # noqa: E402

# Three views of an L-shaped set of 5 points, row j the same point in each: the second turned
# by 90° and shifted by (5, 0), the third twice as large and shifted by (0, 3).
_L = [[0, 0], [2, 0], [0, 1], [0, 2], [1, 0]]
_MULTIWAY_SETS = [_L, [[-y + 5, x] for x, y in _L], [[2 * x, 2 * y + 3] for x, y in _L]]


def _validate_point_sets(value: Any, info: ValidationInfo) -> list[np.ndarray]:
    """A list of (n_i, d) point arrays; each checked like `Points`, named `sets[i]`."""
    name = info.field_name or "sets"
    if isinstance(value, np.ndarray) and value.ndim == 3:
        value = list(value)
    if not isinstance(value, (list, tuple)):
        raise InvalidInputError(f"Expected `{name}` to be a list of (n, d) point arrays, got "
                                f"{type(value).__name__}.", field=name)
    max_points = (info.context or {}).get("max_points")
    return [as_points(v, name=f"{name}[{i}]", max_points=max_points)
            for i, v in enumerate(value)]


def _point_sets_json(value: list[np.ndarray]) -> list[Any]:
    return [a.tolist() for a in value]


PointSets = Annotated[
    list,
    PlainValidator(_validate_point_sets),
    PlainSerializer(_point_sets_json),
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


class MultiwayParams(Params):
    sets: PointSets = Field(description="At least two point sets of the same dimension d. "
                            "With correspondences: all of the same length, row j of each the "
                            "same point, any d. Without: 3-D, any sizes.",
                            examples=[_MULTIWAY_SETS])
    correspondences: bool = Field(
        True, description="true: rows correspond (generalised Procrustes); false: unknown "
        "correspondences (pairwise ICP + pose-graph optimisation on SE(3), 3-D).")
    model: Literal["rigid", "similarity"] = Field(
        "rigid", description="rigid: rotation + translation per set; similarity: also a "
        "uniform scale (generalised Procrustes only).")
    init: Transforms | None = Field(
        None, description="Optional start: one (d+1)×(d+1) transform per set into a common "
        "frame (rigid; similarity allowed for Procrustes).")
    max_iterations: int = Field(100, ge=1, le=10_000, description="Most Procrustes passes, "
                                "or Levenberg-Marquardt iterations per pose-graph round.")
    tolerance: float = Field(1e-9, ge=0, description="Stop when the objective decreases by "
                             "less than this fraction in an iteration.")
    max_correspondence_distance: float | None = Field(
        None, gt=0, description="Pose graph: pair distance bound of the fine pairwise ICP, "
        "of the edge information and of fitness. Default: 2 × the median point spacing.")
    metric: Literal["symmetric", "point_to_plane", "point_to_point"] = Field(
        "symmetric", description="Pose graph: the metric of the coarse-to-fine pairwise ICP "
        "stages, followed by a point_to_point polish (flat targets fall back to "
        "point_to_point).")
    neighbors: int | None = Field(
        None, ge=1, description="Pose graph: register each set with its next `neighbors` sets "
        "in order (consecutive pairs then count as trusted odometry). Default: every pair up "
        "to 10 sets, 2 beyond.")
    min_fitness: float = Field(0.3, ge=0, le=1, description="Pose graph: drop pairwise "
                               "edges of lower ICP fitness.")
    edge_prune_threshold: float = Field(
        0.25, ge=0, lt=1, description="Pose graph: prune loop closures whose line-process "
        "weight falls below this (Open3D's default).")
    preference_loop_closure: float = Field(
        1.0, gt=0, description="Pose graph: weight of loop closures in the line process "
        "(Open3D's option).")
    icp_max_iterations: int = Field(30, ge=1, le=10_000, description="Pose graph: most "
                                    "iterations per pairwise ICP stage.")

    @model_validator(mode="after")
    def _consistent(self) -> MultiwayParams:
        """Counts, lengths, dimensions, flat sets and init are checked before the job runs."""
        sets = check_sets(self.sets, correspondences=self.correspondences, model=self.model,
                          metric=self.metric)
        k, d = len(sets), sets[0].shape[1]
        if self.init is not None:
            check_transforms(self.init, k, d, self.model)
        if self.neighbors is not None and not self.correspondences and self.neighbors > k - 1:
            raise InvalidInputError(
                f"Expected `neighbors` to be at most {k - 1} (the number of other sets), got "
                f"{self.neighbors}.", field="neighbors")
        return self


registry.add(Process(
    id="registration.multiway",
    geometry=scenes.moved_sets,
    title="Multiway registration: generalised Procrustes or pose graph",
    description="Registers several point sets at once into the frame of set 0. With "
    "correspondences: generalised Procrustes analysis (rigid or similarity, any dimension), "
    "iterated to the mean shape. Without: pairwise ICP (coarse to fine, symmetric metric, "
    "point-to-point polish) "
    "with information matrices, then pose-graph optimisation on SE(3) by "
    "Levenberg-Marquardt with line processes for loop closures, low-fitness and "
    "inconsistent edges pruned (as Open3D's multiway registration).",
    function=multiway,
    params=MultiwayParams,
    result=MultiwayResult,
    reference="Gower, J. C. (1975). Generalized Procrustes analysis. Psychometrika 40(1), "
    "33–51; Choi, S., Zhou, Q.-Y., Koltun, V. (2015). Robust reconstruction of indoor "
    "scenes. CVPR 2015.",
    long=True,
    keywords=("multiway", "generalized procrustes", "gpa", "pose graph", "registration",
              "point cloud", "loop closure"),
))
