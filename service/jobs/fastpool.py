"""The fast path's worker processes: small jobs run beside the service, never inside it.

A job on the fast path skips the scheduler's round trip, but it must not cost the service
anything it cannot take back. So it runs in one of a few worker processes of this pool
(``fast_path_threads`` of them), forked from a server process that imported the catalog
once (:mod:`multiprocessing`'s ``forkserver``), and each run is bounded:

- by the fast path's **budget** (``fast_path_seconds``): a job still running then was no
  fast job after all; its worker is killed and replaced, and :meth:`FastPool.run` answers
  ``None``, which tells the engine to hand the job to the Dask workers;
- by the job's **time limit**: past it the worker is killed and the job has failed
  (``time-limit-exceeded``): a job reported failed no longer uses a CPU;
- by **dismissal**: the ``stop`` event set, the worker is killed within
  :data:`POLL_INTERVAL` seconds.

A worker that dies (a crash, a kill by the memory killer) is replaced as well and the job
goes to the Dask workers, whose retries count such deaths. Jobs wait for a free worker in
the order they came; each waits at most the budget per job ahead of it. While no worker is
up (the pool is starting, or every worker is being replaced) :attr:`FastPool.ready` is
false and the engine sends fast jobs to Dask instead of queueing them.

Progress events of a running job come back over the worker's pipe and are handed to the
``publish`` callback (on the thread that watches the worker).
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import multiprocessing
import multiprocessing.forkserver
import signal
import threading
import time
from collections.abc import Callable, Iterator
from concurrent.futures import ThreadPoolExecutor
from multiprocessing.connection import Connection
from typing import Any

from service.jobs.runner import serve_fast
from service.jobs.status import Outcome

__all__ = ["FastPool", "POLL_INTERVAL"]

log = logging.getLogger("morphserve.fastpool")

POLL_INTERVAL = 0.05
"""Seconds between two looks at a running job's stop event and deadline (results are read
as soon as they arrive, not at this pace)."""

START_TIMEOUT = 120.0
"""Seconds a new worker may take to say it is ready."""


class _Worker:
    """One worker process and the parent's end of its pipe."""

    def __init__(self, ctx: Any, test_processes: bool) -> None:
        parent, child = ctx.Pipe()
        self.process = ctx.Process(target=serve_fast, args=(child, test_processes),
                                   name="morphserve-fast", daemon=True)
        self.process.start()
        child.close()
        self.conn: Connection = parent

    def wait_ready(self) -> bool:
        try:
            if self.conn.poll(START_TIMEOUT):
                return bool(self.conn.recv() == ("ready",))
        except (EOFError, OSError):
            pass
        return False

    def kill(self) -> None:
        self.process.kill()
        self.process.join(timeout=10)
        self.conn.close()


