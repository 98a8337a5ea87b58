"""The service under load: 5,000 jobs from 32 concurrent clients, nothing lost.

Starts a service on a fresh data dir (or uses ``--url``), then 32 clients send a mix of
jobs as fast as the service answers: 1,000-point rigid alignments with ``Prefer: wait``
(70 %), nearest-neighbour assignments of 2,000 points with ``Prefer: wait`` (20 %) and
similarity alignments submitted with ``respond-async`` and collected at the end (10 %).
A 429 is counted and retried after its ``Retry-After``. Prints throughput, latency
percentiles, the 429s, the service's resident memory after each fifth of the jobs (it must
not grow with the number of finished jobs) and its peak, the worst rotation error, and
checks that every accepted job ended ``successful``. A benchmark never asserts: a lost or
failed job is printed as such and sets the exit status.

    python bench/load.py [--jobs 5000] [--clients 32] [--url http://127.0.0.1:8000]
"""

from __future__ import annotations

import argparse
import asyncio
import statistics
import sys
import tempfile
import threading
import time
from pathlib import Path

import numpy as np
import orjson
import psutil
from scipy.spatial.transform import Rotation

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "bench")]
sys.path.append(str(ROOT / "tests"))
from _http import Connection, request_bytes  # noqa: E402
from live import LiveServer  # noqa: E402

JSON = {"Content-Type": "application/json"}


def make_jobs(url: str, n: int) -> list[tuple[str, bytes, np.ndarray | None]]:
    """(kind, request, expected rotation) for each job; a handful of distinct bodies."""
    rng = np.random.default_rng(0)
    bodies = []
    for seed in range(8):
        X = rng.normal(size=(1000, 3))
        R = Rotation.random(random_state=seed).as_matrix()
        body = orjson.dumps({"inputs": {"source": X.tolist(),
                                        "target": (X @ R.T + seed).tolist()}})
        bodies.append((body, R))
    P = rng.normal(size=(2000, 3))
    nearest = orjson.dumps({"inputs": {"source": P.tolist(),
                                       "target": (P + 1e-3).tolist()}})
    wait = {**JSON, "Prefer": "wait=60"}
    jobs = []
    for i in range(n):
        body, R = bodies[i % len(bodies)]
        if i % 10 == 9:
            jobs.append(("similarity", request_bytes(
                "POST", url + "/processes/alignment.similarity/execution", body,
                {**JSON, "Prefer": "respond-async"}), R))
        elif i % 10 in (3, 6):
            jobs.append(("nearest", request_bytes(
                "POST", url + "/processes/assignment.nearest/execution", nearest, wait), None))
        else:
            jobs.append(("rigid", request_bytes(
                "POST", url + "/processes/alignment.rigid/execution", body, wait), R))
    return jobs


def angle_deg(A: np.ndarray, B: np.ndarray) -> float:
    return float(np.degrees(Rotation.from_matrix(np.asarray(A).T @ B).magnitude()))


class Memory:
    """Samples the service's resident set every 0.1 s."""

    def __init__(self, pid: int | None) -> None:
        self.proc = psutil.Process(pid) if pid else None
        self.peak = 0
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)

    def now(self) -> int:
        return self.proc.memory_info().rss if self.proc else 0

    def _run(self) -> None:
        while not self._stop.wait(0.1):
            self.peak = max(self.peak, self.now())

    def __enter__(self) -> Memory:
        self._thread.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self._stop.set()
        self._thread.join()


