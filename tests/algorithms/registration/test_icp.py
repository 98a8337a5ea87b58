"""Tests for registration.icp: hand cases, recovery on generated asymmetric shapes (every
metric, model and start), robustness (trimming, kernels), the degenerate cases that must not
pass as success, agreement with trimesh's ICP iteration by iteration, and real meshes
(pyvista's airplane, ant and nut)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import trimesh
from scipy.spatial.transform import Rotation

from algorithms.core import Cancelled, ConvergenceWarning, DegenerateInputError, InvalidInputError
from algorithms.registration import ICPResult, icp
from tests.algorithms.registration._real_meshes import surface_points
from tests.algorithms.registration._shapes import (
    angle_deg,
    bent_bar,
    blob,
    move,
    random_rotation,
    rotation_about,
)

SHAPES = {"blob": blob, "bent_bar": bent_bar}
CUBE = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]


def quiet(*args, **kw) -> ICPResult:  # noqa: ANN002, ANN003
    """icp without the ConvergenceWarning of runs stopped by max_iterations on purpose."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        return icp(*args, **kw)


# --- layer 1: computed by hand --------------------------------------------------------------


def test_hand_shift_is_found_in_one_iteration():
    # Partners are obvious (shift 0.5 against spacing 10): one Kabsch fit gives t exactly,
    # and the next assignment is the same, a fixed point.
    src = np.array([[0, 0], [10, 0], [0, 10]], float)
    res = icp(src, src + [0.5, 0.2])
    np.testing.assert_allclose(res.transform, [[1, 0, 0.5], [0, 1, 0.2], [0, 0, 1]], atol=1e-12)
    assert res.rotation is not None and res.scale == 1.0
    assert res.iterations == 1 and res.converged and res.reason == "assignments unchanged"
    assert res.rmse < 1e-12 and res.fitness == 1.0
    np.testing.assert_array_equal(res.rmse_history, [res.rmse])


def test_hand_fitness_counts_pairs_within_the_bound():
    # Three points shifted by (0.5, 0.2) and a fourth 100 away from everything: within
    # max_correspondence_distance = 5 three of four source points have partners.
    src = np.array([[0, 0], [10, 0], [0, 10], [100, 100]], float)
    dst = src[:3] + [0.5, 0.2]
    res = icp(src, dst, max_correspondence_distance=5.0)
    np.testing.assert_allclose(res.translation, [0.5, 0.2], atol=1e-12)
    assert res.fitness == 0.75 and res.rmse < 1e-12
    # Trimming to 3 of 4 drops the same point; without a bound every point is an inlier.
    trimmed = icp(src, dst, overlap=0.75)
    np.testing.assert_allclose(trimmed.translation, [0.5, 0.2], atol=1e-12)
    assert trimmed.fitness == 1.0 and trimmed.rmse < 1e-12


def test_no_overlap_within_the_bound_is_not_success():
    src = np.array(CUBE, float)
    with pytest.warns(ConvergenceWarning, match="no source point"):
        res = icp(src, src + 50.0, max_correspondence_distance=1.0)
    assert res.converged is False and "no source point" in res.reason
    assert res.fitness == 0.0 and res.rmse == 0.0 and res.iterations == 0
    np.testing.assert_array_equal(res.transform, np.eye(4))  # the start, labelled as failed


def test_similarity_and_affine_hand_cases():
    # target = 2 x + (1, 0): partners obvious at that spacing once scaled? Use a matrix start
    # at the answer: the fit reproduces it and stops at once.
    src = np.array([[0, 0], [3, 0], [0, 5], [2, 2]], float)
    start = np.array([[2, 0, 1], [0, 2, 0], [0, 0, 1]], float)
    res = icp(src, 2 * src + [1, 0], model="similarity", init=start)
    assert res.scale == pytest.approx(2.0, abs=1e-12)
    np.testing.assert_allclose(res.rotation, np.eye(2), atol=1e-12)
    a = np.array([[2, 1, 0.5], [0, 1, 0], [0, 0, 1]], float)
    res = icp(src, src @ a[:2, :2].T + [0.5, 0], model="affine", init=a)
    np.testing.assert_allclose(res.transform, a, atol=1e-12)
    assert res.rotation is None and res.scale is None


