"""The Laplacian core against libigl, and the sparse solver backends, in one run.

Prints three tables, every time the median of --repeats runs on the same data:

1. assembly on a 50,176-vertex mesh (ours and the peer called alternately): our cotangent Laplacian vs ``igl.cotmatrix`` (we return
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
import statistics
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT)]  # the packages first: tests/algorithms must not shadow algorithms

from algorithms.core.laplacian import cotangent_laplacian, mass_matrix  # noqa: E402
from algorithms.core.linalg import batched_rotations, procrustes  # noqa: E402
from algorithms.core.linsolve import Factor, available_backends  # noqa: E402
from algorithms.core.mesh import boundary_loops  # noqa: E402

import igl  # noqa: E402  libigl: the peer


def timed(fn: Callable[[], Any], repeats: int) -> tuple[float, Any]:
    """Median wall time of ``repeats`` calls, and the last call's value."""
    times, value = [], None
    for _ in range(repeats):
        t = time.perf_counter()
        value = fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times), value


def timed_pair(ours: Callable[[], Any], peer: Callable[[], Any], repeats: int
               ) -> tuple[float, Any, float, Any]:
    """Median wall times of ``ours`` and ``peer``, called alternately (so that a busy machine
    slows both alike), and the last values."""
    t_ours, t_peer, a, b = [], [], None, None
    for _ in range(repeats):
        t = time.perf_counter()
        a = ours()
        t_ours.append(time.perf_counter() - t)
        t = time.perf_counter()
        b = peer()
        t_peer.append(time.perf_counter() - t)
    return statistics.median(t_ours), a, statistics.median(t_peer), b


def wavy_grid(nx: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    x, y = np.meshgrid(np.linspace(0, 1, nx), np.linspace(0, 1, nx))
    v = np.c_[x.ravel(), y.ravel(), 0.1 * np.sin(6 * x.ravel()) * np.cos(5 * y.ravel())]
    v[:, :2] += rng.uniform(-0.3, 0.3, (nx * nx, 2)) / nx
    idx = np.arange(nx * nx).reshape(nx, nx)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel()
    return v, np.r_[np.c_[a, b, d], np.c_[a, d, c]].astype(np.int64)


def print_table(title: str, header: tuple[str, ...], rows: list[tuple[str, ...]],
                left: tuple[int, ...] = (0,)) -> None:
    table = [header, *rows]
    widths = [max(len(row[i]) for row in table) for i in range(len(header))]
    print(title)
    for i, row in enumerate(table):
        print("  ".join(cell.ljust(w) if j in left else cell.rjust(w)
                        for j, (cell, w) in enumerate(zip(row, widths, strict=True))))
        if i == 0:
            print("  ".join("-" * w for w in widths))
    print()


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
    lap = cotangent_laplacian(v, f)
    pinned = boundary_loops(f)[0]
    free = np.setdiff1d(np.arange(len(v)), pinned)
    a = lap[free][:, free].tocsc()
    b = np.random.default_rng(1).standard_normal((a.shape[0], 3))
    rows = []
    for backend in available_backends():
        fac_t, fac = timed(lambda backend=backend: Factor(a, backend=backend), r)
        sol_t, x = timed(lambda fac=fac: fac.solve(b), r)
        res = np.abs(a @ x - b).max() / np.abs(b).max()
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
                  f"{peer_t * 1e3:.1f}", f"{ours_t / peer_t:.2f}", f"{abs(ours - peer).max():.1e}")])


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
