"""The Laplacian core against libigl, and the sparse solver backends, in one run.

1. and 3. go through ``_common.compare`` (ours and the peer alternately after a warm-up, on
the meshes of seeds 0..2, median and range, the threads allowed); 2. is a table of its own
(ours against ours, the median of 3):

1. assembly on a 50,176-vertex mesh (``--quick`` 5,041, ``--large`` 200,704): our cotangent
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

    python bench/solvers.py [--quick | --large]

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
from _common import (  # noqa: E402
    apply_policy,
    backend_timings,
    compare,
    print_table,
    report,
    wavy_grid,
)

from algorithms.core.laplacian import cotangent_laplacian, mass_matrix  # noqa: E402
from algorithms.core.linalg import batched_rotations, procrustes  # noqa: E402
from algorithms.core.linsolve import Factor  # noqa: E402
from algorithms.core.mesh import boundary_loops  # noqa: E402

FAMILY = "solvers"


def assembly(nx: int) -> None:
    def mesh(seed: int) -> tuple[np.ndarray, np.ndarray]:
        return wavy_grid(nx, seed)

    compare(FAMILY, f"cotangent Laplacian, {nx * nx:,} vertices", mesh,
            lambda m: cotangent_laplacian(*m), lambda m: igl.cotmatrix(*m), None,
            agreement=lambda _m, a, b: {"max |ours + igl|": float(abs(a + b).max())},
            peer_name="igl.cotmatrix")
    for kind, igl_type in (("voronoi", igl.MASSMATRIX_TYPE_VORONOI),
                           ("barycentric", igl.MASSMATRIX_TYPE_BARYCENTRIC)):
        compare(FAMILY, f"mass matrix ({kind}), {nx * nx:,} vertices", mesh,
                lambda m, kind=kind: mass_matrix(*m, kind),
                lambda m, t=igl_type: igl.massmatrix(*m, t), None,
                agreement=lambda _m, a, b: {"max |ours - igl|": float(abs(a - b).max())},
                peer_name="igl.massmatrix")


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


def rotations(n: int) -> None:
    compare(FAMILY, f"ARAP local step, {n:,} 3×3 matrices",
            lambda seed: np.random.default_rng(seed).standard_normal((n, 3, 3)),
            batched_rotations, lambda s: procrustes(np.swapaxes(s, 1, 2)).rotation, None,
            agreement=lambda _s, a, b: {"max |Δ|": float(abs(a - b).max())},
            peer_name="np.linalg.svd + reflection fix")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="a tenth of the vertices")
    parser.add_argument("--large", action="store_true", help="four times the vertices "
                        "(200,704)")
    args = parser.parse_args()
    apply_policy()
    nx = 71 if args.quick else 448 if args.large else 224  # 5,041, 200,704 or 50,176
    assembly(nx)
    rotations(nx * nx)
    report(FAMILY)
    print()
    v, f = wavy_grid(nx)
    solvers(v, f, 3)


if __name__ == "__main__":
    main()
