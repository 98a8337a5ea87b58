"""Catalog entries of the layout family (positions for a mesh's vertices or a graph's nodes
with pins, or for points known by their pairwise distances)."""

from __future__ import annotations

from functools import partial
from typing import Annotated, Any

import numpy as np
from pydantic import PlainSerializer, PlainValidator, ValidationInfo, WithJsonSchema

from algorithms.core.params import Le
from algorithms.core.validation import MAX_DENSE_POINTS, as_points
from algorithms.layout import (
    as_distance_matrix,
    check_distances,
    check_laplacian,
    check_poisson,
    check_stress,
    laplacian,
    mds,
    poisson,
    stress,
)
from service import scenes
from service.catalog.inputs import Points, handles_type, max_points, tolist
from service.catalog.registry import Process, registry

# -- input types -----------------------------------------------------------------------------
PinsInput = handles_type(
    "Vertices (nodes) held at given positions: their indices and positions, in the layout's "
    "dimension.", indices="Distinct vertex (node) indices, 0-based.",
    positions="The position of each, row i for indices[i]; k ≥ 2 coordinates.", max_dim=None)
"""Pinned vertices ``{"indices": [...], "positions": [[...], ...]}`` in any dimension
``k >= 2`` (the general ``Handles`` input has 2 or 3), validated into
:class:`algorithms.core.mesh.Handles` (structure only: against the mesh or graph, the check)."""


def _max_dense(info: ValidationInfo) -> int:
    limit = max_points(info)
    return MAX_DENSE_POINTS if limit is None else min(MAX_DENSE_POINTS, limit)


def _validate_distances(value: Any, info: ValidationInfo) -> np.ndarray:
    return as_distance_matrix(value, name=info.field_name or "distances",
                              max_points=_max_dense(info))


def _validate_pairs(value: Any, info: ValidationInfo) -> np.ndarray:
    name = info.field_name or "distance_pairs"
    return as_points(value, name=name, dim=3, max_points=_max_dense(info) ** 2)


def _nullable_list(a: np.ndarray) -> list[Any]:
    return [[None if np.isnan(x) else float(x) for x in row] for row in a]


DistanceMatrix = Annotated[
    np.ndarray,
    PlainValidator(_validate_distances),
    PlainSerializer(_nullable_list),
    WithJsonSchema({
        "type": "array",
        "description": "An (n, n) matrix of pairwise distances: non-negative, symmetric, zero "
        "diagonal; null marks an unknown distance.",
        "items": {"type": "array", "items": {"type": ["number", "null"], "minimum": 0}},
        "minItems": 2,
    }),
]
"""An ``(n, n)`` distance matrix, ``null`` (NaN) for unknown entries."""

DistancePairs = Annotated[
    np.ndarray,
    PlainValidator(_validate_pairs),
    PlainSerializer(tolist),
    WithJsonSchema({
        "type": "array",
        "description": "Known distances as rows (i, j, d): points i and j (0-based) are d "
        "apart.",
        "items": {"type": "array", "items": {"type": "number"}, "minItems": 3, "maxItems": 3},
        "minItems": 1,
    }),
]
"""Known distances as ``(m, 3)`` rows ``(i, j, d)``."""

_DISTANCE_INPUTS = {"distances": DistanceMatrix | None, "distance_pairs": DistancePairs | None}


_SQUARE = {"vertices": [[0, 0], [1, 0], [1, 1], [0, 1], [0.5, 0.5]],
           "faces": [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]}
_PATH = {"nodes": 3, "edges": [[0, 1], [1, 2]]}
_TRIANGLE = [[0, 3, 4], [3, 0, 5], [4, 5, 0]]
_SQUARE_DISTANCES = [[0, 1, 1.4142135623730951, 1], [1, 0, 1, None],
                     [1.4142135623730951, 1, 0, 1], [1, None, 1, 0]]

_layout = partial(Process, geometry=scenes.layout)
_distances = partial(_layout, inputs=_DISTANCE_INPUTS, limits={"max_iterations": Le(100_000)})

registry.add(_layout(laplacian, check=check_laplacian, examples={"mesh": _SQUARE},
                     inputs={"pins": PinsInput | None}, fast_path=True,
                     keywords=("tutte embedding", "spring layout", "parameterization",
                               "graph drawing", "harmonic map")))
registry.add(_layout(
    poisson, check=check_poisson, fast_path=True,
    examples={"graph": _PATH, "vectors": [[-1.0, 0.0], [-1.0, 0.0]],
              "anchors": {"indices": [0], "positions": [[0.0, 0.0]]}},
    inputs={"vectors": Points, "anchors": PinsInput | None, "pins": PinsInput | None},
    keywords=("poisson", "gradient domain", "least squares", "integration", "anchors")))
registry.add(_distances(mds, check=check_distances, examples={"distances": _TRIANGLE},
                        keywords=("mds", "torgerson", "principal coordinates",
                                  "matrix completion", "localization")))
registry.add(_distances(stress, check=check_stress, examples={"distances": _SQUARE_DISTANCES},
                        long=True, keywords=("smacof", "stress majorization", "metric mds",
                                             "graph drawing", "kamada-kawai")))
