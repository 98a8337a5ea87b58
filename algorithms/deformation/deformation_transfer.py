r"""Deformation transfer (Sumner & Popović 2004): make a target mesh take on the
per-triangle deformation of a source mesh with the same connectivity."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp

from algorithms.core.errors import DegenerateInputError, InvalidInputError
from algorithms.core.linsolve import PinnedSystem
from algorithms.core.mesh import DEGENERATE_RTOL, Handles, Mesh, read_mesh
from algorithms.core.params import HandlesLike, MeshLike, PointsLike, validate_params
from algorithms.core.types import FloatArray, IntArray
from algorithms.core.validation import as_points
from algorithms.deformation._common import check_handles, handle_residual, pins_of

__all__ = ["DeformationTransferResult", "deformation_transfer", "check_deformation_transfer",
           "frames"]


@dataclass(frozen=True, eq=False)
class DeformationTransferResult:
    """The target mesh deformed like the source.

    Attributes
    ----------
    mesh : Mesh
        The deformed target: the input's faces with the vertices moved; every handle vertex
        sits exactly on its target.
    energy : (k,) float array
        ``Σ_c ‖T_c − Q_c‖²_F``, the squared mismatch between the target's per-face
        transforms and the source's, one value (a single linear least-squares solve).
    handle_residual : float
        The largest distance of a handle vertex from its target (0 up to rounding).
    """

    mesh: Mesh
    energy: FloatArray
    handle_residual: float


def frames(vertices: FloatArray, faces: IntArray) -> FloatArray:
    r"""The edge frame of each face: columns :math:`v_2 - v_1,\ v_3 - v_1` and, in 3-D,
    the scaled normal :math:`(v_2 - v_1) \times (v_3 - v_1) / \sqrt{\lVert (v_2 - v_1)
    \times (v_3 - v_1) \rVert}` (Sumner & Popović's fourth vertex minus :math:`v_1`).

    Returns
    -------
    (m, d, d) float array
    """
    p = vertices[faces]
    e1, e2 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    if vertices.shape[1] == 2:
        return np.stack([e1, e2], axis=2)
    nrm = np.cross(e1, e2)
    size = np.sqrt(np.linalg.norm(nrm, axis=1, keepdims=True))
    nrm = np.divide(nrm, size, out=np.zeros_like(nrm), where=size > 0)
    return np.stack([e1, e2, nrm], axis=2)


def _check_frames(vertices: FloatArray, faces: IntArray, name: str) -> None:
    p = vertices[faces]
    e1, e2, e3 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0], p[:, 2] - p[:, 1]
    if vertices.shape[1] == 2:
        dbl = np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])
    else:
        dbl = np.linalg.norm(np.cross(e1, e2), axis=1)
    longest = np.max([np.einsum("ij,ij->i", e, e) for e in (e1, e2, e3)], axis=0)
    bad = dbl <= DEGENERATE_RTOL * longest
    if bad.any():
        row = int(np.argmax(bad))
        raise DegenerateInputError(
            f"Expected `{name}` to give every face a non-zero area (its rest shape defines "
            f"the per-face transforms), got a degenerate face {faces[row].tolist()} at row "
            f"{row}.", field=name)


def check_deformation_transfer(mesh: Any, handles: Any, source: Any, source_deformed: Any
                               ) -> tuple[Mesh, Handles, FloatArray, FloatArray]:
    """Check the inputs of :func:`deformation_transfer`: handles that fit the mesh
    (:func:`~algorithms.deformation.check_handles`), ``source`` and ``source_deformed`` one
    row per vertex of the mesh, in its dimension. Returns the four checked."""
    m = mesh if isinstance(mesh, Mesh) else read_mesh(mesh)
    h = check_handles(m, handles)
    n, d = m.vertices.shape
    src = as_points(source, name="source", dim=d)
    dst = as_points(source_deformed, name="source_deformed", dim=d)
    for name, arr in (("source", src), ("source_deformed", dst)):
        if arr.shape[0] != n:
            raise InvalidInputError(
                f"Expected `{name}` to hold one row per vertex of `mesh` ({n}), got "
                f"{arr.shape[0]}.", field=name)
    return m, h, src, dst


@validate_params
def deformation_transfer(
    mesh: MeshLike,
    handles: HandlesLike,
    *,
    source: PointsLike,
    source_deformed: PointsLike,
) -> DeformationTransferResult:
    r"""Deformation transfer (same connectivity).

    Gives the target mesh the per-face deformation gradients of a source mesh that deforms from
    source to source_deformed (same faces): min Σ‖T_c − Q_c‖²_F with shared vertices (and, in 3-D, a
    free fourth vertex per face); one factored solve.

    The three share connectivity: ``source`` and ``source_deformed`` are vertex arrays on
    ``mesh.faces`` (face ``c`` of the source corresponds to face ``c`` of the target). For
    each face, the source's deformation gradient is :math:`Q_c = \tilde V'_c
    \tilde V_c^{-1}` with :math:`\tilde V` the face's edge frame (:func:`frames`; in 3-D the
    third column is the scaled normal, Sumner & Popović's fourth vertex). The target's new
    vertices :math:`x` (plus, in 3-D, one free fourth vertex per face) minimise

    .. math::

        \min_{x} \sum_c \lVert T_c(x) - Q_c \rVert_F^2, \qquad
        T_c(x) = \tilde X_c\, \tilde W_c^{-1},

    :math:`\tilde W_c` the target's rest frame and :math:`\tilde X_c` the frame of the
    unknowns, with the handle vertices held at their targets. :math:`T_c` is linear in
    :math:`x`, the coordinates separate, and the normal equations
    :math:`A^\mathsf{T} A x = A^\mathsf{T} q` are factored once for all coordinates.

    Parameters
    ----------
    mesh : Mesh or {"vertices", "faces"}
        The target in its rest shape: ``(n, 2)`` or ``(n, 3)`` vertices and ``(m, 3)``
        triangles of 0-based vertex indices, no zero-area ones. Vertices no face uses stay
        where they are.
    handles : Handles or {"indices", "positions"}
        Target vertices held at given positions: ``(p,)`` distinct vertex indices and their
        ``(p, d)`` positions; at least one in every connected component (the per-face
        gradients leave a translation free). To transfer without user constraints, pin one
        vertex per component where the source's motion puts it (e.g. its rest position plus
        the source's displacement there).
    source : (n, d) float array
        The source's rest vertices on the faces of ``mesh`` (the same connectivity: vertex
        ``i`` corresponds to target vertex ``i``); no zero-area faces.
    source_deformed : (n, d) float array
        The source's deformed vertices, on the faces of ``mesh`` too.

    Returns
    -------
    DeformationTransferResult
        ``mesh``, ``energy`` (one value) and ``handle_residual``.

    Raises
    ------
    InvalidInputError
        Malformed inputs (the field names it); ``source`` or ``source_deformed`` without
        one row per target vertex or of another dimension.
    DegenerateInputError
        A zero-area face in the target (``mesh.faces``) or the source rest shape
        (``source``); a connected component without a handle (``handles``).

    Notes
    -----
    The per-face transforms are kept as close as possible to given ones,
    :math:`\min \sum_c \lVert A_c - A_c^{(0)}\rVert^2` subject to neighbouring triangles
    sharing vertices, with :math:`A_c` written through the face's edge basis (one corner as
    origin and its two edges as basis) so that the unknowns are the vertices.
    Sumner & Popović add the normal as a third basis vector so that the 3-D transform is
    defined; the fourth vertices are extra unknowns of the solve, as in the paper. The
    paper's correspondence step (meshes of different connectivity) is not part of this
    method: the correspondence is the identity on faces.

    If the source moves by one similarity transform (in 2-D: by any non-singular affine
    map) and the handles follow it, the target moves by that transform exactly. A general
    3-D affine map does not carry over exactly: it maps the scaled normal by its cofactor
    matrix, not by itself.

    References
    ----------
    .. [1] R. W. Sumner and J. Popović, "Deformation transfer for triangle meshes", ACM
       Transactions on Graphics 23(3), 399-405, 2004.

    Examples
    --------
    >>> import numpy as np
    >>> from algorithms.deformation import deformation_transfer
    >>> src = np.array([[0, 0], [1, 0], [0, 1], [1, 1]], float)
    >>> f = np.array([[0, 1, 3], [0, 3, 2]])
    >>> tgt = 2 * src                                        # a larger square
    >>> shear = np.array([[1.0, 0.5], [0.0, 1.0]])
    >>> res = deformation_transfer((tgt, f), {"indices": [0], "positions": [[0, 0]]},
    ...                            source=src, source_deformed=src @ shear.T)
    >>> bool(np.allclose(res.mesh.vertices, tgt @ shear.T))  # the shear carries over
    True
    """
    m, h, src, dst = check_deformation_transfer(mesh, handles, source, source_deformed)
    v, f = m.vertices, m.faces
    n, d = v.shape
    nf = f.shape[0]
    _check_frames(src, f, "source")
    pins = pins_of(m, h.indices, name="handles")

    q = np.einsum("mij,mjk->mik", frames(dst, f), np.linalg.inv(frames(src, f)))  # Q_c
    winv = np.linalg.inv(frames(v, f))                              # (m, d, d)
    # T_c[r, :] = Σ_k (x_{node k+1} - x_{node 0})[r] winv[k, :]: coefficient of node j on
    # entry (r, col) is coef[c, col, j] (the same for every coordinate r)
    nodes = 3 if d == 2 else 4
    coef = np.zeros((nf, d, nodes))
    coef[:, :, 1:] = np.transpose(winv, (0, 2, 1))                   # coef[c, col, 1+k]
    coef[:, :, 0] = -winv.sum(axis=1)
    node_ids = f if d == 2 else np.hstack([f, n + np.arange(nf)[:, None]])
    rows = np.broadcast_to((np.arange(nf)[:, None] * d + np.arange(d))[:, :, None],
                           coef.shape)
    cols = np.broadcast_to(node_ids[:, None, :], coef.shape)
    size = n + (nf if d == 3 else 0)
    A = sp.csr_array((coef.ravel(), (rows.ravel(), cols.ravel())), shape=(nf * d, size))
    # q[c, r, col] -> right-hand side column r, row c*d + col
    y = np.transpose(q, (0, 2, 1)).reshape(nf * d, d)
    normal = (A.T @ A).tocsr()
    system = PinnedSystem(normal, pins.indices, name="handles", check_components=False)
    x_all = system.solve(pins.values(h.positions, v), A.T @ y)
    r = A @ x_all - y
    x = np.ascontiguousarray(x_all[:n])
    energy = float(np.einsum("ij,ij->", r, r))
    return DeformationTransferResult(mesh=Mesh(x, f), energy=np.array([energy]),
                                     handle_residual=handle_residual(x, h))
