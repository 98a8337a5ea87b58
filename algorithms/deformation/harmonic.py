r"""Harmonic deformation: the handle displacements spread by the Laplace equation."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp

from algorithms.core.laplacian import cotangent_laplacian, mass_matrix
from algorithms.core.linsolve import PinnedSystem
from algorithms.core.mesh import Mesh, read_mesh
from algorithms.core.params import HandlesLike, MeshLike, validate_params
from algorithms.core.types import FloatArray
from algorithms.deformation._common import handle_residual, pins_of, read_handles

__all__ = ["HarmonicResult", "harmonic", "k_harmonic"]


@dataclass(frozen=True, eq=False)
class HarmonicResult:
    """A mesh deformed by the harmonic extension of its handle displacements.

    Attributes
    ----------
    mesh : Mesh
        The deformed mesh: the input's faces with the vertices moved; every handle vertex
        sits exactly on its target.
    energy : (k,) float array
        The Dirichlet energy of the displacement, one value (a single linear solve).
    handle_residual : float
        The largest distance of a handle vertex from its target (0 up to rounding).
    """

    mesh: Mesh
    energy: FloatArray
    handle_residual: float


def k_harmonic(mesh: Mesh, handle_indices: Any, handle_positions: FloatArray, k: int,
               *, name: str = "handles") -> tuple[FloatArray, float]:
    r"""The k-harmonic displacement field with the handles' displacements as boundary values.

    Minimises :math:`\sum_c u_c^\mathsf{T} Q u_c` over the displacement columns :math:`u_c`
    with :math:`Q = L (M^{-1} L)^{k-1}` (:math:`L` the cotangent Laplacian, :math:`M` the
    Voronoi mass matrix), the handle rows fixed: :math:`Q_{ff} u_f = -Q_{fp} u_p`. This is
    ``igl.harmonic(V, F, b, bc, k)`` with ``bc`` the handle displacements.

    Returns
    -------
    vertices : (n, d) float array
        Rest positions plus displacement.
    energy : float
        :math:`\sum_c u_c^\mathsf{T} Q u_c`.
    """
    v, f = mesh.vertices, mesh.faces
    L = cotangent_laplacian(v, f)
    pins = pins_of(mesh, handle_indices, name=name, adjacency=L)
    Q = L
    if k > 1:
        m = mass_matrix(v, f, kind="voronoi").diagonal()
        inv = np.divide(1.0, m, out=np.zeros_like(m), where=m > 0)   # unused vertices: 0
        Minv_L = (sp.diags_array(inv, format="csr") @ L).tocsr()
        for _ in range(k - 1):
            Q = (Q @ Minv_L).tocsr()
        Q = ((Q + Q.T) * 0.5).tocsr()   # symmetric up to rounding; make it exactly so
    disp = pins.values(handle_positions - v[handle_indices], np.zeros_like(v))
    system = PinnedSystem(Q, pins.indices, name=name, check_components=False)
    u = system.solve(disp)
    energy = float(np.einsum("ij,ij->", u, Q @ u))
    return v + u, energy


@validate_params
def harmonic(mesh: MeshLike, handles: HandlesLike) -> HarmonicResult:
    r"""Harmonic deformation.

    Spreads the handle displacements by the Laplace equation (cotangent Laplacian): L_ff u_f = −L_fp
    u_p, x' = x + u; as igl.harmonic with k = 1.

    The displacement :math:`u = p' - p` minimises the Dirichlet energy
    :math:`\int \lVert \nabla u \rVert^2`, discretised with the cotangent Laplacian
    :math:`L`, with the handle displacements fixed:

    .. math::

        \min_u \sum_c u_c^\mathsf{T} L\, u_c
        \quad\Longrightarrow\quad L_{ff} u_f = -L_{fp} u_p,\qquad p' = p + u.

    Membrane-like: the deformation is as smooth as a soap film, with kinks (:math:`C^0`) at
    the handles. The same as :func:`~algorithms.deformation.laplacian` with cotangent
    weights (both solve :math:`L_{ff} p'_f = (L p)_f - L_{fp} c`), and as
    ``igl.harmonic(V, F, b, bc, 1)`` applied to the handle displacements ``bc``.

    Parameters
    ----------
    mesh : Mesh or {"vertices", "faces"}
        The rest shape: ``(n, 2)`` or ``(n, 3)`` vertices and ``(m, 3)`` triangles of
        0-based vertex indices, no zero-area ones. Vertices no face uses stay where they
        are.
    handles : Handles or {"indices", "positions"}
        The vertices to move and their targets: ``(p,)`` distinct vertex indices and their
        ``(p, d)`` positions; at least one handle in every connected component.

    Returns
    -------
    HarmonicResult
        ``mesh``, ``energy`` (one value: the Dirichlet energy of the displacement) and
        ``handle_residual``.

    Raises
    ------
    InvalidInputError
        Malformed mesh or handles (the field names the input).
    DegenerateInputError
        A zero-area face (``mesh.faces``); a connected component without a handle
        (``handles``).

    Notes
    -----
    **The displacement, not the positions.** The smoothing energy of the map,
    :math:`\min \sum_c \lVert J(F_c)\rVert_F^2`, is often discretised as
    :math:`L_{cot}\, x = 0` for the new positions :math:`x`. On a curved surface
    :math:`L p \ne 0`, so solving for the positions flattens the shape towards a minimal
    surface even with the handles at rest. Following libigl (and its tutorial 402) the
    equation is applied to the displacement instead, and handles at rest give the rest
    shape.

    References
    ----------
    .. [1] M. Botsch and O. Sorkine, "On linear variational surface deformation methods",
       IEEE TVCG 14(1), 213-230, 2008.
    .. [2] A. Jacobson, I. Baran, J. Popović and O. Sorkine, "Bounded biharmonic weights
       for real-time deformation", ACM TOG 30(4), 78, 2011 (libigl's ``harmonic``).

    Examples
    --------
    >>> import numpy as np
    >>> from algorithms.deformation import harmonic
    >>> v = np.array([[0, 0], [1, 0], [2, 0], [0, 1], [1, 1], [2, 1]], float)
    >>> f = np.array([[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4]])
    >>> res = harmonic((v, f), {"indices": [0, 3, 2, 5],
    ...                         "positions": [[0, 0], [0, 1], [2, 1], [2, 2]]})
    >>> res.mesh.vertices[[1, 4]].round(12).tolist()   # the middle column rises half-way
    [[1.0, 0.5], [1.0, 1.5]]
    """
    m = read_mesh(mesh)
    h = read_handles(handles, m)
    x, energy = k_harmonic(m, h.indices, h.positions, 1)
    return HarmonicResult(mesh=Mesh(x, m.faces), energy=np.array([energy]),
                          handle_residual=handle_residual(x, h))
