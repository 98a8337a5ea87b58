r"""Laplacian-preserving deformation: keep every vertex's Laplacian coordinate, move the
handles."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from algorithms.core.laplacian import mesh_laplacian
from algorithms.core.linsolve import PinnedSystem
from algorithms.core.mesh import Mesh
from algorithms.core.types import FloatArray
from algorithms.core.validation import as_choice
from algorithms.deformation._common import handle_residual, pins_of, read_handles, read_mesh

__all__ = ["LaplacianResult", "laplacian", "WEIGHTS"]

#: The accepted values of ``weights``.
WEIGHTS = ("cotangent", "uniform", "tangent")


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


def laplacian(mesh: Any, handles: Any, *, weights: str = "cotangent") -> LaplacianResult:
    r"""Move the handles to their targets and every other vertex so that the edge vectors
    change as little as possible.

    .. math::

        \min_{p'} \sum_{(i,j)} w_{ij} \lVert (p'_i - p'_j) - (p_i - p_j) \rVert^2
        \quad\text{s.t. } p'_h = c_h
        \quad\Longrightarrow\quad L_{ff}\, p'_f = (L p)_f - L_{fp}\, c,

    one sparse solve per coordinate (all coordinates as columns of one factored system):
    the Laplacian coordinates :math:`\delta = L p` are kept wherever no handle pins the
    vertex.

    Parameters
    ----------
    mesh : Mesh or (vertices, faces)
        ``(n, 2)`` or ``(n, 3)`` vertices, ``(m, 3)`` faces without zero-area ones.
        Vertices no face uses stay where they are.
    handles : Handles or {"indices", "positions"}
        Distinct vertex indices and their ``(p, d)`` targets; at least one in every
        connected component.
    weights : {"cotangent", "uniform", "tangent"}, default "cotangent"
        The edge weights :math:`w_{ij}` of :math:`L = D - W`
        (:func:`~algorithms.core.laplacian.mesh_laplacian`): cotangent (the Dirichlet
        energy; may be negative on obtuse triangles), uniform (the graph Laplacian, as in
        Sorkine et al.'s Laplacian coordinates), or tangent (incentre weights, never
        negative).

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
    The seed document's "Laplacian preserving deformation": identity transforms, edge
    error; "solve :math:`L_{00} x' = L_{00} x - L_{01} c`". Its right-hand side is
    :math:`(L x)_0 = L_{00} x_0 + L_{01} x_1`, the Laplacian coordinates of the rest shape
    (the seed's :math:`L_{00} x` reads as the free rows of :math:`L x`: with
    :math:`L_{00} x_0` alone the rest shape would not be reproduced with the handles at
    rest). With the handles at rest the rest shape is the exact solution. With cotangent
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
    kind = as_choice(weights, WEIGHTS, name="weights")
    v = m.vertices
    pins = pins_of(m, h.indices, name="handles")
    L = mesh_laplacian(v, m.faces, kind=kind)
    delta = L @ v
    system = PinnedSystem(L, pins.indices, name="handles", check_components=False)
    x = system.solve(pins.values(h.positions, v), delta)
    u = x - v
    energy = float(np.einsum("ij,ij->", u, L @ u))
    return LaplacianResult(mesh=Mesh(x, m.faces), energy=np.array([energy]),
                           handle_residual=handle_residual(x, h))
