"""The ``morphserve`` command line: parsing, files in, output and exit statuses.

The client commands run against canned answers: ``service.cli.connect`` (the seam the commands
get their SDK client from) is replaced by one built on an ``httpx.MockTransport``.
"""

from __future__ import annotations

import json
import re
import sys
import types
from collections.abc import Callable
from pathlib import Path
from typing import Any

import httpx
import numpy as np
import pytest

from morphserve import Client
from service import cli

STAMP = "2025-01-02T03:04:05+00:00"


def info(status: str = "accepted", progress: int = 0, message: str | None = None) -> dict:
    return {
        "jobID": "job-1",
        "processID": "alignment.rigid",
        "type": "process",
        "status": status,
        "message": message,
        "created": STAMP,
        "started": None,
        "finished": None,
        "updated": STAMP,
        "progress": progress,
        "links": [{"rel": "results", "href": "/jobs/job-1/results"}],
    }


def ok(body: Any, status: int = 200, **headers: str) -> httpx.Response:
    return httpx.Response(status, json=body, headers=headers)


def problem(status: int, slug: str, title: str, detail: str, **extra: Any) -> httpx.Response:
    body = {"type": f"/problems/{slug}", "title": title, "status": status, "detail": detail}
    return httpx.Response(status, json={**body, **extra})


PROCESS = {"id": "alignment.rigid", "title": "Rigid alignment", "version": "1.0.0"}
DESCRIPTION = {
    **PROCESS,
    "description": "Rotation and translation mapping source onto target.",
    "inputs": {
        "source": {
            "title": "Source points",
            "schema": {"type": "array", "items": {"type": "array", "items": {"type": "number"}}},
            "minOccurs": 1,
        },
        "allow_reflection": {
            "title": "Allow reflection",
            "schema": {"type": "boolean", "default": False},
            "minOccurs": 0,
        },
        "weights": {"schema": {"anyOf": [{"type": "array"}, {"type": "null"}]}, "minOccurs": 0},
    },
    "outputs": {"transform": {"title": "Transform", "schema": {"type": "array"}}},
}
RESULTS = {"transform": [[1.0, 0.0], [0.0, 1.0]], "rmse": 0.25}


def routes() -> dict[str, list[httpx.Response]]:
    """The answers of a service with one job that goes accepted → running → successful."""
    return {
        "GET /processes": [ok({"processes": [PROCESS], "links": []})],
        "GET /processes/alignment.rigid": [ok(DESCRIPTION)],
        "POST /processes/alignment.rigid/execution": [ok(info(), 201, Location="/jobs/job-1")],
        "GET /jobs/job-1": [
            ok(info()),
            ok(info("running", 50, "halfway")),
            ok(info("successful", 100, "done")),
        ],
        "GET /jobs/job-1/results": [ok(RESULTS)],
        "DELETE /jobs/job-1": [ok(info("dismissed", 50))],
        "GET /jobs": [ok({"jobs": [info("running", 50, "halfway")], "links": []})],
    }


class Canned:
    """Answers ``METHOD /path`` with the next of its responses (the last one repeats)."""

    def __init__(self, routes: dict[str, list[httpx.Response]]) -> None:
        self.routes = routes
        self.requests: list[httpx.Request] = []
        self.urls: list[str] = []  # the --url of each command

    def __call__(self, request: httpx.Request) -> httpx.Response:
        self.requests.append(request)
        answers = self.routes.get(f"{request.method} {request.url.path}")
        if not answers:
            return problem(404, "not-found", "Not found", request.url.path)
        return answers.pop(0) if len(answers) > 1 else answers[0]


@pytest.fixture
def service(monkeypatch: pytest.MonkeyPatch) -> Canned:
    """The canned service every client command of this test talks to."""
    canned = Canned(routes())

    def connect(url: str) -> Client:
        canned.urls.append(url)
        return Client(url, api_key="", transport=httpx.MockTransport(canned))

    monkeypatch.setattr(cli, "connect", connect)
    return canned


Run = Callable[..., tuple[int, str, str]]


