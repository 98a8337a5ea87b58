"""Input types of the catalog's parameter models.

Geometry inputs arrive as JSON arrays and leave validation as numpy arrays, checked by
:mod:`algorithms.core.validation` (the only place input checks live), with a JSON Schema for
the process description. Limits that depend on the service's settings (most points per
input) come through pydantic's validation context: ``{"max_points": N}``.
"""

from __future__ import annotations

from typing import Annotated, Any

import numpy as np
from pydantic import PlainSerializer, PlainValidator, ValidationInfo, WithJsonSchema

from algorithms.core.errors import InvalidInputError
from algorithms.core.validation import as_points

__all__ = ["Points", "Weights", "points_schema"]


def points_schema(description: str, *, dim: int | None = None,
                  min_points: int = 1) -> dict[str, Any]:
    row: dict[str, Any] = {"type": "array", "items": {"type": "number"}, "minItems": dim or 1}
    if dim is not None:
        row["maxItems"] = dim
    return {"type": "array", "items": row, "minItems": min_points, "description": description}


def _validate_points(value: Any, info: ValidationInfo) -> np.ndarray:
    max_points = (info.context or {}).get("max_points")
    return as_points(value, name=info.field_name or "points", max_points=max_points)


def _validate_weights(value: Any, info: ValidationInfo) -> np.ndarray:
    name = info.field_name or "weights"
    try:
        arr = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise InvalidInputError(
            f"Expected `{name}` to be a flat list of numbers, got {type(value).__name__}.",
            field=name) from None
    if arr.ndim != 1:
        raise InvalidInputError(
            f"Expected `{name}` to be a flat list of numbers, got an array of shape "
            f"{arr.shape}.", field=name)
    return arr  # length, sign and finiteness against the paired points: as_weights


def _tolist(a: np.ndarray) -> list[Any]:
    return a.tolist()


Points = Annotated[
    np.ndarray,
    PlainValidator(_validate_points),
    PlainSerializer(_tolist),
    WithJsonSchema(points_schema("An (n, d) array of point coordinates, one row per point.")),
]
"""An (n, d) float array of points, given as a JSON array of rows."""

Weights = Annotated[
    np.ndarray,
    PlainValidator(_validate_weights),
    PlainSerializer(_tolist),
    WithJsonSchema({"type": "array", "items": {"type": "number", "minimum": 0},
                    "description": "One non-negative weight per point pair."}),
]
"""A flat float array of per-pair weights."""
