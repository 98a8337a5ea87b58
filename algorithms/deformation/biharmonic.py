r"""Biharmonic deformation: the handle displacements spread by the bi-Laplace equation."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Annotated

import numpy as np

from algorithms.core.mesh import Mesh, read_mesh
from algorithms.core.params import Ge, HandlesLike, Le, MeshLike, validate_params
from algorithms.core.types import FloatArray
from algorithms.deformation._common import handle_residual, read_handles
from algorithms.deformation.harmonic import k_harmonic

__all__ = ["BiharmonicResult", "biharmonic"]


@dataclass(frozen=True, eq=False)
class BiharmonicResult:
    """A mesh deformed by the k-harmonic (k ≥ 2) extension of its handle displacements.

    Attributes
    ----------
    mesh : Mesh
        The deformed mesh: the input's faces with the vertices moved; every handle vertex
        sits exactly on its target.
    energy : (k,) float array
        The discrete energy ``Σ uᵀ L (M⁻¹ L)^(k-1) u`` of the displacement, one value (a
        single linear solve).
    handle_residual : float
        The largest distance of a handle vertex from its target (0 up to rounding).
    """

    mesh: Mesh
    energy: FloatArray
    handle_residual: float


@validate_params
def biharmonic(mesh: MeshLike, handles: HandlesLike, *,
               order: Annotated[int, Ge(2), Le(3)] = 2) -> BiharmonicResult:
    r"""Biharmonic deformation.

    Spreads the handle displacements by the bi-Laplace equation L M⁻¹ L u = 0 (cotangent Laplacian,
    Voronoi mass), smooth at the handles; as igl.harmonic with k = 2 (or 3).

    The displacement :math:`u = p' - p` minimises the Laplacian energy
    :math:`\int (\Delta u)^2`, discretised with the cotangent Laplacian :math:`L` and the
    Voronoi mass matrix :math:`M`, with the handle displacements fixed:

    .. math::

        \min_u \sum_c u_c^\mathsf{T} L M^{-1} L\, u_c
        \quad\Longrightarrow\quad Q_{ff} u_f = -Q_{fp} u_p,\quad Q = L M^{-1} L,
        \qquad p' = p + u.

    Thin-plate-like: smooth (:math:`C^1`) at the handles, so handle regions (several
    vertices moved together) carry their rotation into the surroundings. ``order=3``
    (:math:`Q = L M^{-1} L M^{-1} L`, triharmonic) is smoother still.
    ``igl.harmonic(V, F, b, bc, k)`` with ``k = order`` and ``bc`` the handle
    displacements computes the same.

    Parameters
    ----------
    mesh : Mesh or {"vertices", "faces"}
        The rest shape: ``(n, 2)`` or ``(n, 3)`` vertices and ``(m, 3)`` triangles of
        0-based vertex indices, no zero-area ones. Vertices no face uses stay where they
        are.
    handles : Handles or {"indices", "positions"}
        The vertices to move and their targets: ``(p,)`` distinct vertex indices and their
        ``(p, d)`` positions; at least one handle in every connected component (two rings
        of handles pin a boundary's position and slope).
    order : {2, 3}, default 2
        The power ``k`` of the Laplacian: 2 (biharmonic, :math:`Q = L M^{-1} L`) or 3
        (triharmonic, smoother still).

    Returns
    -------
    BiharmonicResult
        ``mesh``, ``energy`` (one value) and ``handle_residual``.

    Raises
    ------
    InvalidInputError
        Malformed mesh or handles (the field names the input); ``order`` not 2 or 3.
    DegenerateInputError
        A zero-area face (``mesh.faces``); a connected component without a handle
        (``handles``).

    Notes
    -----
    **The mass matrix between the Laplacians.** The bending energy :math:`\min \sum_c \lVert
    H(F_c)\rVert^2` is often discretised as :math:`L_{cot}^2\, x = 0`; the mass matrix
    between the two Laplacians, :math:`L M^{-1} L`, makes the discretisation independent of
    the mesh's resolution (each :math:`L` integrates over a vertex's area, :math:`M^{-1}`
    turns that back into a pointwise value). As in :func:`~algorithms.deformation.harmonic`,
    the equation holds for the displacement. :math:`Q` is formed explicitly (two-ring
    sparsity) and factored once.

    References
    ----------
    .. [1] M. Botsch and L. Kobbelt, "An intuitive framework for real-time freeform
       modeling", ACM TOG 23(3), 630-634, 2004.
    .. [2] A. Jacobson, E. Tosun, O. Sorkine and D. Zorin, "Mixed finite elements for
       variational surface modeling", Computer Graphics Forum 29(5), 2010.

    Examples
    --------
    >>> import numpy as np
    >>> from algorithms.deformation import biharmonic
    >>> v = np.array([[0, 0], [1, 0], [2, 0], [0, 1], [1, 1], [2, 1]], float)
    >>> f = np.array([[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4]])
    >>> res = biharmonic((v, f), {"indices": [0, 1, 2, 3, 4, 5], "positions": v + 1})
    >>> res.handle_residual, round(float(res.energy[0]), 12)   # a translation bends nothing
    (0.0, 0.0)
    """
    m = read_mesh(mesh)
    h = read_handles(handles, m)
    x, energy = k_harmonic(m, h.indices, h.positions, order)
    return BiharmonicResult(mesh=Mesh(x, m.faces), energy=np.array([energy]),
                            handle_residual=handle_residual(x, h))
