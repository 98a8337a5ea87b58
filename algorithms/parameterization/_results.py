"""The result types of the parameterization family."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from algorithms.core.mesh import Mesh
from algorithms.core.types import FloatArray, IntArray
from algorithms.parameterization._quality import quality

__all__ = ["ParameterizationResult", "LocalGlobalResult", "direct_result"]


@dataclass(frozen=True, eq=False)
class ParameterizationResult:
    """A map of a disk-like mesh to the plane, computed by one linear solve.

    Attributes
    ----------
    uv : (n, 2) float array
        The position of every vertex in the plane, row ``i`` for vertex ``i``.
    mesh : Mesh
        The input mesh (its faces index ``uv`` too).
    pinned : (p,) int array
        The vertices held at given positions: the boundary loop in its order (Tutte,
        harmonic), the two or more pins (LSCM), none (spectral conformal).
    energy : float
        The method's energy at the result: the spring energy
        Σ wᵢⱼ‖uᵢ − uⱼ‖² (Tutte, harmonic) or the conformal energy
        Σ_t A_t ‖J_t − S_t‖² (LSCM, spectral), S_t the nearest similarity.
    flipped_faces : int
        Faces whose orientation in the plane is opposite to that of the map as a whole.
    degenerate_faces : int
        Faces collapsed to (near) zero area in the plane.
    angle_distortion : float
        Area-weighted mean of σ₁/σ₂ − 1 over the faces (σ the singular values of each
        face's Jacobian): 0 for a conformal map.
    area_distortion : float
        Area-weighted mean of |log(σ₁σ₂ / s)|, s the ratio of total plane area to total
        surface area: 0 when every face's area is scaled alike.
    """

    uv: FloatArray
    mesh: Mesh
    pinned: IntArray
    energy: float
    flipped_faces: int
    degenerate_faces: int
    angle_distortion: float
    area_distortion: float


@dataclass(frozen=True, eq=False)
class LocalGlobalResult:
    """A map of a disk-like mesh to the plane from local/global iterations (ARAP, ASAP).

    Attributes
    ----------
    uv : (n, 2) float array
        The position of every vertex in the plane, row ``i`` for vertex ``i``.
    mesh : Mesh
        The input mesh (its faces index ``uv`` too).
    energy : (k + 1,) float array
        The energy Σ_t A_t ‖J_t − T_t‖² (T_t the best rotation, or similarity, of each
        face) of the initial map and after each iteration; never increasing.
    iterations : int
        The number of local/global iterations run.
    converged : bool
        True when the last iteration lowered the energy by at most ``tolerance`` times its
        value; False when ``max_iterations`` stopped the run first.
    flipped_faces : int
        Faces whose orientation in the plane is opposite to that of the map as a whole.
    degenerate_faces : int
        Faces collapsed to (near) zero area in the plane.
    angle_distortion : float
        Area-weighted mean of σ₁/σ₂ − 1 over the faces: 0 for a conformal map.
    area_distortion : float
        Area-weighted mean of |log(σ₁σ₂ / s)|, s the ratio of total plane area to total
        surface area: 0 when every face's area is scaled alike.
    """

    uv: FloatArray
    mesh: Mesh
    energy: FloatArray
    iterations: int
    converged: bool
    flipped_faces: int
    degenerate_faces: int
    angle_distortion: float
    area_distortion: float


def direct_result(mesh: Mesh, uv: FloatArray, pinned: IntArray, energy: float
                  ) -> ParameterizationResult:
    """A :class:`ParameterizationResult` with its quality figures computed."""
    q = quality(mesh.vertices, mesh.faces, uv)
    return ParameterizationResult(uv=uv, mesh=mesh, pinned=np.asarray(pinned, dtype=np.int64),
                                  energy=float(energy), **q.fields())
