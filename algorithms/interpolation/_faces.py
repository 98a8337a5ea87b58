r"""The per-face machinery of ``arap`` and ``poisson``: per-face affine maps from the source
to the target, their polar decompositions, the gradient operator that turns vertex
positions into per-face linear maps, and the pinned global solve, factored once and
solved per frame.

Per-face maps
-------------
Face :math:`f` with corners :math:`p_0, \dots, p_{k-1}` has the edge matrix
:math:`E_f = [p_1 - p_0, \dots, p_{k-1} - p_0]` (``d × (k-1)``). Its *frame* is
:math:`E_f` itself for triangles in the plane and tetrahedra, and for triangles in space
:math:`[p_1 - p_0,\ p_2 - p_0,\ n / \sqrt{\lVert n\rVert}]` with :math:`n` the cross
product of the two edges (the face normal as third axis, scaled like a length; Sumner &
Popović's fourth vertex, which Xu et al. use too). The map of the face is
:math:`A_f = F'_f F_f^{-1}` (``F'`` the target's frame): it sends every edge of the
source face to the matching edge of the target face and, in space, the normal to the
normal.

Gradient operator
-----------------
For positions :math:`X` (``n × d``) the linear map the face *takes* is
:math:`B_f(X) = [x_1 - x_0, \dots] E_f^{+}` with :math:`E_f^+ = (E_f^\mathsf{T}
E_f)^{-1} E_f^\mathsf{T}`: it agrees with every edge and, for triangles in space, sends
the normal to zero. :math:`B_f(X)^\mathsf{T} = G_f X` with :math:`G_f` a ``d × n`` block
of ``k`` non-zero columns; row :math:`r` of :math:`B_f(X)` is the gradient of
coordinate :math:`r` over the face. Stacking the blocks gives the sparse :math:`G`
(``m d × n``), and with face weights :math:`w_f`

.. math::

    \min_X \sum_f w_f \lVert G_f X - A_f(t)^\mathsf{T} \rVert_F^2 \quad\Longrightarrow\quad
    (G^\mathsf{T} W G)\, X = G^\mathsf{T} W\, [A_f(t)^\mathsf{T}]_f .

For triangles in space only the in-plane part of :math:`A_f(t)` enters (:math:`E_f^+ n
= 0`). With area weights :math:`G^\mathsf{T} W G` is the cotangent Laplacian (tested
against :func:`~algorithms.core.laplacian.cotangent_laplacian` and ``igl.cotmatrix``).
"""

from __future__ import annotations

from typing import Any

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components, dijkstra

from algorithms.core.linalg import batched_polar, det
from algorithms.core.linsolve import PinnedSystem
from algorithms.core.mesh import components
from algorithms.core.progress import Progress, as_progress
from algorithms.core.types import FloatArray, IntArray
from algorithms.interpolation._common import (
    Pair,
    check_anchor,
    rotation_exp,
    rotation_log,
    row_keys,
)

__all__ = [
    "face_frames",
    "face_measures",
    "gradient_operator",
    "face_dets",
    "face_adjacency",
    "unwrap_rotations",
    "anchors_of",
    "FacePath",
]


def _edges(v: FloatArray, f: IntArray) -> FloatArray:
    """``(m, d, k-1)``: the edge vectors from corner 0, as columns."""
    p = v[f]
    return np.swapaxes(p[:, 1:] - p[:, :1], 1, 2)


def face_frames(v: FloatArray, f: IntArray) -> FloatArray:
    """The ``(m, d, d)`` frame of every face (see the module docstring)."""
    e = _edges(v, f)
    if e.shape[1] == e.shape[2]:
        return e
    nrm = np.cross(e[:, :, 0], e[:, :, 1])
    size = np.sqrt(np.linalg.norm(nrm, axis=1, keepdims=True))
    nrm = np.divide(nrm, size, out=np.zeros_like(nrm), where=size > 0)
    return np.concatenate([e, nrm[:, :, None]], axis=2)


def face_measures(v: FloatArray, f: IntArray) -> FloatArray:
    """Area of every triangle or volume of every tetrahedron (unsigned)."""
    e = _edges(v, f)
    if e.shape[2] == 3:
        dets: FloatArray = np.linalg.det(e)
        return np.abs(dets) / 6.0
    if e.shape[1] == 2:
        cross: FloatArray = e[:, 0, 0] * e[:, 1, 1] - e[:, 0, 1] * e[:, 1, 0]
        return 0.5 * np.abs(cross)
    norms: FloatArray = np.linalg.norm(np.cross(e[:, :, 0], e[:, :, 1]), axis=1)
    return 0.5 * norms


