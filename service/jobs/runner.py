"""What runs on a Dask worker: one job, start to end.

:func:`run_job` loads the inputs, calls the algorithm through the catalog with a progress
callback and returns an :class:`~service.jobs.status.Outcome`; with ``persist`` (external
scheduler, tasks submitted fire-and-forget) it first writes the outputs atomically to
``results/{job_id}.pkl`` in the shared data dir, so they outlive a restarting API. It never
raises for a job's own failure: algorithm errors become a ``failed`` outcome carrying a
problem body, so a bad input never costs a worker.

The progress callback (:class:`Reporter`) is also how dismissal and time limits reach running
work, since Dask cannot stop a running Python function: it raises
:class:`~algorithms.core.errors.Cancelled` when the job's ``distributed.Event`` is set or its
deadline has passed. Progress is published with ``Worker.log_event`` on :data:`TOPIC`; the
service subscribes to it.

:func:`serve_fast` is the loop of a fast-path worker process (:mod:`service.jobs.fastpool`):
the same :func:`run_job`, its tasks and progress passing over a pipe.
"""

from __future__ import annotations

import dataclasses
import logging
import math
import pickle
import time
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from algorithms.core.errors import Cancelled, GeometryError
from service.binary import owned
from service.catalog import lookup
from service.jobs.spool import load_inputs
from service.jobs.status import Outcome
from service.jobs.store import result_path, write_atomic
from service.jobs.tasks import job_tasks
from service.problems import geometry_error_problem, problem_body

__all__ = ["TOPIC", "run_job", "cancel_event_name", "Reporter", "serve_fast"]

log = logging.getLogger("morphserve.runner")

TOPIC = "morphserve-progress"
EMIT_INTERVAL = 0.1
"""Seconds between two progress events of one job."""
CANCEL_CHECK_INTERVAL = 0.2
"""Seconds between two looks at the job's cancel event (each one is a scheduler round trip)."""


def cancel_event_name(job_id: str) -> str:
    return f"morphserve-cancel-{job_id}"


def _current_worker() -> Any:
    try:
        from distributed import get_worker

        return get_worker()
    except (ImportError, ValueError):
        return None  # run in-process (tests, the service's own fast path)


class Reporter:
    """The ``progress(done, total, message)`` callback handed to the algorithm.

    On a worker it publishes with ``log_event`` and looks at the job's ``distributed.Event``;
    in the service's own process (the fast path) ``publish`` and ``cancelled`` are given.
    """

    def __init__(self, job_id: str, time_limit: float | None, worker: Any = None, *,
                 publish: Any = None, cancelled: Any = None) -> None:
        self.job_id = job_id
        self.time_limit = time_limit
        self.worker = worker
        self._publish = publish
        self._cancelled = cancelled
        now = time.monotonic()
        self.deadline = now + time_limit if time_limit else math.inf
        self._last_emit = -math.inf
        self._last_check = now
        self.reason: str | None = None

    def emit(self, kind: str, progress: int = 0, message: str = "") -> None:
        event = {"job": self.job_id, "kind": kind, "progress": progress, "message": message}
        if self._publish is not None:
            self._publish(event)
        elif self.worker is not None:
            self.worker.log_event(TOPIC, event)

    def _cancel_requested(self) -> bool:
        if self._cancelled is not None:
            return bool(self._cancelled())
        if self.worker is None:
            return False
        from distributed import Event

        return bool(Event(cancel_event_name(self.job_id)).is_set())

    def __call__(self, done: float, total: float, message: str = "") -> None:
        now = time.monotonic()
        if now > self.deadline:
            self.reason = "time-limit"
            raise Cancelled(f"time limit of {self.time_limit:g} s exceeded")
        if now - self._last_check >= CANCEL_CHECK_INTERVAL:
            self._last_check = now
            if self._cancel_requested():
                self.reason = "dismissed"
                raise Cancelled("dismissed by the client")
        if now - self._last_emit >= EMIT_INTERVAL:
            self._last_emit = now
            pct = int(max(0.0, min(100.0, 100.0 * done / total))) if total else 0
            self.emit("progress", pct, message)


