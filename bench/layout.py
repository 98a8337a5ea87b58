"""The layout family against its peers, side by side in one run.

Prints one table: for each case our time, the peer's time on the same data, their ratio
(ours / peer: below 1 is faster), and the figure each reaches (a stress, or the largest
difference of positions), so that speed is never bought with accuracy unseen. Every time is
the median of --repeats runs.

    python bench/layout.py [--repeats 3] [--quick]

Cases (1,000 points in 6-D, distances laid out in 2-D, unless --quick):

- classical MDS vs scikit-learn ``ClassicalMDS(metric="precomputed")``;
- SMACOF from the same start (classical MDS), 100 iterations each (no early stop) vs
  ``sklearn.manifold.smacof``: the cost of an iteration;
- SMACOF with each library's default stopping rule (ours: relative decrease 1e-6;
  scikit-learn: eps 1e-6 of the sum of squared distances), same start;
- ours with the relaxed update (relaxation 1.9) run just until its stress is at most
  scikit-learn's default result: the time to the same stress;
- Tutte/harmonic layout of a lifted 224 × 224 grid (50,176 vertices) with cotangent weights
  and the boundary on the circle vs ``igl.harmonic(V, F, b, bc, 1)``.

A benchmark never asserts.
"""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

import numpy as np
from scipy.spatial.distance import cdist

ROOT = Path(__file__).resolve().parents[1]
# the packages first (tests/algorithms must not shadow algorithms), then bench/ for _common
sys.path[:0] = [str(ROOT), str(ROOT / "bench")]

import igl  # noqa: E402
from _common import print_ratio_table, timed  # noqa: E402
from sklearn.manifold import ClassicalMDS, smacof  # noqa: E402

from algorithms.core import ConvergenceWarning  # noqa: E402
from algorithms.layout import laplacian, mds, stress  # noqa: E402

warnings.simplefilter("ignore", ConvergenceWarning)


def raw_stress(x: np.ndarray, d: np.ndarray) -> float:
    diff = cdist(x, x) - d
    return 0.5 * float(np.vdot(diff, diff))


def distances(n: int) -> np.ndarray:
    x = np.random.default_rng(0).standard_normal((n, 6))
    return cdist(x, x)


def case_classical(d: np.ndarray, repeats: int) -> tuple[str, float, float, str, str]:
    ours_t, ours = timed(lambda: mds(d).positions, repeats)
    peer_t, theirs = timed(lambda: ClassicalMDS(n_components=2, metric="precomputed")
                           .fit_transform(d), repeats)
    return (f"classical MDS {len(d):,} points  vs sklearn ClassicalMDS", ours_t, peer_t,
            f"stress {raw_stress(ours, d):.8g}",
            f"stress {raw_stress(theirs, d):.8g} (|Δx| {np.abs(ours - theirs).max():.1e})")


def case_iterations(d: np.ndarray, start: np.ndarray, iters: int, repeats: int
                    ) -> tuple[str, float, float, str, str]:
    ours_t, ours = timed(lambda: stress(d, weighting="uniform", initial_positions=start,
                                        max_iterations=iters, tolerance=0.0), repeats)
    peer_t, (_, s_peer) = timed(lambda: smacof(d, init=start, n_init=1, max_iter=iters,
                                               eps=0.0), repeats)
    return (f"SMACOF {len(d):,} points, {iters} iterations, same start  vs sklearn smacof",
            ours_t, peer_t, f"stress {ours.stress:.10g}", f"stress {s_peer:.10g}")


def case_defaults(d: np.ndarray, start: np.ndarray, repeats: int
                  ) -> tuple[tuple[str, float, float, str, str], float]:
    ours_t, ours = timed(lambda: stress(d, weighting="uniform", initial_positions=start),
                         repeats)
    peer_t, (_, s_peer, it_peer) = timed(
        lambda: smacof(d, init=start, n_init=1, return_n_iter=True), repeats)
    row = (f"SMACOF {len(d):,} points, default stopping, same start  vs sklearn smacof",
           ours_t, peer_t, f"stress {ours.stress:.10g} ({ours.iterations} it.)",
           f"stress {s_peer:.10g} ({it_peer} it.)")
    return row, float(s_peer)


def case_same_stress(d: np.ndarray, start: np.ndarray, target: float, peer_t: float,
                     repeats: int) -> tuple[str, float, float, str, str]:
    probe = stress(d, weighting="uniform", initial_positions=start, relaxation=1.9,
                   max_iterations=3000, tolerance=0.0)
    below = np.flatnonzero(probe.stress_history <= target)
    iters = int(below[0]) if below.size else probe.iterations
    ours_t, ours = timed(lambda: stress(d, weighting="uniform", initial_positions=start,
                                        relaxation=1.9, max_iterations=iters,
                                        tolerance=0.0), repeats)
    return (f"SMACOF {len(d):,} points to sklearn's stress (relaxation 1.9)  vs sklearn "
            "default", ours_t, peer_t, f"stress {ours.stress:.10g} ({iters} it.)",
            f"stress {target:.10g}")


def lifted_grid(n: int) -> tuple[np.ndarray, np.ndarray]:
    x, y = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n))
    z = 0.2 * np.sin(6 * x) * np.cos(5 * y)
    v = np.c_[x.ravel(), y.ravel(), z.ravel()]
    i, j = np.meshgrid(np.arange(n - 1), np.arange(n - 1), indexing="ij")
    a = (i * n + j).ravel()
    f = np.concatenate([np.c_[a, a + 1, a + n + 1], np.c_[a, a + n + 1, a + n]])
    return v, f.astype(np.int64)


def case_tutte(n: int, repeats: int) -> tuple[str, float, float, str, str]:
    v, f = lifted_grid(n)
    bnd = igl.boundary_loop(f)
    circle = igl.map_vertices_to_circle(v, bnd.astype(np.int32))
    pins = {"indices": bnd, "positions": circle}
    ours_t, ours = timed(lambda: laplacian((v, f), weighting="cotangent", pins=pins),
                         repeats)
    peer_t, theirs = timed(lambda: igl.harmonic(v, f, bnd, circle, 1), repeats)
    return (f"Tutte (cotangent) {len(v):,} vertices  vs igl.harmonic k=1", ours_t, peer_t,
            f"flipped {ours.flipped_faces}, |Δx| {np.abs(ours.positions - theirs).max():.1e}",
            "")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--quick", action="store_true", help="a fifth of the sizes")
    args = parser.parse_args()
    r = args.repeats
    n = 200 if args.quick else 1000
    d = distances(n)
    start = mds(d).positions
    defaults, sk_stress = case_defaults(d, start, r)
    rows = [
        case_classical(d, r),
        case_iterations(d, start, 100, r),
        defaults,
        case_same_stress(d, start, sk_stress, defaults[2], r),
        case_tutte(45 if args.quick else 224, r),
    ]
    print_ratio_table(rows, r)


if __name__ == "__main__":
    main()
