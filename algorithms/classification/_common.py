"""Shared by the classification family: label checks and deterministic signs."""

from __future__ import annotations

from typing import Any

import numpy as np

from algorithms.core.errors import InvalidInputError
from algorithms.core.types import FloatArray, IntArray
from algorithms.core.validation import as_points, same_dim

__all__ = ["as_labels", "check_labelled", "fix_signs"]


def as_labels(labels: Any, n: int, *, name: str = "labels",
              points: str = "points") -> tuple[np.ndarray, IntArray]:
    """Check one class label per point; return the sorted classes and each point's class
    index. Labels are integers or strings (not a mix, not floats with fractions)."""
    try:
        arr = np.asarray(labels)
    except (TypeError, ValueError):
        arr = None
    if arr is None or arr.ndim != 1 or arr.dtype.kind not in "iuUSf":
        shape = "" if arr is None else f" of shape {arr.shape} and dtype {arr.dtype}"
        raise InvalidInputError(
            f"Expected `{name}` to be a flat list of class labels (integers or strings), got "
            f"{type(labels).__name__}{shape}.", field=name)
    if arr.dtype.kind == "f":
        bad = ~np.isfinite(arr) | (arr != np.round(arr))
        if bad.any():
            i = int(np.argmax(bad))
            raise InvalidInputError(
                f"Expected `{name}` to hold integer or string class labels, got "
                f"{float(arr[i])!r} at position {i}.", field=name)
        arr = arr.astype(np.int64)
    if arr.shape[0] != n:
        raise InvalidInputError(
            f"Expected `{name}` to hold one label per row of `{points}` ({n}), got "
            f"{arr.shape[0]}.", field=name)
    classes, index = np.unique(arr, return_inverse=True)
    if classes.shape[0] < 2:
        raise InvalidInputError(
            f"Expected `{name}` to name at least 2 classes, got {classes.shape[0]}.",
            field=name)
    return classes, index.astype(np.int64)


def check_labelled(points: Any, labels: Any, query: Any = None, *,
                   max_points: int | None = None
                   ) -> tuple[FloatArray, np.ndarray, IntArray, FloatArray | None]:
    """Labelled points: at least 3, one label each (:func:`as_labels`), and query points,
    when given, of their dimension. Returns the points, classes, class indices and query."""
    x = as_points(points, name="points", min_points=3, max_points=max_points)
    classes, y = as_labels(labels, x.shape[0])
    q = None
    if query is not None:
        q = as_points(query, name="query")
        same_dim(x, q, names=("points", "query"))
    return x, classes, y, q


def fix_signs(vectors: FloatArray) -> FloatArray:
    """Flip each column so that its largest entry (in absolute value) is positive."""
    if vectors.size == 0:
        return vectors
    big = np.argmax(np.abs(vectors), axis=0)
    return vectors * np.where(vectors[big, np.arange(vectors.shape[1])] < 0, -1.0, 1.0)
