"""Building blocks shared by every family: errors, validation, progress, types, small dense
linear algebra."""

from algorithms.core.errors import (
    Cancelled,
    ConvergenceWarning,
    DegenerateInputError,
    GeometryError,
    InvalidInputError,
)
from algorithms.core.linalg import Procrustes, homogeneous, numerical_rank, polar, procrustes
from algorithms.core.progress import Progress, as_progress, no_progress
from algorithms.core.validation import (
    as_bool,
    as_choice,
    as_float,
    as_indices,
    as_int,
    as_points,
    as_weights,
    check_min_points,
    same_dim,
    same_shape,
)

__all__ = [
    "Cancelled",
    "ConvergenceWarning",
    "DegenerateInputError",
    "GeometryError",
    "InvalidInputError",
    "Procrustes",
    "homogeneous",
    "numerical_rank",
    "polar",
    "procrustes",
    "Progress",
    "as_progress",
    "no_progress",
    "as_bool",
    "as_choice",
    "as_float",
    "as_indices",
    "as_int",
    "as_points",
    "as_weights",
    "check_min_points",
    "same_dim",
    "same_shape",
]
