"""interpolation.poisson (Xu et al. 2005): endpoints reproduced, bars bent by half a turn
and beyond keep their edge lengths (rotations unwrapped across the mesh) where the linear
blend and the linear interpolation of Laplacian coordinates shrink them, and tetrahedra."""

from __future__ import annotations

import numpy as np
import pytest

from algorithms.core.laplacian import cotangent_laplacian
from algorithms.core.linsolve import PinnedSystem
from algorithms.interpolation import poisson
from algorithms.interpolation._common import edge_errors, edges_of
from tests.algorithms.interpolation.interp_meshes import (
    bar,
    bend2,
    linear_blend_error,
    roll3,
    strip3,
    tet_bar,
)

T = np.linspace(0.0, 1.0, 11)


def _mesh(v: np.ndarray, f: np.ndarray) -> dict:
    return {"vertices": v, "faces": f}


@pytest.mark.parametrize("kind", ["bar", "strip", "tets"])
def test_endpoints_are_the_inputs(kind: str) -> None:
    v, f = {"bar": bar, "strip": strip3, "tets": tet_bar}[kind]()
    w = bend2(v, 4.0) if kind == "bar" else roll3(v, 4.0)
    res = poisson(_mesh(v, f), _mesh(w, f), times=[0.0, 0.3, 1.0])
    np.testing.assert_allclose(res.frames[0], v, atol=1e-10, rtol=0)
    np.testing.assert_allclose(res.frames[-1], w, atol=1e-10, rtol=0)


@pytest.mark.parametrize("kind", ["bar", "strip", "tets"])
@pytest.mark.parametrize("turns", [0.5, 0.75, 0.95])
def test_bent_bar_keeps_its_lengths_past_half_a_turn(kind: str, turns: float) -> None:
    v, f = {"bar": bar, "strip": strip3, "tets": tet_bar}[kind]()
    angle = 2 * np.pi * turns
    w = bend2(v, angle) if kind == "bar" else roll3(v, angle)
    res = poisson(_mesh(v, f), _mesh(w, f), times=T)
    assert res.max_edge_error.max() < 0.05
    assert res.min_det.min() > 0.5
    assert res.max_angle == pytest.approx(angle, rel=0.05)   # continuous, beyond π
    assert linear_blend_error(v, w, f, T) > 0.5


def test_linear_laplacian_coordinates_are_the_linear_blend() -> None:
    # Solving L x = lerp(L p0, L p1) with the anchor on its line gives
    # exactly the linear blend (interpolation and L commute): it shrinks the bar, which is
    # why the gradients, not the Laplacian coordinates, are interpolated.
    v, f = bar()
    w = bend2(v, np.pi)
    lap = cotangent_laplacian(v, f)
    system = PinnedSystem(lap, [0])
    frames = np.array([system.solve(((1 - t) * v + t * w)[[0]], lap @ ((1 - t) * v + t * w))
                       for t in T])
    np.testing.assert_allclose(frames, [(1 - t) * v + t * w for t in T], atol=1e-10)
    blend = edge_errors(frames, T, v, w, edges_of(v, f)).max()
    ours = poisson(_mesh(v, f), _mesh(w, f), times=T).max_edge_error.max()
    assert blend > 0.5 > 0.05 > ours


def test_rigid_motion_past_half_a_turn_is_the_shortest_arc_for_everyone() -> None:
    # a whole mesh turned by 3/4 of a turn: every face alike, so the short way (-1/4)
    v, f = bar(nx=6)
    c, s = np.cos(1.5 * np.pi), np.sin(1.5 * np.pi)
    w = v @ np.array([[c, -s], [s, c]]).T
    res = poisson(_mesh(v, f), _mesh(w, f), times=T)
    assert res.max_angle == pytest.approx(np.pi / 2)
    assert res.max_edge_error.max() < 1e-10
