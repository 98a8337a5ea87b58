"""Catalog entries of the parameterization family (a disk-like mesh in, ``uv`` out, with the
flips and the angle and area distortion of the map)."""

from __future__ import annotations

from typing import Literal

from pydantic import Field, model_validator

from algorithms.core.errors import InvalidInputError
from algorithms.parameterization import (
    LocalGlobalResult,
    ParameterizationResult,
    arap,
    asap,
    check_disk,
    conformal,
    harmonic,
    tutte,
)
from algorithms.parameterization.conformal import _check_pins
from service.catalog.base import Params
from service.catalog.inputs import HandlesInput, MeshInput
from service import scenes
from service.catalog.registry import Process, registry

# A 3 × 3-vertex sheet bent over a ridge: the smallest useful curved disk
_SHEET = {"vertices": [[0, 0, 0], [1, 0, 0.3], [2, 0, 0], [0, 1, 0], [1, 1, 0.5], [2, 1, 0],
                       [0, 2, 0], [1, 2, 0.3], [2, 2, 0]],
          "faces": [[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4], [3, 4, 7], [3, 7, 6],
                    [4, 5, 8], [4, 8, 7]]}

_MESH = ("A topological disk {vertices: (n, 3) or (n, 2), faces: (m, 3) 0-based indices}: "
         "connected, manifold, consistently oriented, exactly one boundary loop, every vertex "
         "in a face, no zero-area faces.")
_BOUNDARY = ("The convex polygon the boundary loop is pinned to, spaced by boundary edge "
             "length: the unit circle, or the square [-1, 1]² with its corners at the "
             "boundary's sharpest vertices.")
_ITERATIONS = "Upper bound on local/global iterations."
_TOLERANCE = ("Stop when an iteration lowers the energy by at most this fraction; 0 runs all "
              "max_iterations.")


class _DiskParams(Params):
    mesh: MeshInput = Field(description=_MESH, examples=[_SHEET])

    @model_validator(mode="after")
    def _is_a_disk(self) -> _DiskParams:
        check_disk(self.mesh, name="mesh")
        return self


class TutteParams(_DiskParams):
    boundary: Literal["circle", "square"] = Field("circle", description=_BOUNDARY)
    weighting: Literal["uniform", "mean_value"] = Field(
        "uniform", description="Interior weights: uniform (Tutte's barycentric map) or "
        "Floater's mean value weights (closer to conformal); both positive, so no face flips.")


class HarmonicParams(_DiskParams):
    boundary: Literal["circle", "square"] = Field("circle", description=_BOUNDARY)


class ConformalParams(_DiskParams):
    method: Literal["lscm", "spectral"] = Field(
        "lscm", description="lscm: least-squares conformal map with pinned vertices; "
        "spectral: free boundary, the first non-trivial generalized eigenvector (no pins).")
    pins: HandlesInput | None = Field(
        None, description="LSCM only: at least two vertices and their positions in the plane "
        "{indices: (p,), positions: (p, 2)}. Default: the two boundary vertices farthest apart, "
        "at (0, 0) and (d, 0).",
        examples=[{"indices": [0, 2], "positions": [[0, 0], [2, 0]]}])

    @model_validator(mode="after")
    def _pins_fit(self) -> ConformalParams:
        if self.pins is not None:
            if self.method == "spectral":
                raise InvalidInputError(
                    "Expected no `pins` with method='spectral' (its boundary is free and its "
                    "similarity fixed by normalisation), got some; use method='lscm'.",
                    field="pins")
            _check_pins(self.pins, self.mesh)
        return self


class _LocalGlobalParams(_DiskParams):
    max_iterations: int = Field(100, ge=1, le=100_000, description=_ITERATIONS)
    tolerance: float = Field(1e-6, ge=0, description=_TOLERANCE)


class ArapParams(_LocalGlobalParams):
    init: Literal["lscm", "harmonic"] = Field(
        "lscm", description="The starting map (scaled to the surface's area): LSCM or the "
        "harmonic map onto the circle.")


class AsapParams(_LocalGlobalParams):
    init: Literal["harmonic", "lscm"] = Field(
        "harmonic", description="The starting map (scaled to the surface's area): the "
        "harmonic map onto the circle, or LSCM (already the ASAP minimum: stops at once).")


_REPORTS = " Reports flipped faces, angle distortion and area distortion."

