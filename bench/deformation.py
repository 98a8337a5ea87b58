"""The deformation family against libigl, side by side in one run.

On one mesh of about 50,000 vertices (``--quick`` 5,041, ``--large`` 200,704; a jittered
wavy grid made in code: obtuse triangles, some negative cotangent weights; its left tenth
held, its right tenth lifted and twisted), every row goes through ``_common.compare`` (ours
and libigl alternately after a warm-up, on the grids of seeds 0..2, the median and range of
the times, the threads allowed):

1. the cotangent Laplacian vs ``igl.cotmatrix`` (ours is ``-cotmatrix``: the difference
   column is ``max |ours + igl|``);
2. ARAP (spokes and rims, libigl's default for triangle meshes): the precomputation
   (``ArapSolver(...)`` vs ``igl.arap_precomputation``), 10 iterations from the rest shape
   (``solver.solve(..., max_iterations=10, tolerance=0)`` vs ``igl.arap_solve`` with
   ``max_iter = 10``), and both together (the one-shot ``arap(..., max_iterations=10,
   tolerance=0)``, which chooses its solver backend for 10 solves);
3. harmonic and biharmonic deformation (``deformation.harmonic`` / ``biharmonic`` vs
   ``igl.harmonic(V, F, b, bc - V[b], k)`` with k = 1, 2), from the mesh to the deformed
   vertices;
4. the sparse Cholesky backends on ARAP's system (the free block of the cotangent
   Laplacian): factor time and the time of one solve with 3 right-hand sides (a table of
   its own, ours against ours: ``bench/linsolve.py`` has the full comparison).

Accuracy: each side's residual of its own problem (the Laplacian's largest row sum; the
harmonic / biharmonic equations' relative residual for the displacement on the free
vertices, ``max |(L u)_i| / max (|L| |u|)_i``, and the handles' largest miss; ARAP's energy,
spokes and rims, computed here for both), and the agreement of the two (the largest and the
RMS distance between our vertices and libigl's, for ARAP relative to the RMS displacement:
libigl fits rotations in single precision).

    python bench/deformation.py [--quick | --large]

A benchmark never asserts.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

import numpy as np
import scipy.sparse as sp

ROOT = Path(__file__).resolve().parents[1]
# the packages first (tests/algorithms must not shadow algorithms), then bench/ for _common
sys.path[:0] = [str(ROOT), str(ROOT / "bench")]

import igl  # noqa: E402  libigl: the peer
from _common import (  # noqa: E402
    apply_policy,
    backend_timings,
    compare,
    print_table,
    report,
    wavy_grid,
)

from algorithms.core.laplacian import cotangent_laplacian  # noqa: E402
from algorithms.deformation import ArapSolver, arap, biharmonic, harmonic  # noqa: E402

FAMILY = "deformation"


def handles(v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Left tenth held; right tenth lifted by 0.3 and turned 30° about the x axis."""
    left = np.flatnonzero(v[:, 0] < 0.1)
    right = np.flatnonzero(v[:, 0] > 0.9)
    t = np.radians(30.0)
    rot = np.array([[1, 0, 0], [0, np.cos(t), -np.sin(t)], [0, np.sin(t), np.cos(t)]])
    centre = np.array([0.95, 0.5, 0.0])
    moved = (v[right] - centre) @ rot.T + centre + [0.0, 0.0, 0.3]
    return np.r_[left, right], np.r_[v[left], moved]


def diff(ours: np.ndarray, peer: np.ndarray) -> dict[str, float]:
    d = np.linalg.norm(ours - peer, axis=1)
    return {"max |Δx|": float(d.max()), "RMS |Δx|": float(np.sqrt(np.mean(d * d)))}


def arap_energy(v: np.ndarray, f: np.ndarray, x: np.ndarray) -> float:
    """ARAP's spokes-and-rims energy of ``x``: per vertex, the best rotation of its one-ring
    triangles' edges (cotangent weights, from the Laplacian's entries) and the weighted sum
    of squared residuals, rotations fitted here in double precision."""
    lap = cotangent_laplacian(v, f).tocoo()
    off = lap.row != lap.col
    i, j, w = lap.row[off], lap.col[off], -lap.data[off]
    e, ex = v[i] - v[j], x[i] - x[j]
    cov = np.zeros((len(v), 3, 3))
    np.add.at(cov, i, w[:, None, None] * ex[:, :, None] * e[:, None, :])
    u, _, vt = np.linalg.svd(cov)
    fix = np.ones((len(v), 3))
    fix[:, 2] = np.sign(np.linalg.det(u @ vt))
    rot = (u * fix[:, None, :]) @ vt
    r = ex - np.einsum("kab,kb->ka", rot[i], e)
    return float(0.5 * (w * np.einsum("ka,ka->k", r, r)).sum())


def mesh(nx: int) -> Any:
    def data(seed: int) -> dict[str, Any]:
        v, f = wavy_grid(nx, seed)
        b, bc = handles(v)
        return {"v": v, "f": f, "b": b, "bc": bc}
    return data