# --- layer 2: recovery and invariants -------------------------------------------------------


@pytest.mark.parametrize("shape", ["blob", "bent_bar"])
@pytest.mark.parametrize("metric", ["point_to_point", "point_to_plane", "symmetric"])
def test_rotations_up_to_30_degrees_are_recovered(shape, metric):
    src = SHAPES[shape](600, 1)
    for seed, degrees in enumerate((5.0, 15.0, 30.0, 30.0)):
        rng = np.random.default_rng(seed)
        truth = rotation_about(rng.standard_normal(3), degrees)
        dst = move(src, truth, rng.normal(0, 0.1, 3), rng)
        res = icp(src, dst, metric=metric, max_iterations=150)
        assert res.converged, res.reason
        assert angle_deg(res.rotation, truth) < 0.1
        assert res.rmse < 1e-6 and res.fitness == 1.0


def test_point_to_plane_needs_fewer_iterations_than_point_to_point():
    src = blob(600, 1)
    for seed in range(4):
        rng = np.random.default_rng(seed)
        dst = move(src, rotation_about(rng.standard_normal(3), 25.0), [0.1, 0, 0], rng)
        p2p = icp(src, dst, max_iterations=200)
        p2l = icp(src, dst, metric="point_to_plane", max_iterations=200)
        sym = icp(src, dst, metric="symmetric", max_iterations=200)
        assert p2l.iterations < p2p.iterations and sym.iterations < p2p.iterations


def test_independent_samplings_with_noise_with_plane_metrics():
    # Source and target sample the surface independently (no exact partners) with noise.
    src, dense = blob(800, 1), blob(4000, 2)
    rng = np.random.default_rng(7)
    truth = rotation_about([1, -2, 1], 20.0)
    dst = move(dense + rng.normal(0, 0.002, dense.shape), truth, [0.1, -0.1, 0.05], rng)
    for metric in ("point_to_plane", "symmetric"):
        res = icp(src, dst, metric=metric, max_iterations=100)
        assert res.converged and angle_deg(res.rotation, truth) < 0.1


@pytest.mark.parametrize("shape", ["blob", "bent_bar"])
def test_pca_start_recovers_arbitrary_rotations(shape):
    src = SHAPES[shape](400, 3)
    for seed in range(5):
        rng = np.random.default_rng(100 + seed)
        truth = random_rotation(rng)
        dst = move(src, truth, rng.normal(0, 5.0, 3), rng)
        res = icp(src, dst, init="pca", metric="point_to_plane", max_iterations=60)
        assert angle_deg(res.rotation, truth) < 0.1, seed


@pytest.mark.parametrize("scale", [0.5, 0.8, 1.3, 2.0])
def test_similarity_recovers_scale(scale):
    src = blob(500, 4)
    rng = np.random.default_rng(int(scale * 10))
    truth = rotation_about(rng.standard_normal(3), 20.0)
    dst = move(src, scale * truth, [0.1, 0.2, -0.1], rng)
    for metric in ("point_to_point", "point_to_plane"):
        res = icp(src, dst, model="similarity", metric=metric, max_iterations=100)
        assert res.scale == pytest.approx(scale, rel=1e-6)
        assert angle_deg(res.rotation, truth) < 0.1
        np.testing.assert_allclose(res.linear, res.scale * res.rotation, atol=1e-12)


def test_affine_recovers_a_general_map():
    src = blob(500, 5)
    a = np.array([[1.2, 0.1, 0.0], [0.0, 0.9, 0.15], [0.05, 0.0, 1.1]]) @ rotation_about(
        [1, 2, 3], 10.0)
    dst = move(src, a, [0.1, 0.2, 0.0], np.random.default_rng(0))
    for metric in ("point_to_point", "point_to_plane"):
        res = icp(src, dst, model="affine", metric=metric, max_iterations=100)
        np.testing.assert_allclose(res.linear, a, atol=1e-8)