@pytest.fixture
def run(capsys: pytest.CaptureFixture[str]) -> Run:
    """``run(*argv)`` → (exit status, stdout, stderr)."""

    def run(*argv: str) -> tuple[int, str, str]:
        code = cli.main(list(argv))
        out, err = capsys.readouterr()
        return code, out, err

    return run


# -- parser ------------------------------------------------------------------------------


def test_parser_reads_serve_and_worker_options() -> None:
    parser = cli.build_parser()
    serve = parser.parse_args(
        ["serve", "--host", "0.0.0.0", "--port", "9000", "--scheduler", "tcp://s:8786"]
    )
    assert (serve.command, serve.host, serve.port, serve.scheduler) == (
        "serve",
        "0.0.0.0",
        9000,
        "tcp://s:8786",
    )
    assert serve.data_dir is None and serve.workers is None
    worker = parser.parse_args(
        ["worker", "--scheduler", "tcp://s:8786", "--nworkers", "2", "--memory-limit", "3GiB"]
    )
    assert (worker.scheduler, worker.nworkers, worker.memory_limit) == ("tcp://s:8786", 2, "3GiB")


def test_parser_defaults_come_from_the_environment(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("HOST", "0.0.0.0")
    monkeypatch.setenv("PORT", "8123")
    monkeypatch.setenv("MORPHSERVE_URL", "http://api:8000")
    args = cli.build_parser().parse_args(["serve"])
    assert (args.host, args.port, args.url) == ("0.0.0.0", 8123, "http://api:8000")
    for name in ("HOST", "PORT", "MORPHSERVE_URL"):
        monkeypatch.delenv(name)
    args = cli.build_parser().parse_args(["serve"])
    assert (args.host, args.port, args.url) == ("127.0.0.1", 8000, "http://127.0.0.1:8000")


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        ([], "the following arguments are required: COMMAND"),
        (["serve", "--port", "http"], "argument --port: expected a whole number"),
        (["serve", "--port", "70000"], "expected a port up to 65535"),
        (["serve", "--workers", "0"], "argument --workers: expected a whole number of 1 or more"),
        (["execute"], "the following arguments are required: ID"),
        (["execute", "p", "--param", "novalue"], "expected NAME=VALUE, got 'novalue'"),
        (["execute", "p", "--wait", "--timeout", "-1"], "expected seconds, 0 or more"),
        (["jobs", "--status", "done"], "argument --status: invalid choice: 'done'"),
        (["jobs", "--limit", "0"], "argument --limit"),
        (["frobnicate"], "invalid choice: 'frobnicate'"),
    ],
)
def test_usage_errors_exit_2(run: Run, argv: list[str], message: str) -> None:
    code, out, err = run(*argv)
    assert code == 2
    assert message in err
    assert out == ""


def test_help_and_version_exit_0(run: Run) -> None:
    code, out, _ = run("--version")
    assert code == 0 and out.startswith("morphserve ")
    code, out, _ = run("execute", "--help")
    assert code == 0 and "--input NAME=FILE" in out


# -- files and parameters ----------------------------------------------------------------


def test_parse_input_reads_json_and_npy(tmp_path: Path) -> None:
    (tmp_path / "a.json").write_text("[[0, 1], [2, 3.5]]")
    np.save(tmp_path / "b.npy", np.arange(6, dtype=np.int32).reshape(3, 2))
    name, value = cli.parse_input(f"source={tmp_path / 'a.json'}")
    assert (name, value) == ("source", [[0, 1], [2, 3.5]])
    name, value = cli.parse_input(f"target={tmp_path / 'b.npy'}")
    assert name == "target"
    assert value.dtype == np.int32 and value.shape == (3, 2)
    (tmp_path / "c.JSON").write_text('"text"')
    assert cli.parse_input(f"x={tmp_path / 'c.JSON'}") == ("x", "text")


