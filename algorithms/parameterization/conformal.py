r"""Conformal parameterization of a disk-like mesh: least-squares conformal maps (two pins)
and spectral conformal parameterization (free boundary)."""

from __future__ import annotations

from typing import Any, Literal, get_args

import numpy as np
import scipy.linalg
import scipy.sparse as sp
import scipy.sparse.linalg as sla
from scipy.spatial.distance import cdist

from algorithms.core.errors import DegenerateInputError, InvalidInputError
from algorithms.core.laplacian import cotangent_laplacian
from algorithms.core.linsolve import Factor, PinnedSystem
from algorithms.core.mesh import (
    Handles,
    Mesh,
    as_handles,
    boundary_edges,
    face_areas,
    signed_areas,
)
from algorithms.core.params import HandlesLike, MeshLike, validate_params
from algorithms.core.types import FloatArray, IntArray
from algorithms.parameterization._disk import Disk, read_disk
from algorithms.parameterization._results import ParameterizationResult, direct_result

__all__ = ["conformal", "conformal_energy_matrix", "conformal_energy_hermitian",
           "farthest_boundary_pair", "lscm_uv",
           "check_pins", "check_conformal", "ConformalMethod", "CONFORMAL_METHODS"]

ConformalMethod = Literal["lscm", "spectral"]
#: The accepted values of ``method``.
CONFORMAL_METHODS = get_args(ConformalMethod)


def conformal_energy_matrix(mesh: Mesh) -> sp.csr_array:
    r"""The ``(2n, 2n)`` matrix :math:`Q` of the conformal energy in the unknowns
    :math:`(u_x, u_y)` stacked: :math:`E_C = \tfrac12(u_x^\mathsf{T} L u_x + u_y^\mathsf{T}
    L u_y) - A(u) = [u_x; u_y]^\mathsf{T} Q\, [u_x; u_y]`, with :math:`L` the cotangent
    Laplacian and :math:`A(u) = \tfrac12 \sum_{(i \to j) \in \partial} (x_i y_j - x_j y_i)`
    the signed area enclosed by the image of the boundary. Symmetric positive semidefinite;
    :math:`E_C = \sum_t A_t \lVert J_t - S_t \rVert_F^2` (:math:`S_t` the similarity nearest
    the face's Jacobian), zero exactly on similarities. ``igl.lscm`` minimises :math:`2Q`.
    Built as the real form ``[[Re K, -Im K], [Im K, Re K]]`` of
    :func:`conformal_energy_hermitian`.
    """
    k = conformal_energy_hermitian(mesh)
    re = sp.csr_array(k.real)
    im = sp.csr_array(k.imag)
    im.eliminate_zeros()          # only the boundary edges carry an area term
    out: sp.csr_array = sp.block_array([[re, -im], [im, re]], format="csr")
    return out


def conformal_energy_hermitian(mesh: Mesh, laplacian: sp.csr_array | None = None
                               ) -> sp.csr_array:
    r"""The conformal energy as a Hermitian form in one complex unknown per vertex,
    :math:`z = u_x + i u_y`: :math:`E_C = z^* K z` with the ``(n, n)`` Hermitian

    .. math::

       K = \tfrac12 L + i M, \qquad
       Q = \begin{pmatrix} \tfrac12 L & -M \\ M & \tfrac12 L \end{pmatrix},

    :math:`M` the antisymmetric matrix of the area term :math:`A(u) = 2 u_x^\mathsf{T} M
    u_y` (:math:`M_{ij} = \tfrac14 = -M_{ji}` on a boundary edge :math:`i \to j`) and
    :math:`Q` :func:`conformal_energy_matrix`, its real form. For :math:`z = x + iy` and
    :math:`K = P + iR` (:math:`P` symmetric, :math:`R` antisymmetric),
    :math:`z^* K z = x^\mathsf{T} P x + y^\mathsf{T} P y - 2 x^\mathsf{T} R y` (the
    imaginary parts cancel: :math:`x^\mathsf{T} P y = y^\mathsf{T} P x`, :math:`x^\mathsf{T}
    R x = 0`), which is :math:`[x; y]^\mathsf{T} Q [x; y]`; likewise :math:`Q [x; y] =
    [b_x; b_y] \iff K z = b_x + i b_y`. The complex system has the sparsity of the mesh;
    the real one couples each vertex's two unknowns, and factors 1.5-2.5 times as slowly
    (:mod:`algorithms.core.linsolve` has the figures).

    ``laplacian``: the mesh's :func:`~algorithms.core.laplacian.cotangent_laplacian`, when
    the caller has it already.
    """
    lap = cotangent_laplacian(mesh.vertices, mesh.faces) if laplacian is None else laplacian
    be = boundary_edges(mesh.faces)
    i, j = be[:, 0], be[:, 1]
    q = np.full(i.shape[0], 0.25)
    n = mesh.n_vertices
    area = sp.coo_array((np.concatenate([q, -q]), (np.concatenate([i, j]),
                                                    np.concatenate([j, i]))), shape=(n, n))
    out: sp.csr_array = (0.5 * lap + 1j * area).tocsr()
    out.sum_duplicates()
    return out


