"""k-means with k-means++ seeding (Lloyd's iterations), deterministic for a given seed.

Private to the clustering family: :func:`~algorithms.clustering.spectral` runs it on the
spectral embedding. Labels are renumbered in order of first appearance (the cluster of point
0 is 0, the next new cluster met is 1, ...) so that equal partitions give equal labels.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from algorithms.core.types import FloatArray, IntArray, RngLike

__all__ = ["KMeansFit", "kmeans", "canonical_labels"]


@dataclass(frozen=True, eq=False)
class KMeansFit:
    labels: IntArray
    centers: FloatArray
    inertia: float
    iterations: int
    converged: bool


def _sq_dist(x: FloatArray, c: FloatArray, x_sq: FloatArray) -> FloatArray:
    d: FloatArray = x_sq[:, None] - 2.0 * (x @ c.T) + np.einsum("ij,ij->i", c, c)[None, :]
    return np.maximum(d, 0.0, out=d)


def _plus_plus(x: FloatArray, k: int, rng: np.random.Generator, x_sq: FloatArray) -> FloatArray:
    """k-means++ seeding (Arthur & Vassilvitskii 2007) with ``2 + ln k`` local trials per
    centre, as scikit-learn does (greedy k-means++)."""
    n = x.shape[0]
    trials = 2 + int(np.log(k))
    centers = np.empty((k, x.shape[1]))
    first = int(rng.integers(n))
    centers[0] = x[first]
    closest = _sq_dist(x, centers[:1], x_sq)[:, 0]
    pot = float(closest.sum())
    for c in range(1, k):
        if pot <= 0.0:  # fewer distinct points than clusters: repeat a point
            centers[c] = x[int(rng.integers(n))]
            continue
        r = rng.random(trials) * pot
        cand = np.searchsorted(np.cumsum(closest), r)
        cand = np.minimum(cand, n - 1)
        d = _sq_dist(x, x[cand], x_sq)                     # (n, trials)
        np.minimum(d, closest[:, None], out=d)
        pots = d.sum(axis=0)
        best = int(np.argmin(pots))
        centers[c] = x[cand[best]]
        closest = d[:, best]
        pot = float(pots[best])
    return centers


def _lloyd(x: FloatArray, centers: FloatArray, x_sq: FloatArray, max_iterations: int,
           tolerance: float) -> KMeansFit:
    k = centers.shape[0]
    labels = np.zeros(x.shape[0], dtype=np.int64)
    scale = float(np.mean(np.var(x, axis=0))) or 1.0
    converged = False
    it = 0
    for it in range(1, max_iterations + 1):  # noqa: B007 - `it` is read after the loop
        d = _sq_dist(x, centers, x_sq)
        labels = np.argmin(d, axis=1)
        counts = np.bincount(labels, minlength=k)
        new = np.zeros_like(centers)
        np.add.at(new, labels, x)
        empty = counts == 0
        new[~empty] /= counts[~empty, None]
        if empty.any():  # an empty cluster takes the points farthest from their centres
            far = np.argsort(-d[np.arange(x.shape[0]), labels], kind="stable")
            new[empty] = x[far[:int(empty.sum())]]
        shift = float(((new - centers) ** 2).sum())
        centers = new
        if shift <= tolerance * scale:
            converged = True
            break
    d = _sq_dist(x, centers, x_sq)
    labels = np.argmin(d, axis=1)
    inertia = float(d[np.arange(x.shape[0]), labels].sum())
    return KMeansFit(labels, centers, inertia, it, converged)


def kmeans(x: FloatArray, k: int, *, n_init: int = 10, max_iterations: int = 300,
           tolerance: float = 1e-4, seed: RngLike = 0) -> KMeansFit:
    """The best (least inertia) of ``n_init`` k-means++ starts refined by Lloyd's iterations.

    ``tolerance`` is relative to the mean variance of the coordinates (scikit-learn's rule).
    """
    rng = np.random.default_rng(seed)
    x = np.ascontiguousarray(x, dtype=np.float64)
    x_sq = np.einsum("ij,ij->i", x, x)
    best: KMeansFit | None = None
    for _ in range(n_init):
        fit = _lloyd(x, _plus_plus(x, k, rng, x_sq), x_sq, max_iterations, tolerance)
        if best is None or fit.inertia < best.inertia - 1e-12 * max(1.0, best.inertia):
            best = fit
    assert best is not None
    labels, order = canonical_labels(best.labels, k)
    return KMeansFit(labels, best.centers[order], best.inertia, best.iterations, best.converged)


def canonical_labels(labels: IntArray, k: int | None = None) -> tuple[IntArray, IntArray]:
    """Renumber labels in order of first appearance; also return ``order`` with
    ``new_label == i`` for old label ``order[i]`` (unused old labels go last)."""
    labels = np.asarray(labels, dtype=np.int64)
    k = int(labels.max()) + 1 if k is None else k
    _, first = np.unique(labels, return_index=True)
    seen = labels[np.sort(first)]
    order = np.concatenate([seen, np.setdiff1d(np.arange(k), seen)])
    rank = np.empty(k, dtype=np.int64)
    rank[order] = np.arange(k)
    return rank[labels], order
