"""Futures and batches: ``Job.result``, ``client.map`` and ``as_completed``, sync and async.

The unit tests play the service in memory (``FakeServer`` of test_client.py); the end-to-end
ones run a real server, where idempotency keys are the service's own.
"""

from __future__ import annotations

import asyncio
import io
import json
import threading
from collections.abc import Callable, Iterator
from typing import Any

import httpx
import numpy as np
import pytest

import morphserve
from morphserve import (
    AsyncClient,
    AsyncJob,
    BatchItem,
    Client,
    InvalidInput,
    Job,
    JobFailed,
    NoSuchFile,
    NoSuchProcess,
    ProgressBar,
    TransportError,
    WaitTimeout,
)
from tests.sdk.test_client import RESULTS, FakeClock, FakeServer, problem


def locked(handler: Callable[[httpx.Request], httpx.Response]
           ) -> Callable[[httpx.Request], httpx.Response]:
    """The fake service answering one request at a time (map sends from several threads)."""
    lock = threading.Lock()

    def answer(request: httpx.Request) -> httpx.Response:
        with lock:
            return handler(request)

    return answer


@pytest.fixture
def fake() -> FakeServer:
    return FakeServer()


@pytest.fixture
def client(fake: FakeServer, monkeypatch: pytest.MonkeyPatch) -> Iterator[Client]:
    monkeypatch.delenv("MORPHSERVE_API_KEY", raising=False)
    with Client("http://morph.test", transport=httpx.MockTransport(locked(fake))) as c:
        yield c


def sent(request: httpx.Request) -> dict[str, Any]:
    inputs: dict[str, Any] = json.loads(request.content)["inputs"]
    return inputs


# -- Job.result, like a Future -----------------------------------------------------------


def test_result_waits_then_gives_the_results(client: Client, fake: FakeServer) -> None:
    job = client.execute("alignment.rigid", source=[[0]])
    assert not job.done()  # accepted
    results = job.result()
    np.testing.assert_array_equal(results["transform"], RESULTS["transform"])
    assert job.done() and job.exception() is None


def test_result_raises_the_jobs_error(client: Client, fake: FakeServer) -> None:
    fake.script = [("running", 10, None), ("failed", 10, "boom")]
    fake.outcome = problem(500, "job-failed", "The job raised: boom")
    job = client.execute("alignment.rigid", source=[[0]])
    with pytest.raises(JobFailed, match="boom"):
        job.result()
    assert isinstance(job.exception(), JobFailed)


def test_result_times_out_as_a_timeout_error(client: Client, fake: FakeServer) -> None:
    fake.script = [("running", 10, None)]
    job = client.execute("alignment.rigid", source=[[0]])
    with pytest.raises(TimeoutError) as caught:
        job.result(timeout=0.01)
    assert isinstance(caught.value, WaitTimeout)
    with pytest.raises(TimeoutError):
        job.exception(timeout=0.01)


def test_a_job_done_within_the_wait_needs_no_request(client: Client,
                                                     fake: FakeServer) -> None:
    job = client.execute("alignment.rigid", source=[[0]], wait=5)
    count = len(fake.requests)
    assert job.done() and job.result()["rmse"] == RESULTS["rmse"]
    assert len(fake.requests) == count


# -- as_completed ------------------------------------------------------------------------


def test_as_completed_yields_jobs_as_they_end(client: Client, fake: FakeServer) -> None:
    fake.script = [("accepted", 0, None), ("running", 50, None), ("successful", 100, None)]
    slow = client.execute("alignment.rigid", source=[[0]])
    fake.script = [("successful", 100, None)]
    fast = client.execute("alignment.rigid", source=[[1]])
    fake.script = [("failed", 100, "boom")]
    fake.outcome = problem(500, "job-failed", "boom")
    failing = client.execute("alignment.rigid", source=[[2]])
    order = list(morphserve.as_completed([slow, fast, failing]))
    assert order == [fast, failing, slow]
    assert all(isinstance(job, Job) for job in order)
    with pytest.raises(JobFailed):
        failing.result()


def test_as_completed_draws_one_bar(client: Client, fake: FakeServer) -> None:
    fake.script = [("successful", 100, None)]
    jobs = [client.execute("alignment.rigid", source=[[i]]) for i in range(3)]
    stream = io.StringIO()
    bar = ProgressBar(stream, total=3, unit="jobs", clock=FakeClock(1.0))
    assert len(list(client.as_completed(jobs, progress=bar))) == 3
    assert stream.getvalue().splitlines()[-1].split()[1] == "3/3"


