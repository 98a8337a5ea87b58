"""Job life cycle over HTTP: progress, dismissal, time limits, listing."""

from __future__ import annotations

import os
import re
import signal
import time

import pytest

from service.problems import OGC_EXCEPTIONS
from tests.live import wait_for_status

pytestmark = pytest.mark.e2e


def _sleep(http, seconds: float, steps: int, **extra):  # noqa: ANN001, ANN202
    r = http.post("/processes/diagnostics.sleep/execution", headers={"Prefer": "respond-async"},
                  json={"inputs": {"seconds": seconds, "steps": steps}, **extra})
    assert r.status_code == 201, r.text
    return r.json()["jobID"]


def test_progress_is_reported(http) -> None:
    job = _sleep(http, 3, 30)
    wait_for_status(http, job, ("running",))
    seen = set()
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline:
        info = http.get(f"/jobs/{job}").json()
        if info["status"] == "running":
            seen.add(info["progress"])
            assert info["message"].startswith(("slept", "running"))
        else:
            break
        time.sleep(0.1)
    assert len(seen) >= 3 and max(seen) > min(seen), seen
    assert wait_for_status(http, job)["progress"] == 100


def _epoch(stamp: str) -> float:
    from datetime import datetime

    return datetime.fromisoformat(stamp.replace("Z", "+00:00")).timestamp()


def test_dismiss_running_job_frees_its_worker(http) -> None:
    """Both workers busy with a minute's sleep, both dismissed: a new job runs on a freed
    worker, long before either sleep would have ended (order of the recorded events)."""
    jobs = [_sleep(http, 60, 6000) for _ in range(2)]
    started = [wait_for_status(http, job, ("running",), timeout=30)["started"] for job in jobs]
    for job in jobs:
        r = http.delete(f"/jobs/{job}")
        assert r.status_code == 200 and r.json()["status"] == "dismissed"
    probe = _sleep(http, 0.1, 1)
    info = wait_for_status(http, probe, timeout=60)
    assert info["status"] == "successful"
    assert _epoch(info["finished"]) < min(_epoch(s) for s in started) + 60
    for job in jobs:
        assert http.get(f"/jobs/{job}").json()["status"] == "dismissed"
        r = http.get(f"/jobs/{job}/results")
        assert r.status_code == 410 and r.json()["type"] == "/problems/job-dismissed"


def test_dismiss_queued_job(http) -> None:
    blockers = [_sleep(http, 3, 30) for _ in range(2)]
    queued = _sleep(http, 0.1, 1)
    r = http.delete(f"/jobs/{queued}")
    assert r.status_code == 200 and r.json()["status"] == "dismissed"
    for b in blockers:
        http.delete(f"/jobs/{b}")
    # the workers free again and a later job run: the dismissed one never ran
    assert wait_for_status(http, _sleep(http, 0, 1))["status"] == "successful"
    info = http.get(f"/jobs/{queued}").json()
    assert info["status"] == "dismissed" and info.get("started") is None
    assert http.get(f"/jobs/{queued}/results").status_code == 410


def test_dismiss_finished_job_removes_it(http) -> None:
    job = _sleep(http, 0, 1)
    wait_for_status(http, job)
    assert http.delete(f"/jobs/{job}").json()["status"] == "dismissed"
    r = http.get(f"/jobs/{job}")
    assert r.status_code == 404 and r.json()["type"] == OGC_EXCEPTIONS + "no-such-job"
    assert http.delete(f"/jobs/{job}").status_code == 404


def test_time_limit_fails_the_job_with_a_clear_message(http) -> None:
    job = _sleep(http, 30, 3000, timeLimit=1)
    info = wait_for_status(http, job, timeout=60)
    assert info["status"] == "failed"
    assert _epoch(info["finished"]) < _epoch(info["started"]) + 30  # before its sleep ends
    assert "time limit of 1 s exceeded" in info["message"]
    r = http.get(f"/jobs/{job}/results")
    assert r.status_code == 504
    assert r.headers["content-type"] == "application/problem+json"
    assert r.json()["type"] == "/problems/time-limit-exceeded"
    assert r.json()["instance"] == f"/jobs/{job}"


def test_result_not_ready(http) -> None:
    job = _sleep(http, 2, 20)
    r = http.get(f"/jobs/{job}/results")
    assert r.status_code == 404 and r.json()["type"] == OGC_EXCEPTIONS + "result-not-ready"
    http.delete(f"/jobs/{job}")


