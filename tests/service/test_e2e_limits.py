"""Limits of a server configured small: the queue length (429 + Retry-After), a family's
time limit."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.live import LiveServer, wait_for_status

pytestmark = pytest.mark.e2e


def test_queue_full_is_429_with_retry_after(tmp_path: Path) -> None:
    srv = LiveServer(tmp_path / "data", {"MORPHSERVE_MAX_QUEUE": "2",
                                         "MORPHSERVE_FAMILY_TIME_LIMITS":
                                         '{"diagnostics": 1.5}'}).start()
    try:
        with srv.client() as http:
            body = {"inputs": {"seconds": 30, "steps": 300}}
            jobs = [http.post("/processes/diagnostics.sleep/execution", json=body).json()["jobID"]
                    for _ in range(2)]
            r = http.post("/processes/diagnostics.sleep/execution", json=body)
            assert r.status_code == 429, r.text
            assert r.headers["content-type"] == "application/problem+json"
            assert r.json()["type"] == "/problems/queue-full"
            assert int(r.headers["retry-after"]) > 0
            http.delete(f"/jobs/{jobs[0]}")
            r = http.post("/processes/diagnostics.sleep/execution",
                          json={"inputs": {"seconds": 0, "steps": 1}})
            assert r.status_code == 201
            assert wait_for_status(http, r.json()["jobID"])["status"] == "successful"
            http.delete(f"/jobs/{jobs[1]}")

            # the family's time limit (1.5 s) replaces the service's 600 s; a request may
            # lower it but not raise it
            for extra in ({}, {"timeLimit": 100}):
                r = http.post("/processes/diagnostics.sleep/execution",
                              json={"inputs": {"seconds": 30, "steps": 3000}, **extra},
                              headers={"Prefer": "respond-async"})
                info = wait_for_status(http, r.json()["jobID"], timeout=20)
                assert info["status"] == "failed"
                assert "time limit of 1.5 s exceeded" in info["message"], info
            r = http.post("/processes/diagnostics.sleep/execution",
                          json={"inputs": {"seconds": 30, "steps": 3000}, "timeLimit": 0.5},
                          headers={"Prefer": "respond-async"})
            info = wait_for_status(http, r.json()["jobID"], timeout=20)
            assert "time limit of 0.5 s exceeded" in info["message"], info
            r = http.post("/processes/alignment.rigid/execution", json={"inputs": {
                "source": [[0, 0], [1, 0], [0, 1]], "target": [[1, 1], [2, 1], [1, 2]]}})
            assert r.status_code == 200  # other families keep the service's limit
    finally:
        srv.stop()