def test_as_completed_times_out(client: Client, fake: FakeServer) -> None:
    fake.script = [("successful", 100, None)]
    done = client.execute("alignment.rigid", source=[[0]])
    fake.script = [("running", 10, None)]
    stuck = client.execute("alignment.rigid", source=[[1]])
    seen = []
    with pytest.raises(TimeoutError, match="1 of 2 jobs did not end within 0.05 s"):
        for job in client.as_completed([stuck, done], timeout=0.05, poll_interval=0.001):
            seen.append(job)
    assert seen == [done]


def test_as_completed_of_nothing_and_of_two_clients(client: Client, fake: FakeServer) -> None:
    assert list(morphserve.as_completed([])) == []
    with Client("http://other.test", transport=httpx.MockTransport(fake)) as other:
        jobs = [client.execute("alignment.rigid", source=[[0]]),
                other.execute("alignment.rigid", source=[[0]])]
        with pytest.raises(ValueError, match="the jobs of one client"):
            morphserve.as_completed(jobs)


# -- map ---------------------------------------------------------------------------------


def test_map_returns_one_item_per_input_in_order(client: Client, fake: FakeServer) -> None:
    inputs = [{"source": [[i]]} for i in range(5)]
    inputs[2] = {"target": [[0]]}  # no source: the fake service refuses it (422)
    items = client.map("alignment.rigid", inputs, target=[[9]], batch_id="b1", max_in_flight=3)
    assert [item.index for item in items] == [0, 1, 2, 3, 4]
    assert [item.ok for item in items] == [True, True, False, True, True]
    assert isinstance(items[2].error, InvalidInput) and items[2].job is None
    with pytest.raises(InvalidInput):
        items[2].result()
    for item in items[:2] + items[3:]:
        assert isinstance(item, BatchItem) and isinstance(item.job, Job)
        assert item.result()["rmse"] == RESULTS["rmse"] and item.exception() is None
    posts = fake.requests_to("POST", r"/processes/alignment.rigid/execution")
    by_source = {json.dumps(sent(r).get("source")): r for r in posts}
    for index in (0, 1, 3, 4):  # keys from the batch id and the position
        request = by_source[json.dumps([[index]])]
        assert request.headers["Idempotency-Key"] == f"b1:alignment.rigid:{index}"
        assert sent(request)["target"] == [[9]]  # the common inputs
        assert request.headers["Prefer"].startswith("wait=")


def test_map_takes_the_users_keys(client: Client, fake: FakeServer) -> None:
    items = client.map("alignment.rigid", [{"source": [[0]]}, {"source": [[1]]}],
                       keys=["scan-a", "scan-b"], max_in_flight=1)
    assert [item.key for item in items] == ["scan-a", "scan-b"]
    keys = [r.headers["Idempotency-Key"] for r in fake.requests_to("POST", r".*execution")]
    assert keys == ["scan-a", "scan-b"]


def test_map_makes_a_batch_id_when_none_is_given(client: Client) -> None:
    first, second = client.map("alignment.rigid", [{"source": [[0]]}, {"source": [[1]]}])
    batch = first.key.rsplit(":", 2)[0]
    assert len(batch) == 32 and second.key == f"{batch}:alignment.rigid:1"


def test_map_refuses_bad_arguments(client: Client) -> None:
    with pytest.raises(ValueError, match="Expected `max_in_flight` to be an integer >= 1, "
                                         "got 0"):
        client.map("alignment.rigid", [{"source": [[0]]}], max_in_flight=0)
    with pytest.raises(TypeError, match="Expected each item of `inputs` to be a dict of named "
                                        "inputs, got list at index 1"):
        client.map("alignment.rigid", [{"source": [[0]]}, [[0]]])  # type: ignore[list-item]
    with pytest.raises(ValueError, match=r"Expected one key per input \(1\), got 2"):
        client.map("alignment.rigid", [{"source": [[0]]}], keys=["a", "b"])
    with pytest.raises(ValueError, match="Expected distinct keys"):
        client.map("alignment.rigid", [{"source": [[0]]}] * 2, keys=["a", "a"])
    with pytest.raises(TypeError, match="Give `batch_id` or `keys`, not both"):
        client.map("alignment.rigid", [{"source": [[0]]}], keys=["a"], batch_id="b")
    with pytest.raises(NoSuchProcess):  # once, before any job is sent
        client.map("nope", [{"source": [[0]]}] * 3)


