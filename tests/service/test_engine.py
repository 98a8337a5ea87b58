"""The engine's bookkeeping, without a cluster: a job's outcome and the requests waiting
for it, against a store whose commit takes as long as the test says."""

from __future__ import annotations

import asyncio
from typing import Any

from service.jobs.engine import Engine, _Handle
from service.jobs.status import JobStatus, Outcome
from service.jobs.store import JobRecord, JobRequest
from service.settings import Settings


class _GatedStore:
    """A store whose writes wait for ``gate``: the commit of an outcome, held open."""

    def __init__(self) -> None:
        self.gate = asyncio.Event()
        self.written: list[tuple[Any, ...]] = []

    async def write(self, fn: Any, *args: Any, **kwargs: Any) -> None:
        await self.gate.wait()
        self.written.append((fn, *args))

    def finish(self, *args: Any, **kwargs: Any) -> bool:
        return True


def _engine(store: _GatedStore) -> tuple[Engine, _Handle]:
    engine = Engine(Settings(), store)  # type: ignore[arg-type]
    job = JobRecord.accepted(process="alignment.rigid", request=JobRequest(), time_limit=None)
    handle = _Handle(job, asyncio.get_running_loop().create_future())
    engine._jobs[job.id] = handle
    return engine, handle


def test_a_request_during_the_commit_waits_for_the_outcome() -> None:
    """The race behind a flaky idempotent retry: the job's handle left the engine before its
    outcome was committed, so a request arriving in between found no handle, read the row
    still active and answered 201 instead of the results."""

    async def scenario() -> None:
        store = _GatedStore()
        engine, handle = _engine(store)
        recording = asyncio.create_task(engine._record(handle, Outcome.successful({"x": 1})))
        await asyncio.sleep(0)  # _record now waits for its commit
        assert not store.written and engine.active == 1
        waiter = asyncio.create_task(engine.wait(handle.job.id, timeout=60.0))
        await asyncio.sleep(0)
        assert not waiter.done()  # before the fix: done at once, with None
        store.gate.set()
        await recording
        outcome = await waiter
        assert outcome is not None and outcome.status is JobStatus.SUCCESSFUL
        assert store.written and engine.active == 0
        assert await engine.wait(handle.job.id, timeout=0.0) is None  # recorded: read the row

    asyncio.run(scenario())


def test_a_second_record_while_the_first_commits_is_ignored() -> None:
    """The time-limit sweep may try to record a job whose own end is being committed."""

    async def scenario() -> None:
        store = _GatedStore()
        engine, handle = _engine(store)
        first = asyncio.create_task(engine._record(handle, Outcome.successful({})))
        await asyncio.sleep(0)
        await engine._record(handle, Outcome.failed({"type": "x", "detail": "late"}))
        store.gate.set()
        await first
        assert len(store.written) == 1 and handle.outcome.result().status is JobStatus.SUCCESSFUL

    asyncio.run(scenario())


class _DismissedStore:
    """A store whose row was dismissed by the route before the job's end was recorded:
    ``finish`` changes nothing (the row is final) and the row reads dismissed."""

    def __init__(self, job: JobRecord) -> None:
        import dataclasses

        self.row = dataclasses.replace(job, status=JobStatus.DISMISSED)

    async def write(self, fn: Any, *args: Any, **kwargs: Any) -> bool:
        return False

    def finish(self, *args: Any, **kwargs: Any) -> bool:
        return False

    def get(self, job_id: str) -> JobRecord | None:
        return self.row if job_id == self.row.id else None