registry.add(Process(
    id="parameterization.tutte",
    geometry=scenes.uv_mesh,
    title="Tutte embedding (circle or square boundary)",
    description="Pins the boundary loop to a circle or square and puts every interior vertex "
    "at a convex combination of its neighbours (uniform or mean value weights): one sparse "
    "solve, no flipped faces." + _REPORTS,
    function=tutte,
    params=TutteParams,
    result=ParameterizationResult,
    reference="Tutte, W. T. (1963). How to draw a graph. Proc. London Math. Soc. 13, 743–767; "
    "Floater, M. S. (2003). Mean value coordinates. CAGD 20(1), 19–27.",
    fast_path=True,
    keywords=("uv", "texture coordinates", "tutte", "mean value", "flattening"),
))

registry.add(Process(
    id="parameterization.harmonic",
    geometry=scenes.uv_mesh,
    title="Harmonic parameterization",
    description="Boundary fixed to a circle or square, interior by the cotangent Laplace "
    "equation (minimal Dirichlet energy); as igl.harmonic." + _REPORTS,
    function=harmonic,
    params=HarmonicParams,
    result=ParameterizationResult,
    reference="Eck, M., DeRose, T., Duchamp, T., Hoppe, H., Lounsbery, M., Stuetzle, W. "
    "(1995). Multiresolution analysis of arbitrary meshes. SIGGRAPH 1995, 173–182.",
    fast_path=True,
    keywords=("uv", "texture coordinates", "harmonic", "cotangent", "flattening"),
))

registry.add(Process(
    id="parameterization.conformal",
    geometry=scenes.uv_mesh,
    title="Conformal parameterization (LSCM, spectral)",
    description="Minimises the conformal energy (Dirichlet minus area): LSCM with two or more "
    "pins (chosen automatically or given; as igl.lscm), or spectral conformal with a free "
    "boundary (generalized eigenproblem)." + _REPORTS,
    function=conformal,
    params=ConformalParams,
    result=ParameterizationResult,
    reference="Lévy, B., Petitjean, S., Ray, N., Maillot, J. (2002). Least squares conformal "
    "maps for automatic texture atlas generation. SIGGRAPH 2002; Mullen, P., Tong, Y., "
    "Alliez, P., Desbrun, M. (2008). Spectral conformal parameterization. SGP 2008.",
    keywords=("uv", "texture coordinates", "lscm", "conformal", "spectral", "free boundary"),
))

registry.add(Process(
    id="parameterization.arap",
    geometry=scenes.uv_mesh,
    title="As-rigid-as-possible parameterization (local/global)",
    description="Alternates per-face nearest rotations (closed form) and one prefactored "
    "cotangent-Laplacian solve with a per-half-edge right-hand side; free boundary, energy "
    "never increasing." + _REPORTS,
    function=arap,
    params=ArapParams,
    result=LocalGlobalResult,
    reference="Liu, L., Zhang, L., Xu, Y., Gotsman, C., Gortler, S. J. (2008). A local/global "
    "approach to mesh parameterization. Computer Graphics Forum 27(5), 1495–1504.",
    long=True,
    keywords=("uv", "texture coordinates", "arap", "isometric", "local/global"),
))

registry.add(Process(
    id="parameterization.asap",
    geometry=scenes.uv_mesh,
    title="As-similar-as-possible parameterization (local/global)",
    description="Alternates per-face nearest similarities and one prefactored solve, two "
    "boundary vertices held; converges to the LSCM map with those pins." + _REPORTS,
    function=asap,
    params=AsapParams,
    result=LocalGlobalResult,
    reference="Liu, L., Zhang, L., Xu, Y., Gotsman, C., Gortler, S. J. (2008). A local/global "
    "approach to mesh parameterization. Computer Graphics Forum 27(5), 1495–1504.",
    long=True,
    keywords=("uv", "texture coordinates", "asap", "conformal", "local/global"),
))

# Stretch minimizing (Yoshizawa et al.) and bijective (symmetric Dirichlet + barrier) ------
from algorithms.parameterization import (  # noqa: E402
    BijectiveResult,
    StretchResult,
    bijective,
    stretch_minimizing,
)


