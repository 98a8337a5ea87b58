"""The synchronous SDK client against the HTTP contract, simulated in memory.

:class:`FakeServer` plays the service behind an ``httpx.MockTransport``; the async tests
(test_async_client.py, in this directory) import it from here.
"""

from __future__ import annotations

import io
import json
import pickle
import re
from collections.abc import Iterator
from datetime import UTC, datetime, timedelta
from email.utils import format_datetime
from typing import Any
from urllib.parse import parse_qsl, urlencode

import httpx
import numpy as np
import pytest

import morphserve
from morphserve import (
    APIError,
    BadRequest,
    Client,
    HeaderTooLarge,
    IdempotencyConflict,
    InsufficientStorage,
    InternalError,
    InvalidInput,
    JobDismissed,
    JobFailed,
    JobStatus,
    MalformedBody,
    MethodNotAllowed,
    MorphserveError,
    NoSuchJob,
    NoSuchOutput,
    NoSuchProcess,
    NotAcceptable,
    NotFound,
    PayloadTooLarge,
    ProgressBar,
    ProtocolError,
    QueueFull,
    RequestTimeout,
    ResultNotReady,
    Results,
    ServiceUnavailable,
    TimeLimitExceeded,
    TransportError,
    Unauthorized,
    UnsupportedMediaType,
    WaitTimeout,
    WorkerLost,
)

PROCESS = {
    "id": "alignment.rigid",
    "title": "Rigid alignment",
    "description": "Least-squares rotation and translation mapping source onto target.",
    "version": "1.0.0",
    "jobControlOptions": ["sync-execute", "async-execute", "dismiss"],
    "outputTransmission": ["value"],
    "links": [{"rel": "self", "href": "/processes/alignment.rigid"}],
}
DESCRIPTION = {
    **PROCESS,
    "inputs": {
        "source": {
            "title": "Source points",
            "description": "(n, d) points",
            "schema": {"type": "array", "items": {"type": "array", "items": {"type": "number"}}},
            "minOccurs": 1,
            "maxOccurs": 1,
        },
        "target": {
            "title": "Target points",
            "description": "(n, d) points",
            "schema": {"type": "array", "items": {"type": "array", "items": {"type": "number"}}},
            "minOccurs": 1,
            "maxOccurs": 1,
        },
        "allow_reflection": {
            "title": "Allow reflection",
            "description": "Allow an improper rotation.",
            "schema": {"type": "boolean", "default": False},
            "minOccurs": 0,
            "maxOccurs": 1,
        },
    },
    "outputs": {
        "transform": {
            "title": "Transform",
            "description": "(d+1, d+1)",
            "schema": {"type": "array"},
        },
        "rmse": {"title": "RMSE", "description": "Residual", "schema": {"type": "number"}},
    },
}
RESULTS = {
    "transform": [[1.0, 0.0, 0.0, 0.5], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [0, 0, 0, 1]],
    "rmse": 0.001,
    "iterations": 3,
    "converged": True,
    "labels": [0, 1, 1],
    "loops": [[0, 1, 2], [3, 4]],
    "names": ["a", "b"],
    "method": "svd",
}
TITLES = {
    "invalid-input": "Invalid input",
    "job-failed": "Job failed",
    "job-dismissed": "Job dismissed",
    "result-not-ready": "Result not ready",
    "no-such-job": "No such job",
    "no-such-process": "No such process",
    "not-found": "Not found",
}
HAPPY = [("accepted", 0, None), ("running", 40, "iteration 12 of 30"), ("successful", 100, "done")]
STAMP = "2025-01-02T03:04:05.123456+00:00"


def problem(
    status: int, slug: str, detail: str = "", *, headers: dict[str, str] | None = None, **extra: Any
) -> httpx.Response:
    """An RFC 9457 answer as the service gives it."""
    body = {
        "type": f"/problems/{slug}",
        "title": TITLES.get(slug, slug.replace("-", " ").capitalize()),
        "status": status,
        "detail": detail,
        **extra,
    }
    return httpx.Response(
        status, json=body, headers={"Content-Type": "application/problem+json", **(headers or {})}
    )


