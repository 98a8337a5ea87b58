"""Catalog entries of the deformation family (a mesh and handles in, the deformed mesh out)."""

from __future__ import annotations

from typing import Any

from algorithms.core.errors import InvalidInputError
from algorithms.core.params import Le
from algorithms.deformation import (
    arap,
    biharmonic,
    check_handles,
    deformation_transfer,
    harmonic,
    isotropic_scaling,
    laplacian,
    laplacian_editing,
)
from service import scenes
from service.catalog.registry import Process, registry

# A 2 × 1 strip of unit squares in the plane z = 0 (six vertices, four triangles) ...
_STRIP_VERTICES = [[0, 0, 0], [1, 0, 0], [2, 0, 0], [0, 1, 0], [1, 1, 0], [2, 1, 0]]
_STRIP = {"vertices": _STRIP_VERTICES, "faces": [[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4]]}
# ... its left end held, its right end lifted by 1
_LIFT = {"indices": [0, 3, 2, 5], "positions": [[0, 0, 0], [0, 1, 0], [2, 0, 1], [2, 1, 1]]}
# the strip folded up along x = 1 (a quarter turn of its right half)
_FOLDED = [[0, 0, 0], [1, 0, 0], [1, 0, 1], [0, 1, 0], [1, 1, 0], [1, 1, 1]]
_TARGET_MESH = {"vertices": [[0, 0, 0], [2, 0, 0], [4, 0, 0], [0, 1, 0], [2, 1, 0],
                             [4, 1, 0]],
                "faces": _STRIP["faces"]}
_EXAMPLES = {"mesh": _STRIP, "handles": _LIFT}


def _handles_fit_the_mesh(p: Any) -> None:
    """The handles index distinct vertices of the mesh, one at least in every component."""
    check_handles(p.mesh, p.handles, name="handles")


def _same_connectivity(p: Any) -> None:
    """The handles fit the mesh; source and source_deformed have one row per mesh vertex."""
    _handles_fit_the_mesh(p)
    n, d = p.mesh.vertices.shape
    for name in ("source", "source_deformed"):
        shape = getattr(p, name).shape
        if shape != (n, d):
            raise InvalidInputError(f"Expected `{name}` to have the shape of `mesh.vertices` "
                                    f"({n}, {d}), got {shape}.", field=name)


registry.add(Process(
    id="deformation.laplacian",
    geometry=scenes.deformed_mesh,
    title="Laplacian-preserving deformation",
    description="Moves the handles and every other vertex so that the weighted edge vectors "
    "change least: L_ff x' = (L x)_f − L_fp c, one factored solve for all coordinates.",
    function=laplacian,
    examples=_EXAMPLES,
    check=_handles_fit_the_mesh,
    keywords=("laplacian coordinates", "mesh editing", "handles", "linear"),
))

registry.add(Process(
    id="deformation.laplacian_editing",
    geometry=scenes.deformed_mesh,
    title="Laplacian surface editing (linearised per-vertex similarities)",
    description="Laplacian coordinates that rotate and scale with the surface: "
    "min Σ‖T_i(x') δ_i − L(x')_i‖² with each T_i the linearised similarity fitted to the "
    "vertex's one-ring, handles fixed; one sparse least-squares solve.",
    function=laplacian_editing,
    examples=_EXAMPLES,
    check=_handles_fit_the_mesh,
    fast_path=True,
    keywords=("laplacian coordinates", "mesh editing", "handles", "similarity"),
))

registry.add(Process(
    id="deformation.arap",
    geometry=scenes.deformed_mesh,
    title="As-rigid-as-possible deformation (local/global)",
    description="Alternates per-vertex best rotations (batched, proper) and one prefactored "
    "cotangent-Laplacian solve; handles met exactly, energy never increasing; spokes or "
    "spokes-and-rims energy, optional per-vertex scale.",
    function=arap,
    examples=_EXAMPLES,
    check=_handles_fit_the_mesh,
    limits={"max_iterations": Le(10_000)},
    long=True,
    keywords=("arap", "rigid", "mesh editing", "handles", "local/global"),
))

registry.add(Process(
    id="deformation.harmonic",
    geometry=scenes.deformed_mesh,
    title="Harmonic deformation",
    description="Spreads the handle displacements by the Laplace equation (cotangent "
    "Laplacian): L_ff u_f = −L_fp u_p, x' = x + u; as igl.harmonic with k = 1.",
    function=harmonic,
    examples=_EXAMPLES,
    check=_handles_fit_the_mesh,
    fast_path=True,
    keywords=("harmonic", "membrane", "handles", "linear"),
))

registry.add(Process(
    id="deformation.biharmonic",
    geometry=scenes.deformed_mesh,
    title="Biharmonic deformation",
    description="Spreads the handle displacements by the bi-Laplace equation L M⁻¹ L u = 0 "
    "(cotangent Laplacian, Voronoi mass), smooth at the handles; as igl.harmonic with "
    "k = 2 (or 3).",
    function=biharmonic,
    examples=_EXAMPLES,
    check=_handles_fit_the_mesh,
    fast_path=True,
    keywords=("biharmonic", "thin plate", "handles", "linear"),
))

registry.add(Process(
    id="deformation.isotropic_scaling",
    geometry=scenes.deformed_mesh,
    title="Isotropic scaling deformation (scale-and-stretch)",
    description="Each face may only scale, edges keep their directions and adapt their "
    "lengths: block coordinate descent between closed-form per-face scales and one "
    "prefactored Laplacian solve, length ratios from the previous iterate (a correction of "
    "the paper, whose fixed ratios cannot be split off from the positions they depend on).",
    function=isotropic_scaling,
    examples=_EXAMPLES,
    check=_handles_fit_the_mesh,
    limits={"max_iterations": Le(100_000)},
    long=True,
    keywords=("scale", "stretch", "resizing", "handles", "local/global"),
))

registry.add(Process(
    id="deformation.deformation_transfer",
    geometry=scenes.deformed_mesh,
    title="Deformation transfer (same connectivity)",
    description="Gives the target mesh the per-face deformation gradients of a source mesh "
    "that deforms from source to source_deformed (same faces): min Σ‖T_c − Q_c‖²_F with "
    "shared vertices (and, in 3-D, a free fourth vertex per face); one factored solve.",
    function=deformation_transfer,
    examples={"mesh": _TARGET_MESH, "handles": {"indices": [0], "positions": [[0, 0, 0]]},
              "source": _STRIP_VERTICES, "source_deformed": _FOLDED},
    check=_same_connectivity,
    fast_path=True,
    keywords=("deformation transfer", "deformation gradient", "retargeting", "handles"),
))
