"""Nothing accepted is lost: kill -9 mid-run and restart; an external Dask scheduler."""

from __future__ import annotations

import os
import sqlite3
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from tests.live import REPO, LiveServer, free_port, wait_for_status

pytestmark = [pytest.mark.e2e, pytest.mark.slow]


def _rigid_case(seed: int, n: int = 2000):  # noqa: ANN202
    rng = np.random.default_rng(seed)
    X = rng.normal(size=(n, 3))
    R = Rotation.random(random_state=seed).as_matrix()
    t = rng.normal(size=3)
    return X, X @ R.T + t, R, t


def _submit_mix(http, count: int) -> dict[str, tuple]:  # noqa: ANN001
    """Two families and a sleeper: every fourth job sleeps (keeps workers busy), every
    fourth from the second is a nearest-neighbour assignment, the others rigid alignments."""
    expected = {}
    for i in range(count):
        if i % 4 == 0:
            body = {"inputs": {"seconds": 0.5, "steps": 10}}
            r = http.post("/processes/diagnostics.sleep/execution", json=body,
                          headers={"Prefer": "respond-async"})
            expected[r.json()["jobID"]] = ("sleep",)
        elif i % 4 == 1:
            rng = np.random.default_rng(i)
            X = rng.normal(size=(500, 3))
            perm = rng.permutation(500)
            r = http.post("/processes/assignment.nearest/execution",
                          json={"inputs": {"source": X.tolist(), "target": X[perm].tolist()}},
                          headers={"Prefer": "respond-async"})
            # target row t is source row perm[t]: source s is paired with t = argsort(perm)[s]
            expected[r.json()["jobID"]] = ("nearest", np.argsort(perm))
        else:
            X, Y, R, t = _rigid_case(i)
            r = http.post("/processes/alignment.rigid/execution",
                          json={"inputs": {"source": X.tolist(), "target": Y.tolist()}},
                          headers={"Prefer": "respond-async"})
            expected[r.json()["jobID"]] = ("rigid", R, t)
        assert r.status_code == 201, r.text
    return expected


def _check_results(http, expected: dict[str, tuple], timeout: float) -> None:  # noqa: ANN001
    for job_id, case in expected.items():
        info = wait_for_status(http, job_id, timeout=timeout)
        assert info["status"] == "successful", info
        res = http.get(f"/jobs/{job_id}/results").json()
        if case[0] == "sleep":
            assert res["steps"] == 10 and res["slept"] >= 0.5
        elif case[0] == "nearest":
            pairs = np.asarray(res["pairs"])
            np.testing.assert_array_equal(pairs[:, 0], np.arange(500))
            np.testing.assert_array_equal(pairs[:, 1], case[1])
            assert res["rmse"] == 0.0
        else:
            np.testing.assert_allclose(res["rotation"], case[1], atol=1e-10)
            np.testing.assert_allclose(res["translation"], case[2], atol=1e-10)


def _epoch(stamp: str) -> float:
    from datetime import datetime

    return datetime.fromisoformat(stamp.replace("Z", "+00:00")).timestamp()


def _group_gone(pgid: int, timeout: float = 10.0) -> bool:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        try:
            os.killpg(pgid, 0)
        except ProcessLookupError:
            return True
        time.sleep(0.1)
    return False


#: Jobs accepted before the kill (issue 9: 200 across two families).
JOBS = 200


def test_kill_9_then_restart_loses_nothing(tmp_path: Path) -> None:
    data = tmp_path / "data"
    # everything through Dask, so that jobs are queued and running when the kill comes
    env = {"MORPHSERVE_FAST_PATH_BYTES": "0"}
    srv = LiveServer(data, env).start()
    try:
        with srv.client() as http:
            expected = _submit_mix(http, JOBS)
        pgid = srv.proc.pid
        srv.kill()  # SIGKILL to the service and its Dask workers at once
        assert _group_gone(pgid), "workers survived the kill"
        with sqlite3.connect(data / "jobs.sqlite3") as db:
            counts = dict(db.execute("SELECT status, COUNT(*) FROM jobs GROUP BY status"))
        assert sum(counts.values()) == JOBS
        assert counts.get("accepted", 0) + counts.get("running", 0) > 0, counts

        srv = LiveServer(data, env, port=srv.port).start()
        with srv.client() as http:
            _check_results(http, expected, timeout=180)
            listed = http.get("/jobs", params={"limit": 1000}).json()
        assert listed["numberMatched"] == JOBS
    finally:
        srv.stop()


