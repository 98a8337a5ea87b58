"""Catalog entries of the assignment family (finding correspondences)."""

from __future__ import annotations

from functools import partial

from algorithms.assignment import (
    bipartite,
    check_dense,
    check_transport,
    closest_pair,
    distance,
    nearest,
    optimal_transport,
)
from algorithms.core.validation import check_point_sets
from service.catalog.registry import Process, registry

_EXAMPLES = {"source": [[0.0, 0.0], [1.0, 0.0], [2.0, 0.1]], "target": [[0.1, 0.0], [2.0, 0.0]]}
# kd-tree queries: the two sets share their dimension (their sizes may differ)
_tree = partial(Process, examples=_EXAMPLES, check=check_point_sets, hidden=("workers",),
                fast_path=True)

registry.add(_tree(nearest, keywords=("nearest neighbour", "kd-tree", "correspondences",
                                      "chamfer")))
registry.add(_tree(closest_pair, keywords=("closest pair", "kd-tree", "minimum distance",
                                           "clearance")))
registry.add(Process(bipartite, examples=_EXAMPLES, check=check_dense,
                     keywords=("hungarian", "linear assignment", "matching",
                               "correspondences")))
registry.add(Process(optimal_transport, examples=_EXAMPLES, check=check_transport,
                     keywords=("wasserstein", "earth mover", "sinkhorn", "transport plan")))
registry.add(_tree(distance, keywords=("chamfer", "hausdorff", "rmse", "set distance")))
