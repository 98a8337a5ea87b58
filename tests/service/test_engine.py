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