def test_parse_input_rejects_what_it_cannot_read(tmp_path: Path) -> None:
    (tmp_path / "bad.json").write_text("[1, 2")
    np.save(tmp_path / "objects.npy", np.array([{"a": 1}], dtype=object))
    (tmp_path / "points.txt").write_text("1 2 3")
    (tmp_path / "scan.PLY").write_bytes(b"ply")
    assert cli.parse_input(f"mesh={tmp_path / 'scan.PLY'}") == ("mesh", tmp_path / "scan.PLY")
    cases = [
        ("source", "expected NAME=FILE, got 'source'"),
        ("=a.json", "expected NAME=FILE"),
        (f"source={tmp_path / 'points.txt'}", "expected a .json, .npy, .ply, .obj, .stl, .off, "
         ".glb file for input 'source'"),
        (f"source={tmp_path / 'missing.npy'}", "cannot read"),
        (f"source={tmp_path / 'missing.ply'}", "no such file"),
        (f"source={tmp_path / 'bad.json'}", "cannot read"),
        (f"source={tmp_path / 'objects.npy'}", "cannot read"),
    ]
    for text, message in cases:
        with pytest.raises(cli.argparse.ArgumentTypeError, match=message.replace(".", r"\.")):
            cli.parse_input(text)


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("k=3", ("k", 3)),
        ("k=2.5", ("k", 2.5)),
        ("k=true", ("k", True)),
        ("k=null", ("k", None)),
        ("k=[1, 2]", ("k", [1, 2])),
        ('k={"a": 1}', ("k", {"a": 1})),
        ('k="3"', ("k", "3")),
        ("k=svd", ("k", "svd")),
        ("k=NaN", ("k", "NaN")),
        ("k=", ("k", "")),
        ("k=a=b", ("k", "a=b")),
    ],
)
def test_parse_param(text: str, expected: tuple[str, Any]) -> None:
    assert cli.parse_param(text) == expected


# -- serve and worker --------------------------------------------------------------------


