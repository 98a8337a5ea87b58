"""The execution engine: Dask distributed, embedded or external, plus a fast path.

Embedded (default): a :class:`distributed.LocalCluster` with process workers, one thread each,
started with the service. External: ``MORPHSERVE_SCHEDULER=tcp://host:8786``; tasks are then
submitted with ``fire_and_forget`` and the workers write their outputs to the shared data dir,
so work survives a restarting API.

Fast path: a round trip through the scheduler costs ~11 ms on a 2-core machine, more than a
closed-form job on a thousand points takes. Jobs of processes marked ``fast_path`` whose inputs
are at most ``fast_path_bytes`` run on a small thread pool inside the service instead. They are
recorded, reported, dismissable and time-limited exactly like the others; after a restart they
are resubmitted through Dask, never in-process, so a job that crashes the service cannot do it
twice. A fast-path job whose client waits for it (``Prefer: wait``) runs before its row is
written, and is then recorded finished in one commit (:meth:`Engine.run_first`): the client
hears of it only after that commit, and a job that takes longer than the wait is recorded
accepted and goes on as any other.

For every job the engine keeps a :class:`_Handle` and a watcher task that records the outcome
in the store and wakes the requests waiting on it (``Prefer: wait``). Progress events
(``log_event`` on :data:`~service.jobs.runner.TOPIC`, or direct calls on the fast path) update
the rows. Dismissal sets the job's ``distributed.Event`` (or its in-process flag), which the
runner's progress callback sees; a Dask job that outlives its time limit by :data:`GRACE`
seconds without cooperating gets its worker restarted.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import signal
import threading
import time
from collections.abc import Awaitable, Callable, Iterator
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from typing import Any

import dask
from distributed import Client, Event, LocalCluster, WorkerPlugin, fire_and_forget
from distributed.client import Future, FutureCancelledError
from distributed.scheduler import KilledWorker

from service.jobs.runner import TOPIC, Reporter, cancel_event_name, run_job
from service.jobs.status import JobStatus, Outcome
from service.jobs.store import JobRecord, JobStore
from service.problems import problem_body
from service.settings import Settings

__all__ = ["Engine", "GRACE"]

log = logging.getLogger("morphserve.engine")

GRACE = 2.0
"""Seconds past its time limit after which a job that ignores its cancel event is stopped
by restarting its worker."""


@contextlib.contextmanager
def _children_ignore_sigint() -> Iterator[None]:
    """Ignore SIGINT while the embedded cluster's worker processes are spawned, so that they
    inherit the ignoring: a Ctrl-C in the terminal reaches the whole process group, and the
    service (which closes the cluster as it shuts down) should be the only one to act on
    it, not each worker with a traceback of its own. Only the main thread may do so."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


class WarmUp(WorkerPlugin):
    """Imports the runner (and so the catalog and every algorithm) when a worker starts."""

    def setup(self, worker: Any) -> None:
        import service.jobs.runner  # noqa: F401


@dataclass
class _Handle:
    job: JobRecord
    outcome: asyncio.Future[Outcome]
    future: Future[Outcome] | None = None
    """The Dask future; None on the fast path."""
    cancel: threading.Event = field(default_factory=threading.Event)
    """The fast path's dismissal flag."""
    started: float | None = None
    marked_running: bool = False
    recording: bool = False
    """The outcome is being committed: the handle stays in the table until it is durable."""


#: Dask's monitoring, turned down. The embedded scheduler and the nannies live in the
#: service's own event loop: at the defaults (psutil disk and network counters every 0.5 s,
#: each nanny's memory every 0.1 s, a 20 ms tick, a 10 ms statistical profiler in every
#: worker) they took about a quarter of the service's busy CPU under load (py-spy), time
#: every request waited for. The memory limit is still enforced, once a second; the tick
#: still warns of a blocked loop.
QUIET_MONITORING = {
    "distributed.admin.system-monitor.interval": "2s",
    "distributed.admin.system-monitor.disk": False,
    "distributed.admin.system-monitor.gil.enabled": False,
    "distributed.admin.tick.interval": "250ms",
    "distributed.worker.memory.monitor-interval": "1s",
    "distributed.worker.profile.enabled": False,
}


