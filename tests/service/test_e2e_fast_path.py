"""No unbounded work in the API process (#17.3), and metrics that tell the truth (#17.11),
over HTTP against a live server of its own.

The fast path takes a job by its estimated cost, not its bytes: a small body of high
dimension, or a graph of many nodes, goes to the Dask workers (asserted through
``morphserve_job_runs_total``, the path each job was given, never through times). A fast
job runs in a worker process of the service's fast path, at most ``fast_path_seconds`` (past
that it goes on on the workers) and never past its time limit (its worker is killed: the
process is gone). Small jobs and ``/healthz`` are answered while a costly job runs: the
small job ends first (order of the store's recorded events).
"""

from __future__ import annotations

import base64
import time
import uuid
from collections.abc import Iterator
from typing import Any

import httpx
import numpy as np
import psutil
import pytest
from prometheus_client.parser import text_string_to_metric_families

from tests.live import LiveServer, execute, wait_for_status

pytestmark = pytest.mark.e2e

SMALL = {"source": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]],
         "target": [[1, 2, 3], [1, 3, 3], [0, 2, 3], [1, 2, 4]]}


@pytest.fixture(scope="module")
def srv(tmp_path_factory: pytest.TempPathFactory) -> Iterator[LiveServer]:
    server = LiveServer(tmp_path_factory.mktemp("fast") / "data", {
        "MORPHSERVE_FAST_PATH_SECONDS": "1", "MORPHSERVE_FAST_PATH_THREADS": "1"}).start()
    try:
        yield server
    finally:
        server.stop()


@pytest.fixture
def http(srv: LiveServer) -> Iterator[httpx.Client]:
    with srv.client() as client:
        yield client


def _scrape(http: httpx.Client) -> dict[str, list[Any]]:
    r = http.get("/metrics")
    assert r.status_code == 200
    return {f.name: f.samples for f in text_string_to_metric_families(r.text)}


def _value(fams: dict[str, list[Any]], family: str, **labels: str) -> float:
    return sum(s.value for s in fams.get(family, [])
               if all(s.labels.get(k) == v for k, v in labels.items())
               and not s.name.endswith("_created"))


def _runs(http: httpx.Client, process: str) -> dict[str, float]:
    fams = _scrape(http)
    return {path: _value(fams, "morphserve_job_runs", process=process, path=path)
            for path in ("fast", "workers")}


def _delta(after: dict[str, float], before: dict[str, float]) -> dict[str, float]:
    return {k: after[k] - before[k] for k in after}


def _binary(a: np.ndarray) -> dict[str, Any]:
    return {"dtype": a.dtype.str, "shape": list(a.shape),
            "data": base64.b64encode(np.ascontiguousarray(a).tobytes()).decode()}


def test_a_small_body_of_high_dimension_runs_on_the_workers(http: httpx.Client) -> None:
    """The issue's case: alignment.homography in d = 40 on 100 pairs, some 80 kB of JSON,
    once 10 s on the service's only fast-path thread with every small job behind it. The
    small rigid job sent after it ends before it, /healthz answers meanwhile."""
    d, n = 40, 100
    rng = np.random.default_rng(40)
    X = rng.normal(size=(n, d))
    P = np.eye(d + 1) + 0.01 * rng.normal(size=(d + 1, d + 1))
    P /= P[d, d]
    H = np.c_[X, np.ones(n)] @ P.T
    Y = H[:, :d] / H[:, d:]
    before = _runs(http, "alignment.homography")
    r = execute(http, "alignment.homography", {"source": X.tolist(), "target": Y.tolist()},
                prefer="respond-async")
    assert r.status_code == 201, r.text
    big = r.json()["jobID"]
    assert http.get("/healthz").json() == {"status": "ok"}
    small = execute(http, "alignment.rigid", SMALL, prefer="wait=60")
    assert small.status_code == 200, small.text
    small_job = http.get(small.headers["content-location"].removesuffix("/results")).json()
    done = wait_for_status(http, big, timeout=300)
    assert done["status"] == "successful", done
    assert small_job["finished"] < done["finished"]  # not queued behind the big one
    assert _delta(_runs(http, "alignment.homography"), before) == {"fast": 0, "workers": 1}
    found = np.array(http.get(f"/jobs/{big}/results/transform").json())
    np.testing.assert_allclose(found, P, atol=1e-6)


def test_a_graph_of_many_nodes_runs_on_the_workers(http: httpx.Client) -> None:
    """A path of 200,000 nodes, its edges as a typed binary array: 1.6 MB, small enough
    for the fast path by bytes, not by cost. Pinned at both ends, every node of a path
    lies where the springs balance: evenly spaced on the segment between the pins."""
    n = 200_000
    i = np.arange(n - 1, dtype=np.int32)
    edges = np.stack([i, i + 1], axis=1)
    before = _runs(http, "layout.laplacian")
    r = execute(http, "layout.laplacian", {
        "graph": {"nodes": n, "edges": _binary(edges)},
        "pins": {"indices": [0, n - 1], "positions": [[0.0, 0.0], [1.0, 0.0]]}},
        prefer="wait=300")
    assert r.status_code == 200, r.text[:500]
    assert _delta(_runs(http, "layout.laplacian"), before) == {"fast": 0, "workers": 1}
    positions = np.array(r.json()["positions"])
    np.testing.assert_allclose(positions[:, 0], np.arange(n) / (n - 1), atol=1e-6)
    np.testing.assert_allclose(positions[:, 1], 0.0, atol=1e-9)


def test_a_small_job_runs_on_the_fast_path(http: httpx.Client) -> None:
    before = _runs(http, "alignment.rigid")
    assert execute(http, "alignment.rigid", SMALL).status_code == 200
    assert _delta(_runs(http, "alignment.rigid"), before) == {"fast": 1, "workers": 0}