class FakeServer:
    """The HTTP contract in memory: a handler for ``httpx.MockTransport``.

    Each job follows ``script``, a list of (status, progress, message) that advances by one
    step per ``GET /jobs/{id}``. A failed job's results answer ``outcome`` (a problem).
    ``forced`` answers the next request whatever it is.
    """

    def __init__(self) -> None:
        self.requests: list[httpx.Request] = []
        self.jobs: dict[str, dict[str, Any]] = {}
        self.script: list[tuple[str, int, str | None]] = list(HAPPY)
        self.outcome: httpx.Response | None = None
        self.done_within_wait = True
        self.forced: httpx.Response | None = None
        self.page_size = 2

    def requests_to(self, method: str, pattern: str) -> list[httpx.Request]:
        return [
            r for r in self.requests if r.method == method and re.fullmatch(pattern, r.url.path)
        ]

    def add_job(self, script: list[tuple[str, int, str | None]] | None = None) -> str:
        job_id = f"job-{len(self.jobs) + 1}"
        self.jobs[job_id] = {"script": list(script or self.script), "step": 0, "dismissed": False}
        return job_id

    def status_info(self, job_id: str) -> dict[str, Any]:
        job = self.jobs[job_id]
        state, progress, message = job["script"][min(job["step"], len(job["script"]) - 1)]
        if job["dismissed"]:
            state, message = "dismissed", "dismissed by the user"
        return {
            "jobID": job_id,
            "processID": "alignment.rigid",
            "type": "process",
            "status": state,
            "message": message,
            "created": STAMP,
            "started": STAMP if state != "accepted" else None,
            "finished": STAMP if state in ("successful", "failed", "dismissed") else None,
            "updated": "2025-01-02T03:04:06Z",
            "progress": progress,
            "links": [
                {"rel": "self", "href": f"/jobs/{job_id}"},
                {"rel": "results", "href": f"/jobs/{job_id}/results"},
            ],
        }

    def __call__(self, request: httpx.Request) -> httpx.Response:
        self.requests.append(request)
        if self.forced is not None:
            forced, self.forced = self.forced, None
            return forced
        path, method = request.url.path, request.method
        if path == "/processes" and method == "GET":
            return httpx.Response(200, json={"processes": [PROCESS], "links": []})
        if m := re.fullmatch(r"/processes/([^/]+)", path):
            if m[1] != PROCESS["id"]:
                return problem(404, "no-such-process", f"No process {m[1]!r}.")
            return httpx.Response(200, json=DESCRIPTION)
        if m := re.fullmatch(r"/processes/([^/]+)/execution", path):
            return self.execute(request)
        if path == "/jobs":
            return self.list_jobs(request)
        if m := re.fullmatch(r"/jobs/([^/]+)(/results)?", path):
            if m[1] not in self.jobs:
                return problem(404, "no-such-job", f"No job {m[1]!r}.")
            return self.results(m[1]) if m[2] else self.job(m[1], method)
        return problem(404, "not-found", path)

    def execute(self, request: httpx.Request) -> httpx.Response:
        body = json.loads(request.content)
        if "source" not in body["inputs"]:
            errors = [{"input": "source", "message": "Expected (n, d) points, got nothing."}]
            return problem(422, "invalid-input", "1 input is invalid.", errors=errors)
        job_id = self.add_job()
        prefer = request.headers.get("Prefer", "")
        if prefer.startswith("wait=") and self.done_within_wait:
            return httpx.Response(
                200,
                json=RESULTS,
                headers={
                    "Preference-Applied": prefer,
                    "Content-Location": f"/jobs/{job_id}/results",
                },
            )
        headers = {"Location": f"/jobs/{job_id}"}
        if prefer.startswith("wait="):
            headers["Preference-Applied"] = "respond-async"
        return httpx.Response(201, json=self.status_info(job_id), headers=headers)

    def job(self, job_id: str, method: str) -> httpx.Response:
        if method == "DELETE":
            self.jobs[job_id]["dismissed"] = True
            return httpx.Response(200, json=self.status_info(job_id))
        info = self.status_info(job_id)
        self.jobs[job_id]["step"] += 1
        return httpx.Response(200, json=info)

    def results(self, job_id: str) -> httpx.Response:
        job = self.jobs[job_id]
        if job["dismissed"]:
            return problem(410, "job-dismissed", f"Job {job_id} was dismissed.")
        state = job["script"][min(job["step"], len(job["script"])) - 1][0]
        if state == "failed":
            assert self.outcome is not None
            return self.outcome
        if state != "successful":
            return problem(404, "result-not-ready", f"Job {job_id} is {state}.")
        return httpx.Response(200, json=RESULTS)

    def list_jobs(self, request: httpx.Request) -> httpx.Response:
        query = parse_qsl(request.url.query.decode())
        wanted = {v for k, v in query if k == "status"}
        processes = {v for k, v in query if k == "processID"}
        params = dict(query)
        limit = min(int(params.get("limit", 10)), self.page_size)
        offset = int(params.get("offset", 0))
        infos = [self.status_info(job_id) for job_id in self.jobs]
        infos = [i for i in infos if not wanted or i["status"] in wanted]
        infos = [i for i in infos if not processes or i["processID"] in processes]
        page = infos[offset : offset + limit]
        links = []
        if offset + limit < len(infos):
            rest = [(k, v) for k, v in query if k not in ("offset", "limit")]
            rest += [("limit", str(limit)), ("offset", str(offset + limit))]
            links.append({"rel": "next", "href": f"/jobs?{urlencode(rest)}"})
        return httpx.Response(200, json={"jobs": page, "links": links})


@pytest.fixture
def server() -> FakeServer:
    return FakeServer()


@pytest.fixture
def client(server: FakeServer, monkeypatch: pytest.MonkeyPatch) -> Iterator[Client]:
    monkeypatch.delenv("MORPHSERVE_API_KEY", raising=False)
    with Client("http://morph.test", transport=httpx.MockTransport(server)) as client:
        yield client


# -- processes ---------------------------------------------------------------------------


def test_processes_lists_summaries(client: Client) -> None:
    (summary,) = client.processes()
    assert summary.id == "alignment.rigid"
    assert summary.title == "Rigid alignment"
    assert summary.version == "1.0.0"
    assert summary.job_control_options == ("sync-execute", "async-execute", "dismiss")
    assert summary.description.startswith("Least-squares")