def test_map_polls_jobs_that_outlast_the_wait(client: Client, fake: FakeServer) -> None:
    fake.done_within_wait = False
    fake.script = [("running", 50, None), ("successful", 100, None)]
    (item,) = client.map("alignment.rigid", [{"source": [[0]]}], poll_interval=0.001)
    assert item.ok and item.results is not None and item.job is not None
    assert item.results["rmse"] == RESULTS["rmse"]


def test_map_reports_a_failed_job_and_goes_on(client: Client, fake: FakeServer) -> None:
    fake.done_within_wait = False
    fake.script = [("failed", 100, "boom")]
    fake.outcome = problem(500, "job-failed", "boom")
    items = client.map("alignment.rigid", [{"source": [[0]]}, {"source": [[1]]}],
                       poll_interval=0.001)
    assert [type(item.error) for item in items] == [JobFailed, JobFailed]
    assert all(item.job is not None for item in items)  # the jobs exist: they failed


def test_map_retries_a_full_queue_with_the_same_key(fake: FakeServer) -> None:
    answered: list[httpx.Request] = []

    def busy_once(request: httpx.Request) -> httpx.Response:
        if request.method == "POST" and not answered:
            answered.append(request)
            return problem(429, "queue-full", "full", headers={"Retry-After": "0"})
        return fake(request)

    with Client("http://morph.test", transport=httpx.MockTransport(busy_once)) as client:
        (item,) = client.map("alignment.rigid", [{"source": [[0]]}], batch_id="q")
    assert item.ok
    posts = [r for r in fake.requests if r.method == "POST"]
    assert len(answered) == 1 and len(posts) == 1
    assert answered[0].headers["Idempotency-Key"] == posts[0].headers["Idempotency-Key"] \
        == "q:alignment.rigid:0"


