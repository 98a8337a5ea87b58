"""Tutte and harmonic parameterizations: hand cases, the convex-combination and no-flip
invariants, mean value linear precision, and agreement with igl.harmonic."""

from __future__ import annotations

import igl
import numpy as np
import pytest
from tests.algorithms.parameterization.param_meshes import bumpy, cap, grid

from algorithms.core.errors import DegenerateInputError, InvalidInputError
from algorithms.core.mesh import signed_areas
from algorithms.parameterization import harmonic, tutte
from algorithms.parameterization._disk import read_disk
from algorithms.parameterization.tutte import _mean_value_solve, mean_value_weights

FAN_V = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0.5, 0.5, 0.3]]
FAN_F = [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]


def test_fan_by_hand() -> None:
    # the centre of a symmetric fan lands at the centre of the circle and of the square
    for fn in (lambda m: tutte(m), lambda m: tutte(m, weighting="mean_value"),
               lambda m: harmonic(m), lambda m: harmonic(m, boundary="square")):
        res = fn((FAN_V, FAN_F))
        np.testing.assert_allclose(res.uv[4], [0, 0], atol=1e-14)
        assert res.flipped_faces == 0 and res.degenerate_faces == 0
        assert res.pinned.tolist() == [0, 1, 2, 3]
    res = tutte((FAN_V, FAN_F), boundary="circle")
    np.testing.assert_allclose(res.uv[:4], [[1, 0], [0, 1], [-1, 0], [0, -1]], atol=1e-14)


@pytest.mark.parametrize("boundary", ["circle", "square"])
@pytest.mark.parametrize("weighting", ["uniform", "mean_value"])
@pytest.mark.parametrize("seed", range(5))
def test_tutte_never_flips(boundary: str, weighting: str, seed: int) -> None:
    v, f = bumpy(seed=seed)
    res = tutte((v, f), boundary=boundary, weighting=weighting)
    assert res.flipped_faces == 0 and res.degenerate_faces == 0
    assert (signed_areas(res.uv, f) > 0).all()       # counter-clockwise, as the input
    if boundary == "square":
        assert np.abs(res.uv).max() <= 1 + 1e-12
        on_side = np.isclose(np.abs(res.uv[res.pinned]), 1.0, atol=1e-12).any(axis=1)
        assert on_side.all()


def test_uniform_tutte_is_the_barycentre_of_neighbours() -> None:
    v, f = bumpy()
    res = tutte((v, f))
    inner = np.setdiff1d(np.arange(len(v)), res.pinned)
    from algorithms.core.laplacian import uniform_weights
    w = uniform_weights(len(v), f)
    avg = (w @ res.uv) / np.asarray(w.sum(axis=1)).reshape(-1, 1)
    np.testing.assert_allclose(res.uv[inner], avg[inner], atol=1e-13)


def test_mean_value_weights_reproduce_a_planar_mesh() -> None:
    # linear precision: boundary pinned to its own (convex) outline gives the mesh back
    v, f = grid(9, 7, jitter=0.3, seed=3)
    disk = read_disk((v, f))
    uv = _mean_value_solve(disk.mesh, disk.loop, v[disk.loop])
    np.testing.assert_allclose(uv, v, atol=1e-12)
    w = mean_value_weights(v, f)
    assert w.data.min() > 0


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
    with pytest.raises(InvalidInputError, match="`boundary`"):
        tutte((FAN_V, FAN_F), boundary="hexagon")
    with pytest.raises(InvalidInputError, match="`weighting`"):
        tutte((FAN_V, FAN_F), weighting="cotangent")
    with pytest.raises(DegenerateInputError, match="at least 4 boundary vertices"):
        harmonic(([[0, 0], [1, 0], [0, 1]], [[0, 1, 2]]), boundary="square")
