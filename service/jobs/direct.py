"""Direct dispatch: a job sent straight to a worker of the embedded Dask cluster.

A job through the scheduler costs a chain of messages, each through a Python event loop and
TLS: the client's ``update-graph`` to the scheduler, ``compute-task`` to a worker,
``task-finished`` back, ``key-in-memory`` to the client, then the client's ``get_data`` from
the worker and the key's release. On the 2-core machine of issue #19 that bare round trip
(``client.submit`` → result, no job at all) took 7.6 ms when quiet, 17 ms under load; a
direct call on a pooled comm to a worker takes 1.0 ms (0.8 ms without TLS). So the embedded
cluster's jobs that need nothing of the scheduler go to its workers directly:

- the service opens (and keeps, in the client's connection pool, over the same mutual TLS)
  a comm to a worker and calls the handler :data:`RUN` that :func:`install` adds to every
  worker (the engine's ``WarmUp`` plugin, so a worker the nanny restarts has it too);
- the worker runs the job on a thread of its own (its event loop stays free for heartbeats)
  with :func:`~service.jobs.runner.run_job`, and answers with the pickled
  :class:`~service.jobs.status.Outcome`: the result travels in the reply, no second fetch;
- progress events go out as before (``log_event`` on :data:`~service.jobs.runner.TOPIC`);
  dismissal is the handler :data:`CANCEL`, which sets the job's flag in the worker's
  process, looked at by the job's progress callback without any round trip; time limits
  are the callback's too, and the engine restarts the worker of a job that ignores them;
- :class:`Slots` keeps one slot per worker thread and hands them to the jobs in the order
  they came (a job waits here, not on a worker, so a free worker takes the next job);
- a worker that dies during a call (crash, memory limit) breaks the comm: :meth:`Slots.run`
  raises :class:`WorkerLost`, the worker leaves the slots until the scheduler lists its
  replacement (:meth:`Slots.refresh`), and the engine runs the job again, up to
  ``allowed_failures`` times, as the scheduler would.

Which jobs: those of processes not marked ``long`` (a long job gains nothing here, and keeps
what only the scheduler offers: the tasks of :mod:`service.jobs.tasks`, which a directly
run job runs one after the other), and only on the embedded cluster (an external
scheduler's jobs are submitted ``fire_and_forget`` to outlive the service).
"""

from __future__ import annotations

import asyncio
import collections
import logging
import pickle
import threading
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from typing import Any

from distributed.core import send_recv

from service.jobs.runner import TOPIC, Reporter, run_job
from service.jobs.status import Outcome

__all__ = ["RUN", "CANCEL", "install", "Slots", "WorkerLost"]

log = logging.getLogger("morphserve.direct")

RUN = "morphserve_run"
"""The worker's handler that runs one job and answers with its outcome."""
CANCEL = "morphserve_cancel"
"""The worker's handler that sets a job's dismissal flag."""

#: Dismissal flags kept for jobs not (yet) running on the worker: a dismissal may overtake
#: its job's call (two comms), or come after its end.
_KEPT_FLAGS = 1024


class WorkerLost(Exception):
    """The worker of a direct call died (or could not be reached) before it answered."""

    def __init__(self, worker: str, sent: bool) -> None:
        super().__init__(f"worker {worker} lost")
        self.worker = worker
        self.sent = sent
        """The job had reached the worker (else it never started: no failure of its own)."""


# -- worker side ------------------------------------------------------------------------------
def install(worker: Any) -> None:
    """Add the handlers :data:`RUN` and :data:`CANCEL` to ``worker`` (a
    :class:`distributed.Worker`)."""
    executor = ThreadPoolExecutor(max_workers=max(1, int(worker.state.nthreads)),
                                  thread_name_prefix="morphserve-job")
    flags: collections.OrderedDict[str, threading.Event] = collections.OrderedDict()

    def flag(job: str) -> threading.Event:
        event = flags.get(job)
        if event is None:
            event = flags[job] = threading.Event()
            while len(flags) > _KEPT_FLAGS:
                flags.popitem(last=False)
        return event

    async def run(job: str, process: str, payload: bytes, time_limit: float | None,
                  test_processes: bool) -> bytes:
        stop = flag(job)
        loop = asyncio.get_running_loop()
        try:
            return await loop.run_in_executor(executor, _run, worker, job, process, payload,
                                              time_limit, test_processes, stop)
        finally:
            flags.pop(job, None)

    def cancel(job: str) -> None:
        flag(job).set()

    worker.handlers[RUN] = run
    worker.handlers[CANCEL] = cancel


