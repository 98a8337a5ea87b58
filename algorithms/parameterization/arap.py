r"""As-rigid-as-possible parameterization (Liu et al. 2008), local/global."""

from __future__ import annotations

from typing import Annotated, Any, Literal, get_args

from algorithms.core.laplacian import cotangent_laplacian
from algorithms.core.params import Ge, MeshLike, validate_params
from algorithms.core.progress import Progress
from algorithms.parameterization._disk import read_disk
from algorithms.parameterization._local_global import LocalGlobalSolver, initial_map
from algorithms.parameterization._results import LocalGlobalResult
from algorithms.parameterization.conformal import farthest_boundary_pair

__all__ = ["arap", "Init", "INITS"]

Init = Literal["lscm", "harmonic"]
#: The accepted values of ``init`` (of ARAP and ASAP).
INITS = get_args(Init)


@validate_params
def arap(
    mesh: MeshLike,
    *,
    init: Init = "lscm",
    max_iterations: Annotated[int, Ge(1)] = 100,
    tolerance: Annotated[float, Ge(0)] = 1e-6,
    progress: Progress | None = None,
) -> LocalGlobalResult:
    r"""As-rigid-as-possible parameterization (local/global).

    Alternates per-face nearest rotations (closed form) and one prefactored cotangent-Laplacian
    solve with a per-half-edge right-hand side; free boundary, energy never increasing. Reports
    flipped faces, angle distortion and area distortion.

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
    mesh : Mesh, (vertices, faces) or mapping
        A topological disk ``{"vertices": (n, 2|3), "faces": (m, 3)}``, faces of 0-based
        vertex indices: connected, manifold, consistently oriented, exactly one boundary
        loop, every vertex in a face, no zero-area face.
    init : {"lscm", "harmonic"}, default "lscm"
        The starting map, scaled to the surface's area: ``"lscm"`` the least-squares
        conformal map (farthest boundary pair pinned), ``"harmonic"`` the harmonic map onto
        the circle.
    max_iterations : int, default 100
        Upper bound on local/global iterations (libigl's ``ARAPData.max_iter`` is 10, run
        to the end; ours stops by ``tolerance``, so the larger bound costs nothing where
        fewer iterations settle; ``max_iterations=10, tolerance=0`` is libigl's run).
    tolerance : float, default 1e-6
        Stop when an iteration lowers the energy by at most this fraction; ``0`` runs all
        ``max_iterations`` (libigl's behaviour), unless the energy reaches zero.
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
    **The global step is assembled per half-edge.** With one transform per *face*, the
    global step is not a Laplacian-preserving solve :math:`L u = \tilde L x` with one
    rotation per vertex or edge (as in ARAP surface deformation), which would mix the
    rotations of the faces around an edge and not minimise :math:`E`. Every half-edge
    keeps its own face's rotation, and the step is the least-squares fit of the rotated
    edge vectors, :math:`D^\mathsf{T} W D\, u = D^\mathsf{T} W\, (R_t e_t^k)`, whose matrix
    happens to be the cotangent Laplacian (each half-edge weighted by
    :math:`\tfrac12\cot` of its own face's angle) while the right-hand side is assembled
    per half-edge. The result is close to an isometry, not one: no map of a curved disk
    to the plane is.

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


def _run(mesh: Any, init: str, max_iterations: int, tolerance: float,
         progress: Progress | None, *, similarity: bool) -> LocalGlobalResult:
    """ARAP or ASAP on checked options."""
    disk = read_disk(mesh)
    # the cotangent Laplacian of both the initial map and the global step, made once
    lap = cotangent_laplacian(disk.mesh.vertices, disk.mesh.faces)
    uv0 = initial_map(disk, init, lap)
    if similarity:
        pinned = farthest_boundary_pair(disk)
    else:
        pinned = disk.loop[:1]
    solver = LocalGlobalSolver(disk.mesh, pinned, similarity=similarity,
                               solves=max_iterations, laplacian=lap)
    return solver.solve(uv0, max_iterations=max_iterations, tolerance=tolerance,
                        progress=progress, name="ASAP" if similarity else "ARAP")
