"""Paired point sets (row ``i`` of ``source`` with row ``i`` of ``target``): checking them,
weighted centring, the residual figures, the rotation fit and the errors for flat sets.

Every alignment with known correspondences (``rigid``, ``similarity``, ``affine``, ...)
validates through :func:`prepare` and reports through :meth:`Pairs.rmse`, so that the same
input gives the same message and the same ``rmse`` definition in every method; ICP fits its
correspondences of each iteration through :func:`trusted_pairs` and :func:`rotation_fit`.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from algorithms.core.errors import DegenerateInputError
from algorithms.core.linalg import RANK_RTOL, Procrustes, numerical_rank, procrustes
from algorithms.core.types import FloatArray
from algorithms.core.validation import (
    SHAPES,
    as_points,
    as_weights,
    check_min_points,
    same_shape,
)

__all__ = [
    "Pairs",
    "prepare",
    "check_pairs",
    "one_per_dimension",
    "rotation_fit",
    "flat_error",
    "procrustes_rank_error",
    "SHAPES",
]

#: How a point set that spans ``r`` dimensions is called in messages.


@dataclass(frozen=True, eq=False)
class Pairs:
    """Validated paired point sets, centred at their (weighted) centroids.

    ``p`` holds the weights normalised to sum 1, or is ``None`` when all pairs weigh the
    same (then every weighted mean is a plain mean, computed as a BLAS product). ``total``
    is the raw weight sum (``n`` without weights), for the one method (``principal_scaling``)
    whose formula is not normalised.
    """

    source: FloatArray
    target: FloatArray
    p: FloatArray | None
    total: float
    x_mean: FloatArray
    y_mean: FloatArray
    xc: FloatArray
    yc: FloatArray

    @property
    def n(self) -> int:
        n: int = self.source.shape[0]
        return n

    @property
    def d(self) -> int:
        d: int = self.source.shape[1]
        return d

    @property
    def weighted(self) -> bool:
        return self.p is not None

    def sqrt_p(self) -> FloatArray:
        """Row factors that turn a weighted sum of squares into a plain one (sum 1)."""
        return np.full(self.n, 1.0 / math.sqrt(self.n)) if self.p is None else np.sqrt(self.p)

    def cross_covariance(self) -> FloatArray:
        """``C = Σ pᵢ ỹᵢ x̃ᵢᵀ`` (``(d, d)``; the plain mean without weights)."""
        if self.p is None:
            return (self.yc.T @ self.xc) / self.n
        return (self.yc * self.p[:, None]).T @ self.xc

    def mean_square(self, resid: np.ndarray) -> float:
        """``Σ pᵢ ‖rᵢ‖²`` of an ``(n, d)`` residual."""
        if self.p is None:
            return float(np.vdot(resid, resid)) / self.n
        return float(self.p @ np.einsum("ij,ij->i", resid, resid))

    def rmse(self, forward: np.ndarray, inverse: np.ndarray | None = None) -> float:
        """``sqrt(Σ pᵢ‖fᵢ‖²)``, or with ``inverse`` residuals too (symmetric alignment)
        ``sqrt((Σ pᵢ‖fᵢ‖² + Σ pᵢ‖gᵢ‖²) / 2)``."""
        total = self.mean_square(forward)
        if inverse is None:
            return math.sqrt(total)
        return math.sqrt(0.5 * (total + self.mean_square(inverse)))

    def linear_rmse(self, linear: FloatArray, *, symmetric: bool = False) -> float:
        r"""The rmse of ``y ≈ L x + t`` with ``t`` through the centroids (``ȳ = L x̄ + t``).

        The forward residual is :math:`e_i = L \tilde x_i - \tilde y_i`; the inverse one,
        :math:`L^{-1}(y_i - t) - x_i = -L^{-1} e_i`, needs ``linear`` invertible (the caller
        has checked).
        """
        resid = self.xc @ linear.T - self.yc
        if not symmetric:
            return self.rmse(resid)
        return self.rmse(resid, np.linalg.solve(linear, resid.T).T)

    def span(self, which: str, rtol: float) -> int:
        """How many dimensions the (weighted, centred) ``source`` or ``target`` spans."""
        pts = self.xc if which == "source" else self.yc
        if self.p is not None:
            pts = pts * np.sqrt(self.p)[:, None]
        return numerical_rank(np.linalg.svd(pts, compute_uv=False), rtol)


def check_pairs(source: Any, target: Any, weights: Any = None) -> FloatArray | None:
    """Check the pairing of two point sets: row ``i`` of ``source`` with row ``i`` of
    ``target`` (the same shape), ``weights``, when given, one per pair. Returns the weights
    as :func:`as_weights` reads them."""
    same_shape(source, target, names=("source", "target"))
    return as_weights(weights, source.shape[0], name="weights")


def prepare(
    source: Any,
    target: Any,
    weights: Any,
    *,
    min_dim: int,
    minimum: Callable[[int], tuple[int, str]],
) -> Pairs:
    """Check ``source``, ``target`` (same shape, paired row by row) and ``weights``.

    ``minimum(d)`` gives the smallest number of pairs for the model in ``d`` dimensions and
    the reason shown in the message, e.g. ``(d + 1, "d + 1 = 4 for an affine map of 3-D")``.
    """
    src = as_points(source, name="source", min_dim=min_dim)
    dst = as_points(target, name="target")
    w = check_pairs(src, dst, weights)
    count, reason = minimum(src.shape[1])
    check_min_points(src, count, name="source", reason=reason)
    if w is None:
        return trusted_pairs(src, dst)
    total = float(w.sum())
    rel = w / w.max()  # keep the sum finite even for huge weights
    p = rel / rel.sum()
    x_mean = p @ src
    y_mean = p @ dst
    return Pairs(src, dst, p, total, x_mean, y_mean, src - x_mean, dst - y_mean)


def trusted_pairs(src: FloatArray, dst: FloatArray) -> Pairs:
    """Unweighted :class:`Pairs` of arrays the caller has already checked (finite float64,
    same ``(n, d)`` shape): what :func:`prepare` builds, without checking again. For inner
    loops such as ICP's, which fit thousands of times on data validated once."""
    n = src.shape[0]
    ones = np.ones(n)  # means as BLAS products: several times faster than mean(axis=0)
    x_mean = (ones @ src) / n
    y_mean = (ones @ dst) / n
    return Pairs(src, dst, None, float(n), x_mean, y_mean, src - x_mean, dst - y_mean)


