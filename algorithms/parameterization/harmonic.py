r"""Harmonic parameterization of a disk-like mesh: boundary fixed to a convex polygon,
interior by the cotangent Laplace equation."""

from __future__ import annotations

from algorithms.core.params import MeshLike, validate_params
from algorithms.parameterization._disk import Boundary, convex_boundary, pinned_map, read_disk
from algorithms.parameterization._results import ParameterizationResult, direct_result

__all__ = ["harmonic"]


@validate_params
def harmonic(mesh: MeshLike, *, boundary: Boundary = "circle") -> ParameterizationResult:
    r"""Harmonic parameterization.

    Boundary fixed to a circle or square, interior by the cotangent Laplace equation (minimal
    Dirichlet energy); as igl.harmonic. Reports flipped faces, angle distortion and area distortion.

    .. math::

        \min_u \int \lVert \nabla u \rVert^2 = \min_u\; u_x^\mathsf{T} L u_x
        + u_y^\mathsf{T} L u_y \quad\text{s.t.}\quad u_{\text{boundary}} = c
        \qquad\Longleftrightarrow\qquad L_{00}\, u = -L_{01}\, c,

    :math:`L` the cotangent Laplacian (:math:`w_{ij} = \tfrac12(\cot\alpha_{ij} +
    \cot\beta_{ij})`) and :math:`c` the boundary loop on the unit circle (arc length, as
    ``igl.map_vertices_to_circle``) or the square :math:`[-1, 1]^2`. One factored solve
    for both coordinates (what :func:`algorithms.layout.laplacian` solves with these pins);
    the same as ``igl.harmonic(V, F, loop, c, 1)``.

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

    Returns
    -------
    ParameterizationResult
        ``uv``, ``mesh``, ``pinned`` (the boundary loop), ``energy`` (the Dirichlet energy
        :math:`u^\mathsf{T} L u`), flips and distortion.

    Raises
    ------
    InvalidInputError
        A malformed mesh, an unknown option.
    NotADiskError
        The mesh is not a topological disk; field ``mesh``.
    DegenerateInputError
        Zero-area faces; ``boundary="square"`` with fewer than 4 boundary vertices.

    Notes
    -----
    **Why the cotangent weights.** The Dirichlet energy of the piecewise-linear map equals
    the graph energy :math:`\sum_{(i,j)} w_{ij} \lVert u_i - u_j \rVert^2` with the
    cotangent weights (Pinkall and Polthier). The conformal energy is half the Dirichlet
    energy minus the area of the image, and that area depends on the boundary's image
    alone; with the boundary pinned, the most conformal map is therefore the harmonic one.

    **Flips.** On a mesh that is not Delaunay some cotangent weights are negative, the
    maximum principle fails, and faces may flip (counted in ``flipped_faces``);
    :func:`~algorithms.parameterization.tutte` with positive weights never flips.

    References
    ----------
    .. [1] U. Pinkall and K. Polthier, "Computing discrete minimal surfaces and their
       conjugates", Experimental Mathematics 2(1), 1993.
    .. [2] M. Eck, T. DeRose, T. Duchamp, H. Hoppe, M. Lounsbery and W. Stuetzle,
       "Multiresolution analysis of arbitrary meshes", SIGGRAPH 1995.

    Examples
    --------
    >>> v = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0.5, 0.5, 0.3]]
    >>> f = [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]
    >>> res = harmonic((v, f))
    >>> (res.uv[4].round(12) + 0.0).tolist(), res.flipped_faces
    ([0.0, 0.0], 0)
    """
    disk = read_disk(mesh)
    m = disk.mesh
    values = convex_boundary(disk, boundary)
    uv, energy = pinned_map(disk, values, "cotangent")
    return direct_result(m, uv, disk.loop, energy)
