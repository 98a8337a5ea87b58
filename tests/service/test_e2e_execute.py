"""Execution over HTTP against a live server (uvicorn + embedded Dask cluster)."""

from __future__ import annotations

import subprocess
import time

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from tests.live import wait_for_status

pytestmark = pytest.mark.e2e

SOURCE = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]
TARGET = [[1, 2, 3], [1, 3, 3], [0, 2, 3], [1, 2, 4]]
# Hand computation: TARGET - (1, 2, 3) sends e1 -> e2, e2 -> -e1, e3 -> e3: 90° about z.
R_Z90 = np.array([[0, -1, 0], [1, 0, 0], [0, 0, 1]], float)
T = np.array([1, 2, 3], float)


def test_acceptance_curl(server) -> None:
    """The issue's acceptance command, verbatim, through curl."""
    out = subprocess.run(
        ["curl", "-s", "-i", "-X", "POST",
         f"{server.url}/processes/alignment.rigid/execution", "-H", "Prefer: wait=10",
         "-H", "Content-Type: application/json", "-d",
         '{"inputs":{"source":[[0,0,0],[1,0,0],[0,1,0],[0,0,1]],'
         '"target":[[1,2,3],[1,3,3],[0,2,3],[1,2,4]]}}'],
        capture_output=True, text=True, timeout=30, check=True).stdout
    head, _, body = out.replace("\r\n", "\n").partition("\n\n")
    assert head.startswith("HTTP/1.1 200"), head
    assert "preference-applied: wait=10" in head.lower()
    import json

    doc = json.loads(body)
    M = np.array(doc["transform"])
    assert M.shape == (4, 4)
    np.testing.assert_allclose(M[:3, :3], R_Z90, atol=1e-12)
    np.testing.assert_allclose(M[:3, 3], T, atol=1e-12)
    np.testing.assert_allclose(M[3], [0, 0, 0, 1])
    np.testing.assert_allclose(doc["rotation"], R_Z90, atol=1e-12)
    np.testing.assert_allclose(doc["translation"], T, atol=1e-12)
    assert doc["rmse"] < 1e-12


def _random_pair(seed: int, n: int = 1000):  # noqa: ANN202
    rng = np.random.default_rng(seed)
    X = rng.normal(size=(n, 3))
    R = Rotation.random(random_state=seed).as_matrix()
    t = rng.normal(size=3)
    return X, X @ R.T + t, R, t


def test_async_submit_and_poll(http) -> None:
    X, Y, R, t = _random_pair(1)
    r = http.post("/processes/alignment.rigid/execution", headers={"Prefer": "respond-async"},
                  json={"inputs": {"source": X.tolist(), "target": Y.tolist()}})
    assert r.status_code == 201, r.text
    assert r.headers["preference-applied"] == "respond-async"
    info = r.json()
    assert r.headers["location"] == f"{str(http.base_url).rstrip('/')}/jobs/{info['jobID']}"
    assert info["status"] in ("accepted", "running", "successful")
    assert info["processID"] == "alignment.rigid" and info["type"] == "process"
    done = wait_for_status(http, info["jobID"])
    assert done["status"] == "successful" and done["progress"] == 100
    assert done["created"] <= done["started"] <= done["finished"]
    assert any(link["rel"] == "results" for link in done["links"])
    res = http.get(f"/jobs/{info['jobID']}/results").json()
    np.testing.assert_allclose(res["rotation"], R, atol=1e-10)
    np.testing.assert_allclose(res["translation"], t, atol=1e-10)


def test_wait_returns_results_when_fast_enough(http) -> None:
    X, Y, R, _ = _random_pair(2)
    r = http.post("/processes/alignment.rigid/execution", headers={"Prefer": "wait=30"},
                  json={"inputs": {"source": X.tolist(), "target": Y.tolist()}})
    assert r.status_code == 200 and r.headers["preference-applied"] == "wait=30"
    job_path = r.headers["content-location"]
    assert job_path.endswith("/results")
    np.testing.assert_allclose(r.json()["rotation"], R, atol=1e-10)
    # the sync job is recorded like any other
    assert http.get(job_path.removesuffix("/results")).json()["status"] == "successful"


