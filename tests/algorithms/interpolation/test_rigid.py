"""interpolation.rigid: a rigid motion or similarity, fitted (Kabsch / Umeyama) or given,
moved along the shortest arc with the pivot on a straight line and the scale geometric."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation, Slerp

from algorithms.core.errors import InvalidInputError
from algorithms.interpolation import affine, rigid
from tests.algorithms.interpolation.interp_meshes import random_rotation, rot2, strip3

SQUARE = np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]])


def _pairwise(x: np.ndarray) -> np.ndarray:
    return np.linalg.norm(x[:, None] - x[None], axis=-1)


def test_quarter_turn_and_shift_by_hand() -> None:
    y = SQUARE @ rot2(np.pi / 2).T + [5.0, 0.0]
    res = rigid(SQUARE, y, times=[0.0, 0.5, 1.0])
    # centroid (1, 1) -> (4, 1); half-way: (2.5, 1), turned by 45 degrees about it
    c = np.array([2.5, 1.0])
    np.testing.assert_allclose(res.frames[1], (SQUARE - 1.0) @ rot2(np.pi / 4).T + c,
                               atol=1e-12)
    np.testing.assert_allclose(res.frames[2], y, atol=1e-12)
    assert res.scale == 1.0 and res.rmse < 1e-12


@pytest.mark.parametrize("d", [2, 3])
def test_random_rigid_motions_stay_rigid_and_hit_both_ends(d: int) -> None:
    rng = np.random.default_rng(d)
    x = rng.normal(size=(25, d)) * 3
    for _ in range(30):
        r = random_rotation(rng, d)
        y = x @ r.T + rng.normal(size=d) * 10
        res = rigid(x, y)
        np.testing.assert_allclose(res.frames[0], x, atol=1e-10)
        np.testing.assert_allclose(res.frames[-1], y, atol=1e-10)
        np.testing.assert_allclose(res.rotation, r, atol=1e-10)
        for frame in res.frames:                     # every frame is congruent to x
            np.testing.assert_allclose(_pairwise(frame), _pairwise(x), atol=1e-9)
        assert res.max_edge_error.max() < 1e-10 and res.angle <= np.pi + 1e-12


def test_rotation_follows_scipy_slerp() -> None:
    rng = np.random.default_rng(3)
    x = rng.normal(size=(12, 3))
    t = np.linspace(0, 1, 7)
    for _ in range(20):
        r = random_rotation(rng)
        b = rng.normal(size=3)
        res = rigid(x, transform=np.block([[r, b[:, None]], [np.zeros((1, 3)), np.ones((1, 1))]]),
                    times=t, pivot="origin")
        peer = Slerp([0, 1], Rotation.from_matrix([np.eye(3), r]))(t).as_matrix()
        expected = np.einsum("tij,nj->tni", peer, x) + t[:, None, None] * b
        np.testing.assert_allclose(res.frames, expected, atol=1e-10)


def test_similarity_scales_geometrically() -> None:
    rng = np.random.default_rng(4)
    x = rng.normal(size=(20, 3))
    r = random_rotation(rng)
    y = 4.0 * x @ r.T + [1.0, 2.0, 3.0]
    t = np.linspace(0, 1, 5)
    res = rigid(x, y, scale=True, times=t)
    assert res.scale == pytest.approx(4.0)
    for ti, frame in zip(t, res.frames):
        np.testing.assert_allclose(_pairwise(frame), 4.0 ** ti * _pairwise(x), atol=1e-9)
    np.testing.assert_allclose(res.frames[-1], y, atol=1e-10)
    # the same map through affine: the same rotation, a linear instead of geometric scale
    aff = affine(x, transform=res.transform, times=t)
    np.testing.assert_allclose(aff.rotation, res.rotation, atol=1e-10)
    np.testing.assert_allclose(aff.det, (1 + 3 * t) ** 3, rtol=1e-10)


def test_noisy_target_is_reached_by_blending_the_residual() -> None:
    v, f = strip3(nx=6, ny=2)
    rng = np.random.default_rng(5)
    y = v @ random_rotation(rng).T + rng.normal(size=v.shape) * 0.01
    res = rigid({"vertices": v, "faces": f}, {"vertices": y, "faces": f})
    assert 0 < res.rmse < 0.05
    np.testing.assert_allclose(res.frames[-1], y, atol=1e-12)
    assert (res.faces == f).all()


@pytest.mark.parametrize("transform, kwargs, match", [
    (np.diag([2.0, 1.0, 1.0]), {}, "scaled rotation"),
    (np.diag([2.0, 2.0, 1.0]), {}, "scale=true"),
    (np.diag([-1.0, 1.0, 1.0]), {}, "det > 0"),
    (np.diag([-1.0, -1.0, 1.0]), {"scale": True}, None),
])
def test_transform_must_be_a_rigid_motion(transform, kwargs, match) -> None:  # noqa: ANN001
    if match is None:        # a half turn is a proper rotation: accepted
        res = rigid(SQUARE, transform=transform, **kwargs)
        assert res.angle == pytest.approx(np.pi)
        return
    with pytest.raises(InvalidInputError, match=match) as info:
        rigid(SQUARE, transform=transform, **kwargs)
    assert info.value.field == "transform"


def test_errors_name_their_input() -> None:
    with pytest.raises(InvalidInputError, match="true or false") as info:
        rigid(SQUARE, SQUARE, scale="yes")
    assert info.value.field == "scale"
    with pytest.raises(InvalidInputError, match="'centroid', 'origin'") as info:
        rigid(SQUARE, SQUARE, pivot="corner")
    assert info.value.field == "pivot"
    with pytest.raises(InvalidInputError) as info:
        rigid(SQUARE, SQUARE, times=[1.0, 0.0])
    assert info.value.field == "times"
    with pytest.raises(InvalidInputError) as info:
        rigid(SQUARE, SQUARE[:, :1])
    assert info.value.field == "target"