def case_laplacian(data: Any) -> None:
    compare(FAMILY, "cotangent Laplacian", data,
            lambda d: cotangent_laplacian(d["v"], d["f"]),
            lambda d: igl.cotmatrix(d["v"], d["f"]),
            lambda _d, L: {"max |row sum|": float(abs(L.sum(axis=1)).max())},
            agreement=lambda _d, a, b: {"max |ours + igl|": float(abs(a + b).max())},
            peer_name="igl.cotmatrix")


def case_arap(data: Any) -> None:
    def igl_pre(d: dict[str, Any]) -> Any:
        pre = igl.ARAPData()
        pre.energy = igl.ARAP_ENERGY_TYPE_SPOKES_AND_RIMS
        pre.max_iter = 10
        igl.arap_precomputation(d["v"], d["f"], 3, d["b"].astype(np.int32), pre)
        return pre

    def ours_pre(d: dict[str, Any]) -> Any:
        return ArapSolver((d["v"], d["f"]), d["b"])

    def ours_solve(d: dict[str, Any], solver: Any) -> np.ndarray:
        return solver.solve(d["bc"], max_iterations=10, tolerance=0.0).mesh.vertices

    def igl_solve(d: dict[str, Any], pre: Any) -> np.ndarray:
        return igl.arap_solve(d["bc"], pre, d["v"].copy())

    def with_factors(seed: int) -> dict[str, Any]:
        d = data(seed)
        d["solver"], d["pre"] = ours_pre(d), igl_pre(d)
        return d

    def energy(d: dict[str, Any], x: np.ndarray) -> dict[str, float]:
        return {"E": arap_energy(d["v"], d["f"], x)}

    def agree(d: dict[str, Any], a: np.ndarray, b: np.ndarray) -> dict[str, float]:
        disp = float(np.sqrt(np.mean(np.sum((b - d["v"]) ** 2, axis=1))))
        out = diff(a, b)
        out["RMS/disp"] = out["RMS |Δx|"] / disp
        return out

    compare(FAMILY, "ARAP precompute", data, ours_pre, igl_pre,
            peer_name="igl.arap_precomputation")
    compare(FAMILY, "ARAP 10 iterations (factors made outside)", with_factors,
            lambda d: ours_solve(d, d["solver"]), lambda d: igl_solve(d, d["pre"]), energy,
            agreement=agree, peer_name="igl.arap_solve")
    compare(FAMILY, "ARAP precompute + 10 iterations", data,
            lambda d: arap((d["v"], d["f"]), {"indices": d["b"], "positions": d["bc"]},
                           max_iterations=10, tolerance=0.0).mesh.vertices,
            lambda d: igl_solve(d, igl_pre(d)), energy,
            agreement=agree, peer_name="igl.arap_precomputation + arap_solve")


def case_harmonic(data: Any) -> None:
    for k, fn in ((1, harmonic), (2, biharmonic)):
        def residual(d: dict[str, Any], x: np.ndarray, k: int = k) -> dict[str, float]:
            lap = cotangent_laplacian(d["v"], d["f"])
            mass = igl.massmatrix(d["v"], d["f"], igl.MASSMATRIX_TYPE_VORONOI)
            op = lap if k == 1 else lap @ sp.diags(1.0 / mass.diagonal()) @ lap
            free = np.setdiff1d(np.arange(len(x)), d["b"])
            u = x - d["v"]                     # the displacement is the k-harmonic field
            r = (op @ u)[free]
            scale = abs(op).dot(np.abs(u))[free].max()
            return {"rel. residual": float(abs(r).max() / scale),
                    "max |x_b - bc|": float(abs(x[d["b"]] - d["bc"]).max())}

        compare(FAMILY, f"{fn.__name__} deformation", data,
                lambda d, fn=fn: fn((d["v"], d["f"]),
                                    {"indices": d["b"], "positions": d["bc"]}).mesh.vertices,
                lambda d, k=k: d["v"] + igl.harmonic(d["v"], d["f"], d["b"],
                                                     d["bc"] - d["v"][d["b"]], k),
                residual, agreement=lambda _d, a, b: diff(a, b),
                peer_name=f"igl.harmonic(k={k})")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="a tenth of the vertices")
    parser.add_argument("--large", action="store_true", help="four times the vertices "
                        "(200,704)")
    args = parser.parse_args()
    apply_policy()
    nx = 71 if args.quick else 448 if args.large else 224  # 5,041, 200,704 or 50,176
    data = mesh(nx)
    case_laplacian(data)
    case_arap(data)
    case_harmonic(data)
    report(f"deformation vs libigl, {nx * nx:,} vertices")

    # the solver backends on ARAP's system (ours against ours)
    d = data(0)
    a, timings = backend_timings(d["v"], d["f"], d["b"], 3)
    brows = [(fac.backend, f"{fac_t:.3f}", f"{sol_t * 1e3:.1f}", f"{res_norm:.1e}")
             for _, fac, fac_t, sol_t, res_norm in timings]
    print()
    print_table(f"sparse Cholesky backends on ARAP's free block ({a.shape[0]:,} unknowns, "
                f"{a.nnz:,} non-zeros; median of 3)",
                ("backend", "factor (s)", "solve 3 rhs (ms)", "rel. residual"), brows)


if __name__ == "__main__":
    main()
