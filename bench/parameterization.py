"""The parameterization family against libigl, side by side in one run.

On one disk of about 50,000 vertices (``wavy_grid(224)``: a jittered wavy grid, some obtuse
triangles), prints our time, libigl's time, their ratio and the distortion of each (flipped
faces, angle distortion, area distortion, the figures every parameterization reports), the
median of --repeats runs with ours and libigl called alternately:

1. LSCM with the same two pins (the farthest boundary pair): ``conformal(mesh)`` vs
   ``igl.lscm`` given those pins;
2. harmonic onto the circle: ``harmonic(mesh)`` vs ``igl.boundary_loop`` +
   ``igl.map_vertices_to_circle`` + ``igl.harmonic(..., 1)``;
3. ARAP parameterization, 10 iterations from the same harmonic start, one vertex held in
   both: precomputation plus iterations (``LocalGlobalSolver`` + ``solve(max_iterations=10,
   tolerance=0)`` vs ``igl.arap_precomputation`` + ``igl.arap_solve``, libigl's per-element
   energy for 2-D targets); the energy column is Σ A_t‖J_t − R_t‖² of each result.

Times are end to end from (V, F): mesh checks and quality figures included on our side.

    python bench/parameterization.py [--repeats 3] [--quick]

A benchmark never asserts.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "bench")]

import igl  # noqa: E402  libigl: the peer
from _common import print_table, timed_pair, wavy_grid  # noqa: E402

from algorithms.parameterization import conformal, harmonic  # noqa: E402
from algorithms.parameterization._disk import read_disk  # noqa: E402
from algorithms.parameterization._local_global import (  # noqa: E402
    LocalGlobalSolver,
    fit_transforms,
    initial_map,
    local_global_energy,
)
from algorithms.parameterization._quality import face_frames, jacobians, quality  # noqa: E402
from algorithms.parameterization.conformal import farthest_boundary_pair  # noqa: E402


def figures(v: np.ndarray, f: np.ndarray, uv: np.ndarray) -> str:
    q = quality(v, f, uv)
    return f"{q.flipped_faces} / {q.angle_distortion:.4f} / {q.area_distortion:.4f}"


def arap_energy(v: np.ndarray, f: np.ndarray, uv: np.ndarray) -> float:
    fr = face_frames(v, f)
    J = jacobians(fr, f, uv)
    return local_global_energy(0.5 * fr[:, 1, 0] * fr[:, 2, 1], J, fit_transforms(J, False))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--quick", action="store_true", help="a 10,000-vertex disk")
    args = ap.parse_args()
    nx = 100 if args.quick else 224
    v, f = wavy_grid(nx)
    print(f"disk: {len(v)} vertices, {len(f)} faces; median of {args.repeats} runs\n")
    rows = []

    disk = read_disk((v, f))
    pins = farthest_boundary_pair(disk)
    d = float(np.linalg.norm(v[pins[1]] - v[pins[0]]))
    bc = np.array([[0.0, 0.0], [d, 0.0]])
    t_o, ours, t_p, peer = timed_pair(lambda: conformal((v, f)),
                                      lambda: igl.lscm(v, f, pins, bc)[0], args.repeats)
    rows.append(("lscm", f"{t_o:.3f}", f"{t_p:.3f}", f"{t_o / t_p:.2f}",
                 figures(v, f, ours.uv), figures(v, f, peer),
                 f"{np.abs(ours.uv - peer).max():.1e}"))

    def igl_harmonic() -> np.ndarray:
        loop = igl.boundary_loop(f)
        return igl.harmonic(v, f, loop, igl.map_vertices_to_circle(v, loop), 1)

    t_o, ours, t_p, peer = timed_pair(lambda: harmonic((v, f)), igl_harmonic, args.repeats)
    rows.append(("harmonic", f"{t_o:.3f}", f"{t_p:.3f}", f"{t_o / t_p:.2f}",
                 figures(v, f, ours.uv), figures(v, f, peer),
                 f"{np.abs(ours.uv - peer).max():.1e}"))

    uv0 = initial_map(disk, "harmonic")
    pin = disk.loop[:1]

    def ours_arap():  # noqa: ANN202
        solver = LocalGlobalSolver(disk.mesh, pin, similarity=False)
        return solver.solve(uv0, max_iterations=10, tolerance=0)

    def igl_arap() -> np.ndarray:
        data = igl.ARAPData()
        data.max_iter = 10
        data.energy = igl.ARAP_ENERGY_TYPE_ELEMENTS
        igl.arap_precomputation(v, f, 2, pin.astype(np.int32), data)
        return igl.arap_solve(uv0[pin], data, uv0)

    t_o, ours, t_p, peer = timed_pair(ours_arap, igl_arap, args.repeats)
    rows.append(("arap (10 it.)", f"{t_o:.3f}", f"{t_p:.3f}", f"{t_o / t_p:.2f}",
                 figures(v, f, ours.uv) + f" / E {ours.energy[-1]:.6g}",
                 figures(v, f, peer) + f" / E {arap_energy(v, f, peer):.6g}",
                 f"{np.abs(ours.uv - peer).max():.1e}"))
    from _param_abf import case_abf  # noqa: PLC0415

    rows += case_abf(args.repeats, args.quick)
    from _param_extra import case_stretch_bijective  # noqa: PLC0415

    rows += case_stretch_bijective(args.repeats, args.quick)
    print_table("parameterization vs libigl (time in s; flips / angle / area distortion)",
                ("method", "ours", "igl", "ratio", "ours: quality", "igl: quality",
                 "max |Δuv|"), rows, left=(0, 4, 5))


if __name__ == "__main__":
    main()
