r"""Exact neighbour searches in many dimensions, pruned by a partition of the points.

The points are cut into groups by a few Lloyd (k-means) iterations; each group keeps its
centre :math:`c_G` and radius :math:`R_G` (the largest distance of a member from the
centre, from the differences). By the triangle inequality no member of group :math:`H`
is closer to a member of :math:`G` than

.. math:: \operatorname{gap}(G, H) = \max(0,\ \lVert c_G - c_H\rVert - R_G - R_H),

so a search for the points of :math:`G` within a squared distance :math:`\tau` needs only
the groups with :math:`\operatorname{gap}(G, H)^2 \le \tau` (:meth:`Groups.reach`). The
result is exact whatever the partition; the partition only decides how much is pruned:
on clustered data nearly every other cluster, on data without clusters (or in so many
dimensions that all distances are alike) nothing, and the search costs what the full
``n × n`` one does.

Used by t-SNE's nearest neighbours (:func:`~algorithms.embedding._quality._nearest_neighbors`)
and by the rank counts of :func:`~algorithms.embedding.trustworthiness`.
"""

from __future__ import annotations

import numpy as np

from algorithms.core.types import FloatArray, IntpArray

__all__ = ["Groups", "partition", "group_count"]

#: Lloyd iterations of the partition (its quality only decides how much is pruned).
_ITERATIONS = 5
#: Cells of a block of point-to-centre distances (4 bytes each).
_CELLS = 4_000_000
#: Inputs of fewer points are one group (nothing to prune worth the partition).
GROUPED_FROM = 5_000
#: Relative margin on the pruning test (the centre distances are rounded).
_MARGIN = 1e-6


class Groups:
    """A partition of the points into groups with centres and radii.

    Attributes
    ----------
    order : (n,) int array
        The points, group by group.
    starts : (c + 1,) int array
        Group ``g`` is ``order[starts[g]:starts[g + 1]]``.
    label : (n,) int array
        Each point's group.
    gap : (c, c) float array
        The lower bound :math:`\\max(0, \\lVert c_G - c_H\\rVert - R_G - R_H)` on the
        distance between members of two groups (0 on the diagonal).
    """

    def __init__(self, label: IntpArray, centres: FloatArray, radii: FloatArray) -> None:
        c = centres.shape[0]
        self.label = label
        self.order: IntpArray = np.argsort(label, kind="stable")
        self.starts: IntpArray = np.r_[0, np.cumsum(np.bincount(label, minlength=c))]
        dist = np.empty((c, c))
        for g in range(c):                              # from the differences: no cancellation
            diff = centres - centres[g]
            dist[g] = np.sqrt(np.einsum("ij,ij->i", diff, diff))
        self.centre_distance: FloatArray = dist
        self.gap: FloatArray = np.maximum(dist - radii[:, None] - radii[None, :], 0.0)

    def __len__(self) -> int:
        return int(self.starts.size - 1)

    def members(self, g: int) -> IntpArray:
        """The points of group ``g``."""
        out: IntpArray = self.order[self.starts[g]:self.starts[g + 1]]
        return out

    def reach(self, g: int, tau: float) -> IntpArray:
        """Every point that may lie within squared distance ``tau`` of a member of group
        ``g``: the members of the groups whose gap to ``g`` is not provably larger."""
        limit = np.sqrt(max(tau, 0.0)) * (1.0 + _MARGIN)
        near = np.flatnonzero(self.gap[g] <= limit)
        return self._union(near)

    def nearest_groups(self, g: int, count: int) -> IntpArray:
        """The members of the groups nearest ``g`` by centre distance (``g`` first), as
        many groups as hold at least ``count`` points (all of them if fewer)."""
        by_distance = np.argsort(self.centre_distance[g], kind="stable")
        sizes = np.diff(self.starts)[by_distance]
        take = int(np.searchsorted(np.cumsum(sizes), count)) + 1
        return self._union(by_distance[:take])

    def _union(self, groups: IntpArray) -> IntpArray:
        groups = np.sort(groups)
        if groups.size == len(self):
            return np.sort(self.order)
        parts = [self.order[self.starts[h]:self.starts[h + 1]] for h in groups]
        out: IntpArray = np.sort(np.concatenate(parts)) if parts else np.zeros(0, np.intp)
        return out


def group_count(n: int) -> int:
    """Groups for ``n`` points: one below :data:`GROUPED_FROM`, else about
    :math:`\\sqrt{n} / 2` (at most 1,024)."""
    if n < GROUPED_FROM:
        return 1
    return int(min(1024, max(2, round(np.sqrt(n) / 2))))


def partition(xc: FloatArray, count: int) -> Groups:
    """``count`` groups of the (centred) points ``xc`` by Lloyd iterations from distinct
    points drawn with a fixed seed (the same input gives the same groups); empty groups
    are dropped. The assignments use single-precision distance estimates (only the
    pruning depends on them); the centres are the members' means and the radii the exact
    largest distance of a member from its centre."""
    n, dim = xc.shape
    count = max(1, min(count, n))
    if count == 1:
        label = np.zeros(n, dtype=np.intp)
        centre = xc.mean(axis=0, keepdims=True)
    else:
        rng = np.random.default_rng(0)
        centre = xc[np.sort(rng.choice(n, count, replace=False))].copy()
        x32 = xc.astype(np.float32)
        label = np.empty(n, dtype=np.intp)
        rows = max(1, _CELLS // count)
        for it in range(_ITERATIONS + 1):
            c32 = centre.astype(np.float32)
            csq = np.einsum("ij,ij->i", c32, c32)
            for s in range(0, n, rows):
                est = x32[s:s + rows] @ c32.T
                est *= -2.0
                est += csq[None, :]
                label[s:s + rows] = est.argmin(axis=1)
            sizes = np.bincount(label, minlength=centre.shape[0])
            kept = np.flatnonzero(sizes)
            remap = np.full(centre.shape[0], -1, dtype=np.intp)
            remap[kept] = np.arange(kept.size)
            label = remap[label]
            sizes = sizes[kept]
            centre = np.stack([np.bincount(label, weights=xc[:, d], minlength=kept.size)
                               for d in range(dim)], axis=1) / sizes[:, None]
            if it == _ITERATIONS:
                break
    diff = xc - centre[label]
    dist = np.sqrt(np.einsum("ij,ij->i", diff, diff))
    radii = np.zeros(centre.shape[0])
    np.maximum.at(radii, label, dist)
    return Groups(label, centre, radii)
