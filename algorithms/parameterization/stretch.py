r"""Stretch-minimizing parameterization: Sander et al.'s L2 texture stretch, lowered by
Yoshizawa et al.'s iterative reweighting of a Tutte-type linear system."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Annotated, Any

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as sla

from algorithms.core.errors import ConvergenceWarning, DegenerateInputError, warn
from algorithms.core.mesh import Mesh
from algorithms.core.params import Ge, Interval, MeshLike, validate_params
from algorithms.core.progress import Progress, as_progress
from algorithms.core.types import FloatArray, IntArray
from algorithms.parameterization._disk import Boundary, convex_boundary, read_disk
from algorithms.parameterization._quality import face_frames, jacobians, quality
from algorithms.parameterization.tutte import mean_value_weights

__all__ = ["StretchResult", "stretch_minimizing", "l2_stretch", "face_stretch"]


@dataclass(frozen=True, eq=False)
class StretchResult:
    """A fixed-boundary map of a disk-like mesh to the plane with low texture stretch.

    Attributes
    ----------
    uv : (n, 2) float array
        The position of every vertex in the plane, row ``i`` for vertex ``i``.
    mesh : Mesh
        The input mesh (its faces index ``uv`` too).
    pinned : (p,) int array
        The boundary loop, held on the circle or square in its order.
    stretch : (k + 1,) float array
        The normalised L2 stretch (1 for an isometry up to scale, larger otherwise) of the
        mean value Tutte start and after each reweighting; ``uv`` is the map with the
        smallest.
    l2_stretch : float
        The normalised L2 stretch of ``uv`` (the minimum of ``stretch``).
    max_stretch : float
        The normalised L∞ stretch of ``uv``: the largest singular value of the map from the
        plane to the surface over all faces, times the square root of the ratio of plane
        area to surface area.
    iterations : int
        The number of reweightings run.
    converged : bool
        True when the last reweighting lowered the stretch by at most ``tolerance`` times
        its value, or raised it (the method's own stopping rule); False when
        ``max_iterations`` stopped the run first.
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
    pinned: IntArray
    stretch: FloatArray
    l2_stretch: float
    max_stretch: float
    iterations: int
    converged: bool
    flipped_faces: int
    degenerate_faces: int
    angle_distortion: float
    area_distortion: float


def face_stretch(frames: FloatArray, faces: IntArray, uv: FloatArray
                 ) -> tuple[FloatArray, FloatArray]:
    r"""Per-face squared L2 stretch and L∞ stretch of the map from the plane to the surface.

    With :math:`J_t` the Jacobian from the surface to the plane (singular values
    :math:`\sigma_1 \ge \sigma_2`), the map back has singular values :math:`\Gamma =
    1/\sigma_2`, :math:`\gamma = 1/\sigma_1`, so

    .. math:: L^2(t)^2 = \tfrac12(\Gamma^2 + \gamma^2) = \frac{\lVert J_t\rVert_F^2}
       {2 \det(J_t)^2}, \qquad L^\infty(t) = \Gamma.

    Faces collapsed in the plane get ``inf``.
    """
    J = jacobians(frames, faces, uv)
    fro = np.einsum("tij,tij->t", J, J)
    det = J[:, 0, 0] * J[:, 1, 1] - J[:, 0, 1] * J[:, 1, 0]
    # σ₁² the larger root of σ⁴ − ‖J‖²σ² + det² = 0; Γ = 1/σ₂ = σ₁/|det|
    s1 = np.sqrt(0.5 * (fro + np.sqrt(np.maximum(fro * fro - 4.0 * det * det, 0.0))))
    with np.errstate(divide="ignore", invalid="ignore"):
        l2sq = np.where(det != 0, fro / (2.0 * det * det), np.inf)
        linf = np.where(det != 0, s1 / np.abs(det), np.inf)
    return l2sq, linf


def l2_stretch(vertices: Any, faces: Any, uv: Any) -> float:
    r"""Sander et al.'s normalised L2 stretch of the map ``uv`` of a triangle mesh.

    .. math:: L^2(M) = \sqrt{\frac{\sum_t A_t\, L^2(t)^2}{\sum_t A_t}}
       \cdot \sqrt{\frac{\sum_t A'_t}{\sum_t A_t}},

    :math:`A_t` the surface area of face :math:`t`, :math:`A'_t` its area in the plane,
    :math:`L^2(t)` as in :func:`face_stretch`. At least 1; 1 exactly when every face is
    mapped by a similarity of one common scale. ``inf`` if a face collapses.
    """
    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces, dtype=np.int64)
    fr = face_frames(v, f)
    return _l2(fr, f, np.asarray(uv, dtype=np.float64))[0]