def test_describe_parses_inputs_and_outputs(client: Client) -> None:
    description = client.describe("alignment.rigid")
    assert description.id == "alignment.rigid"
    assert set(description.inputs) == {"source", "target", "allow_reflection"}
    assert description.inputs["allow_reflection"]["schema"]["default"] is False
    assert set(description.outputs) == {"transform", "rmse"}
    assert description.raw == DESCRIPTION
    assert isinstance(description, morphserve.ProcessSummary)


def test_describe_unknown_process_raises_no_such_process(client: Client) -> None:
    with pytest.raises(NoSuchProcess, match="No process 'nope'") as caught:
        client.describe("nope")
    assert caught.value.status == 404
    assert caught.value.type == "/problems/no-such-process"


# -- execute -----------------------------------------------------------------------------


def test_execute_asks_for_async_and_reads_location(client: Client, server: FakeServer) -> None:
    job = client.execute("alignment.rigid", source=[[0, 0]], target=[[1, 1]])
    assert job.id == "job-1"
    assert job.process_id == "alignment.rigid"
    assert job.submitted_status is not None and job.submitted_status.status == "accepted"
    (request,) = server.requests
    assert request.method == "POST"
    assert request.url.path == "/processes/alignment.rigid/execution"
    assert request.headers["Prefer"] == "respond-async"
    assert request.headers["Content-Type"] == "application/json"
    assert "Idempotency-Key" not in request.headers
    assert json.loads(request.content) == {"inputs": {"source": [[0, 0]], "target": [[1, 1]]}}


def test_execute_converts_numpy_inputs(client: Client, server: FakeServer) -> None:
    client.execute(
        "alignment.rigid",
        source=np.arange(6, dtype=np.float32).reshape(3, 2),
        target=np.eye(2, dtype=np.int64),
        weights=[np.float64(0.5), np.int32(2)],
        allow_reflection=np.bool_(True),
        options={"iterations": np.int64(3), "points": (np.zeros(2),)},
    )
    inputs = json.loads(server.requests[0].content)["inputs"]
    assert inputs == {
        "source": [[0.0, 1.0], [2.0, 3.0], [4.0, 5.0]],
        "target": [[1, 0], [0, 1]],
        "weights": [0.5, 2],
        "allow_reflection": True,
        "options": {"iterations": 3, "points": [[0.0, 0.0]]},
    }
    assert isinstance(inputs["target"][0][0], int)


def test_execute_leaves_validation_to_the_service(client: Client, server: FakeServer) -> None:
    """NaN/Infinity and strings are sent as they are, for the service to name in its
    InvalidInput; only what JSON cannot hold at all is refused here."""
    client.execute("alignment.rigid", source=np.array([[0.0, np.nan]]),
                   options={"tol": float("inf")}, labels=np.array(["a", "b"]))
    sent = server.requests[0].content
    assert b"[[0.0,NaN]]" in sent and b'"tol":Infinity' in sent and b'["a","b"]' in sent
    with pytest.raises(TypeError, match="Expected `source` to be an array of numbers"):
        client.execute("alignment.rigid", source=np.array([object()]))
    with pytest.raises(TypeError, match="got object"):
        client.execute("alignment.rigid", source=object())
    assert len(server.requests) == 1


def test_execute_with_wait_keeps_the_results(client: Client, server: FakeServer) -> None:
    job = client.execute("alignment.rigid", wait=2.5, source=[[0, 0]], target=[[1, 1]])
    assert job.id == "job-1"
    assert server.requests[0].headers["Prefer"] == "wait=3, arrays=binary"
    results = job.results()
    assert results["rmse"] == 0.001
    assert len(server.requests) == 1  # the results came with the answer


def test_execute_with_wait_falls_back_to_async(client: Client, server: FakeServer) -> None:
    server.done_within_wait = False
    job = client.execute("alignment.rigid", wait=0, source=[[0, 0]])
    assert server.requests[0].headers["Prefer"] == "wait=0, arrays=binary"
    assert job.id == "job-1"
    with pytest.raises(ResultNotReady, match=r"job-1 is running.*\(job\.result\(\) waits for it\)"):
        server.jobs["job-1"]["step"] = 2
        job.results()


def test_execute_sends_outputs_and_idempotency_key(client: Client, server: FakeServer) -> None:
    client.execute("alignment.rigid", outputs=["transform"], idempotency_key="k-1", source=[[0]])
    client.execute("alignment.rigid", outputs={"rmse": None}, source=[[0]])
    first, second = server.requests
    assert first.headers["Idempotency-Key"] == "k-1"
    assert json.loads(first.content)["outputs"] == {"transform": {}}
    assert json.loads(second.content)["outputs"] == {"rmse": {}}


def test_execute_rejects_a_negative_wait(client: Client) -> None:
    with pytest.raises(ValueError, match="Expected `wait` to be 0 or more seconds, got -1"):
        client.execute("alignment.rigid", wait=-1, source=[[0]])