def test_serve_passes_the_options_to_the_server(
    run: Run, monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    calls: list[dict[str, Any]] = []
    fake = types.ModuleType("service.server")
    fake.run = lambda **kwargs: calls.append(kwargs)  # type: ignore[attr-defined]
    monkeypatch.setitem(sys.modules, "service.server", fake)
    monkeypatch.delenv("HOST", raising=False)
    monkeypatch.delenv("PORT", raising=False)
    assert run("serve")[0] == 0
    assert run("serve", "--port", "9000", "--data-dir", str(tmp_path), "--workers", "3")[0] == 0
    assert calls == [
        {"host": "127.0.0.1", "port": 8000, "data_dir": None, "scheduler": None, "workers": None},
        {"host": "127.0.0.1", "port": 9000, "data_dir": tmp_path, "scheduler": None, "workers": 3},
    ]


def test_worker_argv_runs_one_thread_per_process(monkeypatch: pytest.MonkeyPatch) -> None:
    argv = cli.worker_argv("tcp://s:8786", nworkers=4, memory_limit="4GiB", name="w")
    assert argv == [
        sys.executable,
        "-m",
        "distributed.cli.dask_worker",
        "tcp://s:8786",
        "--nthreads",
        "1",
        "--nworkers",
        "4",
        "--memory-limit",
        "4GiB",
        "--name",
        "w",
    ]
    monkeypatch.setattr(cli, "_cpu_count", lambda: 6)
    assert cli.worker_argv("tcp://s:8786")[4:] == ["--nthreads", "1", "--nworkers", "6"]


def test_worker_replaces_itself_with_dask_worker(run: Run, monkeypatch: pytest.MonkeyPatch) -> None:
    execs: list[tuple[str, list[str]]] = []
    monkeypatch.setattr(cli.os, "execv", lambda path, argv: execs.append((path, argv)))
    monkeypatch.setenv("MORPHSERVE_SCHEDULER", "tcp://env:8786")
    assert run("worker", "--nworkers", "2")[0] == 0
    assert run("worker", "--scheduler", "tcp://flag:8786", "--nworkers", "2")[0] == 0
    (path, first), (_, second) = execs
    assert path == sys.executable == first[0]
    assert first[3] == "tcp://env:8786" and second[3] == "tcp://flag:8786"


def test_worker_without_a_scheduler_is_a_usage_error(
    run: Run, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.delenv("MORPHSERVE_SCHEDULER", raising=False)
    monkeypatch.setattr(cli.os, "execv", lambda *a: pytest.fail("must not exec"))
    code, _, err = run("worker")
    assert code == 2
    assert "error: worker needs --scheduler tcp://HOST:8786 or MORPHSERVE_SCHEDULER" in err


# -- client commands ---------------------------------------------------------------------


def test_processes_prints_a_table(run: Run, service: Canned) -> None:
    code, out, _ = run("processes")
    assert code == 0
    assert out.splitlines() == ["ID               TITLE", "alignment.rigid  Rigid alignment"]


def test_describe_prints_inputs_and_outputs(run: Run, service: Canned) -> None:
    code, out, _ = run("describe", "alignment.rigid")
    assert code == 0
    lines = out.splitlines()
    assert lines[0] == "alignment.rigid: Rigid alignment (version 1.0.0)"
    assert lines[1] == "Rotation and translation mapping source onto target."
    assert "inputs:" in lines and "outputs:" in lines
    rows = {line.split()[0]: line.split(None, 3)[1:] for line in lines if line.startswith("  ")}
    assert rows["source"] == ["array[array[number]]", "required", "Source points"]
    assert rows["allow_reflection"] == ["boolean", "default", "false  Allow reflection"]
    assert rows["weights"] == ["array|null", "optional"]
    assert rows["transform"] == ["array", "Transform"]


def test_execute_prints_the_job_id(run: Run, service: Canned, tmp_path: Path) -> None:
    np.save(tmp_path / "a.npy", np.array([[0.0, 1.0], [2.0, 3.0]]))
    (tmp_path / "b.json").write_text("[[1, 1], [2, 2]]")
    code, out, err = run(
        "execute",
        "alignment.rigid",
        "--input",
        f"source={tmp_path / 'a.npy'}",
        "--input",
        f"target={tmp_path / 'b.json'}",
        "--param",
        "allow_reflection=true",
        "--param",
        "method=svd",
    )
    assert (code, out, err) == (0, "job-1\n", "")
    # a string input may name a file: the SDK reads the process description to tell
    (request,) = [r for r in service.requests if r.method == "POST"]
    assert request.headers["Prefer"] == "respond-async"
    assert json.loads(request.content)["inputs"] == {
        "source": [[0.0, 1.0], [2.0, 3.0]],
        "target": [[1, 1], [2, 2]],
        "allow_reflection": True,
        "method": "svd",
    }


def test_execute_wait_prints_results_and_progress(run: Run, service: Canned) -> None:
    code, out, err = run("execute", "alignment.rigid", "--param", "source=[[0]]", "--wait")
    assert code == 0
    assert json.loads(out) == RESULTS
    # the bar, then the elapsed time, rate and time left (which vary), then the message
    bars = [re.fullmatch(r"(\[[#-]{30}\] +\d+%) .*? (\w+)", line) for line in err.splitlines()]
    assert [(m[1], m[2]) if m else line for m, line in zip(bars, err.splitlines())] == [
        ("[------------------------------]   0%", "accepted"),
        ("[###############---------------]  50%", "halfway"),
        ("[##############################] 100%", "done"),
    ]


def test_execute_wait_writes_the_output_file(run: Run, service: Canned, tmp_path: Path) -> None:
    target = tmp_path / "out.json"
    code, out, err = run(
        "execute", "alignment.rigid", "--wait", "--no-progress", "--output", str(target)
    )
    assert (code, out) == (0, "")
    assert err == f"results written to {target}\n"
    assert json.loads(target.read_text()) == RESULTS


def test_execute_wait_timeout(run: Run, service: Canned) -> None:
    service.routes["GET /jobs/job-1"] = [ok(info("running", 50, "halfway"))]
    code, out, err = run("execute", "alignment.rigid", "--wait", "--timeout", "0", "--no-progress")
    assert (code, out) == (7, "")  # timeout
    assert err == ("error: Job job-1 did not end within 0 s (last seen running, 50%). It goes "
                   "on: 'morphserve status job-1' follows it, 'morphserve dismiss job-1' "
                   "stops it.\n")


def test_execute_wait_on_a_failed_job(run: Run, service: Canned) -> None:
    service.routes["GET /jobs/job-1"] = [ok(info("failed", 100, "diverged"))]
    service.routes["GET /jobs/job-1/results"] = [
        problem(500, "job-failed", "Job failed", "Matrix is singular at iteration 4.")
    ]
    code, out, err = run("execute", "alignment.rigid", "--wait", "--no-progress")
    assert (code, out) == (6, "")  # the job failed
    assert err == "error: Job failed: Matrix is singular at iteration 4.\n"


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--timeout", "3"], "--timeout and --output need --wait"),
        (["--output", "x.json"], "--timeout and --output need --wait"),
        (["--param", "a=1", "--param", "a=2"], "input 'a' given twice"),
    ],
)
def test_execute_usage_errors(run: Run, service: Canned, argv: list[str], message: str) -> None:
    code, _, err = run("execute", "alignment.rigid", *argv)
    assert code == 2
    assert f"morphserve: error: execute: {message}" in err
    assert service.requests == []


