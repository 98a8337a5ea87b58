r"""As-similar-as-possible parameterization (Liu et al. 2008), local/global."""

from __future__ import annotations

from typing import Annotated

from algorithms.core.params import Ge, MeshLike, validate_params
from algorithms.core.progress import Progress
from algorithms.parameterization._results import LocalGlobalResult
from algorithms.parameterization.arap import Init, _run

__all__ = ["asap"]


@validate_params
def asap(
    mesh: MeshLike,
    *,
    init: Init = "harmonic",
    max_iterations: Annotated[int, Ge(1)] = 100,
    tolerance: Annotated[float, Ge(0)] = 1e-6,
    progress: Progress | None = None,
) -> LocalGlobalResult:
    r"""As-similar-as-possible parameterization (local/global).

    Alternates per-face nearest similarities and one prefactored solve, two boundary vertices held;
    converges to the LSCM map with those pins. Reports flipped faces, angle distortion and area
    distortion.

    Minimises over the UV positions :math:`u` and one similarity
    :math:`S_t = \begin{pmatrix} p_t & -s_t \\ s_t & p_t \end{pmatrix}` per face

    .. math:: E(u, S) = \sum_t A_t \lVert J_t(u) - S_t \rVert_F^2

    by the local/global iteration of :func:`~algorithms.parameterization.arap` with the
    similarity nearest each Jacobian in the local step (closed form, no SVD). The energy
    is zero on the collapsed map, so two vertices (the boundary pair farthest apart) are
    held where ``init`` put them.

    Parameters
    ----------
    mesh : Mesh, (vertices, faces) or mapping
        A topological disk ``{"vertices": (n, 2|3), "faces": (m, 3)}``, faces of 0-based
        vertex indices: connected, manifold, consistently oriented, exactly one boundary
        loop, every vertex in a face, no zero-area face.
    init : {"lscm", "harmonic"}, default "harmonic"
        The starting map, scaled to the surface's area: ``"harmonic"`` the harmonic map
        onto the circle; ``"lscm"`` the least-squares conformal map with the same two pins,
        already the minimum of the ASAP energy (the iteration stops at once).
    max_iterations : int, default 100
        Upper bound on local/global iterations.
    tolerance : float, default 1e-6
        Stop when an iteration lowers the energy by at most this fraction; ``0`` runs all
        ``max_iterations``.
    progress : callable, optional
        ``progress(done, max_iterations, message)`` after every iteration.

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
    The global step is the least-squares solve of
    :func:`~algorithms.parameterization.arap`, assembled per half-edge with each face's own
    similarity. Minimised over
    :math:`S`, :math:`E` is exactly the conformal energy of
    :func:`~algorithms.parameterization.conformal` (per face :math:`\lVert J - S\rVert^2 =
    \tfrac12\lVert J\rVert^2 - \det J` times two), so ASAP with two pins converges to the
    LSCM map with the same pins (Liu et al. say as much); from ``init="lscm"`` it stops at
    once. The local/global form is kept for the iteration history and as a starting point
    between harmonic and conformal maps.

    References
    ----------
    .. [1] L. Liu, L. Zhang, Y. Xu, C. Gotsman and S. J. Gortler, "A local/global approach
       to mesh parameterization", Computer Graphics Forum 27(5) (SGP), 2008.

    Examples
    --------
    >>> import numpy as np
    >>> v = np.array([[0, 0], [2, 0], [2, 1], [0, 1], [1, 0.5]])
    >>> f = [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]
    >>> res = asap((v, f), max_iterations=500, tolerance=1e-14)
    >>> res.angle_distortion < 1e-6, res.flipped_faces
    (True, 0)
    """
    return _run(mesh, init, max_iterations, tolerance, progress, similarity=True)
