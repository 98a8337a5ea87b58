"""``/metrics`` in the Prometheus text format (version 0.0.4), without a client library.

Gauges are read from the job store and the engine at scrape time (so they survive restarts);
the counters and the latency histogram count the jobs this process has finished since it
started, as Prometheus counters do (a restart resets them; ``rate()`` copes).
"""

from __future__ import annotations

import bisect
import threading
import time
from collections import defaultdict
from typing import Any

from service.jobs.status import JobStatus

__all__ = ["Metrics", "LATENCY_BUCKETS", "render"]

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
        self.started = time.time()

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
    """The exposition text: ``jobs`` maps (process, status) to the store's counts."""
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
    family("morphserve_queue_length", "gauge", "Jobs accepted or running in this service.")
    out.append(f"morphserve_queue_length {queue}")
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
    family("morphserve_start_time_seconds", "gauge", "When this process started (Unix time).")
    out.append(f"morphserve_start_time_seconds {metrics.started:.3f}")
    return "\n".join(out) + "\n"


def wire(engine: Any, metrics: Metrics) -> None:
    """Count every job the engine finishes."""
    engine.on_finish.append(
        lambda job, outcome: metrics.finished(job.process, outcome.status, job.created))
