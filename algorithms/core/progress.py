"""The progress protocol.

Long-running algorithms take ``progress: Progress | None = None`` and call it as
``progress(done, total, message)`` at natural steps (each iteration, each solved
right-hand side). ``done`` and ``total`` are in the algorithm's own units (iterations,
points); the service turns them into a percentage. The callback may raise
:class:`~algorithms.core.errors.Cancelled`; algorithms must let it propagate and hold no
state that a cancelled call would leave half-written. Callers that do not care pass
nothing: :func:`as_progress` turns ``None`` into :func:`no_progress`.
"""

from __future__ import annotations

from typing import Protocol

__all__ = ["Progress", "no_progress", "as_progress"]


class Progress(Protocol):
    """A callable ``progress(done, total, message="")`` that may raise ``Cancelled``."""

    def __call__(self, done: float, total: float, message: str = "") -> None: ...


def no_progress(done: float, total: float, message: str = "") -> None:
    """The default progress callback: does nothing."""


def as_progress(progress: Progress | None) -> Progress:
    """Return ``progress`` itself, or :func:`no_progress` when it is ``None``."""
    return no_progress if progress is None else progress
