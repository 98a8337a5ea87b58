"""The assignment family against its peers, side by side in one run.

Every row goes through ``_common.compare``: ours and the peer alternately after a warm-up,
on the data of seeds 0..2, the median and range of the times, the threads each side was
allowed and the figure each reports (a cost, or an RMSE) on every seed, so that speed is
never bought with accuracy unseen. Both sides start from the points: the peer's time
includes building its cost matrix (``cdist``) or its kd-tree, as a user of the peer would.
Under the one-thread policy the kd-tree ``workers`` of both sides are 1.

    python bench/assignment.py [--quick]

Cases: bipartite 2,000 × 2,000 vs scipy ``linear_sum_assignment``; exact optimal transport
1,000 × 1,000 with uniform masses (our assignment path) and with random masses (POT's network
simplex under our layer) vs POT ``ot.emd``; Sinkhorn 500 × 500 at reg 0.05 vs POT
``ot.sinkhorn2`` in the log domain; nearest for 1,000,000 query points vs
``cKDTree(...).query(workers=-1)``; distance (Chamfer/Hausdorff) 200,000 × 200,000 vs two
``cKDTree`` queries. A benchmark never asserts.
"""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path
from typing import Any

import numpy as np
from scipy.optimize import linear_sum_assignment
from scipy.spatial import cKDTree
from scipy.spatial.distance import cdist

ROOT = Path(__file__).resolve().parents[1]
# the packages first (tests/algorithms must not shadow algorithms), then bench/ for _common
sys.path[:0] = [str(ROOT), str(ROOT / "bench")]

import ot  # noqa: E402 - POT: the optimal transport peer (and our exact path's simplex)
from _common import apply_policy, compare, report, single_thread, workers  # noqa: E402

from algorithms.assignment import (  # noqa: E402
    bipartite,
    distance,
    nearest,
    optimal_transport,
)

FAMILY = "assignment"


def points(seed: int, n: int, d: int) -> np.ndarray:
    return np.random.default_rng(seed).random((n, d))


def pair(n: int) -> Any:
    """The data of one seed: two independent uniform sets of ``n`` points in the unit cube."""
    return lambda s: (points(2 * s, n, 3), points(2 * s + 1, n, 3))


def cost(_d: Any, value: float) -> dict[str, float]:
    return {"cost": value}


def ours_workers() -> dict[str, int]:
    """Our kd-tree functions' ``workers``: their default, or 1 under the one-thread policy."""
    return {"workers": 1} if single_thread() else {}


def case_bipartite(n: int) -> None:
    def peer(d: Any) -> float:
        c = cdist(*d)
        r, k = linear_sum_assignment(c)
        return float(c[r, k].sum())

    compare(FAMILY, f"bipartite {n:,}×{n:,} (3-D)", pair(n), lambda d: bipartite(*d).cost,
            peer, cost, peer_name="scipy linear_sum_assignment")


def case_exact(n: int, weighted: bool) -> None:
    def data(s: int) -> Any:
        src, dst = pair(n)(s)
        rng = np.random.default_rng(100 + s)
        wa = rng.random(n) if weighted else np.ones(n)
        wb = rng.random(n) if weighted else np.ones(n)
        return src, dst, wa, wb

    def ours(d: Any) -> float:
        src, dst, wa, wb = d
        return optimal_transport(src, dst, source_weights=wa, target_weights=wb).cost

    def peer(d: Any) -> float:
        src, dst, wa, wb = d
        c = cdist(src, dst, "sqeuclidean")
        plan = ot.emd(wa / wa.sum(), wb / wb.sum(), c, numItermax=10_000_000)
        return float((plan * c).sum())

    label = "random masses, simplex" if weighted else "uniform masses"
    compare(FAMILY, f"exact OT {n:,}×{n:,} ({label})", data, ours, peer, cost,
            peer_name="POT ot.emd")


def case_sinkhorn(n: int, reg: float) -> None:
    def ours(d: Any) -> Any:
        return optimal_transport(*d, method="sinkhorn", reg=reg, tolerance=1e-9,
                                 max_iterations=10_000).cost

    u = np.full(n, 1.0 / n)

    def peer(d: Any) -> float:
        c = cdist(*d, "sqeuclidean")
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return float(ot.sinkhorn2(u, u, c, reg, method="sinkhorn_log", stopThr=1e-9,
                                      numItermax=10_000))

    compare(FAMILY, f"Sinkhorn {n:,}×{n:,} reg {reg}", pair(n), ours, peer, cost,
            peer_name="POT sinkhorn2 (log domain)")


def case_nearest(n_query: int, n_ref: int) -> None:
    def data(s: int) -> Any:
        return points(2 * s, n_query, 3), points(2 * s + 1, n_ref, 3)

    def peer(d: Any) -> float:
        dist, _ = cKDTree(d[1]).query(d[0], workers=workers())
        return float(np.sqrt(np.mean(dist**2)))

    compare(FAMILY, f"nearest {n_query:,} queries in {n_ref:,}", data,
            lambda d: nearest(*d, **ours_workers()).rmse, peer,
            lambda _d, v: {"rmse": v}, peer_name="cKDTree.query",
            ours_threads="workers -1 by default", peer_threads=f"workers {workers()}")


def case_distance(n: int) -> None:
    def peer(d: Any) -> float:
        src, dst = d
        fwd, _ = cKDTree(dst).query(src, workers=workers())
        bwd, _ = cKDTree(src).query(dst, workers=workers())
        return float(max(fwd.max(), bwd.max()))

    compare(FAMILY, f"distance {n:,}×{n:,}", pair(n),
            lambda d: distance(*d, **ours_workers()).hausdorff, peer,
            lambda _d, v: {"hausdorff": v}, peer_name="two cKDTree queries",
            ours_threads="workers -1 by default", peer_threads=f"workers {workers()}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="a tenth of the sizes")
    args = parser.parse_args()
    apply_policy()
    k = 10 if args.quick else 1
    case_bipartite(2000 // k)
    case_exact(1000 // k, False)
    case_exact(1000 // k, True)
    case_sinkhorn(500 // k, 0.05)
    case_nearest(1_000_000 // k, 100_000 // k)
    case_distance(200_000 // k)
    report(FAMILY)


if __name__ == "__main__":
    main()