def face_dets(source: FloatArray, frames: FloatArray, f: IntArray) -> FloatArray:
    """Per frame, the smallest ratio of a face's signed area (volume) to its source's; for
    triangles in space the unsigned area ratio. ``frames`` is ``(T, n, d)``."""
    e0 = _edges(source, f)
    square = e0.shape[1] == e0.shape[2]

    def size(e: FloatArray) -> FloatArray:
        if square:
            return np.asarray(det(e))
        norms: FloatArray = np.linalg.norm(np.cross(e[:, :, 0], e[:, :, 1]), axis=1)
        return norms

    base = size(e0)
    out = np.empty(frames.shape[0])
    for i, x in enumerate(frames):
        ratio = size(_edges(x, f)) / base
        out[i] = ratio.min() if ratio.size else 1.0
    return out


def gradient_operator(v: FloatArray, f: IntArray) -> sp.csr_array:
    """The sparse ``(m d, n)`` operator :math:`G` with :math:`G_f X = B_f(X)^\\mathsf{T}`."""
    m, k = f.shape
    n, d = v.shape
    e = _edges(v, f)                                           # (m, d, k-1)
    pinv = np.linalg.solve(np.swapaxes(e, 1, 2) @ e, np.swapaxes(e, 1, 2))  # (m, k-1, d)
    coef = np.empty((m, k, d))
    coef[:, 1:] = pinv
    coef[:, 0] = -pinv.sum(axis=1)
    rows = (np.arange(m)[:, None, None] * d + np.arange(d)[None, None, :])
    rows = np.broadcast_to(rows, (m, k, d))
    cols = np.broadcast_to(f[:, :, None], (m, k, d))
    g = sp.coo_array((coef.ravel(), (rows.ravel(), cols.ravel())), shape=(m * d, n))
    return g.tocsr()


def face_adjacency(f: IntArray) -> sp.csr_array:
    """Faces sharing a side (an edge of a triangle, a triangle of a tetrahedron), as a
    symmetric ``(m, m)`` 0/1 matrix; around a side shared by more than two faces, the
    faces are chained."""
    m, k = f.shape
    sides = np.sort(np.stack([np.delete(f, c, axis=1) for c in range(k)], axis=1), axis=2)
    inv = row_keys(sides.reshape(m * k, k - 1), int(f.max()) + 1)
    owner = np.repeat(np.arange(m), k)
    order = np.argsort(inv, kind="stable")
    same = inv[order][1:] == inv[order][:-1]
    a, b = owner[order][:-1][same], owner[order][1:][same]
    g = sp.coo_array((np.ones(2 * a.size), (np.concatenate([a, b]), np.concatenate([b, a]))),
                     shape=(m, m)).tocsr()
    g.data[:] = 1.0
    return g


def unwrap_rotations(w: FloatArray, adjacency: sp.csr_array) -> FloatArray:
    r"""Make per-face rotation vectors continuous across the mesh.

    Each face's rotation vector is only defined up to whole turns: :math:`\theta + 2\pi k`
    in 2-D, :math:`w + 2\pi k\,\hat w` in 3-D. Per connected component (through shared
    sides), the face with the smallest angle keeps its shortest-arc vector; every other face
    takes, in breadth-first order, the representative nearest the face it was reached from.
    A bar bent by more than half a turn then turns continuously instead of splitting where
    its faces' shortest arcs change direction.
    """
    m = w.shape[0]
    if m == 0:
        return w
    out = w.copy()
    angle = np.linalg.norm(w, axis=1)
    count, labels = connected_components(adjacency, directed=False)
    roots = np.empty(count, dtype=np.int64)
    order = np.lexsort((np.arange(m), angle, labels))
    first = np.flatnonzero(np.r_[True, labels[order][1:] != labels[order][:-1]])
    roots[labels[order][first]] = order[first]
    dist, pred, _ = dijkstra(adjacency, directed=False, indices=roots, unweighted=True,
                             return_predecessors=True, min_only=True)
    dist = np.where(np.isfinite(dist), dist, 0).astype(np.int64)
    two_pi = 2.0 * np.pi
    for level in range(1, int(dist.max()) + 1):
        idx = np.flatnonzero(dist == level)
        ref = out[pred[idx]]
        if w.shape[1] == 1:
            out[idx] += two_pi * np.round((ref - out[idx]) / two_pi)
        else:
            theta = angle[idx]
            ok = theta > 1e-12
            axis = np.zeros_like(ref)
            axis[ok] = out[idx][ok] / theta[ok, None]
            k = np.round((np.einsum("ij,ij->i", axis, ref) - theta) / two_pi)
            k[~ok] = 0.0
            out[idx] += (two_pi * k)[:, None] * axis
    return out


