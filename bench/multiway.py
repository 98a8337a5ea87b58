"""Multiway registration without correspondences as a job on a Dask cluster: its pairwise
registrations run as tasks across the workers (service.jobs.tasks), 2 single-threaded
worker processes against 1 (issue #19 item 4: at least 1.7× faster with 2 workers on 12
views, the same poses).

Both clusters are up at once and the job goes to each alternately (:func:`_common.compare`:
warm-up, seeds, interleaved), submitted as the engine submits it (``run_job``, one task;
its pairs then as tasks of its own). The data: 12 partial (70 %), noisy (1 % of the size)
views of a generated lumpy surface, each seen from its own pose (a turn up to 10°, a shift
up to 0.1); more than 10 views, so each is registered with its next 2 (21 pairs). Accuracy
of each side: the largest difference of its transforms from the serial in-process call on
the same views (0: the same poses, bit for bit), and the largest rotation error against
the true poses.

Run at default threads only: the one-thread policy pins this process, and so the workers it
spawns, to one core, where 2 workers cannot be faster than 1. The machine is shared: the
figure means something only with its load average (printed with the row).

    python bench/multiway.py [--quick] [--views 12] [--points 3000]
"""

from __future__ import annotations

import argparse
import itertools
import logging
import os
import sys
import warnings
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "bench")]
import dask  # noqa: E402
from _common import angle_deg, apply_policy, blob, compare, report  # noqa: E402
from distributed import Client, LocalCluster  # noqa: E402

from algorithms.registration import multiway  # noqa: E402
from service.jobs.engine import QUIET_MONITORING  # noqa: E402
from service.jobs.runner import run_job  # noqa: E402
from service.jobs.status import JobStatus  # noqa: E402
from tests.algorithms.registration._views import views as test_views  # noqa: E402

_ids = itertools.count()


def views(k: int, n: int, seed: int) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """``k`` views of :func:`_common.blob` as the multiway tests make them
    (tests/algorithms/registration/_views.py): view ``i`` keeps the 70 % of the points seen
    from the direction ``2πi/k`` in the xy-plane, adds noise of 1 % of the size and is seen
    from a pose ``T_i`` (a turn up to 10°, a shift up to 0.1; ``T_0 = I``). The views and
    the poses."""
    return test_views(blob, k=k, n=n, seed=seed)


def job(client: Client, sets: list[np.ndarray]) -> np.ndarray:
    """The multiway job on ``client``'s cluster, as the engine submits it: its transforms."""
    job_id = f"bench-{os.getpid()}-{next(_ids)}"
    outcome = client.submit(run_job, job_id, "registration.multiway",
                            {"sets": sets, "correspondences": False},
                            key=f"morphserve-{job_id}", pure=False).result()
    if outcome.status is not JobStatus.SUCCESSFUL:
        raise RuntimeError(f"the job failed: {outcome.message}")
    return np.asarray(outcome.outputs["transforms"])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--views", type=int, default=12)
    parser.add_argument("--points", type=int, default=3000,
                        help="points of the surface each view keeps 70 %% of")
    args = parser.parse_args()
    apply_policy()
    n = 1200 if args.quick else args.points

    def data(seed: int) -> dict[str, Any]:
        sets, poses = views(args.views, n, seed)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            serial = multiway(sets, correspondences=False).transforms
        return {"sets": sets, "poses": poses, "serial": serial}

    def accuracy(d: dict[str, Any], transforms: np.ndarray) -> dict[str, float]:
        return {"max |T - serial T|": float(np.abs(transforms - d["serial"]).max()),
                "max rotation error (deg)": max(angle_deg(t[:3, :3], p[:3, :3])
                                                for t, p in zip(transforms, d["poses"],
                                                                strict=True))}

    dask.config.set(QUIET_MONITORING)
    logging.getLogger("distributed").setLevel(logging.ERROR)
    clusters = {w: LocalCluster(n_workers=w, threads_per_worker=1, processes=True,
                                dashboard_address=None, silence_logs=logging.ERROR)
                for w in (1, 2)}
    clients = {w: Client(c) for w, c in clusters.items()}
    try:
        print(f"multiway, {args.views} views of {int(0.7 * n)} points, no correspondences: "
              "a job on 2 workers (ours) vs 1 worker (peer), 1 thread each; "
              f"load average {os.getloadavg()[0]:.2f}", flush=True)
        row = compare("registration", f"multiway {args.views} views, 2 Dask workers",
                      data, lambda d: job(clients[2], d["sets"]),
                      lambda d: job(clients[1], d["sets"]), accuracy,
                      peer_name="1 Dask worker", ours_threads="2 workers × 1 thread",
                      peer_threads="1 worker × 1 thread")
    finally:
        for c in clients.values():
            c.close()
        for cluster in clusters.values():
            cluster.close()
    report("multiway: pairwise registrations as tasks")
    if row is not None:
        r = row["ratio"]
        print(f"\n2 workers: {row['ours']['median']:.3f} s, 1 worker: "
              f"{row['peer_times']['median']:.3f} s, speed-up {1 / r['median']:.2f}× "
              f"[{1 / r['max']:.2f}–{1 / r['min']:.2f}] (goal >= 1.7×); load average "
              f"{row['load']['before'][0]:.2f} → {row['load']['after'][0]:.2f} on "
              f"{os.cpu_count()} cores")


if __name__ == "__main__":
    main()
