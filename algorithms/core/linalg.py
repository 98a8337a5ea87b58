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

from algorithms.core.types import BoolArray, FloatArray

__all__ = [
    "RANK_RTOL",
    "Procrustes",
    "procrustes",
    "polar",
    "det",
    "numerical_rank",
    "homogeneous",
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
        return np.einsum("...i,...i->...", self.signs, self.singular_values)


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
