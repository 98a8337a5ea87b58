r"""The local/global solver shared by the ARAP and ASAP parameterizations (Liu et al. 2008).

Energy, with one 2×2 transform :math:`T_t` per face (a rotation for ARAP, a similarity
:math:`\begin{pmatrix} p & -s \\ s & p \end{pmatrix}` for ASAP):

.. math::

    E(u, T) = \sum_t \sum_{k=0}^{2} \tfrac12\cot\theta_t^k\,
    \lVert (u_{a} - u_{b}) - T_t\, e_t^k \rVert^2 = \sum_t A_t \lVert J_t(u) - T_t \rVert_F^2,

:math:`e_t^k` the edge opposite corner :math:`k` of face :math:`t` (from corner :math:`a`
to :math:`b`) in an isometric frame of the face, :math:`J_t` the face's Jacobian.

* Local step: :math:`T_t` nearest :math:`J_t` in Frobenius norm, in closed form: with
  :math:`p = (J_{00} + J_{11})/2` and :math:`s = (J_{10} - J_{01})/2`, the similarity
  :math:`(p, s)` or the rotation :math:`(p, s)/\lVert(p, s)\rVert` (always proper, so no
  reflection fix is needed in 2-D).
* Global step: the per-half-edge least squares over :math:`u` with every :math:`T_t`
  fixed, :math:`L u = \sum_t \sum_k \tfrac12\cot\theta_t^k\, D_k^\mathsf{T} T_t e_t^k`,
  :math:`L` the cotangent Laplacian, factored once; the right-hand side is one sparse
  product :math:`C\,\operatorname{vec}(T)`. Pinned vertices fix what the energy leaves
  free.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from algorithms.core.errors import ConvergenceWarning, warn
from algorithms.core.laplacian import cotangent_entries, cotangent_laplacian
from algorithms.core.linsolve import PinnedSystem
from algorithms.core.mesh import Mesh, face_areas, signed_areas
from algorithms.core.progress import Progress, as_progress
from algorithms.core.types import FloatArray, IntArray
from algorithms.parameterization._disk import Disk, convex_boundary, pinned_map
from algorithms.parameterization._quality import face_frames, jacobians, quality
from algorithms.parameterization._results import LocalGlobalResult
from algorithms.parameterization.conformal import lscm_uv

__all__ = ["LocalGlobalSolver", "fit_transforms", "local_global_energy", "initial_map"]


def fit_transforms(J: FloatArray, similarity: bool) -> FloatArray:
    """The rotation (or similarity) nearest each Jacobian, ``(m, 2, 2)``."""
    p = 0.5 * (J[:, 0, 0] + J[:, 1, 1])
    s = 0.5 * (J[:, 1, 0] - J[:, 0, 1])
    if not similarity:
        r = np.hypot(p, s)
        zero = r == 0
        r[zero] = 1.0
        p = np.where(zero, 1.0, p) / r
        s = s / r
    out = np.empty_like(J)
    out[:, 0, 0] = p
    out[:, 0, 1] = -s
    out[:, 1, 0] = s
    out[:, 1, 1] = p
    return out


def local_global_energy(area: FloatArray, J: FloatArray, T: FloatArray) -> float:
    """:math:`\\sum_t A_t \\lVert J_t - T_t \\rVert_F^2`."""
    d = J - T
    return float(np.einsum("t,tij,tij->", area, d, d))


class LocalGlobalSolver:
    """Factor the global step once for a mesh and a set of pinned vertices.

    Parameters
    ----------
    mesh : Mesh
        A checked disk.
    pinned : (p,) int array
        Vertices held where the initial map puts them (one for ARAP: translation; two
        for ASAP: translation, rotation and scale).
    similarity : bool
        ASAP (similarities) instead of ARAP (rotations).
    solves : int
        The most global steps :meth:`solve` will run (``max_iterations``): the backend is
        chosen for that many solves (:class:`~algorithms.core.linsolve.Factor`).
    laplacian : (n, n) csr_array, optional
        The mesh's :func:`~algorithms.core.laplacian.cotangent_laplacian`, when the caller
        has it already (made here otherwise).
    """

    def __init__(self, mesh: Mesh, pinned: IntArray, *, similarity: bool,
                 solves: int, laplacian: sp.csr_array | None = None) -> None:
        v, f = mesh.vertices, mesh.faces
        n, m = mesh.n_vertices, mesh.n_faces
        self.mesh, self.similarity = mesh, similarity
        self.pinned = np.asarray(pinned, dtype=np.int64)
        self.frames = face_frames(v, f)
        self.area = 0.5 * self.frames[:, 1, 0] * self.frames[:, 2, 1]
        x = self.frames
        e = x[:, [1, 2, 0]] - x[:, [2, 0, 1]]                   # e_k = x_{k+1} - x_{k+2}
        ce = cotangent_entries(v, f)[:, :, None] * e             # (m, 3, 2)
        # Edge k runs from f_{k+1} to f_{k+2}: it adds c_k to row f_{k+1} and -c_k to row
        # f_{k+2} of face t's two columns 2t, 2t+1. So the column holds each corner once,
        # c_{j-1} - c_{j+1} in row f_j: built by columns (3 entries each), then as rows.
        vals = ce[:, [2, 0, 1]] - ce[:, [1, 2, 0]]               # (m, 3, 2): corner j
        self._C = sp.csc_array(
            (vals.transpose(0, 2, 1).ravel(), np.repeat(f, 2, axis=0).ravel(),
             np.arange(0, 6 * m + 1, 3)), shape=(n, 2 * m)).tocsr()
        lap = cotangent_laplacian(v, f) if laplacian is None else laplacian
        self.system = PinnedSystem(lap, self.pinned, name="mesh", solves=solves,
                                   check_components=False)

    def _global(self, T: FloatArray, values: FloatArray) -> FloatArray:
        rhs = self._C @ T.transpose(0, 2, 1).reshape(-1, 2)
        return self.system.solve(values, rhs)

    def solve(self, initial: FloatArray, *, max_iterations: int, tolerance: float,
              progress: Progress | None = None, name: str = "ARAP") -> LocalGlobalResult:
        """Iterate from ``initial`` (``(n, 2)``; the pinned vertices stay there)."""
        report = as_progress(progress)
        f = self.mesh.faces
        uv = np.array(initial, dtype=np.float64)
        values = uv[self.pinned]
        J = jacobians(self.frames, f, uv)
        T = fit_transforms(J, self.similarity)
        energies = [local_global_energy(self.area, J, T)]
        floor = 1e-15 * float(self.area.sum())
        converged = False
        for it in range(max_iterations):
            uv = self._global(T, values)
            J = jacobians(self.frames, f, uv)
            T = fit_transforms(J, self.similarity)
            e = local_global_energy(self.area, J, T)
            energies.append(e)
            report(it + 1, max_iterations, f"iteration {it + 1}: energy {e:.6g}")
            if e <= floor or (tolerance > 0 and energies[-2] - e <= tolerance * max(e, floor)):
                converged = True
                break
        if not converged and tolerance > 0:
            warn(f"{name} parameterization stopped after {max_iterations} iterations "
                 f"with the energy still falling faster than tolerance={tolerance}.",
                 ConvergenceWarning)
        q = quality(self.mesh.vertices, f, uv, self.frames)
        return LocalGlobalResult(uv=uv, mesh=self.mesh, energy=np.array(energies),
                                 iterations=len(energies) - 1, converged=converged,
                                 **q.fields())


def initial_map(disk: Disk, init: str, laplacian: sp.csr_array | None = None) -> FloatArray:
    """LSCM (farthest boundary pair pinned) or the harmonic map onto the circle, scaled so
    its area equals the surface's. ``laplacian``: the mesh's cotangent Laplacian, if made
    already (both maps use it)."""
    m = disk.mesh
    if init == "lscm":
        uv = lscm_uv(disk, laplacian=laplacian)[0]
    else:
        uv = pinned_map(disk, convex_boundary(disk, "circle"), "cotangent", laplacian)[0]
    plane = abs(float(signed_areas(uv, m.faces).sum()))
    scale: float = np.sqrt(face_areas(m.vertices, m.faces).sum() / plane)
    return uv * scale
