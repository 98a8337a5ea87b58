"""Shape interpolation (homotopy): frames of a path from a source shape to a target shape
(the same points, or a mesh with the same faces) or to its image under a transform. A whole
shape moves by one interpolated map (``affine``: polar decomposition; ``rigid``: a rigid
motion or similarity), or every face by its own map with the vertices solved for per frame
(``arap``: Alexa et al. 2000; ``poisson``: Xu et al. 2005).

The readers of the inputs every method shares (:func:`read_shape`, :func:`read_pair`,
:func:`read_times`, :func:`check_frame_count`) are public, so that a caller (the service)
can refuse a request before running it with the methods' own checks and messages."""

from algorithms.interpolation._common import (
    DEFAULT_TIMES,
    MAX_FRAMES,
    Pair,
    check_anchored,
    check_frame_count,
    check_pair,
    read_pair,
    read_shape,
    read_times,
    surface_triangles,
)
from algorithms.interpolation.affine import AffineInterpolationResult, affine
from algorithms.interpolation.arap import ArapInterpolationResult, arap
from algorithms.interpolation.poisson import PoissonInterpolationResult, poisson
from algorithms.interpolation.rigid import RigidInterpolationResult, rigid

__all__ = [
    "DEFAULT_TIMES",
    "MAX_FRAMES",
    "Pair",
    "check_anchored",
    "check_frame_count",
    "check_pair",
    "read_pair",
    "read_shape",
    "read_times",
    "surface_triangles",
    "AffineInterpolationResult",
    "affine",
    "ArapInterpolationResult",
    "arap",
    "PoissonInterpolationResult",
    "poisson",
    "RigidInterpolationResult",
    "rigid",
]
