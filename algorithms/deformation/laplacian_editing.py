r"""Laplacian surface editing (Sorkine et al. 2004): Laplacian coordinates that rotate and
scale with the surface, through per-vertex linearised similarity transforms."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal, get_args

import numpy as np
import scipy.sparse as sp

from algorithms.core.errors import DegenerateInputError
from algorithms.core.laplacian import mesh_laplacian, normalized_laplacian, uniform_weights
from algorithms.core.linsolve import PinnedSystem
from algorithms.core.mesh import Mesh, read_mesh
from algorithms.core.params import HandlesLike, MeshLike, validate_params
from algorithms.core.types import FloatArray, IntArray
from algorithms.deformation._common import check_spread, handle_residual, pins_of, read_handles

__all__ = ["LaplacianEditingResult", "laplacian_editing", "WEIGHTS"]

Weights = Literal["uniform", "cotangent"]
#: The accepted values of ``weights``.
WEIGHTS = get_args(Weights)


@dataclass(frozen=True, eq=False)
class LaplacianEditingResult:
    """A mesh deformed by Laplacian surface editing.

    Attributes
    ----------
    mesh : Mesh
        The deformed mesh: the input's faces with the vertices moved; every handle vertex
        sits exactly on its target.
    energy : (k,) float array
        ``Σ_i ‖T_i δ_i − L(p')_i‖²``, one value (a single linear least-squares solve); 0
        when the handles stay at rest or move by one similarity transform.
    handle_residual : float
        The largest distance of a handle vertex from its target (0 up to rounding).
    """

    mesh: Mesh
    energy: FloatArray
    handle_residual: float


def _ring_pairs(n: int, L: sp.csr_array) -> tuple[IntArray, IntArray]:
    """``(i, j)`` for every ``j`` in the closed one-ring of ``i`` (``j = i`` included),
    sorted by ``i``: the non-zeros of ``L`` plus its diagonal."""
    coo = sp.coo_array(L)
    row, col = coo.row.astype(np.int64), coo.col.astype(np.int64)   # n² overflows int32
    keys = np.unique(np.concatenate([row * n + col, np.arange(n, dtype=np.int64) * (n + 1)]))
    return keys // n, keys % n


def _blocks(p: FloatArray) -> FloatArray:
    r"""The matrix :math:`A(p)` with :math:`T p = A(p)\,\theta` for the linearised
    similarity :math:`\theta` (rows: coordinates; columns: parameters).

    2-D: :math:`\theta = (s, w, t_x, t_y)`, :math:`T p = (s p_x - w p_y + t_x,
    w p_x + s p_y + t_y)`. 3-D: :math:`\theta = (s, h_1, h_2, h_3, t)`,
    :math:`T p = s p + h \times p + t`.
    """
    k, d = p.shape
    if d == 2:
        a = np.zeros((k, 2, 4))
        a[:, 0, 0], a[:, 0, 1], a[:, 0, 2] = p[:, 0], -p[:, 1], 1.0
        a[:, 1, 0], a[:, 1, 1], a[:, 1, 3] = p[:, 1], p[:, 0], 1.0
        return a
    x, y, z = p[:, 0], p[:, 1], p[:, 2]
    a = np.zeros((k, 3, 7))
    a[:, 0, 0], a[:, 0, 2], a[:, 0, 3], a[:, 0, 4] = x, z, -y, 1.0     # s x + h2 z - h3 y
    a[:, 1, 0], a[:, 1, 1], a[:, 1, 3], a[:, 1, 5] = y, -z, x, 1.0     # s y - h1 z + h3 x
    a[:, 2, 0], a[:, 2, 1], a[:, 2, 2], a[:, 2, 6] = z, y, -x, 1.0     # s z + h1 y - h2 x
    return a


def editing_matrix(vertices: FloatArray, faces: IntArray, weights: Weights = "uniform"
                   ) -> sp.csr_array:
    r"""The sparse ``(d n) × (d n)`` matrix :math:`E` with :math:`(E x)_i = T_i(x)\,\delta_i
    - L(x)_i`, coordinates interleaved (row ``d i + c`` is coordinate ``c`` of vertex ``i``).

    :math:`T_i(x)` is the linearised similarity that best maps the closed one-ring of
    :math:`i` in the rest shape onto the same vertices of :math:`x` (least squares, linear
    in :math:`x`), and :math:`\delta = L p` the rest shape's Laplacian coordinates.
    """
    n, d = vertices.shape
    if weights == "uniform":
        L = normalized_laplacian(uniform_weights(n, faces), kind="row")
    else:
        L = mesh_laplacian(vertices, faces, kind="cotangent")
        deg = L.diagonal()
        inv = np.divide(1.0, deg, out=np.zeros_like(deg), where=deg > 0)
        L = (sp.diags_array(inv, format="csr") @ L).tocsr()
    delta = L @ vertices
    ri, rj = _ring_pairs(n, L)
    # A(p) is affine in p: A(p) = Σ_a m_a(p) B_a with monomials m = (1, p_1, .., p_d) and
    # constant B_a, so the per-vertex Gram matrix Σ_j A(p_j)ᵀ A(p_j) needs only the ring's
    # second moments Σ_j m_a m_b, and ∂(T_i δ_i)/∂x_j = Σ_a m_a(p_j) (D_i G_i B_aᵀ): no
    # (pairs, d, q) array is ever formed.
    basis = _blocks(np.vstack([np.zeros(d), np.eye(d)]))        # A(0), A(e_1), ...
    basis[1:] -= basis[0]                                       # B_0 = A(0), B_a = ∂A/∂p_a
    mono = np.column_stack([np.ones(rj.shape[0]), vertices[rj]])  # (pairs, 1 + d)
    starts = np.flatnonzero(np.r_[True, ri[1:] != ri[:-1]])    # every i has a pair (i, i)
    moments = np.add.reduceat(mono[:, :, None] * mono[:, None, :], starts, axis=0)
    ata = np.einsum("nab,adq,bdr->nqr", moments, basis, basis)  # (n, q, q)
    # Gram matrices of a closed one-ring are invertible unless the ring is degenerate;
    # pinv keeps isolated vertices (no ring) harmless.
    g = np.linalg.pinv(ata)                                     # (n, q, q)
    # T_i δ_i = D_i θ_i with D_i = A(δ_i) minus its translation columns
    dmat = _blocks(delta)
    dmat[:, :, -d:] = 0.0
    dg = np.einsum("ndq,nqr->ndr", dmat, g)                      # (n, d, q)
    per_vertex = np.einsum("ndq,aeq->nade", dg, basis)          # (n, 1 + d, d, d)
    coef = np.zeros((ri.shape[0], d, d))                        # ∂(T_i δ_i) / ∂x_j
    for a_ in range(d + 1):
        coef += mono[:, a_, None, None] * per_vertex[ri, a_]
    shape = coef.shape
    rows = np.broadcast_to(ri[:, None, None] * d + np.arange(d)[None, :, None], shape)
    cols = np.broadcast_to(rj[:, None, None] * d + np.arange(d)[None, None, :], shape)
    t_part = sp.coo_array((coef.ravel(), (rows.ravel(), cols.ravel())), shape=(d * n, d * n))
    l_part = sp.kron(L, sp.eye_array(d), format="csr")
    out: sp.csr_array = (t_part.tocsr() - l_part).tocsr()
    return out


@validate_params
def laplacian_editing(mesh: MeshLike, handles: HandlesLike, *, weights: Weights = "uniform"
                      ) -> LaplacianEditingResult:
    r"""Laplacian surface editing (linearised per-vertex similarities).

    Laplacian coordinates that rotate and scale with the surface: min Σ‖T_i(x') δ_i − L(x')_i‖² with
    each T_i the linearised similarity fitted to the vertex's one-ring, handles fixed; one sparse
    least-squares solve.

    With the rest shape's Laplacian coordinates :math:`\delta_i = L(p)_i`, solve

    .. math::

        \min_{p'} \sum_i \lVert T_i(p')\, \delta_i - L(p')_i \rVert^2
        \quad\text{s.t. } p'_h = c_h,

    where :math:`T_i(p')` is the similarity transform — linearised, so that the problem
    stays linear — that best maps the closed one-ring :math:`\{i\} \cup N(i)` of the rest
    shape onto the new positions:
    :math:`T_i = \arg\min_T \sum_{j} \lVert T p_j - p'_j \rVert^2` with
    :math:`T p = s p + h \times p + t` in 3-D (:math:`(s, h, t)`, 7 parameters) and
    :math:`T p = \begin{psmallmatrix} s & -w \\ w & s \end{psmallmatrix} p + t` in 2-D.
    Each :math:`T_i` is a linear function of :math:`p'` (a least-squares fit), so the whole
    problem is one sparse linear least-squares system in the :math:`d n` coordinates,
    coupled across coordinates, solved through its normal equations with the handles
    eliminated (factored once).

    Parameters
    ----------
    mesh : Mesh or {"vertices", "faces"}
        The rest shape: ``(n, 2)`` or ``(n, 3)`` vertices and ``(m, 3)`` triangles of
        0-based vertex indices, no zero-area ones. Vertices no face uses stay where they
        are.
    handles : Handles or {"indices", "positions"}
        The vertices to move and their targets: ``(p,)`` distinct vertex indices and their
        ``(p, d)`` positions. Every connected component needs handles whose rest positions
        span a plane in 3-D (three not on a line) or a line in 2-D (two distinct): fewer
        leave a global similarity transform about them undetermined.
    weights : {"uniform", "cotangent"}, default "uniform"
        The Laplacian: ``"uniform"`` gives :math:`\delta_i = p_i - \operatorname{mean}_j
        p_j` (the paper's), ``"cotangent"`` the cotangent-weighted average instead (both
        row-normalised).

    Returns
    -------
    LaplacianEditingResult
        ``mesh``, ``energy`` (one value) and ``handle_residual``.

    Raises
    ------
    InvalidInputError
        Malformed mesh or handles (the field names the input), an unknown ``weights``.
    DegenerateInputError
        A zero-area face (``mesh.faces``); a connected component without enough handles
        (``handles``).

    Notes
    -----
    The fit of :math:`T_i` is a per-vertex transform with a point error over the closed
    one-ring, :math:`\min \lVert p'_i - (A_i p_i + b)\rVert^2 + \sum_{j} \lVert p'_j -
    (A_i p_j + b)\rVert^2`, with :math:`A_i` a linearised similarity. As in the paper, the handles
    are hard constraints here (the paper's soft weighted version converges to this as the
    weights grow), and the linearisation means large rotations also scale the details
    (the paper's Fig. 5; ARAP does not, see :func:`~algorithms.deformation.arap`). With
    the handles at rest the rest shape is the exact solution (zero energy).

    References
    ----------
    .. [1] O. Sorkine, D. Cohen-Or, Y. Lipman, M. Alexa, C. Rössl and H.-P. Seidel,
       "Laplacian surface editing", Symposium on Geometry Processing, 175-184, 2004.

    Examples
    --------
    >>> import numpy as np
    >>> from algorithms.deformation import laplacian_editing
    >>> v = np.array([[0, 0], [1, 0], [2, 0], [0, 1], [1, 1], [2, 1]], float)
    >>> f = np.array([[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4]])
    >>> res = laplacian_editing((v, f), {"indices": [0, 3], "positions": 2 * v[[0, 3]]})
    >>> bool(np.allclose(res.mesh.vertices, 2 * v))   # a similarity is reproduced
    True
    """
    m = read_mesh(mesh)
    h = read_handles(handles, m)
    v, f = m.vertices, m.faces
    n, d = v.shape
    pins = pins_of(m, h.indices, name="handles")
    check_spread(pins, v[h.indices], d - 1, name="handles",
                 what="three handles not on one line" if d == 3 else "two distinct handles",
                 why="fewer leave a similarity transform about them undetermined")
    E = editing_matrix(v, f, weights)
    normal = (E.T @ E).tocsr()
    pinned = (pins.indices[:, None] * d + np.arange(d)).ravel()
    try:
        system = PinnedSystem(normal, pinned, name="handles", check_components=False)
    except DegenerateInputError:
        raise DegenerateInputError(
            "Expected `handles` to determine the deformation, got a configuration that "
            "leaves it undetermined (the normal equations are singular).",
            field="handles") from None
    values = pins.values(h.positions, v).reshape(-1, 1)
    x = system.solve(values).reshape(n, d)
    r = E @ x.reshape(-1)
    energy = float(np.einsum("i,i->", r, r))
    return LaplacianEditingResult(mesh=Mesh(x, f), energy=np.array([energy]),
                                  handle_residual=handle_residual(x, h))
