"""service.metrics without a server: the exposition text against prometheus_client's parser."""

from __future__ import annotations

from prometheus_client.parser import text_string_to_metric_families

from service.metrics import LATENCY_BUCKETS, Metrics, render


def _families(text: str) -> dict:
    return {f.name: f for f in text_string_to_metric_families(text)}


def test_histogram_buckets_are_cumulative_and_counts_add_up() -> None:
    m = Metrics()
    for latency in (0.001, 0.02, 0.02, 7.0, 5000.0):  # the last one beyond every bucket
        m.finished("alignment.rigid", "successful", created=100.0, now=100.0 + latency)
    m.finished("assignment.nearest", "failed", created=5.0, now=5.5)
    fams = _families(render(m, jobs={}, queue=0, workers=0, processes=0))
    hist = fams["morphserve_job_latency_seconds"]
    assert hist.type == "histogram"
    rigid = {s.labels["le"]: s.value for s in hist.samples
             if s.name.endswith("_bucket") and s.labels["process"] == "alignment.rigid"}
    assert rigid["0.005"] == 1 and rigid["0.025"] == 3 and rigid["10"] == 4
    assert rigid["3600"] == 4 and rigid["+Inf"] == 5
    assert len(rigid) == len(LATENCY_BUCKETS) + 1
    sums = {s.labels["process"]: s.value for s in hist.samples if s.name.endswith("_sum")}
    assert abs(sums["alignment.rigid"] - (0.001 + 0.04 + 7.0 + 5000.0)) < 1e-5
    assert sums["assignment.nearest"] == 0.5
    done = {(s.labels["process"], s.labels["status"]): s.value
            for s in fams["morphserve_jobs_finished"].samples}
    assert done == {("alignment.rigid", "successful"): 5, ("assignment.nearest", "failed"): 1}


def test_gauges_from_the_store_and_odd_labels_are_escaped() -> None:
    jobs = {("alignment.rigid", "successful"): 4, ("alignment.rigid", "failed"): 1,
            ('odd"name\\', "running"): 2}
    fams = _families(render(Metrics(), jobs=jobs, queue=2, workers=3, processes=11))
    per = {(s.labels["process"], s.labels["status"]): s.value
           for s in fams["morphserve_jobs"].samples}
    assert per == {k: float(v) for k, v in jobs.items()}
    status = {s.labels["status"]: s.value for s in fams["morphserve_jobs_by_status"].samples}
    assert status == {"accepted": 0, "running": 2, "successful": 4, "failed": 1, "dismissed": 0}
    assert fams["morphserve_queue_length"].samples[0].value == 2
    assert fams["morphserve_workers"].samples[0].value == 3
    assert fams["morphserve_processes"].samples[0].value == 11


def test_queued_and_running_gauges_are_the_stores_rows() -> None:
    """The queue is what the store holds accepted and running, not what the engine holds
    (``queue``, the engine's count, is its own gauge)."""
    jobs = {("alignment.rigid", "accepted"): 3, ("diagnostics.sleep", "accepted"): 1,
            ("diagnostics.sleep", "running"): 2, ("alignment.rigid", "successful"): 7}
    fams = _families(render(Metrics(), jobs=jobs, queue=9, workers=2, processes=1))
    assert fams["morphserve_jobs_queued"].samples[0].value == 4
    assert fams["morphserve_jobs_running"].samples[0].value == 2
    assert fams["morphserve_queue_length"].samples[0].value == 6
    assert fams["morphserve_engine_jobs"].samples[0].value == 9


def test_job_runs_are_counted_by_path() -> None:
    m = Metrics()
    for path in ("fast", "fast", "workers"):
        m.ran("alignment.homography", path)
    fams = _families(render(m, jobs={}, queue=0, workers=0, processes=0))
    runs = {(s.labels["process"], s.labels["path"]): s.value
            for s in fams["morphserve_job_runs"].samples}
    assert runs == {("alignment.homography", "fast"): 2, ("alignment.homography", "workers"): 1}


def test_http_responses_by_route_template_and_status_class() -> None:
    """A route with a path parameter counts under its template, an unknown path under
    (unmatched), an unhandled error as the 500 it becomes."""
    from types import SimpleNamespace

    from fastapi import FastAPI
    from fastapi.testclient import TestClient

    from service.metrics import UNMATCHED, HttpMetrics

    app = FastAPI()
    metrics = Metrics()
    app.state.morphserve = SimpleNamespace(metrics=metrics)

    @app.get("/jobs/{job_id}")
    async def job(job_id: str) -> dict[str, str]:
        return {"id": job_id}

    @app.post("/boom")
    async def boom() -> None:
        raise RuntimeError("a bug")

    app.add_middleware(HttpMetrics)
    with TestClient(app, raise_server_exceptions=False) as client:
        assert client.get("/jobs/a").status_code == 200
        assert client.get("/jobs/b").status_code == 200
        assert client.post("/boom").status_code == 500
        assert client.get("/nowhere").status_code == 404
        assert client.post("/jobs/a").status_code == 405
    fams = _families(render(metrics, jobs={}, queue=0, workers=0, processes=0))
    http = {(s.labels["method"], s.labels["route"], s.labels["status"]): s.value
            for s in fams["morphserve_http_responses"].samples}
    assert http == {("GET", "/jobs/{job_id}", "2xx"): 2, ("POST", "/boom", "5xx"): 1,
                    ("GET", UNMATCHED, "4xx"): 1, ("POST", "/jobs/{job_id}", "4xx"): 1}