@pytest.mark.parametrize("d", [2, 5])
def test_point_to_point_in_other_dimensions(d):
    rng = np.random.default_rng(d)
    src = rng.gamma(2.0, size=(300, d)) * np.linspace(1.0, 2.0, d)  # skewed, anisotropic
    truth = random_rotation(rng, d)
    dst = move(src, truth, rng.normal(0, 1.0, d), rng)
    res = icp(src, dst, init="pca", max_iterations=100)
    np.testing.assert_allclose(res.rotation, truth, atol=1e-8)
    assert res.transform.shape == (d + 1, d + 1)


def test_rmse_history_never_rises_for_plain_point_to_point():
    # Besl & McKay's theorem: each half-step minimises exactly.
    src = bent_bar(500, 2)
    rng = np.random.default_rng(3)
    dst = move(bent_bar(1500, 9), rotation_about([0, 1, 1], 25.0), [0.2, 0, 0], rng)
    res = quiet(src, dst, max_iterations=40, tolerance=0.0)
    h = res.rmse_history
    assert len(h) == res.iterations and h[-1] == res.rmse
    assert np.all(np.diff(h) <= 1e-12 * h[:-1])


def test_matrix_start_is_part_of_the_result():
    src = blob(300, 6)
    truth = rotation_about([0, 0, 1], 40.0)
    dst = move(src, truth, [1.0, 2.0, 3.0])
    start = np.eye(4)
    start[:3, :3] = rotation_about([0, 0, 1], 35.0)
    start[:3, 3] = [1.0, 2.0, 3.0]
    res = icp(src, dst, init=start, max_iterations=100)
    assert angle_deg(res.rotation, truth) < 0.1  # the whole map, start included
    np.testing.assert_allclose(res.translation, [1.0, 2.0, 3.0], atol=1e-6)


def test_robust_kernels_and_trimming_resist_outliers():
    src = blob(800, 1)
    rng = np.random.default_rng(0)
    truth = rotation_about(rng.standard_normal(3), 15.0)
    dst = move(src, truth, [0.05, 0.1, 0.0], rng)
    noisy = src.copy()
    bad = rng.choice(len(src), 80, replace=False)
    noisy[bad] += rng.normal(0, 0.5, (80, 3))     # 10% of the source thrown off the surface
    plain = icp(noisy, dst, max_iterations=100)
    assert angle_deg(plain.rotation, truth) > 0.1  # the outliers bias plain ICP
    for kw in ({"kernel": "huber"}, {"kernel": "tukey"}, {"overlap": 0.9},
               {"kernel": "tukey", "metric": "point_to_plane"},
               {"kernel": "tukey", "metric": "point_to_plane"}):
        res = icp(noisy, dst, max_iterations=100, **kw)
        assert angle_deg(res.rotation, truth) < 0.01, kw
    # A fixed Huber threshold only bounds the outliers' pull: better than plain, not exact.
    fixed = icp(noisy, dst, max_iterations=100, kernel="huber", kernel_scale=0.05)
    assert angle_deg(fixed.rotation, truth) < 0.5 * angle_deg(plain.rotation, truth)


def test_trimming_registers_a_partial_overlap():
    src = blob(800, 1)
    rng = np.random.default_rng(1)
    truth = rotation_about(rng.standard_normal(3), 15.0)
    dst = move(src, truth, [0.05, 0.1, 0.0], rng)
    crop = dst[dst[:, 0] < np.quantile(dst[:, 0], 0.8)]      # the target lost a fifth
    res = icp(src, crop, overlap=0.8, max_iterations=100)
    assert angle_deg(res.rotation, truth) < 0.01
    assert quiet(src, crop, max_iterations=100).rmse > 10 * max(res.rmse, 1e-9)


def test_progress_each_iteration_and_cancellation():
    src = blob(300, 2)
    dst = move(src, rotation_about([1, 0, 0], 20.0), [0, 0, 0])
    calls = []
    res = quiet(src, dst, max_iterations=5, tolerance=0.0,
                progress=lambda done, total, msg="": calls.append((done, total)))
    assert calls == [(k, 5) for k in range(1, res.iterations + 1)]

    def cancel(done, total, msg=""):  # noqa: ANN001, ANN202
        raise Cancelled("stop")

    with pytest.raises(Cancelled):
        icp(src, dst, progress=cancel)
    calls.clear()
    quiet(src, dst, init="pca", max_iterations=3, tolerance=0.0,
          progress=lambda done, total, msg="": calls.append((done, total)))
    assert {t for _, t in calls} == {4 * 3}  # four sign choices, three iterations each


