"""Tests for alignment.rigid: hand cases, recovery invariants, agreement with scipy."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from algorithms.alignment import RigidResult, rigid
from algorithms.core import DegenerateInputError, InvalidInputError

SEEDS = range(100)


def random_rotation(rng: np.random.Generator, d: int, *, proper: bool = True) -> np.ndarray:
    """A Haar-random orthogonal matrix (QR of a Gaussian with the sign fix), det +1 if proper."""
    q, r = np.linalg.qr(rng.standard_normal((d, d)))
    q = q * np.sign(np.diag(r))
    if proper and np.linalg.det(q) < 0:
        q[:, 0] = -q[:, 0]
    return q


# --- layer 1: computed by hand --------------------------------------------------------------


def test_hand_quarter_turn_and_shift():
    # R turns by +90°: (a, b) -> (-b, a); then t = (3, 4).
    # (0,0) -> (3,4); (1,0) -> (0,1)+(3,4) = (3,5); (0,2) -> (-2,0)+(3,4) = (1,4).
    source = [[0, 0], [1, 0], [0, 2]]
    target = [[3, 4], [3, 5], [1, 4]]
    res = rigid(source, target)
    np.testing.assert_allclose(res.rotation, [[0, -1], [1, 0]], atol=1e-12)
    np.testing.assert_allclose(res.translation, [3, 4], atol=1e-12)
    np.testing.assert_allclose(res.transform, [[0, -1, 3], [1, 0, 4], [0, 0, 1]], atol=1e-12)
    np.testing.assert_array_equal(res.linear, res.rotation)
    assert res.scale == 1.0
    assert res.rmse < 1e-12
    assert res.reflection is False


def test_hand_collinear_2d_with_residual():
    # x = (-1,0), (1,0); y = (-2,0), (2,0). Centroids 0; C = sum y x^T = [[4,0],[0,0]], rank 1 =
    # d - 1, so R = I is determined. Residuals R x - y = (1,0), (-1,0): rmse = sqrt(2/2) = 1.
    res = rigid([[-1, 0], [1, 0]], [[-2, 0], [2, 0]])
    np.testing.assert_allclose(res.rotation, np.eye(2), atol=1e-15)
    np.testing.assert_allclose(res.translation, [0, 0], atol=1e-15)
    assert res.rmse == pytest.approx(1.0, abs=1e-15)


def test_hand_mirror_2d():
    # A 4x2 "diamond" mirrored across the x-axis: (x, y) -> (x, -y).
    # C = sum y x^T = diag(2*2*2, -(1*1 + 1*1)) = diag(8, -2): singular values 8 and 2, and
    # U V^T = diag(1, -1) is a reflection.
    source = np.array([[2, 0], [0, 1], [-2, 0], [0, -1]], dtype=float)
    target = source * [1, -1]
    refl = rigid(source, target, allow_reflection=True)
    np.testing.assert_allclose(refl.rotation, [[1, 0], [0, -1]], atol=1e-15)
    assert refl.reflection is True and refl.rmse < 1e-15
    # Proper rotation: flip the singular vector of sigma = 2 -> R = I. Residuals x - y are
    # (0,0), (0,2), (0,0), (0,-2): sum 8 over 4 points, rmse = sqrt(2).
    proper = rigid(source, target)
    np.testing.assert_allclose(proper.rotation, np.eye(2), atol=1e-15)
    assert proper.reflection is False
    assert proper.rmse == pytest.approx(np.sqrt(2.0), abs=1e-14)


def test_hand_weights_pick_the_pair():
    # Three pairs; the third (weight 0) contradicts the first two, which say "shift by (1, 0)".
    source = [[0, 0], [2, 0], [0, 5]]
    target = [[1, 0], [3, 0], [7, 7]]
    res = rigid(source, target, weights=[1, 1, 0])
    np.testing.assert_allclose(res.rotation, np.eye(2), atol=1e-15)
    np.testing.assert_allclose(res.translation, [1, 0], atol=1e-15)
    assert res.rmse == 0.0


def test_result_is_frozen_dataclass_with_documented_fields():
    res = rigid([[0, 0], [1, 0], [0, 1]], [[0, 0], [1, 0], [0, 1]])
    names = [f.name for f in dataclasses.fields(RigidResult)]
    assert names == [
        "transform", "linear", "rotation", "translation", "scale", "rmse", "reflection"
    ]
    for name in names:  # every field has its line in the numpydoc Attributes section
        assert f"\n    {name} : " in RigidResult.__doc__
    with pytest.raises(dataclasses.FrozenInstanceError):
        res.rmse = 1.0  # type: ignore[misc]
    assert isinstance(res.rmse, float) and isinstance(res.reflection, bool)
    assert res.transform.shape == (3, 3) and res.translation.shape == (2,)


# --- layer 2: invariants and recovery --------------------------------------------------------


@pytest.mark.parametrize("d", [2, 3, 5])
def test_recovers_random_rotation_and_translation(d):
    for seed in SEEDS:
        rng = np.random.default_rng(seed)
        n = d + 1 + seed % 7
        x = rng.standard_normal((n, d)) * 3
        rot = random_rotation(rng, d)
        t = rng.standard_normal(d) * 10
        y = x @ rot.T + t
        res = rigid(x, y)
        np.testing.assert_allclose(res.rotation, rot, atol=1e-10, err_msg=f"seed {seed}")
        np.testing.assert_allclose(res.translation, t, atol=1e-10, err_msg=f"seed {seed}")
        np.testing.assert_allclose(res.rotation @ res.rotation.T, np.eye(d), atol=1e-12)
        assert np.linalg.det(res.rotation) == pytest.approx(1.0, abs=1e-12)
        assert res.rmse < 1e-10 and res.reflection is False
        hom = np.c_[x, np.ones(n)] @ res.transform.T
        np.testing.assert_allclose(hom[:, :d], y, atol=1e-9)
        np.testing.assert_allclose(hom[:, d], 1.0)


@pytest.mark.parametrize("d", [2, 3, 5])
def test_mirrored_data(d):
    for seed in SEEDS:
        rng = np.random.default_rng(seed)
        x = rng.standard_normal((2 * d + 3, d))
        refl = random_rotation(rng, d, proper=False)
        if np.linalg.det(refl) > 0:
            refl[:, 0] = -refl[:, 0]
        t = rng.standard_normal(d)
        y = x @ refl.T + t
        proper = rigid(x, y)
        assert np.linalg.det(proper.rotation) == pytest.approx(1.0, abs=1e-12)
        assert proper.reflection is False and proper.rmse > 1e-3
        np.testing.assert_allclose(proper.rotation @ proper.rotation.T, np.eye(d), atol=1e-12)
        # The proper answer beats every other proper rotation: try small perturbations.
        for _ in range(3):
            other = proper.rotation @ _small_rotation(rng, d)
            assert _rmse(x, y, other) >= proper.rmse - 1e-12
        improper = rigid(x, y, allow_reflection=True)
        assert np.linalg.det(improper.rotation) == pytest.approx(-1.0, abs=1e-12)
        assert improper.reflection is True and improper.rmse < 1e-10
        np.testing.assert_allclose(improper.rotation, refl, atol=1e-10)


def _small_rotation(rng: np.random.Generator, d: int) -> np.ndarray:
    # Cayley transform of a small skew matrix: a rotation near I (cheaper than expm).
    a = rng.standard_normal((d, d)) * 1e-3
    k = a - a.T
    return np.linalg.solve(np.eye(d) - k, np.eye(d) + k)


def _rmse(x: np.ndarray, y: np.ndarray, rot: np.ndarray) -> float:
    xc, yc = x - x.mean(0), y - y.mean(0)
    return float(np.sqrt(np.mean(np.sum((xc @ rot.T - yc) ** 2, axis=1))))


def test_allow_reflection_on_proper_data_returns_rotation():
    rng = np.random.default_rng(7)
    x = rng.standard_normal((10, 3))
    rot = random_rotation(rng, 3)
    res = rigid(x, x @ rot.T, allow_reflection=True)
    assert res.reflection is False
    np.testing.assert_allclose(res.rotation, rot, atol=1e-10)


@pytest.mark.parametrize("d", [2, 3, 5])
def test_zero_weight_outliers_are_ignored(d):
    for seed in SEEDS:
        rng = np.random.default_rng(seed)
        n = 3 * d
        x = rng.standard_normal((n, d))
        rot = random_rotation(rng, d)
        t = rng.standard_normal(d)
        y = x @ rot.T + t
        outliers = rng.choice(n, size=d, replace=False)
        y[outliers] += rng.standard_normal((d, d)) * 100
        w = np.ones(n)
        w[outliers] = 0.0
        res = rigid(x, y, weights=w)
        np.testing.assert_allclose(res.rotation, rot, atol=1e-10, err_msg=f"seed {seed}")
        np.testing.assert_allclose(res.translation, t, atol=1e-10, err_msg=f"seed {seed}")
        assert res.rmse < 1e-10


def test_weights_equal_duplicates_and_scale_free():
    rng = np.random.default_rng(3)
    x = rng.standard_normal((8, 3))
    y = x @ random_rotation(rng, 3).T + rng.standard_normal((8, 3)) * 0.1
    w = rng.integers(1, 4, size=8).astype(float)
    weighted = rigid(x, y, weights=w)
    repeated = rigid(np.repeat(x, w.astype(int), axis=0), np.repeat(y, w.astype(int), axis=0))
    np.testing.assert_allclose(weighted.transform, repeated.transform, atol=1e-12)
    assert weighted.rmse == pytest.approx(repeated.rmse, rel=1e-12)
    scaled = rigid(x, y, weights=w * 1e6)
    np.testing.assert_allclose(scaled.transform, weighted.transform, atol=1e-12)
    ones = rigid(x, y, weights=np.ones(8))
    plain = rigid(x, y)
    np.testing.assert_allclose(ones.transform, plain.transform, atol=1e-13)
    assert ones.rmse == pytest.approx(plain.rmse, rel=1e-12)


def test_inverse_and_rmse_definition():
    rng = np.random.default_rng(11)
    x = rng.standard_normal((12, 3))
    y = x @ random_rotation(rng, 3).T + 5 + rng.standard_normal((12, 3)) * 0.05
    w = rng.uniform(0.1, 2.0, 12)
    fwd = rigid(x, y, weights=w)
    back = rigid(y, x, weights=w)
    np.testing.assert_allclose(fwd.transform @ back.transform, np.eye(4), atol=1e-12)
    resid = x @ fwd.rotation.T + fwd.translation - y
    expected = np.sqrt(np.sum(w * np.sum(resid**2, axis=1)) / np.sum(w))
    assert fwd.rmse == pytest.approx(expected, rel=1e-12)
    assert back.rmse == pytest.approx(fwd.rmse, rel=1e-10)


def test_accepts_float32_and_int_input():
    x = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=np.int32)
    res = rigid(x.astype(np.float32), x + 1)
    np.testing.assert_allclose(res.rotation, np.eye(3), atol=1e-12)
    np.testing.assert_allclose(res.translation, [1, 1, 1], atol=1e-12)


def test_minimum_count_d_points_is_enough():
    # d points in d-D span a (d-1)-flat: the proper rotation is still determined.
    rng = np.random.default_rng(5)
    for d in (2, 3, 5):
        x = rng.standard_normal((d, d))
        rot = random_rotation(rng, d)
        res = rigid(x, x @ rot.T)
        np.testing.assert_allclose(res.rotation, rot, atol=1e-9)


# --- layer 3: agreement with scipy (and trimesh) -------------------------------------------


def _weighted_centre(p: np.ndarray, w: np.ndarray | None) -> np.ndarray:
    return p - (p.mean(0) if w is None else (w @ p) / w.sum())


@pytest.mark.parametrize("weighted", [False, True])
def test_agrees_with_scipy_align_vectors(weighted):
    for seed in SEEDS:
        rng = np.random.default_rng(seed)
        n = 20
        x = rng.standard_normal((n, 3)) * 2
        y = x @ Rotation.random(random_state=rng).as_matrix().T + rng.standard_normal(3) * 5
        y += rng.standard_normal((n, 3)) * 0.05
        w = rng.uniform(0.1, 2.0, n) if weighted else None
        ours = rigid(x, y, weights=w)
        # align_vectors(a, b) returns C with a ≈ C b: a is the target, b the source.
        theirs, rssd = Rotation.align_vectors(
            _weighted_centre(y, w), _weighted_centre(x, w), weights=w
        )
        np.testing.assert_allclose(ours.rotation, theirs.as_matrix(), atol=1e-10,
                                   err_msg=f"seed {seed}")
        total = n if w is None else w.sum()
        assert ours.rmse == pytest.approx(rssd / np.sqrt(total), rel=1e-9, abs=1e-12)


def test_agrees_with_trimesh_procrustes():
    import trimesh.registration as trimesh_registration
    for seed in range(20):
        rng = np.random.default_rng(seed)
        x = rng.standard_normal((15, 3))
        y = x @ Rotation.random(random_state=rng).as_matrix().T + 1.0
        y += rng.standard_normal((15, 3)) * 0.05
        matrix, _, _ = trimesh_registration.procrustes(x, y, reflection=False, scale=False)
        np.testing.assert_allclose(rigid(x, y).transform, matrix, atol=1e-10)


# --- errors ----------------------------------------------------------------------------------


def test_error_fewer_points_than_dimensions():
    with pytest.raises(
        InvalidInputError, match=r"Expected `source` to hold at least 3 points .*, got 2\."
    ) as info:
        rigid(np.zeros((2, 3)), np.zeros((2, 3)))
    assert info.value.field == "source"
    assert not isinstance(info.value, DegenerateInputError)


def test_error_dimension_one():
    with pytest.raises(InvalidInputError, match=r"d >= 2 coordinates per point, got shape \(4, 1\)"):
        rigid(np.arange(4.0)[:, None], np.arange(4.0)[:, None])


def test_error_shapes_differ():
    with pytest.raises(
        InvalidInputError, match=r"Expected `target` to hold as many points as `source` \(4"
    ) as info:
        rigid(np.eye(4, 3), np.eye(3))
    assert info.value.field == "target"
    with pytest.raises(InvalidInputError, match=r"same dimension as `source` \(3\)") as info:
        rigid(np.eye(4, 3), np.eye(4, 2))
    assert info.value.field == "target"


@pytest.mark.parametrize("which", ["source", "target"])
def test_error_nonfinite(which):
    x = np.random.default_rng(0).standard_normal((6, 3))
    bad = x.copy()
    bad[4, 2] = np.inf
    args = (bad, x) if which == "source" else (x, bad)
    with pytest.raises(
        InvalidInputError, match=rf"Expected `{which}` to hold finite numbers, got inf at row 4\."
    ) as info:
        rigid(*args)
    assert info.value.field == which


def test_error_1d_and_ragged():
    with pytest.raises(InvalidInputError, match=r"got shape \(3,\)"):
        rigid([1.0, 2.0, 3.0], [1.0, 2.0, 3.0])
    with pytest.raises(InvalidInputError, match="ragged"):
        rigid([[1.0, 2.0], [3.0]], [[1.0, 2.0], [3.0, 4.0]])


@pytest.mark.parametrize(
    ("weights", "message"),
    [
        ([1.0, -1.0, 1.0, 1.0], r"`weights` to be non-negative, got -1.0 at position 1"),
        ([1.0, np.nan, 1.0, 1.0], r"`weights` to hold finite numbers, got nan at position 1"),
        ([1.0, 1.0, 1.0], r"`weights` to be an \(4,\) array .* got shape \(3,\)"),
        ([0.0, 0.0, 0.0, 0.0], r"`weights` to have a positive sum"),
    ],
)
def test_error_weights(weights, message):
    x = np.array([[0, 0], [1, 0], [0, 1], [1, 1]], dtype=float)
    with pytest.raises(InvalidInputError, match=message) as info:
        rigid(x, x, weights=weights)
    assert info.value.field == "weights"


def test_error_allow_reflection_not_bool():
    x = np.eye(3)
    with pytest.raises(InvalidInputError, match=r"`allow_reflection` to be true or false, got 'no'"):
        rigid(x, x, allow_reflection="no")


def test_degenerate_coincident_points():
    x = np.ones((5, 3))
    with pytest.raises(
        DegenerateInputError, match=r"`source` to span at least 2 dimensions .* coincident"
    ) as info:
        rigid(x, np.random.default_rng(0).standard_normal((5, 3)))
    assert info.value.field == "source"


def test_degenerate_target_named():
    x = np.random.default_rng(0).standard_normal((5, 3))
    with pytest.raises(DegenerateInputError, match=r"`target` .* coincident") as info:
        rigid(x, np.zeros((5, 3)))
    assert info.value.field == "target"


def test_degenerate_collinear_3d_even_far_from_origin():
    t = np.linspace(0.0, 1.0, 7)[:, None]
    for offset in (0.0, 1e4):
        x = offset + t * [1.0, 2.0, 3.0]
        y = x @ random_rotation(np.random.default_rng(1), 3).T
        with pytest.raises(DegenerateInputError, match=r"collinear.*rotation is undetermined"):
            rigid(x, y)


def test_degenerate_coplanar_3d_only_with_reflection():
    rng = np.random.default_rng(2)
    x = np.c_[rng.standard_normal((8, 2)), np.zeros(8)]
    y = x @ random_rotation(rng, 3).T
    assert rigid(x, y).rmse < 1e-10  # rank 2 = d - 1: determined
    with pytest.raises(DegenerateInputError, match=r"coplanar.*reflection .* fits equally well"):
        rigid(x, y, allow_reflection=True)


def test_degenerate_collinear_2d_only_with_reflection():
    x = np.array([[0.0, 0.0], [1.0, 1.0], [3.0, 3.0]])
    assert rigid(x, x + 1).rmse < 1e-12
    with pytest.raises(DegenerateInputError, match=r"`source` .* collinear .* reflection"):
        rigid(x, x + 1, allow_reflection=True)


def test_degenerate_when_positive_weights_are_collinear():
    rng = np.random.default_rng(4)
    x = rng.standard_normal((6, 3))
    x[:3] = [[0, 0, 0], [1, 1, 1], [2, 2, 2]]
    with pytest.raises(DegenerateInputError, match=r"collinear \(counting only points with positive weight\)"):
        rigid(x, x, weights=[1, 1, 1, 0, 0, 0])


def test_degenerate_cross_covariance_without_degenerate_sets():
    # Each set alone is fine in 2-D (x spans the plane, y a line), but they are uncorrelated:
    # C = a e1' - a e1' + b e2' - b e2' = 0.
    x = np.array([[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]])
    y = np.array([[1.0, 1.0], [1.0, 1.0], [-1.0, -1.0], [-1.0, -1.0]])
    with pytest.raises(DegenerateInputError, match=r"cross-covariance .* rank at least 1, got 0") as info:
        rigid(x, y)
    assert info.value.field is None


def test_docstring_examples_run():
    import doctest
    import sys

    module = sys.modules["algorithms.alignment.rigid"]
    assert doctest.testmod(module, raise_on_error=False).failed == 0
