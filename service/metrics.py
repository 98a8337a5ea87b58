"""``/metrics`` in the Prometheus text format (version 0.0.4), without a client library.

Gauges are read from the job store at scrape time (so they survive restarts and agree with
``/jobs``: the queued and running jobs are the store's accepted and running rows); the
counters and the latency histogram count what this process has seen since it started, as
Prometheus counters do (a restart resets them; ``rate()`` copes):

- jobs finished, by process and by how they ended, as the store records it (a job dismissed
  while it ran counts as dismissed, whatever its computation returned);
- job runs, by process and path: ``fast`` (the service's fast-path workers) or ``workers``
  (Dask; also a fast job that ran past the fast path's budget and was handed over);
- HTTP responses, by method, route (its template, ``/jobs/{jobId}``, never the raw path)
  and status class (``2xx`` … ``5xx``), counted by :class:`HttpMetrics`, which the app
  mounts outermost but for Starlette's error middleware: a 500 from an unhandled error, a
  401 of the key check and a 404 of an unknown path are counted too.
"""

from __future__ import annotations

import bisect
import threading
import time
from collections import defaultdict
from typing import Any

from service.jobs.status import JobStatus

__all__ = ["Metrics", "LATENCY_BUCKETS", "render", "HttpMetrics", "UNMATCHED"]

#: The route label of a request that matched no route (a 404 of an unknown path).
UNMATCHED = "(unmatched)"

#: Upper bounds (seconds) of the job latency histogram: acceptance to the end.
LATENCY_BUCKETS = (0.005, 0.01, 0.025, 0.05, 0.1, 0.25, 0.5, 1.0, 2.5, 5.0, 10.0, 30.0, 60.0,
                   300.0, 600.0, 1800.0, 3600.0)

STATES = tuple(JobStatus)


def _label(value: str) -> str:
    return value.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n")


class _Histogram:
    __slots__ = ("counts", "total", "count")

    def __init__(self) -> None:
        self.counts = [0] * len(LATENCY_BUCKETS)
        self.total = 0.0
        self.count = 0

    def observe(self, value: float) -> None:
        i = bisect.bisect_left(LATENCY_BUCKETS, value)
        if i < len(self.counts):
            self.counts[i] += 1
        self.total += value
        self.count += 1


