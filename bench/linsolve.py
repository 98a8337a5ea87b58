"""The sparse positive definite backends (real and Hermitian), side by side, on our systems.

Four systems, each at about 5k, 50k and 200k vertices, all made in code:

* ``laplacian``: the cotangent Laplacian of a jittered wavy grid with its boundary pinned
  (harmonic and biharmonic deformation, Tutte and Laplacian layout: factor once, solve once);
* ``arap``: the ARAP global step's free block, the cotangent Laplacian of a torus
  (``trimesh.creation.torus``, a closed surface) with 8 handle patches pinned (1 % of the
  vertices); ARAP reuses one factorization for every iteration, 3 right-hand sides a solve;
* ``lscm``: the conformal energy matrix ``Q`` of LSCM (``2n × 2n``: ``u_x`` and ``u_y``
  coupled through the boundary's area term) on the wavy grid, two boundary vertices pinned;
* ``lscm_complex``: the same energy as the ``n × n`` Hermitian ``K`` of the complex unknowns
  ``u_x + i u_y`` (``Q`` is its real form), what LSCM solves; the backends that factor
  complex matrices only (not cholespy or qdldl), complex right-hand sides.

Backends: every one that is installed of ``cholmod`` (SuiteSparse CHOLMOD through cvxopt,
GPL-3.0), ``cholespy`` (CHOLMOD compiled in: GPL-2.0), ``superlu`` (SciPy, BSD-3-Clause) through
:class:`algorithms.core.linsolve.Factor`, and ``qdldl`` (Apache-2.0; LDLᵀ with an AMD
ordering, one thread; not a backend of ``Factor``) called directly.

Factor and solve are timed separately (the solve of 1 and of 3 right-hand sides). Runs are
interleaved: each repeat factors and solves with every backend in turn, so a busy machine
slows them alike, and a backend's figure is the median over the repeats; the ratio column
is the backend's time over the fastest one's in the same table, which is what means
something on a shared machine. The threads each library may use, the machine's load
average before and after each table, and the relative residual ``‖A x - b‖∞ / ‖b‖∞`` are
printed too.

    python bench/linsolve.py [--repeats 3] [--sizes 5k,50k,200k]
        [--systems laplacian,arap,lscm,lscm_complex]

A benchmark never asserts.
"""

from __future__ import annotations

import argparse
import importlib.metadata
import importlib.util
import os
import statistics
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import scipy.sparse as sp

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "bench")]

import trimesh  # noqa: E402
from _common import print_table, wavy_grid  # noqa: E402

from algorithms.core.laplacian import cotangent_laplacian  # noqa: E402
from algorithms.core.linsolve import Factor, available_backends  # noqa: E402
from algorithms.core.mesh import as_mesh, boundary_loops  # noqa: E402
from algorithms.parameterization.conformal import (  # noqa: E402
    conformal_energy_hermitian,
    conformal_energy_matrix,
)

#: grid side and torus sections for each size (vertices: nx², major × minor)
SIZES = {"5k": (71, (100, 50)), "50k": (224, (316, 158)), "200k": (448, (632, 316))}


class _Qdldl:
    """qdldl's LDLᵀ (it takes the upper triangle and solves one column at a time)."""

    name = "qdldl"

    def __init__(self, a: sp.csc_array) -> None:
        import qdldl

        self._s = qdldl.Solver(sp.csc_matrix(sp.triu(a, format="csc")), upper=True)

    def solve(self, b: np.ndarray) -> np.ndarray:
        if b.ndim == 1:
            return self._s.solve(b)
        return np.stack([self._s.solve(np.ascontiguousarray(b[:, j]))
                         for j in range(b.shape[1])], axis=1)


def backends() -> list[tuple[str, Callable[[sp.csc_array], Any]]]:
    """Every installed candidate: ``(name, factor function)``."""
    out: list[tuple[str, Callable[[sp.csc_array], Any]]] = [
        (b, lambda a, b=b: Factor(a, backend=b)) for b in available_backends()]
    if importlib.util.find_spec("qdldl") is not None:
        out.append(("qdldl", _Qdldl))
    return out


def free_block(a: sp.csr_array, pinned: np.ndarray) -> sp.csc_array:
    free = np.setdiff1d(np.arange(a.shape[0]), pinned)
    return a[free][:, free].tocsc()


