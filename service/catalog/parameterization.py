"""Catalog entries of the parameterization family (a disk-like mesh in, ``uv`` out, with the
flips and the angle and area distortion of the map)."""

from __future__ import annotations

from typing import Any

from algorithms.core.errors import InvalidInputError
from algorithms.core.params import Le
from algorithms.parameterization import (
    abf,
    arap,
    asap,
    bijective,
    check_disk,
    check_pins,
    conformal,
    harmonic,
    stretch_minimizing,
    tutte,
)
from service import scenes
from service.catalog.registry import Process, registry

# A 3 × 3-vertex sheet bent over a ridge: the smallest useful curved disk
_SHEET = {"vertices": [[0, 0, 0], [1, 0, 0.3], [2, 0, 0], [0, 1, 0], [1, 1, 0.5], [2, 1, 0],
                       [0, 2, 0], [1, 2, 0.3], [2, 2, 0]],
          "faces": [[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4], [3, 4, 7], [3, 7, 6],
                    [4, 5, 8], [4, 8, 7]]}
_EXAMPLES = {"mesh": _SHEET}
_REPORTS = " Reports flipped faces, angle distortion and area distortion."
_UV = ("uv", "texture coordinates")


def _disk(p: Any) -> None:
    """The mesh is a topological disk."""
    check_disk(p.mesh, name="mesh")


def _conformal(p: Any) -> None:
    """A disk; pins only with LSCM, and then vertices of the mesh in the plane."""
    _disk(p)
    if p.pins is None:
        return
    if p.method == "spectral":
        raise InvalidInputError(
            "Expected no `pins` with method='spectral' (its boundary is free and its "
            "similarity fixed by normalisation), got some; use method='lscm'.",
            field="pins")
    check_pins(p.pins, p.mesh)


registry.add(Process(
    id="parameterization.tutte",
    geometry=scenes.uv_mesh,
    title="Tutte embedding (circle or square boundary)",
    description="Pins the boundary loop to a circle or square and puts every interior vertex "
    "at a convex combination of its neighbours (uniform or mean value weights): one sparse "
    "solve, no flipped faces." + _REPORTS,
    function=tutte,
    examples=_EXAMPLES,
    check=_disk,
    fast_path=True,
    keywords=(*_UV, "tutte", "mean value", "flattening"),
))

registry.add(Process(
    id="parameterization.harmonic",
    geometry=scenes.uv_mesh,
    title="Harmonic parameterization",
    description="Boundary fixed to a circle or square, interior by the cotangent Laplace "
    "equation (minimal Dirichlet energy); as igl.harmonic." + _REPORTS,
    function=harmonic,
    examples=_EXAMPLES,
    check=_disk,
    fast_path=True,
    keywords=(*_UV, "harmonic", "cotangent", "flattening"),
))

registry.add(Process(
    id="parameterization.conformal",
    geometry=scenes.uv_mesh,
    title="Conformal parameterization (LSCM, spectral)",
    description="Minimises the conformal energy (Dirichlet minus area): LSCM with two or more "
    "pins (chosen automatically or given; as igl.lscm), or spectral conformal with a free "
    "boundary (generalized eigenproblem)." + _REPORTS,
    function=conformal,
    examples={**_EXAMPLES, "pins": {"indices": [0, 2], "positions": [[0, 0], [2, 0]]}},
    check=_conformal,
    keywords=(*_UV, "lscm", "conformal", "spectral", "free boundary"),
))

registry.add(Process(
    id="parameterization.arap",
    geometry=scenes.uv_mesh,
    title="As-rigid-as-possible parameterization (local/global)",
    description="Alternates per-face nearest rotations (closed form) and one prefactored "
    "cotangent-Laplacian solve with a per-half-edge right-hand side; free boundary, energy "
    "never increasing." + _REPORTS,
    function=arap,
    examples=_EXAMPLES,
    check=_disk,
    limits={"max_iterations": Le(100_000)},
    long=True,
    keywords=(*_UV, "arap", "isometric", "local/global"),
))

registry.add(Process(
    id="parameterization.asap",
    geometry=scenes.uv_mesh,
    title="As-similar-as-possible parameterization (local/global)",
    description="Alternates per-face nearest similarities and one prefactored solve, two "
    "boundary vertices held; converges to the LSCM map with those pins." + _REPORTS,
    function=asap,
    examples=_EXAMPLES,
    check=_disk,
    limits={"max_iterations": Le(100_000)},
    long=True,
    keywords=(*_UV, "asap", "conformal", "local/global"),
))

registry.add(Process(
    id="parameterization.stretch_minimizing",
    geometry=scenes.uv_mesh,
    title="Stretch-minimizing parameterization (fixed boundary)",
    description="Starts from the mean value Tutte map (boundary on a circle or square), then "
    "divides each weight w_ij by the stretch around vertex j and solves again while "
    "Sander et al.'s L2 stretch falls; keeps the best map. Positive weights and a convex "
    "boundary: no flipped faces. Reports the L2 and L-infinity stretch, flipped faces, "
    "angle distortion and area distortion.",
    function=stretch_minimizing,
    examples=_EXAMPLES,
    check=_disk,
    limits={"max_iterations": Le(10_000)},
    long=True,
    keywords=(*_UV, "stretch", "texture stretch", "yoshizawa", "sander"),
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
    examples=_EXAMPLES,
    check=_disk,
    limits={"max_iterations": Le(100_000)},
    long=True,
    keywords=(*_UV, "bijective", "injective", "symmetric dirichlet", "slim", "free boundary"),
))

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
    examples=_EXAMPLES,
    check=_disk,
    limits={"max_iterations": Le(10_000)},
    long=True,
    keywords=(*_UV, "abf", "abf++", "angle based flattening", "free boundary"),
))
