"""The Laplacian core against libigl, and the sparse solver backends, in one run.

Prints three tables, every time the median of --repeats runs on the same data:

1. assembly on a 50,176-vertex mesh (ours and the peer called alternately): our cotangent
   Laplacian vs ``igl.cotmatrix`` (we return
   ``L = D - W``, libigl ``W - D``: the accuracy column is ``max |ours + igl|``), our mass
   matrices vs ``igl.massmatrix`` (``max |ours - igl|``); ratio = ours / igl (below 1: we are
   faster);
2. the solver backends of :class:`algorithms.core.linsolve.Factor` on that mesh's cotangent
   Laplacian with its boundary pinned (the free block ``L_ff``, 49,284 unknowns): time to
   factor, time to solve 3 right-hand sides, relative residual ``‖L_ff x - b‖∞ / ‖b‖∞``;
   and whether scikit-sparse (CHOLMOD) is importable;
3. the ARAP local step: :func:`batched_rotations` on 50,176 3×3 matrices vs
   ``np.linalg.svd`` + the reflection fix, with the largest difference of the rotations.

    python bench/solvers.py [--repeats 5] [--quick]

The mesh is a jittered wavy grid (many obtuse triangles, some negative cotangent weights),
made in code. A benchmark never asserts.
"""

from __future__ import annotations

import argparse
import importlib.util
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
# the packages first (tests/algorithms must not shadow algorithms), then bench/ for _common
sys.path[:0] = [str(ROOT), str(ROOT / "bench")]

import igl  # noqa: E402  libigl: the peer
from _common import backend_timings, print_table, timed_pair, wavy_grid  # noqa: E402

from algorithms.core.laplacian import cotangent_laplacian, mass_matrix  # noqa: E402
from algorithms.core.linalg import batched_rotations, procrustes  # noqa: E402
from algorithms.core.linsolve import Factor  # noqa: E402
from algorithms.core.mesh import boundary_loops  # noqa: E402


def assembly(v: np.ndarray, f: np.ndarray, r: int) -> None:
    rows = []
    ours_t, ours, peer_t, peer = timed_pair(lambda: cotangent_laplacian(v, f),
                                            lambda: igl.cotmatrix(v, f), r)
    rows.append(("cotangent Laplacian vs igl.cotmatrix", f"{ours_t * 1e3:.1f}",
                 f"{peer_t * 1e3:.1f}", f"{ours_t / peer_t:.2f}", f"{abs(ours + peer).max():.1e}"))
    for kind, igl_type in (("voronoi", igl.MASSMATRIX_TYPE_VORONOI),
                           ("barycentric", igl.MASSMATRIX_TYPE_BARYCENTRIC)):
        ours_t, ours, peer_t, peer = timed_pair(lambda kind=kind: mass_matrix(v, f, kind),
                                                lambda t=igl_type: igl.massmatrix(v, f, t), r)
        rows.append((f"mass matrix ({kind}) vs igl.massmatrix", f"{ours_t * 1e3:.1f}",
                     f"{peer_t * 1e3:.1f}", f"{ours_t / peer_t:.2f}",
                     f"{abs(ours - peer).max():.1e}"))
    print_table(f"1. assembly, {len(v):,} vertices, {len(f):,} faces (median of {r})",
                ("case", "ours (ms)", "igl (ms)", "ratio", "max abs diff"), rows)


def solvers(v: np.ndarray, f: np.ndarray, r: int) -> None:
    a, timings = backend_timings(v, f, boundary_loops(f)[0], r)
    rows = []
    for backend, fac, fac_t, sol_t, res in timings:
        rows.append((backend + ("" if fac.backend == backend else f" (fell back to "
                                f"{fac.backend})"), f"{fac_t:.3f}", f"{sol_t * 1e3:.1f}",
                     f"{res:.1e}"))
    sks = "installed" if importlib.util.find_spec("sksparse") else \
        "not installable here (no wheel; needs SuiteSparse headers)"
    rows.append(("scikit-sparse (CHOLMOD)", "-", "-", sks))
    print_table(f"2. solver backends, pinned cotangent Laplacian: {a.shape[0]:,} unknowns, "
                f"{a.nnz:,} non-zeros (median of {r}); 'auto' picks "
                f"{Factor(np.eye(2)).backend}", ("backend", "factor (s)", "solve 3 rhs (ms)",
                                                 "rel. residual"), rows, left=(0, 3))


def rotations(n: int, r: int) -> None:
    s = np.random.default_rng(2).standard_normal((n, 3, 3))
    ours_t, ours, peer_t, peer = timed_pair(
        lambda: batched_rotations(s), lambda: procrustes(np.swapaxes(s, 1, 2)).rotation, r)
    print_table(f"3. ARAP local step, {n:,} 3×3 matrices (median of {r})",
                ("case", "ours (ms)", "svd (ms)", "ratio", "max abs diff"),
                [("batched_rotations vs np.linalg.svd + reflection fix", f"{ours_t * 1e3:.1f}",
                  f"{peer_t * 1e3:.1f}", f"{ours_t / peer_t:.2f}",
                  f"{abs(ours - peer).max():.1e}")])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--quick", action="store_true", help="a tenth of the vertices")
    args = parser.parse_args()
    nx = 71 if args.quick else 224                        # 5,041 or 50,176 vertices
    v, f = wavy_grid(nx)
    print("ratio = ours / peer (below 1: we are faster)\n")
    assembly(v, f, args.repeats)
    solvers(v, f, args.repeats)
    rotations(len(v), args.repeats)


if __name__ == "__main__":
    main()
