"""The asyncio SDK client against the same in-memory service as the synchronous one.

Both clients run the same flows (morphserve._client._Protocol), so these tests check that the
async driver carries each kind of step: requests, pauses, errors thrown back into a flow.
"""

from __future__ import annotations

import asyncio
import sys
from collections.abc import Awaitable, Callable
from typing import Any, TypeVar

import httpx
import numpy as np
import pytest

from morphserve import (
    APIError,
    AsyncClient,
    AsyncJob,
    InvalidInput,
    JobDismissed,
    JobFailed,
    NoSuchJob,
    NoSuchProcess,
    QueueFull,
    ResultNotReady,
    TransportError,
    WaitTimeout,
)
from tests.sdk.test_client import RESULTS, FakeServer, FakeTerminal, problem

T = TypeVar("T")


@pytest.fixture
def server() -> FakeServer:
    return FakeServer()


@pytest.fixture
def run(
    server: FakeServer, monkeypatch: pytest.MonkeyPatch
) -> Callable[[Callable[[AsyncClient], Awaitable[T]]], T]:
    """Run ``scenario(client)`` in a fresh event loop, on an AsyncClient of ``server``."""
    monkeypatch.delenv("MORPHSERVE_API_KEY", raising=False)

    def run(scenario: Callable[[AsyncClient], Awaitable[T]], **options: Any) -> T:
        async def main() -> T:
            transport = httpx.MockTransport(server)
            async with AsyncClient("http://morph.test", transport=transport, **options) as client:
                return await scenario(client)

        return asyncio.run(main())

    return run


def test_processes_and_describe(run: Any) -> None:
    async def scenario(client: AsyncClient) -> None:
        (summary,) = await client.processes()
        assert summary.id == "alignment.rigid"
        description = await client.describe(summary.id)
        assert set(description.inputs) == {"source", "target", "allow_reflection"}
        with pytest.raises(NoSuchProcess):
            await client.describe("nope")

    run(scenario)


def test_execute_wait_and_results(run: Any, server: FakeServer) -> None:
    async def scenario(client: AsyncClient) -> None:
        job = await client.execute("alignment.rigid", source=np.zeros((2, 3)), target=[[1]])
        assert isinstance(job, AsyncJob)
        assert job.id == "job-1"
        status = await job.wait(poll_interval=0.001)
        assert status.status == "successful"
        results = await job.results()
        np.testing.assert_array_equal(results["transform"], RESULTS["transform"])
        assert results["labels"].dtype.kind == "i"

    run(scenario)
    assert server.requests[0].headers["Prefer"] == "respond-async"
    assert b'"source":[[0.0,0.0,0.0],[0.0,0.0,0.0]]' in server.requests[0].content
    assert len(server.requests_to("GET", "/jobs/job-1")) == 3


def test_execute_with_wait_keeps_the_results(run: Any, server: FakeServer) -> None:
    async def scenario(client: AsyncClient) -> None:
        job = await client.execute("alignment.rigid", wait=5, source=[[0]])
        assert (await job.results())["rmse"] == 0.001

    run(scenario)
    assert len(server.requests) == 1
    assert server.requests[0].headers["Prefer"] == "wait=5, arrays=binary"


def test_results_before_the_end_name_the_call_that_waits(run: Any, server: FakeServer) -> None:
    server.done_within_wait = False

    async def scenario(client: AsyncClient) -> None:
        job = await client.execute("alignment.rigid", wait=0, source=[[0, 0]])
        server.jobs[job.id]["step"] = 2
        with pytest.raises(ResultNotReady,
                           match=r"is running.*\(await job\.result\(\) waits for it\)"):
            await job.results()

    run(scenario)


def test_wait_raises_job_failed(run: Any, server: FakeServer) -> None:
    server.script = [("running", 10, None), ("failed", 100, "diverged")]
    server.outcome = problem(500, "job-failed", "Matrix is singular.")

    async def scenario(client: AsyncClient) -> None:
        job = await client.execute("alignment.rigid", source=[[0]])
        with pytest.raises(JobFailed, match="Matrix is singular"):
            await job.wait(poll_interval=0.001)

    run(scenario)


def test_wait_timeout_and_dismiss(run: Any, server: FakeServer) -> None:
    server.script = [("running", 40, None)]

    async def scenario(client: AsyncClient) -> None:
        job = await client.execute("alignment.rigid", source=[[0]])
        with pytest.raises(WaitTimeout, match=r"did not end within 0\.02 s"):
            await job.wait(timeout=0.02, poll_interval=0.005)
        status = await job.dismiss()
        assert status.status == "dismissed"
        with pytest.raises(JobDismissed):
            await job.wait()

    run(scenario)