def _check_finite(outputs: Mapping[str, Any], prefix: str = "") -> None:
    """A numerical failure must not pass as a result: no NaN or Inf in any output, nested
    results (a Mesh's vertices) and lists of numbers included."""
    for name, value in outputs.items():
        where = f"{prefix}{name}"
        if dataclasses.is_dataclass(value) and not isinstance(value, type):
            _check_finite({f.name: getattr(value, f.name) for f in dataclasses.fields(value)},
                          f"{where}.")
        elif isinstance(value, np.ndarray) and value.dtype.kind in "fc" and \
                not np.isfinite(value).all():
            raise FloatingPointError(f"output {where!r} holds NaN or Inf")
        elif isinstance(value, float) and not math.isfinite(value):
            raise FloatingPointError(f"output {where!r} is {value}")
        elif isinstance(value, (list, tuple)) and value and \
                all(isinstance(v, float) for v in value) and not all(map(math.isfinite, value)):
            raise FloatingPointError(f"output {where!r} holds NaN or Inf")


def run_job(job_id: str, process_id: str, payload: Mapping[str, Any] | str, *,
            data_dir: str = "", time_limit: float | None = None, fsync: bool = True,
            test_processes: bool = False, persist: bool = False,
            reporter: Reporter | None = None) -> Outcome:
    """Run one job: the process ``process_id`` on ``payload``, its inputs (or the path of
    the file holding them); return how it ended, successful with its outputs, or failed or
    dismissed with a problem.

    ``time_limit`` is in seconds; ``persist`` (external scheduler) first writes the outputs
    to ``results/{job_id}.pkl`` under ``data_dir``, fsynced if ``fsync``;
    ``test_processes`` offers the diagnostic processes; ``reporter`` is the progress
    callback (default: one publishing on this worker's event log)."""
    reporter = reporter or Reporter(job_id, time_limit, _current_worker())
    reporter.emit("started", 0, "running")
    try:
        process = lookup(process_id, test_processes=test_processes)
        if process is None:
            raise LookupError(f"unknown process {process_id!r} on this worker")
        # inputs unpickled (inline ones from the task's frame) are views at any byte offset,
        # maybe read-only: a method gets aligned, writable arrays, as a local call does
        # (BLAS takes other paths for misaligned operands, with other last bits)
        kwargs = owned(dict(payload) if not isinstance(payload, str) else load_inputs(payload))
        with job_tasks(reporter):  # on a Dask worker, task_map's calls run as tasks
            outputs = process.run(kwargs, progress=reporter)
        _check_finite(outputs)
        if persist:
            write_atomic(result_path(Path(data_dir), job_id),
                         pickle.dumps(outputs, protocol=5), fsync=fsync)
        return Outcome.successful(outputs)
    except Cancelled:
        if reporter.reason == "time-limit":
            assert reporter.time_limit is not None  # only a limit runs out
            return Outcome.time_limit_exceeded(reporter.time_limit)
        return Outcome.dismissed()
    except GeometryError as exc:
        return Outcome.failed(geometry_error_problem(exc))
    except Exception as exc:  # a bug in an algorithm: fail the job, keep the worker
        log.exception("job %s (%s) failed", job_id, process_id)
        return Outcome.failed(problem_body(
            "job-failed", f"The algorithm failed: {type(exc).__name__}: {exc}"))


def serve_fast(conn: Any, test_processes: bool = False) -> None:
    """Run jobs sent over ``conn`` (a :class:`multiprocessing.connection.Connection`) until
    it closes: the loop of one fast-path worker process.

    It says ``("ready",)`` once, then takes tasks ``(job_id, process_id, inputs,
    time_limit)`` one at a time and answers each with ``("event", event)`` for every
    progress event and ``("outcome", outcome)`` at the end. Dismissal and time limits are
    the parent's to enforce: it kills this process (a kill is the only stop that cannot be
    ignored)."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)  # the service's Ctrl-C is the service's
    conn.send(("ready",))

    def publish(event: dict[str, Any]) -> None:
        if event["kind"] != "started":  # the parent noted the start
            try:
                conn.send(("event", event))
            except OSError:  # the parent is gone: so is the job
                raise Cancelled("the service closed the fast path") from None

    while True:
        try:
            job_id, process_id, payload, time_limit = conn.recv()
        except (EOFError, OSError):
            return
        reporter = Reporter(job_id, time_limit, publish=publish, cancelled=lambda: False)
        outcome = run_job(job_id, process_id, payload, time_limit=time_limit,
                          test_processes=test_processes, reporter=reporter)
        try:
            conn.send(("outcome", outcome))
        except OSError:
            return