def farthest_boundary_pair(disk: Disk) -> IntArray:
    """The two boundary vertices farthest apart in space (smaller loop position first)."""
    loop = disk.loop
    p = disk.mesh.vertices[loop]
    best, pair = -1.0, (0, 1)
    step = max(1, 2_000_000 // max(p.shape[0], 1))
    for s in range(0, p.shape[0], step):   # blocks of rows: memory stays bounded
        d = cdist(p[s:s + step], p, "sqeuclidean")
        k = int(np.argmax(d))
        r, c = divmod(k, p.shape[0])
        if d[r, c] > best:
            best, pair = float(d[r, c]), (s + r, c)
    a, b = sorted(pair)
    return loop[[a, b]]


def _conformal_energy(k: sp.csr_array, uv: FloatArray) -> float:
    """:math:`E_C = z^* K z` (:func:`conformal_energy_hermitian`) of the map ``uv``."""
    z = uv[:, 0] + 1j * uv[:, 1]
    return max(float((np.conj(z) @ (k @ z)).real), 0.0)


def lscm_uv(disk: Disk, pins: Handles | None = None, laplacian: sp.csr_array | None = None
            ) -> tuple[FloatArray, IntArray, float]:
    """LSCM on a checked disk; ``pins`` default: the farthest boundary pair at ``(0, 0)``
    and ``(d, 0)``, ``d`` their distance in space. Returns ``uv``, the pinned indices and
    the conformal energy. ``laplacian``: the mesh's cotangent Laplacian, if made already."""
    m = disk.mesh
    if pins is None:
        idx = farthest_boundary_pair(disk)
        d = float(np.linalg.norm(m.vertices[idx[1]] - m.vertices[idx[0]]))
        pos = np.array([[0.0, 0.0], [d, 0.0]])
    else:
        idx, pos = pins.indices, pins.positions
    # the complex form: one unknown per vertex, factored 1.5-2.5x faster than the real
    # (2n, 2n) system (see conformal_energy_hermitian)
    k = conformal_energy_hermitian(m, laplacian)
    system = PinnedSystem(k, idx, name="pins", check_components=False)
    z = system.solve(pos[:, 0] + 1j * pos[:, 1])
    uv = np.stack([z.real, z.imag], axis=1)
    return uv, idx, _conformal_energy(k, uv)


def check_pins(pins: Any, mesh: Mesh) -> Handles:
    """LSCM's ``pins`` checked against ``mesh``: at least two vertices of it, at ``(p, 2)``
    positions in the plane that are not all one point."""
    h = as_handles(pins, mesh.n_vertices, name="pins")
    if h.positions.shape[1] != 2:
        raise InvalidInputError(
            f"Expected `pins.positions` to be (p, 2) points in the plane, got shape "
            f"{h.positions.shape}.", field="pins.positions")
    if h.indices.shape[0] < 2:
        raise DegenerateInputError(
            f"Expected `pins` to hold at least 2 vertices (LSCM with one pin leaves a "
            f"rotation and a scale free: the map collapses), got {h.indices.shape[0]}.",
            field="pins")
    if np.ptp(h.positions, axis=0).max() == 0:
        raise DegenerateInputError(
            "Expected `pins.positions` to hold at least two distinct points, got all "
            f"at {h.positions[0].tolist()} (the map would collapse to a point).",
            field="pins.positions")
    return h


def _boundary_mass(disk: Disk) -> FloatArray:
    """Half the length of the boundary edges at each vertex (zero inside)."""
    m = disk.mesh
    loop = disk.loop
    p = m.vertices[loop]
    seg = np.linalg.norm(np.roll(p, -1, axis=0) - p, axis=1)
    mass = np.zeros(m.n_vertices)
    mass[loop] = 0.5 * (seg + np.roll(seg, 1))
    return mass


#: Boundary unknowns (2 per boundary vertex) up to which the spectral problem is reduced to
#: the boundary and solved densely (:func:`_boundary_eigenvectors`).
_DENSE_BOUNDARY = 600


def _boundary_eigenvectors(q: sp.csc_array, mass: FloatArray, loop: IntArray,
                           k: int) -> FloatArray:
    r"""The ``k`` generalized eigenvectors of :math:`Qx = \lambda Bx` of smallest
    :math:`\lambda`, with ``B`` the boundary mass (zero inside), by reduction to the boundary.

    Notes
    -----
    ``B`` vanishes on the interior unknowns, so an eigenvector's interior part solves
    :math:`Q_{II} x_I + Q_{IB} x_B = 0` and its boundary part the dense, positive definite
    problem :math:`(Q_{BB} - Q_{BI} Q_{II}^{-1} Q_{IB}) x_B = \lambda B_{BB} x_B` (the Schur
    complement; :math:`Q_{II}` is positive definite, since a similarity that vanishes on the
    boundary is zero). Shift-invert Lanczos on the full problem works in the range of
    :math:`Q^{-1}B`, of dimension ``2 b``: with a short boundary its Krylov space is
    exhausted before it converges (ARPACK's "could not build an Arnoldi factorization").
    """
    n = mass.size
    bnd = np.concatenate([loop, loop + n])
    inner = np.setdiff1d(np.arange(2 * n), bnd)
    qbb = q[bnd][:, bnd].toarray()
    if inner.size:
        qib = q[inner][:, bnd].toarray()
        z = Factor(q[inner][:, inner], name="Q").solve(qib)
        schur = qbb - qib.T @ z
    else:
        z = np.zeros((0, bnd.size))
        schur = qbb
    _, y = scipy.linalg.eigh(0.5 * (schur + schur.T), np.diag(np.tile(mass, 2)[bnd]),
                             subset_by_index=[0, k - 1])
    vecs = np.empty((2 * n, k))
    vecs[bnd] = y
    vecs[inner] = -z @ y
    return vecs


def spectral_uv(disk: Disk) -> tuple[FloatArray, float]:
    r"""Spectral conformal parameterization of a checked disk: the minimiser of
    :math:`E_C` with unit boundary norm, orthogonal to the constants; returned centred,
    scaled to the surface's area and turned so the farthest boundary pair lies along +x."""
    m = disk.mesh
    n = m.n_vertices
    q = conformal_energy_matrix(m).tocsc()
    mass = _boundary_mass(disk)
    b = sp.diags_array(np.concatenate([mass, mass]), format="csc")
    # shift below 0: Q + εB is positive definite (Q vanishes only on similarities, which
    # do not vanish on the boundary); ε small against Q's smallest non-zero eigenvalues
    eps = 1e-8 * float(q.diagonal().sum() / b.diagonal().sum())
    k = min(4, 2 * n - 1)
    if 2 * disk.loop.size <= _DENSE_BOUNDARY:
        vecs = _boundary_eigenvectors(q, mass, disk.loop, k)
    else:
        factor = Factor(q + eps * b, name="Q")
        op = sla.LinearOperator(q.shape, matvec=factor.solve, dtype=np.float64)
        v0 = np.concatenate([np.cos(np.arange(n)), np.sin(np.arange(n))])   # deterministic
        _, vecs = sla.eigsh(q, k=k, M=b, sigma=-eps, which="LM", OPinv=op, v0=v0, tol=0)
    # remove the constants (B-orthogonally), then Rayleigh-Ritz in what remains
    c = np.zeros((2 * n, 2))
    c[:n, 0] = 1.0
    c[n:, 1] = 1.0
    bc = b @ c
    vecs = vecs - c @ np.linalg.solve(c.T @ bc, bc.T @ vecs)
    gram = vecs.T @ (b @ vecs)
    w, u = np.linalg.eigh(0.5 * (gram + gram.T))
    keep = w > 1e-10 * w.max()
    basis = vecs @ (u[:, keep] / np.sqrt(w[keep]))
    small = basis.T @ (q @ basis)
    _, y = np.linalg.eigh(0.5 * (small + small.T))
    x = basis @ y[:, 0]
    uv = np.stack([x[:n], x[n:]], axis=1)
    uv -= uv.mean(axis=0)
    signed = float(signed_areas(uv, m.faces).sum())
    if signed < 0:                        # cannot happen for a minimiser; guards rounding
        uv[:, 1] = -uv[:, 1]
    uv *= np.sqrt(face_areas(m.vertices, m.faces).sum() / abs(signed))
    a, bb = farthest_boundary_pair(disk)
    d = uv[bb] - uv[a]
    t = np.arctan2(d[1], d[0])
    rot = np.array([[np.cos(t), np.sin(t)], [-np.sin(t), np.cos(t)]])
    uv = uv @ rot.T
    return uv, _conformal_energy(conformal_energy_hermitian(m), uv)


def check_conformal(mesh: Any, method: str = "lscm", pins: Any = None
                    ) -> tuple[Disk, Handles | None]:
    """Check the inputs of :func:`conformal`: a disk-like mesh (:func:`check_disk`), and
    pins only with LSCM, then vertices of the mesh in the plane (:func:`check_pins`).
    Returns the disk and the pins."""
    disk = read_disk(mesh)
    if pins is None:
        return disk, None
    if method == "spectral":
        raise InvalidInputError(
            "Expected no `pins` with method='spectral' (its boundary is free and its "
            "similarity fixed by normalisation), got some; use method='lscm'.",
            field="pins")
    return disk, check_pins(pins, disk.mesh)


@validate_params
def conformal(mesh: MeshLike, *, method: ConformalMethod = "lscm",
              pins: HandlesLike | None = None) -> ParameterizationResult:
    r"""Conformal parameterization (LSCM, spectral).

    Minimises the conformal energy (Dirichlet minus area): LSCM with two or more pins (chosen
    automatically or given; as igl.lscm), or spectral conformal with a free boundary (generalized
    eigenproblem). Reports flipped faces, angle distortion and area distortion.

    Both methods minimise the conformal energy

    .. math::

        E_C(u) = \tfrac12 \int \lVert \nabla u \rVert^2 - A(u)
        = \sum_t A_t \lVert J_t - S_t \rVert_F^2,

    Dirichlet energy minus the area of the image (:math:`J_t` each face's Jacobian,
    :math:`S_t` the nearest similarity), which vanishes exactly on conformal maps and is
    unchanged by similarities of the plane, so they differ in how that freedom is fixed:

    * ``"lscm"`` (Lévy et al. 2002; Desbrun et al. 2002): pin at least two vertices and solve
      :math:`Q_{ff} u_f = -Q_{fp} c`, one sparse Cholesky solve of size :math:`2n`. Without
      ``pins`` the two boundary vertices farthest apart in space are pinned at
      :math:`(0, 0)` and :math:`(d, 0)`, :math:`d` their distance. Equal to ``igl.lscm``
      with the same pins.
    * ``"spectral"`` (Mullen et al. 2008): no pins; the minimiser of :math:`E_C` under
      :math:`u^\mathsf{T} B u = 1` and :math:`u \perp_B` the constants, :math:`B` the lumped
      boundary length: the first non-trivial eigenvector of :math:`Q u = \lambda B u`
      (shift-invert Lanczos). The result is centred, scaled so its area equals the
      surface's, and turned so the farthest boundary pair lies along +x. A planar mesh comes
      back as itself up to a similarity.

    Parameters
    ----------
    mesh : Mesh, (vertices, faces) or mapping
        A topological disk ``{"vertices": (n, 2|3), "faces": (m, 3)}``, faces of 0-based
        vertex indices: connected, manifold, consistently oriented, exactly one boundary
        loop, every vertex in a face, no zero-area face.
    method : {"lscm", "spectral"}, default "lscm"
        ``"lscm"``: the least-squares conformal map with at least two vertices pinned
        (``pins``); ``"spectral"``: free boundary and no pins, the first non-trivial
        generalized eigenvector, centred, scaled to the surface's area and turned so the
        farthest boundary pair lies along +x.
    pins : Handles or mapping, optional
        LSCM only: at least two vertices and their positions in the plane,
        ``{"indices": (p,), "positions": (p, 2)}``. Omitted: the two boundary vertices
        farthest apart in space, at :math:`(0, 0)` and :math:`(d, 0)`, :math:`d` their
        distance.

    Returns
    -------
    ParameterizationResult
        ``uv``, ``mesh``, ``pinned`` (the pins; empty for spectral), ``energy`` (the
        conformal energy :math:`E_C`), flips and distortion.

    Raises
    ------
    InvalidInputError
        A malformed mesh or pins, ``pins`` with ``method="spectral"``, an unknown option.
    NotADiskError
        The mesh is not a topological disk; field ``mesh``.
    DegenerateInputError
        Zero-area faces; fewer than two pins or all pins at one point (libigl issue 66:
        LSCM with one pin is singular).

    Notes
    -----
    **Conformal and harmonic.** The area :math:`A(u)` of the image depends on the
    boundary's image alone, so with the whole boundary pinned, minimising :math:`E_C` is
    minimising the Dirichlet energy: the harmonic map
    (:func:`~algorithms.parameterization.harmonic`). The :math:`-A(u)` term is what lets
    the boundary move instead. With :math:`E_C` written as
    :math:`\sum_t A_t\lVert J_t - S_t\rVert^2`, LSCM is also the fixed point of the ASAP
    local/global iteration with the same pins
    (:func:`~algorithms.parameterization.asap`). The spectral method uses the boundary
    length as :math:`B` (Mullen et al. use the boundary vertex indicator); the minimiser
    differs only in scale on a uniformly sampled boundary, and the length makes it
    independent of the boundary's sampling.

    References
    ----------
    .. [1] B. Lévy, S. Petitjean, N. Ray and J. Maillot, "Least squares conformal maps for
       automatic texture atlas generation", SIGGRAPH 2002.
    .. [2] M. Desbrun, M. Meyer and P. Alliez, "Intrinsic parameterizations of surface
       meshes", Eurographics 2002.
    .. [3] P. Mullen, Y. Tong, P. Alliez and M. Desbrun, "Spectral conformal
       parameterization", SGP 2008.

    Examples
    --------
    A planar square with a centre vertex is its own conformal map:

    >>> v = [[0, 0], [2, 0], [2, 2], [0, 2], [1, 1]]
    >>> f = [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]
    >>> res = conformal((v, f), pins={"indices": [0, 1], "positions": [[0, 0], [2, 0]]})
    >>> (res.uv.round(12) + 0.0).tolist(), res.angle_distortion < 1e-12
    ([[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0], [1.0, 1.0]], True)
    """
    disk, h = check_conformal(mesh, method, pins)
    m = disk.mesh
    if method == "spectral":
        uv, energy = spectral_uv(disk)
        return direct_result(m, uv, np.zeros(0, dtype=np.int64), energy)
    uv, idx, energy = lscm_uv(disk, h)
    return direct_result(m, uv, idx, energy)
