"""The direct calls' bookkeeping (service.jobs.direct.Slots) with a stand-in client: which
workers it sends jobs to after a call fails. No cluster, no processes."""

from __future__ import annotations

import asyncio
import pickle
import threading
from collections.abc import Awaitable, Callable, Coroutine
from typing import Any

import pytest
from distributed.comm import CommClosedError

from service.jobs import direct
from service.jobs.direct import RUN, Slots, WorkerLost
from service.jobs.status import JobStatus, Outcome


class _Pool:
    """The client's connection pool: workers in ``unreachable`` take no connection (a
    worker whose loop is busy: the connect times out)."""

    def __init__(self) -> None:
        self.unreachable: set[str] = set()

    async def connect(self, address: str, timeout: float | None = None) -> str:
        if address in self.unreachable:
            raise OSError(f"Timed out trying to connect to {address} after {timeout} s")
        return address  # the comm: its worker's address

    def reuse(self, address: str, comm: str) -> None:
        pass

    def remove(self, address: str) -> None:
        pass


class _Client:
    """The engine's client as Slots uses it: the scheduler's list of workers, the pool."""

    def __init__(self, *workers: str) -> None:
        self.listed = dict.fromkeys(workers, 1)
        self.rpc = _Pool()

    async def nthreads(self) -> dict[str, int]:
        return dict(self.listed)


def _in_slots(scenario: Callable[[Slots, _Client, list[str]], Awaitable[None]],
              monkeypatch: pytest.MonkeyPatch, *workers: str,
              dies: frozenset[str] = frozenset()) -> None:
    """Run ``scenario(slots, client, ran)``: the workers in ``dies`` break the comm under
    the job (killed), the others answer a successful outcome; ``ran`` lists the workers
    that answered."""
    ran: list[str] = []

    async def send_recv(comm: str, *, op: str, **msg: Any) -> bytes:
        assert op == RUN
        if comm in dies:
            raise CommClosedError(f"in {comm}: Stream is closed")
        ran.append(comm)
        return pickle.dumps(Outcome.successful({"worker": comm}), protocol=5)

    monkeypatch.setattr(direct, "send_recv", send_recv)

    async def main() -> None:
        client = _Client(*workers)
        slots = Slots(client)
        await slots.refresh()
        await scenario(slots, client, ran)

    asyncio.run(main())


def _run(slots: Slots, job_id: str) -> Coroutine[Any, Any, Outcome]:
    return slots.run(job_id, "diagnostics.nap", b"", time_limit=None, test_processes=True,
                     stop=threading.Event(), on_start=lambda worker: None)


def test_a_worker_not_reached_yet_gets_the_job_once_it_answers(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """A worker the nanny has just started is listed by the scheduler before it answers (its
    loop busy with its set-up for seconds under load): a job that cannot reach it is sent
    again without counting, and the worker, still listed at the next look, is sent jobs
    again, that one first. It was written off for good: with every worker replaced so, jobs
    waited for ever (test_a_lost_worker_runs_the_job_again_then_fails_it, under load)."""

    async def scenario(slots: Slots, client: _Client, ran: list[str]) -> None:
        client.rpc.unreachable.add("tls://new")
        with pytest.raises(WorkerLost) as lost:
            await _run(slots, "job")
        assert lost.value.worker == "tls://new" and not lost.value.started
        assert slots.workers == 0  # set aside until the scheduler is asked again
        again = asyncio.get_running_loop().create_task(_run(slots, "job"))  # the engine's retry
        await asyncio.sleep(0)
        assert not again.done() and len(slots._waiting) == 1  # waits for a worker

        client.rpc.unreachable.clear()  # its set-up is done
        await slots.refresh()
        assert slots.workers == 1
        outcome = await asyncio.wait_for(again, 30)  # a bound, should it hang
        assert outcome.status is JobStatus.SUCCESSFUL and ran == ["tls://new"]

    _in_slots(scenario, monkeypatch, "tls://new")


def test_a_worker_not_reached_and_gone_from_the_scheduler_is_not_taken_back(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """A worker that cannot be reached because it died: the scheduler no longer lists it,
    and the job goes to the other worker."""

    async def scenario(slots: Slots, client: _Client, ran: list[str]) -> None:
        client.rpc.unreachable.add("tls://a")
        with pytest.raises(WorkerLost):
            await _run(slots, "job")
        del client.listed["tls://a"]
        await slots.refresh()
        assert slots.workers == 1
        outcome = await _run(slots, "job")
        assert outcome.status is JobStatus.SUCCESSFUL and ran == ["tls://b"]

    _in_slots(scenario, monkeypatch, "tls://a", "tls://b")


def test_a_worker_that_died_under_a_job_is_never_taken_back(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """The comm broke under the job: the worker died there, the job counts it
    (``started``), and the worker gets no more jobs, though the scheduler still lists it for
    a while; its replacement (a new address) does."""

    async def scenario(slots: Slots, client: _Client, ran: list[str]) -> None:
        with pytest.raises(WorkerLost) as lost:
            await _run(slots, "job")
        assert lost.value.worker == "tls://dead" and lost.value.started
        await slots.refresh()
        assert slots.workers == 0
        client.listed["tls://replacement"] = 1
        await slots.refresh()
        assert slots.workers == 1
        outcome = await _run(slots, "job")
        assert outcome.status is JobStatus.SUCCESSFUL and ran == ["tls://replacement"]

    _in_slots(scenario, monkeypatch, "tls://dead", dies=frozenset({"tls://dead"}))