def anchors_of(n: int, f: IntArray, anchor: Any) -> IntArray:
    """One vertex per connected component: ``anchor`` in its own, the lowest-numbered
    vertex in every other one (vertices no face uses are components of their own)."""
    a = check_anchor(anchor, n)
    k = f.shape[1]
    pairs = np.concatenate([f[:, [i, j]] for i in range(k) for j in range(i + 1, k)])
    count, labels = components(n, pairs)
    first = np.full(count, n, dtype=np.int64)
    np.minimum.at(first, labels, np.arange(n))
    first[labels[a]] = a
    return first


class FacePath:
    """Per-face interpolation of ``pair`` and the global least-squares solve, factored once.

    Parameters
    ----------
    pair : Pair
        Source and target on the same faces (triangles in 2-D or 3-D, tetrahedra).
    weights : (m,) float array
        The face weights :math:`w_f` of the objective.
    rotations : (m, r) float array
        The rotation vector of each face's map (from :meth:`decompose`, possibly
        unwrapped).
    stretch : (m, d, d) float array
        The symmetric factor of each face's map.
    system : sparse (n, n), optional
        :math:`G^\\mathsf{T} W G` when the caller has it in another form (the cotangent
        Laplacian); assembled here otherwise.
    anchor : int
        The vertex held on its straight path (see :func:`anchors_of`).
    solves : int
        How many frames will be solved: the solver backend is chosen for that many
        solves (:class:`~algorithms.core.linsolve.Factor`).
    """

    def __init__(self, pair: Pair, weights: FloatArray, rotations: FloatArray,
                 stretch: FloatArray, *, anchor: Any = 0, system: Any = None,
                 solves: int = 1) -> None:
        self.pair = pair
        self.d = pair.dim
        self.grad = gradient_operator(pair.source, pair.faces)
        self.weights = weights
        self.rotations = rotations
        self.stretch = stretch
        self.gtw = (self.grad.T @ sp.diags_array(np.repeat(weights, self.d))).tocsr()
        lap = system if system is not None else (self.gtw @ self.grad).tocsr()
        self.pins = anchors_of(pair.n, pair.faces, anchor)
        self.solver = PinnedSystem(lap, self.pins, name="anchor", solves=solves,
                                   check_components=False)

    @staticmethod
    def decompose(pair: Pair) -> tuple[FloatArray, FloatArray]:
        """Per face, the shortest-arc rotation vector and the stretch of ``A_f = R_f S_f``
        (proper polar decomposition: ``R_f`` a rotation even for a flipped face, whose
        ``S_f`` then has one negative eigenvalue, as ``affine``'s ``reflection="flip"``)."""
        src = face_frames(pair.source, pair.faces)
        dst = face_frames(pair.target, pair.faces)
        a = np.swapaxes(np.linalg.solve(np.swapaxes(src, 1, 2), np.swapaxes(dst, 1, 2)), 1, 2)
        rot, stretch = batched_polar(a, proper=True)
        return rotation_log(rot), stretch

    def maps(self, t: float) -> FloatArray:
        """``A_f(t) = exp(t log R_f) ((1 - t) I + t S_f)`` for every face."""
        s_t = (1.0 - t) * np.eye(self.d) + t * self.stretch
        return rotation_exp(t * self.rotations, self.d) @ s_t

    def frame(self, t: float) -> FloatArray:
        """The vertex positions at time ``t``."""
        at = np.swapaxes(self.maps(t), 1, 2).reshape(-1, self.d)   # stacked A_f(t)ᵀ
        rhs = self.gtw @ at
        src, tgt = self.pair.source, self.pair.target
        pinned = (1.0 - t) * src[self.pins] + t * tgt[self.pins]
        return self.solver.solve(pinned, rhs)

    def run(self, times: FloatArray, progress: Progress | None,
            label: str) -> FloatArray:
        """All frames, ``(T, n, d)``, reporting ``progress`` after each."""
        report = as_progress(progress)
        frames = np.empty((times.shape[0],) + self.pair.source.shape)
        total = times.shape[0]
        for i, t in enumerate(times):
            frames[i] = self.frame(float(t))
            report(i + 1, total, f"{label}: frame {i + 1} of {total}")
        return frames
