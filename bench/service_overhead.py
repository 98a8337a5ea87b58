"""Service overhead of a 1,000-point rigid alignment, side by side in one run.

Prints one table: p50/p95 latency of `POST /processes/alignment.rigid/execution` with
`Prefer: wait=10` (the body pre-encoded, so the client's JSON encoder is not measured) on the
fast path and through Dask, the same alignment called in-process, their ratio, the rotation
error of each, and jobs/s with 16 concurrent clients (keep-alive, bench/_http.py); the fast
path both with the arrays as JSON lists and as typed binary arrays (what the SDK sends).
"Through Dask" is a service whose fast path is off (MORPHSERVE_FAST_PATH_BYTES=0): each job
runs on a worker of its embedded Dask cluster (sent there directly, service/jobs/direct.py).
The last row is the floor of a round trip through Dask's scheduler: `client.submit` of a
function that returns at once, on the same 1,000 points, to a cluster set up as the
service's (2 process workers of one thread, mutual TLS, the scheduler in a process of its
own, the same monitoring and batching intervals), and `await` of its result.
Goals: p50 <= 15 ms and >= 150 jobs/s (issue #2), p50 <= 10 ms and >= 200 jobs/s (issue #9),
through Dask p50 <= 8 ms and >= 200 jobs/s, the fast path as fast as before (issue #19).
The machine is shared and noisy: the services are all up at once and measured in turn in
each of --repeats rounds (the floor too); each figure is the median of the rounds; the load
average is printed before and after.

    python bench/service_overhead.py [--requests 200] [--repeats 3] [--clients 16]
"""

from __future__ import annotations

import argparse
import asyncio
import base64
import contextlib
import os
import statistics
import sys
import tempfile
import threading
import time
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import orjson
from scipy.spatial.transform import Rotation

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "bench")]  # first: tests/algorithms must not shadow
sys.path.append(str(ROOT / "tests"))
from _http import Connection, request_bytes  # noqa: E402
from live import LiveServer  # noqa: E402

from algorithms.alignment import rigid  # noqa: E402

PATH = "/processes/alignment.rigid/execution"


def case(seed: int = 0, n: int = 1000):  # noqa: ANN201
    rng = np.random.default_rng(seed)
    X = rng.normal(size=(n, 3))
    R = Rotation.random(random_state=seed).as_matrix()
    return X, X @ R.T + rng.normal(size=3), R


def angle_deg(A: np.ndarray, B: np.ndarray) -> float:
    """Angle of the rotation between A and B (stable near 0, unlike arccos of the trace)."""
    return float(np.degrees(Rotation.from_matrix(np.asarray(A).T @ B).magnitude()))


def latency(url: str, body: bytes, n: int) -> tuple[list[float], float]:
    import httpx

    headers = {"Prefer": "wait=10", "Content-Type": "application/json"}
    times, err = [], 0.0
    with httpx.Client(base_url=url, timeout=30) as c:
        for _ in range(10):  # warm-up
            c.post(PATH, content=body, headers=headers)
        for _ in range(n):
            t = time.perf_counter()
            r = c.post(PATH, content=body, headers=headers)
            times.append(time.perf_counter() - t)
            assert r.status_code == 200, r.text
        err = r.json()["rotation"]
    return times, err


def throughput(url: str, body: bytes, clients: int, per_client: int) -> float:
    """Jobs/s with ``clients`` concurrent keep-alive connections, each sending ``per_client``
    requests back to back. The clients are the light asyncio client of bench/_http.py, so
    that the figure is the service's, not a Python HTTP library's sharing the two cores."""
    raw = request_bytes("POST", url + PATH, body,
                        {"Prefer": "wait=30", "Content-Type": "application/json"})
    errors: list[bytes] = []

    async def work() -> None:
        conn = Connection(url)
        for _ in range(per_client):
            status, _, answer = await conn.send(raw)
            if status != 200:
                errors.append(answer)
        await conn.close()

    async def run() -> float:
        t = time.perf_counter()
        await asyncio.gather(*(work() for _ in range(clients)))
        return time.perf_counter() - t

    wall = asyncio.run(run())
    assert not errors, errors[:3]
    return clients * per_client / wall


def _floor_task(inputs: dict) -> dict:  # noqa: ARG001 - the inputs travel, nothing else
    return {"rotation": np.eye(3)}