def test_result_is_independent_of_source_order():
    src = blob(400, 8)
    dst = move(src, rotation_about([1, 1, 0], 10.0), [0.1, 0, 0])
    perm = np.random.default_rng(0).permutation(len(src))
    a, b = icp(src, dst), icp(src[perm], dst)
    np.testing.assert_allclose(a.transform, b.transform, atol=1e-9)


# --- degenerate input: typed errors or converged=False with a reason ------------------------


def test_coplanar_target_without_normals_is_an_error_for_plane_metrics():
    rng = np.random.default_rng(0)
    plane = np.c_[rng.random((200, 2)), np.zeros(200)]
    for metric in ("point_to_plane", "symmetric"):
        with pytest.raises(DegenerateInputError, match="coplanar") as err:
            icp(plane + [0.01, 0, 0], plane, metric=metric)
        assert err.value.field == "target"
    # point-to-point on the same data is fine (the in-plane motion is determined there)
    assert icp(plane + [0.01, 0.02, 0], plane).converged


def test_coplanar_target_with_its_normals_stops_with_a_reason():
    rng = np.random.default_rng(1)
    plane = np.c_[rng.random((200, 2)), np.zeros(200)]
    normals = np.tile([0.0, 0.0, 1.0], (200, 1))
    with pytest.warns(ConvergenceWarning, match="undetermined"):
        res = icp(plane + [0.01, 0, 0.02], plane, metric="point_to_plane",
                  target_normals=normals)
    assert res.converged is False and "undetermined" in res.reason


def test_too_few_points_and_flat_sets_are_errors():
    with pytest.raises(InvalidInputError, match="at least 3 points") as err:
        icp(CUBE[:2], CUBE)
    assert err.value.field == "source"
    with pytest.raises(InvalidInputError, match="at least 4 points"):
        icp(CUBE[:3], CUBE, model="affine")
    with pytest.raises(InvalidInputError, match="at least 6 points"):
        icp(CUBE, CUBE, metric="point_to_plane")
    with pytest.raises(InvalidInputError, match="at least 3 points") as err:
        icp(CUBE, CUBE[:2])
    assert err.value.field == "target"
    line = [[0, 0, 0], [1, 1, 1], [2, 2, 2], [3, 3, 3]]
    with pytest.raises(DegenerateInputError, match="collinear") as err:
        icp(line, CUBE)
    assert err.value.field == "source"
    with pytest.raises(DegenerateInputError, match="coplanar") as err:
        icp(CUBE, [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], model="affine")
    assert err.value.field == "target"


def test_all_weights_zero_stops_with_a_reason():
    src = blob(200, 1)
    dst = move(src, rotation_about([0, 0, 1], 10.0), [0.3, 0, 0])
    with pytest.warns(ConvergenceWarning, match="zero weight"):
        res = icp(src, dst, kernel="tukey", kernel_scale=1e-9)
    assert res.converged is False and "zero weight" in res.reason


