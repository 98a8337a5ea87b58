"""ABF++ rows for ``bench/parameterization.py``.

libigl has no angle-based flattening (CGAL's ``ABF_plus_plus_parameterizer_3`` is C++
only), so the peer column is ``igl.lscm`` with the same two pins as our layout step (the
farthest boundary pair): the map ABF is meant to improve on, timed in the same run. Two
disks: the benchmark's ``wavy_grid`` (nearly flat, jittered: many thin and obtuse
triangles) and the same grid with a four times higher wave (strongly curved). The quality
columns are flips / angle distortion / area distortion as in the other rows, ours followed
by the Newton iterations; the last column is the gradient norm reached.

    from _param_abf import case_abf
    rows += case_abf(args.repeats, args.quick)

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

import igl  # noqa: E402  libigl: the peer (its LSCM)
from _common import timed_pair, wavy_grid  # noqa: E402

from algorithms.parameterization import abf  # noqa: E402
from algorithms.parameterization._disk import read_disk  # noqa: E402
from algorithms.parameterization._quality import quality  # noqa: E402
from algorithms.parameterization.conformal import farthest_boundary_pair  # noqa: E402

__all__ = ["case_abf"]


def _figures(v: np.ndarray, f: np.ndarray, uv: np.ndarray) -> str:
    q = quality(v, f, uv)
    return f"{q.flipped_faces} / {q.angle_distortion:.4f} / {q.area_distortion:.4f}"


def case_abf(repeats: int, quick: bool) -> list[tuple[str, ...]]:
    """Rows ``(case, ours s, peer s, ratio, ours: quality, peer: quality, extra)`` for ABF
    (defaults: tolerance 1e-8, at most 20 iterations) against ``igl.lscm``, on the
    benchmark's disk (``wavy_grid(100)`` with ``quick``, else ``wavy_grid(224)``) and on the
    same grid with a four times higher wave."""
    nx = 100 if quick else 224
    rows: list[tuple[str, ...]] = []
    for label, amplitude in (("abf vs igl lscm", 1.0), ("abf vs igl lscm, 4x wave", 4.0)):
        v, f = wavy_grid(nx)
        v[:, 2] *= amplitude
        pins = farthest_boundary_pair(read_disk((v, f)))
        d = float(np.linalg.norm(v[pins[1]] - v[pins[0]]))
        bc = np.array([[0.0, 0.0], [d, 0.0]])
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            t_o, ours, t_p, peer = timed_pair(lambda v=v, f=f: abf((v, f)),
                                              lambda v=v, f=f, p=pins, bc=bc:
                                              igl.lscm(v, f, p, bc)[0],
                                              repeats)
        rows.append((label, f"{t_o:.3f}", f"{t_p:.3f}", f"{t_o / t_p:.2f}",
                     _figures(v, f, ours.uv) + f" / {ours.iterations} it.",
                     _figures(v, f, peer), f"|∇| {ours.gradient_norm[-1]:.1e}"))
    return rows


if __name__ == "__main__":
    from _common import print_table

    quick = "--quick" in sys.argv
    print_table("ABF++ vs libigl LSCM (time in s; flips / angle / area distortion)",
                ("method", "ours", "igl", "ratio", "ours: quality", "igl: quality", "extra"),
                case_abf(1, quick), left=(0, 4, 5))
