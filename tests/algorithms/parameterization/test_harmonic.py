"""Harmonic parameterization: a hand case, agreement with igl.harmonic, no flips on a
Delaunay disk, zero distortion for an exact similarity."""

from __future__ import annotations

import igl
import numpy as np
import pytest

from algorithms.core.errors import DegenerateInputError, InvalidInputError
from algorithms.parameterization import harmonic, tutte
from tests.algorithms.parameterization.param_meshes import bumpy, cap

FAN_V = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0.5, 0.5, 0.3]]
FAN_F = [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]


def test_fan_by_hand() -> None:
    # the centre of a symmetric fan lands at the centre of the circle and of the square
    for boundary in ("circle", "square"):
        res = harmonic((FAN_V, FAN_F), boundary=boundary)
        np.testing.assert_allclose(res.uv[4], [0, 0], atol=1e-14)
        assert res.flipped_faces == 0 and res.degenerate_faces == 0
        assert res.pinned.tolist() == [0, 1, 2, 3]


@pytest.mark.parametrize("boundary", ["circle", "square"])
def test_harmonic_equals_igl(boundary: str) -> None:
    v, f = bumpy(seed=1)
    res = harmonic((v, f), boundary=boundary)
    peer = igl.harmonic(v, f.astype(np.int64), res.pinned, res.uv[res.pinned], 1)
    np.testing.assert_allclose(res.uv, peer, atol=1e-12)
    if boundary == "circle":  # our boundary is igl's map_vertices_to_circle
        circ = igl.map_vertices_to_circle(v, res.pinned)
        np.testing.assert_allclose(res.uv[res.pinned], circ, atol=1e-12)
    lap = -igl.cotmatrix(v, f)
    assert res.energy == pytest.approx(float(np.sum(res.uv * (lap @ res.uv))), rel=1e-12)


@pytest.mark.parametrize("boundary", ["circle", "square"])
def test_harmonic_no_flips_on_a_delaunay_disk(boundary: str) -> None:
    v, f = cap()
    res = harmonic((v, f), boundary=boundary)
    assert res.flipped_faces == 0 and res.degenerate_faces == 0
    assert res.angle_distortion < tutte((v, f), boundary=boundary).angle_distortion


def test_distortion_of_an_exact_similarity_is_zero() -> None:
    # a regular fan flattened onto the circle: the harmonic map of a planar regular fan
    # with its boundary on its own circle is the identity up to scale
    t = 2 * np.pi * np.arange(6) / 6
    v = np.r_[[[0, 0]], np.c_[np.cos(t), np.sin(t)]] * 3.0
    f = np.array([[0, 1 + k, 1 + (k + 1) % 6] for k in range(6)])
    res = harmonic((v, f))
    assert res.angle_distortion == pytest.approx(0, abs=1e-12)
    assert res.area_distortion == pytest.approx(0, abs=1e-12)


def test_errors() -> None:
    with pytest.raises(InvalidInputError, match="Expected `boundary` to be one of 'circle', "
                       "'square', got 'hexagon'"):
        harmonic((FAN_V, FAN_F), boundary="hexagon")
    with pytest.raises(DegenerateInputError, match="at least 4 boundary vertices"):
        harmonic(([[0, 0], [1, 0], [0, 1]], [[0, 1, 2]]), boundary="square")