def one_per_dimension(d: int) -> tuple[int, str]:
    """The ``minimum`` of :func:`prepare` for rotations: ``d`` pairs."""
    return d, f"at least one per dimension in {d}-D"


def flat_error(
    name: str, rank: int, need: int, why: str, *, weighted: bool = False
) -> DegenerateInputError:
    """The error for a point set that spans too few dimensions, e.g. "Expected `source` to
    span at least 3 dimensions after centring, got 2: the points are coplanar and <why>."."""
    what = SHAPES.get(rank, f"confined to a {rank}-dimensional flat")
    weighted_note = " (counting only points with positive weight)" if weighted else ""
    return DegenerateInputError(
        f"Expected `{name}` to span at least {need} dimensions after centring, got {rank}: "
        f"the points are {what}{weighted_note} and {why}.",
        field=name,
    )


def procrustes_rank_error(pairs: Pairs, rank: int, need: int, why: str) -> DegenerateInputError:
    """The error for a cross-covariance of rank below ``need`` (rigid, similarity, principal
    scaling), naming the point set responsible when one is (error path only)."""
    # The singular values of C are roughly products of the two sets' own singular values,
    # so a set counts as flat at the square root of the tolerance used for C.
    for name in ("source", "target"):
        r = pairs.span(name, math.sqrt(RANK_RTOL))
        if r < need:
            return flat_error(name, r, need, why, weighted=pairs.weighted)
    return DegenerateInputError(
        f"Expected the weighted cross-covariance of `source` and `target` to have rank at "
        f"least {need}, got {rank}: {why}.",
        field=None,
    )


def rotation_fit(pairs: Pairs, *, reflect_ok: bool, invertible: bool = False) -> Procrustes:
    """:func:`~algorithms.core.linalg.procrustes` of the cross-covariance, after checking
    that it determines the rotation: rank ``d - 1`` (``d`` with reflections, or with
    ``invertible`` when the caller needs the map built from it to have an inverse)."""
    fit = procrustes(pairs.cross_covariance(), allow_reflection=reflect_ok)
    need = pairs.d if reflect_ok or invertible else pairs.d - 1
    rank = numerical_rank(fit.singular_values, RANK_RTOL)
    if rank < need:
        if rank == pairs.d - 1 and reflect_ok:
            why = "a reflection across the flat they span fits equally well"
        elif rank == pairs.d - 1:
            why = "the map has no inverse, which `symmetric=true` needs"
        else:
            why = "the rotation is undetermined"
        raise procrustes_rank_error(pairs, rank, need, why)
    return fit
