"""interpolation.affine: polar decomposition, slerp of R, lerp of S and the translation.

Hand-computed turns, endpoints reproduced, det > 0 all along the path, the shortest arc
(against scipy's Slerp), reflections passed through a flattened shape, and every error
branch."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation, Slerp

from algorithms.core.errors import DegenerateInputError, InvalidInputError
from algorithms.interpolation import affine
from tests.algorithms.interpolation.interp_meshes import random_rotation, rot2, tet_bar

SQUARE = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])


def _homogeneous(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    d = a.shape[0]
    t = np.eye(d + 1)
    t[:d, :d], t[:d, d] = a, b
    return t


def _spd(rng: np.random.Generator, d: int) -> np.ndarray:
    q = random_rotation(rng, d)
    return q @ np.diag(rng.uniform(0.2, 3.0, d)) @ q.T


# -- by hand --------------------------------------------------------------------------------
def test_quarter_turn_about_the_origin_by_hand() -> None:
    res = affine(SQUARE, transform=_homogeneous(rot2(np.pi / 2), np.zeros(2)),
                 times=[0.0, 0.5, 1.0], pivot="origin")
    h = np.sqrt(0.5)
    np.testing.assert_allclose(res.frames[1], [[0, 0], [h, h], [0, 2 * h], [-h, h]],
                               atol=1e-15)
    np.testing.assert_allclose(res.frames[2], [[0, 0], [0, 1], [-1, 1], [-1, 0]], atol=1e-15)
    assert res.angle == pytest.approx(np.pi / 2) and not res.reflection


def test_stretch_and_translation_move_linearly_by_hand() -> None:
    # A = diag(3, 1): R = I, S = A; at t = 1/2, S(t) = diag(2, 1); b(t) = t b (origin pivot)
    res = affine(SQUARE, transform=[[3, 0, 4], [0, 1, -2], [0, 0, 1]], times=[0.5],
                 pivot="origin")
    np.testing.assert_allclose(res.frames[0], SQUARE * [2, 1] + [2, -1], atol=1e-15)
    np.testing.assert_allclose(res.det, [2.0])
    np.testing.assert_allclose(res.rotation, np.eye(2), atol=1e-15)


def test_centroid_pivot_moves_the_centroid_on_a_straight_line() -> None:
    a = rot2(2.0) @ np.diag([2.0, 0.5])
    res = affine(SQUARE + 10.0, transform=_homogeneous(a, [1.0, -3.0]))
    c0 = (SQUARE + 10.0).mean(axis=0)
    c1 = a @ c0 + [1.0, -3.0]
    for t, frame in zip(res.times, res.frames):
        np.testing.assert_allclose(frame.mean(axis=0), (1 - t) * c0 + t * c1, atol=1e-12)


# -- endpoints and invariants ---------------------------------------------------------------
@pytest.mark.parametrize("d", [2, 3])
@pytest.mark.parametrize("pivot", ["centroid", "origin"])
def test_endpoints_are_the_inputs(d: int, pivot: str) -> None:
    rng = np.random.default_rng(d)
    x = rng.normal(size=(30, d)) * 5
    for _ in range(20):
        a = random_rotation(rng, d) @ _spd(rng, d)
        b = rng.normal(size=d) * 10
        res = affine(x, transform=_homogeneous(a, b), pivot=pivot)
        np.testing.assert_allclose(res.frames[0], x, atol=1e-10, rtol=0)
        np.testing.assert_allclose(res.frames[-1], x @ a.T + b, atol=1e-10, rtol=0)
        np.testing.assert_allclose(res.rotation @ res.stretch, a, atol=1e-12)


def test_fitted_map_lands_on_a_non_affine_target() -> None:
    rng = np.random.default_rng(1)
    x = rng.normal(size=(40, 3))
    y = x @ (random_rotation(rng) @ _spd(rng, 3)).T + rng.normal(size=(40, 3)) * 0.05
    res = affine(x, y)
    assert res.rmse > 0.01
    np.testing.assert_allclose(res.frames[0], x, atol=1e-12)
    np.testing.assert_allclose(res.frames[-1], y, atol=1e-12)


@pytest.mark.parametrize("d", [2, 3])
def test_det_stays_positive_along_the_path(d: int) -> None:
    rng = np.random.default_rng(10 + d)
    t = np.linspace(0, 1, 101)
    x = rng.normal(size=(d + 2, d))
    for _ in range(50):
        s = _spd(rng, d)
        a = random_rotation(rng, d) @ s
        res = affine(x, transform=_homogeneous(a, np.zeros(d)), times=t)
        lam = np.linalg.eigvalsh(s)
        expected = np.prod((1 - t)[:, None] + t[:, None] * lam, axis=1)
        np.testing.assert_allclose(res.det, expected, rtol=1e-10)
        assert (res.det > 0).all()
        # the frames' own volume ratio agrees (simplex of the first d + 1 points)
        vol = [np.linalg.det(f[1:d + 1] - f[0]) / np.linalg.det(x[1:d + 1] - x[0])
               for f in res.frames]
        np.testing.assert_allclose(vol, res.det, rtol=1e-8)


def test_rotation_path_is_scipy_slerp_shortest_arc() -> None:
    rng = np.random.default_rng(7)
    x = rng.normal(size=(10, 3))
    t = np.linspace(0, 1, 9)
    for _ in range(30):
        r = random_rotation(rng)
        res = affine(x, transform=_homogeneous(r, np.zeros(3)), times=t, pivot="origin")
        peer = Slerp([0, 1], Rotation.from_matrix([np.eye(3), r]))(t).as_matrix()
        np.testing.assert_allclose(res.frames, x @ np.swapaxes(peer, 1, 2), atol=1e-10)
        assert res.angle <= np.pi + 1e-12


def test_three_quarter_turn_goes_the_short_way() -> None:
    res = affine(SQUARE, transform=_homogeneous(rot2(1.5 * np.pi), np.zeros(2)),
                 times=[0.5], pivot="origin")
    np.testing.assert_allclose(res.frames[0], SQUARE @ rot2(-np.pi / 4).T, atol=1e-14)
    assert res.angle == pytest.approx(np.pi / 2)


def test_tetrahedra_are_accepted_and_keep_their_faces() -> None:
    v, t = tet_bar(nx=3)
    res = affine({"vertices": v, "faces": t}, transform=np.diag([2.0, 1.0, 0.5, 1.0]))
    assert res.faces.shape == t.shape and (res.faces == t).all()
    np.testing.assert_allclose(res.frames[-1], v * [2.0, 1.0, 0.5], atol=1e-12)


# -- reflections ----------------------------------------------------------------------------
def test_reflection_refused_by_default_naming_the_input() -> None:
    mirror = np.diag([1.0, -1.0, 1.0])
    with pytest.raises(DegenerateInputError, match="reflection") as info:
        affine(SQUARE, transform=mirror)
    assert info.value.field == "transform"
    with pytest.raises(DegenerateInputError, match="det A") as info:
        affine(SQUARE, SQUARE * [1, -1])
    assert info.value.field == "target"


def test_reflection_flip_flattens_once() -> None:
    a = np.array([[2.0, 0.0], [0.0, -0.5]])        # σ = (2, 0.5), det < 0
    res = affine(SQUARE, transform=_homogeneous(a, np.zeros(2)), reflection="flip",
                 times=[0.0, 0.5, 1 / 1.5, 0.9, 1.0], pivot="origin")
    assert res.reflection
    assert np.linalg.det(res.rotation) == pytest.approx(1.0)
    np.testing.assert_allclose(res.rotation @ res.stretch, a, atol=1e-14)
    # S has eigenvalues (2, -0.5): det S(t) = (1 + t)(1 - 1.5 t): zero at t = 1 / (1 + σ_d)
    assert res.det[1] > 0 and abs(res.det[2]) < 1e-14 and res.det[3] < 0
    np.testing.assert_allclose(res.frames[-1], SQUARE @ a.T, atol=1e-14)


# -- errors ---------------------------------------------------------------------------------
@pytest.mark.parametrize("times, match", [
    ([], "at least 1"),
    ([0.0, 1.5], r"\[0, 1\]"),
    ([-0.1, 0.5], r"\[0, 1\]"),
    ([0.0, float("nan")], r"\[0, 1\]"),
    ([0.5, 0.5], "strictly increasing"),
    ([[0.0, 1.0]], "flat list"),
    (["a"], "flat list"),
    (list(np.linspace(0, 1, 1002)), "at most 1001"),
])
def test_bad_times_are_named(times, match) -> None:  # noqa: ANN001
    with pytest.raises(InvalidInputError, match=match) as info:
        affine(SQUARE, transform=np.eye(3), times=times)
    assert info.value.field == "times"


@pytest.mark.parametrize("kwargs, field, match", [
    ({}, "target", "neither"),
    ({"target": SQUARE, "transform": np.eye(3)}, "transform", "both"),
    ({"transform": np.eye(4)}, "transform", r"\(3, 3\)"),
    ({"transform": [[1, 0, 0], [0, 1, 0], [0, 1, 1]]}, "transform", "last row"),
    ({"transform": [[1, 0, 0], [0, float("nan"), 0], [0, 0, 1]]}, "transform", "finite"),
    ({"target": SQUARE[:3]}, "target", "shape of the source"),
    ({"target": np.zeros((4, 3))}, "target", "shape of the source"),
    ({"transform": np.eye(3), "reflection": "mirror"}, "reflection", "reflection"),
    ({"transform": np.eye(3), "pivot": "corner"}, "pivot", "pivot"),
])
def test_errors_name_their_input(kwargs, field, match) -> None:  # noqa: ANN001
    with pytest.raises(InvalidInputError, match=match) as info:
        affine(SQUARE, **kwargs)
    assert info.value.field == field


def test_different_connectivity_is_refused_naming_target() -> None:
    f = [[0, 1, 2], [0, 2, 3]]
    with pytest.raises(InvalidInputError, match="same connectivity") as info:
        affine({"vertices": SQUARE, "faces": f},
               {"vertices": SQUARE * 2, "faces": [[0, 1, 3], [1, 2, 3]]})
    assert info.value.field == "target.faces"
    with pytest.raises(InvalidInputError, match="point set") as info:
        affine(SQUARE, {"vertices": SQUARE, "faces": f})
    assert info.value.field == "target"


def test_bad_source_is_named() -> None:
    with pytest.raises(InvalidInputError) as info:
        affine(np.zeros((4, 4)), transform=np.eye(5))
    assert info.value.field == "source"
    with pytest.raises(DegenerateInputError) as info:
        affine([[0, 0], [1, 1], [2, 2]], [[0, 0], [1, 0], [2, 0]])   # collinear source
    assert info.value.field == "source"
    with pytest.raises(InvalidInputError) as info:
        affine({"vertices": SQUARE, "faces": [[0, 1, 9]]}, transform=np.eye(3))
    assert info.value.field == "source.faces"
