"""The assignment family against its peers, side by side in one run.

Prints one table: for each case our time, the peer's time on the same data, their ratio
(ours / peer: below 1 is faster), and the figure each reports (a cost, or an RMSE), so that
speed is never bought with accuracy unseen. Every time is the median of --repeats runs.
Both sides start from the points: the peer's time includes building its cost matrix
(``cdist``) or its kd-tree, as a user of the peer would.

    python bench/assignment.py [--repeats 3] [--quick]

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
from _common import print_ratio_table, timed  # noqa: E402

from algorithms.assignment import (  # noqa: E402
    bipartite,
    distance,
    nearest,
    optimal_transport,
)


def points(seed: int, n: int, d: int) -> np.ndarray:
    return np.random.default_rng(seed).random((n, d))


def case_bipartite(n: int, repeats: int) -> tuple[str, float, float, str, str]:
    src, dst = points(0, n, 3), points(1, n, 3)

    def peer() -> float:
        cost = cdist(src, dst)
        r, c = linear_sum_assignment(cost)
        return float(cost[r, c].sum())

    ours_t, ours = timed(lambda: bipartite(src, dst).cost, repeats)
    peer_t, theirs = timed(peer, repeats)
    return (f"bipartite {n:,}×{n:,} (3-D)  vs scipy linear_sum_assignment", ours_t, peer_t,
            f"cost {ours:.10g}", f"cost {theirs:.10g}")


def case_exact(n: int, weighted: bool, repeats: int) -> tuple[str, float, float, str, str]:
    src, dst = points(2, n, 3), points(3, n, 3)
    rng = np.random.default_rng(4)
    wa = rng.random(n) if weighted else np.ones(n)
    wb = rng.random(n) if weighted else np.ones(n)
    a, b = wa / wa.sum(), wb / wb.sum()
    label = "random masses, simplex" if weighted else "uniform masses"
    name = f"exact OT {n:,}×{n:,} ({label})  vs POT ot.emd"
    ours_t, res = timed(lambda: optimal_transport(src, dst, source_weights=wa,
                                                  target_weights=wb), repeats)

    def peer() -> float:
        cost = cdist(src, dst, "sqeuclidean")
        plan = ot.emd(a, b, cost, numItermax=10_000_000)
        return float((plan * cost).sum())

    peer_t, theirs = timed(peer, repeats)
    return name, ours_t, peer_t, f"cost {res.cost:.10g}", f"cost {theirs:.10g}"


def case_sinkhorn(n: int, reg: float, repeats: int) -> tuple[str, float, float, str, str]:
    src, dst = points(5, n, 3), points(6, n, 3)
    name = f"Sinkhorn {n:,}×{n:,} reg {reg}  vs POT sinkhorn_log"

    def ours() -> Any:
        return optimal_transport(src, dst, method="sinkhorn", reg=reg, tolerance=1e-9,
                                 max_iterations=10_000)

    ours_t, res = timed(ours, repeats)
    mine = f"cost {res.cost:.10g} ({res.iterations} it)"
    u = np.full(n, 1.0 / n)

    def peer() -> float:
        cost = cdist(src, dst, "sqeuclidean")
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return float(ot.sinkhorn2(u, u, cost, reg, method="sinkhorn_log", stopThr=1e-9,
                                      numItermax=10_000))

    peer_t, theirs = timed(peer, repeats)
    return name, ours_t, peer_t, mine, f"cost {theirs:.10g}"


def case_nearest(n_query: int, n_ref: int, repeats: int) -> tuple[str, float, float, str, str]:
    query, ref = points(7, n_query, 3), points(8, n_ref, 3)

    def peer() -> float:
        dist, _ = cKDTree(ref).query(query, workers=-1)
        return float(np.sqrt(np.mean(dist**2)))

    ours_t, res = timed(lambda: nearest(query, ref), repeats)
    peer_t, theirs = timed(peer, repeats)
    return (f"nearest {n_query:,} queries in {n_ref:,}  vs cKDTree.query(workers=-1)", ours_t,
            peer_t, f"rmse {res.rmse:.10g}", f"rmse {theirs:.10g}")


def case_distance(n: int, repeats: int) -> tuple[str, float, float, str, str]:
    src, dst = points(9, n, 3), points(10, n, 3)

    def peer() -> float:
        fwd, _ = cKDTree(dst).query(src, workers=-1)
        bwd, _ = cKDTree(src).query(dst, workers=-1)
        return float(max(fwd.max(), bwd.max()))

    ours_t, res = timed(lambda: distance(src, dst), repeats)
    peer_t, theirs = timed(peer, repeats)
    return (f"distance {n:,}×{n:,}  vs two cKDTree queries", ours_t, peer_t,
            f"hausdorff {res.hausdorff:.10g}", f"hausdorff {theirs:.10g}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--quick", action="store_true", help="a tenth of the sizes")
    args = parser.parse_args()
    k = 10 if args.quick else 1
    r = args.repeats
    rows = [
        case_bipartite(2000 // k, r),
        case_exact(1000 // k, False, r),
        case_exact(1000 // k, True, r),
        case_sinkhorn(500 // k, 0.05, r),
        case_nearest(1_000_000 // k, 100_000 // k, r),
        case_distance(200_000 // k, r),
    ]
    print_ratio_table(rows, r)


if __name__ == "__main__":
    main()