def test_a_job_dismissed_while_it_ran_ends_dismissed_whatever_it_returned() -> None:
    """Its computation came back successful after the client dismissed it: the store keeps
    it dismissed, and so do the waiters, the callbacks and the metrics."""
    from service.metrics import Metrics, render, wire

    async def scenario() -> None:
        job = JobRecord.accepted(process="alignment.rigid", request=JobRequest(),
                                 time_limit=None)
        engine = Engine(Settings(), _DismissedStore(job))  # type: ignore[arg-type]
        metrics = Metrics()
        wire(engine, metrics)
        heard: list[JobStatus] = []
        engine.on_finish.append(lambda job, outcome: heard.append(outcome.status))
        handle = _Handle(job, asyncio.get_running_loop().create_future())
        engine._jobs[job.id] = handle
        waiter = asyncio.create_task(engine.wait(job.id, timeout=60.0))
        await asyncio.sleep(0)  # the waiter waits on the job
        await engine._record(handle, Outcome.successful({"x": 1}))
        outcome = await waiter
        assert outcome is not None and outcome.status is JobStatus.DISMISSED
        assert heard == [JobStatus.DISMISSED]
        text = render(metrics, jobs={}, queue=0, workers=0, processes=0)
        assert 'morphserve_jobs_finished_total{process="alignment.rigid",status="dismissed"} 1' \
            in text.splitlines()
        assert not [line for line in text.splitlines()
                    if line.startswith("morphserve_jobs_finished_total") and "successful" in line]

    asyncio.run(scenario())


class _SlowPool:
    """A fast-path pool whose worker notices a dismissal only when the test says (a real
    one looks every POLL_INTERVAL seconds, then kills the worker and waits for it)."""

    def __init__(self) -> None:
        self.started = asyncio.Event()
        self.noticed = asyncio.Event()

    async def run(self, *args: Any, stop: Any, **kwargs: Any) -> Outcome:
        self.started.set()
        await self.noticed.wait()
        assert stop.is_set()
        return Outcome.dismissed()


def test_a_dismissed_fast_job_is_recorded_before_its_worker_stops() -> None:
    """The race behind a flaky metrics test: a fast-path job was counted dismissed only
    once its pool had killed the worker, after the DELETE that dismissed it had answered;
    a client reading the metrics (or waiting on the job) right after the DELETE found it
    still running. Now ``dismiss`` records it before it returns, and the worker's late
    answer is not recorded twice."""
    from service.metrics import Metrics, render, wire

    async def scenario() -> None:
        job = JobRecord.accepted(process="diagnostics.nap", request=JobRequest(),
                                 time_limit=None)
        engine = Engine(Settings(), _DismissedStore(job))  # type: ignore[arg-type]
        engine._pool = pool = _SlowPool()  # type: ignore[assignment]
        metrics = Metrics()
        wire(engine, metrics)
        heard: list[JobStatus] = []
        engine.on_finish.append(lambda job, outcome: heard.append(outcome.status))
        engine.submit(job, {}, fast=True)
        await pool.started.wait()
        assert engine.active == 1
        await engine.dismiss(job.id)
        assert heard == [JobStatus.DISMISSED] and engine.active == 0  # before: [] and 1
        outcome = await engine.wait(job.id, timeout=0.0)
        assert outcome is None  # recorded: whoever asks reads the row
        text = render(metrics, jobs={}, queue=0, workers=0, processes=0)
        assert 'morphserve_jobs_finished_total{process="diagnostics.nap",status="dismissed"} 1' \
            in text.splitlines()
        pool.noticed.set()  # the worker stops: its dismissed run is not recorded again
        for _ in range(10):
            await asyncio.sleep(0)
        assert heard == [JobStatus.DISMISSED] and not engine._tasks

    asyncio.run(scenario())


def test_an_announced_job_is_waited_for_until_it_is_submitted_or_forgotten() -> None:
    async def scenario() -> None:
        engine = Engine(Settings(), _GatedStore())  # type: ignore[arg-type]
        engine.expect("j1")
        waiter = asyncio.create_task(engine.wait("j1", timeout=60.0))
        await asyncio.sleep(0)
        assert not waiter.done()  # the row may be readable, but the job is not here yet
        engine.forget("j1")  # its row was never written
        assert await waiter is None
        assert await engine.wait("j2", timeout=60.0) is None  # unknown: at once

    asyncio.run(scenario())