def test_execute_invalid_input_carries_field_errors(client: Client) -> None:
    with pytest.raises(InvalidInput, match="1 input is invalid") as caught:
        client.execute("alignment.rigid", target=[[0]])
    error = caught.value
    assert isinstance(error, ValueError)
    assert error.status == 422
    assert error.errors == [{"input": "source", "message": "Expected (n, d) points, got nothing."}]
    assert "source: Expected (n, d) points" in str(error)


def test_execute_200_without_content_location_is_a_protocol_error(
    client: Client, server: FakeServer
) -> None:
    server.forced = httpx.Response(200, json=RESULTS)
    with pytest.raises(ProtocolError, match="Content-Location"):
        client.execute("alignment.rigid", wait=1, source=[[0]])


def test_location_may_be_absolute(client: Client, server: FakeServer) -> None:
    info = {"jobID": "abc", "processID": "alignment.rigid", "status": "accepted"}
    server.forced = httpx.Response(
        201, json=info, headers={"Location": "http://elsewhere/api/jobs/a%20b"}
    )
    assert client.execute("alignment.rigid", source=[[0]]).id == "a b"


# -- results -----------------------------------------------------------------------------


def test_results_convert_json_to_numpy(client: Client, server: FakeServer) -> None:
    job = client.execute("alignment.rigid", wait=1, source=[[0]])
    results = job.results()
    assert isinstance(results, Results)
    transform = results["transform"]
    assert isinstance(transform, np.ndarray)
    assert transform.dtype == np.float64 and transform.shape == (4, 4)
    assert results["labels"].dtype.kind == "i"
    np.testing.assert_array_equal(results["labels"], [0, 1, 1])
    assert results["rmse"] == 0.001 and isinstance(results["rmse"], float)
    assert results["converged"] is True
    assert results["iterations"] == 3
    assert results["loops"] == [[0, 1, 2], [3, 4]]  # ragged: stays a list
    assert results["names"] == ["a", "b"]
    assert results["method"] == "svd"
    assert results.raw == RESULTS
    assert set(results) == set(RESULTS) and len(results) == len(RESULTS)
    assert "transform=<float64 array (4, 4)>" in repr(results)


def test_results_are_read_only_and_name_the_outputs(client: Client) -> None:
    results = client.execute("alignment.rigid", wait=1, source=[[0]]).results()
    with pytest.raises(TypeError):
        results["rmse"] = 2  # type: ignore[index]
    with pytest.raises(KeyError, match="No output 'nope'; the outputs are: transform, rmse"):
        results["nope"]


def test_results_fetched_once(client: Client, server: FakeServer) -> None:
    server.script = [("successful", 100, None)]
    job = client.execute("alignment.rigid", source=[[0]])
    job.status()
    assert job.results() is job.results()
    assert len(server.requests_to("GET", r"/jobs/job-1/results")) == 1


# -- wait --------------------------------------------------------------------------------


def test_wait_polls_until_successful(client: Client, server: FakeServer) -> None:
    job = client.execute("alignment.rigid", source=[[0]])
    status = job.wait(poll_interval=0.001)
    assert status.status == "successful" and status.done
    assert status.progress == 100
    assert len(server.requests_to("GET", r"/jobs/job-1")) == 3
    assert job.results()["rmse"] == 0.001


def test_wait_raises_job_failed_with_the_problem_detail(client: Client, server: FakeServer) -> None:
    server.script = [("running", 10, None), ("failed", 100, "ICP diverged")]
    server.outcome = problem(500, "job-failed", "Matrix is singular at iteration 4.")
    job = client.execute("alignment.rigid", source=[[0]])
    with pytest.raises(JobFailed, match="Matrix is singular at iteration 4") as caught:
        job.wait(poll_interval=0.001)
    assert caught.value.type == "/problems/job-failed"
    assert caught.value.response is not None


def test_wait_raises_time_limit_exceeded_as_a_job_failure(
    client: Client, server: FakeServer
) -> None:
    server.script = [("failed", 30, "stopped")]
    server.outcome = problem(504, "time-limit-exceeded", "Ran longer than 600 s.")
    job = client.execute("alignment.rigid", source=[[0]])
    with pytest.raises(TimeLimitExceeded, match="600 s") as caught:
        job.wait()
    assert isinstance(caught.value, JobFailed)


def test_wait_on_failed_job_whose_results_answer_200(client: Client, server: FakeServer) -> None:
    server.script = [("failed", 30, "worker died twice")]
    server.outcome = httpx.Response(200, json={})
    job = client.execute("alignment.rigid", source=[[0]])
    with pytest.raises(JobFailed, match="worker died twice"):
        job.wait()


def test_wait_raises_job_dismissed(client: Client, server: FakeServer) -> None:
    job = client.execute("alignment.rigid", source=[[0]])
    job.dismiss()
    with pytest.raises(JobDismissed, match="was dismissed"):
        job.wait()


def test_wait_timeout(client: Client, server: FakeServer) -> None:
    server.script = [("running", 40, "slow")]
    job = client.execute("alignment.rigid", source=[[0]])
    with pytest.raises(WaitTimeout, match=r"did not end within 0.05 s \(last seen running, 40%\)"):
        job.wait(timeout=0.05, poll_interval=0.01)
    with pytest.raises(TimeoutError) as caught:
        job.wait(timeout=0)
    assert isinstance(caught.value, WaitTimeout)
    assert caught.value.job_id == "job-1"
    assert caught.value.status.progress == 40


