"""Limits of a server configured small: the queue length (429 + Retry-After)."""

from __future__ import annotations

from pathlib import Path

import pytest
from live import LiveServer, wait_for_status

pytestmark = pytest.mark.e2e


def test_queue_full_is_429_with_retry_after(tmp_path: Path) -> None:
    srv = LiveServer(tmp_path / "data", {"MORPHSERVE_MAX_QUEUE": "2"}).start()
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
    finally:
        srv.stop()
