"""The parameterization family against libigl, through the harness of ``_common.compare``.

Every row: ours and libigl alternately after a warm-up, on the disks of seeds 0..2
(``wavy_grid(nx, seed)``: 50,176 vertices, ``--quick`` 10,000, ``--large`` 200,704), the
median and range of the times, the threads allowed, and the quality of each side's map on
every seed (flipped faces, angle distortion, area distortion, and the energy the method
minimises where it has one), with the agreement of the two maps (the largest ``|Δuv|`` after
the best rigid motion of the plane, since the two sides may start the boundary loop
elsewhere).

Both sides start from the mesh (vertices and faces) every call: our time includes reading
the mesh into a disk, finding the pins and the starting map; libigl's includes
``boundary_loop``, its pins and its starting map, so neither side gets a step for free.

- LSCM: ``conformal`` vs ``igl.lscm`` with the same two pins (the farthest boundary pair,
  found by libigl's side on its own boundary loop);
- harmonic onto the circle: ``harmonic`` vs ``igl.harmonic`` of
  ``map_vertices_to_circle``;
- ARAP, 10 iterations from the harmonic map scaled to the surface's area: ``arap(...,
  init="harmonic", max_iterations=10, tolerance=0)`` vs the harmonic map, its scaling,
  ``igl.arap_precomputation`` and ``igl.arap_solve`` (one pinned vertex each);
- ABF++ vs ``igl.lscm`` (``_param_abf``), bijective vs SLIM and stretch-minimizing vs
  ``igl.harmonic`` (``_param_extra``), on this disk and on its four-times-wavier twin.

    python bench/parameterization.py [--quick | --large]

A benchmark never asserts.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

import numpy as np
from scipy.spatial.distance import cdist

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "bench")]

import igl  # noqa: E402  libigl: the peer
from _common import apply_policy, compare, report, wavy_grid  # noqa: E402

from algorithms.parameterization import arap, conformal, harmonic  # noqa: E402
from algorithms.parameterization._local_global import (  # noqa: E402
    fit_transforms,
    local_global_energy,
)
from algorithms.parameterization._quality import face_frames, jacobians, quality  # noqa: E402

FAMILY = "parameterization"


def disk(nx: int, amplitude: float = 1.0) -> Any:
    """The data of one seed: a jittered wavy grid, its wave scaled by ``amplitude``."""
    def data(seed: int) -> dict[str, Any]:
        v, f = wavy_grid(nx, seed)
        v[:, 2] *= amplitude
        return {"v": v, "f": f}
    return data


def figures(d: dict[str, Any], uv: np.ndarray) -> dict[str, float]:
    """Flipped faces, angle and area distortion of a map."""
    q = quality(d["v"], d["f"], uv)
    return {"flips": q.flipped_faces, "angle": q.angle_distortion, "area": q.area_distortion}


def rigid_gap(_d: Any, a: np.ndarray, b: np.ndarray) -> dict[str, float]:
    """The largest ``|Δuv|`` between two maps after the best rigid motion of ``b`` onto
    ``a`` (reflections allowed: the pins may be taken in either order)."""
    am, bm = a - a.mean(axis=0), b - b.mean(axis=0)
    u, _, vt = np.linalg.svd(bm.T @ am)
    return {"max |Δuv|": float(np.linalg.norm(bm @ (u @ vt) - am, axis=1).max())}


def igl_pins(v: np.ndarray, f: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """libigl's side of the pins: its boundary loop's two vertices farthest apart, placed
    at (0, 0) and (distance, 0)."""
    loop = igl.boundary_loop(f)
    dist = cdist(v[loop], v[loop], "sqeuclidean")
    i, j = np.unravel_index(int(np.argmax(dist)), dist.shape)
    pins = loop[[i, j]]
    return pins, np.array([[0.0, 0.0], [float(np.sqrt(dist[i, j])), 0.0]])


def igl_circle(v: np.ndarray, f: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """libigl's harmonic map onto the circle, and its boundary loop."""
    loop = igl.boundary_loop(f)
    return igl.harmonic(v, f, loop, igl.map_vertices_to_circle(v, loop), 1), loop


def area_scale(v: np.ndarray, f: np.ndarray, uv: np.ndarray) -> np.ndarray:
    """``uv`` scaled so that its area equals the surface's (the ARAP starts of both sides)."""
    surf = 0.5 * np.linalg.norm(np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]]),
                                axis=1).sum()
    e1, e2 = uv[f[:, 1]] - uv[f[:, 0]], uv[f[:, 2]] - uv[f[:, 0]]
    plane = abs(0.5 * (e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]).sum())
    return uv * np.sqrt(surf / plane)


def arap_energy(d: dict[str, Any], uv: np.ndarray) -> dict[str, float]:
    """The quality figures and ARAP's energy of the map (the same function for both)."""
    fr = face_frames(d["v"], d["f"])
    J = jacobians(fr, d["f"], uv)
    e = local_global_energy(0.5 * fr[:, 1, 0] * fr[:, 2, 1], J, fit_transforms(J, False))
    return {**figures(d, uv), "E": e}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="a 10,000-vertex disk")
    ap.add_argument("--large", action="store_true", help="a 200,704-vertex disk")
    args = ap.parse_args()
    apply_policy()
    nx = 100 if args.quick else 448 if args.large else 224
    data = disk(nx)
    size = f"{nx * nx:,} vertices"

    def igl_lscm(d: dict[str, Any]) -> np.ndarray:
        pins, bc = igl_pins(d["v"], d["f"])
        return igl.lscm(d["v"], d["f"], pins, bc)[0]

    compare(FAMILY, f"lscm, {size}", data, lambda d: conformal((d["v"], d["f"])).uv,
            igl_lscm, figures, agreement=rigid_gap, peer_name="igl.lscm")
    compare(FAMILY, f"harmonic (circle), {size}", data,
            lambda d: harmonic((d["v"], d["f"])).uv,
            lambda d: igl_circle(d["v"], d["f"])[0], figures, agreement=rigid_gap,
            peer_name="igl.harmonic k=1 of map_vertices_to_circle")

    def igl_arap(d: dict[str, Any]) -> np.ndarray:
        v, f = d["v"], d["f"]
        uv0, loop = igl_circle(v, f)
        uv0 = area_scale(v, f, uv0)
        pre = igl.ARAPData()
        pre.max_iter = 10
        pre.energy = igl.ARAP_ENERGY_TYPE_ELEMENTS
        pin = loop[:1].astype(np.int32)
        igl.arap_precomputation(v, f, 2, pin, pre)
        return igl.arap_solve(uv0[pin], pre, uv0)

    compare(FAMILY, f"arap 10 it. from the harmonic map, {size}", data,
            lambda d: arap((d["v"], d["f"]), init="harmonic", max_iterations=10,
                           tolerance=0).uv,
            igl_arap, arap_energy, agreement=rigid_gap,
            peer_name="igl harmonic + arap_precomputation + arap_solve")
    from _param_abf import case_abf  # noqa: PLC0415

    case_abf(nx)
    from _param_extra import case_stretch_bijective  # noqa: PLC0415

    case_stretch_bijective(nx)
    report(f"parameterization vs libigl, {size}")


if __name__ == "__main__":
    main()