@pytest.mark.parametrize("kw, field, fragment", [
    ({"metric": "point_to_plane", "source": [[0, 0], [1, 0], [0, 1]] * 3,
      "target": [[0, 0], [1, 0], [0, 1]]}, "metric", "3-D"),
    ({"metric": "symmetric", "model": "similarity"}, "model", "rigid"),
    ({"model": "projective"}, "model", "one of"),
    ({"kernel": "cauchy"}, "kernel", "one of"),
    ({"init": "random"}, "init", "one of"),
    ({"init": np.eye(3)}, "init", "(4, 4)"),
    ({"init": np.diag([1.0, 1.0, 2.0, 1.0])}, "init", "rotation"),
    ({"init": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [1, 0, 0, 1]]}, "init", "last row"),
    ({"init": np.diag([2.0, 2.0, 2.0, 1.0]), "model": "similarity"}, None, ""),
    ({"init": np.diag([2.0, 1.0, 2.0, 1.0]), "model": "similarity"}, "init", "multiple"),
    ({"init": np.diag([0.0, 1.0, 2.0, 1.0]), "model": "affine"}, "init", "invertible"),
    ({"max_iterations": 0}, "max_iterations", ">= 1"),
    ({"tolerance": -1.0}, "tolerance", ">= 0"),
    ({"max_correspondence_distance": 0.0}, "max_correspondence_distance", "> 0"),
    ({"overlap": 0.0}, "overlap", "> 0"),
    ({"overlap": 1.5}, "overlap", "<= 1"),
    ({"kernel": "huber", "kernel_scale": -1.0}, "kernel_scale", "> 0"),
    ({"metric": "point_to_plane", "normal_neighbors": 1}, "normal_neighbors", ">= 2"),
    ({"metric": "point_to_plane", "target_normals": np.ones((5, 3))}, "target_normals",
     "one normal per"),
    ({"metric": "point_to_plane", "target_normals": np.zeros((8, 3))}, "target_normals",
     "non-zero"),
    ({"metric": "symmetric", "source_normals": np.ones((8, 2))}, "source_normals", "(n, 3)"),
    ({"source_normals": np.ones((5, 3))}, "source_normals", "one normal per `source` point"),
    ({"target": [[0.0, 0.0]] * 8}, "target", "same dimension"),
    ({"source": [[0.0, np.nan, 0.0]] + [[1.0, 2.0, 3.0]] * 7}, "source", "row 0"),
])
def test_invalid_inputs_name_the_field(kw, field, fragment):
    rng = np.random.default_rng(0)
    pts = rng.random((8, 3))
    args = {"source": pts, "target": pts + 0.01}
    args.update(kw)
    source, target = args.pop("source"), args.pop("target")
    if field is None:  # the valid counterpart of a neighbouring case
        quiet(source, target, **args)
        return
    with pytest.raises(InvalidInputError) as err:
        icp(source, target, **args)
    assert err.value.field == field, err.value
    assert fragment in str(err.value)


# --- layer 3: agreement with the peer (trimesh.registration.icp) ---------------------------


@pytest.mark.parametrize("iterations", [1, 3, 8])
def test_agrees_with_trimesh_iteration_by_iteration(iterations):
    # trimesh's loop is the textbook one (nearest point, Procrustes, compose); with scale and
    # reflections off it is the same rigid point-to-point ICP, so every iterate matches.
    src = blob(500, 1)
    dst = move(src, rotation_about([1, 2, 3], 12.0), [0.05, 0.1, 0.0], np.random.default_rng(0))
    theirs, _, _ = trimesh.registration.icp(src, dst, initial=np.eye(4), threshold=-1.0,
                                            max_iterations=iterations, reflection=False,
                                            scale=False)
    ours = quiet(src, dst, max_iterations=iterations, tolerance=0.0)
    np.testing.assert_allclose(ours.transform, theirs, atol=1e-10)


# --- real meshes (pyvista's PLY files) ------------------------------------------------------


@pytest.mark.parametrize("name", ["airplane.ply", "ant.ply", "nut.ply"])
def test_icp_recovers_a_20_degree_turn_of_a_real_shape(name: str) -> None:
    src = surface_points(name, 2000, 0)
    rot = Rotation.from_rotvec(np.radians(20) * np.array([1.0, -2.0, 0.5]) / np.sqrt(5.25))
    dst = rot.apply(src) + [0.05, -0.02, 0.03]
    res = icp(src, dst, metric="point_to_plane", max_iterations=100)
    assert res.converged, res.reason
    assert angle_deg(res.rotation, rot.as_matrix()) < 0.1


def test_icp_with_pca_init_finds_any_turn_of_the_ant() -> None:
    src = surface_points("ant.ply", 1500, 1)
    rot = Rotation.from_euler("xyz", [150, -60, 110], degrees=True)
    dst = rot.apply(src) + [0.3, 0.1, -0.2]
    res = icp(src, dst, init="pca", max_iterations=60)
    assert angle_deg(res.rotation, rot.as_matrix()) < 0.1