class Metrics:
    """What this process has seen finish; fed by the engine's ``on_finish`` callbacks."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._finished: dict[tuple[str, JobStatus], int] = defaultdict(int)
        self._latency: dict[str, _Histogram] = defaultdict(_Histogram)
        self._runs: dict[tuple[str, str], int] = defaultdict(int)
        self._http: dict[tuple[str, str, str], int] = defaultdict(int)
        self.started = time.time()

    def ran(self, process: str, path: str) -> None:
        """A job of ``process`` started on ``path`` (``fast`` or ``workers``)."""
        with self._lock:
            self._runs[(process, path)] += 1

    def responded(self, method: str, route: str, status: int) -> None:
        """An HTTP response of ``status`` to ``method`` on the route template ``route``."""
        key = (method, route, f"{status // 100}xx")
        with self._lock:
            self._http[key] += 1

    def counts(self) -> tuple[dict[tuple[str, str], int], dict[tuple[str, str, str], int]]:
        """Job runs by (process, path) and HTTP responses by (method, route, class)."""
        with self._lock:
            return dict(self._runs), dict(self._http)

    def finished(self, process: str, status: JobStatus, created: float,
                 now: float | None = None) -> None:
        latency = max(0.0, (now or time.time()) - created)
        with self._lock:
            self._finished[(process, status)] += 1
            self._latency[process].observe(latency)

    def snapshot(self) -> tuple[dict[tuple[str, JobStatus], int],
                                dict[str, tuple[list[int], float, int]]]:
        with self._lock:
            return (dict(self._finished),
                    {p: (list(h.counts), h.total, h.count) for p, h in self._latency.items()})


def render(metrics: Metrics, *, jobs: dict[tuple[str, JobStatus], int], queue: int,
           workers: int, processes: int) -> str:
    """The exposition text: ``jobs`` maps (process, status) to the store's counts, from
    which the queued and running gauges are taken too; ``queue`` is the number of jobs the
    engine holds (:attr:`service.jobs.engine.Engine.active`: those of the store's accepted
    and running rows this process runs, and waited fast-path jobs not yet recorded)."""
    out: list[str] = []

    def family(name: str, kind: str, text: str) -> None:
        out.append(f"# HELP {name} {text}")
        out.append(f"# TYPE {name} {kind}")

    family("morphserve_jobs", "gauge", "Jobs in the store by process and status.")
    by_status: dict[JobStatus, int] = dict.fromkeys(STATES, 0)
    for (process, status), n in sorted(jobs.items()):
        by_status[status] = by_status.get(status, 0) + n
        out.append(f'morphserve_jobs{{process="{_label(process)}",status="{status}"}} {n}')
    family("morphserve_jobs_by_status", "gauge", "Jobs in the store by status.")
    for status, n in by_status.items():
        out.append(f'morphserve_jobs_by_status{{status="{status}"}} {n}')
    family("morphserve_jobs_queued", "gauge", "Jobs accepted and not yet running (the "
           "store's accepted rows).")
    out.append(f"morphserve_jobs_queued {by_status[JobStatus.ACCEPTED]}")
    family("morphserve_jobs_running", "gauge", "Jobs running (the store's running rows).")
    out.append(f"morphserve_jobs_running {by_status[JobStatus.RUNNING]}")
    family("morphserve_queue_length", "gauge", "Jobs accepted or running (the store's rows: "
           "queued plus running).")
    out.append("morphserve_queue_length "
               f"{by_status[JobStatus.ACCEPTED] + by_status[JobStatus.RUNNING]}")
    family("morphserve_engine_jobs", "gauge", "Jobs this process is running or waiting on, "
           "waited fast-path jobs not yet recorded included.")
    out.append(f"morphserve_engine_jobs {queue}")
    family("morphserve_workers", "gauge", "Connected Dask workers.")
    out.append(f"morphserve_workers {workers}")
    family("morphserve_processes", "gauge", "Processes offered.")
    out.append(f"morphserve_processes {processes}")

    finished, latency = metrics.snapshot()
    family("morphserve_jobs_finished_total", "counter",
           "Jobs finished by this process since it started, by process and status.")
    for (process, status), n in sorted(finished.items()):
        out.append(f'morphserve_jobs_finished_total{{process="{_label(process)}",'
                   f'status="{status}"}} {n}')
    family("morphserve_job_latency_seconds", "histogram",
           "Seconds from a job's acceptance to its end, by process.")
    for process, (counts, total, count) in sorted(latency.items()):
        p = _label(process)
        cumulative = 0
        for bound, n in zip(LATENCY_BUCKETS, counts, strict=True):
            cumulative += n
            out.append(f'morphserve_job_latency_seconds_bucket{{process="{p}",le="{bound:g}"}} '
                       f"{cumulative}")
        out.append(f'morphserve_job_latency_seconds_bucket{{process="{p}",le="+Inf"}} {count}')
        out.append(f'morphserve_job_latency_seconds_sum{{process="{p}"}} {total:.6f}')
        out.append(f'morphserve_job_latency_seconds_count{{process="{p}"}} {count}')
    runs, http = metrics.counts()
    family("morphserve_job_runs_total", "counter", "Job runs started by this process, by "
           "process and path: fast (the fast path's workers) or workers (Dask).")
    for (process, path), n in sorted(runs.items()):
        out.append(f'morphserve_job_runs_total{{process="{_label(process)}",path="{path}"}} {n}')
    family("morphserve_http_responses_total", "counter", "HTTP responses by method, route "
           "template and status class.")
    for (method, route, klass), n in sorted(http.items()):
        out.append(f'morphserve_http_responses_total{{method="{_label(method)}",'
                   f'route="{_label(route)}",status="{klass}"}} {n}')
    out.extend(_callback_lines())
    family("morphserve_start_time_seconds", "gauge", "When this process started (Unix time).")
    out.append(f"morphserve_start_time_seconds {metrics.started:.3f}")
    return "\n".join(out) + "\n"


def wire(engine: Any, metrics: Metrics) -> None:
    """Count every job the engine finishes, and every run it starts, by path."""
    engine.on_finish.append(
        lambda job, outcome: metrics.finished(job.process, outcome.status, job.created))
    engine.on_run.append(lambda job, path: metrics.ran(job.process, path))


def _route_template(scope: Any) -> str:
    """The template of the route that served ``scope`` (``/jobs/{jobId}``): the one the
    router recorded, else the first of the app's routes that matches, else
    :data:`UNMATCHED`."""
    route = scope.get("route")
    path = getattr(route, "path", None)
    if isinstance(path, str):
        return path
    app = scope.get("app")
    from starlette.routing import Match

    for candidate in getattr(getattr(app, "router", None), "routes", ()):
        match, _ = candidate.matches(scope)
        if match is Match.FULL:
            return str(getattr(candidate, "path", UNMATCHED))
    return UNMATCHED


class HttpMetrics:
    """Pure ASGI middleware counting every HTTP response by method, route template and
    status class in the app's :class:`Metrics` (``app.state.morphserve.metrics``). Mounted
    last (outermost), it sees the answers of the other middlewares too; an exception that
    escapes the app is counted as the 500 Starlette's error middleware then sends."""

    def __init__(self, app: Any) -> None:
        self.app = app

    async def __call__(self, scope: Any, receive: Any, send: Any) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        status = 500

        async def send_status(message: Any) -> None:
            nonlocal status
            if message["type"] == "http.response.start":
                status = int(message["status"])
            await send(message)

        try:
            await self.app(scope, receive, send_status)
        finally:
            st = getattr(getattr(scope.get("app"), "state", None), "morphserve", None)
            if st is not None:
                st.metrics.responded(scope["method"], _route_template(scope), status)


def _callback_lines() -> list[str]:
    """The subscriber callbacks' counters (delivered, failed, retried), kept by
    :data:`service.callbacks.DELIVERIES`."""
    from service.callbacks import DELIVERIES

    return DELIVERIES.exposition()
