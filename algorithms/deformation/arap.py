r"""As-rigid-as-possible surface deformation (Sorkine & Alexa 2007), local/global."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Annotated, Any, Literal, get_args

import numpy as np
import scipy.sparse as sp

from algorithms.core.errors import ConvergenceWarning, InvalidInputError, warn
from algorithms.core.laplacian import cotangent_entries, cotangent_laplacian
from algorithms.core.linalg import RotationFitter
from algorithms.core.linsolve import BREAK_EVEN, Factor
from algorithms.core.mesh import Handles, Mesh, read_mesh
from algorithms.core.params import Ge, HandlesLike, MeshLike, validate_params
from algorithms.core.progress import Progress, as_progress
from algorithms.core.types import FloatArray, IntArray
from algorithms.core.validation import as_points
from algorithms.deformation._common import (
    handle_residual,
    pins_of,
    read_handle_indices,
    read_handles,
    read_positions,
)

__all__ = ["ArapResult", "ArapSolver", "arap", "ENERGIES"]

Energy = Literal["spokes_and_rims", "spokes"]
Backend = Literal["auto", "cholmod", "cholespy", "multifrontal", "superlu"]
"""``"auto"`` or one of :data:`algorithms.core.linsolve.BACKENDS`."""
#: The accepted values of ``energy``.
ENERGIES = get_args(Energy)

#: Energies below this fraction of the rest shape's total weighted squared edge length
#: count as zero (rounding noise of the trace formula used to evaluate them).
_NOISE = 1e-13


@dataclass(frozen=True, eq=False)
class ArapResult:
    """The as-rigid-as-possible deformation of a mesh under handle constraints.

    Attributes
    ----------
    mesh : Mesh
        The deformed mesh: the input's faces with the vertices moved; every handle vertex
        sits exactly on its target.
    energy : (k,) float array
        The ARAP energy after each iteration (after its global step); never increasing.
    handle_residual : float
        The largest distance of a handle vertex from its target (0 up to rounding).
    iterations : int
        The number of local/global iterations run.
    converged : bool
        True when the last iteration lowered the energy by at most ``tolerance`` times its
        value; False when ``max_iterations`` stopped the run first.
    """

    mesh: Mesh
    energy: FloatArray
    handle_residual: float
    iterations: int
    converged: bool


def _face_blocks(vertices: FloatArray, faces: IntArray, rims: bool
                 ) -> tuple[FloatArray, FloatArray]:
    r"""Per-face blocks of the covariance scatter and of the similarity denominators.

    For face ``f`` with corners ``v_0, v_1, v_2``, edge ``k`` (opposite corner ``k``) runs
    :math:`e_k = p_{v_{k+1}} - p_{v_{k+2}}` with weight :math:`c_k = \tfrac12\cot\theta_k`.
    Corner ``r`` owns edge ``k`` when ``rims`` (all three edges) or when ``r != k`` (its two
    spokes). The covariance of vertex ``v_r`` collects
    :math:`\sum_k [\text{r owns k}]\, c_k\, e_k (p'_{v_{k+1}} - p'_{v_{k+2}})^\mathsf{T}`, so its
    row ``a`` has coefficient ``block[f, r, j, a]`` on :math:`p'_{v_j}`.

    Returns
    -------
    block : (m, 3, 3, d) float array
    den : (m, 3) float array
        :math:`\sum_k [\text{r owns k}]\, c_k \lVert e_k\rVert^2` per corner.
    """
    c = cotangent_entries(vertices, faces)                           # (m, 3)
    p = vertices[faces]                                              # (m, 3, d)
    e = p[:, [1, 2, 0]] - p[:, [2, 0, 1]]                            # e_k = p_{k+1} - p_{k+2}
    ce = c[:, :, None] * e                                           # (m, 3, d)
    sq = c * np.einsum("mkd,mkd->mk", e, e)                          # c_k |e_k|²
    # with every edge owned: coefficient of p'_{v_j} = c_{j-1} e_{j-1} - c_{j+1} e_{j+1}
    g = ce[:, [2, 0, 1]] - ce[:, [1, 2, 0]]                          # (m, 3, d), by j
    block = np.repeat(g[:, None], 3, axis=1)                         # (m, r, j, d)
    den = np.repeat(sq.sum(axis=1, keepdims=True), 3, axis=1)
    if not rims:   # corner r does not own the edge opposite it, k = r
        for r in range(3):
            block[:, r, (r + 1) % 3] -= ce[:, r]
            block[:, r, (r + 2) % 3] += ce[:, r]
        den -= sq
    return block, den


class ArapSolver:
    r"""ARAP deformation of one mesh with a fixed set of handle vertices: the system is
    factored once, then :meth:`solve` runs for any number of handle positions.

    Parameters
    ----------
    mesh : Mesh or (vertices, faces)
        The rest shape, ``(n, 2)`` or ``(n, 3)`` vertices and ``(m, 3)`` faces, checked by
        :func:`~algorithms.core.mesh.as_mesh` (no zero-area faces).
    handle_indices : (p,) int array
        Distinct vertex indices whose positions :meth:`solve` prescribes; at least one in
        every connected component.
    energy : {"spokes_and_rims", "spokes"}, default "spokes_and_rims"
        Which edges each vertex's rotation answers for: its spokes (the edges at the
        vertex, Sorkine & Alexa's energy) or also the rims (every edge of its incident
        faces, Chao et al. 2010; libigl's default for triangle meshes). See :func:`arap`.
    similarity : bool, default False
        Fit a rotation and a non-negative scale per vertex (as-similar-as-possible).
    backend : {"auto", "cholmod", "cholespy", "multifrontal", "superlu"}, default "auto"
        The sparse Cholesky backend (:class:`~algorithms.core.linsolve.Factor`), chosen by
        ``"auto"`` for ``solves`` solves.
    solves : int, optional
        How many iterations the factorization will serve, over every :meth:`solve` (each
        iteration is one solve with ``d`` right-hand sides). Omitted: many (interactive
        handles, many targets), which favours the backend with the fastest solves
        (cholespy, with the ``cholmod`` extra: 2-3.6× faster than CHOLMOD through cvxopt,
        which factors 3-8× faster; in the default install SuperLU, whose solves are
        faster than those of our own multifrontal Cholesky); :func:`arap`
        passes its ``max_iterations``.

    Attributes
    ----------
    mesh : Mesh
        The checked rest shape.
    handle_indices : (p,) int array
        The handle vertices, in the order :meth:`solve` expects their targets.
    laplacian : (n, n) csr_array
        The cotangent Laplacian ``D - W`` (``-igl.cotmatrix``).
    factor : Factor
        The factorization of its free block, computed once.

    Raises
    ------
    InvalidInputError
        A malformed mesh, handle index or option.
    DegenerateInputError
        A zero-area face; a component without a handle (field ``handle_indices``).

    Notes
    -----
    Precomputation: the cotangent Laplacian :math:`L` (= ``-igl.cotmatrix``), its free
    block factored once with the handles (and any vertex no face uses) pinned, and the
    sparse covariance scatter matrix ``K`` (``(d n) × n``, on the pattern of the one-ring)
    with :math:`S = K P'` giving every vertex's covariance at once. An iteration is then one
    sparse product for the covariances, the batched rotation fit
    (:class:`~algorithms.core.linalg.RotationFitter`, the buffered form of
    :func:`~algorithms.core.linalg.batched_rotations`: no Python loop over vertices), one
    sparse product :math:`K^\mathsf{T}` for the right-hand side and one pinned solve with all
    coordinates as columns.
    """

    @validate_params
    def __init__(self, mesh: MeshLike, handle_indices: Any, *,
                 energy: Energy = "spokes_and_rims", similarity: bool = False,
                 backend: Backend = "auto", solves: Annotated[int, Ge(1)] | None = None,
                 _handles_name: str = "handle_indices") -> None:
        self.mesh = read_mesh(mesh)
        self.energy = energy
        self.similarity = similarity
        self.handle_indices = read_handle_indices(handle_indices, self.mesh,
                                                  name=_handles_name)
        self._name = _handles_name
        v, f = self.mesh.vertices, self.mesh.faces
        self.laplacian = lap = cotangent_laplacian(v, f)
        self.pins = pins_of(self.mesh, self.handle_indices, name=_handles_name,
                            adjacency=lap)
        n, d = v.shape
        rims = self.energy == "spokes_and_rims"
        self._owners = 3.0 if rims else 2.0
        block, den = _face_blocks(v, f, rims)
        # The scatter matrix K ((d n) × n, K x = every covariance) has the pattern of every
        # (owner, vertex) pair of every face. Work in the free unknowns only, x = (x_f, c)
        # with c the pinned values, so that an iteration gathers and scatters no rows: split
        # K's columns into free and pinned while assembling.
        pinned = self.pins.indices
        mask = np.zeros(n, dtype=bool)
        mask[pinned] = True
        self._free = free = np.flatnonzero(~mask)
        rank = np.empty(n, dtype=np.int64)
        rank[free] = np.arange(free.shape[0])
        rank[pinned] = np.arange(pinned.shape[0])
        rows = np.repeat(f, 3, axis=1).ravel()                       # (m*9,) owner-major
        cols = np.tile(f, (1, 3)).ravel()
        keys, pos = np.unique(rows * n + cols, return_inverse=True)  # sorted by row, col
        pr, pc = keys // n, keys % n
        flat = block.reshape(-1, d)
        data = [np.bincount(pos, weights=flat[:, a], minlength=keys.shape[0]) for a in range(d)]

        def stacked(sel: np.ndarray, width: int) -> sp.csr_array:
            counts = np.bincount(pr[sel], minlength=n)
            indptr = np.zeros(d * n + 1, dtype=np.int64)
            np.cumsum(np.tile(counts, d), out=indptr[1:])
            return sp.csr_array((np.concatenate([x[sel] for x in data]),
                                 np.tile(rank[pc[sel]], d), indptr), shape=(d * n, width))

        self._scatter_f = stacked(~mask[pc], free.shape[0])          # (d n, n_f)
        self._scatter_p = stacked(mask[pc], pinned.shape[0])         # (d n, p)
        self._gather_f = (self._scatter_f.T / self._owners).tocsr()  # (n_f, d n)
        self._den = np.bincount(f.ravel(), weights=den.ravel(), minlength=n)
        rows_f = lap[free]
        self._L_ff = rows_f[:, free].tocsr()
        self._L_fp = rows_f[:, pinned].tocsr()
        self._L_pp = lap[pinned][:, pinned].tocsr()
        self.factor = Factor(self._L_ff, backend=backend, name="L",
                             solves=max(BREAK_EVEN.values()) if solves is None else solves)
        self._fit = RotationFitter(n, d)

    @validate_params
    def solve(self, handle_positions: Any, *, initial: Any = None,
              max_iterations: Annotated[int, Ge(1)] = 30,
              tolerance: Annotated[float, Ge(0)] = 1e-5,
              progress: Progress | None = None) -> ArapResult:
        r"""Deform the mesh so that the handles reach ``handle_positions``.

        Parameters
        ----------
        handle_positions : (p, d) float array
            Targets, row ``i`` for ``handle_indices[i]``.
        initial : (n, d) float array, optional
            The starting guess (e.g. the previous solution while dragging); the rest shape
            when omitted. Its handle rows are replaced by the targets.
        max_iterations : int, default 30
            Upper bound on local/global iterations (``>= 1``).
        tolerance : float, default 1e-5
            Stop when an iteration lowers the energy by at most ``tolerance`` times its
            value (``0`` runs all ``max_iterations``, as libigl's ``arap_solve`` does, unless
            the energy reaches zero).
        progress : callable, optional
            ``progress(done, max_iterations, message)`` after every iteration; it may raise
            :class:`~algorithms.core.errors.Cancelled`.

        Returns
        -------
        ArapResult

        Raises
        ------
        InvalidInputError
            ``handle_positions`` not ``(p, d)`` finite numbers, ``initial`` not ``(n, d)``,
            a bad ``max_iterations`` or ``tolerance``.
        Cancelled
            Raised by ``progress``.
        """
        v = self.mesh.vertices
        n, d = v.shape
        targets = read_positions(handle_positions, self.handle_indices.shape[0], d,
                                 name="handles.positions" if self._name == "handles"
                                 else "handle_positions")
        report = as_progress(progress)
        c = self.pins.values(targets, v)                              # pinned values
        if initial is None:
            x_f = v[self._free]
        else:
            x0 = as_points(initial, name="initial", dim=d)
            if x0.shape[0] != n:
                raise InvalidInputError(
                    f"Expected `initial` to hold one row per vertex ({n}), got {x0.shape[0]}.",
                    field="initial")
            x_f = x0[self._free]
        owners, den = self._owners, self._den
        b_p = -(self._L_fp @ c)                                       # -L_fp c
        s_p = self._scatter_p @ c                                     # pinned part of K x
        c_quad = float(np.einsum("ij,ij->", c, self._L_pp @ c))       # cᵀ L_pp c
        floor = _NOISE * float(np.abs(den).sum())   # energies this small are rounding noise
        S = (self._scatter_f @ x_f + s_p).reshape(d, n, d)
        scale = np.ones(n)
        positive = den > 0
        safe_den = np.where(positive, den, 1.0)
        energies: list[float] = []
        converged = False
        for it in range(max_iterations):
            rs = self._fit(S)                                         # rs[a, r, b] = R_r[b, a]
            if self.similarity:
                trace = np.einsum("anb,anb->n", rs, S)
                scale = np.where(positive, np.maximum(trace, 0.0) / safe_den, scale)
                rs = rs * scale[None, :, None]
            rhs = self._gather_f @ rs.reshape(d * n, d)
            rhs += b_p
            x_f = self.factor.solve(rhs)
            S = self._scatter_f @ x_f
            S += s_p
            S = S.reshape(d, n, d)
            # xᵀ L x = x_fᵀ L_ff x_f + 2 x_fᵀ L_fp c + cᵀ L_pp c, and L_ff x_f = rhs
            # (einsum, not vdot/dot: BLAS threads waking on a busy machine cost milliseconds)
            quad = (float(np.einsum("ij,ij->", x_f, rhs))
                    - 2.0 * float(np.einsum("ij,ij->", x_f, b_p)) + c_quad)
            e = (owners * quad - 2.0 * float(np.einsum("anb,anb->", rs, S))
                 + float(np.einsum("i,i,i->", scale, scale, den)))
            energies.append(e)
            report(it + 1, max_iterations, f"iteration {it + 1}: energy {e:.6g}")
            if abs(e) <= floor or (it > 0 and tolerance > 0 and
                                   energies[-2] - e <= tolerance * max(abs(e), floor)):
                converged = True
                break
        if not converged and tolerance > 0:
            warn(f"ARAP stopped after {max_iterations} iterations with the energy "
                 f"still falling faster than tolerance={tolerance}.",
                 ConvergenceWarning)
        x = np.empty((n, d))
        x[self._free] = x_f
        x[self.pins.indices] = c
        return ArapResult(mesh=Mesh(x, self.mesh.faces), energy=np.array(energies),
                          handle_residual=handle_residual(x, Handles(self.handle_indices,
                                                                     targets)),
                          iterations=len(energies), converged=converged)


@validate_params
def arap(
    mesh: MeshLike,
    handles: HandlesLike,
    *,
    energy: Energy = "spokes_and_rims",
    similarity: bool = False,
    max_iterations: Annotated[int, Ge(1)] = 30,
    tolerance: Annotated[float, Ge(0)] = 1e-5,
    progress: Progress | None = None,
) -> ArapResult:
    r"""As-rigid-as-possible deformation (local/global).

    Alternates per-vertex best rotations (batched, proper) and one prefactored cotangent-Laplacian
    solve; handles met exactly, energy never increasing; spokes or spokes-and-rims energy, optional
    per-vertex scale.

    Minimises over the new positions :math:`p'` and one rotation :math:`R_i` per vertex

    .. math::

        E(p', R) = \sum_i \sum_{(j,k) \in \mathcal{E}(i)} w_{jk}
        \lVert (p'_j - p'_k) - R_i (p_j - p_k) \rVert^2,

    with :math:`\mathcal{E}(i)` the spokes of vertex :math:`i` (edges :math:`(i, j)`,
    ``energy="spokes"``, Sorkine & Alexa's energy) or its spokes and rims (every edge of the
    faces around :math:`i`, each face's edge weighted by that face's :math:`\tfrac12\cot`,
    ``"spokes_and_rims"``), and :math:`w` the cotangent weights; handle vertices are held at
    their targets. Block coordinate descent alternates the local step (each :math:`R_i`
    maximises :math:`\operatorname{tr}(R_i S_i)` for the weighted covariance
    :math:`S_i = \sum w\, e\, e'^\mathsf{T}`: a rigid alignment, proper rotation enforced)
    and the global step (:math:`L p' = b(R)`, a Laplacian solve with the factor computed
    once). Each step minimises the energy over its block exactly, so the energy never
    increases.

    With ``similarity=True`` each vertex also gets a scale :math:`s_i \ge 0`
    (:math:`R_i \to s_i R_i`), fitted in the local step as
    :math:`s_i = \max(\operatorname{tr}(R_i S_i), 0) / \sum w \lVert e\rVert^2`.

    Parameters
    ----------
    mesh : Mesh or {"vertices", "faces"}
        The rest shape: ``(n, 2)`` or ``(n, 3)`` vertices and ``(m, 3)`` triangles of
        0-based vertex indices, no zero-area ones. Vertices no face uses stay where they
        are.
    handles : Handles or {"indices", "positions"}
        The vertices to move and their targets: ``(p,)`` distinct vertex indices and their
        ``(p, d)`` positions; at least one handle in every connected component.
    energy : {"spokes_and_rims", "spokes"}, default "spokes_and_rims"
        The edges each vertex's rotation answers for: ``"spokes_and_rims"`` every edge of
        the faces around the vertex (Chao et al.; libigl's default,
        ``ARAP_ENERGY_TYPE_SPOKES_AND_RIMS``), ``"spokes"`` only the edges at the vertex
        (Sorkine & Alexa; ``ARAP_ENERGY_TYPE_SPOKES``).
    similarity : bool, default False
        Fit a non-negative scale per vertex too, besides its rotation
        (as-similar-as-possible).
    max_iterations : int, default 30
        Upper bound on local/global iterations (libigl's ``ARAPData.max_iter`` is 10, run
        to the end; ours stops earlier by ``tolerance``, so a larger bound costs nothing on
        easy edits and lets hard ones converge).
    tolerance : float, default 1e-5
        Stop when an iteration lowers the energy by at most this fraction; ``0`` runs all
        ``max_iterations`` (libigl's behaviour), unless the energy reaches zero.
    progress : callable, optional
        ``progress(done, max_iterations, message)`` after every iteration; raising
        :class:`~algorithms.core.errors.Cancelled` from it stops the run.

    Returns
    -------
    ArapResult
        ``mesh``, ``energy`` per iteration, ``handle_residual``, ``iterations`` and
        ``converged``.

    Raises
    ------
    InvalidInputError
        Malformed mesh, handles or options (the field names the input).
    DegenerateInputError
        A zero-area face (``mesh.faces``); a connected component with no handle
        (``handles``).
    Cancelled
        Raised by ``progress``.

    Notes
    -----
    The method is a rigid alignment per vertex and a Laplacian-preserving deformation in
    turn; the outcome is *like* a rigid motion, neither rigid nor as-rigid-as-possible in
    the singular-value sense. With one rotation per vertex the global step is exactly
    Sorkine & Alexa's eq. (9), a cotangent-Laplacian solve (for spokes; spokes and rims
    average the face's three rotations instead of the edge's two).

    The energy is reported as written above, summed over every vertex's edge set, so
    "spokes" counts each edge twice and "spokes_and_rims" each face's edges three times.
    Cotangent weights can be negative on obtuse triangles; the steps stay exact minimisers
    (the Laplacian remains positive semidefinite), but with ``similarity`` a vertex whose
    :math:`\sum w\lVert e\rVert^2` is not positive keeps its previous scale (initially 1).

    The local step's rotations come from Horn's quaternion eigenproblem, solved for all
    vertices at once (:func:`~algorithms.core.linalg.batched_rotations`) to rounding, so
    the local step attains the exact block minimum; libigl's ``arap_solve`` runs the same
    iterations with a single-precision SVD. Measured after 10 iterations (RMS of the
    difference over RMS of the displacement, both energies): 2e-7 to 2.5e-5 on pyvista's
    sphere (180 of 1,260 edges with negative cotangent weights), airplane (its largest
    part: 165 of 1,544) and ant (31 of 192). Where many weights are negative the two
    drift further apart while reaching the same energy: on pymeshlab 2025.7's cow (2,904
    vertices, 1,402 of 8,706 edges negative; the tenth of the vertices at each end of its
    longest axis pinned, one end moved sideways by a fifth of that length) 1.9e-4 with
    ``"spokes"`` and 1.8e-5 with ``"spokes_and_rims"`` (measured, not a test: the cow
    ships under the GPL and is not copied here).
    The energy never increasing is what
    guards against the "more iterations, worse result" reports (libigl issue 1539): there,
    the iterations were fine and the energy or the constraints were not what the user
    expected.

    Use :class:`ArapSolver` to factor once and deform the same mesh and handle set for many
    targets.

    References
    ----------
    .. [1] O. Sorkine and M. Alexa, "As-rigid-as-possible surface modeling", Symposium on
       Geometry Processing, 109-116, 2007.
    .. [2] I. Chao, U. Pinkall, P. Sanan and P. Schröder, "A simple geometric model for
       elastic deformations", ACM Transactions on Graphics 29(4), 38, 2010.

    Examples
    --------
    >>> import numpy as np
    >>> from algorithms.deformation import arap
    >>> v = np.array([[0, 0], [1, 0], [2, 0], [0, 1], [1, 1], [2, 1]], float)
    >>> f = np.array([[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4]])
    >>> turn = np.array([[0.0, -1.0], [1.0, 0.0]])            # a quarter turn
    >>> res = arap((v, f), {"indices": [0, 2, 3], "positions": v[[0, 2, 3]] @ turn.T},
    ...            max_iterations=200, tolerance=1e-12)
    >>> bool(np.allclose(res.mesh.vertices, v @ turn.T, atol=1e-6))  # rigid motion: free
    True
    >>> bool(np.all(np.diff(res.energy) <= 0)), res.handle_residual
    (True, 0.0)
    """
    m = read_mesh(mesh)
    h = read_handles(handles, m)
    solver = ArapSolver(m, h.indices, energy=energy, similarity=similarity,
                        solves=max_iterations, _handles_name="handles")
    return solver.solve(h.positions, max_iterations=max_iterations, tolerance=tolerance,
                        progress=progress)
