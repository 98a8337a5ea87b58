"""The fast path's worker processes (service.jobs.fastpool): a job's outcome as a local call
gives it, and every way a run is cut short (budget, time limit, dismissal, a dying worker)
kills the worker that ran it and starts another. Real processes, no cluster."""

from __future__ import annotations

import asyncio
import os
import re
import threading
from collections.abc import Awaitable, Callable
from typing import Any

import numpy as np
from scipy.spatial.transform import Rotation

from algorithms.alignment import rigid
from service.jobs.fastpool import FastPool
from service.jobs.status import JobStatus


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    try:  # a zombie (killed, not yet reaped) is not running either
        with open(f"/proc/{pid}/stat") as f:
            return f.read().split(")")[-1].split()[0] != "Z"
    except FileNotFoundError:
        return False


def _in_pool(scenario: Callable[[FastPool], Awaitable[None]], *, budget: float = 60.0,
             size: int = 1) -> None:
    async def main() -> None:
        pool = FastPool(size, budget=budget, test_processes=True)
        pool.start()
        try:
            await _ready(pool)
            await scenario(pool)
        finally:
            pool.shutdown()

    asyncio.run(main())


async def _ready(pool: FastPool) -> None:
    while not pool.ready:
        await asyncio.sleep(0.01)


def _nap_pid(events: list[dict[str, Any]]) -> int:
    """The pid of the process that ran a nap, from its progress messages."""
    found = next(re.search(r"in pid (\d+)", e["message"]) for e in events
                 if "in pid" in e.get("message", ""))
    assert found is not None
    return int(found[1])


def _run(pool: FastPool, process: str, inputs: dict[str, Any], events: list[dict[str, Any]],
         *, time_limit: float | None = None, stop: threading.Event | None = None) -> Any:
    return pool.run("job", process, inputs, time_limit=time_limit,
                    stop=stop or threading.Event(), publish=events.append)


def test_a_job_gives_what_a_local_call_gives() -> None:
    rng = np.random.default_rng(5)
    X = rng.normal(size=(300, 3))
    R = Rotation.random(random_state=5).as_matrix()
    Y = X @ R.T + [1.0, -2.0, 0.5]

    async def scenario(pool: FastPool) -> None:
        outcome = await _run(pool, "alignment.rigid", {"source": X, "target": Y}, [])
        assert outcome.status is JobStatus.SUCCESSFUL
        local = rigid(X, Y)
        np.testing.assert_array_equal(outcome.outputs["rotation"], local.rotation)
        np.testing.assert_allclose(outcome.outputs["rotation"], R, atol=1e-12)
        bad = await _run(pool, "alignment.rigid", {"source": X, "target": Y[:10]}, [])
        assert bad.status is JobStatus.FAILED  # the runner's error handling, as on Dask
        assert pool.replaced == 0  # neither cost the worker

    _in_pool(scenario)


def test_past_the_budget_the_worker_is_replaced_and_the_job_given_back() -> None:
    async def scenario(pool: FastPool) -> None:
        events: list[dict[str, Any]] = []
        assert await _run(pool, "diagnostics.nap", {"seconds": 60, "steps": 600}, events) is None
        pid = _nap_pid(events)
        assert not _alive(pid) and pool.replaced == 1
        assert max(e["progress"] for e in events) < 100  # cut short, not run to its end
        await _ready(pool)
        again: list[dict[str, Any]] = []
        outcome = await _run(pool, "diagnostics.nap", {"seconds": 0.05, "steps": 5}, again)
        assert outcome.status is JobStatus.SUCCESSFUL and outcome.outputs["steps"] == 5
        assert _nap_pid(again) != pid  # the replacement ran it

    _in_pool(scenario, budget=0.5)


def test_a_job_past_its_time_limit_fails_and_its_worker_is_killed() -> None:
    """One step: the nap reports nothing until its end, so it cannot stop itself; the
    worker is killed, and the job's failure says why."""
    async def scenario(pool: FastPool) -> None:
        events: list[dict[str, Any]] = []
        first = await _run(pool, "diagnostics.nap", {"seconds": 0.05, "steps": 2}, events)
        assert first.status is JobStatus.SUCCESSFUL
        pid = _nap_pid(events)
        outcome = await _run(pool, "diagnostics.nap", {"seconds": 60, "steps": 1}, [],
                             time_limit=0.3)
        assert outcome.status is JobStatus.FAILED and outcome.timed_out
        assert outcome.problem["detail"] == \
            "The job was stopped: time limit of 0.3 s exceeded."
        assert not _alive(pid)

    _in_pool(scenario)


def test_dismissal_kills_the_worker() -> None:
    async def scenario(pool: FastPool) -> None:
        events: list[dict[str, Any]] = []
        stop = threading.Event()

        def publish(event: dict[str, Any]) -> None:
            events.append(event)
            stop.set()  # dismissed once it is seen running

        outcome = await pool.run("job", "diagnostics.nap", {"seconds": 60, "steps": 600},
                                 time_limit=None, stop=stop, publish=publish)
        assert outcome.status is JobStatus.DISMISSED
        assert not _alive(_nap_pid(events)) and pool.replaced == 1

    _in_pool(scenario)


def test_a_dying_worker_gives_the_job_back_and_is_replaced() -> None:
    async def scenario(pool: FastPool) -> None:
        assert await _run(pool, "diagnostics.crash", {}, []) is None
        assert pool.replaced == 1
        await _ready(pool)
        outcome = await _run(pool, "diagnostics.nap", {"seconds": 0, "steps": 1}, [])
        assert outcome.status is JobStatus.SUCCESSFUL

    _in_pool(scenario)


def test_a_small_job_behind_a_big_one_waits_for_the_budget_only() -> None:
    """Two jobs, one worker: the big one (a minute's nap) is cut at the budget and given
    back; the small one, queued behind it, then runs. Order of events, not times."""
    async def scenario(pool: FastPool) -> None:
        ended: list[str] = []

        async def job(name: str, inputs: dict[str, Any]) -> Any:
            outcome = await _run(pool, "diagnostics.nap", inputs, [])
            ended.append(name)
            return outcome

        big = asyncio.create_task(job("big", {"seconds": 60, "steps": 600}))
        await asyncio.sleep(0)  # the big one takes the worker first
        small = await job("small", {"seconds": 0, "steps": 1})
        assert await big is None and small.status is JobStatus.SUCCESSFUL
        assert ended == ["big", "small"]

    _in_pool(scenario, budget=0.5)


def test_jobs_run_side_by_side_on_several_workers() -> None:
    async def scenario(pool: FastPool) -> None:
        events: tuple[list[dict[str, Any]], ...] = ([], [])
        outcomes = await asyncio.gather(*(
            _run(pool, "diagnostics.nap", {"seconds": 0.3, "steps": 3}, e) for e in events))
        assert all(o.status is JobStatus.SUCCESSFUL for o in outcomes)
        assert _nap_pid(events[0]) != _nap_pid(events[1])  # each on a worker of its own

    _in_pool(scenario, size=2)
