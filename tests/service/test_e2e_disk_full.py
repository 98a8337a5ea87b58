"""A full disk is an answer, not a crash (issue 17, class 4): a real server whose data dir is
a 30 MB tmpfs, filled until it refuses a single byte.

While the disk is full: every way of submitting a job (a fast job the client waits for, an
asynchronous one, a body large enough to be spooled) answers 507 problem+json
``insufficient-storage``; jobs and results still read; ``/readyz`` says not ready and how
much room is left; ``/healthz`` answers; a job that ends meanwhile reads as ended, its
outcome held in memory. Once room returns the held outcome is on disk, ``/readyz`` is ready
again and submissions are accepted. The job that ends on the full disk is frozen
(``SIGSTOP`` of its worker, whose pid its progress names) while the disk is filled, so it
ends after the disk is full, whatever the machine's speed.
"""

from __future__ import annotations

import os
import re
import signal
import sqlite3
import time
from collections.abc import Iterator
from pathlib import Path

import httpx
import pytest

from tests.live import LiveServer, wait_for_status
from tests.small_disk import fill, free_bytes, small_disk

pytestmark = [pytest.mark.e2e, pytest.mark.slow]

SQ = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
SHIFT = [1.0, 2.0, 3.0]
MOVED = [[x + s for x, s in zip(p, SHIFT, strict=True)] for p in SQ]
"""``SQ`` translated by ``SHIFT``: the rigid fit is the identity rotation and ``SHIFT``."""


@pytest.fixture
def full_disk_server(tmp_path: Path) -> Iterator[tuple[LiveServer, Path]]:
    with small_disk(tmp_path / "disk") as disk:
        # bodies of 1000 bytes and more are spooled: the spooled path is refused too
        srv = LiveServer(disk, {"MORPHSERVE_SPOOL_BYTES": "1000"}).start()
        try:
            yield srv, disk
        finally:
            srv.stop()


def _rigid(http: httpx.Client, prefer: str) -> httpx.Response:
    return http.post("/processes/alignment.rigid/execution", headers={"Prefer": prefer},
                     json={"inputs": {"source": SQ, "target": MOVED}})


def _row_status(disk: Path, job_id: str) -> str:
    """The job's status as it is on disk (a connection of the test's own)."""
    db = sqlite3.connect(f"file:{disk / 'jobs.sqlite3'}?mode=ro", uri=True)
    try:
        ((status,),) = db.execute("SELECT status FROM jobs WHERE id = ?", (job_id,))
        return str(status)
    finally:
        db.close()


def _insufficient_storage(r: httpx.Response) -> dict:
    assert r.status_code == 507, r.text
    assert r.headers["content-type"] == "application/problem+json"
    problem = r.json()
    assert problem["type"].endswith("insufficient-storage") and problem["status"] == 507
    assert "data dir is full" in problem["detail"]
    return problem