def test_api_errors_print_title_detail_and_fields(run: Run, service: Canned) -> None:
    errors = [
        {"input": "source", "message": "Expected (n, 3) points, got (4, 2)."},
        {"input": "target", "message": "Expected finite numbers."},
    ]
    service.routes["POST /processes/alignment.rigid/execution"] = [
        problem(422, "invalid-input", "Invalid input", "2 inputs are invalid.", errors=errors)
    ]
    code, out, err = run("execute", "alignment.rigid", "--param", "source=[[1, 2]]")
    assert (code, out) == (3, "")  # invalid input
    assert err.splitlines() == [
        "error: Invalid input: 2 inputs are invalid.",
        "  source: Expected (n, 3) points, got (4, 2).",
        "  target: Expected finite numbers.",
    ]


def test_unknown_job(run: Run, service: Canned) -> None:
    service.routes["GET /jobs/nope"] = [problem(404, "no-such-job", "No such job", "No job nope.")]
    code, _, err = run("status", "nope")
    assert code == 4  # not found
    assert err == "error: No such job: No job nope.\n"


def test_unreachable_service(run: Run, monkeypatch: pytest.MonkeyPatch) -> None:
    def refuse(request: httpx.Request) -> httpx.Response:
        raise httpx.ConnectError("Connection refused", request=request)

    monkeypatch.setattr(
        cli, "connect", lambda url: Client(url, transport=httpx.MockTransport(refuse))
    )
    code, _, err = run("--url", "http://nowhere:1", "processes")
    assert code == 5  # unreachable
    assert err.startswith("error: cannot reach http://nowhere:1: ConnectError: Connection refused")