def _l2(frames: FloatArray, faces: IntArray, uv: FloatArray
        ) -> tuple[float, float, FloatArray]:
    """Normalised L2 and L∞ stretch and the per-face squared L2 stretch."""
    area = 0.5 * frames[:, 1, 0] * frames[:, 2, 1]
    l2sq, linf = face_stretch(frames, faces, uv)
    p0, p1, p2 = uv[faces[:, 0]], uv[faces[:, 1]], uv[faces[:, 2]]
    a, b = p1 - p0, p2 - p0
    plane = abs(0.5 * float((a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]).sum()))
    scale = np.sqrt(plane / area.sum())
    if not np.isfinite(l2sq).all():
        return float("inf"), float("inf"), l2sq
    l2 = float(np.sqrt(np.dot(area, l2sq) / area.sum()) * scale)
    return l2, float(linf.max() * scale), l2sq


def _vertex_stretch(n: int, faces: IntArray, area: FloatArray, l2sq: FloatArray
                    ) -> FloatArray:
    r""":math:`\sigma(v_i) = \sqrt{\sum_{t \ni i} A_t L^2(t)^2 / \sum_{t \ni i} A_t}`."""
    num = np.bincount(faces.ravel(), weights=np.repeat(area * l2sq, 3), minlength=n)
    den = np.bincount(faces.ravel(), weights=np.repeat(area, 3), minlength=n)
    return np.sqrt(num / den)


class _RowSolver:
    """Solves Σⱼ wᵢⱼ (uᵢ − uⱼ) = 0 for the free vertices, the pinned ones given, for
    reweighted copies of one sparsity pattern."""

    def __init__(self, w: sp.csr_array, pinned: IntArray, values: FloatArray) -> None:
        n = w.shape[0]
        self.w = w
        self.n = n
        self.pinned, self.values = pinned, values
        self.free = np.setdiff1d(np.arange(n), pinned)
        self.cols = w.indices                       # column of every stored weight

    def solve(self, data: FloatArray) -> FloatArray:
        w = sp.csr_array((data, self.w.indices, self.w.indptr), shape=self.w.shape)
        lap: sp.csr_array = (sp.diags_array(np.asarray(w.sum(axis=1)).ravel()) - w).tocsr()
        rows = lap[self.free]
        x = np.empty((self.n, 2))
        x[self.pinned] = self.values
        if self.free.size:
            try:
                # an M-matrix (positive weights, every row reaching the boundary): no
                # pivoting needed, so keep the fill-reducing order of its symmetric pattern
                lu = sla.splu(sp.csc_matrix(rows[:, self.free]), permc_spec="MMD_AT_PLUS_A",
                              diag_pivot_thresh=0.0, options={"SymmetricMode": True})
            except RuntimeError:                      # pragma: no cover - positive weights
                raise DegenerateInputError("Expected `mesh` to give a non-singular stretch "
                                           "system, got a singular one.", field="mesh") from None
            x[self.free] = lu.solve(-(rows[:, self.pinned] @ self.values))
        return x


