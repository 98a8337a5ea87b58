"""The layout family against its peers, side by side in one run.

Every row goes through ``_common.compare``: ours and the peer alternately after a warm-up,
on the data of seeds 0..2, the median and range of the times, the threads allowed, and the
figure each reaches on every seed (a stress, or the largest difference of positions), so
that speed is never bought with accuracy unseen.

    python bench/layout.py [--quick]

Cases (1,000 points in 6-D drawn per seed, distances laid out in 2-D; 200 with --quick):

- classical MDS vs scikit-learn ``ClassicalMDS(metric="precomputed")``;
- SMACOF from the same start (classical MDS), 100 iterations each (no early stop) vs
  ``sklearn.manifold.smacof``: the cost of an iteration;
- SMACOF with each library's default stopping rule (ours: relative decrease 1e-6;
  scikit-learn: eps 1e-6 of the sum of squared distances), same start;
- ours with the relaxed update (relaxation 1.9) run just until its stress is at most
  scikit-learn's default result (the iterations found beforehand, outside the timing)
  against scikit-learn's default run: the time to the same stress;
- Tutte/harmonic layout of a lifted 224 × 224 grid (50,176 vertices; 45 × 45 with --quick)
  with cotangent weights and the boundary on the circle vs ``igl.harmonic(V, F, b, bc, 1)``
  (the boundary and its circle made outside the timing, the same for both).

A benchmark never asserts.
"""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path
from typing import Any

import numpy as np
from scipy.spatial.distance import cdist

ROOT = Path(__file__).resolve().parents[1]
# the packages first (tests/algorithms must not shadow algorithms), then bench/ for _common
sys.path[:0] = [str(ROOT), str(ROOT / "bench")]

import igl  # noqa: E402
from _common import apply_policy, compare, report  # noqa: E402
from sklearn.manifold import ClassicalMDS, smacof  # noqa: E402

from algorithms.core import ConvergenceWarning  # noqa: E402
from algorithms.layout import laplacian, mds, stress  # noqa: E402

warnings.simplefilter("ignore", ConvergenceWarning)


FAMILY = "layout"


def raw_stress(x: np.ndarray, d: np.ndarray) -> float:
    diff = cdist(x, x) - d
    return 0.5 * float(np.vdot(diff, diff))


def distances(n: int, seed: int = 0) -> np.ndarray:
    x = np.random.default_rng(seed).standard_normal((n, 6))
    return cdist(x, x)


def problem(n: int) -> Any:
    """The data of one seed: the distances and the classical MDS start."""
    def data(seed: int) -> dict[str, Any]:
        d = distances(n, seed)
        return {"d": d, "start": mds(d).positions}
    return data


def stress_of(p: dict[str, Any], x: np.ndarray) -> dict[str, float]:
    return {"stress": raw_stress(x, p["d"])}


def case_classical(n: int) -> None:
    compare(FAMILY, f"classical MDS {n:,} points", problem(n),
            lambda p: mds(p["d"]).positions,
            lambda p: ClassicalMDS(n_components=2, metric="precomputed").fit_transform(p["d"]),
            stress_of, peer_name="sklearn ClassicalMDS",
            agreement=lambda _p, a, b: {"max |Δx|": float(np.abs(a - b).max())})


def case_iterations(n: int, iters: int) -> None:
    compare(FAMILY, f"SMACOF {n:,} points, {iters} iterations, same start", problem(n),
            lambda p: stress(p["d"], weighting="uniform", initial_positions=p["start"],
                             max_iterations=iters, tolerance=0.0).positions,
            lambda p: smacof(p["d"], init=p["start"], n_init=1, max_iter=iters, eps=0.0)[0],
            stress_of, peer_name="sklearn smacof")


def case_defaults(n: int) -> None:
    def ours(p: dict[str, Any]) -> Any:
        res = stress(p["d"], weighting="uniform", initial_positions=p["start"])
        return res.positions, res.iterations

    def peer(p: dict[str, Any]) -> Any:
        x, _, it = smacof(p["d"], init=p["start"], n_init=1, return_n_iter=True)
        return x, it

    compare(FAMILY, f"SMACOF {n:,} points, default stopping, same start", problem(n), ours,
            peer, lambda p, r: {**stress_of(p, r[0]), "it": r[1]}, peer_name="sklearn smacof")


def case_same_stress(n: int) -> None:
    base = problem(n)

    def data(seed: int) -> dict[str, Any]:
        p = base(seed)
        x = smacof(p["d"], init=p["start"], n_init=1)[0]
        target = raw_stress(x, p["d"])
        probe = stress(p["d"], weighting="uniform", initial_positions=p["start"],
                       relaxation=1.9, max_iterations=3000, tolerance=0.0)
        below = np.flatnonzero(probe.stress_history <= target)   # raw stress, as sklearn's
        p["iters"] = int(below[0]) if below.size else probe.iterations
        return p

    def ours(p: dict[str, Any]) -> np.ndarray:
        return stress(p["d"], weighting="uniform", initial_positions=p["start"],
                      relaxation=1.9, max_iterations=max(p["iters"], 1),
                      tolerance=0.0).positions

    compare(FAMILY, f"SMACOF {n:,} points to sklearn's default stress (relaxation 1.9)",
            data, ours, lambda p: smacof(p["d"], init=p["start"], n_init=1)[0], stress_of,
            peer_name="sklearn smacof (defaults)")


def lifted_grid(n: int) -> tuple[np.ndarray, np.ndarray]:
    x, y = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n))
    z = 0.2 * np.sin(6 * x) * np.cos(5 * y)
    v = np.c_[x.ravel(), y.ravel(), z.ravel()]
    i, j = np.meshgrid(np.arange(n - 1), np.arange(n - 1), indexing="ij")
    a = (i * n + j).ravel()
    f = np.concatenate([np.c_[a, a + 1, a + n + 1], np.c_[a, a + n + 1, a + n]])
    return v, f.astype(np.int64)


def case_tutte(n: int) -> None:
    def data(seed: int) -> dict[str, Any]:
        v, f = lifted_grid(n)
        v[:, :2] += np.random.default_rng(seed).uniform(-0.2, 0.2, (len(v), 2)) / n
        bnd = igl.boundary_loop(f)
        return {"v": v, "f": f, "b": bnd, "bc": igl.map_vertices_to_circle(v, bnd)}

    def ours(g: dict[str, Any]) -> np.ndarray:
        return laplacian((g["v"], g["f"]), weighting="cotangent",
                         pins={"indices": g["b"], "positions": g["bc"]}).positions

    compare(FAMILY, f"Tutte (cotangent) {n * n:,} vertices", data, ours,
            lambda g: igl.harmonic(g["v"], g["f"], g["b"], g["bc"], 1), None,
            peer_name="igl.harmonic k=1",
            agreement=lambda _g, a, b: {"max |Δx|": float(np.abs(a - b).max())})


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="a fifth of the sizes")
    args = parser.parse_args()
    apply_policy()
    n = 200 if args.quick else 1000
    case_classical(n)
    case_iterations(n, 100)
    case_defaults(n)
    case_same_stress(n)
    case_tutte(45 if args.quick else 224)
    report(FAMILY)


if __name__ == "__main__":
    main()