def test_url_option_before_or_after_the_command(
    run: Run, service: Canned, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.delenv("MORPHSERVE_URL", raising=False)
    run("--url", "http://a:1", "processes")
    run("processes", "--url", "http://b:2")
    run("processes")
    assert service.urls == ["http://a:1", "http://b:2", "http://127.0.0.1:8000"]


def test_jobs_prints_a_table_and_filters(run: Run, service: Canned) -> None:
    code, out, _ = run(
        "jobs", "--status", "running", "--status", "accepted", "--process", "alignment.rigid"
    )
    assert code == 0
    header, row = out.splitlines()
    assert header.split() == ["JOB", "PROCESS", "STATUS", "PROGRESS", "CREATED", "MESSAGE"]
    assert row.split() == ["job-1", "alignment.rigid", "running", "50%", STAMP, "halfway"]
    params = service.requests[0].url.params
    assert params.get_list("status") == ["running", "accepted"]
    assert params["processID"] == "alignment.rigid"


def test_status_prints_the_fields(run: Run, service: Canned) -> None:
    service.routes["GET /jobs/job-1"] = [ok(info("running", 50, "halfway"))]
    code, out, _ = run("status", "job-1")
    assert code == 0
    lines = out.splitlines()
    assert lines[:5] == [
        "job      job-1",
        "process  alignment.rigid",
        "status   running",
        "progress 50%",
        "message  halfway",
    ]
    assert "created  2025-01-02T03:04:05+00:00" in lines  # as `jobs` prints it
    assert "started" in lines


def test_results_prints_or_writes_json(run: Run, service: Canned, tmp_path: Path) -> None:
    code, out, _ = run("results", "job-1")
    assert code == 0 and json.loads(out) == RESULTS
    code, out, _ = run("results", "job-1", "--output", str(tmp_path / "r.json"))
    assert code == 0 and out == ""
    assert json.loads((tmp_path / "r.json").read_text()) == RESULTS
    code, _, err = run("results", "job-1", "--output", str(tmp_path / "no" / "r.json"))
    assert code == 1 and err.startswith(f"error: cannot write {tmp_path / 'no' / 'r.json'}")


def test_output_in_a_mesh_format_writes_the_geometry(run: Run, service: Canned,
                                                      tmp_path: Path) -> None:
    """``--output`` of .ply, .obj, .stl or .off writes the result's mesh as the SDK's
    ``Results.save`` does (not the JSON document under a mesh file's name); results with no
    mesh or points are a usage error naming the way out."""
    import trimesh

    mesh = {"vertices": [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0]],
            "faces": [[0, 1, 2], [1, 3, 2]]}
    service.routes["GET /jobs/job-1/results"] = [ok({"mesh": mesh, "rmse": 0.0})]
    for suffix in (".ply", ".obj", ".stl", ".off"):
        target = tmp_path / f"out{suffix}"
        code, _, err = run("results", "job-1", "--output", str(target))
        assert code == 0, err
        back = trimesh.load(target, process=False)
        assert len(back.faces) == 2, suffix
    code, _, err = run("execute", "alignment.rigid", "--param", "source=[[0]]", "--wait",
                       "--no-progress", "--output", str(tmp_path / "moved.ply"))
    assert code == 0 and len(trimesh.load(tmp_path / "moved.ply", process=False).faces) == 2
    service.routes["GET /jobs/job-1/results"] = [ok(RESULTS)]
    code, _, err = run("results", "job-1", "--output", str(tmp_path / "none.ply"))
    assert code == 2 and "These results hold no mesh or points" in err
    assert "(--output FILE.json writes them all)" in err and not (tmp_path / "none.ply").exists()


def test_dismiss(run: Run, service: Canned) -> None:
    code, out, _ = run("dismiss", "job-1")
    assert (code, out) == (0, "job-1 dismissed\n")
    assert service.requests[-1].method == "DELETE"


# -- scripts: --json and the exit statuses ----------------------------------------------


def test_json_of_processes_and_describe(run: Run, service: Canned) -> None:
    code, out, _ = run("processes", "--json")
    assert code == 0
    assert json.loads(out) == [{"id": "alignment.rigid", "title": "Rigid alignment",
                                "description": "", "version": "1.0.0",
                                "jobControlOptions": []}]
    code, out, _ = run("describe", "alignment.rigid", "--json")
    assert code == 0 and json.loads(out) == DESCRIPTION  # the document, as the service sent it


def test_json_of_jobs_and_status(run: Run, service: Canned) -> None:
    code, out, _ = run("jobs", "--json")
    assert code == 0 and json.loads(out) == [info("running", 50, "halfway")]
    service.routes["GET /jobs/job-1"] = [ok(info("running", 50, "halfway"))]
    code, out, _ = run("status", "job-1", "--json")
    assert code == 0 and json.loads(out) == info("running", 50, "halfway")


def test_json_of_execute(run: Run, service: Canned, tmp_path: Path) -> None:
    code, out, _ = run("execute", "alignment.rigid", "--param", "source=[[0]]", "--json")
    assert code == 0 and json.loads(out) == info()  # the status the service answered
    code, out, _ = run("execute", "alignment.rigid", "--param", "source=[[0]]", "--wait",
                       "--no-progress", "--json")
    assert code == 0
    assert json.loads(out) == {"jobID": "job-1", "processID": "alignment.rigid",
                               "status": "successful", "results": RESULTS}
    target = tmp_path / "r.json"
    code, out, _ = run("execute", "alignment.rigid", "--param", "source=[[0]]", "--wait",
                       "--no-progress", "--json", "--output", str(target))
    assert code == 0 and json.loads(out)["output"] == str(target)
    assert json.loads(target.read_text()) == RESULTS


