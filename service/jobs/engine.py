"""The execution engine: Dask distributed, embedded or external, plus a fast path.

Embedded (default): a :class:`distributed.LocalCluster` with process workers, one thread each,
and its scheduler in a process of its own (:mod:`service.jobs.scheduler`), started with the
service. Its jobs are sent to its workers directly (:mod:`service.jobs.direct`: one call on a
kept TLS comm instead of the scheduler's chain of messages), but for those of ``long``
processes, which go through the scheduler (their own tasks need it, its cost is nothing to
them). External: ``MORPHSERVE_SCHEDULER=tcp://host:8786``; tasks are then
submitted with ``fire_and_forget`` and the workers write their outputs to the shared data dir,
so work survives a restarting API.

Fast path: a round trip through the scheduler costs ~11 ms on a 2-core machine, more than a
closed-form job on a thousand points takes. Jobs of processes marked ``fast_path`` whose inputs
are at most ``fast_path_bytes`` and whose estimated cost is at most ``fast_path_cost`` (the
route's estimate: the inputs' numbers times the square of their dimension, more for meshes
and graphs) run on the service's own small pool of worker processes
(:class:`~service.jobs.fastpool.FastPool`) instead, never in the service's process. There a
job may run for ``fast_path_seconds`` at most: one that runs longer has its worker killed
and replaced and goes on on the Dask workers, so a small job waits behind a big one for that
long at most. A fast job's time limit and dismissal kill its worker too: a job reported
failed or dismissed uses no CPU any more. They are recorded, reported, dismissable and
time-limited exactly like the others; after a restart they are resubmitted through Dask. A
fast-path job whose client waits for it (``Prefer: wait``) runs before its row is written,
and is then recorded finished in one commit (:meth:`Engine.run_first`): the client hears of
it only after that commit, and a job that takes longer than the wait is recorded accepted
and goes on as any other.

For every job the engine keeps a :class:`_Handle` and a watcher task that records the outcome
in the store and wakes the requests waiting on it (``Prefer: wait``). Progress events
(``log_event`` on :data:`~service.jobs.runner.TOPIC`, or direct calls on the fast path) update
the rows. Dismissal sets the job's ``distributed.Event`` (or its flag in the worker's
process, for a job sent directly, or its in-process flag), which the runner's progress
callback sees; a Dask job that outlives its time limit (or, sent directly, its dismissal) by
:data:`GRACE` seconds without cooperating gets its worker restarted.
"""

from __future__ import annotations

import asyncio
import contextvars
import logging
import pickle
import threading
import time
from collections.abc import Awaitable, Callable
from dataclasses import dataclass, field
from typing import Any

import dask
from distributed import Client, Event, LocalCluster, WorkerPlugin, fire_and_forget
from distributed.client import Future, FutureCancelledError
from distributed.core import Status
from distributed.scheduler import KilledWorker
from distributed.security import Security

from service.catalog import lookup
from service.jobs.direct import Slots, WorkerLost, install
from service.jobs.fastpool import FastPool, children_ignore_sigint
from service.jobs.runner import TOPIC, cancel_event_name, run_job
from service.jobs.scheduler import embedded_scheduler, send_promptly
from service.jobs.status import JobStatus, Outcome
from service.jobs.store import JobRecord, JobStore
from service.problems import problem_body
from service.settings import Settings

__all__ = ["Engine", "GRACE", "HEARTBEAT_WAIT", "embedded_cluster"]

log = logging.getLogger("morphserve.engine")

GRACE = 2.0
"""Seconds past its time limit (or its dismissal, for a job sent to a worker directly) after
which a job that ignores its cancel event is stopped by restarting its worker."""

MARK_RUNNING_AFTER = 0.05
"""Seconds a job sent to a worker directly runs before its start is recorded (a shorter one
has its start recorded with its end: one commit instead of two)."""


def _worker_lost(times: int, worker: Any) -> Outcome:
    """The outcome of a job whose worker died ``times`` times, last ``worker``."""
    return Outcome.failed(problem_body(
        "worker-lost", f"The job's worker died {times} times (crash or memory limit); last on "
        f"{worker}."))


