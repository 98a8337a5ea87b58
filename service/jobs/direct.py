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
- :class:`Slots` sends the jobs to the workers in the order they came, at most
  :data:`DEPTH` per worker thread: one running, the next already there, so that a worker
  does not idle while its answer and the next job cross (Dask's scheduler does the same,
  ``worker-saturation``). A job waits here while every worker is that busy, so a free worker
  takes the next job; a job sent to a worker whose thread is busy counts as started (time
  limit, ``running``) only when the job ahead of it ends there, and is taken back and sent
  elsewhere (:data:`WITHDRAW`) if another worker runs out of work meanwhile for
  :data:`STEAL_AFTER` seconds (the job ahead turned out long);
- a worker that dies during a call (crash, memory limit) breaks the comm: :meth:`Slots.run`
  raises :class:`WorkerLost`, the worker is no longer sent jobs, and the engine runs the
  job again, up to ``allowed_failures`` times, as the scheduler would (a job that had not
  started there yet is sent again without counting). A worker that cannot be reached
  within :data:`CONNECT_TIMEOUT` is only set aside until the next look at the scheduler's
  list: a replacement the nanny has just started is listed before it answers (its loop
  busy with its plugins' set-up, seconds under load). The list of workers follows the
  scheduler's (:meth:`Slots.refresh`, twice a second: workers die under the scheduler's
  jobs too, and the nannies' replacements come).

Which jobs: those of processes not marked ``long`` (a long job gains nothing here, and keeps
what only the scheduler offers: the tasks of :mod:`service.jobs.tasks`, which a directly
run job runs one after the other), and only on the embedded cluster (an external
scheduler's jobs are submitted ``fire_and_forget`` to outlive the service).
"""

from __future__ import annotations

import asyncio
import collections
import concurrent.futures
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
WITHDRAW = "morphserve_withdraw"
"""The worker's handler that takes back a job it has not started: the job's call answers
:data:`WITHDRAWN`."""
WITHDRAWN = b"withdrawn"
"""The answer of a job taken back before it started (never a pickled outcome)."""

DEPTH = 2
"""Jobs in flight per worker thread: the running one and the next."""
STEAL_AFTER = 0.02
"""Seconds a worker may have no work while a job waits behind another on a busy worker,
before that job is taken back and sent to it."""

CONNECT_TIMEOUT = 5.0
"""Seconds a comm to a worker may take to open (Dask's default, 30 s of retries, would hold
a job that long at a worker that died unseen)."""

#: Dismissal flags kept for jobs not (yet) running on the worker: a dismissal may overtake
#: its job's call (two comms), or come after its end.
_KEPT_FLAGS = 1024


class WorkerLost(Exception):
    """The worker of a direct call died (or could not be reached) before it answered."""

    def __init__(self, worker: str, started: bool) -> None:
        super().__init__(f"worker {worker} lost")
        self.worker = worker
        self.started = started
        """The job had started there (else it is no failure of its own)."""


# -- worker side ------------------------------------------------------------------------------
def install(worker: Any) -> None:
    """Add the handlers :data:`RUN`, :data:`CANCEL` and :data:`WITHDRAW` to ``worker`` (a
    :class:`distributed.Worker`)."""
    executor = ThreadPoolExecutor(max_workers=max(1, int(worker.state.nthreads)),
                                  thread_name_prefix="morphserve-job")
    flags: collections.OrderedDict[str, threading.Event] = collections.OrderedDict()
    queued: dict[str, concurrent.futures.Future[bytes]] = {}
    """Jobs here, not yet started or running."""
    withdrawn: set[str] = set()

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
        future = executor.submit(_run, worker, job, process, payload, time_limit,
                                 test_processes, stop)
        queued[job] = future
        try:
            return await asyncio.wrap_future(future)
        except asyncio.CancelledError:
            if not future.cancelled():  # the handler itself is cancelled (worker closing)
                raise
            if job in withdrawn:
                return WITHDRAWN
            return pickle.dumps(Outcome.dismissed(), protocol=5)
        finally:
            queued.pop(job, None)
            withdrawn.discard(job)
            flags.pop(job, None)

    def cancel(job: str) -> None:
        flag(job).set()
        future = queued.get(job)
        if future is not None:
            future.cancel()  # not started yet: never will

    def withdraw(job: str) -> bool:
        future = queued.get(job)
        if future is None or future.done() or job in withdrawn:
            return False
        withdrawn.add(job)
        if future.cancel():
            return True
        withdrawn.discard(job)  # started meanwhile: it stays
        return False

    worker.handlers[RUN] = run
    worker.handlers[CANCEL] = cancel
    worker.handlers[WITHDRAW] = withdraw


def _run(worker: Any, job: str, process: str, payload: bytes, time_limit: float | None,
         test_processes: bool, stop: threading.Event) -> bytes:
    """One job, on the worker's job thread: its pickled outcome."""

    def publish(event: dict[str, Any]) -> None:
        if event["kind"] != "started":  # the service notes the start
            worker.log_event(TOPIC, event)

    if stop.is_set():
        return pickle.dumps(Outcome.dismissed(), protocol=5)
    reporter = Reporter(job, time_limit, publish=publish, cancelled=stop.is_set)
    outcome = run_job(job, process, pickle.loads(payload), time_limit=time_limit,
                      test_processes=test_processes, reporter=reporter)
    return pickle.dumps(outcome, protocol=5)


# -- service side -----------------------------------------------------------------------------
class _Call:
    """One job's call, from the moment it asks for a worker."""

    def __init__(self, job_id: str, on_start: Callable[[str], None]) -> None:
        self.job_id = job_id
        self.on_start = on_start
        self.worker: _Worker | None = None
        self.started = False
        self.placed: asyncio.Future[None] | None = None
        """Set while the call waits for a worker."""


class _Worker:
    def __init__(self, address: str, threads: int) -> None:
        self.address = address
        self.threads = threads
        self.calls: list[_Call] = []
        """Calls sent here and not answered, in the order they were sent."""
        self.idle_since: float | None = None

    @property
    def room(self) -> bool:
        return len(self.calls) < self.threads * DEPTH


class Slots:
    """The calls to the workers: who runs what, who waits; see the module's description.

    ``client`` is the engine's :class:`distributed.Client` (its connection pool and security
    are used; the scheduler is asked only for the list of workers)."""

    def __init__(self, client: Any) -> None:
        self.client = client
        self._workers: dict[str, _Worker] = {}
        self._waiting: collections.deque[_Call] = collections.deque()
        self._calls: dict[str, _Call] = {}
        """Job id -> its call, sent or waiting."""
        self._lost: set[str] = set()
        """Workers that died under a call (the comm broke): never taken back, even while the
        scheduler still lists them (a restarted worker has a new address). A worker that
        could not be reached is not among them (:meth:`run`)."""
        self._tasks: set[asyncio.Task[None]] = set()

    @property
    def workers(self) -> int:
        return len(self._workers)

    async def refresh(self) -> None:
        """Take the scheduler's list of workers: new ones get jobs, gone ones no more."""
        threads = await self.client.nthreads()
        for address in list(self._workers):
            if address not in threads:
                self._drop(address, lost=False)
        for address, n in threads.items():
            if address not in self._workers and address not in self._lost:
                self._workers[address] = _Worker(address, max(1, int(n)))
        self._place_waiting()

    def _drop(self, address: str, *, lost: bool = True) -> None:
        """Take ``address`` out of the workers (for good if it was ``lost``)."""
        if lost:
            self._lost.add(address)
            self.client.rpc.remove(address)  # its pooled comms are dead too
        self._workers.pop(address, None)

    def _place_waiting(self) -> None:
        """Send waiting calls to the workers with room, the least busy first."""
        while self._waiting:
            free = [w for w in self._workers.values() if w.room]
            if not free:
                break
            call = self._waiting.popleft()
            if call.placed is None or call.placed.done():
                continue  # cancelled while it waited
            self._assign(call, min(free, key=lambda w: len(w.calls)))
            call.placed.set_result(None)
        self._watch_idle()

    def _assign(self, call: _Call, worker: _Worker) -> None:
        call.worker = worker
        call.started = False
        worker.calls.append(call)
        worker.idle_since = None
        self._start_due(worker)

    def _start_due(self, worker: _Worker) -> None:
        """The calls among the first ``threads`` of ``worker`` run now."""
        for call in worker.calls[:worker.threads]:
            if not call.started:
                call.started = True
                call.on_start(worker.address)

    def _done(self, call: _Call) -> None:
        """The call's answer came (or its worker is gone): its place goes to the next."""
        worker = call.worker
        call.worker = None
        if worker is not None and call in worker.calls:
            worker.calls.remove(call)
            if worker.address in self._workers:
                self._start_due(worker)
        self._place_waiting()

    def _watch_idle(self) -> None:
        """A worker without work while a job waits behind another elsewhere: take that job
        back after :data:`STEAL_AFTER` seconds, if it is still so."""
        loop = asyncio.get_running_loop()
        for worker in self._workers.values():
            if worker.calls or worker.idle_since is not None:
                continue
            worker.idle_since = loop.time()
            if any(not c.started for w in self._workers.values() for c in w.calls):
                loop.call_later(STEAL_AFTER, self._steal, worker)

    def _steal(self, idle: _Worker) -> None:
        if self._workers.get(idle.address) is not idle or idle.calls:
            return
        for worker in self._workers.values():
            for call in worker.calls:
                if not call.started:
                    task = asyncio.get_running_loop().create_task(self._withdraw(worker, call))
                    self._tasks.add(task)
                    task.add_done_callback(self._tasks.discard)
                    return

    async def _withdraw(self, worker: _Worker, call: _Call) -> None:
        try:
            await getattr(self.client.rpc(worker.address), WITHDRAW)(job=call.job_id)
        except Exception:  # the worker is gone: its calls fail by themselves
            log.debug("could not withdraw %s from %s", call.job_id, worker.address,
                      exc_info=True)

    async def _place(self, call: _Call, *, front: bool = False) -> _Worker:
        """Wait for a worker with room, in turn (``front``: first in the line)."""
        free = [w for w in self._workers.values() if w.room]
        if free and (front or not self._waiting):
            self._assign(call, min(free, key=lambda w: len(w.calls)))
        else:
            call.placed = asyncio.get_running_loop().create_future()
            if front:
                self._waiting.appendleft(call)
            else:
                self._waiting.append(call)
            try:
                await call.placed
            except asyncio.CancelledError:
                if call.worker is not None:
                    self._done(call)
                raise
            finally:
                call.placed = None
        assert call.worker is not None
        return call.worker

    def worker_of(self, job_id: str) -> str | None:
        """The worker running ``job_id`` or holding it next (None if it is not sent)."""
        call = self._calls.get(job_id)
        return call.worker.address if call is not None and call.worker is not None else None

    async def run(self, job_id: str, process: str, payload: bytes, *,
                  time_limit: float | None, test_processes: bool, stop: threading.Event,
                  on_start: Callable[[str], None]) -> Outcome:
        """Run a job on the next free worker: its outcome. ``payload`` is the pickled inputs
        (or the path of their file); ``on_start(worker)`` is called as it starts there;
        ``stop`` set before it is sent, it is not (dismissed). Raises :class:`WorkerLost`
        if the worker dies or cannot be reached."""
        call = _Call(job_id, on_start)
        self._calls[job_id] = call
        pool = self.client.rpc
        withdrawn = False
        try:
            while True:
                worker = await self._place(call, front=withdrawn)
                address = worker.address
                try:
                    if stop.is_set():
                        return Outcome.dismissed()
                    try:
                        comm = await pool.connect(address, timeout=CONNECT_TIMEOUT)
                    except OSError as exc:
                        # not reached is not lost (see the module's notes): out until the
                        # next refresh, back if the scheduler still lists it
                        self._drop(address, lost=False)
                        raise WorkerLost(address, started=False) from exc
                    try:
                        reply = await send_recv(comm, op=RUN, job=job_id, process=process,
                                                payload=payload, time_limit=time_limit,
                                                test_processes=test_processes)
                    except OSError as exc:
                        self._drop(address)
                        raise WorkerLost(address, started=call.started) from exc
                    finally:
                        pool.reuse(address, comm)
                finally:
                    self._done(call)
                if reply == WITHDRAWN:  # taken back before it started: to the next free worker
                    withdrawn = True
                    continue
                if not isinstance(reply, bytes):  # no handler there (yet): ask again later
                    self._drop(address, lost=False)
                    raise WorkerLost(address, started=False)
                outcome: Outcome = pickle.loads(reply)
                return outcome
        finally:
            del self._calls[job_id]

    async def cancel(self, job_id: str) -> None:
        """Set the dismissal flag of ``job_id`` on its worker (nothing if it is not sent)."""
        address = self.worker_of(job_id)
        if address is None:
            return
        try:
            await getattr(self.client.rpc(address), CANCEL)(job=job_id)
        except Exception:  # the worker is gone: so is the job
            log.debug("could not cancel %s on %s", job_id, address, exc_info=True)