@validate_params
def stretch_minimizing(
    mesh: MeshLike,
    *,
    boundary: Boundary = "circle",
    power: Annotated[float, Interval(gt=0, le=4)] = 1.0,
    max_iterations: Annotated[int, Ge(1)] = 20,
    tolerance: Annotated[float, Ge(0)] = 1e-4,
    progress: Progress | None = None,
) -> StretchResult:
    r"""Stretch-minimizing parameterization (fixed boundary).

    Starts from the mean value Tutte map (boundary on a circle or square), then divides each weight
    w_ij by the stretch around vertex j and solves again while Sander et al.'s L2 stretch falls;
    keeps the best map. Positive weights and a convex boundary: no flipped faces. Reports the L2 and
    L-infinity stretch, flipped faces, angle distortion and area distortion.

    Lowers Sander et al.'s L2 stretch (the root mean square, over the surface, of the
    stretch a texture suffers when mapped back onto the surface)

    .. math:: L^2(M)^2 = \frac{\sum_t A_t \tfrac12(\Gamma_t^2 + \gamma_t^2)}{\sum_t A_t}
       \cdot \frac{\sum_t A'_t}{\sum_t A_t}

    (:math:`\Gamma_t \ge \gamma_t` the singular values of the map from the plane to face
    :math:`t`; :math:`A_t`, :math:`A'_t` its surface and plane areas) by Yoshizawa et al.'s
    reweighting:

    1. start from the mean value Tutte map (Floater's weights :math:`w^0_{ij}`, boundary on
       the convex polygon);
    2. compute each vertex's stretch :math:`\sigma_j = \sqrt{\sum_{t \ni j} A_t L^2(t)^2 /
       \sum_{t \ni j} A_t}`;
    3. reweight :math:`w_{ij} \leftarrow w_{ij} / \sigma_j^{p}` (a stretched neighbour pulls
       harder, so the region around it grows) and solve
       :math:`\sum_j w_{ij}(u_i - u_j) = 0` for the interior again (one sparse LU);
    4. repeat while the L2 stretch falls; return the map with the smallest.

    The weights stay positive and the boundary convex, so by Tutte's theorem in Floater's
    form no face flips at any step.

    Parameters
    ----------
    mesh : Mesh, (vertices, faces) or mapping
        A topological disk ``{"vertices": (n, 2|3), "faces": (m, 3)}``, faces of 0-based
        vertex indices: connected, manifold, consistently oriented, exactly one boundary
        loop, every vertex in a face, no zero-area face.
    boundary : {"circle", "square"}, default "circle"
        The convex polygon the boundary loop is pinned to, its vertices spaced by boundary
        edge length: ``"circle"`` the unit circle; ``"square"`` the square
        :math:`[-1, 1]^2`, its corners at the four boundary vertices of smallest angle sum
        (the surface's own corners; at least 4 boundary vertices).
    power : float, default 1.0
        The exponent :math:`p` of the reweighting :math:`w_{ij} \leftarrow w_{ij} /
        \sigma_j^p`, :math:`\sigma_j` the stretch around vertex :math:`j`; ``0 < p <= 4``
        (Yoshizawa et al.: 1). Smaller steps are safer on very stretched meshes; larger
        ones converge faster when they work.
    max_iterations : int, default 20
        Upper bound on reweightings.
    tolerance : float, default 1e-4
        Stop when a reweighting lowers the L2 stretch by at most this fraction (or raises
        it: the method's stopping rule).
    progress : callable, optional
        ``progress(done, max_iterations, message)`` after every reweighting; it may raise
        :class:`~algorithms.core.errors.Cancelled`.

    Returns
    -------
    StretchResult
        ``uv``, ``mesh``, ``pinned`` (the boundary loop), ``stretch`` (per iteration),
        ``l2_stretch``, ``max_stretch``, ``iterations``, ``converged``, flips and
        distortion.

    Raises
    ------
    InvalidInputError
        A malformed mesh, an unknown ``boundary``, a bad ``power``, ``max_iterations`` or
        ``tolerance``.
    NotADiskError
        The mesh is not a topological disk; field ``mesh``.
    DegenerateInputError
        Zero-area faces; ``boundary="square"`` with fewer than 4 boundary vertices.
    Cancelled
        Raised by ``progress``.

    Notes
    -----
    **No proof of descent.** The reweighting is a heuristic: no step of it is proven to
    lower the stretch, and on some meshes one does not. The best map seen is therefore
    kept, and the iteration stops at the first step that does not lower the stretch, as
    Yoshizawa et al. do.

    **Cumulative weights.** The weights are updated cumulatively,
    :math:`w_{ij} \leftarrow w_{ij}/\sigma_j^p` as in the paper, not reset to
    :math:`1/\sigma_j^p` times uniform weights at each step (which would undo the earlier
    steps' corrections). The stretch measured is that of the map from the plane to the
    surface (Sander et al.), i.e. of :math:`J_t^{-1}`.

    References
    ----------
    .. [1] P. V. Sander, J. Snyder, S. J. Gortler and H. Hoppe, "Texture mapping
       progressive meshes", SIGGRAPH 2001.
    .. [2] S. Yoshizawa, A. Belyaev and H.-P. Seidel, "A fast and simple stretch-minimizing
       mesh parameterization", Shape Modeling International 2004.

    Examples
    --------
    A flat square mesh with its own square outline is already stretch-free: the
    Tutte start is the mesh itself, which has L2 stretch 1.

    >>> v = [[0, 0], [1, 0], [1, 1], [0, 1], [0.5, 0.5]]
    >>> f = [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]
    >>> res = stretch_minimizing((v, f), boundary="square")
    >>> round(res.l2_stretch, 12), res.flipped_faces
    (1.0, 0)
    """
    report = as_progress(progress)
    disk = read_disk(mesh)
    m = disk.mesh
    f, n = m.faces, m.n_vertices
    frames = face_frames(m.vertices, f)
    area = 0.5 * frames[:, 1, 0] * frames[:, 2, 1]
    w = mean_value_weights(m.vertices, f)
    w.sort_indices()
    solver = _RowSolver(w, disk.loop, convex_boundary(disk, boundary))
    data = w.data.copy()
    uv = solver.solve(data)
    l2, linf, l2sq = _l2(frames, f, uv)
    best = (l2, linf, uv)
    history = [l2]
    converged = False
    for it in range(max_iterations):
        if not np.isfinite(l2):
            converged = True
            break
        sigma = _vertex_stretch(n, f, area, l2sq)
        data = data / sigma[solver.cols] ** power
        data /= data.max()                              # keep the weights O(1)
        uv = solver.solve(data)
        l2, linf, l2sq = _l2(frames, f, uv)
        history.append(l2)
        report(it + 1, max_iterations, f"iteration {it + 1}: L2 stretch {l2:.6g}")
        if l2 < best[0]:
            gain = best[0] - l2
            best = (l2, linf, uv)
            if gain <= tolerance * l2:
                converged = True
                break
        else:
            converged = True
            break
    if not converged and tolerance > 0:
        warn(f"Stretch minimization stopped after {max_iterations} iterations with "
             f"the L2 stretch still falling faster than tolerance={tolerance}.",
             ConvergenceWarning)
    l2, linf, uv = best
    q = quality(m.vertices, f, uv, frames)
    return StretchResult(uv=uv, mesh=m, pinned=disk.loop.copy(), stretch=np.array(history),
                         l2_stretch=float(l2), max_stretch=float(linf),
                         iterations=len(history) - 1, converged=converged,
                         **q.fields())
