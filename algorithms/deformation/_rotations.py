r"""The ARAP local step: for every covariance :math:`S_r` of a stack, the proper rotation
:math:`R_r` maximising :math:`\operatorname{tr}(R_r S_r)`, fast.

``numpy.linalg.svd`` on a stack of 3×3 matrices pays LAPACK's per-matrix overhead
(about 4 µs a matrix: 0.2 s for 50,000 vertices, more than libigl's whole ARAP iteration).
Here the 3-D rotation comes from Horn's quaternion method instead: the unit quaternion of the
best rotation is the eigenvector of the largest eigenvalue of a symmetric 4×4 matrix
:math:`N(S)` built linearly from :math:`S` (Horn 1987, §4). Shifted by
:math:`c = \sqrt{3}\,\lVert S\rVert_F \ge \sigma_1 + \sigma_2 + \sigma_3 \ge |\lambda|`,
:math:`N + cI` is positive semidefinite with the same eigenvectors, and repeated squaring
(normalised by the trace) turns it into the projector onto that eigenvector: after
:math:`k` squarings the other eigenvalues have shrunk by
:math:`((\lambda_2 + c)/(\lambda_1 + c))^{2^k}`. The squarings run as element-wise
operations on the ten distinct entries, in preallocated buffers (allocating a fresh array per
operation costs ten times the arithmetic here). Where the eigen-gap is too small for the
squarings to converge (rings whose rotation is nearly undetermined) the exact SVD solution
(:func:`algorithms.core.linalg.procrustes`, reflection fixed) is used for those matrices
only. The result is the exact maximiser, so the ARAP energy never increases in the local
step. Horn's maximiser ranges over rotations only, which is the reflection fix of the SVD
route (flip the singular vector of the smallest singular value) by construction.

In 2-D the answer is closed-form: :math:`R = \operatorname{rot}(\theta)` with
:math:`\theta = \operatorname{atan2}(S_{01} - S_{10}, S_{00} + S_{11})`.

References
----------
.. [1] B. K. P. Horn, "Closed-form solution of absolute orientation using unit quaternions",
   Journal of the Optical Society of America A 4(4), 629-642, 1987.
"""

from __future__ import annotations

import numpy as np

from algorithms.core.linalg import procrustes
from algorithms.core.types import FloatArray

__all__ = ["RotationFitter", "best_rotations"]

# The ten distinct entries of a symmetric 4×4 matrix, row-major upper triangle.
_UPPER = [(0, 0), (0, 1), (0, 2), (0, 3), (1, 1), (1, 2), (1, 3), (2, 2), (2, 3), (3, 3)]
_AT = {}
for _k, (_i, _j) in enumerate(_UPPER):
    _AT[_i, _j] = _AT[_j, _i] = _k
# (B_ij = sum_k A_ik A_kj) as index quadruples into the ten entries.
_PRODUCTS = [[(_AT[i, k], _AT[k, j]) for k in range(4)] for (i, j) in _UPPER]
_DIAG = [_AT[i, i] for i in range(4)]
_ENTRY = np.array([[_AT[i, j] for j in range(4)] for i in range(4)])  # (i, j) -> entry

#: Squarings every matrix gets (the other eigenvalues shrink by the gap ratio to the 64th
#: power: below 1e-16 for a ratio of 0.55, that of a flat ring); then only the unconverged
#: ones go on.
_FIRST_SQUARINGS = 6
#: Further squarings for the slow ones before the SVD fallback.
_MORE_SQUARINGS = 6
#: Converged when the bound of :meth:`RotationFitter._square` on the weight the result
#: leaves off its top eigenvector is below this: the angle between the extracted
#: quaternion and the eigenvector is then below ~1e-8 (libigl's single-precision SVD is
#: 1e-7). The attained ``tr(R S)`` falls short of the maximum by the square of that angle
#: times the eigen-gap, ~1e-16 relative: the local step never increases the ARAP energy by
#: more than rounding.
_CONVERGED = 1e-8