def test_wait_rejects_a_bad_poll_interval(client: Client) -> None:
    job = client.execute("alignment.rigid", source=[[0]])
    with pytest.raises(ValueError, match="Expected `poll_interval` above 0 s, got 0"):
        job.wait(poll_interval=0)


class FakeClock:
    """A monotonic clock that moves ``step`` seconds each time it is read."""

    def __init__(self, step: float = 1.0) -> None:
        self.now = 0.0
        self.step = step

    def __call__(self) -> float:
        now = self.now
        self.now += self.step
        return now


def test_wait_draws_progress_with_elapsed_time_rate_and_eta(client: Client) -> None:
    stream = io.StringIO()  # not a terminal: a line at each tenth of the way
    bar = ProgressBar(stream, clock=FakeClock(1.0))
    client.execute("alignment.rigid", source=[[0]]).wait(progress=bar, poll_interval=0.001)
    # read at 0 s, 1 s, 2 s: 40 % after 1 s is 40 %/s, so 60 % more takes 1.5 s
    assert stream.getvalue().splitlines() == [
        "[------------------------------]   0% 00:00<? ?%/s accepted",
        "[############------------------]  40% 00:01<00:01 40.0%/s iteration 12 of 30",
        "[##############################] 100% 00:02<00:00 50.0%/s done",
    ]


def test_wait_progress_true_draws_on_stderr(
    client: Client, capsys: pytest.CaptureFixture[str]
) -> None:
    client.execute("alignment.rigid", source=[[0]]).wait(progress=True, poll_interval=0.001)
    lines = capsys.readouterr().err.splitlines()
    assert [re.sub(r"\d\d:\d\d<.*?/s ", "", line) for line in lines] == [
        "[------------------------------]   0% accepted",
        "[############------------------]  40% iteration 12 of 30",
        "[##############################] 100% done",
    ]


class FakeTerminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_progress_bar_redraws_in_place_on_a_terminal() -> None:
    stream = FakeTerminal()
    with ProgressBar(stream, width=10, clock=FakeClock(0.0)) as bar:
        bar.update(45, "long message here")
        bar.update(45, "long message here")  # unchanged: not drawn
        bar.update(100, "done")
    first = "[####------]  45% 00:00<? ?%/s long message here"
    last = "[##########] 100% 00:00<00:00 ?%/s done".ljust(len(first))  # blanks the rest
    assert stream.getvalue() == f"\r{first}\r{last}\n"


def test_progress_bar_clamps_and_closes_once() -> None:
    stream = FakeTerminal()
    bar = ProgressBar(stream, width=4)
    assert bar.render(None) == "[----]   0% 00:00<? ?%/s"
    assert bar.render(250, "x", elapsed=4) == "[####] 100% 00:04<00:00 25.0%/s x"
    bar.close()
    assert stream.getvalue() == ""  # nothing drawn, no newline


def test_wait_ends_the_progress_line_when_failing(client: Client, server: FakeServer) -> None:
    stream = FakeTerminal()
    server.script = [("failed", 50, "boom")]
    server.outcome = problem(500, "job-failed", "boom")
    with pytest.raises(JobFailed):
        client.execute("alignment.rigid", source=[[0]]).wait(progress=ProgressBar(stream))
    assert stream.getvalue().endswith("boom\n")


# -- jobs --------------------------------------------------------------------------------


def test_job_looks_up_status(client: Client, server: FakeServer) -> None:
    job_id = server.add_job()
    job = client.job(job_id)
    assert job.id == job_id and job.process_id == "alignment.rigid"
    assert job == client.job(job_id) and hash(job) == hash(client.job(job_id))
    assert repr(job) == "<Job job-1 of alignment.rigid>"
    with pytest.raises(NoSuchJob, match="No job 'nope'"):
        client.job("nope")


def test_status_parses_times_and_progress(client: Client, server: FakeServer) -> None:
    job = client.execute("alignment.rigid", source=[[0]])
    job.status()
    status = job.status()
    assert isinstance(status, JobStatus)
    assert (status.job_id, status.process_id, status.status) == (
        "job-1",
        "alignment.rigid",
        "running",
    )
    assert (status.progress, status.message, status.done) == (40, "iteration 12 of 30", False)
    assert status.created == datetime(2025, 1, 2, 3, 4, 5, 123456, tzinfo=UTC)
    assert status.updated == datetime(2025, 1, 2, 3, 4, 6, tzinfo=UTC)
    assert status.finished is None
    assert status.raw["links"][1]["rel"] == "results"


def test_status_with_a_bad_time_is_a_protocol_error(client: Client, server: FakeServer) -> None:
    server.forced = httpx.Response(200, json={"jobID": "x", "status": "running", "created": "soon"})
    with pytest.raises(
        ProtocolError, match="Expected `created` to be an ISO-8601 time, got 'soon'"
    ):
        client.job("x")
    server.forced = httpx.Response(200, json={"status": "running"})
    with pytest.raises(ProtocolError, match="Expected a job status to hold `jobID`"):
        client.job("x")


