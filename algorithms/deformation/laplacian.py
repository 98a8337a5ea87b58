r"""Laplacian-preserving deformation: keep every vertex's Laplacian coordinate, move the
handles."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal, get_args

import numpy as np

from algorithms.core.laplacian import mesh_laplacian
from algorithms.core.linsolve import PinnedSystem
from algorithms.core.mesh import Mesh, read_mesh
from algorithms.core.params import HandlesLike, MeshLike, validate_params
from algorithms.core.types import FloatArray
from algorithms.deformation._common import handle_residual, pins_of, read_handles

__all__ = ["LaplacianResult", "laplacian", "WEIGHTS"]

Weights = Literal["cotangent", "uniform", "tangent"]
#: The accepted values of ``weights``.
WEIGHTS = get_args(Weights)


@dataclass(frozen=True, eq=False)
class LaplacianResult:
    """A mesh deformed to keep its Laplacian coordinates with the handles moved.

    Attributes
    ----------
    mesh : Mesh
        The deformed mesh: the input's faces with the vertices moved; every handle vertex
        sits exactly on its target.
    energy : (k,) float array
        ``Σ w_ij ‖(p'_i − p'_j) − (p_i − p_j)‖²`` over the edges, one value (a single
        linear solve); 0 when the handles stay at rest.
    handle_residual : float
        The largest distance of a handle vertex from its target (0 up to rounding).
    """

    mesh: Mesh
    energy: FloatArray
    handle_residual: float


@validate_params
def laplacian(mesh: MeshLike, handles: HandlesLike, *, weights: Weights = "cotangent"
              ) -> LaplacianResult:
    r"""Laplacian-preserving deformation.

    Moves the handles and every other vertex so that the weighted edge vectors change least: L_ff x'
    = (L x)_f − L_fp c, one factored solve for all coordinates.

    .. math::

        \min_{p'} \sum_{(i,j)} w_{ij} \lVert (p'_i - p'_j) - (p_i - p_j) \rVert^2
        \quad\text{s.t. } p'_h = c_h
        \quad\Longrightarrow\quad L_{ff}\, p'_f = (L p)_f - L_{fp}\, c,

    one sparse solve per coordinate (all coordinates as columns of one factored system):
    the Laplacian coordinates :math:`\delta = L p` are kept wherever no handle pins the
    vertex.

    Parameters
    ----------
    mesh : Mesh or {"vertices", "faces"}
        The rest shape: ``(n, 2)`` or ``(n, 3)`` vertices and ``(m, 3)`` triangles of
        0-based vertex indices, no zero-area ones. Vertices no face uses stay where they
        are.
    handles : Handles or {"indices", "positions"}
        The vertices to move and their targets: ``(p,)`` distinct vertex indices and their
        ``(p, d)`` positions; at least one handle in every connected component.
    weights : {"cotangent", "uniform", "tangent"}, default "cotangent"
        The edge weights :math:`w_{ij}` of the Laplacian :math:`L = D - W`:
        ``"cotangent"`` (the Dirichlet energy; may be negative on obtuse triangles),
        ``"uniform"`` (the graph Laplacian, as in Sorkine et al.'s Laplacian coordinates)
        or ``"tangent"`` (incentre weights, never negative).

    Returns
    -------
    LaplacianResult
        ``mesh``, ``energy`` (one value) and ``handle_residual``.

    Raises
    ------
    InvalidInputError
        Malformed mesh or handles (the field names the input), an unknown ``weights``.
    DegenerateInputError
        A zero-area face (``mesh.faces``); a connected component without a handle
        (``handles``).

    Notes
    -----
    **The right-hand side is the free rows of** :math:`L p`. The system is sometimes
    written :math:`L_{ff}\, p'_f = L_{ff}\, p - L_{fp}\, c`; the product there must be the
    free rows of the whole :math:`L p`, :math:`(L p)_f = L_{ff} p_f + L_{fp} p_p`, the
    Laplacian coordinates of the rest shape: with :math:`L_{ff} p_f` alone the rest shape
    would not be reproduced with the handles at rest. With the right-hand side above, the
    handles at rest give the rest shape exactly. With cotangent
    weights this is the same deformation as :func:`~algorithms.deformation.harmonic`:
    :math:`L_{ff} p'_f = (Lp)_f - L_{fp} c` is :math:`L_{ff} u_f = -L_{fp} u_p` for the
    displacement :math:`u = p' - p`. The edge vectors keep their directions: the method does
    not rotate details (see :func:`~algorithms.deformation.laplacian_editing` and
    :func:`~algorithms.deformation.arap`).

    References
    ----------
    .. [1] Y. Lipman, O. Sorkine, D. Cohen-Or, D. Levin, C. Rössl and H.-P. Seidel,
       "Differential coordinates for interactive mesh editing", Shape Modeling
       International, 181-190, 2004.
    .. [2] M. Botsch and O. Sorkine, "On linear variational surface deformation methods",
       IEEE TVCG 14(1), 213-230, 2008.

    Examples
    --------
    >>> import numpy as np
    >>> from algorithms.deformation import laplacian
    >>> v = np.array([[0, 0], [1, 0], [2, 0], [0, 1], [1, 1], [2, 1]], float)
    >>> f = np.array([[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4]])
    >>> res = laplacian((v, f), {"indices": [0, 3], "positions": v[[0, 3]] + [5, 0]})
    >>> bool(np.allclose(res.mesh.vertices, v + [5, 0]))   # a translation is free
    True
    """
    m = read_mesh(mesh)
    h = read_handles(handles, m)
    v = m.vertices
    pins = pins_of(m, h.indices, name="handles")
    L = mesh_laplacian(v, m.faces, kind=weights)
    delta = L @ v
    system = PinnedSystem(L, pins.indices, name="handles", check_components=False)
    x = system.solve(pins.values(h.positions, v), delta)
    u = x - v
    energy = float(np.einsum("ij,ij->", u, L @ u))
    return LaplacianResult(mesh=Mesh(x, m.faces), energy=np.array([energy]),
                           handle_residual=handle_residual(x, h))
