"""Jobs sent to the embedded cluster's workers directly (service/jobs/direct.py): they run in
a worker's process, past the scheduler; progress, dismissal, time limits and worker deaths
are handled as for jobs through the scheduler."""

from __future__ import annotations

import asyncio
import os
import re
import signal
import tempfile
from collections.abc import Awaitable, Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from service.jobs.engine import Engine
from service.jobs.status import JobStatus
from service.jobs.store import JobRecord, JobRequest, JobStore
from service.settings import Settings

pytestmark = pytest.mark.e2e

Scenario = Callable[[Engine, JobStore], Awaitable[None]]


def _run(scenario: Scenario, **settings: Any) -> None:
    async def main(data: Path) -> None:
        store = JobStore(data, fsync=False)
        engine = Engine(Settings(data_dir=data, fast_path_bytes=0, test_processes=True,
                                 **settings), store)
        await engine.start()
        try:
            await scenario(engine, store)
        finally:
            await engine.close()
            store.close()

    with tempfile.TemporaryDirectory() as tmp:
        asyncio.run(main(Path(tmp)))


async def _submit(engine: Engine, store: JobStore, process: str, inputs: dict[str, Any],
                  time_limit: float | None = 60.0) -> JobRecord:
    job = await store.write(store.create, process=process, request=JobRequest(),
                            time_limit=time_limit, idempotency_key=None, request_hash=None,
                            owner="", job_id=None, inputs=inputs, spool=None, body=b"",
                            encoded=())
    engine.submit(job, inputs)
    return job


async def _ended(engine: Engine, store: JobStore, job_id: str, timeout: float) -> JobStatus:
    """The status the job ends with (within ``timeout`` seconds, else its status then): the
    engine's outcome, or the store's row if it ended before the engine was asked."""
    outcome = await engine.wait(job_id, timeout)
    if outcome is not None:
        return outcome.status
    row = store.get(job_id)
    assert row is not None
    return row.status


async def _running_pid(store: JobStore, job_id: str, other_than: int | None = None) -> int:
    """The pid a running nap job reports in its progress messages (polled: a bound on a
    wait, not a timing assertion)."""
    for _ in range(600):
        row = store.get(job_id)
        assert row is not None
        found = re.search(r"in pid (\d+)", row.message)
        if row.status is JobStatus.RUNNING and found and int(found[1]) != other_than:
            return int(found[1])
        await asyncio.sleep(0.05)
    raise AssertionError(f"job {job_id} never reported progress")


def test_a_job_runs_on_a_worker_past_the_scheduler() -> None:
    """A rigid alignment comes back right; a nap reports progress from a worker's process
    (not the service's); the scheduler never holds a task of either."""

    async def scenario(engine: Engine, store: JobStore) -> None:
        paths: list[str] = []
        engine.on_run.append(lambda job, path: paths.append(path))
        x = np.random.default_rng(0).normal(size=(50, 3))
        c, s = np.cos(0.3), np.sin(0.3)
        rot = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
        job = await _submit(engine, store, "alignment.rigid", {"source": x, "target": x @ rot.T})
        outcome = await engine.wait(job.id, 120)
        assert outcome is not None and outcome.status is JobStatus.SUCCESSFUL
        np.testing.assert_allclose(outcome.outputs["rotation"], rot, atol=1e-12)
        assert store.get(job.id).status is JobStatus.SUCCESSFUL  # type: ignore[union-attr]

        nap = await _submit(engine, store, "diagnostics.nap", {"seconds": 1.0, "steps": 10})
        pid = await _running_pid(store, nap.id)
        assert engine.client is not None
        workers = await engine.client.run(os.getpid)
        assert pid != os.getpid() and pid in workers.values()
        outcome = await engine.wait(nap.id, 120)
        assert outcome is not None and outcome.status is JobStatus.SUCCESSFUL
        assert paths == ["workers", "workers"]
        keys = await engine.client.run_on_scheduler(
            lambda dask_scheduler: [str(k) for k in dask_scheduler.tasks])
        assert not [k for k in keys if "morphserve" in k]

    _run(scenario, workers=2)


def test_dismissal_and_time_limit_stop_the_job_on_its_worker() -> None:
    """With one worker: a running nap of a minute, dismissed, frees the worker for the next
    job (which could not run otherwise); a nap past its time limit fails with it."""

    async def scenario(engine: Engine, store: JobStore) -> None:
        long = await _submit(engine, store, "diagnostics.nap", {"seconds": 60.0, "steps": 6000})
        queued = await _submit(engine, store, "diagnostics.nap", {"seconds": 0.0, "steps": 1})
        await _running_pid(store, long.id)
        await engine.dismiss(long.id)
        # well before the minute is up
        assert await _ended(engine, store, queued.id, 30) is JobStatus.SUCCESSFUL

        limited = await _submit(engine, store, "diagnostics.nap",
                                {"seconds": 30.0, "steps": 3000}, time_limit=0.5)
        outcome = await engine.wait(limited.id, 25)
        assert outcome is not None and outcome.status is JobStatus.FAILED
        assert outcome.problem is not None
        assert outcome.problem["type"] == "/problems/time-limit-exceeded"

    _run(scenario, workers=1)