class Engine:
    """Runs jobs and records their outcome in the :class:`JobStore`."""

    def __init__(self, settings: Settings, store: JobStore) -> None:
        self.settings = settings
        self.store = store
        self.cluster: LocalCluster | None = None
        self.client: Client | None = None
        self._jobs: dict[str, _Handle] = {}
        self._unrecorded = 0
        """Fast-path jobs running before their row is written (:meth:`run_first`)."""
        self._tasks: set[asyncio.Task[Any]] = set()
        self._pool = ThreadPoolExecutor(max_workers=settings.fast_path_threads,
                                        thread_name_prefix="morphserve-fast")
        self._closing = False
        self.on_finish: list[Callable[[JobRecord, Outcome], Any]] = []
        """Called with the job and its outcome when it ends (subscriber callbacks)."""
        self.on_start: list[Callable[[JobRecord], Any]] = []
        """Called with the job when it starts running."""

    # -- life cycle --------------------------------------------------------------------------
    async def start(self) -> None:
        dask.config.set({"distributed.scheduler.allowed-failures":
                         self.settings.allowed_failures, **QUIET_MONITORING})
        if self.settings.scheduler:
            self.client = await Client(self.settings.scheduler, asynchronous=True)
        else:
            with _children_ignore_sigint():
                self.cluster = await LocalCluster(
                    n_workers=self.settings.workers, threads_per_worker=1, processes=True,
                    asynchronous=True, dashboard_address=None, scheduler_port=0,
                    host="127.0.0.1", memory_limit=self.settings.worker_memory_limit,
                    silence_logs=logging.ERROR)
            self.client = await Client(self.cluster, asynchronous=True)
        self.client.subscribe_topic(TOPIC, self._on_event)
        await self.client.register_plugin(WarmUp(), name="morphserve-warm-up")
        await self.recover()
        self._spawn(self._sweep())

    async def close(self) -> None:
        self._closing = True
        for task in list(self._tasks):
            task.cancel()
        for handle in self._jobs.values():
            handle.cancel.set()
        self._pool.shutdown(wait=False, cancel_futures=True)
        if self.client is not None:
            await self.client.close()
        if self.cluster is not None:
            closing = self.cluster.close()  # None only for a synchronous cluster: never here
            if closing is not None:
                await closing

    def _spawn(self, coro: Any) -> asyncio.Task[Any]:
        task = asyncio.get_running_loop().create_task(coro)
        self._tasks.add(task)
        task.add_done_callback(self._tasks.discard)
        return task

    @property
    def active(self) -> int:
        """Jobs accepted or running here (the queue-length limit counts these)."""
        return len(self._jobs) + self._unrecorded

    async def n_workers(self) -> int:
        if self.client is None:
            return 0
        try:
            return len(await self.client.nthreads())
        except Exception:  # scheduler gone
            return 0

    # -- submission --------------------------------------------------------------------------
    def submit(self, job: JobRecord, payload: dict[str, Any] | str, *,
               fast: bool = False) -> None:
        """Run ``job``: on the fast path when ``fast`` (payload must be the inputs), else on
        Dask. Returns at once; :meth:`wait` waits."""
        handle = _Handle(job, asyncio.get_running_loop().create_future())
        self._jobs[job.id] = handle
        if fast and isinstance(payload, dict):
            self._spawn(self._run_fast(handle, payload))
            return
        assert self.client is not None, "engine not started"
        persist = self.settings.scheduler is not None
        # Dask hands the keywords it does not take itself (key, pure, ...) to run_job
        handle.future = self.client.submit(
            run_job, job.id, job.process, payload, data_dir=str(self.store.data_dir),
            time_limit=job.time_limit, fsync=self.settings.fsync,
            test_processes=self.settings.test_processes, persist=persist,
            key=f"morphserve-{job.id}", pure=False)
        if persist:
            fire_and_forget(handle.future)
        self._spawn(self._watch(handle))

    async def recover(self) -> None:
        """Finish what a previous run of the service left: complete rows whose outputs a
        worker wrote, resubmit the others (through Dask)."""
        jobs = self.store.unfinished()
        resubmitted = 0
        for job in jobs:
            if self.store.result_file_exists(job.id):  # start-up: the loop serves nothing yet
                self.store.finish(job.id, JobStatus.SUCCESSFUL,
                                  "done (recovered after a restart)")
                continue
            self.store.requeue(job.id)
            self.submit(job, self.store.payload(job))
            resubmitted += 1
        if jobs:
            log.warning("recovered %d unfinished jobs, %d resubmitted", len(jobs), resubmitted)

    async def wait(self, job_id: str, timeout: float) -> Outcome | None:
        """The job's outcome if it ends within ``timeout`` seconds, else ``None`` (also when
        the job is not running here, e.g. already finished: read the store then)."""
        handle = self._jobs.get(job_id)
        if handle is None:
            return None
        try:
            return await asyncio.wait_for(asyncio.shield(handle.outcome), timeout)
        except TimeoutError:
            return None

    async def dismiss(self, job_id: str) -> None:
        """Stop a queued or running job (the store row is marked by the caller)."""
        handle = self._jobs.get(job_id)
        if handle is None:
            return
        handle.cancel.set()
        if handle.future is not None:
            await self._signal_cancel(job_id)
            await handle.future.cancel()

    async def _signal_cancel(self, job_id: str) -> None:
        try:
            await Event(cancel_event_name(job_id), client=self.client).set()
        except Exception:  # the scheduler is gone: nothing is running there either
            log.warning("could not signal cancellation of %s", job_id, exc_info=True)

    # -- running and watching ----------------------------------------------------------------
    async def _run_fast(self, handle: _Handle, kwargs: dict[str, Any]) -> None:
        self._on_event((0.0, {"job": handle.job.id, "kind": "started"}))
        await self._record(handle, await self._compute(handle, kwargs))

    async def _compute(self, handle: _Handle, kwargs: dict[str, Any]) -> Outcome:
        """Run a fast-path job on the pool; its outcome (the runner catches every error)."""
        loop = asyncio.get_running_loop()
        job = handle.job

        def publish(event: dict[str, Any]) -> None:
            if event["kind"] != "started":  # the start is noted by the caller, no thread hop
                loop.call_soon_threadsafe(self._on_event, (0.0, event))

        reporter = Reporter(job.id, job.time_limit, publish=publish,
                            cancelled=handle.cancel.is_set)
        return await loop.run_in_executor(
            self._pool, lambda: run_job(job.id, job.process, kwargs, time_limit=job.time_limit,
                                        test_processes=self.settings.test_processes,
                                        reporter=reporter))

    async def run_first(self, job: JobRecord, kwargs: dict[str, Any], wait: float,
                        record: Callable[[Outcome | None, float], Awaitable[JobRecord]]
                        ) -> tuple[JobRecord, Outcome | None]:
        """Run a fast-path job *before* its row is written, for a client that waits for it.

        ``job`` is the record to be (its id fixed, not yet stored). If the job ends within
        ``wait`` seconds, ``record(outcome, started)`` stores it finished, row, inputs and
        outcome in one commit; else ``record(None, started)`` stores it accepted and it goes
        on like any other job, its end recorded when it comes. Either way the client hears
        of the job only once it is recorded, so nothing is answered that a crash could lose,
        and a finished fast job costs one fsync instead of two. Returns the stored record
        and the outcome (``None`` while still running)."""
        handle = _Handle(job, asyncio.get_running_loop().create_future(),
                         started=time.monotonic())
        started = time.time()
        self._unrecorded += 1
        try:
            compute = self._spawn(self._compute(handle, kwargs))
            if job.time_limit is not None:
                wait = min(wait, job.time_limit + GRACE)
            await asyncio.wait({compute}, timeout=wait)
            if compute.done():
                outcome = compute.result()
                stored = await record(outcome, started)
                handle.job = stored
                for callback in self.on_finish:
                    callback(stored, outcome)
                return stored, outcome
            stored = await record(None, started)
        finally:
            self._unrecorded -= 1
        handle.job = stored
        self._jobs[stored.id] = handle
        self._spawn(self._adopt(handle, compute))
        return stored, None

    async def _adopt(self, handle: _Handle, compute: asyncio.Task[Outcome]) -> None:
        """Record the end of a job :meth:`run_first` stored while it was running."""
        await self._record(handle, await compute)

    async def _watch(self, handle: _Handle) -> None:
        assert handle.future is not None
        try:
            outcome: Outcome = await handle.future
        except FutureCancelledError:
            outcome = Outcome.dismissed()
        except KilledWorker as exc:
            outcome = Outcome.failed(problem_body(
                "worker-lost", f"The job's worker died {self.settings.allowed_failures + 1} "
                f"times (crash or memory limit); last on {getattr(exc, 'last_worker', '?')}."))
        except asyncio.CancelledError:
            raise
        except Exception as exc:
            if self._closing:
                return
            log.exception("job %s: unexpected error from the scheduler", handle.job.id)
            outcome = Outcome.failed(problem_body(
                "job-failed", f"The scheduler reported {type(exc).__name__}: {exc}"))
        await self._record(handle, outcome)
        if self.settings.scheduler is None:
            handle.future.release()

    async def _record(self, handle: _Handle, outcome: Outcome) -> None:
        job = handle.job
        if self._jobs.get(job.id) is not handle or handle.recording:
            return  # recorded already, or being recorded (the time-limit sweep)
        handle.recording = True
        started = time.time() - (time.monotonic() - handle.started) if handle.started else None
        try:
            if outcome.status is not JobStatus.DISMISSED:  # the route records a dismissal
                await self.store.write(self.store.finish, job.id, outcome.status,
                                       outcome.message, outcome.problem, outcome.outputs,
                                       started=started)
        finally:
            # Only now does the job leave the table: a request that arrives while the outcome
            # is being committed (an idempotent retry with Prefer: wait) waits for it here,
            # instead of finding no handle, reading the row still active and answering 201.
            del self._jobs[job.id]
        if handle.future is not None and (outcome.status is JobStatus.DISMISSED
                                          or outcome.timed_out):
            # The worker may look at the event for a while yet: a cancelled Dask future does
            # not stop its thread. By the job's own deadline it has stopped either way.
            self._spawn(self._clear_cancel(job.id, (job.time_limit or 0.0) + GRACE))
        if not handle.outcome.done():
            handle.outcome.set_result(outcome)
        for callback in self.on_finish:
            callback(job, outcome)

    async def _clear_cancel(self, job_id: str, delay: float) -> None:
        await asyncio.sleep(delay)
        try:
            await Event(cancel_event_name(job_id), client=self.client).clear()
        except Exception:
            pass

    def _on_event(self, event: tuple[float, dict[str, Any]]) -> None:
        _, msg = event
        handle = self._jobs.get(msg.get("job", ""))
        if handle is None:
            return
        if msg.get("kind") == "started":
            handle.started = time.monotonic()
            # A fast-path job takes milliseconds: its start is recorded with its end, one
            # commit instead of two.
            if handle.future is not None or self.on_start_wanted(handle.job):
                self.store.write(self.store.mark_running, handle.job.id)
            for callback in self.on_start:
                callback(handle.job)
        else:
            if handle.future is None and not handle.marked_running:
                handle.marked_running = True  # a fast-path job long enough to report progress
                self.store.write(self.store.mark_running, handle.job.id)
            self.store.write(self.store.set_progress, handle.job.id,
                             int(msg.get("progress", 0)), str(msg.get("message", ""))[:500])

    @staticmethod
    def on_start_wanted(job: JobRecord) -> bool:
        """A subscriber asked to hear when the job starts: record the start at once."""
        sub = job.request.subscriber
        return sub is not None and bool(sub.in_progress_uri)

    async def _sweep(self) -> None:
        """Stop jobs that ignore their time limit: after GRACE seconds, restart the worker."""
        while True:
            await asyncio.sleep(0.5)
            now = time.monotonic()
            for handle in list(self._jobs.values()):
                limit = handle.job.time_limit
                if (handle.recording or handle.started is None or limit is None
                        or now - handle.started < limit + GRACE):
                    continue
                log.warning("job %s ignored its time limit of %g s; stopping it",
                            handle.job.id, limit)
                handle.cancel.set()
                if handle.future is not None:
                    await self._signal_cancel(handle.job.id)
                    await self._restart_worker_of(handle.job.id)
                await self._record(handle, Outcome.failed(problem_body(
                    "time-limit-exceeded",
                    f"The job was stopped: time limit of {limit:g} s exceeded.")))
                if handle.future is not None:
                    await handle.future.cancel()

    async def _restart_worker_of(self, job_id: str) -> None:
        assert self.client is not None
        key = f"morphserve-{job_id}"
        try:
            processing = await self.client.processing()
            workers = [w for w, keys in processing.items() if key in keys]
            if workers:
                await self.client.restart_workers(workers, raise_for_error=False)
        except Exception:
            log.warning("could not restart the worker of %s", job_id, exc_info=True)
