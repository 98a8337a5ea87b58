r"""As-rigid-as-possible parameterization (Liu et al. 2008), local/global."""

from __future__ import annotations

from typing import Any

from algorithms.core.progress import Progress
from algorithms.core.validation import as_choice, as_float, as_int
from algorithms.parameterization._disk import read_disk
from algorithms.parameterization._local_global import LocalGlobalSolver, initial_map
from algorithms.parameterization._results import LocalGlobalResult
from algorithms.parameterization.conformal import farthest_boundary_pair

__all__ = ["arap", "INITS"]

#: The accepted values of ``init``.
INITS = ("lscm", "harmonic")


def arap(mesh: Any, *, init: str = "lscm", max_iterations: int = 100,
         tolerance: float = 1e-6, progress: Progress | None = None) -> LocalGlobalResult:
    r"""Map a disk-like mesh to the plane with every triangle as close to an isometry as
    possible, its boundary free.

    Minimises over the UV positions :math:`u` and one rotation :math:`R_t` per face

    .. math::

        E(u, R) = \sum_t A_t \lVert J_t(u) - R_t \rVert_F^2
        = \sum_t \sum_{k} \tfrac12\cot\theta_t^k
        \lVert (u_a - u_b) - R_t\, e_t^k \rVert^2,

    by block coordinate descent from ``init``: the local step gives each face the rotation
    nearest its Jacobian (closed form in 2-D), the global step solves for :math:`u` with
    the rotations fixed (one prefactored cotangent-Laplacian solve per iteration). Each
    step minimises the energy over its block exactly, so it never increases. One vertex is
    held where ``init`` put it (the energy does not see translations).

    Parameters
    ----------
    mesh : Mesh, (vertices, faces) or {"vertices", "faces"}
        A topological disk.
    init : {"lscm", "harmonic"}, default "lscm"
        The starting map: LSCM (farthest boundary pair pinned) or the harmonic map onto the
        circle, scaled to the surface's area.
    max_iterations : int, default 100
    tolerance : float, default 1e-6
        Stop when an iteration lowers the energy by at most this fraction; ``0`` runs all
        ``max_iterations`` (libigl's behaviour).
    progress : callable, optional
        ``progress(done, max_iterations, message)`` after every iteration; it may raise
        :class:`~algorithms.core.errors.Cancelled`.

    Returns
    -------
    LocalGlobalResult
        ``uv``, ``mesh``, ``energy`` (initial, then per iteration), ``iterations``,
        ``converged``, flips and distortion.

    Raises
    ------
    InvalidInputError
        A malformed mesh, an unknown ``init``, a bad ``max_iterations`` or ``tolerance``.
    NotADiskError
        The mesh is not a topological disk; field ``mesh``.
    DegenerateInputError
        Zero-area faces.
    Cancelled
        Raised by ``progress``.

    Notes
    -----
    The global step follows the seed document, which corrects the paper's presentation of
    it: with per-*face* transforms the global step "cannot be turned into a
    Laplacian-preserving deformation" (:math:`L u = L x`-style, one rotation per edge or
    vertex); every half-edge keeps its own face's rotation, and the system is the
    least-squares one of "relative positions as fixed as possible",
    :math:`D^\mathsf{T} W D\, u = D^\mathsf{T} W\, (R_t e_t^k)`, whose matrix happens to be
    the cotangent Laplacian (each half-edge weighted by :math:`\tfrac12\cot` of its own
    face) while the right-hand side is assembled per half-edge. The seed's other remark
    holds: the result is *like* a rigid map, not rigid (no map of a curved disk is).

    ARAP does not prevent flipped or overlapping triangles (libigl issue 2523): they are
    counted in ``flipped_faces``.

    References
    ----------
    .. [1] L. Liu, L. Zhang, Y. Xu, C. Gotsman and S. J. Gortler, "A local/global approach
       to mesh parameterization", Computer Graphics Forum 27(5) (SGP), 2008.

    Examples
    --------
    A planar mesh is already an isometry: ARAP keeps it, up to a rigid motion.

    >>> import numpy as np
    >>> v = np.array([[0, 0], [2, 0], [2, 1], [0, 1], [1, 0.5]])
    >>> f = [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]
    >>> res = arap((v, f))
    >>> d = lambda x: np.linalg.norm(x[:, None] - x[None], axis=-1)
    >>> bool(np.allclose(d(res.uv), d(v), atol=1e-9)), res.flipped_faces
    (True, 0)
    """
    return _run(mesh, init, max_iterations, tolerance, progress, similarity=False)


def _run(mesh: Any, init: str, max_iterations: Any, tolerance: Any,
         progress: Progress | None, *, similarity: bool) -> LocalGlobalResult:
    init = as_choice(init, INITS, name="init")
    max_iterations = as_int(max_iterations, name="max_iterations", minimum=1)
    tolerance = as_float(tolerance, name="tolerance", minimum=0.0)
    disk = read_disk(mesh)
    uv0 = initial_map(disk, init)
    if similarity:
        pinned = farthest_boundary_pair(disk)
    else:
        pinned = disk.loop[:1]
    solver = LocalGlobalSolver(disk.mesh, pinned, similarity=similarity)
    return solver.solve(uv0, max_iterations=max_iterations, tolerance=tolerance,
                        progress=progress, name="ASAP" if similarity else "ARAP")
