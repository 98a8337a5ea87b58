"""Port of the suite's ``JobList`` class: ``GET /jobs`` (/conf/job-list)."""

from __future__ import annotations

import json

import pytest

from tests.service.ogc.standard import ECHO, ECHO_INPUTS, json_of, validate

pytestmark = pytest.mark.e2e


def _one_job(http) -> str:  # noqa: ANN001
    r = http.post(f"/processes/{ECHO}/execution", content=json.dumps({"inputs": ECHO_INPUTS}),
                  headers={"Content-Type": "application/json", "Prefer": "respond-async"})
    assert r.status_code == 201
    return str(r.json()["jobID"])


def test_job_list(http) -> None:  # noqa: ANN001
    """/req/job-list/job-list-op: ``GET /jobs`` lists the jobs: after one is created, the
    list is not empty and holds it."""
    job = _one_job(http)
    doc = json_of(http.get("/jobs?limit=1000", headers={"Accept": "application/json"}))
    assert doc["jobs"] and job in [j["jobID"] for j in doc["jobs"]]


def test_job_list_success(http) -> None:  # noqa: ANN001
    """/req/job-list/job-list-success: the job list is valid against jobList.yaml (each
    job a statusInfo.yaml, no null member), and its paging links are absolute and work."""
    _one_job(http)
    _one_job(http)
    r = http.get("/jobs?limit=1", headers={"Accept": "application/json"})
    assert r.status_code == 200
    doc = json_of(r)
    validate("job_list", doc)
    assert len(doc["jobs"]) == 1
    base = str(http.base_url).rstrip("/")
    (nxt,) = [link["href"] for link in doc["links"] if link["rel"] == "next"]
    assert nxt.startswith(base + "/jobs?")
    page = http.get(nxt).json()
    validate("job_list", page)
    assert page["jobs"][0]["jobID"] != doc["jobs"][0]["jobID"]