async def embedded_cluster(workers: int, *, memory_limit: Any = "auto",
                           dashboard: str | None = None) -> LocalCluster:
    """The embedded cluster: ``workers`` process workers of one thread each (their nannies
    here), the scheduler in a process of its own (:mod:`service.jobs.scheduler`), all on
    loopback over mutual TLS with an in-memory certificate; HTTP routes (job keys, the
    dashboard) only with a ``dashboard`` address. bench/service_overhead.py measures the
    bare Dask round trip on the same."""
    if dashboard is None:
        dask.config.set({"distributed.scheduler.http.routes": [],
                         "distributed.worker.http.routes": []})
    with children_ignore_sigint():
        cluster: LocalCluster = await embedded_scheduler(LocalCluster(
            n_workers=workers, threads_per_worker=1, processes=True, asynchronous=True,
            dashboard_address=dashboard, scheduler_port=0, host="127.0.0.1",
            protocol="tls://", security=Security.temporary(), memory_limit=memory_limit,
            silence_logs=logging.ERROR))
    return cluster


HEARTBEAT_WAIT = 2.0
"""Seconds a closing worker waits for its heartbeats under way to end
(:meth:`WarmUp.teardown`): a scheduler that is gone answers none."""

_IN_HEARTBEAT = contextvars.ContextVar("morphserve_in_heartbeat", default=False)
"""True in a worker's heartbeat, and so in the close it runs when the scheduler no longer
knows the worker."""


class WarmUp(WorkerPlugin):
    """Imports the runner (and so the catalog and every algorithm) when a worker starts, has
    the worker report to the scheduler promptly
    (:data:`~service.jobs.scheduler.SEND_INTERVAL`) and take jobs sent to it directly
    (:mod:`service.jobs.direct`); a closing worker lets its heartbeat end first
    (:meth:`teardown`)."""

    def setup(self, worker: Any) -> None:
        import service.jobs.runner  # noqa: F401
        send_promptly(getattr(worker, "batched_stream", None))
        install(worker)
        self._beats: set[asyncio.Future[None]] = set()
        """The worker's heartbeats under way."""
        timer = worker.periodic_callbacks["heartbeat"]
        self._heartbeat = heartbeat = timer.callback
        """The worker's own heartbeat (given back by :meth:`teardown`)."""

        async def beat() -> None:
            _IN_HEARTBEAT.set(True)  # in this heartbeat's task and the tasks it starts
            await heartbeat()

        def tracked() -> asyncio.Future[None]:
            future = asyncio.ensure_future(beat())
            self._beats.add(future)
            future.add_done_callback(self._beats.discard)
            return future  # the timer awaits it, as it awaited the heartbeat

        timer.callback = tracked

    async def teardown(self, worker: Any) -> None:
        """As the worker closes: stop its heartbeat and wait, up to :data:`HEARTBEAT_WAIT`
        seconds, for the ones under way to end. Else (the plugin replaced or removed, the
        worker goes on): give the heartbeat back as it was.

        ``Worker.close`` closes the worker's pool of comms, the ones in use too: a heartbeat
        waiting there for the scheduler's answer fails on its own closed comm, and the
        worker logs that with a traceback though nothing is wrong. The embedded cluster
        closes its workers while its scheduler is up, so a shutdown of the service printed
        one whenever a heartbeat was under way (a Ctrl-C of ``morphserve serve``, about
        once in 40 on a loaded 2-core machine). Plugins are torn down early in
        ``Worker.close``, before it stops its timers and closes the pool. A close that a
        heartbeat runs (the scheduler no longer knows the worker) waits for none: its
        heartbeat has its answer, and would wait for the close."""
        timer = worker.periodic_callbacks["heartbeat"]
        if worker.status is not Status.closing:
            timer.callback = self._heartbeat
            return
        timer.stop()
        if self._beats and not _IN_HEARTBEAT.get():
            await asyncio.wait(set(self._beats), timeout=HEARTBEAT_WAIT)