def test_map_gives_up_on_an_unreachable_service(fake: FakeServer,
                                                monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr("morphserve._batch._backoff", lambda attempt, error: 0.0)

    def unreachable(request: httpx.Request) -> httpx.Response:
        if request.method == "POST":
            raise httpx.ConnectError("refused", request=request)
        return fake(request)

    with Client("http://morph.test", transport=httpx.MockTransport(unreachable)) as client:
        (item,) = client.map("alignment.rigid", [{"source": [[0]]}])
    assert isinstance(item.error, TransportError) and item.job is None


def test_map_draws_one_bar_with_the_failures(client: Client) -> None:
    stream = io.StringIO()
    bar = ProgressBar(stream, total=4, unit="jobs", clock=FakeClock(1.0))
    inputs = [{"source": [[0]]}, {"target": [[0]]}, {"source": [[1]]}, {"source": [[2]]}]
    client.map("alignment.rigid", inputs, progress=bar, max_in_flight=1)
    lines = stream.getvalue().splitlines()
    assert [line.split()[1] for line in lines] == ["1/4", "2/4", "3/4", "4/4"]
    assert lines[-1].endswith("1 failed")


def test_map_of_a_missing_file_is_an_item_error(client: Client, fake: FakeServer,
                                                tmp_path: Any,
                                                monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    first, second = client.map("alignment.rigid", [{"source": "gone.ply"}, {"source": [[0]]}])
    assert isinstance(first.error, NoSuchFile) and second.ok
    assert len(fake.requests_to("POST", r".*execution")) == 1


# -- the asyncio client ------------------------------------------------------------------


def run_async(fake: FakeServer, scenario: Callable[[AsyncClient], Any]) -> Any:
    async def main() -> Any:
        async with AsyncClient("http://morph.test", transport=httpx.MockTransport(fake)) as c:
            return await scenario(c)

    return asyncio.run(main())


def test_async_result_and_await(fake: FakeServer) -> None:
    async def scenario(client: AsyncClient) -> None:
        job = await client.execute("alignment.rigid", source=[[0]])
        assert not await job.done()
        results = await job  # the same as await job.result()
        assert results["rmse"] == RESULTS["rmse"] and await job.done()
        fake.script = [("running", 10, None)]
        stuck = await client.execute("alignment.rigid", source=[[0]])
        with pytest.raises(TimeoutError):
            await stuck.result(timeout=0.01)
        fake.script = [("failed", 100, "boom")]
        fake.outcome = problem(500, "job-failed", "boom")
        failing = await client.execute("alignment.rigid", source=[[0]])
        assert isinstance(await failing.exception(), JobFailed)

    run_async(fake, scenario)


def test_async_map_and_as_completed(fake: FakeServer) -> None:
    async def scenario(client: AsyncClient) -> None:
        inputs = [{"source": [[i]]} for i in range(6)]
        inputs[4] = {}
        items = await client.map("alignment.rigid", inputs, batch_id="a", max_in_flight=2)
        assert [item.ok for item in items] == [True] * 4 + [False, True]
        assert all(isinstance(item.job, AsyncJob) for item in items if item.ok)
        assert isinstance(items[4].error, InvalidInput)
        keys = sorted(r.headers["Idempotency-Key"]
                      for r in fake.requests_to("POST", r".*execution"))
        assert keys == sorted(f"a:alignment.rigid:{i}" for i in range(6))  # 4: refused

        fake.script = [("accepted", 0, None), ("successful", 100, None)]
        slow = await client.execute("alignment.rigid", source=[[0]])
        fake.script = [("successful", 100, None)]
        fast = await client.execute("alignment.rigid", source=[[0]])
        order = [job async for job in morphserve.as_completed([slow, fast])]
        assert order == [fast, slow]
        with pytest.raises(NoSuchProcess):
            await client.map("nope", inputs)

    run_async(fake, scenario)


def test_async_map_keeps_at_most_max_in_flight(fake: FakeServer) -> None:
    in_flight = 0
    most = 0

    class Counting(httpx.AsyncBaseTransport):
        async def handle_async_request(self, request: httpx.Request) -> httpx.Response:
            nonlocal in_flight, most
            if request.method != "POST":
                return fake(request)
            await request.aread()
            in_flight += 1
            most = max(most, in_flight)
            await asyncio.sleep(0.01)  # the service works on it
            in_flight -= 1
            return fake(request)

    async def main() -> list[BatchItem[AsyncJob]]:
        async with AsyncClient("http://morph.test", transport=Counting()) as client:
            return await client.map("alignment.rigid", [{"source": [[i]]} for i in range(9)],
                                    max_in_flight=3)

    items = asyncio.run(main())
    assert all(item.ok for item in items) and most == 3



# -- end to end --------------------------------------------------------------------------

#: A sleep that never ends during a test, in slices that a dismissal stops at once.
LONG_SLEEP = {"seconds": 60, "steps": 6000}


@pytest.fixture
def live(server: Any) -> Iterator[Client]:
    """A client of the session's live server (tests/conftest.py)."""
    with Client(server.url, timeout=60) as c:
        yield c


def _scans(count: int, n: int = 60) -> tuple[np.ndarray, list[dict[str, Any]]]:
    """A target and ``count`` sources, each the target moved by a small rotation."""
    from scipy.spatial.transform import Rotation

    rng = np.random.default_rng(7)
    target = rng.normal(size=(n, 3))
    sources = []
    for index in range(count):
        rotation = Rotation.from_rotvec(rng.normal(size=3) * 0.05).as_matrix()
        sources.append({"source": target @ rotation.T + 0.01 * index})
    return target, sources


@pytest.mark.e2e
def test_live_map_matches_one_job_at_a_time(live: Client, tmp_path: Any,
                                            monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    target, inputs = _scans(6)
    inputs[2] = {"source": np.zeros((5, 2))}  # 2-D against a 3-D target: refused
    inputs[4] = {"source": "missing.ply"}  # no such file: refused before sending
    stream = io.StringIO()
    items = live.map("registration.icp", inputs, target=target, model="rigid",
                     progress=ProgressBar(stream, total=6, unit="jobs"))
    assert [item.ok for item in items] == [True, True, False, True, False, True]
    assert isinstance(items[2].error, InvalidInput) and isinstance(items[4].error, NoSuchFile)
    for index in (0, 1, 3, 5):
        alone = live.execute("registration.icp", source=inputs[index]["source"],
                             target=target, model="rigid").result(timeout=60)
        np.testing.assert_array_equal(items[index].result()["transform"], alone["transform"])
        assert items[index].job is not None and items[index].job.process_id == \
            "registration.icp"
    assert stream.getvalue().splitlines()[-1].split()[1:2] == ["6/6"]
    assert stream.getvalue().rstrip().endswith("2 failed")


@pytest.mark.e2e
def test_live_map_run_again_gives_back_the_same_jobs(live: Client) -> None:
    target, inputs = _scans(4)
    batch = f"again-{np.random.default_rng().integers(1 << 62)}"
    first = live.map("registration.icp", inputs, target=target, batch_id=batch)
    again = live.map("registration.icp", inputs, target=target, batch_id=batch)
    assert all(item.ok for item in first + again)
    assert [item.job.id for item in first if item.job] == \
        [item.job.id for item in again if item.job]
    assert len({item.job.id for item in first if item.job}) == 4


@pytest.mark.e2e
def test_live_map_retry_after_a_lost_answer_makes_no_second_job(server: Any) -> None:
    target, inputs = _scans(3)
    lost: list[str] = []
    network = httpx.HTTPTransport()

    class LosesOneAnswer(httpx.BaseTransport):
        """Sends every request; the answer to the first execution never arrives."""

        def handle_request(self, request: httpx.Request) -> httpx.Response:
            response = network.handle_request(request)
            if request.method == "POST" and not lost:
                response.read()
                response.close()
                lost.append(request.headers["Idempotency-Key"])
                raise httpx.ReadError("connection reset", request=request)
            return response

    with Client(server.url, timeout=60, transport=LosesOneAnswer()) as client:
        before = len(client.jobs(process="registration.icp", limit=1000))
        items = client.map("registration.icp", inputs, target=target, max_in_flight=1)
        after = len(client.jobs(process="registration.icp", limit=1000))
    assert all(item.ok for item in items) and len(lost) == 1
    assert after - before == 3  # the lost request's job was found again by its key
    assert before + 3 <= 1000


@pytest.mark.e2e
def test_live_result_waits_times_out_and_raises(live: Client) -> None:
    quick = live.execute("diagnostics.sleep", seconds=0.05, steps=2)
    assert quick.result(timeout=30)["steps"] == 2  # waited for: the job ran to its end
    slow = live.execute("diagnostics.sleep", **LONG_SLEEP)
    try:
        with pytest.raises(TimeoutError):
            slow.result(timeout=0.2)
    finally:
        slow.dismiss()
    limited = live.execute("diagnostics.sleep", seconds=30, steps=3000, time_limit=0.5)
    with pytest.raises(JobFailed, match="time"):
        limited.result(timeout=30)


@pytest.mark.e2e
def test_live_as_completed_yields_by_the_end_not_the_start(live: Client) -> None:
    slow = live.execute("diagnostics.sleep", **LONG_SLEEP)  # on a worker: never ends alone
    quick = live.execute("diagnostics.nap", seconds=0.01, steps=1)  # in the service
    order = []
    for job in live.as_completed([slow, quick], timeout=60):
        order.append(job)
        if job == quick:
            slow.dismiss()
    assert order == [quick, slow]
    assert quick.result()["steps"] == 1  # successful
    assert slow.status().status == "dismissed"


@pytest.mark.e2e
def test_live_async_map_and_as_completed(server: Any) -> None:
    target, inputs = _scans(5)
    inputs[1] = {"source": [[0.0, 0.0]]}

    async def scenario() -> None:
        async with AsyncClient(server.url, timeout=60) as client:
            items = await client.map("registration.icp", inputs, target=target,
                                     max_in_flight=3)
            assert [item.ok for item in items] == [True, False, True, True, True]
            alone = await (await client.execute("registration.icp",
                                                source=inputs[3]["source"], target=target))
            np.testing.assert_array_equal(items[3].result()["transform"], alone["transform"])
            slow = await client.execute("diagnostics.sleep", **LONG_SLEEP)
            quick = await client.execute("diagnostics.nap", seconds=0.01, steps=1)
            order = []
            async for job in client.as_completed([slow, quick], timeout=60):
                order.append(job)
                if job == quick:
                    await slow.dismiss()
            assert order == [quick, slow]

    asyncio.run(scenario())
