"""A job's own tasks: the independent calls an algorithm hands to
:func:`algorithms.core.parallel.task_map` (the pairwise registrations of a multiway pose
graph), run as Dask tasks across the cluster while the job runs on a Dask worker.

:func:`job_tasks` installs the mapper (:class:`DaskMapper`) around the algorithm's call in
:func:`~service.jobs.runner.run_job`, for jobs on a Dask worker only: on the fast path and
in-process, ``task_map`` stays the plain loop.

How a map runs, from the job's thread on its worker:

- ``worker_client()`` secedes the job's thread from the worker's pool, so the slot it held
  runs tasks meanwhile (with one thread per worker, the job's own worker is one of the
  workers its tasks run on), and rejoins it when the tasks are done;
- each call is one task, ``pure=False``, keyed ``morphserve-{job}-task-{map}-{n}`` (the
  job's key ``morphserve-{job}`` and a suffix), sent its own item only;
- in a task, the call's progress callback is a :class:`~service.jobs.runner.Reporter` of
  the job that publishes nothing but keeps its stops: it raises
  :class:`~algorithms.core.errors.Cancelled` when the job's cancel event is set or when the
  time left to the job when the task was submitted has run out. A task stopped so
  returns the reason, and the job ends dismissed or timed out as if it had stopped itself;
- the job's progress advances as tasks end (each task's last report, the largest so far,
  goes to the job's callback, which also looks at the cancel event and the deadline);
- results come back in the items' order. The first error of a task (a degenerate pair)
  propagates as the job's error; the tasks not yet started are then cancelled, and those
  running end with their own call (they are bounded by their iterations and the job's
  deadline).
"""

from __future__ import annotations

import contextlib
import math
import time
import uuid
from collections.abc import Callable, Iterator, Sequence
from typing import TYPE_CHECKING, Any

from algorithms.core.errors import Cancelled
from algorithms.core.parallel import serial_map, use_mapper
from algorithms.core.progress import Progress
from service.binary import owned_value

if TYPE_CHECKING:
    from service.jobs.runner import Reporter

__all__ = ["DaskMapper", "job_tasks", "task_prefix"]

_DONE = "done"
_CANCELLED = "cancelled"


def task_prefix(job_id: str) -> str:
    """The start of the key of every task of the job ``job_id``."""
    return f"morphserve-{job_id}-task-"


@contextlib.contextmanager
def job_tasks(reporter: Reporter) -> Iterator[None]:
    """Inside the block, :func:`~algorithms.core.parallel.task_map` runs its calls as Dask
    tasks if the job of ``reporter`` runs on a Dask worker (the reporter knows its worker);
    else (the fast path, in-process calls) it stays the plain loop."""
    if reporter.worker is None:
        yield
        return
    with use_mapper(DaskMapper(reporter)):
        yield


class DaskMapper:
    """The mapper of :mod:`algorithms.core.parallel` for a job running on a Dask worker: one
    task per call, from the job's worker's client (the module's description)."""

    def __init__(self, reporter: Reporter) -> None:
        self.reporter = reporter

    def __call__(self, fn: Callable[[Any, Progress], Any], items: Sequence[Any],
                 progress: Progress) -> list[Any]:
        if len(items) < 2:  # one call: a task would free nothing
            return serial_map(fn, items, progress)
        from distributed import as_completed, worker_client

        job_id = self.reporter.job_id
        left = self.reporter.deadline - time.monotonic()
        time_left = None if math.isinf(left) else max(left, 1e-6)
        prefix = f"{task_prefix(job_id)}{uuid.uuid4().hex[:12]}-"
        results: list[Any] = [None] * len(items)
        with worker_client() as client:  # secedes now, rejoins at the end of the block
            # one message for all the tasks; the results fetched by the batch that ended
            futures = client.map(_run_task, items, fn=fn, job_id=job_id,
                                 time_left=time_left, pure=False,
                                 key=[f"{prefix}{n}" for n in range(len(items))])
            index = {f.key: n for n, f in enumerate(futures)}
            best = -math.inf
            try:
                for batch in as_completed(futures).batches():
                    # a task's error raises here
                    for future, (status, value, last) in zip(batch, client.gather(batch),
                                                             strict=True):
                        if status == _CANCELLED:
                            self.reporter.reason = value
                            raise Cancelled(f"a task of the job stopped: {value}")
                        results[index[future.key]] = value
                        if last is not None and last[0] > best:
                            best = last[0]
                            progress(*last)
            except BaseException:
                client.cancel(futures)  # those not started never will
                raise
        return results


class _LastReport:
    """A task's progress callback: the job's stops (``reporter``), the last report kept."""

    def __init__(self, reporter: Reporter) -> None:
        self.reporter = reporter
        self.last: tuple[float, float, str] | None = None

    def __call__(self, done: float, total: float, message: str = "") -> None:
        self.last = (done, total, message)
        self.reporter(done, total, message)


def _drop(event: dict[str, Any]) -> None:
    """A task publishes no progress of its own: the job's thread reports as tasks end."""


def _run_task(item: Any, fn: Callable[[Any, Progress], Any], job_id: str,
              time_left: float | None) -> tuple[str, Any, tuple[float, float, str] | None]:
    """One call, on a worker: ``(status, result or reason, last report)``; ``status`` is
    ``"done"``, or ``"cancelled"`` with the reason (``"dismissed"``, ``"time-limit"``)."""
    from distributed import get_worker

    from service.jobs.runner import Reporter

    reporter = Reporter(job_id, time_left, get_worker(), publish=_drop)
    progress = _LastReport(reporter)
    try:
        value = fn(owned_value(item), progress)
    except Cancelled:
        return _CANCELLED, reporter.reason or "dismissed", progress.last
    return _DONE, value, progress.last
