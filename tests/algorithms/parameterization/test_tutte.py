"""Tutte's embedding: hand cases, the convex-combination and no-flip invariants, mean value
linear precision."""

from __future__ import annotations

import numpy as np
import pytest

from algorithms.core.errors import InvalidInputError
from algorithms.core.mesh import signed_areas
from algorithms.parameterization import tutte
from algorithms.parameterization._disk import read_disk
from algorithms.parameterization.tutte import _mean_value_solve, mean_value_weights
from tests.algorithms.parameterization.param_meshes import bumpy, grid

FAN_V = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0.5, 0.5, 0.3]]
FAN_F = [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]


def test_fan_by_hand() -> None:
    # the centre of a symmetric fan lands at the centre of the circle and of the square
    for kwargs in ({}, {"weighting": "mean_value"}, {"boundary": "square"}):
        res = tutte((FAN_V, FAN_F), **kwargs)
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


def test_errors() -> None:
    with pytest.raises(InvalidInputError, match="Expected `boundary` to be one of 'circle', "
                       "'square', got 'hexagon'"):
        tutte((FAN_V, FAN_F), boundary="hexagon")
    with pytest.raises(InvalidInputError, match="Expected `weighting` to be one of 'uniform', "
                       "'mean_value', got 'cotangent'"):
        tutte((FAN_V, FAN_F), weighting="cotangent")