def test_execute_sends_the_time_limit(run: Run, service: Canned) -> None:
    code, _, _ = run("execute", "alignment.rigid", "--param", "source=[[0]]",
                     "--time-limit", "2.5")
    assert code == 0
    (request,) = [r for r in service.requests if r.method == "POST"]
    assert json.loads(request.content)["timeLimit"] == 2.5


@pytest.mark.parametrize(("slug", "status", "code"), [
    ("invalid-input", 422, 3),
    ("no-such-process", 404, 4),
    ("not-found", 404, 4),
    ("queue-full", 429, 1),
    ("unauthorized", 401, 1),
    ("service-unavailable", 503, 5),
    ("internal-error", 500, 1),
])
def test_each_refusal_has_its_exit_status(run: Run, service: Canned, slug: str, status: int,
                                          code: int) -> None:
    service.routes["POST /processes/alignment.rigid/execution"] = [
        problem(status, slug, slug.replace("-", " ").capitalize(), "Refused.")]
    got, out, err = run("execute", "alignment.rigid", "--param", "source=[[0]]")
    assert (got, out) == (code, "")
    assert err.startswith("error: ")


@pytest.mark.parametrize(("final", "slug", "status"), [
    ("failed", "job-failed", 500),
    ("failed", "time-limit-exceeded", 500),
    ("dismissed", "job-dismissed", 410),
])
def test_a_job_that_did_not_succeed_exits_6(run: Run, service: Canned, final: str, slug: str,
                                            status: int) -> None:
    service.routes["GET /jobs/job-1"] = [ok(info(final, 100, "stopped"))]
    service.routes["GET /jobs/job-1/results"] = [problem(status, slug, "Stopped", "It stopped.")]
    code, out, err = run("execute", "alignment.rigid", "--wait", "--no-progress")
    assert (code, out) == (6, "")
    assert err == "error: Stopped: It stopped.\n"


def test_results_not_ready_is_not_a_missing_job(run: Run, service: Canned) -> None:
    service.routes["GET /jobs/job-1/results"] = [
        problem(404, "result-not-ready", "Result not ready", "The job is running.")]
    code, _, err = run("results", "job-1")
    assert code == 1 and "Result not ready" in err
    assert "job.result()" not in err  # the SDK's hint is for Python callers, not the shell


def test_the_exit_statuses_are_documented() -> None:
    """Each status is distinct, and listed in ``morphserve --help`` and the README's CLI
    section with the same meaning."""
    codes = [int(e) for e in cli.Exit]
    assert len(set(codes)) == len(codes)
    epilog = cli.build_parser().format_help().split("exit status:", 1)[1]
    readme = (Path(__file__).resolve().parents[2] / "README.md").read_text(encoding="utf-8")
    for code in cli.Exit:
        assert re.search(rf"^  {int(code)} +\S", epilog, flags=re.M), code
        assert re.search(rf"^\| {int(code)} \| .+ \|$", readme, flags=re.M), code


def test_execute_takes_every_file_the_sdk_takes(tmp_path: Path) -> None:
    """Every file suffix the SDK uploads (``morphserve._geometry.FILE_SUFFIXES``) is an
    input file of ``morphserve execute`` too: geometry files go to the SDK as paths, .npy
    files as their arrays."""
    from morphserve._geometry import FILE_SUFFIXES

    for suffix in sorted(FILE_SUFFIXES):
        path = tmp_path / f"x{suffix}"
        if suffix == ".npy":
            np.save(path, np.eye(3))
        else:
            path.write_bytes(b"")
        name, value = cli.parse_input(f"mesh={path}")
        assert name == "mesh"
        if suffix == ".npy":
            np.testing.assert_array_equal(value, np.eye(3))
        else:
            assert value == path
