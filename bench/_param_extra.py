"""Stretch-minimizing and bijective parameterization rows for ``bench/parameterization.py``.

1. ``bijective`` against ``igl.slim_precompute`` + ``igl.slim_solve`` (symmetric Dirichlet,
   free boundary, no constraints), the same number of iterations from the same flip-free
   start (our mean value Tutte map onto the circle, scaled to the surface's area), setup
   included on both sides; the quality columns add the area-weighted mean symmetric
   Dirichlet energy (4 for an isometry) and the boundary crossings of each map.
2. ``stretch_minimizing`` (Yoshizawa et al.: defaults, circle boundary) against the map it
   is meant to improve on that libigl has, ``igl.harmonic`` onto the same circle (libigl has
   no stretch minimisation); the quality columns add Sander et al.'s normalised L2 stretch
   of each.

Both on the benchmark's disk (``wavy_grid(100)`` with ``quick``, else ``wavy_grid(224)``,
about 50,000 vertices) and on the same grid with a four times higher wave (strongly curved).

    from _param_extra import case_stretch_bijective
    rows += case_stretch_bijective(args.repeats, args.quick)

A benchmark never asserts.
"""

from __future__ import annotations

import sys
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
for _p in (str(ROOT), str(ROOT / "bench")):
    if _p not in sys.path:
        sys.path.insert(0, _p)

import igl  # noqa: E402  libigl: the peer (SLIM, harmonic)
from _common import timed_pair, wavy_grid  # noqa: E402

from algorithms.parameterization import stretch_minimizing  # noqa: E402
from algorithms.parameterization._disk import read_disk  # noqa: E402
from algorithms.parameterization._quality import quality  # noqa: E402
from algorithms.parameterization.bijective import (  # noqa: E402
    BijectiveSolver,
    boundary_crossings,
    symmetric_dirichlet,
    tutte_start,
)
from algorithms.parameterization.stretch import l2_stretch  # noqa: E402

__all__ = ["case_stretch_bijective"]

#: SLIM iterations on each side.
ITERATIONS = 10


def _figures(v: np.ndarray, f: np.ndarray, uv: np.ndarray) -> str:
    q = quality(v, f, uv)
    return f"{q.flipped_faces} / {q.angle_distortion:.4f} / {q.area_distortion:.4f}"


def case_stretch_bijective(repeats: int, quick: bool) -> list[tuple[str, ...]]:
    """Rows ``(case, ours s, peer s, ratio, ours: quality, peer: quality, extra)``:
    bijective vs igl SLIM (``ITERATIONS`` each) and stretch_minimizing vs igl harmonic, on
    the benchmark's disk and on its four-times-wavier twin."""
    nx = 100 if quick else 224
    rows: list[tuple[str, ...]] = []
    for tag, amplitude in (("", 1.0), (", 4x wave", 4.0)):
        v, f = wavy_grid(nx)
        v[:, 2] *= amplitude
        f32 = np.asfortranarray(f.astype(np.int32))
        disk = read_disk((v, f))
        uv0 = tutte_start(disk)

        def ours_bij(disk=disk, uv0=uv0):  # noqa: ANN001, ANN202
            return BijectiveSolver(disk, uv0).solve(uv0, max_iterations=ITERATIONS,
                                                    tolerance=0)

        def igl_slim(v=v, uv0=uv0, f32=f32) -> np.ndarray:  # noqa: ANN001
            data = igl.slim_precompute(np.asfortranarray(v), f32, np.asfortranarray(uv0),
                                       igl.SYMMETRIC_DIRICHLET, np.zeros(0, dtype=np.int32),
                                       np.zeros((0, 2)), 0.0)
            return igl.slim_solve(data, ITERATIONS)

        t_o, ours, t_p, peer = timed_pair(ours_bij, igl_slim, repeats)
        rows.append((f"bijective vs igl slim ({ITERATIONS} it.){tag}", f"{t_o:.3f}",
                     f"{t_p:.3f}", f"{t_o / t_p:.2f}",
                     _figures(v, f, ours.uv) + f" / SD {ours.symmetric_dirichlet:.6f}",
                     _figures(v, f, peer) + f" / SD {symmetric_dirichlet(v, f, peer):.6f}",
                     f"crossings {ours.boundary_crossings} / "
                     f"{boundary_crossings(peer, disk.loop)}"))

        def igl_harmonic(v=v, f=f) -> np.ndarray:  # noqa: ANN001
            loop = igl.boundary_loop(f)
            return igl.harmonic(v, f, loop, igl.map_vertices_to_circle(v, loop), 1)

        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            t_o, ours, t_p, peer = timed_pair(lambda v=v, f=f: stretch_minimizing((v, f)),
                                              igl_harmonic, repeats)
        rows.append((f"stretch_minimizing vs igl harmonic{tag}", f"{t_o:.3f}", f"{t_p:.3f}",
                     f"{t_o / t_p:.2f}",
                     _figures(v, f, ours.uv) + f" / L2 {ours.l2_stretch:.4f}",
                     _figures(v, f, peer) + f" / L2 {l2_stretch(v, f, peer):.4f}",
                     f"{ours.iterations} it."))
    return rows


if __name__ == "__main__":
    from _common import print_table

    quick = "--quick" in sys.argv
    print_table("stretch / bijective vs libigl (time in s; flips / angle / area distortion)",
                ("method", "ours", "igl", "ratio", "ours: quality", "igl: quality", "extra"),
                case_stretch_bijective(1, quick), left=(0, 4, 5))
