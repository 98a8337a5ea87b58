"""Throughput of a batch through ``Client.map`` against a loop of one job at a time.

Starts one live embedded server (uvicorn + a Dask cluster of 2 workers), then runs the same
200 small registrations (ICP of 200-point scans onto one target) both ways, interleaved:
``client.map("registration.icp", scans, target=...)`` and ``for scan in scans:
client.execute(..., wait=60).result()``. Prints one table: the median seconds of --repeats
runs of each, jobs/s, their ratio, and how far the transforms of the two differ (they must
not). Goal: map >= 1.8x the loop on 2 workers (issue #21).

    python bench/sdk_map.py [--jobs 200] [--points 200] [--repeats 3] [--in-flight 8]
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "tests")]
from live import LiveServer  # noqa: E402

from morphserve import Client  # noqa: E402

PROCESS = "registration.icp"


def scans(count: int, points: int, seed: int = 0) -> tuple[np.ndarray, list[dict[str, np.ndarray]]]:
    """One target and ``count`` sources: the target turned a few degrees and shifted."""
    rng = np.random.default_rng(seed)
    target = rng.normal(size=(points, 3))
    sources = []
    for _ in range(count):
        rotation = Rotation.from_rotvec(rng.normal(size=3) * 0.05).as_matrix()
        sources.append({"source": target @ rotation.T + rng.normal(size=3) * 0.02})
    return target, sources


def run_map(client: Client, target: np.ndarray, inputs: list[dict[str, np.ndarray]],
            in_flight: int) -> tuple[float, list[np.ndarray]]:
    start = time.perf_counter()
    items = client.map(PROCESS, inputs, target=target, max_in_flight=in_flight)
    seconds = time.perf_counter() - start
    return seconds, [item.result()["transform"] for item in items]


def run_loop(client: Client, target: np.ndarray, inputs: list[dict[str, np.ndarray]]
             ) -> tuple[float, list[np.ndarray]]:
    start = time.perf_counter()
    transforms = [client.execute(PROCESS, target=target, wait=60, **item).result()["transform"]
                  for item in inputs]
    return time.perf_counter() - start, transforms


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--jobs", type=int, default=200)
    parser.add_argument("--points", type=int, default=200)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--in-flight", type=int, default=8)
    args = parser.parse_args()
    target, inputs = scans(args.jobs, args.points)
    with tempfile.TemporaryDirectory() as tmp:
        server = LiveServer(Path(tmp) / "data", {"MORPHSERVE_WORKERS": "2"}).start()
        try:
            with Client(server.url, timeout=120) as client:
                run_map(client, target, inputs[:10], args.in_flight)  # warm the workers
                times: dict[str, list[float]] = {"map": [], "loop": []}
                differences = []
                for _ in range(args.repeats):  # interleaved: noise hits both alike
                    seconds, mapped = run_map(client, target, inputs, args.in_flight)
                    times["map"].append(seconds)
                    seconds, looped = run_loop(client, target, inputs)
                    times["loop"].append(seconds)
                    differences.append(max(float(np.abs(a - b).max())
                                           for a, b in zip(mapped, looped)))
        finally:
            server.stop()
    loop, mapped_s = statistics.median(times["loop"]), statistics.median(times["map"])
    print(f"{args.jobs} x {PROCESS} ({args.points} points), 2 workers, median of "
          f"{args.repeats} interleaved runs")
    print(f"{'way':<28}{'seconds':>10}{'jobs/s':>10}{'ratio':>8}{'max |dT|':>12}")
    print(f"{'loop (execute + result)':<28}{loop:>10.2f}{args.jobs / loop:>10.1f}"
          f"{1.0:>8.2f}{'':>12}")
    print(f"{f'map (max_in_flight={args.in_flight})':<28}{mapped_s:>10.2f}"
          f"{args.jobs / mapped_s:>10.1f}{loop / mapped_s:>8.2f}{max(differences):>12.1e}")
    print(f"runs (s): map {[round(t, 2) for t in times['map']]}, "
          f"loop {[round(t, 2) for t in times['loop']]}")


if __name__ == "__main__":
    main()