@pytest.fixture
def external_cluster(tmp_path: Path):  # noqa: ANN201
    """`dask scheduler` and two `dask worker` processes on loopback."""
    port = free_port()
    address = f"tcp://127.0.0.1:{port}"
    dask = str(Path(sys.executable).with_name("dask"))
    log = open(tmp_path / "cluster.log", "wb")  # noqa: SIM115
    procs = [subprocess.Popen([dask, "scheduler", "--host", "127.0.0.1", "--port", str(port),
                               "--no-dashboard"], cwd=REPO, stdout=log, stderr=log,
                              start_new_session=True)]
    time.sleep(1.0)
    for i in range(2):
        procs.append(subprocess.Popen([dask, "worker", address, "--nthreads", "1", "--name",
                                       f"ext-{i}", "--no-dashboard"], cwd=REPO, stdout=log,
                                      stderr=log, start_new_session=True))
    yield address, tmp_path / "cluster.log"
    for p in reversed(procs):
        try:
            os.killpg(p.pid, 9)
        except ProcessLookupError:
            pass
        p.wait(timeout=30)
    log.close()


def test_external_scheduler_runs_jobs(tmp_path: Path, external_cluster) -> None:
    address, _ = external_cluster
    data = tmp_path / "data"
    srv = LiveServer(data, {"MORPHSERVE_SCHEDULER": address,
                            "MORPHSERVE_FAST_PATH_BYTES": "0"}).start()
    try:
        with srv.client() as http:
            assert http.get("/readyz").json()["workers"] == 2
            expected = _submit_mix(http, 8)
            _check_results(http, expected, timeout=60)
            # workers persisted the outputs themselves (fire-and-forget tasks)
            rigid = [j for j, case in expected.items() if case[0] == "rigid"]
            assert all((data / "results" / f"{j}.pkl").exists() for j in rigid)
            # dismissal reaches running tasks on external workers: both workers busy with a
            # minute's sleep, both dismissed, then the probes run on the freed workers long
            # before either sleep would have ended (order of the recorded events)
            sleepers = [http.post("/processes/diagnostics.sleep/execution",
                                  json={"inputs": {"seconds": 60, "steps": 6000}},
                                  headers={"Prefer": "respond-async"}).json()["jobID"]
                        for _ in range(2)]
            started = [wait_for_status(http, job, ("running",), timeout=30)["started"]
                       for job in sleepers]
            for job in sleepers:
                assert http.delete(f"/jobs/{job}").json()["status"] == "dismissed"
            probes = [http.post("/processes/diagnostics.sleep/execution",
                                json={"inputs": {"seconds": 0.1, "steps": 1}},
                                headers={"Prefer": "respond-async"}).json()["jobID"]
                      for _ in range(2)]
            for p in probes:
                info = wait_for_status(http, p, timeout=60)
                assert info["status"] == "successful", info
                assert _epoch(info["finished"]) < min(map(_epoch, started)) + 60
    finally:
        srv.stop()


def test_restart_with_external_scheduler_keeps_running_work(tmp_path: Path,
                                                          external_cluster) -> None:
    """The API dies; fire-and-forget tasks finish on the workers and the new API finds their
    outputs (or resubmits what has none)."""
    address, _ = external_cluster
    data = tmp_path / "data"
    env = {"MORPHSERVE_SCHEDULER": address, "MORPHSERVE_FAST_PATH_BYTES": "0"}
    srv = LiveServer(data, env).start()
    with srv.client() as http:
        expected = _submit_mix(http, 12)
    srv.kill()  # the API only: the external cluster keeps going
    srv = LiveServer(data, env, port=srv.port).start()
    try:
        with srv.client() as http:
            _check_results(http, expected, timeout=60)
    finally:
        srv.stop()