@contextlib.contextmanager
def bare_dask() -> Iterator[object]:
    """A cluster set up as the service's embedded one, and a function measuring ``n`` round
    trips (``client.submit`` -> result) on it: ``measure(inputs, n) -> times``."""
    import dask
    from distributed import Client

    from service.jobs.engine import QUIET_MONITORING, embedded_cluster
    from service.jobs.scheduler import send_promptly

    loop = asyncio.new_event_loop()
    thread = threading.Thread(target=loop.run_forever, daemon=True)
    thread.start()

    def call(coro):  # noqa: ANN001, ANN202
        return asyncio.run_coroutine_threadsafe(coro, loop).result()

    async def start():  # noqa: ANN202
        dask.config.set(QUIET_MONITORING)
        cluster = await embedded_cluster(2)   # the service's embedded cluster, as it makes it
        client = await Client(cluster, asynchronous=True)
        send_promptly(client.scheduler_comm)
        return cluster, client

    async def measure(inputs: dict, n: int) -> list[float]:
        times = []
        for i in range(n + 10):
            t = time.perf_counter()
            future = client.submit(_floor_task, inputs, pure=False)
            await future
            if i >= 10:  # warm-up
                times.append(time.perf_counter() - t)
            future.release()
        return times

    cluster, client = call(start())
    try:
        yield lambda inputs, n: call(measure(inputs, n))
    finally:
        async def close() -> None:
            await client.close()
            await cluster.close()

        call(close())
        loop.call_soon_threadsafe(loop.stop)
        thread.join(10)


def in_process(X: np.ndarray, Y: np.ndarray, n: int) -> tuple[list[float], np.ndarray]:
    times = []
    for _ in range(n):
        t = time.perf_counter()
        res = rigid(X, Y)
        times.append(time.perf_counter() - t)
    return times, res.rotation


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--requests", type=int, default=200)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--clients", type=int, default=16)
    ap.add_argument("--per-client", type=int, default=25)
    args = ap.parse_args()

    X, Y, R = case()
    body = orjson.dumps({"inputs": {"source": X, "target": Y}},
                        option=orjson.OPT_SERIALIZE_NUMPY)
    load_before = os.getloadavg()
    ref_times, ref_rot = [], None
    for _ in range(args.repeats):
        t, ref_rot = in_process(X, Y, args.requests)
        ref_times.append(statistics.median(t))
    ref_p50 = statistics.median(ref_times)
    ref_err = angle_deg(ref_rot, R)

    # the arrays as typed binary arrays, as the SDK sends any array of 1,024 numbers or more
    binary = orjson.dumps({"inputs": {name: {"dtype": "<f8", "shape": list(a.shape),
                                             "data": base64.b64encode(a.tobytes()).decode()}
                                      for name, a in (("source", X), ("target", Y))}})
    configs = (("fast path", {}, (("JSON lists", body), ("binary", binary))),
               ("through Dask", {"MORPHSERVE_FAST_PATH_BYTES": "0"},
                (("JSON lists", body), ("binary", binary))))
    measured: dict[str, tuple[list[float], list[float], list[float], float]] = {}
    floor: list[float] = []
    with contextlib.ExitStack() as stack:
        servers = []
        for label, env, encodings in configs:
            tmp = stack.enter_context(tempfile.TemporaryDirectory())
            srv = LiveServer(Path(tmp) / "data", {"MORPHSERVE_TEST_PROCESSES": "0", **env})
            srv.start()
            stack.callback(srv.stop)
            servers.append((label, srv, encodings))
        measure_floor = stack.enter_context(bare_dask())
        for _ in range(args.repeats):  # each round: every service in turn, then the floor
            for label, srv, encodings in servers:
                for encoding, payload in encodings:
                    times, rot = latency(srv.url, payload, args.requests)
                    rate = throughput(srv.url, payload, args.clients, args.per_client)
                    p50s, p95s, rates, _ = measured.setdefault(f"{label}, {encoding}",
                                                               ([], [], [], 0.0))
                    p50s.append(statistics.median(times))
                    p95s.append(float(np.percentile(times, 95)))
                    rates.append(rate)
                    measured[f"{label}, {encoding}"] = (p50s, p95s, rates, angle_deg(rot, R))
            floor.append(statistics.median(measure_floor({"source": X, "target": Y},
                                                         args.requests)))
    load_after = os.getloadavg()

    print(f"rigid alignment, 1,000 points, {args.requests} requests x {args.repeats} rounds "
          f"(medians); {args.clients} concurrent clients for jobs/s; load average "
          f"{load_before[0]:.2f} before, {load_after[0]:.2f} after; {os.cpu_count()} cores")
    print(f"{'path, body':<26}{'p50 ms':>9}{'p95 ms':>9}{'in-proc ms':>12}{'ratio':>9}"
          f"{'jobs/s':>9}{'rot err °':>12}{'in-proc err °':>15}")
    for label, (p50s, p95s, rates, err) in measured.items():
        p50 = statistics.median(p50s)
        print(f"{label:<26}{p50 * 1e3:>9.2f}{statistics.median(p95s) * 1e3:>9.2f}"
              f"{ref_p50 * 1e3:>12.3f}{p50 / ref_p50:>9.1f}{statistics.median(rates):>9.0f}"
              f"{err:>12.1e}{ref_err:>15.1e}")
        print(f"{'':<26}p50 of each round: "
              + ", ".join(f"{t * 1e3:.2f}" for t in p50s) + " ms")
    print(f"{'Dask floor (bare submit)':<26}{statistics.median(floor) * 1e3:>9.2f}"
          f"{'':>9}{'':>12}{'':>9}{'':>9}  (p50 of each round: "
          + ", ".join(f"{t * 1e3:.2f}" for t in floor) + " ms)")


if __name__ == "__main__":
    main()