def test_a_full_disk_refuses_new_jobs_keeps_reads_and_holds_outcomes(
        full_disk_server: tuple[LiveServer, Path]) -> None:
    server, disk = full_disk_server
    with server.client(timeout=30) as http:
        ready = http.get("/readyz").json()
        assert ready["status"] == "ready" and ready["held"] == 0
        assert ready["reserve_bytes"] == int(30 * 2**20 * 0.05)
        assert ready["reserve_bytes"] < ready["free_bytes"] <= 30 * 2**20

        done = _rigid(http, "respond-async")  # a job that ends before the disk fills
        assert done.status_code == 201, done.text
        done_id = done.json()["jobID"]
        assert wait_for_status(http, done_id)["status"] == "successful"

        r = http.post("/processes/diagnostics.sleep/execution",
                      headers={"Prefer": "respond-async"},
                      json={"inputs": {"seconds": 6, "steps": 60}})
        assert r.status_code == 201, r.text
        sleeper = r.json()["jobID"]
        deadline = time.monotonic() + 60
        while "pid" not in (info := http.get(f"/jobs/{sleeper}").json()).get("message", ""):
            assert info["status"] in ("accepted", "running"), info
            assert time.monotonic() < deadline, info
            time.sleep(0.02)
        worker = int(re.search(r"in pid (\d+)", info["message"]).group(1))

        os.kill(worker, signal.SIGSTOP)  # the sleeper cannot end until the disk is full
        try:
            filler = fill(disk)
            assert free_bytes(disk) == 0
            logged = server.log.stat().st_size

            # -- every way in is refused with 507 ------------------------------------------
            for r in (_rigid(http, "wait=10"),  # fast path, run then recorded
                      _rigid(http, "respond-async"),  # recorded accepted
                      http.post("/processes/diagnostics.sleep/execution",  # spooled body
                                headers={"Prefer": "respond-async"},
                                json={"inputs": {"seconds": 0.1}, "pad": "x" * 4000})):
                assert _insufficient_storage(r)["free_bytes"] == 0
                assert http.get("/healthz").json() == {"status": "ok"}
            # -- reads go on ------------------------------------------------------------------
            assert http.get(f"/jobs/{done_id}").json()["status"] == "successful"
            fit = http.get(f"/jobs/{done_id}/results").json()
            assert fit["translation"] == pytest.approx(SHIFT, abs=1e-12)
            listed = http.get("/jobs", params={"limit": 100}).json()
            assert {done_id, sleeper} <= {j["jobID"] for j in listed["jobs"]}
            # -- not ready, and says why ------------------------------------------------------
            r = http.get("/readyz")
            assert r.status_code == 503 and r.json()["free_bytes"] == 0
            assert r.json()["type"].endswith("service-unavailable")
            assert "bytes free" in r.json()["detail"]
            # -- DELETE: done where SQLite finds room, else refused and nothing changed ------
            r = http.delete(f"/jobs/{done_id}")
            if r.status_code == 507:
                _insufficient_storage(r)
                assert http.get(f"/jobs/{done_id}").json()["status"] == "successful"
            else:
                assert r.status_code == 200, r.text
                assert http.get(f"/jobs/{done_id}").status_code == 404
        finally:
            os.kill(worker, signal.SIGCONT)

        # -- the sleeper ends on the full disk: read as ended, held, not yet on disk -------
        assert wait_for_status(http, sleeper)["status"] == "successful"
        assert http.get(f"/jobs/{sleeper}/results").json()["steps"] == 60
        r = http.get("/readyz")
        assert r.status_code == 503 and r.json()["held"] == 1 and r.json()["free_bytes"] == 0
        assert _row_status(disk, sleeper) == "running"
        assert http.get("/healthz").json() == {"status": "ok"}

        # -- room again -------------------------------------------------------------------
        filler.unlink()
        deadline = time.monotonic() + 30
        while (r := http.get("/readyz")).status_code != 200:
            assert time.monotonic() < deadline, r.text
            time.sleep(0.1)
        assert r.json()["held"] == 0 and r.json()["free_bytes"] > r.json()["reserve_bytes"]
        assert _row_status(disk, sleeper) == "successful"  # the held outcome, written
        result = http.get(f"/jobs/{sleeper}/results").json()
        assert result["steps"] == 60 and result["slept"] >= 6.0
        again = _rigid(http, "wait=30")
        assert again.status_code == 200, again.text
        assert again.json()["translation"] == pytest.approx(SHIFT, abs=1e-12)
        r = http.delete(f"/jobs/{done_id}")
        assert r.status_code in (200, 404)  # 404: deleted while the disk was full
        assert http.get(f"/jobs/{done_id}").status_code == 404

    with open(server.log, "rb") as log:  # a full disk is no traceback in the log
        log.seek(logged)
        text = log.read()
        assert b"Traceback" not in text, server.tail()
        assert b"data dir is full" in text  # but it is logged
