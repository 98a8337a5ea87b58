"""ABF++ rows for ``bench/parameterization.py``.

libigl has no angle-based flattening (CGAL's ``ABF_plus_plus_parameterizer_3`` is C++
only), so the peer is ``igl.lscm`` with the farthest boundary pair pinned: the map ABF is
meant to improve on. Two disks: the benchmark's ``wavy_grid`` (nearly flat, jittered: many
thin and obtuse triangles) and the same grid with a four times higher wave (strongly
curved). Figures: flips, angle and area distortion of each map, ours with its Newton
iterations and the gradient norm reached.

    from _param_abf import case_abf
    case_abf(nx)

A benchmark never asserts.
"""

from __future__ import annotations

from typing import Any

import igl  # libigl: the peer (its LSCM)
import numpy as np
from _common import compare  # bench/ is on the path (run by parameterization.py)
from parameterization import FAMILY, disk, figures, igl_pins, rigid_gap

from algorithms.parameterization import abf

__all__ = ["case_abf"]


def case_abf(nx: int) -> None:
    """ABF (defaults: tolerance 1e-8, at most 20 iterations) against ``igl.lscm`` on the
    benchmark's disk and on its four-times-wavier twin."""

    def ours(d: dict[str, Any]) -> Any:
        return abf((d["v"], d["f"]))

    def ours_figures(d: dict[str, Any], res: Any) -> dict[str, float]:
        return {**figures(d, res.uv), "it": res.iterations, "|∇|": res.gradient_norm[-1]}

    def igl_lscm(d: dict[str, Any]) -> np.ndarray:
        pins, bc = igl_pins(d["v"], d["f"])
        return igl.lscm(d["v"], d["f"], pins, bc)[0]

    def both(d: dict[str, Any], x: Any) -> dict[str, float]:
        return figures(d, x) if isinstance(x, np.ndarray) else ours_figures(d, x)

    for tag, amplitude in (("", 1.0), (", 4x wave", 4.0)):
        compare(FAMILY, f"abf, {nx * nx:,} vertices{tag}", disk(nx, amplitude), ours,
                igl_lscm, both, agreement=lambda d, a, b: rigid_gap(d, a.uv, b),
                peer_name="igl.lscm")
