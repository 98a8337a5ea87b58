"""Tests for registration.ransac: hand cases of the feature-free sampling of point triples,
the acceptance case of issue #4 (two crops sharing 70 % of a surface, 0.5 % noise, any
rotation, 20 seeded trials; and on pyvista's real airplane and ant), bit-identical results
for a seed, the stopping rule, honest failures, progress and cancellation, and the
errors."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from scipy.spatial import cKDTree
from scipy.spatial.transform import Rotation
from threadpoolctl import threadpool_limits

from algorithms.alignment import rigid
from algorithms.core import Cancelled, ConvergenceWarning, DegenerateInputError, InvalidInputError
from algorithms.registration import RANSACResult, icp, ransac
from algorithms.registration.ransac import _kabsch, _needed
from tests.algorithms.registration._real_meshes import surface_points
from tests.algorithms.registration._shapes import (
    angle_deg,
    blob,
    move,
    random_rotation,
    rotation_about,
)

# Six asymmetric points (the catalog example's): every triple is a distinct triangle.
SIX = np.array([[0, 0, 0], [2, 0, 0], [0, 1, 0], [0, 0, 0.5], [1, 1, 0.2], [0.5, 0.2, 0.4]])


def quiet(*args, **kw) -> RANSACResult:  # noqa: ANN002, ANN003
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        return ransac(*args, **kw)


def crop_case(trial: int, n: int = 3000, keep: float = 0.85, noise: float = 0.005):
    """Issue #4's case: two independent samplings of an asymmetric lumpy closed surface, each
    cut by the same plane from opposite sides keeping ``keep`` of its points, so that they
    share ``2 keep - 1`` = 70 % of the surface; the target turned by a Haar-random rotation
    and moved; both with Gaussian noise of ``noise`` × the bounding-box diagonal."""
    rng = np.random.default_rng(1000 + trial)
    full = blob(n, 2 * trial + 1)
    diag = float(np.linalg.norm(full.max(axis=0) - full.min(axis=0)))
    normal = rng.standard_normal(3)
    normal /= np.linalg.norm(normal)
    src = full[full @ normal <= np.quantile(full @ normal, keep)]
    other = blob(n, 2 * trial + 2)
    dst = other[other @ -normal <= np.quantile(other @ -normal, keep)]
    src = src + rng.normal(0.0, noise * diag, src.shape)
    rot = random_rotation(rng)
    dst = move(dst, rot, rng.uniform(-2, 2, 3)) + rng.normal(0.0, noise * diag, dst.shape)
    return src, dst, rot, diag


# --- layer 1: by hand -------------------------------------------------------------------------


def test_seed_sampling_recovers_a_large_rotation_exactly():
    rot = rotation_about([0, 0, 1], 120.0)
    dst = move(SIX[::-1], rot, [1.0, -0.5, 0.0])
    res = ransac(SIX, dst, features="none", max_correspondence_distance=0.05)
    assert res.converged and res.fitness == 1.0 and res.inlier_count == 6
    np.testing.assert_allclose(res.rotation, rot, atol=1e-9)
    np.testing.assert_allclose(res.translation, [1.0, -0.5, 0.0], atol=1e-9)
    np.testing.assert_allclose(res.transform[3], [0, 0, 0, 1])
    assert res.rmse < 1e-9 and res.correspondence_count == 36
    assert "confidence 0.999 reached" in res.reason


def test_local_icp_cannot_do_what_ransac_does():
    # ICP from the identity falls into a wrong minimum for a 120° turn; RANSAC has no start.
    rot = rotation_about([0, 0, 1], 120.0)
    dst = move(SIX[::-1], rot, [1.0, -0.5, 0.0])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        local = icp(SIX, dst)
    assert angle_deg(local.rotation, rot) > 10.0
    assert angle_deg(ransac(SIX, dst, features="none").rotation, rot) < 1e-6


def test_seed_sampling_in_two_dimensions():
    rng = np.random.default_rng(4)
    pts = rng.gamma(2.0, size=(12, 2))
    c, s = math.cos(2.5), math.sin(2.5)
    rot = np.array([[c, -s], [s, c]])
    res = ransac(pts, move(pts, rot, [3.0, 1.0], rng), features="none",
                 max_correspondence_distance=0.01)
    np.testing.assert_allclose(res.rotation, rot, atol=1e-9)
    assert res.transform.shape == (3, 3) and res.converged


def test_stopping_rule_is_open3d_formula():
    # log(1 - 0.999) / log(1 - w³): w = 0.5 needs 52 samples, w = 1 none, w = 0 never.
    assert _needed(0.5, 0.999, 3) == pytest.approx(math.log(0.001) / math.log(1 - 0.125))
    assert math.ceil(_needed(0.5, 0.999, 3)) == 52
    assert _needed(1.0, 0.999, 3) == 0.0 and _needed(0.0, 0.999, 3) == math.inf
    assert _needed(0.5, 1.0, 3) == math.inf


def test_batched_kabsch_agrees_with_rigid_alignment():
    rng = np.random.default_rng(5)
    a = rng.standard_normal((50, 3, 3))
    b = np.stack([move(x, random_rotation(rng), rng.standard_normal(3)) for x in a])
    b = b + rng.normal(0, 0.05, b.shape)
    rot, shift = _kabsch(a, b)
    for k in range(50):
        ref = rigid(a[k], b[k])
        np.testing.assert_allclose(rot[k], ref.rotation, atol=1e-12)
        np.testing.assert_allclose(shift[k], ref.translation, atol=1e-12)


# --- layer 2: recovery, reproducibility -----------------------------------------------------------


def test_registers_crops_with_70_percent_overlap_and_noise_in_19_of_20_trials():
    errors = []
    for trial in range(20):
        src, dst, rot, _ = crop_case(trial)
        res = quiet(src, dst, voxel_size=0.15, seed=trial)
        errors.append(angle_deg(res.rotation, rot))
    assert sum(e < 2.0 for e in errors) >= 19, np.round(errors, 3)


def test_reported_fitness_and_rmse_are_open3d_definitions():
    src, dst, rot, _ = crop_case(1)
    res = ransac(src, dst, voxel_size=0.15)
    tau = 1.5 * 0.15
    dist, _ = cKDTree(dst).query(move(src, res.rotation, res.translation))
    inside = dist[dist <= tau]
    assert res.inlier_count == inside.size
    assert res.fitness == pytest.approx(inside.size / len(src), abs=0)
    assert res.rmse == pytest.approx(math.sqrt(np.mean(inside ** 2)), rel=1e-12)
    assert res.converged and res.iterations < 100_000


def test_same_seed_gives_identical_bits():
    src, dst, rot, _ = crop_case(2)
    a = ransac(src, dst, voxel_size=0.15, seed=11)
    b = ransac(src, dst, voxel_size=0.15, seed=11)
    with threadpool_limits(limits=1):
        c = ransac(src, dst, voxel_size=0.15, seed=11)
    for other in (b, c):
        np.testing.assert_array_equal(a.transform, other.transform)
        assert (a.iterations, a.rmse, a.fitness, a.reason) == \
            (other.iterations, other.rmse, other.fitness, other.reason)
    d = ransac(src, dst, voxel_size=0.15, seed=np.random.default_rng(11))
    np.testing.assert_array_equal(a.transform, d.transform)     # a Generator is a seed too
    e = ransac(src, dst, voxel_size=0.15, seed=12)
    assert angle_deg(e.rotation, rot) < 2.0 and angle_deg(a.rotation, rot) < 2.0


def test_default_voxel_tries_two_scales_and_is_reproducible():
    # Without voxel_size: passes at 1.5 and 3 × the point spacing, the pose fitting the
    # full sets best wins; the same seed still gives the same bits, on any thread count.
    src, dst, rot, _ = crop_case(7)
    a = quiet(src, dst, seed=3)
    with threadpool_limits(limits=1):
        b = quiet(src, dst, seed=3)
    np.testing.assert_array_equal(a.transform, b.transform)
    assert (a.iterations, a.rmse, a.reason) == (b.iterations, b.rmse, b.reason)
    assert angle_deg(a.rotation, rot) < 2.0
    assert "of those tried" in a.reason and "× the point spacing" in a.reason
    assert a.iterations >= 2 * 4096       # two passes, each at least 4 batches


def test_default_registers_the_crops_too():
    errors = []
    for trial in range(8, 14):
        src, dst, rot, _ = crop_case(trial)
        errors.append(angle_deg(quiet(src, dst, seed=trial).rotation, rot))
    assert max(errors) < 2.0, np.round(errors, 3)


def test_refinement_improves_the_sampled_transform():
    src, dst, rot, _ = crop_case(3)
    raw = ransac(src, dst, voxel_size=0.15, refine=False)
    refined = ransac(src, dst, voxel_size=0.15)
    assert "refine" not in raw.reason and "refined by point_to_plane ICP" in refined.reason
    assert angle_deg(refined.rotation, rot) < min(2.0, angle_deg(raw.rotation, rot))
    assert raw.iterations == refined.iterations   # the same sampling, then ICP


def test_features_without_mutual_filter_also_register():
    src, dst, rot, _ = crop_case(4)
    res = ransac(src, dst, voxel_size=0.15, mutual_filter=False)
    assert angle_deg(res.rotation, rot) < 2.0
    mutual = ransac(src, dst, voxel_size=0.15)
    assert mutual.correspondence_count < res.correspondence_count


# --- never a silent identity -----------------------------------------------------------------


def test_no_congruent_sample_is_reported_not_hidden():
    # The target is the source scaled by 3: no rigid sample passes the edge-length check.
    with pytest.warns(ConvergenceWarning, match="no hypothesis"):
        res = ransac(SIX, 3.0 * SIX + 10.0, features="none", max_iterations=2000)
    assert res.converged is False and "no hypothesis of 2000" in res.reason
    np.testing.assert_array_equal(res.transform, np.eye(4))
    assert res.fitness == 0.0 and res.iterations == 2000


def test_max_iterations_before_confidence_is_not_convergence():
    src, dst, _, _ = crop_case(5)
    # confidence 1 is never reached: every one of max_iterations hypotheses is drawn
    with pytest.warns(ConvergenceWarning, match="max_iterations = 300 reached"):
        res = ransac(src, dst, voxel_size=0.15, max_iterations=300, confidence=1.0)
    assert res.converged is False and res.iterations == 300


def test_progress_is_reported_and_cancellation_propagates():
    src, dst, _, _ = crop_case(6)
    seen = []
    ransac(src, dst, voxel_size=0.15, progress=lambda *a: seen.append(a))
    done = [s[0] for s in seen]
    assert done == sorted(done) and seen[-1][0] == seen[-1][1] == 100_001

    def stop(done, total, message=""):  # noqa: ANN001, ANN202
        raise Cancelled("dismissed")

    with pytest.raises(Cancelled):
        ransac(src, dst, voxel_size=0.15, progress=stop)


# --- errors -------------------------------------------------------------------------------------


LINE = np.c_[np.arange(10.0), 2 * np.arange(10.0), np.zeros(10)]


@pytest.mark.parametrize("source, target, kwargs, field, fragment", [
    (SIX[:, :2], SIX[:, :2], {}, "features", "3-D"),
    (SIX[:3], SIX, {}, "source", "at least 4"),
    (SIX, SIX[:2], {"features": "none"}, "target", "at least 3"),
    (LINE, SIX, {}, "source", "collinear"),
    (SIX, LINE, {"features": "none"}, "target", "collinear"),
    (SIX, SIX[:, :2], {}, "target", "dimension"),
    (SIX, SIX, {"features": "sift"}, "features", "'fpfh', 'none'"),
    (SIX, SIX, {"voxel_size": 10.0}, "voxel_size", "leave at least 4"),
    (SIX, SIX, {"voxel_size": 0.0}, "voxel_size", "> 0"),
    (SIX, SIX, {"feature_radius": -1.0}, "feature_radius", "> 0"),
    (SIX, SIX, {"max_correspondence_distance": 0}, "max_correspondence_distance", "> 0"),
    (SIX, SIX, {"max_iterations": 0}, "max_iterations", ">= 1"),
    (SIX, SIX, {"confidence": 0.0}, "confidence", "> 0"),
    (SIX, SIX, {"confidence": 1.5}, "confidence", "<= 1"),
    (SIX, SIX, {"mutual_filter": "yes"}, "mutual_filter", "true or false"),
    (SIX, SIX, {"refine": 1}, "refine", "true or false"),
    ([[0, 0, np.nan]] * 6, SIX, {}, "source", "row 0"),
])
def test_errors_name_the_input(source, target, kwargs, field, fragment):
    with pytest.raises(InvalidInputError) as info:
        ransac(source, target, **kwargs)
    assert info.value.field == field
    assert fragment in str(info.value), str(info.value)


def test_collinear_is_a_degenerate_input_error():
    with pytest.raises(DegenerateInputError, match="collinear"):
        ransac(LINE, LINE, features="none")


# --- real meshes (pyvista's PLY files) ------------------------------------------------------


@pytest.mark.parametrize("name, seeds", [("airplane.ply", 20), ("ant.ply", 10)])
def test_ransac_registers_cropped_noisy_real_shapes(name: str, seeds: int) -> None:
    # Issue #4's acceptance on real shapes: two crops by a plane along a random axis, each
    # keeping 85 % (70 % shared), the target with 0.5 % noise, turned by a Haar-random
    # rotation and moved; default parameters; at least 19 of 20 seeds under 2° (seeds 0-19
    # of the ant also all pass; 10 of them here, to keep the test under 40 s).
    errors = []
    for seed in range(seeds):
        rng = np.random.default_rng(seed)
        points = surface_points(name, 6000, seed)
        axis = rng.normal(size=3)
        proj = points @ (axis / np.linalg.norm(axis))
        src = points[proj <= np.quantile(proj, 0.85)]
        dst = points[proj >= np.quantile(proj, 0.15)]
        rot = Rotation.random(random_state=seed)
        dst = rot.apply(dst + rng.normal(0, 0.005, dst.shape)) + rng.normal(size=3)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ConvergenceWarning)
            res = ransac(src, dst, seed=seed)
        errors.append(angle_deg(res.rotation, rot.as_matrix()))
    assert sum(e < 2.0 for e in errors) >= seeds - 1, np.round(errors, 2)
