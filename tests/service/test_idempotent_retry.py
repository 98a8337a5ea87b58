"""The idempotent retry that races its first request (#17.10), made deterministic.

A job's row is committed, and readable, a moment before the engine is given the job. A retry
with the same Idempotency-Key that reads the row in that moment used to find no job in the
engine, read the row as it was (accepted) and answer 201 although it asked to wait. Here the
first request is held right after its row's commit (a store that says when it committed and
waits for a go), the retry is sent then, and it is let go only once the retry has asked the
engine for the job: order of events, no sleeps.

The routes run in-process (ASGI transport) on a real store and engine; the fast path's
worker processes run the jobs (no Dask cluster: these jobs never go there).
"""

from __future__ import annotations

import asyncio
import uuid
from collections.abc import Awaitable, Callable
from pathlib import Path
from typing import Any

import httpx
import numpy as np
import pytest
from fastapi import FastAPI

from service.errors import install_handlers
from service.jobs.engine import Engine
from service.jobs.status import Outcome
from service.jobs.store import JobStore
from service.routes import processes
from service.routes.common import State
from service.settings import Settings

SOURCE = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]
TARGET = [[1, 2, 3], [1, 3, 3], [0, 2, 3], [1, 2, 4]]
R_Z90 = np.array([[0, -1, 0], [1, 0, 0], [0, 0, 1]], float)  # by hand: see test_e2e_execute


class _HeldStore(JobStore):
    """A store whose first ``create`` commits, says so (``committed``), then waits for
    ``go`` before its caller hears of it."""

    def __init__(self, data_dir: Path) -> None:
        super().__init__(data_dir, fsync=False)
        self.committed = asyncio.Event()
        self.go = asyncio.Event()
        self._holding = False

    def write(self, method: Callable[..., Any], /, *args: Any, **kwargs: Any) -> Any:
        written = super().write(method, *args, **kwargs)
        if getattr(method, "__name__", "") != "create" or self._holding:
            return written
        self._holding = True

        async def held() -> Any:
            result = await written
            self.committed.set()
            await self.go.wait()
            return result

        return asyncio.ensure_future(held())


async def _service(tmp_path: Path) -> tuple[FastAPI, _HeldStore, Engine]:
    settings = Settings(data_dir=tmp_path, test_processes=True, fsync=False)
    store = _HeldStore(tmp_path)
    engine = Engine(settings, store)
    await engine.recover()  # nothing to recover; starts the fast path's workers
    while not engine.fast_path_ready:
        await asyncio.sleep(0.01)
    app = FastAPI()
    install_handlers(app)
    app.include_router(processes.router)
    app.state.morphserve = State(settings=settings, store=store, engine=engine)
    return app, store, engine


def _asked_the_engine(engine: Engine) -> asyncio.Event:
    """Set once a request asks the engine to wait for a job (a spy on Engine.wait)."""
    asked = asyncio.Event()
    wait: Callable[[str, float], Awaitable[Outcome | None]] = engine.wait

    async def spy(job_id: str, timeout: float) -> Outcome | None:
        asked.set()
        return await wait(job_id, timeout)

    engine.wait = spy  # type: ignore[method-assign]
    return asked


@pytest.mark.parametrize(("process", "inputs", "first"), [
    # the first request is answered at once: its row written, then the job submitted
    ("alignment.rigid", {"source": SOURCE, "target": TARGET}, "respond-async"),
    # the first request's wait ends while its fast job runs: then its row is written
    ("diagnostics.nap", {"seconds": 0.5, "steps": 5}, "wait=0.05"),
])
def test_a_retry_between_the_commit_and_the_submission_waits_for_the_job(
        tmp_path: Path, process: str, inputs: dict[str, Any], first: str) -> None:
    async def scenario() -> None:
        app, store, engine = await _service(tmp_path)
        asked = _asked_the_engine(engine)
        url = f"/processes/{process}/execution"
        body = {"inputs": inputs}
        key = f"key-{uuid.uuid4()}"
        try:
            async with httpx.AsyncClient(transport=httpx.ASGITransport(app=app),
                                         base_url="http://morphserve") as http:
                a = asyncio.create_task(http.post(url, json=body, headers={
                    "Idempotency-Key": key, "Prefer": first}))
                await store.committed.wait()  # the row is readable; the engine has no job
                b = asyncio.create_task(http.post(url, json=body, headers={
                    "Idempotency-Key": key, "Prefer": "wait=60"}))
                seen = asyncio.create_task(asked.wait())
                await asyncio.wait({seen, b}, return_when=asyncio.FIRST_COMPLETED)
                seen.cancel()
                assert not b.done(), b.result().text  # the retry waits for the job
                store.go.set()
                ra, rb = await a, await b
        finally:
            await engine.close()
            store.close()
        assert ra.status_code == 201, ra.text
        assert rb.status_code == 200, rb.text
        assert rb.headers["content-location"] == f"/jobs/{ra.json()['jobID']}/results"
        if process == "alignment.rigid":
            np.testing.assert_allclose(rb.json()["rotation"], R_Z90, atol=1e-12)
        else:
            assert rb.json()["steps"] == 5

    asyncio.run(scenario())
