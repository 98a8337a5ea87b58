"""Catalog entries of the deformation family (a mesh and handles in, the deformed mesh out)."""

from __future__ import annotations

from typing import Literal

from pydantic import Field, model_validator

from algorithms.core.errors import InvalidInputError
from algorithms.deformation import (
    ArapResult,
    BiharmonicResult,
    DeformationTransferResult,
    HarmonicResult,
    IsotropicScalingResult,
    LaplacianEditingResult,
    LaplacianResult,
    arap,
    biharmonic,
    check_handles,
    deformation_transfer,
    harmonic,
    isotropic_scaling,
    laplacian,
    laplacian_editing,
)
from service.catalog.base import Params
from service.catalog.inputs import HandlesInput, MeshInput, Points
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

_TRIANGLES = ("a triangle mesh {vertices: (n, 2) or (n, 3), faces: (m, 3) 0-based indices}, "
              "no zero-area faces. Vertices no face uses stay where they are.")
_MESH = "The rest shape: " + _TRIANGLES
_HANDLES = ("The vertices to move and their targets: {indices: (p,) distinct vertex indices, "
            "positions: (p, d)}; at least one handle in every connected component.")
_ITERATIONS = "Upper bound on iterations."


class _DeformParams(Params):
    mesh: MeshInput = Field(description=_MESH, examples=[_STRIP])
    handles: HandlesInput = Field(description=_HANDLES, examples=[_LIFT])

    @model_validator(mode="after")
    def _handles_fit_the_mesh(self) -> _DeformParams:
        check_handles(self.mesh, self.handles, name="handles")
        return self


class LaplacianParams(_DeformParams):
    weights: Literal["cotangent", "uniform", "tangent"] = Field(
        "cotangent",
        description="Edge weights of the Laplacian: cotangent (Dirichlet energy; may be "
        "negative on obtuse triangles), uniform (graph Laplacian), tangent (incentre "
        "weights, never negative).")


class LaplacianEditingParams(_DeformParams):
    handles: HandlesInput = Field(
        description=_HANDLES + " Per component, handles whose rest positions span a plane "
        "(3-D: three not on a line) or a line (2-D: two distinct).", examples=[_LIFT])
    weights: Literal["uniform", "cotangent"] = Field(
        "uniform",
        description="The Laplacian (row-normalised): uniform as in the paper, or cotangent.")


class ArapParams(_DeformParams):
    energy: Literal["spokes_and_rims", "spokes"] = Field(
        "spokes_and_rims",
        description="The edges each vertex's rotation answers for: its spokes (Sorkine & "
        "Alexa) or also the rims of its faces (Chao et al.; libigl's default).")
    similarity: bool = Field(False, description="Fit a non-negative scale per vertex too "
                             "(as-similar-as-possible).")
    max_iterations: int = Field(30, ge=1, le=10_000, description=_ITERATIONS)
    tolerance: float = Field(1e-5, ge=0, description="Stop when an iteration lowers the "
                             "energy by at most this fraction; 0 runs all max_iterations.")


class HarmonicParams(_DeformParams):
    pass


class BiharmonicParams(_DeformParams):
    order: int = Field(2, ge=2, le=3, description="The power k of the Laplacian: 2 "
                       "(biharmonic) or 3 (triharmonic).")


class IsotropicScalingParams(_DeformParams):
    regularization: float = Field(1.0, ge=0, description="Weight of the edge-length term "
                                  "(keeps edge directions); 0 leaves only per-face scales.")
    max_iterations: int = Field(200, ge=1, le=100_000, description=_ITERATIONS)
    tolerance: float = Field(1e-6, ge=0, description="Stop when no vertex moved more than "
                             "this fraction of the bounding-box diagonal in an iteration.")


class DeformationTransferParams(_DeformParams):
    mesh: MeshInput = Field(description="The target in its rest shape: " + _TRIANGLES,
                            examples=[_TARGET_MESH])
    handles: HandlesInput = Field(description=_HANDLES + " The per-face transforms leave "
                                  "a translation free: one handle per component fixes it.",
                                  examples=[{"indices": [0], "positions": [[0, 0, 0]]}])
    source: Points = Field(description="The source's rest vertices (n, d), on the faces of "
                           "mesh: same connectivity, vertex i corresponds to vertex i.",
                           examples=[_STRIP_VERTICES])
    source_deformed: Points = Field(description="The source's deformed vertices (n, d), on "
                                    "the faces of mesh.", examples=[_FOLDED])

    @model_validator(mode="after")
    def _same_connectivity(self) -> DeformationTransferParams:
        n, d = self.mesh.vertices.shape
        for name in ("source", "source_deformed"):
            arr = getattr(self, name)
            if arr.shape != (n, d):
                raise InvalidInputError(
                    f"Expected `{name}` to have the shape of `mesh.vertices` ({n}, {d}), got "
                    f"{arr.shape}.", field=name)
        return self


registry.add(Process(
    id="deformation.laplacian",
    geometry=scenes.deformed_mesh,
    title="Laplacian-preserving deformation",
    description="Moves the handles and every other vertex so that the weighted edge vectors "
    "change least: L_ff x' = (L x)_f − L_fp c, one factored solve for all coordinates.",
    function=laplacian,
    params=LaplacianParams,
    result=LaplacianResult,
    reference="Lipman, Y., Sorkine, O., Cohen-Or, D., Levin, D., Rössl, C., Seidel, H.-P. "
    "(2004). Differential coordinates for interactive mesh editing. SMI 2004, 181–190.",
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
    params=LaplacianEditingParams,
    result=LaplacianEditingResult,
    reference="Sorkine, O., Cohen-Or, D., Lipman, Y., Alexa, M., Rössl, C., Seidel, H.-P. "
    "(2004). Laplacian surface editing. SGP 2004, 175–184.",
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
    params=ArapParams,
    result=ArapResult,
    reference="Sorkine, O., Alexa, M. (2007). As-rigid-as-possible surface modeling. "
    "SGP 2007, 109–116.",
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
    params=HarmonicParams,
    result=HarmonicResult,
    reference="Botsch, M., Sorkine, O. (2008). On linear variational surface deformation "
    "methods. IEEE TVCG 14(1), 213–230.",
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
    params=BiharmonicParams,
    result=BiharmonicResult,
    reference="Botsch, M., Kobbelt, L. (2004). An intuitive framework for real-time freeform "
    "modeling. ACM TOG 23(3), 630–634.",
    fast_path=True,
    keywords=("biharmonic", "thin plate", "handles", "linear"),
))

registry.add(Process(
    id="deformation.isotropic_scaling",
    geometry=scenes.deformed_mesh,
    title="Isotropic scaling deformation (scale-and-stretch)",
    description="Each face may only scale, edges keep their directions and adapt their "
    "lengths: block coordinate descent between closed-form per-face scales and one "
    "prefactored Laplacian solve, length ratios from the previous iterate (the seed's "
    "correction of the paper).",
    function=isotropic_scaling,
    params=IsotropicScalingParams,
    result=IsotropicScalingResult,
    reference="Wang, Y.-S., Tai, C.-L., Sorkine, O., Lee, T.-Y. (2008). Optimized "
    "scale-and-stretch for image resizing. ACM TOG 27(5), 118.",
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
    params=DeformationTransferParams,
    result=DeformationTransferResult,
    reference="Sumner, R. W., Popović, J. (2004). Deformation transfer for triangle meshes. "
    "ACM TOG 23(3), 399–405.",
    fast_path=True,
    keywords=("deformation transfer", "deformation gradient", "retargeting", "handles"),
))