@contextlib.contextmanager
def children_ignore_sigint() -> Iterator[None]:
    """Ignore SIGINT while worker processes are started (the embedded cluster's, the fast
    path's forkserver), so that they inherit the ignoring: a Ctrl-C in the terminal reaches
    the whole process group, and the service (which closes them as it shuts down) should be
    the only one to act on it, not each child with a traceback of its own (a forkserver
    interrupted while it imports its preload prints one). Only the main thread may do so."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


class FastPool:
    """``size`` worker processes for fast-path jobs; see the module's docstring."""

    def __init__(self, size: int, *, budget: float, test_processes: bool = False) -> None:
        self.size = size
        self.budget = budget
        self.test_processes = test_processes
        self._ctx = multiprocessing.get_context("forkserver")
        self._ctx.set_forkserver_preload(["service.jobs.runner"])
        self._threads = ThreadPoolExecutor(max_workers=size, thread_name_prefix="morphserve-fast")
        self._spawner = ThreadPoolExecutor(max_workers=1, thread_name_prefix="morphserve-spawn")
        self._loop: asyncio.AbstractEventLoop | None = None
        self._idle: asyncio.Queue[_Worker | None] | None = None
        self._up = 0
        """Workers started and not dead: idle or running a job."""
        self._all: set[_Worker] = set()
        self._closed = False
        self.replaced = 0
        """Workers killed and replaced (overran, timed out, dismissed, died)."""

    @property
    def ready(self) -> bool:
        """At least one worker is up: a job given to :meth:`run` will get one."""
        return self._up > 0 and not self._closed

    def start(self) -> None:
        """Start the workers (in the background: :attr:`ready` turns true as they come up).
        Call it from the event loop; a second call does nothing."""
        if self._loop is not None or self._closed:
            return
        self._loop = asyncio.get_running_loop()
        self._idle = asyncio.Queue()
        with children_ignore_sigint():  # the forkserver, and so its forks, ignore Ctrl-C
            multiprocessing.forkserver.ensure_running()
        for _ in range(self.size):
            self._spawn()

    def _spawn(self) -> None:
        """Start one worker in the background; it joins the idle queue once ready."""
        if self._closed:
            return
        try:
            self._spawner.submit(self._start_worker)
        except RuntimeError:  # shut down meanwhile
            pass

    def _start_worker(self) -> None:
        assert self._loop is not None and self._idle is not None
        worker: _Worker | None = None
        try:
            worker = _Worker(self._ctx, self.test_processes)
            if not worker.wait_ready():
                raise RuntimeError("no word from the new worker")
        except Exception:
            log.exception("could not start a fast-path worker; fast jobs go to Dask")
            if worker is not None:
                worker.kill()
            worker = None  # wakes one waiting job, which then goes to Dask

        def arrive() -> None:
            assert self._idle is not None
            if worker is not None:
                if self._closed:
                    worker.kill()
                    return
                self._all.add(worker)
                self._up += 1
            self._idle.put_nowait(worker)
        try:
            self._loop.call_soon_threadsafe(arrive)
        except RuntimeError:  # the loop is closed
            if worker is not None:
                worker.kill()

    async def run(self, job_id: str, process_id: str, kwargs: dict[str, Any], *,
                  time_limit: float | None, stop: threading.Event,
                  publish: Callable[[dict[str, Any]], None]) -> Outcome | None:
        """Run one job on a worker; its outcome, or ``None`` when it must go to the Dask
        workers instead (it ran past the budget, its worker died, or no worker is up).

        ``stop`` set (dismissal) ends the run with a dismissed outcome; ``time_limit``
        seconds of running end it failed. Either way the worker is killed and replaced."""
        if not self.ready or self._idle is None:
            return None
        worker = await self._idle.get()
        if worker is None:  # a replacement failed to start
            return None
        if stop.is_set():
            self._idle.put_nowait(worker)
            return Outcome.dismissed()
        loop = asyncio.get_running_loop()
        try:
            end, value = await loop.run_in_executor(
                self._threads, self._call, worker, (job_id, process_id, kwargs, time_limit),
                time_limit, stop, publish)
        except BaseException:
            self._replace(worker)  # cancelled (the service closing) or a bug: not reusable
            raise
        if end == "done":
            self._idle.put_nowait(worker)
            outcome: Outcome = value
            return outcome
        self._replace(worker)
        if end == "stopped":
            return Outcome.dismissed()
        if end == "time-limit":
            assert time_limit is not None  # only a job with a limit runs out of it
            return Outcome.time_limit_exceeded(time_limit)
        log.info("fast-path job %s %s; handing it to the workers", job_id,
                 "ran past the fast path's budget" if end == "overran" else "lost its worker")
        return None

    def _call(self, worker: _Worker, task: tuple[Any, ...], time_limit: float | None,
              stop: threading.Event, publish: Callable[[dict[str, Any]], None]
              ) -> tuple[str, Any]:
        """Send the task and watch it (on a thread of its own): ``("done", outcome)``, or
        how it was cut short: ``"overran"``, ``"time-limit"``, ``"stopped"``, ``"died"``;
        cut short, the worker is dead when this returns."""
        end = self._watch(worker, task, time_limit, stop, publish)
        if end[0] != "done":
            worker.process.kill()
            worker.process.join(timeout=10)
        return end

    def _watch(self, worker: _Worker, task: tuple[Any, ...], time_limit: float | None,
               stop: threading.Event, publish: Callable[[dict[str, Any]], None]
               ) -> tuple[str, Any]:
        started = time.monotonic()
        limit = min(self.budget, time_limit if time_limit is not None else float("inf"))
        deadline = started + limit
        try:
            worker.conn.send(task)
            while True:
                if stop.is_set():
                    return "stopped", None
                remaining = deadline - time.monotonic()
                if remaining <= 0:
                    overran = time_limit is None or self.budget < time_limit
                    return ("overran" if overran else "time-limit"), None
                if worker.conn.poll(min(remaining, POLL_INTERVAL)):
                    kind, value = worker.conn.recv()
                    if kind == "event":
                        publish(value)
                        continue
                    return "done", value
        except (EOFError, OSError):
            return "died", None

    def _replace(self, worker: _Worker) -> None:
        """Kill ``worker`` (it is running a job nobody wants any more) and start another."""
        self._up -= 1
        self._all.discard(worker)
        self.replaced += 1
        try:
            self._spawner.submit(worker.kill)
        except RuntimeError:
            worker.kill()
        self._spawn()

    def shutdown(self, wait: bool = False, cancel_futures: bool = True) -> None:
        """Stop every worker (as :meth:`concurrent.futures.Executor.shutdown` is called)."""
        self._closed = True
        self._spawner.shutdown(wait=wait, cancel_futures=cancel_futures)
        for worker in list(self._all):
            worker.kill()
        self._all.clear()
        self._threads.shutdown(wait=wait, cancel_futures=cancel_futures)
