"""Bijective and stretch-minimizing parameterization rows for ``bench/parameterization.py``.

1. ``bijective`` (10 SLIM iterations, no early stop) against ``igl.slim_precompute`` +
   ``igl.slim_solve`` (symmetric Dirichlet, free boundary, no constraints, 10 iterations),
   each from its own flip-free start made in the timed call: ours its mean value Tutte map
   onto the circle, libigl's side the uniform Tutte map onto ``map_vertices_to_circle``
   (``adjacency_matrix`` and one sparse solve, what libigl's SLIM tutorial does), both
   scaled to the surface's area. The figures add the area-weighted mean symmetric
   Dirichlet energy (4 for an isometry) and the boundary crossings of each map.
2. ``stretch_minimizing`` (Yoshizawa et al.: defaults, circle boundary) against the map it
   is meant to improve on that libigl has, ``igl.harmonic`` onto the same circle (libigl has
   no stretch minimisation); the figures add Sander et al.'s normalised L2 stretch.

Both on the benchmark's disk and on the same grid with a four times higher wave.

    from _param_extra import case_stretch_bijective
    case_stretch_bijective(nx)

A benchmark never asserts.
"""

from __future__ import annotations

from typing import Any

import igl  # libigl: the peer (SLIM, harmonic)
import numpy as np
import scipy.sparse as sp
from _common import compare  # bench/ is on the path (run by parameterization.py)
from parameterization import FAMILY, area_scale, disk, figures, igl_circle, rigid_gap
from scipy.sparse.linalg import spsolve

from algorithms.parameterization import bijective, stretch_minimizing
from algorithms.parameterization.bijective import boundary_crossings, symmetric_dirichlet
from algorithms.parameterization.stretch import l2_stretch

__all__ = ["case_stretch_bijective"]

#: SLIM iterations on each side.
ITERATIONS = 10


def uniform_tutte(v: np.ndarray, f: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The uniform (graph Laplacian) Tutte map onto libigl's circle, and the loop."""
    loop = igl.boundary_loop(f)
    circle = igl.map_vertices_to_circle(v, loop)
    adj = igl.adjacency_matrix(f).astype(np.float64).tocsr()
    lap = sp.diags(np.asarray(adj.sum(axis=1)).ravel()) - adj
    free = np.setdiff1d(np.arange(len(v)), loop)
    uv = np.zeros((len(v), 2))
    uv[loop] = circle
    rhs = -(lap[free][:, loop] @ circle)
    uv[free] = spsolve(lap[free][:, free].tocsc(), rhs)
    return uv, loop


def case_stretch_bijective(nx: int) -> None:
    """bijective vs igl SLIM and stretch_minimizing vs igl harmonic, on the benchmark's disk
    and on its four-times-wavier twin."""

    def igl_slim(d: dict[str, Any]) -> np.ndarray:
        v, f = d["v"], d["f"]
        uv0, _ = uniform_tutte(v, f)
        uv0 = area_scale(v, f, uv0)
        data = igl.slim_precompute(np.asfortranarray(v), np.asfortranarray(f.astype(np.int32)),
                                   np.asfortranarray(uv0), igl.SYMMETRIC_DIRICHLET,
                                   np.zeros(0, dtype=np.int32), np.zeros((0, 2)), 0.0)
        return igl.slim_solve(data, ITERATIONS)

    def sd(d: dict[str, Any], uv: np.ndarray) -> dict[str, float]:
        loop = igl.boundary_loop(d["f"])
        return {**figures(d, uv), "SD": symmetric_dirichlet(d["v"], d["f"], uv),
                "crossings": boundary_crossings(uv, loop)}

    def l2(d: dict[str, Any], uv: np.ndarray) -> dict[str, float]:
        return {**figures(d, uv), "L2": l2_stretch(d["v"], d["f"], uv)}

    for tag, amplitude in (("", 1.0), (", 4x wave", 4.0)):
        data = disk(nx, amplitude)
        size = f"{nx * nx:,} vertices{tag}"
        compare(FAMILY, f"bijective ({ITERATIONS} it.), {size}", data,
                lambda d: bijective((d["v"], d["f"]), max_iterations=ITERATIONS,
                                    tolerance=0).uv,
                igl_slim, sd, agreement=rigid_gap,
                peer_name="igl uniform Tutte + slim_precompute + slim_solve")
        compare(FAMILY, f"stretch_minimizing, {size}", data,
                lambda d: stretch_minimizing((d["v"], d["f"])).uv,
                lambda d: igl_circle(d["v"], d["f"])[0], l2,
                peer_name="igl.harmonic k=1 (circle): the map it improves on")