def test_dismiss(client: Client, server: FakeServer) -> None:
    job = client.execute("alignment.rigid", source=[[0]])
    status = job.dismiss()
    assert status.status == "dismissed" and status.done
    assert server.requests[-1].method == "DELETE"
    assert server.requests[-1].url.path == "/jobs/job-1"


def test_jobs_follows_next_links(client: Client, server: FakeServer) -> None:
    for _ in range(5):
        server.add_job()
    jobs = client.jobs()
    assert [j.job_id for j in jobs] == [f"job-{i}" for i in range(1, 6)]
    assert len(server.requests_to("GET", "/jobs")) == 3
    assert server.requests[0].url.params["limit"] == "100"


def test_jobs_follows_absolute_next_links(server: FakeServer) -> None:
    def absolute(request: httpx.Request) -> httpx.Response:
        response = server(request)
        if request.url.path != "/jobs":
            return response
        document = response.json()
        for link in document["links"]:
            link["href"] = "http://morph.test" + link["href"]
        return httpx.Response(response.status_code, json=document)

    for _ in range(5):
        server.add_job()
    with Client("http://morph.test", transport=httpx.MockTransport(absolute)) as client:
        assert [j.job_id for j in client.jobs()] == [f"job-{i}" for i in range(1, 6)]
    assert [r.url.params.get("offset") for r in server.requests_to("GET", "/jobs")] == \
        [None, "2", "4"]


def test_jobs_filters_and_limits(client: Client, server: FakeServer) -> None:
    for _ in range(5):
        server.add_job()
    server.jobs["job-2"]["step"] = 1  # running
    server.jobs["job-4"]["step"] = 1
    jobs = client.jobs(status=["running", "accepted"], process="alignment.rigid", limit=3)
    assert [j.job_id for j in jobs] == ["job-1", "job-2", "job-3"]
    first = server.requests[0].url.params
    assert first.get_list("status") == ["running", "accepted"]
    assert first["processID"] == "alignment.rigid" and first["limit"] == "3"
    running = client.jobs(status="running")
    assert [j.job_id for j in running] == ["job-2", "job-4"]


def test_jobs_stops_on_a_repeated_next_link() -> None:
    page = {
        "jobs": [{"jobID": "a", "status": "accepted"}],
        "links": [{"rel": "next", "href": "/jobs?p=2"}],
    }
    requests: list[httpx.Request] = []

    def loop(request: httpx.Request) -> httpx.Response:
        requests.append(request)
        return httpx.Response(200, json=page)

    with Client("http://morph.test", transport=httpx.MockTransport(loop)) as client:
        assert [j.job_id for j in client.jobs()] == ["a", "a"]
    assert [str(r.url) for r in requests] == [
        "http://morph.test/jobs?limit=100",
        "http://morph.test/jobs?p=2",
    ]


def test_jobs_rejects_bad_arguments(client: Client) -> None:
    with pytest.raises(ValueError, match="Expected `status` among accepted, running"):
        client.jobs(status="done")
    with pytest.raises(ValueError, match="Expected `limit` to be 1 or more, got 0"):
        client.jobs(limit=0)


# -- errors ------------------------------------------------------------------------------

SLUGS = [
    ("invalid-input", 422, InvalidInput),
    ("no-such-process", 404, NoSuchProcess),
    ("no-such-job", 404, NoSuchJob),
    ("no-such-output", 404, NoSuchOutput),
    ("result-not-ready", 404, ResultNotReady),
    ("job-failed", 500, JobFailed),
    ("job-dismissed", 410, JobDismissed),
    ("time-limit-exceeded", 504, TimeLimitExceeded),
    ("worker-lost", 500, WorkerLost),
    ("not-found", 404, NotFound),
    ("method-not-allowed", 405, MethodNotAllowed),
    ("malformed-body", 400, MalformedBody),
    ("payload-too-large", 413, PayloadTooLarge),
    ("unsupported-media-type", 415, UnsupportedMediaType),
    ("not-acceptable", 406, NotAcceptable),
    ("idempotency-conflict", 422, IdempotencyConflict),
    ("queue-full", 429, QueueFull),
    ("unauthorized", 401, Unauthorized),
    ("internal-error", 500, InternalError),
    ("service-unavailable", 503, ServiceUnavailable),
    ("insufficient-storage", 507, InsufficientStorage),
    ("bad-request", 400, BadRequest),
    ("request-timeout", 408, RequestTimeout),
    ("header-too-large", 431, HeaderTooLarge),
]


def test_every_problem_of_the_service_has_its_class() -> None:
    from service import problems
    assert {slug for slug, _, _ in SLUGS} == set(problems.PROBLEMS)
    for slug, status, cls in SLUGS:
        assert problems.PROBLEMS[slug].status == status, slug
        assert morphserve._exceptions.error_class(f"/problems/{slug}", status) is cls


@pytest.mark.parametrize(("slug", "status", "cls"), SLUGS, ids=[s for s, _, _ in SLUGS])
def test_each_problem_slug_raises_its_class(
    client: Client, server: FakeServer, slug: str, status: int, cls: type[APIError]
) -> None:
    server.forced = problem(status, slug, f"detail of {slug}", instance="/jobs/x")
    with pytest.raises(cls, match=f"detail of {slug}") as caught:
        client.processes()
    error = caught.value
    assert type(error) is cls
    assert isinstance(error, APIError) and isinstance(error, MorphserveError)
    assert (error.status, error.type, error.instance) == (status, f"/problems/{slug}", "/jobs/x")
    assert error.detail == f"detail of {slug}"
    assert error.errors == []
    assert error.response is not None and error.response.status_code == status


