"""Mesh deformation: move some vertices (the handles) to targets and let the rest of the
mesh follow a model of how shapes bend: kept Laplacian coordinates (``laplacian``,
``laplacian_editing``), rigidity (``arap``), smoothness (``harmonic``, ``biharmonic``),
per-face scale (``isotropic_scaling``) or per-face transforms taken from another mesh
(``deformation_transfer``). Every method takes a mesh and handles and returns the deformed
mesh with its energy per iteration and the handle residual."""

from algorithms.deformation._common import check_handles
from algorithms.deformation.arap import ArapResult, ArapSolver, arap
from algorithms.deformation.biharmonic import BiharmonicResult, biharmonic
from algorithms.deformation.deformation_transfer import (
    DeformationTransferResult,
    check_deformation_transfer,
    deformation_transfer,
)
from algorithms.deformation.harmonic import HarmonicResult, harmonic
from algorithms.deformation.isotropic_scaling import IsotropicScalingResult, isotropic_scaling
from algorithms.deformation.laplacian import LaplacianResult, laplacian
from algorithms.deformation.laplacian_editing import LaplacianEditingResult, laplacian_editing

__all__ = [
    "check_handles",
    "ArapResult",
    "ArapSolver",
    "arap",
    "BiharmonicResult",
    "biharmonic",
    "DeformationTransferResult",
    "deformation_transfer",
    "check_deformation_transfer",
    "HarmonicResult",
    "harmonic",
    "IsotropicScalingResult",
    "isotropic_scaling",
    "LaplacianResult",
    "laplacian",
    "LaplacianEditingResult",
    "laplacian_editing",
]
