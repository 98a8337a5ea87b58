"""Where an algorithm's independent calls run: one after the other in the calling thread by
default, or wherever the caller has installed a mapper.

An algorithm whose work splits into independent calls (the pairwise registrations of a pose
graph) hands them to :func:`task_map` instead of looping itself. Left alone, that is the
plain loop. A caller that has more room (the service, inside a job on a Dask worker, runs
the calls as tasks across the cluster) installs its own mapper for the duration of a call
with :func:`use_mapper`. The library imports nothing of the caller's: a mapper is any
callable with the signature of :func:`serial_map`.

The installed mapper lives in a :class:`contextvars.ContextVar`: it holds for the thread (or
asyncio task) that installed it and for nothing else, so two jobs that run at once in the
threads of one process never see each other's mapper. Threads started from inside the
block (a thread pool's) start from an empty context: their own calls of :func:`task_map`
run serially.

The contract of a call ``fn(item, progress)``, so that a mapper may run it in another
process:

- ``fn`` and the items are picklable (a module-level function, or a
  :func:`functools.partial` of one with picklable arguments) and each item holds what its
  call needs: only that is sent;
- ``fn`` reports through the ``progress`` it is handed, in the caller's own units (the
  ``done`` of the whole run). The serial mapper hands over the caller's callback itself;
  another may hand over one of its own that stops the call in the same way (it raises
  :class:`~algorithms.core.errors.Cancelled` on the same dismissal or time limit) and
  reports to the caller as the calls end;
- the results come back in the order of the items, each the same as the plain loop's; the
  first error of a call propagates (a mapper may then abandon the calls still to run).
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable, Iterator, Sequence
from contextvars import ContextVar
from typing import Any, Protocol, TypeVar

from algorithms.core.progress import Progress, as_progress

__all__ = ["Mapper", "serial_map", "task_map", "use_mapper", "current_mapper"]

T = TypeVar("T")
R = TypeVar("R")


class Mapper(Protocol):
    """A callable ``mapper(fn, items, progress)`` returning ``[fn(item, p) for item in
    items]`` in order, wherever it runs the calls (see the module's contract)."""

    def __call__(self, fn: Callable[[Any, Progress], Any], items: Sequence[Any],
                 progress: Progress) -> list[Any]: ...


def serial_map(fn: Callable[[T, Progress], R], items: Sequence[T],
               progress: Progress) -> list[R]:
    """The default mapper: the calls one after the other in this thread, each handed
    ``progress`` itself."""
    return [fn(item, progress) for item in items]


_MAPPER: ContextVar[Mapper] = ContextVar("algorithms_task_mapper", default=serial_map)


def task_map(fn: Callable[[T, Progress], R], items: Sequence[T],
             progress: Progress | None = None) -> list[R]:
    """``[fn(item, progress) for item in items]``, by the mapper installed in this context
    (:func:`serial_map` unless :func:`use_mapper` installed another).

    Parameters
    ----------
    fn : callable
        ``fn(item, progress)``: one independent call, picklable, reporting in the caller's
        units through the ``progress`` it is handed (the module's contract).
    items : sequence
        The calls' arguments, each holding only what its call needs.
    progress : callable, optional
        The caller's ``progress(done, total, message)``; it may raise
        :class:`~algorithms.core.errors.Cancelled`, which propagates.

    Returns
    -------
    list
        The results, in the order of ``items``.

    Examples
    --------
    >>> task_map(lambda x, progress: x * x, [1, 2, 3])
    [1, 4, 9]
    """
    return list(_MAPPER.get()(fn, list(items), as_progress(progress)))


def current_mapper() -> Mapper:
    """The mapper :func:`task_map` uses in this context."""
    return _MAPPER.get()


@contextlib.contextmanager
def use_mapper(mapper: Mapper) -> Iterator[Mapper]:
    """Install ``mapper`` for :func:`task_map` in this context (thread or asyncio task)
    inside the block; the previous one comes back after it. Blocks may nest.

    Examples
    --------
    >>> calls = []
    >>> def recording(fn, items, progress):
    ...     calls.append(len(items))
    ...     return serial_map(fn, items, progress)
    >>> with use_mapper(recording):
    ...     task_map(lambda x, progress: -x, [1, 2])
    [-1, -2]
    >>> calls, current_mapper() is serial_map
    ([2], True)
    """
    token = _MAPPER.set(mapper)
    try:
        yield mapper
    finally:
        _MAPPER.reset(token)