@dataclass
class _Handle:
    job: JobRecord
    outcome: asyncio.Future[Outcome]
    future: Future[Outcome] | None = None
    """The Dask future; None on the fast path and for a job sent to a worker directly."""
    direct: bool = False
    """Sent to a worker directly (:mod:`service.jobs.direct`), not through the scheduler."""
    cancel: threading.Event = field(default_factory=threading.Event)
    """The fast path's dismissal flag."""
    started: float | None = None
    marked_running: bool = False
    stored: bool = True
    """The job's row exists (false while :meth:`Engine.run_first` writes it)."""
    recording: bool = False
    """The outcome is being committed: the handle stays in the table until it is durable."""


#: Dask's monitoring, turned down. The nannies live in the service's own event loop (the
#: embedded scheduler did too, before it had a process of its own): at the defaults (psutil
#: disk and network counters every 0.5 s, each nanny's memory every 0.1 s, a 20 ms tick, a
#: 10 ms statistical profiler in every worker) they took about a quarter of the service's
#: busy CPU under load (py-spy), time every request waited for. The memory limit is still
#: enforced, once a second; the tick still warns of a blocked loop.
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
        self._slots: Slots | None = None
        """The embedded cluster's workers, for jobs sent to them directly."""
        self._stopping: dict[str, float] = {}
        """Direct jobs dismissed while running -> when their worker is restarted if they
        still run then (they ignore their dismissal)."""
        self._jobs: dict[str, _Handle] = {}
        self._unrecorded = 0
        """Fast-path jobs running before their row is written (:meth:`run_first`)."""
        self._expected: dict[str, asyncio.Future[None]] = {}
        """Jobs whose row is being written and which are about to be submitted
        (:meth:`expect`): a request that reads the row meanwhile waits for the job."""
        self._tasks: set[asyncio.Task[Any]] = set()
        self._pool = FastPool(settings.fast_path_threads, budget=settings.fast_path_seconds,
                              test_processes=settings.test_processes)
        self._closing = False
        self.on_finish: list[Callable[[JobRecord, Outcome], Any]] = []
        """Called with the job and its outcome when it ends (subscriber callbacks)."""
        self.on_start: list[Callable[[JobRecord], Any]] = []
        """Called with the job when it starts running."""
        self.on_run: list[Callable[[JobRecord, str], Any]] = []
        """Called with the job and its path, ``"fast"`` or ``"workers"``, when it is given to
        the fast path or to Dask (a job the fast path gives back: once for each)."""

    # -- life cycle --------------------------------------------------------------------------
    async def start(self) -> None:
        dask.config.set({"distributed.scheduler.allowed-failures":
                         self.settings.allowed_failures, **QUIET_MONITORING})
        if self.settings.scheduler:
            # TLS, if the scheduler wants it, from Dask's own configuration
            # (DASK_DISTRIBUTED__COMM__TLS__*: docs/security.md)
            if self.settings.api_keys_file and not self.settings.scheduler.startswith("tls://"):
                log.warning("API keys are on, but the scheduler %s is not reached over TLS: "
                            "whoever reaches it can run code on its workers (docs/security.md)",
                            self.settings.scheduler)
            self.client = await Client(self.settings.scheduler, asynchronous=True)
        else:
            # The embedded scheduler runs whatever it is sent: only holders of this in-memory
            # certificate (the service and the workers it spawns) may talk to it or to the
            # workers, over mutual TLS. Its HTTP server (job keys, the dashboard) only if asked.
            self.cluster = await embedded_cluster(
                self.settings.workers, memory_limit=self.settings.worker_memory_limit,
                dashboard=self.settings.dashboard_address)
            self.client = await Client(self.cluster, asynchronous=True)  # its security too
        send_promptly(getattr(self.client, "scheduler_comm", None))
        self.client.subscribe_topic(TOPIC, self._on_event)
        await self.client.register_plugin(WarmUp(), name="morphserve-warm-up")
        if self.cluster is not None:
            self._slots = Slots(self.client)
            await self._slots.refresh()
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

    @property
    def fast_path_ready(self) -> bool:
        """The fast path has a worker process up: fast jobs may be given to it."""
        return self._pool.ready

    # -- submission --------------------------------------------------------------------------
    def submit(self, job: JobRecord, payload: dict[str, Any] | str, *,
               fast: bool = False) -> None:
        """Run ``job``: on the fast path when ``fast`` (payload must be the inputs), else on
        Dask. Returns at once; :meth:`wait` waits."""
        handle = _Handle(job, asyncio.get_running_loop().create_future())
        self._jobs[job.id] = handle
        self.forget(job.id)  # here now: who waited for it to come waits for its end
        if fast and isinstance(payload, dict):
            self._spawn(self._run_fast(handle, payload))
            return
        self._submit_dask(handle, payload)

    def _submit_dask(self, handle: _Handle, payload: dict[str, Any] | str) -> None:
        """Send the job of ``handle`` to the Dask workers and watch it there: directly to a
        worker of the embedded cluster unless its process is ``long``
        (:mod:`service.jobs.direct`), else through the scheduler."""
        assert self.client is not None, "engine not started"
        job = handle.job
        for callback in self.on_run:
            callback(job, "workers")
        if self._slots is not None and self._direct_ok(job.process):
            handle.direct = True
            self._spawn(self._run_direct(handle, payload))
            return
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

    def direct(self, process_id: str) -> bool:
        """Jobs of ``process_id`` that leave the fast path are sent to a worker of the
        embedded cluster directly (:mod:`service.jobs.direct`), so :meth:`run_first` can
        run them."""
        return self._slots is not None and self._direct_ok(process_id)

    def _direct_ok(self, process_id: str) -> bool:
        """Jobs of ``process_id`` may be sent to a worker directly: it is not ``long``."""
        process = lookup(process_id, test_processes=self.settings.test_processes)
        return process is not None and not process.long

    async def recover(self) -> None:
        """Finish what a previous run of the service left: complete rows whose outputs a
        worker wrote, resubmit the others (through Dask). Also starts the fast path's
        worker processes (they come up in the background)."""
        self._pool.start()  # the fast path's workers start meanwhile, in the background
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

    def expect(self, job_id: str) -> None:
        """Announce the job ``job_id``, whose row is about to be written and which will then
        be :meth:`submit`-ted (or :meth:`forget`-ten if the row is not written). From the
        moment its row is readable until it is submitted, the job is in the store but not
        yet here: a request that finds the row then (an idempotent retry racing in) must
        wait for the job, not read the row as it is and answer "still running"."""
        self._expected[job_id] = asyncio.get_running_loop().create_future()

    def forget(self, job_id: str) -> None:
        """The announced job will not be submitted (its row was not written)."""
        expected = self._expected.pop(job_id, None)
        if expected is not None and not expected.done():
            expected.set_result(None)

    async def wait(self, job_id: str, timeout: float) -> Outcome | None:
        """The job's outcome if it ends within ``timeout`` seconds, else ``None`` (also when
        the job is not running here, e.g. already finished: read the store then). A job
        announced by :meth:`expect` and not yet submitted is waited for too."""
        loop = asyncio.get_running_loop()
        until = loop.time() + timeout
        expected = self._expected.get(job_id)
        try:
            if expected is not None:
                await asyncio.wait_for(asyncio.shield(expected), timeout)
            handle = self._jobs.get(job_id)
            if handle is None:
                return None
            return await asyncio.wait_for(asyncio.shield(handle.outcome),
                                          max(0.0, until - loop.time()))
        except TimeoutError:
            return None

    async def dismiss(self, job_id: str) -> None:
        """Stop a queued or running job (the store row is marked by the caller)."""
        handle = self._jobs.get(job_id)
        if handle is None:
            return
        handle.cancel.set()
        if handle.direct and self._slots is not None:
            # the flag on its worker, looked at by the job's progress callback; recorded at
            # once, as a cancelled future is: a job that ignores its flag has its worker
            # restarted after GRACE seconds (the sweep)
            if self._slots.worker_of(job_id) is not None:
                self._stopping[job_id] = time.monotonic() + GRACE
                await self._slots.cancel(job_id)
            await self._record(handle, Outcome.dismissed())
        elif handle.future is not None:
            await self._signal_cancel(job_id)
            await handle.future.cancel()
        else:
            # on the fast path: its pool kills the worker within POLL_INTERVAL, and the run
            # it gives back is recorded by nobody (the handle is gone). Recorded at once, as
            # a direct job is, so that whoever reads the dismissed row (the client, the
            # metrics) finds the job ended, not still counted as running
            await self._record(handle, Outcome.dismissed())

    async def _signal_cancel(self, job_id: str) -> None:
        try:
            await Event(cancel_event_name(job_id), client=self.client).set()
        except Exception:  # the scheduler is gone: nothing is running there either
            log.warning("could not signal cancellation of %s", job_id, exc_info=True)

    # -- running and watching ----------------------------------------------------------------
    async def _run_fast(self, handle: _Handle, kwargs: dict[str, Any]) -> None:
        self._on_event((0.0, {"job": handle.job.id, "kind": "started"}))
        await self._finish_fast(handle, kwargs, await self._compute(handle, kwargs))

    async def _finish_fast(self, handle: _Handle, kwargs: dict[str, Any],
                           outcome: Outcome | None) -> None:
        """Record how a fast-path job ended, or, when the fast path gave it back (``None``:
        it ran past the fast path's budget, or lost its worker), run it on Dask."""
        if outcome is not None:
            await self._record(handle, outcome)
        elif handle.cancel.is_set():  # dismissed (or timed out) while it was handed over
            await self._record(handle, Outcome.dismissed())
        elif self._jobs.get(handle.job.id) is handle:
            self._submit_dask(handle, kwargs)

    async def _compute(self, handle: _Handle, kwargs: dict[str, Any]) -> Outcome | None:
        """Run a fast-path job on the pool: its outcome (the runner catches every error), or
        ``None`` when it must run on Dask instead (:meth:`FastPool.run`)."""
        loop = asyncio.get_running_loop()
        job = handle.job

        def publish(event: dict[str, Any]) -> None:
            loop.call_soon_threadsafe(self._on_event, (0.0, event))

        for callback in self.on_run:
            callback(job, "fast")
        return await self._pool.run(job.id, job.process, kwargs, time_limit=job.time_limit,
                                    stop=handle.cancel, publish=publish)

    async def run_first(self, job: JobRecord, kwargs: dict[str, Any], wait: float,
                        record: Callable[[Outcome | None, float], Awaitable[JobRecord]],
                        *, direct: bool = False) -> tuple[JobRecord, Outcome | None]:
        """Run a fast-path job *before* its row is written, for a client that waits for it
        (with ``direct``: a job sent to a worker of the embedded cluster directly, see
        :meth:`direct`; inputs inline, not in a file).

        ``job`` is the record to be (its id fixed, not yet stored). If the job ends within
        ``wait`` seconds, ``record(outcome, started)`` stores it finished, row, inputs and
        outcome in one commit; else ``record(None, started)`` stores it accepted and it goes
        on like any other job, its end recorded when it comes. Either way the client hears
        of the job only once it is recorded, so nothing is answered that a crash could lose,
        and a finished fast job costs one fsync instead of two. A job the fast path gives
        back (past its budget) is recorded accepted, goes on on Dask, and is waited for
        there for what is left of ``wait``. Returns the stored record and the outcome
        (``None`` while still running)."""
        loop = asyncio.get_running_loop()
        handle = _Handle(job, loop.create_future(),
                         started=None if direct else time.monotonic())
        handle.direct = direct
        handle.stored = False
        if job.time_limit is not None:
            wait = min(wait, job.time_limit + GRACE)
        until = loop.time() + wait
        self._unrecorded += 1
        try:
            if direct:
                for run in self.on_run:
                    run(job, "workers")
                compute = self._spawn(self._direct(handle, pickle.dumps(kwargs, protocol=5)))
            else:
                compute = self._spawn(self._compute(handle, kwargs))
            await asyncio.wait({compute}, timeout=wait)
            if compute.done() and compute.result() is not None:
                outcome = compute.result()
                stored = await record(outcome, self._wall(handle.started))
                handle.job = stored
                for callback in self.on_finish:
                    callback(stored, outcome)
                return stored, outcome
        finally:
            self._unrecorded -= 1
        # Here before its row is readable: a request that finds the row (an idempotent
        # retry) finds the job too, and waits for it.
        self._jobs[job.id] = handle
        try:
            stored = await record(None, self._wall(handle.started))
        except BaseException:
            del self._jobs[job.id]
            handle.cancel.set()  # nobody will hear of this job: stop it
            if direct and self._slots is not None:
                self._spawn(self._slots.cancel(job.id))
            raise
        handle.job = stored
        handle.stored = True
        self._spawn(self._adopt(handle, compute, kwargs))
        if direct and handle.started is not None:
            self._announce_start(handle)  # it started while its row was being written
        if not compute.done() or direct:
            return stored, None
        # given back by the fast path: on Dask now, waited for there
        outcome = await self.wait(stored.id, max(0.0, until - loop.time()))
        return (self.store.get(stored.id) or stored), outcome

    async def _adopt(self, handle: _Handle, compute: asyncio.Task[Outcome | None],
                     kwargs: dict[str, Any]) -> None:
        """Record the end of a job :meth:`run_first` stored while it was running."""
        outcome = await compute
        if handle.direct:
            if outcome is not None:  # else whoever stopped it records how it ended
                await self._record(handle, outcome)
            return
        await self._finish_fast(handle, kwargs, outcome)

    @staticmethod
    def _wall(started: float | None) -> float:
        """The wall-clock time of the monotonic ``started`` (now if None)."""
        now = time.time()
        return now if started is None else now - (time.monotonic() - started)

    async def _run_direct(self, handle: _Handle, payload: dict[str, Any] | str) -> None:
        """Run the job of ``handle`` on a worker of the embedded cluster, sent directly, and
        record its outcome."""
        outcome = await self._direct(handle, pickle.dumps(payload, protocol=5))
        if outcome is not None:
            await self._record(handle, outcome)

    async def _direct(self, handle: _Handle, payload: bytes) -> Outcome | None:
        """The outcome of a direct job, or ``None`` if it is not this coroutine's to record
        (dismissed, timed out by the sweep, the service closing). A worker lost under the
        job counts against it as the scheduler counts it (``allowed_failures``); one lost
        before the job reached it does not."""
        assert self._slots is not None
        job = handle.job
        failures = 0
        while True:
            if handle.cancel.is_set() or handle.recording or handle.outcome.done():
                return None  # whoever stopped it records how it ended
            try:
                return await self._slots.run(
                    job.id, job.process, payload, time_limit=job.time_limit,
                    test_processes=self.settings.test_processes, stop=handle.cancel,
                    on_start=lambda worker: self._direct_started(handle))
            except WorkerLost as exc:
                if not exc.started:
                    continue
                failures += 1
                log.warning("job %s: its worker %s died (%d of %d allowed)", job.id,
                            exc.worker, failures, self.settings.allowed_failures)
                if failures > self.settings.allowed_failures:
                    return _worker_lost(failures, exc.worker)
            except asyncio.CancelledError:
                raise
            except Exception as exc:
                if self._closing:
                    return None
                log.exception("job %s: unexpected error from its worker", job.id)
                return Outcome.failed(problem_body(
                    "job-failed", f"The worker reported {type(exc).__name__}: {exc}"))

    def _direct_started(self, handle: _Handle) -> None:
        """A direct job was sent to a free worker: it starts now. Its start is recorded
        with its end (one commit instead of two), unless it runs for
        :data:`MARK_RUNNING_AFTER` seconds, or reports progress, or a subscriber wants to
        hear of it."""
        handle.started = time.monotonic()
        if handle.stored:  # else (run_first) when its row is written
            self._announce_start(handle)

    def _announce_start(self, handle: _Handle) -> None:
        if self.on_start_wanted(handle.job):
            handle.marked_running = True
            self.store.write(self.store.mark_running, handle.job.id)
        else:
            asyncio.get_running_loop().call_later(MARK_RUNNING_AFTER, self._mark_running,
                                                  handle)
        for callback in self.on_start:
            callback(handle.job)

    def _mark_running(self, handle: _Handle) -> None:
        if (self._jobs.get(handle.job.id) is handle and handle.stored
                and not handle.recording and not handle.marked_running):
            handle.marked_running = True
            self.store.write(self.store.mark_running, handle.job.id)

    async def _watch(self, handle: _Handle) -> None:
        assert handle.future is not None
        try:
            outcome: Outcome = await handle.future
        except FutureCancelledError:
            outcome = Outcome.dismissed()
        except KilledWorker as exc:
            outcome = _worker_lost(self.settings.allowed_failures + 1,
                                   getattr(exc, "last_worker", "?"))
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
                applied = await self.store.write(self.store.finish, job.id, outcome.status,
                                                 outcome.message, outcome.problem,
                                                 outcome.outputs, started=started)
                if applied is False:  # the row was final already: dismissed meanwhile
                    row = self.store.get(job.id)
                    if row is None or row.status is JobStatus.DISMISSED:
                        outcome = Outcome.dismissed()
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
        if handle is None or not handle.stored:
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
        """Stop jobs that ignore their time limit (or their dismissal, if sent directly):
        after GRACE seconds, restart the worker. Keep the direct jobs' list of workers
        current."""
        while True:
            await asyncio.sleep(0.5)
            now = time.monotonic()
            if self._slots is not None:
                # every tick (one small scheduler call): workers die under jobs through the
                # scheduler too, unseen here, and the nannies' replacements come
                try:
                    await self._slots.refresh()
                except Exception:  # the scheduler is gone
                    log.warning("could not list the workers", exc_info=True)
                for job_id, when in list(self._stopping.items()):
                    worker = self._slots.worker_of(job_id)
                    if worker is None:
                        del self._stopping[job_id]
                    elif now >= when:
                        del self._stopping[job_id]
                        log.warning("job %s ignored its dismissal; restarting its worker",
                                    job_id)
                        await self._restart_workers([worker])
            for handle in list(self._jobs.values()):
                limit = handle.job.time_limit
                if (handle.recording or not handle.stored or handle.started is None
                        or limit is None
                        or now - handle.started < limit + GRACE):
                    continue
                log.warning("job %s ignored its time limit of %g s; stopping it",
                            handle.job.id, limit)
                handle.cancel.set()
                if handle.direct and self._slots is not None:
                    worker = self._slots.worker_of(handle.job.id)
                    if worker is not None:
                        await self._restart_workers([worker])
                elif handle.future is not None:
                    await self._signal_cancel(handle.job.id)
                    await self._restart_worker_of(handle.job.id)
                await self._record(handle, Outcome.time_limit_exceeded(limit))
                if handle.future is not None:
                    await handle.future.cancel()

    async def _restart_worker_of(self, job_id: str) -> None:
        assert self.client is not None
        key = f"morphserve-{job_id}"
        try:
            processing = await self.client.processing()
            workers = [w for w, keys in processing.items() if key in keys]
        except Exception:
            log.warning("could not find the worker of %s", job_id, exc_info=True)
            return
        await self._restart_workers(workers)

    async def _restart_workers(self, workers: list[str]) -> None:
        assert self.client is not None
        if not workers:
            return
        try:
            await self.client.restart_workers(workers, raise_for_error=False)
        except Exception:
            log.warning("could not restart the workers %s", workers, exc_info=True)