class StretchParams(_DiskParams):
    boundary: Literal["circle", "square"] = Field("circle", description=_BOUNDARY)
    power: float = Field(1.0, gt=0, le=4, description="Exponent p of the reweighting "
                         "w_ij <- w_ij / sigma_j^p (sigma_j the stretch around vertex j); "
                         "1 as Yoshizawa et al.")
    max_iterations: int = Field(20, ge=1, le=10_000, description="Upper bound on "
                                "reweightings.")
    tolerance: float = Field(1e-4, ge=0, description="Stop when a reweighting lowers the L2 "
                             "stretch by at most this fraction (or raises it).")


class BijectiveParams(_DiskParams):
    max_iterations: int = Field(100, ge=1, le=100_000, description="Upper bound on SLIM "
                                "iterations.")
    tolerance: float = Field(1e-6, ge=0, description=_TOLERANCE)


registry.add(Process(
    id="parameterization.stretch_minimizing",
    geometry=scenes.uv_mesh,
    title="Stretch-minimizing parameterization (fixed boundary)",
    description="Starts from the mean value Tutte map (boundary on a circle or square), then "
    "divides each weight w_ij by the stretch around vertex j and solves again while "
    "Sander et al.'s L2 stretch falls; keeps the best map. Positive weights and a convex "
    "boundary: no flipped faces. Reports the L2 and L-infinity stretch too." + _REPORTS,
    function=stretch_minimizing,
    params=StretchParams,
    result=StretchResult,
    reference="Yoshizawa, S., Belyaev, A., Seidel, H.-P. (2004). A fast and simple "
    "stretch-minimizing mesh parameterization. Shape Modeling International 2004, 200–208; "
    "Sander, P. V., Snyder, J., Gortler, S. J., Hoppe, H. (2001). Texture mapping "
    "progressive meshes. SIGGRAPH 2001.",
    long=True,
    keywords=("uv", "texture coordinates", "stretch", "texture stretch", "yoshizawa",
              "sander"),
))

registry.add(Process(
    id="parameterization.bijective",
    geometry=scenes.uv_mesh,
    title="Bijective parameterization (symmetric Dirichlet, free boundary)",
    description="Minimises the symmetric Dirichlet energy plus a boundary barrier from a "
    "flip-free Tutte start by SLIM steps; the line search never lets a face flip or the "
    "boundary cross itself (quadratic step bounds), so the map is bijective by "
    "construction." + _REPORTS,
    function=bijective,
    params=BijectiveParams,
    result=BijectiveResult,
    reference="Smith, J., Schaefer, S. (2015). Bijective parameterization with free "
    "boundaries. ACM Trans. Graph. 34(4); Rabinovich, M., Poranne, R., Panozzo, D., "
    "Sorkine-Hornung, O. (2017). Scalable locally injective mappings. ACM Trans. Graph. "
    "36(2).",
    long=True,
    keywords=("uv", "texture coordinates", "bijective", "injective", "symmetric dirichlet",
              "slim", "free boundary"),
))

# ABF++ (angle-based flattening) --------------------------------------------------------
from algorithms.parameterization import AbfResult, abf  # noqa: E402


class AbfParams(_DiskParams):
    max_iterations: int = Field(20, ge=1, le=10_000, description="Upper bound on Newton "
                                "iterations.")
    tolerance: float = Field(1e-8, ge=0, description="Stop when the norm of the gradient of "
                             "the Lagrangian (angle optimality and constraint residuals, in "
                             "radians) is at most this; 0 runs all max_iterations.")


registry.add(Process(
    id="parameterization.abf",
    geometry=scenes.uv_mesh,
    title="Angle-based flattening (ABF++)",
    description="Solves for the flat angles nearest the surface's (relative error, weights "
    "1/β²) under the triangle, planarity and wheel constraints by Newton's method on a "
    "sparse reduced system (angle and triangle multipliers eliminated, one sparse Cholesky "
    "per iteration), then lays the mesh out from the angles by a least-squares conformal "
    "step with two boundary vertices pinned; free boundary." + _REPORTS,
    function=abf,
    params=AbfParams,
    result=AbfResult,
    reference="Sheffer, A., Lévy, B., Mogilnitsky, M., Bogomyakov, A. (2005). ABF++: fast and "
    "robust angle based flattening. ACM Transactions on Graphics 24(2), 311–330.",
    long=True,
    keywords=("uv", "texture coordinates", "abf", "abf++", "angle based flattening",
              "free boundary"),
))