def test_problem_type_may_be_an_absolute_uri(client: Client, server: FakeServer) -> None:
    server.forced = httpx.Response(
        422, json={"type": "https://morph.test/problems/invalid-input/", "title": "Invalid"}
    )
    with pytest.raises(InvalidInput):
        client.processes()


@pytest.mark.parametrize(
    ("status", "cls"), [(418, APIError), (404, NotFound), (429, QueueFull), (502, APIError)]
)
def test_unknown_slug_falls_back_on_the_status(
    client: Client, server: FakeServer, status: int, cls: type[APIError]
) -> None:
    server.forced = problem(status, "brand-new-problem", "something new")
    with pytest.raises(APIError, match="something new") as caught:
        client.processes()
    assert type(caught.value) is cls


def test_error_page_that_is_not_a_problem(client: Client, server: FakeServer) -> None:
    server.forced = httpx.Response(502, text="<html>Bad gateway</html>")
    with pytest.raises(APIError, match=r"Bad Gateway \(502\): <html>Bad gateway</html>") as caught:
        client.processes()
    assert type(caught.value) is APIError
    assert caught.value.type == "about:blank"


def test_success_that_is_not_json_is_a_protocol_error(client: Client, server: FakeServer) -> None:
    server.forced = httpx.Response(200, text="<html>hello</html>")
    with pytest.raises(ProtocolError, match=r"Expected a JSON object from GET http://morph\.test/"):
        client.processes()
    server.forced = httpx.Response(200, json=[1, 2])
    with pytest.raises(ProtocolError, match=r"application/json: '\[1,2\]'"):
        client.processes()


def test_queue_full_retry_after(client: Client, server: FakeServer) -> None:
    server.forced = problem(429, "queue-full", "10000 jobs queued", headers={"Retry-After": "7"})
    with pytest.raises(QueueFull) as caught:
        client.execute("alignment.rigid", source=[[0]])
    assert caught.value.retry_after == 7.0
    later = format_datetime(datetime.now(UTC) + timedelta(seconds=120), usegmt=True)
    server.forced = problem(429, "queue-full", headers={"Retry-After": later})
    with pytest.raises(QueueFull) as caught:
        client.execute("alignment.rigid", source=[[0]])
    assert caught.value.retry_after is not None and 100 < caught.value.retry_after <= 120
    server.forced = problem(429, "queue-full")
    with pytest.raises(QueueFull) as caught:
        client.execute("alignment.rigid", source=[[0]])
    assert caught.value.retry_after is None


def test_insufficient_storage_says_what_was_free(client: Client, server: FakeServer) -> None:
    server.forced = problem(507, "insufficient-storage", "The data dir is full.",
                            headers={"Retry-After": "30"}, free_bytes=4096)
    with pytest.raises(InsufficientStorage) as caught:
        client.execute("alignment.rigid", source=[[0]])
    assert (caught.value.free_bytes, caught.value.retry_after) == (4096, 30.0)
    server.forced = problem(507, "insufficient-storage")
    with pytest.raises(InsufficientStorage) as caught:
        client.execute("alignment.rigid", source=[[0]])
    assert (caught.value.free_bytes, caught.value.retry_after) == (None, None)


def test_api_errors_pickle(client: Client, server: FakeServer) -> None:
    server.forced = problem(422, "invalid-input", "bad", errors=[{"input": "a", "message": "m"}])
    with pytest.raises(InvalidInput) as caught:
        client.processes()
    copy = pickle.loads(pickle.dumps(caught.value))
    assert type(copy) is InvalidInput
    assert (copy.status, copy.detail, copy.errors) == (422, "bad", [{"input": "a", "message": "m"}])
    timeout = pickle.loads(pickle.dumps(WaitTimeout("j", 1.0)))
    assert str(timeout) == "Job j did not end within 1 s."


def test_transport_errors_are_wrapped() -> None:
    def refuse(request: httpx.Request) -> httpx.Response:
        raise httpx.ConnectError("Connection refused", request=request)

    transport = httpx.MockTransport(refuse)
    with (
        Client("http://morph.test", transport=transport) as client,
        pytest.raises(TransportError, match="ConnectError: Connection refused") as caught,
    ):
        client.processes()
    assert isinstance(caught.value.__cause__, httpx.ConnectError)
    assert caught.value.request is not None and caught.value.request.url.path == "/processes"


def test_transport_error_during_wait_ends_the_progress_line(server: FakeServer) -> None:
    calls = 0

    def flaky(request: httpx.Request) -> httpx.Response:
        nonlocal calls
        calls += 1
        if calls == 3:
            raise httpx.ReadTimeout("timed out", request=request)
        return server(request)

    stream = FakeTerminal()
    with Client("http://morph.test", transport=httpx.MockTransport(flaky)) as client:
        job = client.execute("alignment.rigid", source=[[0]])
        with pytest.raises(TransportError, match="ReadTimeout"):
            job.wait(progress=ProgressBar(stream), poll_interval=0.001)
    assert stream.getvalue().endswith("accepted\n")