def system(kind: str, size: str) -> tuple[str, sp.csc_array]:
    """The matrix of ``kind`` at ``size`` and a description of it."""
    nx, (major, minor) = SIZES[size]
    if kind == "arap":
        t = trimesh.creation.torus(1.0, 0.35, major_sections=major, minor_sections=minor)
        v, f = np.asarray(t.vertices), np.asarray(t.faces, dtype=np.int64)
        n = len(v)
        # 8 patches of handles, evenly round the torus: the vertices nearest 8 centres
        centres = v[np.linspace(0, n - 1, 8).astype(np.int64)]
        d = np.linalg.norm(v[:, None, :] - centres[None, :, :], axis=2)
        pinned = np.unique(np.argsort(d, axis=0)[: max(1, n // 800)].ravel())
        return (f"ARAP free block, torus {n:,} vertices, {len(pinned)} pinned",
                free_block(cotangent_laplacian(v, f), pinned))
    v, f = wavy_grid(nx)
    n = len(v)
    if kind == "laplacian":
        return (f"cotangent Laplacian, grid {n:,} vertices, boundary pinned",
                free_block(cotangent_laplacian(v, f), boundary_loops(f)[0]))
    loop = boundary_loops(f)[0]
    pins = loop[[0, len(loop) // 2]]
    if kind == "lscm_complex":
        return (f"LSCM matrix K (Hermitian), grid {n:,} vertices (n complex unknowns), "
                "2 pinned", free_block(conformal_energy_hermitian(as_mesh(v, f)), pins))
    q = conformal_energy_matrix(as_mesh(v, f))
    return (f"LSCM matrix Q, grid {n:,} vertices (2n unknowns), 2 pinned",
            free_block(q, np.concatenate([pins, n + pins])))


def threads() -> str:
    """The thread pools the libraries may use."""
    available_backends()  # imports every backend, so that their BLAS libraries are listed
    parts = [f"cpus={os.cpu_count()}"]
    try:
        from threadpoolctl import threadpool_info

        for p in threadpool_info():
            parts.append(f"{p['internal_api']}({Path(p['filepath']).name})={p['num_threads']}")
    except ImportError:  # pragma: no cover
        pass
    parts.append("cholespy=all cores (its own pool); superlu, qdldl=1; multifrontal=its "
                 "BLAS's (the openblas above)")
    return ", ".join(parts)


def load() -> str:
    return "/".join(f"{x:.2f}" for x in os.getloadavg())


def version(dist: str) -> str:
    try:
        return importlib.metadata.version(dist)
    except importlib.metadata.PackageNotFoundError:
        return "-"


def bench(kind: str, size: str, repeats: int) -> None:
    desc, a = system(kind, size)
    rng = np.random.default_rng(1)
    b1 = rng.standard_normal(a.shape[0])
    b3 = rng.standard_normal((a.shape[0], 3))
    cands = backends()
    if a.dtype.kind == "c":  # complex right-hand sides; cholespy and qdldl are real only
        b1 = b1 + 1j * rng.standard_normal(a.shape[0])
        b3 = b3 + 1j * rng.standard_normal((a.shape[0], 3))
        cands = [(n, make) for n, make in cands
                 if n not in ("cholespy", "qdldl", "multifrontal")]
    times: dict[str, dict[str, list[float]]] = {n: {"f": [], "s1": [], "s3": []}
                                                 for n, _ in cands}
    res: dict[str, float] = {}
    used: dict[str, str] = {}
    before = load()
    for _ in range(repeats):
        for name, make in cands:
            t = time.perf_counter()
            fac = make(a)
            times[name]["f"].append(time.perf_counter() - t)
            t = time.perf_counter()
            fac.solve(b1)
            times[name]["s1"].append(time.perf_counter() - t)
            t = time.perf_counter()
            x = fac.solve(b3)
            times[name]["s3"].append(time.perf_counter() - t)
            res[name] = float(np.abs(a @ x - b3).max() / np.abs(b3).max())
            used[name] = getattr(fac, "backend", name)
            del fac
    med = {n: {k: statistics.median(v) for k, v in d.items()} for n, d in times.items()}
    best = {k: min(m[k] for m in med.values()) for k in ("f", "s1", "s3")}
    dists = {"cholmod": "cvxopt", "cholespy": "cholespy", "superlu": "scipy", "qdldl": "qdldl",
             "multifrontal": "morphserve"}
    rows = []
    for name, m in med.items():
        label = f"{name} ({dists[name]} {version(dists[name])})"
        if used[name] != name:
            label += f" -> {used[name]}"
        rows.append((label, f"{m['f']:.3f}", f"{m['f'] / best['f']:.2f}",
                     f"{m['s1'] * 1e3:.1f}", f"{m['s3'] * 1e3:.1f}",
                     f"{m['s3'] / best['s3']:.2f}", f"{res[name]:.0e}"))
    print_table(f"{desc}: {a.shape[0]:,} unknowns, {a.nnz:,} non-zeros; median of {repeats} "
                f"interleaved runs; load {before} -> {load()}",
                ("backend", "factor (s)", "x best", "solve 1 (ms)", "solve 3 (ms)", "x best",
                 "residual"), rows)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--sizes", default="5k,50k,200k")
    parser.add_argument("--systems", default="laplacian,arap,lscm,lscm_complex")
    args = parser.parse_args()
    print(f"threads: {threads()}")
    for size in args.sizes.split(","):
        for kind in args.systems.split(","):
            bench(kind, size, args.repeats)


if __name__ == "__main__":
    main()