def test_job_list_filter_and_paging(http) -> None:
    mine = [_sleep(http, 0, 1) for _ in range(5)]
    for job in mine:
        wait_for_status(http, job)
    page = http.get("/jobs", params={"processID": "diagnostics.sleep", "status": "successful",
                                     "limit": 2}).json()
    assert len(page["jobs"]) == 2 and page["numberMatched"] >= 5
    assert all(j["processID"] == "diagnostics.sleep" and j["status"] == "successful"
               for j in page["jobs"])
    assert page["jobs"][0]["jobID"] == mine[-1]  # newest first
    nxt = next(link["href"] for link in page["links"] if link["rel"] == "next")
    page2 = http.get(nxt).json()
    assert page2["jobs"][0]["jobID"] == mine[-3]
    assert any(link["rel"] == "prev" for link in page2["links"])
    none = http.get("/jobs", params={"processID": "no.such"}).json()
    assert none["jobs"] == [] and none["numberMatched"] == 0


def test_metrics_count_jobs_by_process_and_time_them(http) -> None:
    from prometheus_client.parser import text_string_to_metric_families

    def scrape() -> dict[str, list]:
        r = http.get("/metrics")
        assert r.status_code == 200 and r.headers["content-type"].startswith("text/plain")
        return {f.name: f.samples for f in text_string_to_metric_families(r.text)}

    def value(fams, family, sample, **labels) -> float:
        return sum(s.value for s in fams.get(family, []) if s.name == sample
                   and all(s.labels.get(k) == v for k, v in labels.items()))

    before = scrape()
    body = {"inputs": {"source": [[0, 0], [1, 0], [0, 1]], "target": [[1, 1], [1, 2], [0, 1]]}}
    for _ in range(3):
        assert http.post("/processes/alignment.rigid/execution", json=body).status_code == 200
    after = scrape()
    ok = {"process": "alignment.rigid", "status": "successful"}
    assert value(after, "morphserve_jobs", "morphserve_jobs", **ok) - \
        value(before, "morphserve_jobs", "morphserve_jobs", **ok) == 3
    assert value(after, "morphserve_jobs_finished", "morphserve_jobs_finished_total", **ok) - \
        value(before, "morphserve_jobs_finished", "morphserve_jobs_finished_total", **ok) == 3
    lat = "morphserve_job_latency_seconds"
    count = value(after, lat, lat + "_count", process="alignment.rigid")
    assert count - value(before, lat, lat + "_count", process="alignment.rigid") == 3
    assert value(after, lat, lat + "_bucket", process="alignment.rigid", le="+Inf") == count
    assert 0 < value(after, lat, lat + "_sum", process="alignment.rigid") < 60 * count
    assert value(after, "morphserve_workers", "morphserve_workers") == 2
    assert value(after, "morphserve_queue_length", "morphserve_queue_length") >= 0
    by_status = value(after, "morphserve_jobs_by_status", "morphserve_jobs_by_status",
                      status="successful")
    assert by_status == value(after, "morphserve_jobs", "morphserve_jobs", status="successful")


def test_a_worker_killed_mid_job_does_not_lose_the_job(http, server) -> None:
    """SIGKILL the worker running a job (its pid from the progress message): the nanny
    starts a new worker, the scheduler runs the job again, and it ends successful."""
    job = _sleep(http, 2, 40)
    deadline = time.monotonic() + 60
    while True:
        info = http.get(f"/jobs/{job}").json()
        found = re.search(r"in pid (\d+)", info.get("message", ""))
        if found or time.monotonic() > deadline:
            break
        time.sleep(0.05)
    assert found, info
    pid = int(found[1])
    assert pid not in (os.getpid(), server.proc.pid)  # a worker, not the service
    os.kill(pid, signal.SIGKILL)
    info = wait_for_status(http, job, timeout=120)
    assert info["status"] == "successful", info
    slept = http.get(f"/jobs/{job}/results").json()["slept"]
    assert slept >= 2.0  # the whole job ran again after the kill
    with pytest.raises(ProcessLookupError):
        os.kill(pid, 0)  # and the killed worker really is gone


def test_poison_job_fails_with_a_reason_and_the_service_keeps_serving(http) -> None:
    """A job that kills its worker every time ends failed (worker-lost) after the allowed
    failures; the nanny replaces the workers and other jobs run."""
    r = http.post("/processes/diagnostics.crash/execution", headers={"Prefer": "respond-async"},
                  json={"inputs": {}})
    assert r.status_code == 201
    info = wait_for_status(http, r.json()["jobID"], timeout=90)
    assert info["status"] == "failed"
    assert "worker died" in info["message"]
    problem = http.get(f"/jobs/{info['jobID']}/results").json()
    assert problem["type"] == "/problems/worker-lost"
    deadline = time.monotonic() + 30
    while http.get("/readyz").json().get("workers") != 2 and time.monotonic() < deadline:
        time.sleep(0.2)
    job = _sleep(http, 0.1, 1)
    assert wait_for_status(http, job, timeout=30)["status"] == "successful"