# -- configuration -----------------------------------------------------------------------


def test_api_key_from_the_environment(server: FakeServer, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("MORPHSERVE_API_KEY", "s3cret")
    with Client("http://morph.test", transport=httpx.MockTransport(server)) as client:
        client.processes()
    with Client("http://morph.test", api_key="other", transport=httpx.MockTransport(server)) as c:
        c.processes()
    monkeypatch.setenv("MORPHSERVE_API_KEY", "")
    with Client("http://morph.test", transport=httpx.MockTransport(server)) as client:
        client.processes()
    from_env, explicit, empty = server.requests
    assert from_env.headers["Authorization"] == "Bearer s3cret"
    assert explicit.headers["Authorization"] == "Bearer other"
    assert "Authorization" not in empty.headers
    assert from_env.headers["User-Agent"] == f"morphserve-python/{morphserve.__version__}"


def test_no_authorization_without_a_key(client: Client, server: FakeServer) -> None:
    client.processes()
    assert "Authorization" not in server.requests[0].headers


def test_base_url_with_a_path_prefix(server: FakeServer) -> None:
    seen: list[str] = []

    def prefixed(request: httpx.Request) -> httpx.Response:
        seen.append(request.url.path)
        return httpx.Response(200, json={"processes": [], "links": []})

    with Client("http://morph.test/api/", transport=httpx.MockTransport(prefixed)) as client:
        assert client.processes() == []
        assert repr(client) == "<Client http://morph.test/api/>"
    assert seen == ["/api/processes"]


def test_wait_timeout_extends_the_read_timeout(client: Client, server: FakeServer) -> None:
    client.execute("alignment.rigid", wait=60, source=[[0]])
    client.execute("alignment.rigid", source=[[0]])
    long, short = server.requests
    assert long.extensions["timeout"]["read"] == 70.0
    assert short.extensions["timeout"]["read"] == 30.0


def test_the_sdk_imports_neither_service_nor_algorithms() -> None:
    import subprocess
    import sys

    code = (
        "import sys, morphserve; "
        "bad = [m for m in sys.modules if m.split('.')[0] in ('service', 'algorithms')]; "
        "print(bad)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


def test_public_names() -> None:
    assert set(morphserve.__all__) <= set(dir(morphserve))
    assert re.fullmatch(r"\d+\.\d+\.\d+.*", morphserve.__version__)


class _PieceCounter(httpx.BaseTransport, httpx.AsyncBaseTransport):
    """Reads each request body piece by piece as httpx hands it to the connection, keeps
    the whole request in ``server.requests`` and answers that a job was accepted."""

    def __init__(self, server: FakeServer) -> None:
        self.server = server
        self.pieces: list[int] = []

    def _answer(self, request: httpx.Request, body: bytes) -> httpx.Response:
        assert len(body) == int(request.headers["Content-Length"])
        self.server.requests.append(httpx.Request(request.method, request.url,
                                                  headers=request.headers, content=body))
        job = self.server.add_job()
        return httpx.Response(201, json=self.server.status_info(job),
                              headers={"Location": f"/jobs/{job}"})

    def handle_request(self, request: httpx.Request) -> httpx.Response:
        pieces = [bytes(p) for p in request.stream]  # type: ignore[union-attr]
        self.pieces = [len(p) for p in pieces]
        return self._answer(request, b"".join(pieces))

    async def handle_async_request(self, request: httpx.Request) -> httpx.Response:
        pieces = [bytes(p) async for p in request.stream]  # type: ignore[union-attr]
        self.pieces = [len(p) for p in pieces]
        return self._answer(request, b"".join(pieces))


@pytest.mark.parametrize("kind", ["sync", "async"])
def test_large_bodies_reach_httpx_in_pieces(server: FakeServer, kind: str,
                                            monkeypatch: pytest.MonkeyPatch) -> None:
    """httpcore copies what is left of a piece after every send(): the SDK hands a large
    body over in pieces of at most PIECE_BYTES, the same bytes and Content-Length."""
    import asyncio

    from morphserve import AsyncClient
    from morphserve._client import PIECE_BYTES
    from morphserve._models import npy_bytes

    monkeypatch.delenv("MORPHSERVE_API_KEY", raising=False)
    X = np.random.default_rng(0).normal(size=(400_000, 3))  # 9.6 MB: an .npy part
    transport = _PieceCounter(server)
    if kind == "sync":
        with Client("http://morph.test", transport=transport) as client:
            client.execute("alignment.rigid", source=X, target=[[1.0, 2.0, 3.0]])
    else:
        async def main() -> None:
            async with AsyncClient("http://morph.test", transport=transport) as client:
                await client.execute("alignment.rigid", source=X, target=[[1.0, 2.0, 3.0]])

        asyncio.run(main())
    (request,) = server.requests
    assert request.headers["Content-Type"].startswith("multipart/form-data")
    assert npy_bytes(X) in request.content
    assert len(transport.pieces) > 9 and max(transport.pieces) <= PIECE_BYTES
