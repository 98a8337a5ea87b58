r"""Small dense linear algebra shared by the families: the orthogonal Procrustes core with the
reflection fix, the polar decomposition, numerical rank, homogeneous matrices.

Every function that takes a ``(d, d)`` matrix also takes a stack ``(..., d, d)`` of them and
works on the whole stack at once (one batched LAPACK call), which is what per-vertex or
per-face local steps (ARAP, ASAP) need; a single matrix is the stack of shape ``()``.

The reflection fix
------------------
For :math:`C = U \Sigma V^\mathsf{T}`, the orthogonal matrix :math:`R` that maximises
:math:`\operatorname{tr}(R^\mathsf{T} C)` is :math:`U V^\mathsf{T}`; the best *proper* one
(:math:`\det R = +1`) is :math:`U D V^\mathsf{T}` with
:math:`D = \operatorname{diag}(1, \dots, 1, \operatorname{sign}\det(U V^\mathsf{T}))`:
flipping the singular vector of the smallest singular value costs the least,
:math:`2\sigma_d` of the trace (Umeyama 1991, the matrix ``S`` of his lemma). Both the
rotation and the attained maximum :math:`\operatorname{tr}(D\Sigma)` come out of
:func:`procrustes`; similarity alignment needs the latter for its scale.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from algorithms.core.errors import InvalidInputError
from algorithms.core.types import BoolArray, FloatArray

__all__ = [
    "RANK_RTOL",
    "Procrustes",
    "procrustes",
    "polar",
    "det",
    "numerical_rank",
    "homogeneous",
    "batched_rotations",
    "RotationFitter",
    "batched_polar",
]

#: Singular values below this fraction of the largest count as zero (:func:`numerical_rank`).
RANK_RTOL = 1e-10


@dataclass(frozen=True, eq=False)
class Procrustes:
    """The solution of :math:`\\max_R \\operatorname{tr}(R^\\mathsf{T} C)` over orthogonal
    ``R`` (proper unless reflections are allowed), for one matrix or a stack.

    Attributes
    ----------
    rotation : (..., d, d) float array
        ``R = U D Vᵀ`` (``u @ vt``).
    u : (..., d, d) float array
        The left singular vectors of ``C`` with the fix applied: ``U D``.
    singular_values : (..., d) float array
        ``Σ``, non-negative, in decreasing order.
    vt : (..., d, d) float array
        The right singular vectors of ``C``, transposed: ``Vᵀ``.
    signs : (..., d) float array
        The diagonal of ``D``: all +1 except the last, which is -1 where the fix was applied.
    reflection : (...) bool array
        Where ``det R = -1`` (only possible with ``allow_reflection=True``).
    """

    rotation: FloatArray
    u: FloatArray
    singular_values: FloatArray
    vt: FloatArray
    signs: FloatArray
    reflection: BoolArray

    @property
    def trace(self) -> FloatArray:
        """``tr(Rᵀ C) = tr(D Σ)``, the attained maximum (``(...)``-shaped)."""
        attained: FloatArray = np.einsum("...i,...i->...", self.signs, self.singular_values)
        return attained


def det(m: Any) -> Any:
    """Determinant of a matrix or a stack; closed forms for ``d <= 3`` (where
    :func:`numpy.linalg.det` costs more than the SVD it accompanies)."""
    m = np.asarray(m)
    d = m.shape[-1]
    if m.ndim == 2 and d <= 3:  # one small matrix: Python floats beat numpy scalars
        rows = m.tolist()
        if d == 3:
            (a, b, c), (e, f, g), (h, i, j) = rows
            return a * (f * j - g * i) - b * (e * j - g * h) + c * (e * i - f * h)
        return rows[0][0] * rows[1][1] - rows[0][1] * rows[1][0] if d == 2 else rows[0][0]
    if d == 1:
        return m[..., 0, 0]
    if d == 2:
        return m[..., 0, 0] * m[..., 1, 1] - m[..., 0, 1] * m[..., 1, 0]
    if d == 3:
        return (m[..., 0, 0] * (m[..., 1, 1] * m[..., 2, 2] - m[..., 1, 2] * m[..., 2, 1])
                - m[..., 0, 1] * (m[..., 1, 0] * m[..., 2, 2] - m[..., 1, 2] * m[..., 2, 0])
                + m[..., 0, 2] * (m[..., 1, 0] * m[..., 2, 1] - m[..., 1, 1] * m[..., 2, 0]))
    return np.linalg.det(m)


def procrustes(c: Any, *, allow_reflection: bool = False) -> Procrustes:
    r"""The orthogonal matrix nearest to ``c`` in the Procrustes sense, with the reflection fix.

    Solves :math:`\max_{R^\mathsf{T} R = I} \operatorname{tr}(R^\mathsf{T} C)` (equivalently
    :math:`\min \lVert R - C \rVert_F`), with :math:`\det R = +1` unless
    ``allow_reflection``. For a cross-covariance :math:`C = \sum_i w_i \tilde y_i \tilde
    x_i^\mathsf{T}` this is the rotation of rigid and similarity alignment (Kabsch, Umeyama).

    Parameters
    ----------
    c : (..., d, d) float array
        One matrix or a stack.
    allow_reflection : bool, default False
        Return :math:`U V^\mathsf{T}` as it comes, determinant -1 included.

    Returns
    -------
    Procrustes
        ``rotation``, the fixed factors ``u``, ``singular_values``, ``vt``, the ``signs`` of
        ``D``, where a ``reflection`` was kept, and ``trace`` = :math:`\operatorname{tr}(D\Sigma)`.

    Notes
    -----
    Where the two smallest singular values are equal and the fix applies, the best proper
    rotation is not unique; one of the minimisers is returned. Rank-deficient ``c`` leaves
    the singular vectors of the zero singular values, and so ``R``, undetermined: callers
    check the rank (:func:`numerical_rank` of ``singular_values``) before trusting ``R``.
    """
    c = np.asarray(c, dtype=np.float64)
    u, s, vt = np.linalg.svd(c)
    rotation = u @ vt
    negative = np.asarray(det(rotation) < 0)
    signs = np.ones(s.shape)
    if allow_reflection or not negative.any():
        return Procrustes(rotation, u, s, vt, signs, negative)
    signs[..., -1] = np.where(negative, -1.0, 1.0)
    u = u * signs[..., None, :]
    return Procrustes(u @ vt, u, s, vt, signs, np.zeros(negative.shape, dtype=bool))


def polar(a: Any, *, proper: bool = False) -> tuple[FloatArray, FloatArray]:
    r"""Polar decomposition :math:`A = R S` of a matrix or a stack.

    ``R`` is the orthogonal factor (the :func:`procrustes` solution for ``A``) and
    :math:`S = R^\mathsf{T} A = V D \Sigma V^\mathsf{T}` is symmetric. With ``proper=True``
    ``R`` is a rotation even when :math:`\det A < 0`; ``S`` then has one negative
    eigenvalue (the smallest singular value, negated), as in Shoemake & Duff (1992).

    Returns
    -------
    rotation : (..., d, d) float array
    stretch : (..., d, d) float array
    """
    fit = procrustes(a, allow_reflection=not proper)
    v = np.swapaxes(fit.vt, -1, -2)
    stretch = (v * (fit.signs * fit.singular_values)[..., None, :]) @ fit.vt
    return fit.rotation, stretch


def numerical_rank(singular_values: Any, rtol: float = RANK_RTOL) -> int:
    """How many of the (decreasing) ``singular_values`` exceed ``rtol`` times the largest."""
    s = np.asarray(singular_values, dtype=np.float64)
    if s.size == 0 or not s[0] > 0:
        return 0
    return int(np.count_nonzero(s > rtol * s[0]))


def homogeneous(linear: Any, translation: Any) -> FloatArray:
    """The ``(..., d+1, d+1)`` matrix ``[[linear, translation], [0, 1]]`` (a stack for stacks)."""
    linear = np.asarray(linear, dtype=np.float64)
    translation = np.asarray(translation, dtype=np.float64)
    d = linear.shape[-1]
    out = np.zeros(linear.shape[:-2] + (d + 1, d + 1))
    out[..., :d, :d] = linear
    out[..., :d, d] = translation
    out[..., d, d] = 1.0
    return out


# --- batched rotations for per-vertex / per-face local steps -------------------------------
#
# Horn's quaternion method by repeated squaring (see the Notes of batched_rotations). The ten
# distinct entries of a symmetric 4×4 matrix, row-major upper triangle:
_UPPER = [(0, 0), (0, 1), (0, 2), (0, 3), (1, 1), (1, 2), (1, 3), (2, 2), (2, 3), (3, 3)]
_AT: dict[tuple[int, int], int] = {}
for _k, (_i, _j) in enumerate(_UPPER):
    _AT[_i, _j] = _AT[_j, _i] = _k
#: (B_ij = sum_k A_ik A_kj) as index pairs into the ten entries.
_PRODUCTS = [[(_AT[i, k], _AT[k, j]) for k in range(4)] for (i, j) in _UPPER]
_DIAG = [_AT[i, i] for i in range(4)]
_ENTRY = np.array([[_AT[i, j] for j in range(4)] for i in range(4)])  # (i, j) -> entry

#: Squarings every matrix gets (the other eigenvalues shrink by the gap ratio to the 128th
#: power: below 1e-33 for a ratio of 0.55, that of a flat ring); then only the unconverged
#: ones go on.
_FIRST_SQUARINGS = 7
#: Further squarings for the slow ones before the SVD fallback.
_MORE_SQUARINGS = 6
#: Converged when the bound of :meth:`RotationFitter._square` on the weight the result
#: leaves off its top eigenvector is below this: the extracted quaternion is then within
#: rounding (~1e-16) of the eigenvector, and the rotations agree with the SVD solution to
#: ~1e-13, as closely as two SVDs agree.
_CONVERGED = 1e-16
#: Matrices fitted at a time, so that the two 10-row stacks a squaring reads and writes
#: (2.6 MB) stay near the core. On ARAP's covariances of the 200,704-vertex bench grid one
#: pass over all of them at once took 1,176 ns a matrix, blocks of 8,192-16,384 665-681
#: (2,048: 777; 32,768: 826); on the 50,176-vertex grid 870-1,000 against 590-840.
_BLOCK = 16384


class RotationFitter:
    """The rotations of :func:`batched_rotations` for a stack of ``n`` covariances of
    dimension ``d``, with the work buffers allocated once: ARAP's iterations call it with the
    same ``n`` every time, in the layout of its right-hand side, and so skip the allocations
    and the transposes of the one-shot function (about 10 % of an ARAP iteration).

    Parameters
    ----------
    n : int
        Number of covariances.
    d : {2, 3}
        Their dimension.

    Notes
    -----
    The covariances come as a ``(d, n, d)`` array ``S`` with ``S[a, r, b]`` the entry
    ``(a, b)`` of matrix ``r``, and the rotations leave in the layout the ARAP right-hand
    side needs: ``out[a, r, b] = R_r[b, a]`` (so that ``tr(R_r S_r)`` is the sum over
    ``a, b`` of ``out[a, r, b] * S[a, r, b]``). Calls overwrite and return the same ``out``
    buffer. The method is described in the Notes of :func:`batched_rotations`.
    """

    def __init__(self, n: int, d: int) -> None:
        self.n, self.d = int(n), int(d)
        if self.d not in (2, 3):
            raise InvalidInputError(f"Expected the dimension `d` to be 2 or 3, got {d}.",
                                    field="d")
        self.out = np.empty((d, n, d))
        if d == 3:
            w = min(self.n, _BLOCK)
            self._a = np.empty((10, w))
            self._b = np.empty((10, w))
            self._t = np.empty(w)
            self._p = np.empty((10, w))
            self._s9 = np.empty((9, w))
            self._q = np.empty((4, w))

    def __call__(self, S: FloatArray) -> FloatArray:
        """Fit the rotations of ``S`` (``(d, n, d)``); returns the ``out`` buffer."""
        if self.d == 2:
            return self._fit2(S)
        return self._fit3(S)

    # -- 2-D: closed form -----------------------------------------------------------------
    def _fit2(self, S: FloatArray) -> FloatArray:
        a = S[0, :, 0] + S[1, :, 1]
        b = S[0, :, 1] - S[1, :, 0]
        r = np.hypot(a, b)
        zero = r == 0
        r[zero] = 1.0
        a[zero] = 1.0                                     # S = 0: any rotation; gives I
        c, s = a / r, b / r
        out = self.out
        out[0, :, 0] = c
        out[0, :, 1] = s
        out[1, :, 0] = -s
        out[1, :, 1] = c
        return out

    # -- 3-D: Horn's quaternion by repeated squaring -----------------------------------------
    def _fit3(self, S: FloatArray) -> FloatArray:
        for lo in range(0, self.n, _BLOCK):
            hi = min(lo + _BLOCK, self.n)
            self._fit3_block(S[:, lo:hi], self.out[:, lo:hi])
        return self.out

    def _fit3_block(self, S: FloatArray, out: FloatArray) -> None:
        """:meth:`_fit3` on a block of at most :data:`_BLOCK` matrices, into ``out``."""
        n = S.shape[1]
        A, B, t, s9 = self._a[:, :n], self._b[:, :n], self._t[:n], self._s9[:, :n]
        np.copyto(s9.reshape(3, 3, n), np.transpose(S, (0, 2, 1)))   # contiguous entries
        sxx, sxy, sxz, syx, syy, syz, szx, szy, szz = s9
        # c = sqrt(3) |S|_F, the shift that makes N + cI positive semidefinite
        np.einsum("kn,kn->n", s9, s9, out=t)
        np.multiply(t, 3.0, out=t)
        np.sqrt(t, out=t)
        t[t == 0] = 1.0                                   # S = 0: any rotation; gives I
        np.add(sxx, syy, out=A[0]); A[0] += szz           # N00 = tr S
        np.subtract(syz, szy, out=A[1])
        np.subtract(szx, sxz, out=A[2])
        np.subtract(sxy, syx, out=A[3])
        np.subtract(sxx, syy, out=A[4]); A[4] -= szz
        np.add(sxy, syx, out=A[5])
        np.add(szx, sxz, out=A[6])
        np.subtract(syy, sxx, out=A[7]); A[7] -= szz
        np.add(syz, szy, out=A[8])
        np.subtract(szz, sxx, out=A[9]); A[9] -= syy
        for k in _DIAG:
            A[k] += t
        A /= t                                            # eigenvalues now in [0, 2√3]
        A, gap = self._square(A, B, _FIRST_SQUARINGS)
        slow = np.flatnonzero(gap > _CONVERGED)
        if slow.size:                                     # small eigen-gaps: square on
            sub, gap = self._square(np.ascontiguousarray(A[:, slow]),
                                    np.empty((10, slow.size)), _MORE_SQUARINGS)
            A[:, slow] = sub
            slow = slow[gap > _CONVERGED]
        # the column of the largest diagonal entry is a multiple of the eigenvector
        col = np.argmax(A[_DIAG], axis=0)
        q = self._q[:, :n]
        q[...] = A[_ENTRY[:, col], np.arange(n)]          # q[i, r] = A_r[i, col_r]
        np.einsum("in,in->n", q, q, out=t)
        np.sqrt(t, out=t)
        q /= t
        self._quaternion_to_out(q, out)
        if slow.size:                                     # exact SVD rotations for those
            # procrustes(C) maximises tr(Rᵀ C); with C = S_rᵀ that is tr(S_r R) = tr(R S_r).
            C = np.transpose(S[:, slow, :], (1, 2, 0))    # C[r, b, a] = S[a, r, b]
            R = procrustes(C).rotation
            out[:, slow, :] = np.transpose(R, (2, 0, 1))  # out[a, r, b] = R_r[b, a]

    def _square(self, A: FloatArray, B: FloatArray, times: int
                ) -> tuple[FloatArray, FloatArray]:
        """Square the stack ``times`` times, normalising the trace to 1 after each.

        Returns the result and a bound on what it leaves off its top eigenvector: with
        ``τ = 1 - tr(A²)`` of the next-to-last iterate (the trace the last squaring divides
        by), that iterate's other eigenvalues sum to ``δ <= τ / (2(1 - δ))``, and the last
        squaring leaves ``δ' <= δ² / (1 - 2δ)``: the returned bound is ``τ²`` (about
        ``4δ'``), free of charge.
        """
        tmp = np.empty(A.shape[1])
        tr = np.empty(A.shape[1])
        for _ in range(times):
            for k, prods in enumerate(_PRODUCTS):
                (a0, b0), (a1, b1), (a2, b2), (a3, b3) = prods
                np.multiply(A[a0], A[b0], out=B[k])
                np.multiply(A[a1], A[b1], out=tmp); B[k] += tmp
                np.multiply(A[a2], A[b2], out=tmp); B[k] += tmp
                np.multiply(A[a3], A[b3], out=tmp); B[k] += tmp
            np.add(B[0], B[4], out=tr); tr += B[7]; tr += B[9]
            tr[tr <= 0] = 1.0
            B /= tr
            A, B = B, A
        np.subtract(1.0, tr, out=tr)
        np.maximum(tr, 0.0, out=tr)
        np.square(tr, out=tr)
        return A, tr

    def _quaternion_to_out(self, q: FloatArray, out: FloatArray) -> None:
        """Write the rotation of each unit quaternion ``q`` (4, n) into ``out`` (d, n, d)."""
        w, x, y, z = q
        p = self._p[:, :q.shape[1]]
        ww, xx, yy, zz, xy, wz, xz, wy, yz, wx = p
        for dst, a, b in ((ww, w, w), (xx, x, x), (yy, y, y), (zz, z, z), (xy, x, y),
                          (wz, w, z), (xz, x, z), (wy, w, y), (yz, y, z), (wx, w, x)):
            np.multiply(a, b, out=dst)
        # out[a, :, b] = R[b, a]
        for o, plus, minus in ((out[0, :, 0], xx, (yy, zz)),      # R00 = ww + xx - yy - zz
                               (out[1, :, 1], yy, (xx, zz)),      # R11
                               (out[2, :, 2], zz, (xx, yy))):     # R22
            np.add(ww, plus, out=o)
            o -= minus[0]
            o -= minus[1]
        for o, a, b, sign in ((out[1, :, 0], xy, wz, -1), (out[0, :, 1], xy, wz, 1),  # R01, R10
                              (out[2, :, 0], xz, wy, 1), (out[0, :, 2], xz, wy, -1),  # R02, R20
                              (out[2, :, 1], yz, wx, -1), (out[1, :, 2], yz, wx, 1)):  # R12, R21
            (np.add if sign > 0 else np.subtract)(a, b, out=o)
            o *= 2.0


def _square_stack(m: Any, name: str) -> FloatArray:
    """``m`` as a float array of shape ``(..., d, d)``, or an :class:`InvalidInputError`."""
    a = np.asarray(m, dtype=np.float64)
    if a.ndim < 2 or a.shape[-1] != a.shape[-2]:
        raise InvalidInputError(
            f"Expected `{name}` to be a stack of square matrices (..., d, d), got shape "
            f"{tuple(a.shape)}.", field=name)
    return a


def batched_rotations(S: Any) -> FloatArray:
    r"""For each matrix :math:`S` of a stack, the rotation :math:`R` maximising
    :math:`\operatorname{tr}(R S)`: the local step of ARAP.

    With :math:`S = U \Sigma V^\mathsf{T}`, :math:`R = V D U^\mathsf{T}` where
    :math:`D = \operatorname{diag}(1, \dots, 1, \pm 1)` flips the singular vector of the
    smallest singular value when :math:`\det(V U^\mathsf{T}) < 0` (the reflection fix of
    the module docstring). For ARAP's covariance :math:`S_i = \sum_j w_{ij} e_{ij}
    e'^\mathsf{T}_{ij}` (rest edges times deformed edges) this is Sorkine & Alexa's
    :math:`R_i = V_i U_i^\mathsf{T}` with their determinant correction.

    Parameters
    ----------
    S : (..., d, d) float array
        One matrix or a stack (``(b, d, d)`` for ``b`` vertices or faces).

    Returns
    -------
    (..., d, d) float array
        Proper rotations (``det = +1``), also where ``S`` is rank-deficient (a flat
        neighbourhood) or zero (identity).

    Notes
    -----
    ``numpy.linalg.svd`` on a stack of 3×3 matrices pays LAPACK's per-matrix overhead
    (about 4 µs a matrix: 0.2 s for 50,000 vertices, more than libigl's whole ARAP
    iteration). For ``d = 3`` the rotation comes from Horn's quaternion method instead: the
    unit quaternion of the best rotation is the eigenvector of the largest eigenvalue of a
    symmetric 4×4 matrix :math:`N(S)` built linearly from :math:`S` (Horn 1987, §4). Shifted
    by :math:`c = \sqrt{3}\,\lVert S\rVert_F \ge \sigma_1 + \sigma_2 + \sigma_3 \ge
    |\lambda|`, :math:`N + cI` is positive semidefinite with the same eigenvectors, and
    repeated squaring (normalised by the trace) turns it into the projector onto that
    eigenvector: after :math:`k` squarings the other eigenvalues have shrunk by
    :math:`((\lambda_2 + c)/(\lambda_1 + c))^{2^k}`. The squarings run as element-wise
    operations on the ten distinct entries, in preallocated buffers
    (:class:`RotationFitter`, which ARAP keeps across its iterations). Where the eigen-gap
    is too small for the squarings to converge (neighbourhoods whose rotation is nearly
    undetermined) the SVD solution (:func:`procrustes`, reflection fixed) is used for those
    matrices only. The squarings run until the quaternion is exact to rounding, so the
    result agrees with the SVD solution to ~1e-13 wherever that is unique, and the ARAP
    energy never increases in the local step. Horn's maximiser ranges over rotations only,
    which is the reflection fix of the SVD route by construction; a zero ``S`` gives the
    identity.

    ``d = 2`` is closed-form: :math:`R = \operatorname{rot}(\theta)` with
    :math:`\theta = \operatorname{atan2}(S_{01} - S_{10}, S_{00} + S_{11})`; ``d = 1`` is
    1; other ``d`` fall back to :func:`procrustes`.

    References
    ----------
    .. [1] O. Sorkine and M. Alexa, "As-rigid-as-possible surface modeling", SGP 2007.
    .. [2] B. K. P. Horn, "Closed-form solution of absolute orientation using unit
       quaternions", Journal of the Optical Society of America A 4(4), 629-642, 1987.

    Examples
    --------
    >>> c, s = np.cos(0.3), np.sin(0.3)
    >>> R = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    >>> np.allclose(batched_rotations((2 * R.T)[None]), R)   # tr(R · 2Rᵀ) = 6 is the max
    True
    """
    s = _square_stack(S, "S")
    d = s.shape[-1]
    flat = s.reshape((-1, d, d))
    if d in (2, 3):
        out = RotationFitter(flat.shape[0], d)(np.transpose(flat, (1, 0, 2)))
        rot = np.transpose(out, (1, 2, 0))                # R[r, b, a] = out[a, r, b]
    elif d == 1:
        rot = np.ones_like(flat)
    else:
        rot = procrustes(np.swapaxes(flat, -1, -2)).rotation
    return np.ascontiguousarray(rot).reshape(s.shape)


def batched_polar(A: Any, proper: bool = True) -> tuple[FloatArray, FloatArray]:
    r"""Polar decomposition :math:`A = R P` of every matrix of a stack, fast for 2×2 and 3×3.

    Parameters
    ----------
    A : (..., d, d) float array
    proper : bool, default True
        ``R`` a rotation even where :math:`\det A < 0` (``P`` then has one negative
        eigenvalue, the smallest singular value negated); ``False`` gives the orthogonal
        polar factor (a reflection where :math:`\det A < 0`) and ``P`` positive
        semidefinite.

    Returns
    -------
    R : (..., d, d) float array
        The orthogonal factor nearest to ``A``: :math:`\arg\max \operatorname{tr}(R^\mathsf{T} A)`.
    P : (..., d, d) float array
        :math:`R^\mathsf{T} A`, symmetrised.

    Notes
    -----
    Same results as :func:`polar` (``proper`` there defaults to ``False``), computed by
    :func:`batched_rotations` of :math:`A^\mathsf{T}` (:math:`\operatorname{tr}(R^\mathsf{T}
    A) = \operatorname{tr}(R A^\mathsf{T})`). The best reflection for :math:`A` is
    :math:`Q F` with :math:`F = \operatorname{diag}(1, \dots, 1, -1)` and :math:`Q` the best
    rotation for :math:`A F`; it is the orthogonal factor where :math:`\det A < 0`.
    """
    a = _square_stack(A, "A")
    d = a.shape[-1]
    flat = a.reshape((-1, d, d))
    r = batched_rotations(np.swapaxes(flat, -1, -2))
    if not proper:
        flip = np.flatnonzero(np.asarray(det(flat)) < 0)
        if flip.size:
            af = flat[flip]                               # a copy
            af[..., -1] *= -1.0                           # A F: last column negated
            q = batched_rotations(np.swapaxes(af, -1, -2))
            q[..., -1] *= -1.0                            # Q F
            r[flip] = q
    r = r.reshape(a.shape)
    p = np.swapaxes(r, -1, -2) @ a
    return r, 0.5 * (p + np.swapaxes(p, -1, -2))
