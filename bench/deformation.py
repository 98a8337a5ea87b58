"""The deformation family against libigl, side by side in one run.

On one mesh of about 50,000 vertices (a jittered wavy grid made in code: obtuse triangles,
some negative cotangent weights; its left tenth held, its right tenth lifted and twisted),
prints, every time the median of --repeats runs with ours and libigl called alternately (so
that a busy machine slows both alike):

1. the cotangent Laplacian vs ``igl.cotmatrix`` (ours is ``-cotmatrix``: the difference
   column is ``max |ours + igl|``);
2. ARAP (spokes and rims, libigl's default for triangle meshes): the precomputation
   (``ArapSolver(...)`` vs ``igl.arap_precomputation``), 10 iterations from the rest shape
   (``solver.solve(..., max_iterations=10, tolerance=0)`` vs ``igl.arap_solve`` with
   ``max_iter = 10``), and both together;
3. harmonic and biharmonic deformation (``deformation.harmonic`` / ``biharmonic`` vs
   ``igl.harmonic(V, F, b, bc - V[b], k)`` with k = 1, 2), from the mesh to the deformed
   vertices;
4. the sparse Cholesky backends on ARAP's system (the free block of the cotangent
   Laplacian): factor time and the time of one solve with 3 right-hand sides.

Accuracy: the largest and the RMS distance between our vertices and libigl's, and for ARAP
that RMS relative to the RMS displacement (libigl fits rotations in single precision).

    python bench/deformation.py [--repeats 3] [--quick]

A benchmark never asserts.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
# the packages first (tests/algorithms must not shadow algorithms), then bench/ for _common
sys.path[:0] = [str(ROOT), str(ROOT / "bench")]

import igl  # noqa: E402  libigl: the peer
from _common import backend_timings, print_table, timed_pair, wavy_grid  # noqa: E402

from algorithms.core.laplacian import cotangent_laplacian  # noqa: E402
from algorithms.deformation import ArapSolver, biharmonic, harmonic  # noqa: E402


def handles(v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Left tenth held; right tenth lifted by 0.3 and turned 30° about the x axis."""
    left = np.flatnonzero(v[:, 0] < 0.1)
    right = np.flatnonzero(v[:, 0] > 0.9)
    t = np.radians(30.0)
    rot = np.array([[1, 0, 0], [0, np.cos(t), -np.sin(t)], [0, np.sin(t), np.cos(t)]])
    centre = np.array([0.95, 0.5, 0.0])
    moved = (v[right] - centre) @ rot.T + centre + [0.0, 0.0, 0.3]
    return np.r_[left, right], np.r_[v[left], moved]


def diff(ours: np.ndarray, peer: np.ndarray) -> tuple[float, float]:
    d = np.linalg.norm(ours - peer, axis=1)
    return float(d.max()), float(np.sqrt(np.mean(d * d)))


def row(name: str, ours_t: float, peer_t: float, accuracy: str) -> tuple[str, ...]:
    return (name, f"{ours_t:.3f}", f"{peer_t:.3f}", f"{ours_t / peer_t:.2f}", accuracy)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--quick", action="store_true", help="a tenth of the vertices")
    args = parser.parse_args()
    r = args.repeats
    nx = 71 if args.quick else 224                          # 5,041 or 50,176 vertices
    v, f = wavy_grid(nx)
    b, bc = handles(v)
    rows = []

    # 1. cotangent Laplacian
    ours_t, L, peer_t, Lp = timed_pair(lambda: cotangent_laplacian(v, f),
                                       lambda: igl.cotmatrix(v, f), r)
    rows.append(row("cotangent Laplacian vs igl.cotmatrix", ours_t, peer_t,
                    f"max |ours + igl| {abs(L + Lp).max():.1e}"))

    # 2. ARAP: precomputation, 10 iterations, both
    b32 = b.astype(np.int32)

    def igl_pre() -> Any:
        data = igl.ARAPData()
        data.energy = igl.ARAP_ENERGY_TYPE_SPOKES_AND_RIMS
        data.max_iter = 10
        igl.arap_precomputation(v, f, 3, b32, data)
        return data

    pre_t, solver, ipre_t, data = timed_pair(lambda: ArapSolver((v, f), b), igl_pre, r)
    it_t, res, iit_t, ref = timed_pair(
        lambda: solver.solve(bc, max_iterations=10, tolerance=0.0),
        lambda: igl.arap_solve(bc, data, v.copy()), r)
    x = res.mesh.vertices
    dmax, drms = diff(x, ref)
    disp = float(np.sqrt(np.mean(np.sum((ref - v) ** 2, axis=1))))
    acc = f"max {dmax:.1e}, RMS {drms:.1e} ({drms / disp:.1e} of the displacement)"
    rows.append(row("ARAP precompute vs igl.arap_precomputation", pre_t, ipre_t,
                    f"factor: {solver.factor.backend}"))
    rows.append(row("ARAP 10 iterations vs igl.arap_solve", it_t, iit_t, acc))
    rows.append(row("ARAP precompute + 10 iterations", pre_t + it_t, ipre_t + iit_t, acc))

    # 3. harmonic and biharmonic
    h = {"indices": b, "positions": bc}
    for k, fn in ((1, harmonic), (2, biharmonic)):
        ours_t, res, peer_t, w = timed_pair(
            lambda fn=fn: fn((v, f), h),
            lambda k=k: v + igl.harmonic(v, f, b, bc - v[b], k), r)
        dmax, drms = diff(res.mesh.vertices, w)
        rows.append(row(f"{fn.__name__} vs igl.harmonic(k={k})", ours_t, peer_t,
                        f"max {dmax:.1e}, RMS {drms:.1e}"))

    print(f"{len(v):,} vertices, {len(f):,} faces, {len(b):,} handles; median of {r} runs; "
          "ratio = ours / igl (below 1: we are faster)\n")
    print_table("deformation vs libigl", ("case", "ours (s)", "igl (s)", "ratio", "accuracy"),
                rows, left=(0, 4))

    # 4. solver backends on ARAP's system
    a, timings = backend_timings(v, f, b, r)
    brows = [(fac.backend, f"{fac_t:.3f}", f"{sol_t * 1e3:.1f}", f"{res_norm:.1e}")
             for _, fac, fac_t, sol_t, res_norm in timings]
    print_table(f"sparse Cholesky backends on ARAP's free block ({a.shape[0]:,} unknowns, "
                f"{a.nnz:,} non-zeros; median of {r})",
                ("backend", "factor (s)", "solve 3 rhs (ms)", "rel. residual"), brows)


if __name__ == "__main__":
    main()
