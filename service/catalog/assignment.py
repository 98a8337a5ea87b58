"""Catalog entries of the assignment family (finding correspondences)."""

from __future__ import annotations

from typing import Literal

from pydantic import Field

from algorithms.assignment import NearestResult, nearest
from service.catalog.base import Params
from service.catalog.inputs import Points
from service.catalog.registry import Process, registry


class NearestParams(Params):
    source: Points = Field(description="Query points: an (n, d) array.",
                           examples=[[[0.0, 0.0], [1.0, 0.0], [2.0, 0.1]]])
    target: Points = Field(description="Reference points: an (m, d) array, same d.",
                           examples=[[[0.1, 0.0], [2.0, 0.0]]])
    k: int = Field(1, ge=1, description="Neighbours per point.")
    direction: Literal["forward", "backward", "union", "intersection", "both"] = Field(
        "forward",
        description="forward: each source point to its k nearest targets; backward: each "
        "target to its k nearest sources; union / intersection (mutual) of both; both: "
        "forward then backward (the distances sum to the Chamfer distance).",
    )
    max_distance: float | None = Field(None, gt=0, description="Drop pairs farther apart.")


registry.add(Process(
    id="assignment.nearest",
    title="Nearest-neighbour assignment (kd-tree)",
    description="Pairs each point with its k nearest neighbours in the other set, in one or "
    "both directions, optionally within a distance.",
    function=nearest,
    params=NearestParams,
    result=NearestResult,
    reference="Bentley, J. L. (1975). Multidimensional binary search trees used for "
    "associative searching. CACM 18(9).",
    fast_path=True,
    keywords=("nearest neighbour", "kd-tree", "correspondences", "chamfer"),
))