def test_waited_fast_job_is_recorded_whole(http) -> None:
    """A fast-path job the client waits for runs before its row is written, then is stored
    with its inputs and outcome at once: the job, its times and results read back."""
    X, Y, R, _ = _random_pair(4, n=50)
    before = time.time()
    r = http.post("/processes/alignment.rigid/execution", headers={"Prefer": "wait=30"},
                  json={"inputs": {"source": X.tolist(), "target": Y.tolist()}})
    assert r.status_code == 200, r.text
    job = http.get(r.headers["content-location"].removesuffix("/results")).json()
    assert job["status"] == "successful" and job["progress"] == 100
    created, started, finished = (job[k] for k in ("created", "started", "finished"))
    assert before - 1 <= _epoch(created) <= _epoch(started) <= _epoch(finished) <= time.time() + 1
    again = http.get(r.headers["content-location"]).json()
    np.testing.assert_array_equal(again["rotation"], r.json()["rotation"])
    np.testing.assert_allclose(again["rotation"], R, atol=1e-10)


def test_fast_job_outlasting_the_wait_is_dismissable(http) -> None:
    """A fast-path job still running when the wait ends (recorded then, answered 201) is
    dismissed like any other job: it ends dismissed, not run to its end."""
    r = http.post("/processes/diagnostics.nap/execution", headers={"Prefer": "wait=0.2"},
                  json={"inputs": {"seconds": 20.0, "steps": 200}})
    assert r.status_code == 201, r.text
    job_id = r.json()["jobID"]
    assert http.delete(f"/jobs/{job_id}").json()["status"] == "dismissed"
    info = wait_for_status(http, job_id)
    assert info["status"] == "dismissed" and info["progress"] < 100
    assert http.get(f"/jobs/{job_id}/results").status_code == 410


def _epoch(stamp: str) -> float:
    from datetime import datetime

    return datetime.fromisoformat(stamp.replace("Z", "+00:00")).timestamp()


@pytest.mark.parametrize("process", ["diagnostics.sleep", "diagnostics.nap"])  # Dask, fast
def test_wait_expiring_answers_async(http, process: str) -> None:
    """A job still running when the wait ends is answered 201, recorded, and finishes
    after that answer; on the fast path too, where it ran before its row was written."""
    r = http.post(f"/processes/{process}/execution", headers={"Prefer": "wait=0.5"},
                  json={"inputs": {"seconds": 2, "steps": 20}})
    answered = time.time()
    assert r.status_code == 201, r.text
    assert r.headers["preference-applied"] == "respond-async"
    job_id = r.json()["jobID"]
    assert r.json()["status"] in ("accepted", "running")
    assert http.get(f"/jobs/{job_id}").json()["status"] in ("accepted", "running")
    done = wait_for_status(http, job_id)
    assert done["status"] == "successful" and _epoch(done["finished"]) > answered
    assert http.get(f"/jobs/{job_id}/results").json()["slept"] >= 2.0


def test_respond_sync_waits_for_a_long_process(http) -> None:
    r = http.post("/processes/diagnostics.sleep/execution", headers={"Prefer": "respond-sync"},
                  json={"inputs": {"seconds": 0.5, "steps": 5}})
    assert r.status_code == 200 and r.headers["preference-applied"] == "respond-sync"
    assert r.json()["slept"] >= 0.5 and r.json()["steps"] == 5


def test_no_preference_long_is_async_short_is_sync(http) -> None:
    r = http.post("/processes/diagnostics.sleep/execution",
                  json={"inputs": {"seconds": 0.2, "steps": 2}})
    assert r.status_code == 201 and "preference-applied" not in r.headers
    r = http.post("/processes/alignment.rigid/execution",
                  json={"inputs": {"source": SOURCE, "target": TARGET}})
    assert r.status_code == 200 and "preference-applied" not in r.headers


def test_outputs_subset_and_raw(http) -> None:
    body = {"inputs": {"source": SOURCE, "target": TARGET}, "outputs": {"rmse": {}, "rotation": {}}}
    doc = http.post("/processes/alignment.rigid/execution", json=body).json()
    assert set(doc) == {"rmse", "rotation"}
    body = {"inputs": {"source": SOURCE, "target": TARGET}, "outputs": {"translation": {}},
            "response": "raw"}
    raw = http.post("/processes/alignment.rigid/execution", json=body).json()
    np.testing.assert_allclose(raw, T, atol=1e-12)


def test_qualified_value_inputs(http) -> None:
    doc = http.post("/processes/alignment.rigid/execution",
                    json={"inputs": {"source": {"value": SOURCE}, "target": TARGET,
                                     "allow_reflection": {"value": False}}}).json()
    np.testing.assert_allclose(doc["rotation"], R_Z90, atol=1e-12)