async def run(url: str, n: int, clients: int, pid: int | None) -> int:
    jobs = make_jobs(url, n)
    latencies: list[float] = []
    too_many = 0
    failures: list[str] = []
    pending: list[tuple[str, np.ndarray]] = []
    worst = 0.0
    accepted = 0
    done = 0
    rss_marks: list[tuple[int, int]] = []
    next_index = 0

    def take() -> int | None:
        nonlocal next_index
        if next_index >= n:
            return None
        next_index += 1
        return next_index - 1

    with Memory(pid) as memory:
        async def client() -> None:
            nonlocal too_many, worst, accepted, done
            conn = Connection(url)
            while (i := take()) is not None:
                kind, raw, R = jobs[i]
                while True:
                    t = time.perf_counter()
                    status, headers, body = await conn.send(raw)
                    if status != 429:
                        break
                    too_many += 1
                    await asyncio.sleep(float(headers.get("retry-after", "1")))
                latencies.append(time.perf_counter() - t)
                if status in (200, 201):
                    accepted += 1
                if status == 200:
                    doc = orjson.loads(body)
                    if kind == "rigid":
                        worst = max(worst, angle_deg(doc["rotation"], R))
                    elif doc.get("n_pairs") != 2000:
                        failures.append(f"nearest: {doc.get('n_pairs')} pairs")
                elif status == 201:
                    pending.append((orjson.loads(body)["jobID"], R))
                else:
                    failures.append(f"{kind}: HTTP {status} {body[:200]!r}")
                done += 1
                if done % max(1, n // 5) == 0:
                    rss_marks.append((done, memory.now()))
            await conn.close()

        start = time.perf_counter()
        await asyncio.gather(*(client() for _ in range(clients)))
        submitted = time.perf_counter() - start

        # the asynchronous ones: wait for each, check its result
        conn = Connection(url)
        for job_id, R in pending:
            while True:
                status, _, body = await conn.send(request_bytes("GET", f"{url}/jobs/{job_id}"))
                info = orjson.loads(body)
                if info.get("status") not in ("accepted", "running"):
                    break
                await asyncio.sleep(0.05)
            if info.get("status") != "successful":
                failures.append(f"similarity {job_id}: {info.get('status')}")
                continue
            _, _, body = await conn.send(request_bytes("GET", f"{url}/jobs/{job_id}/results"))
            worst = max(worst, angle_deg(orjson.loads(body)["rotation"], R))
        elapsed = time.perf_counter() - start
        counts = {}
        for state in ("accepted", "running", "successful", "failed", "dismissed"):
            _, _, body = await conn.send(request_bytes(
                "GET", f"{url}/jobs?status={state}&limit=1"))
            counts[state] = orjson.loads(body)["numberMatched"]
        await conn.close()

    lat = sorted(latencies)
    pct = {p: lat[min(len(lat) - 1, int(p / 100 * len(lat)))] * 1e3 for p in (50, 95, 99)}
    mib = 2**20
    print(f"{n} jobs from {clients} clients against {url}")
    print(f"  submitted in {submitted:.1f} s: {n / submitted:.0f} jobs/s; all done in "
          f"{elapsed:.1f} s: {n / elapsed:.0f} jobs/s")
    print(f"  latency ms: p50 {pct[50]:.1f}  p95 {pct[95]:.1f}  p99 {pct[99]:.1f}  "
          f"(mean {statistics.fmean(lat) * 1e3:.1f})")
    print(f"  429 answers: {too_many} (each retried after Retry-After)")
    if pid:
        marks = "  ".join(f"{d}: {r / mib:.0f}" for d, r in rss_marks)
        print(f"  service RSS MiB after jobs {marks};  peak {memory.peak / mib:.0f}")
    print(f"  worst rotation error: {worst:.2e} degrees")
    print(f"  store: {counts}; accepted by the clients: {accepted}")
    lost = accepted - counts["successful"] if n == sum(counts.values()) else None
    ok = not failures and counts["successful"] == accepted and lost == 0
    for f in failures[:20]:
        print(f"  FAILED {f}")
    print("  every accepted job ended successful" if ok else
          "  NOT every accepted job ended successful")
    return 0 if ok else 1


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--jobs", type=int, default=5000)
    parser.add_argument("--clients", type=int, default=32)
    parser.add_argument("--url", help="an already running service with an empty store")
    args = parser.parse_args()
    if args.url:
        sys.exit(asyncio.run(run(args.url.rstrip("/"), args.jobs, args.clients, None)))
    with tempfile.TemporaryDirectory() as tmp:
        srv = LiveServer(Path(tmp) / "data", env={"MORPHSERVE_TEST_PROCESSES": "0"}).start()
        try:
            code = asyncio.run(run(srv.url, args.jobs, args.clients, srv.proc.pid))
        finally:
            srv.stop()
    sys.exit(code)


if __name__ == "__main__":
    main()