def _run(worker: Any, job: str, process: str, payload: bytes, time_limit: float | None,
         test_processes: bool, stop: threading.Event) -> bytes:
    """One job, on the worker's job thread: its pickled outcome."""

    def publish(event: dict[str, Any]) -> None:
        if event["kind"] != "started":  # the service noted the start when it sent the job
            worker.log_event(TOPIC, event)

    if stop.is_set():
        return pickle.dumps(Outcome.dismissed(), protocol=5)
    reporter = Reporter(job, time_limit, publish=publish, cancelled=stop.is_set)
    outcome = run_job(job, process, pickle.loads(payload), time_limit=time_limit,
                      test_processes=test_processes, reporter=reporter)
    return pickle.dumps(outcome, protocol=5)


# -- service side -----------------------------------------------------------------------------
class Slots:
    """The workers' threads as slots, handed to direct calls in the order they ask.

    ``client`` is the engine's :class:`distributed.Client` (its connection pool and security
    are used; the scheduler is asked only for the list of workers)."""

    def __init__(self, client: Any) -> None:
        self.client = client
        self._threads: dict[str, int] = {}
        """Known workers and their threads."""
        self._free: collections.deque[str] = collections.deque()
        self._waiting: collections.deque[asyncio.Future[str]] = collections.deque()
        self._running: dict[str, str] = {}
        """Job id -> the worker running it."""
        self._lost: set[str] = set()
        """Workers that died under a call: never taken back, even while the scheduler still
        lists them (a restarted worker has a new address)."""
        self.stale = True
        """The list of workers may be out of date (a worker was lost): refresh it."""

    @property
    def workers(self) -> int:
        return len(self._threads)

    async def refresh(self) -> None:
        """Take the scheduler's list of workers: new ones get their slots, gone ones lose
        theirs."""
        threads = await self.client.nthreads()
        self.stale = False
        for address in list(self._threads):
            if address not in threads:
                self._drop(address)
        for address, n in threads.items():
            if address not in self._threads and address not in self._lost:
                self._threads[address] = int(n)
                for _ in range(int(n)):
                    self._release(address)

    def _drop(self, address: str, *, lost: bool = True) -> None:
        """Take ``address`` out of the slots (for good if it was ``lost``)."""
        if lost:
            self._lost.add(address)
            self.client.rpc.remove(address)  # its pooled comms are dead too
        if self._threads.pop(address, None) is not None:
            self._free = collections.deque(a for a in self._free if a != address)
        self.stale = True

    def _release(self, address: str) -> None:
        if address not in self._threads:
            return  # a worker gone meanwhile: its slot goes with it
        while self._waiting:
            waiter = self._waiting.popleft()
            if not waiter.done():
                waiter.set_result(address)
                return
        self._free.append(address)

    async def _acquire(self) -> str:
        if self._free and not self._waiting:
            return self._free.popleft()
        waiter = asyncio.get_running_loop().create_future()
        self._waiting.append(waiter)
        try:
            return await waiter
        except asyncio.CancelledError:
            if waiter.done() and not waiter.cancelled():
                self._release(waiter.result())  # handed over as we were cancelled
            raise

    def worker_of(self, job_id: str) -> str | None:
        """The worker running ``job_id`` (None if it is not running)."""
        return self._running.get(job_id)

    async def run(self, job_id: str, process: str, payload: bytes, *,
                  time_limit: float | None, test_processes: bool, stop: threading.Event,
                  on_start: Callable[[str], None]) -> Outcome:
        """Run a job on the next free worker: its outcome. ``payload`` is the pickled inputs
        (or the path of their file); ``on_start(worker)`` is called as it is sent; ``stop``
        set before that, the job is not sent (dismissed). Raises :class:`WorkerLost` if the
        worker dies or cannot be reached."""
        address = await self._acquire()
        sent = False
        pool = self.client.rpc
        try:
            if stop.is_set():
                return Outcome.dismissed()
            try:
                comm = await pool.connect(address)
            except OSError as exc:
                self._drop(address)
                raise WorkerLost(address, sent=False) from exc
            self._running[job_id] = address
            on_start(address)
            try:
                sent = True
                reply = await send_recv(comm, op=RUN, job=job_id, process=process,
                                        payload=payload, time_limit=time_limit,
                                        test_processes=test_processes)
            except OSError as exc:
                self._drop(address)
                raise WorkerLost(address, sent=sent) from exc
            finally:
                pool.reuse(address, comm)
                self._running.pop(job_id, None)
            if not isinstance(reply, bytes):  # no handler there (yet): ask again later
                self._drop(address, lost=False)
                raise WorkerLost(address, sent=False)
            outcome: Outcome = pickle.loads(reply)
            return outcome
        finally:
            self._release(address)

    async def cancel(self, job_id: str) -> None:
        """Set the dismissal flag of ``job_id`` on its worker (nothing if it is not
        running)."""
        address = self._running.get(job_id)
        if address is None:
            return
        try:
            await getattr(self.client.rpc(address), CANCEL)(job=job_id)
        except Exception:  # the worker is gone: so is the job
            log.debug("could not cancel %s on %s", job_id, address, exc_info=True)
