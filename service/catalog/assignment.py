"""Catalog entries of the assignment family (finding correspondences)."""

from __future__ import annotations

from typing import Any

from algorithms.assignment import (
    bipartite,
    check_cost_size,
    closest_pair,
    distance,
    nearest,
    optimal_transport,
)
from algorithms.core.validation import as_weights, same_dim
from service.catalog.registry import Process, registry

_EXAMPLES = {"source": [[0.0, 0.0], [1.0, 0.0], [2.0, 0.1]], "target": [[0.1, 0.0], [2.0, 0.0]]}


def _same_dim(p: Any) -> None:
    """The two sets share their dimension (their sizes may differ)."""
    same_dim(p.source, p.target, names=("source", "target"))


def _dense(p: Any) -> None:
    """The same dimension, and a dense n×m cost matrix of bounded size."""
    _same_dim(p)
    check_cost_size(p.source.shape[0], p.target.shape[0])


def _transport(p: Any) -> None:
    """As _dense, and one mass per point when masses are given."""
    _dense(p)
    as_weights(p.source_weights, p.source.shape[0], name="source_weights")
    as_weights(p.target_weights, p.target.shape[0], name="target_weights")


registry.add(Process(
    id="assignment.nearest",
    title="Nearest-neighbour assignment (kd-tree)",
    description="Pairs each point with its k nearest neighbours in the other set, in one or "
    "both directions, optionally within a distance.",
    function=nearest,
    examples=_EXAMPLES,
    check=_same_dim,
    hidden=("workers",),
    fast_path=True,
    keywords=("nearest neighbour", "kd-tree", "correspondences", "chamfer"),
))

registry.add(Process(
    id="assignment.closest_pair",
    title="Closest pair between two point sets (kd-tree)",
    description="The single pair of points, one from each set, at the smallest distance.",
    function=closest_pair,
    examples=_EXAMPLES,
    check=_same_dim,
    hidden=("workers",),
    fast_path=True,
    keywords=("closest pair", "kd-tree", "minimum distance", "clearance"),
))

registry.add(Process(
    id="assignment.bipartite",
    title="Optimal one-to-one matching (linear assignment)",
    description="Matches the points of two sets one to one at the least total cost; sets "
    "may differ in size (the surplus stays unmatched), and max_cost leaves far points "
    "single. At most 16 million pairs n·m.",
    function=bipartite,
    examples=_EXAMPLES,
    check=_dense,
    keywords=("hungarian", "linear assignment", "matching", "correspondences"),
))

registry.add(Process(
    id="assignment.optimal_transport",
    title="Optimal transport between weighted point sets (exact or Sinkhorn)",
    description="The transport plan moving the mass of one weighted point set onto another "
    "at the least cost, returned sparse as (source, target, mass) pairs, with its cost "
    "(Wasserstein distance). Exact linear program, or entropic Sinkhorn in the log domain. "
    "At most 16 million pairs n·m.",
    function=optimal_transport,
    examples=_EXAMPLES,
    check=_transport,
    keywords=("wasserstein", "earth mover", "sinkhorn", "transport plan"),
))

registry.add(Process(
    id="assignment.distance",
    title="Chamfer, Hausdorff and RMSE distances between point sets",
    description="How far apart two point sets are, from their nearest-neighbour assignment "
    "in both directions: Chamfer (sum and mean), Hausdorff (and both directed halves), "
    "RMSE, and every point's distance to the other set.",
    function=distance,
    examples=_EXAMPLES,
    check=_same_dim,
    hidden=("workers",),
    fast_path=True,
    keywords=("chamfer", "hausdorff", "rmse", "set distance"),
))