def test_job_and_jobs(run: Any, server: FakeServer) -> None:
    for _ in range(3):
        server.add_job()

    async def scenario(client: AsyncClient) -> None:
        job = await client.job("job-2")
        assert job.process_id == "alignment.rigid"
        assert (await job.status()).status == "running"
        with pytest.raises(NoSuchJob):
            await client.job("nope")
        jobs = await client.jobs(status="accepted")
        assert [j.job_id for j in jobs] == ["job-1", "job-3"]

    run(scenario)


def test_problems_map_to_their_classes(run: Any, server: FakeServer) -> None:
    async def scenario(client: AsyncClient) -> None:
        with pytest.raises(InvalidInput) as caught:
            await client.execute("alignment.rigid", target=[[0]])
        assert caught.value.errors[0]["input"] == "source"
        server.forced = problem(429, "queue-full", headers={"Retry-After": "3"})
        with pytest.raises(QueueFull) as full:
            await client.execute("alignment.rigid", source=[[0]])
        assert full.value.retry_after == 3.0
        server.forced = problem(418, "teapot")
        with pytest.raises(APIError) as other:
            await client.processes()
        assert type(other.value) is APIError

    run(scenario)


def test_transport_errors_are_wrapped() -> None:
    def refuse(request: httpx.Request) -> httpx.Response:
        raise httpx.ConnectError("Connection refused", request=request)

    async def main() -> None:
        async with AsyncClient("http://morph.test", transport=httpx.MockTransport(refuse)) as c:
            with pytest.raises(TransportError, match="Connection refused") as caught:
                await c.processes()
        assert isinstance(caught.value.__cause__, httpx.ConnectError)

    asyncio.run(main())


def test_api_key_header_and_close(server: FakeServer, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("MORPHSERVE_API_KEY", "s3cret")

    async def main() -> None:
        client = AsyncClient("http://morph.test", transport=httpx.MockTransport(server))
        await client.processes()
        await client.close()
        assert client._http.is_closed

    asyncio.run(main())
    assert server.requests[0].headers["Authorization"] == "Bearer s3cret"


def test_cancelling_a_wait_ends_the_progress_line(
    server: FakeServer, monkeypatch: pytest.MonkeyPatch
) -> None:
    server.script = [("running", 40, "slow")]
    terminal = FakeTerminal()
    monkeypatch.setattr(sys, "stderr", terminal)
    monkeypatch.setitem(sys.modules, "tqdm.auto", None)  # the SDK's own bar, tqdm or not

    async def main() -> None:
        async with AsyncClient("http://morph.test", transport=httpx.MockTransport(server)) as c:
            job = await c.execute("alignment.rigid", source=[[0]])
            with pytest.raises(asyncio.TimeoutError):
                await asyncio.wait_for(job.wait(progress=True, poll_interval=0.01), 0.05)

    asyncio.run(main())
    drawn = terminal.getvalue()
    assert drawn.startswith("\r[############------------------]  40% "), drawn
    assert drawn.endswith(" slow\n"), drawn


def test_geometry_objects_and_missing_files(run: Any, server: FakeServer, tmp_path: Any,
                                            monkeypatch: pytest.MonkeyPatch) -> None:
    import json

    import trimesh

    from morphserve import NoSuchFile

    monkeypatch.chdir(tmp_path)
    box = trimesh.creation.box()

    async def scenario(client: AsyncClient) -> None:
        await client.execute("alignment.rigid", source=box, target=box)
        with pytest.raises(NoSuchFile, match="'scan.ply', which names no file"):
            await client.execute("alignment.rigid", source="scan.ply", target=box)

    run(scenario)
    # the description once (a mesh given to a points input: its vertices), then one job
    assert [r.method for r in server.requests] == ["GET", "POST"]
    sent = json.loads(server.requests[1].content)["inputs"]
    np.testing.assert_array_equal(sent["source"], box.vertices)


def test_job_result_and_map(run: Any, server: FakeServer) -> None:
    async def scenario(client: AsyncClient) -> None:
        job = await client.execute("alignment.rigid", source=[[0]])
        np.testing.assert_array_equal((await job.result(timeout=5))["transform"],
                                      RESULTS["transform"])
        items = await client.map("alignment.rigid", [{"source": [[0]]}, {}], max_in_flight=1)
        assert [item.ok for item in items] == [True, False]
        assert isinstance(items[1].error, InvalidInput)

    run(scenario)