class RotationFitter:
    """Best rotations for a stack of ``n`` covariances of dimension ``d``, with the work
    buffers allocated once (the ARAP iterations call it with the same ``n`` every time).

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
    ``a, b`` of ``out[a, r, b] * S[a, r, b]``).
    """

    def __init__(self, n: int, d: int) -> None:
        self.n, self.d = int(n), int(d)
        self.out = np.empty((d, n, d))
        if d == 3:
            self._a = np.empty((10, n))
            self._b = np.empty((10, n))
            self._t = np.empty(n)
            self._p = np.empty((10, n))
            self._s9 = np.empty((9, n))
            self._q = np.empty((4, n))

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
        a[zero] = 1.0
        c, s = a / r, b / r
        out = self.out
        out[0, :, 0] = c
        out[0, :, 1] = s
        out[1, :, 0] = -s
        out[1, :, 1] = c
        return out

    # -- 3-D: Horn's quaternion by repeated squaring -----------------------------------------
    def _fit3(self, S: FloatArray) -> FloatArray:
        n = self.n
        A, t, s9 = self._a, self._t, self._s9
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
        A, gap = self._square(A, self._b, _FIRST_SQUARINGS)
        slow = np.flatnonzero(gap > _CONVERGED)
        if slow.size:                                     # small eigen-gaps: square on
            sub, gap = self._square(A[:, slow], np.empty((10, slow.size)), _MORE_SQUARINGS)
            A[:, slow] = sub
            slow = slow[gap > _CONVERGED]
        # the column of the largest diagonal entry is a multiple of the eigenvector
        col = np.argmax(A[_DIAG], axis=0)
        q = self._q
        q[...] = A[_ENTRY[:, col], np.arange(n)]          # q[i, r] = A_r[i, col_r]
        np.einsum("in,in->n", q, q, out=t)
        np.sqrt(t, out=t)
        q /= t
        self._quaternion_to_out(q)
        if slow.size:
            self._fallback(S, slow)
        return self.out

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

    def _quaternion_to_out(self, q: FloatArray) -> None:
        """Write the rotation of each unit quaternion ``q`` (4, n) into ``out``."""
        w, x, y, z = q
        p = self._p
        ww, xx, yy, zz, xy, wz, xz, wy, yz, wx = p
        for dst, a, b in ((ww, w, w), (xx, x, x), (yy, y, y), (zz, z, z), (xy, x, y),
                          (wz, w, z), (xz, x, z), (wy, w, y), (yz, y, z), (wx, w, x)):
            np.multiply(a, b, out=dst)
        out = self.out                                    # out[a, :, b] = R[b, a]
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

    def _fallback(self, S: FloatArray, slow: np.ndarray) -> None:
        """Exact SVD rotations for the matrices the squarings left unconverged."""
        # procrustes(C) maximises tr(Rᵀ C); with C = S_rᵀ that is tr(S_r R) = tr(R S_r).
        C = np.transpose(S[:, slow, :], (1, 2, 0))        # C[r, b, a] = S[a, r, b]
        R = procrustes(C).rotation
        self.out[:, slow, :] = np.transpose(R, (2, 0, 1))  # out[a, r, b] = R_r[b, a]


def best_rotations(S: FloatArray) -> FloatArray:
    """The proper rotations maximising ``tr(R_r S_r)`` for a ``(n, d, d)`` stack, ``d`` = 2
    or 3, as an ``(n, d, d)`` array (a convenience wrapper of :class:`RotationFitter`)."""
    S = np.asarray(S, dtype=np.float64)
    n, d = S.shape[0], S.shape[-1]
    fitter = RotationFitter(n, d)
    out = fitter(np.ascontiguousarray(np.transpose(S, (1, 0, 2))))
    return np.transpose(out, (1, 2, 0)).copy()           # R[r, b, a] = out[a, r, b]