def test_a_fast_job_past_the_budget_goes_on_on_the_workers(http: httpx.Client) -> None:
    """diagnostics.nap looks cheap (no arrays) and sleeps 3 s: the fast path gives it up
    after its 1 s and the workers run it whole."""
    before = _runs(http, "diagnostics.nap")
    r = execute(http, "diagnostics.nap", {"seconds": 3, "steps": 30}, prefer="wait=120")
    assert r.status_code == 200, r.text
    assert r.json()["slept"] >= 3.0 and r.json()["steps"] == 30  # all of it, once more
    assert _delta(_runs(http, "diagnostics.nap"), before) == {"fast": 1, "workers": 1}


def _fast_workers(srv: LiveServer) -> set[int]:
    """The pids of the fast path's worker processes: the children of the service's
    forkserver."""
    assert srv.proc is not None
    service = psutil.Process(srv.proc.pid)
    servers = [p for p in service.children() if "forkserver" in " ".join(p.cmdline())]
    assert len(servers) == 1, [p.cmdline() for p in service.children()]
    return {p.pid for p in servers[0].children() if p.status() != psutil.STATUS_ZOMBIE}


def test_a_fast_job_past_its_time_limit_stops_using_the_cpu(http: httpx.Client,
                                                            srv: LiveServer) -> None:
    """One step: the nap cannot notice its limit; its worker is killed when the job is
    failed, and a new one takes its place."""
    assert execute(http, "diagnostics.nap", {"seconds": 0, "steps": 1}).status_code == 200
    workers = _fast_workers(srv)
    assert len(workers) == 1
    r = execute(http, "diagnostics.nap", {"seconds": 600, "steps": 1}, prefer="wait=60",
                timeLimit=0.5)
    assert r.status_code == 504, r.text
    assert r.json()["type"] == "/problems/time-limit-exceeded"
    assert "time limit of 0.5 s exceeded" in r.json()["detail"]
    (pid,) = workers
    assert not psutil.pid_exists(pid) or psutil.Process(pid).status() == psutil.STATUS_ZOMBIE
    assert execute(http, "diagnostics.nap", {"seconds": 0, "steps": 1}).status_code == 200
    assert len(_fast_workers(srv)) == 1 and _fast_workers(srv) != workers


def test_a_dismissed_fast_job_counts_as_dismissed(http: httpx.Client) -> None:
    fams = _scrape(http)
    label = {"process": "diagnostics.nap"}
    before = {s: _value(fams, "morphserve_jobs_finished", **label, status=s)
              for s in ("successful", "dismissed")}
    r = execute(http, "diagnostics.nap", {"seconds": 0.5, "steps": 50},
                prefer="respond-async")
    job = r.json()["jobID"]
    wait_for_status(http, job, ("running",))
    assert http.delete(f"/jobs/{job}").json()["status"] == "dismissed"
    assert wait_for_status(http, job)["status"] == "dismissed"
    fams = _scrape(http)
    after = {s: _value(fams, "morphserve_jobs_finished", **label, status=s)
             for s in ("successful", "dismissed")}
    assert after["dismissed"] - before["dismissed"] == 1
    assert after["successful"] == before["successful"]


def test_queued_and_running_gauges_agree_with_the_store(http: httpx.Client) -> None:
    """Both workers busy with a long job, a third one queued: the gauges say what /jobs
    says."""
    body = {"inputs": {"seconds": 120, "steps": 1200}}
    jobs = [http.post("/processes/diagnostics.sleep/execution", json=body,
                      headers={"Prefer": "respond-async"}).json()["jobID"] for _ in range(3)]
    try:
        for _ in range(600):  # until two run (the third one waits for a worker)
            states = [http.get(f"/jobs/{j}").json()["status"] for j in jobs]
            if sorted(states) == ["accepted", "running", "running"]:
                break
            time.sleep(0.1)
        assert sorted(states) == ["accepted", "running", "running"], states
        fams = _scrape(http)
        listed = {s: http.get("/jobs", params={"status": s}).json()["numberMatched"]
                  for s in ("accepted", "running")}
        assert _value(fams, "morphserve_jobs_queued") == listed["accepted"] >= 1
        assert _value(fams, "morphserve_jobs_running") == listed["running"] >= 2
        assert _value(fams, "morphserve_queue_length") == sum(listed.values())
    finally:
        for j in jobs:
            http.delete(f"/jobs/{j}")


def test_http_responses_are_counted_by_route_and_status_class(http: httpx.Client) -> None:
    """Needs the app to mount service.metrics.HttpMetrics (service/app.py)."""
    fams = _scrape(http)
    route = {"method": "GET", "route": "/jobs/{jobId}"}
    before = {c: _value(fams, "morphserve_http_responses", **route, status=c)
              for c in ("2xx", "4xx")}
    missing = http.get(f"/jobs/{uuid.uuid4()}")
    assert missing.status_code == 404
    r = execute(http, "alignment.rigid", SMALL)
    job = r.headers["content-location"].removesuffix("/results")
    assert http.get(job).status_code == 200
    assert http.post("/processes/alignment.rigid/execution", content=b"{",
                     headers={"Content-Type": "application/json"}).status_code == 400
    fams = _scrape(http)
    after = {c: _value(fams, "morphserve_http_responses", **route, status=c)
             for c in ("2xx", "4xx")}
    assert _delta(after, before) == {"2xx": 1, "4xx": 1}
    execute_route = {"method": "POST", "route": "/processes/{processId}/execution"}
    assert _value(fams, "morphserve_http_responses", **execute_route, status="4xx") >= 1
    assert not [s for s in fams["morphserve_http_responses"]
                if s.labels["route"].startswith("/jobs/") and "{" not in s.labels["route"]]
