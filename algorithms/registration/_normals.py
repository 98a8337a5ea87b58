"""Unit normals of a 3-D point set: checked when given, estimated by local PCA when not.

Private to the registration family (the plane metrics of ``icp``, ``fpfh``, ``ransac``);
:func:`given_normals`, the check of normals a caller gives, is public as
``algorithms.registration.given_normals``.
"""

from __future__ import annotations

import contextlib
import hashlib
from collections.abc import Iterator
from contextvars import ContextVar
from typing import Any

import numpy as np
from scipy.spatial import cKDTree

from algorithms.core.errors import InvalidInputError
from algorithms.core.types import FloatArray
from algorithms.core.validation import as_points

__all__ = ["given_normals", "estimate_normals", "reuse_normals", "MIN_NORMAL_POINTS"]

#: Points a normal needs: itself and two neighbours span a plane.
MIN_NORMAL_POINTS = 3
#: A given normal shorter than this counts as missing (it cannot be normalised).
MIN_NORMAL_LENGTH = 1e-12


def given_normals(normals: Any, n: int, *, name: str) -> FloatArray:
    """Check user normals (``(n, 3)``, finite, non-zero) and return them normalised."""
    out = as_points(normals, name=name, dim=3)
    if out.shape[0] != n:
        points = name.replace("_normals", "")
        raise InvalidInputError(
            f"Expected `{name}` to hold one normal per `{points}` point ({n}), got "
            f"{out.shape[0]}.", field=name)
    squared: FloatArray = np.einsum("ij,ij->i", out, out)
    length = np.sqrt(squared)
    short = np.flatnonzero(length < MIN_NORMAL_LENGTH)
    if short.size:
        raise InvalidInputError(
            f"Expected `{name}` to hold non-zero vectors, got length "
            f"{float(length[short[0]]):.3g} at row {int(short[0])}.", field=name)
    return out / length[:, None]


#: Inside :func:`reuse_normals`: the estimates made so far, by a BLAKE2b digest of the
#: points' bytes, their shape and ``k``; outside, None.
_REUSED: ContextVar[dict[tuple[bytes, tuple[int, ...], int], tuple[FloatArray, FloatArray]]
                    | None] = ContextVar("reused_normals", default=None)


@contextlib.contextmanager
def reuse_normals() -> Iterator[None]:
    """Inside the block, :func:`estimate_normals` estimates the normals of the same points
    (equal bytes: equal 32-byte BLAKE2b digests) with the same ``k`` once and returns that
    estimate again after, read-only: for a caller that runs ICP with a plane metric several
    times on the same sets (the stages and pairs of a pose graph). A block inside another
    uses the outer one's estimates. The estimate is a function of the points and ``k``
    only, so the answers are those without the block, to the bit. The estimates live till
    the block ends: 32 bytes per point of each set."""
    if _REUSED.get() is not None:
        yield
        return
    token = _REUSED.set({})
    try:
        yield
    finally:
        _REUSED.reset(token)


def estimate_normals(points: FloatArray, tree: cKDTree | None, k: int, workers: int
                     ) -> tuple[FloatArray, FloatArray]:
    r"""Normals by principal component analysis of each point's ``k`` nearest neighbours
    (``tree``: a kd-tree of ``points``, built here if None).

    For the neighbourhood :math:`N_i` (the point and its ``k`` nearest others) the
    covariance :math:`C_i = \frac{1}{|N_i|}\sum_{j \in N_i} (p_j - \bar p)(p_j - \bar p)^\mathsf{T}`
    is diagonalised; the normal is the eigenvector of the smallest eigenvalue (Hoppe et al.
    1992). Its sign is arbitrary, which the point-to-plane residual does not notice.

    Returns
    -------
    normals : (n, 3) float array
        Unit normals.
    planarity : (n,) float array
        The middle eigenvalue over the largest, in ``[0, 1]``: near 0 where the neighbourhood
        is collinear and the normal undetermined (such points get no weight in the fit).
    """
    reused = _REUSED.get()
    if reused is None:
        return _estimate(points, tree, k, workers)
    key = (hashlib.blake2b(np.ascontiguousarray(points).data).digest(), points.shape, k)
    if key not in reused:
        normals, planarity = _estimate(points, tree, k, workers)
        normals.flags.writeable = planarity.flags.writeable = False
        reused[key] = normals, planarity
    return reused[key]


def _estimate(points: FloatArray, tree: cKDTree | None, k: int, workers: int
              ) -> tuple[FloatArray, FloatArray]:
    k = min(k, points.shape[0] - 1)
    if tree is None:
        tree = cKDTree(points)
    _, idx = tree.query(points, k=k + 1, workers=workers)
    nbhd = points[idx]                                    # (n, k+1, 3)
    nbhd = nbhd - nbhd.mean(axis=1, keepdims=True)
    cov = np.einsum("nki,nkj->nij", nbhd, nbhd)
    val, vec = np.linalg.eigh(cov)                        # ascending eigenvalues
    top = np.maximum(val[:, 2], np.finfo(float).tiny)
    return np.ascontiguousarray(vec[:, :, 0]), np.clip(val[:, 1] / top, 0.0, 1.0)
