"""The error tree shared by every algorithm.

::

    Exception
     └── GeometryError                       base of everything raised on purpose here
          ├── InvalidInputError(ValueError)  the input is malformed: shape, dtype, NaN/Inf,
          │    │                             index out of range, unknown option
          │    └── DegenerateInputError      well-formed but the problem is undetermined:
          │                                  coincident or collinear points, no pin in a
          │                                  component, zero-area faces
          └── Cancelled                      the progress callback asked the work to stop
                                             (dismissal or a time limit)

    UserWarning
     └── ConvergenceWarning                  an iterative method stopped before its tolerance

``InvalidInputError`` subclasses :class:`ValueError` so callers that catch ``ValueError`` (as
with numpy and scipy) keep working. Every error may name the input it is about in ``field``
(``"source"``, ``"faces"``, ``"k"``); the service turns that into the ``input`` member of a
problem+json ``errors`` entry. Not converging is not an error: results carry
``converged=False`` and a :class:`ConvergenceWarning` is issued.
"""

from __future__ import annotations

import sys
import warnings
from collections.abc import Callable

__all__ = [
    "GeometryError",
    "InvalidInputError",
    "DegenerateInputError",
    "Cancelled",
    "ConvergenceWarning",
    "warn",
]


class GeometryError(Exception):
    """Base of every error raised on purpose by :mod:`algorithms`.

    Parameters
    ----------
    message : str
        What was expected and what came, e.g. "Expected `source` to have shape (n, 3),
        got (5, 2)."
    field : str, optional
        The name of the input the error is about, as the caller spelled it.
    """

    def __init__(self, message: str, *, field: str | None = None) -> None:
        super().__init__(message)
        self.message = message
        self.field = field

    def __reduce__(  # keep `field` when pickled across processes (Dask workers)
        self,
    ) -> tuple[Callable[..., GeometryError], tuple[type[GeometryError], str, str | None]]:
        return (_rebuild, (type(self), self.message, self.field))


def _rebuild(cls: type[GeometryError], message: str, field: str | None) -> GeometryError:
    return cls(message, field=field)


class InvalidInputError(GeometryError, ValueError):
    """The input is malformed: wrong shape or dtype, NaN/Inf, an index out of range, an
    unknown option or a parameter outside its domain."""


class DegenerateInputError(InvalidInputError):
    """The input is well formed but the problem it poses is undetermined or singular:
    too few distinct points, coincident or collinear points where a rank is needed, a
    component without a pin, zero-area faces."""


class Cancelled(GeometryError):
    """Raised from a progress callback to stop long work (dismissal, time limit)."""


class ConvergenceWarning(UserWarning):
    """An iterative method reached its iteration limit before its tolerance."""


def warn(message: str, category: type[Warning] = ConvergenceWarning) -> None:
    """Issue a warning attributed to the first caller outside this library.

    A fixed ``stacklevel`` points at the wrong line as soon as a function is reached through
    another (a validating wrapper, a dispatcher such as ``multiway``, ICP's PCA start), so
    the frames of ``algorithms`` are skipped: the warning names the user's line that called
    the library (or the service's runner)."""
    frame = sys._getframe(1)
    level = 2  # warnings.warn's stacklevel of our caller
    while frame.f_back is not None and str(frame.f_globals.get("__name__", "")).startswith(
            "algorithms."):
        frame = frame.f_back
        level += 1
    warnings.warn(message, category, stacklevel=level)