def test_nearest_over_http(http) -> None:
    src = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.1]]
    tgt = [[0.1, 0.0], [2.0, 0.0]]
    doc = http.post("/processes/assignment.nearest/execution",
                    json={"inputs": {"source": src, "target": tgt}}).json()
    # hand: 0 -> 0 (0.1), 1 -> 0 (0.9), 2 -> 1 (0.1)
    assert doc["pairs"] == [[0, 0], [1, 0], [2, 1]]
    np.testing.assert_allclose(doc["distances"], [0.1, 0.9, 0.1], atol=1e-12)


def test_dask_path_gives_the_same_answer(server) -> None:
    """A job too big for the fast path runs on a worker; same results as in-process."""
    X, Y, R, t = _random_pair(3, n=200_000)
    with server.client() as http:
        r = http.post("/processes/alignment.rigid/execution", headers={"Prefer": "wait=60"},
                      json={"inputs": {"source": X.tolist(), "target": Y.tolist()}})
    assert r.status_code == 200, r.text
    np.testing.assert_allclose(r.json()["rotation"], R, atol=1e-10)
    np.testing.assert_allclose(r.json()["translation"], t, atol=1e-10)


def test_idempotency_key(http) -> None:
    import uuid

    key = f"key-{uuid.uuid4()}"
    body = {"inputs": {"source": SOURCE, "target": TARGET}}
    h = {"Idempotency-Key": key, "Prefer": "respond-async"}
    a = http.post("/processes/alignment.rigid/execution", headers=h, json=body)
    b = http.post("/processes/alignment.rigid/execution", headers=h, json=body)
    assert (a.status_code, b.status_code) == (201, 201), (a.text, b.text)
    assert b.headers["location"] == a.headers["location"]
    first = a.json()["jobID"]
    # a retry that waits gets the first job's results (the first may still be queued behind
    # earlier tests' jobs on a busy machine: 10 s was once too short)
    w = http.post("/processes/alignment.rigid/execution",
                  headers={"Idempotency-Key": key, "Prefer": "wait=60"}, json=body)
    assert w.status_code == 200 and w.headers["content-location"] == f"/jobs/{first}/results"
    np.testing.assert_allclose(w.json()["rotation"], R_Z90, atol=1e-12)
    c = http.post("/processes/alignment.rigid/execution", headers=h,
                  json={"inputs": {"source": SOURCE, "target": SOURCE}})
    assert c.status_code == 422
    assert c.json()["type"] == "/problems/idempotency-conflict"
    assert c.json()["errors"][0]["input"] == "Idempotency-Key"
    assert first in c.json()["detail"]


def test_callbacks(http) -> None:
    """successUri is POSTed the results; inProgressUri the running statusInfo."""
    import json
    import threading
    from http.server import BaseHTTPRequestHandler, HTTPServer

    received: list[tuple[str, dict]] = []

    class Handler(BaseHTTPRequestHandler):
        def do_POST(self) -> None:  # noqa: N802
            n = int(self.headers["Content-Length"])
            received.append((self.path, json.loads(self.rfile.read(n))))
            self.send_response(204)
            self.end_headers()

        def log_message(self, *args: object) -> None:
            pass

    hook = HTTPServer(("127.0.0.1", 0), Handler)
    threading.Thread(target=hook.serve_forever, daemon=True).start()
    base = f"http://127.0.0.1:{hook.server_port}"
    try:
        r = http.post("/processes/alignment.rigid/execution", headers={"Prefer": "respond-async"},
                      json={"inputs": {"source": SOURCE, "target": TARGET},
                            "subscriber": {"successUri": base + "/ok",
                                           "inProgressUri": base + "/running"}})
        assert r.status_code == 201
        deadline = time.monotonic() + 10
        while len(received) < 2 and time.monotonic() < deadline:
            time.sleep(0.05)
        paths = dict(received)
        assert paths["/running"]["jobID"] == r.json()["jobID"]
        np.testing.assert_allclose(paths["/ok"]["rotation"], R_Z90, atol=1e-12)
    finally:
        hook.shutdown()


def test_wait_beyond_the_limit_is_cut_and_says_so(http, server) -> None:
    r = http.post("/processes/alignment.rigid/execution", headers={"Prefer": "wait=100000"},
                  json={"inputs": {"source": SOURCE, "target": TARGET}})
    assert r.status_code == 200
    assert r.headers["preference-applied"] == "wait=600"  # the default max_wait