def test_a_lost_worker_runs_the_job_again_then_fails_it() -> None:
    """A worker killed under a job (-9, as the memory killer does): the job runs again on
    another worker and succeeds; killed more often than ``allowed_failures``, it fails
    (worker-lost)."""

    async def scenario(engine: Engine, store: JobStore) -> None:
        job = await _submit(engine, store, "diagnostics.nap", {"seconds": 2.0, "steps": 40})
        os.kill(await _running_pid(store, job.id), signal.SIGKILL)
        outcome = await engine.wait(job.id, 120)
        assert outcome is not None and outcome.status is JobStatus.SUCCESSFUL

        job = await _submit(engine, store, "diagnostics.nap", {"seconds": 30.0, "steps": 600})
        pid = await _running_pid(store, job.id)
        os.kill(pid, signal.SIGKILL)
        os.kill(await _running_pid(store, job.id, other_than=pid), signal.SIGKILL)
        outcome = await engine.wait(job.id, 120)
        assert outcome is not None and outcome.status is JobStatus.FAILED
        assert outcome.problem is not None and outcome.problem["type"] == "/problems/worker-lost"
        # the nannies bring the workers back, and jobs run on them
        job = await _submit(engine, store, "diagnostics.nap", {"seconds": 0.0, "steps": 1})
        assert await _ended(engine, store, job.id, 120) is JobStatus.SUCCESSFUL

    _run(scenario, workers=2, allowed_failures=1)


def test_a_job_sent_behind_a_long_one_is_taken_back_by_a_free_worker() -> None:
    """Two workers, two jobs in flight each at most: a minute's nap on the first worker, a
    short nap on the second, then a quick job, sent behind the minute's nap. When the second
    worker runs out of work, the quick job is taken back and runs there, long before the
    minute is up; the minute's nap runs on, then is dismissed."""

    async def scenario(engine: Engine, store: JobStore) -> None:
        long = await _submit(engine, store, "diagnostics.nap", {"seconds": 60.0, "steps": 6000})
        short = await _submit(engine, store, "diagnostics.nap", {"seconds": 0.5, "steps": 5})
        quick = await _submit(engine, store, "diagnostics.nap", {"seconds": 0.0, "steps": 1})
        await asyncio.sleep(0)  # each job to its worker
        assert engine._slots is not None
        assert engine._slots.worker_of(quick.id) == engine._slots.worker_of(long.id)
        assert engine._slots.worker_of(short.id) != engine._slots.worker_of(long.id)
        for job in (short, quick):
            assert await _ended(engine, store, job.id, 30) is JobStatus.SUCCESSFUL
        row = store.get(long.id)
        assert row is not None and row.status is JobStatus.RUNNING
        await engine.dismiss(long.id)

    _run(scenario, workers=2)


def test_run_first_sends_the_job_before_its_row_is_written() -> None:
    """``run_first(direct=True)``: a job that ends within the wait is written once, finished
    (one commit); one that outlasts it is written accepted and recorded when it ends."""

    async def scenario(engine: Engine, store: JobStore) -> None:
        assert engine.direct("diagnostics.nap") and not engine.direct("diagnostics.sleep")
        written: list[Any] = []

        def recorder(job: JobRecord, inputs: dict[str, Any]) -> Any:
            async def record(outcome: Any, started: float) -> JobRecord:
                written.append(outcome)
                create = {"process": job.process, "request": job.request,
                          "time_limit": job.time_limit, "job_id": job.id,
                          "created": job.created, "inputs": inputs}
                if outcome is None:
                    return await store.write(store.create, **create)
                return await store.write(store.create_finished, outcome, started=started,
                                         **create)
            return record

        inputs = {"seconds": 0.0, "steps": 1}
        job = JobRecord.accepted(process="diagnostics.nap", request=JobRequest(),
                                 time_limit=60.0)
        stored, outcome = await engine.run_first(job, inputs, 30.0, recorder(job, inputs),
                                                 direct=True)
        assert outcome is not None and outcome.status is JobStatus.SUCCESSFUL
        assert stored.status is JobStatus.SUCCESSFUL and len(written) == 1
        assert store.get(job.id).status is JobStatus.SUCCESSFUL  # type: ignore[union-attr]

        inputs = {"seconds": 1.0, "steps": 10}
        job = JobRecord.accepted(process="diagnostics.nap", request=JobRequest(),
                                 time_limit=60.0)
        stored, outcome = await engine.run_first(job, inputs, 0.1, recorder(job, inputs),
                                                 direct=True)
        assert outcome is None and stored.active and written[-1] is None
        assert await _ended(engine, store, job.id, 60) is JobStatus.SUCCESSFUL
        assert store.get(job.id).status is JobStatus.SUCCESSFUL  # type: ignore[union-attr]

    _run(scenario, workers=1)
