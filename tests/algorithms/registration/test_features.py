"""Tests for the FPFH features of registration.ransac: a hand case, agreement with a plain
per-point transcription of Open3D's ComputePairFeatures / ComputeSPFHFeature /
ComputeFPFHFeature, invariants (rotation and order invariance, histogram sums), normal
orientation, voxel down-sampling, mutual matching, and the errors."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.spatial import cKDTree

from algorithms.core import InvalidInputError
from algorithms.registration import fpfh, match_features
from algorithms.registration.features import (
    _fpfh,
    feature_normals,
    orient_normals,
    point_spacing,
    voxel_downsample,
)
from tests.algorithms.registration._shapes import blob, move, random_rotation


def _grid(k: int, h: float = 0.1) -> np.ndarray:
    x, y = np.meshgrid(np.arange(k) * h, np.arange(k) * h)
    return np.c_[x.ravel(), y.ravel(), np.zeros(k * k)]


# --- a plain transcription of Open3D's Feature.cpp, one point and one pair at a time -----------


def _o3d_pair(p1, n1, p2, n2):  # noqa: ANN001, ANN202
    dp = p2 - p1
    f4 = np.linalg.norm(dp)
    if f4 == 0:
        return np.zeros(4)
    a1, a2 = n1 @ dp / f4, n2 @ dp / f4
    # the one deliberate difference: a tie |a1| = |a2| (equal normals) takes the end with the
    # larger phi, independent of the order of the points; Open3D keeps point 1
    tie = abs(abs(a1) - abs(a2)) <= 1e-9
    if (tie and -a2 > a1) or (not tie and math.acos(min(1.0, abs(a1)))
                              > math.acos(min(1.0, abs(a2)))):
        u, nt, dp, f3 = n2, n1, -dp, -a2
    else:
        u, nt, f3 = n1, n2, a1
    v = np.cross(dp, u)
    vn = np.linalg.norm(v)
    if vn == 0:
        return np.zeros(4)
    v = v / vn
    w = np.cross(u, v)
    return np.array([math.atan2(w @ nt, u @ nt), v @ nt, f3, f4])


def _o3d_fpfh(points, normals, radius, max_nn):  # noqa: ANN001, ANN202
    n = len(points)
    tree = cKDTree(points)
    nbrs = []
    for i in range(n):
        # Open3D's SearchHybrid(radius, max_nn) returns at most max_nn points, the query
        # point itself first; ComputeSPFHFeature skips that first index
        dist, idx = tree.query(points[i], k=min(max_nn, n), distance_upper_bound=radius)
        nbrs.append([(j, d) for j, d in zip(np.atleast_1d(idx), np.atleast_1d(dist))
                     if j < n and j != i and d > 0])
    spfh = np.zeros((n, 33))
    for i in range(n):
        if not nbrs[i]:
            continue
        incr = 100.0 / len(nbrs[i])
        for j, _ in nbrs[i]:
            f = _o3d_pair(points[i], normals[i], points[j], normals[j])
            for block, value, low, high in ((0, f[0], -math.pi, math.pi), (1, f[1], -1, 1),
                                            (2, f[2], -1, 1)):
                b = min(10, max(0, int(math.floor(11 * (value - low) / (high - low)))))
                spfh[i, 11 * block + b] += incr
    out = np.zeros((n, 33))
    for i in range(n):
        acc = np.zeros(33)
        for j, d in nbrs[i]:
            acc += spfh[j] / d ** 2
        sums = acc.reshape(3, 11).sum(axis=1)
        scale = np.where(sums > 0, 100.0 / np.where(sums > 0, sums, 1), 0.0)
        out[i] = (acc.reshape(3, 11) * scale[:, None]).ravel() + spfh[i]
    return out


# --- layer 1: by hand ----------------------------------------------------------------------------


def test_flat_grid_with_upward_normals_fills_the_middle_bins():
    # Every pair of a plane with parallel normals has alpha = phi = theta = 0: bin 5 of each
    # histogram; the SPFH puts 100 there and the normalised neighbour sum another 100.
    pts = _grid(6)
    f = fpfh(pts, radius=0.25, normals=np.tile([0.0, 0.0, 1.0], (36, 1)))
    expected = np.zeros(33)
    expected[[5, 16, 27]] = 200.0
    np.testing.assert_allclose(f, np.tile(expected, (36, 1)), atol=1e-12)


def test_a_point_without_neighbours_has_a_zero_feature():
    pts = np.vstack([_grid(5), [[10.0, 10.0, 10.0]]])
    f = fpfh(pts, radius=0.25, normals=np.tile([0.0, 0.0, 1.0], (26, 1)))
    np.testing.assert_array_equal(f[-1], 0.0)
    np.testing.assert_allclose(f[:-1].reshape(25, 3, 11).sum(axis=2), 200.0)


def test_point_spacing_of_a_grid_is_its_step():
    assert point_spacing(_grid(10, 0.3)) == pytest.approx(0.3, rel=1e-12)


def test_voxel_downsample_by_hand():
    pts = np.array([[0.1, 0.1, 0.1], [0.3, 0.3, 0.3], [1.2, 0.1, 0.1], [1.4, 0.3, 0.5]])
    out = voxel_downsample(pts, 1.0)
    np.testing.assert_allclose(out, [[0.2, 0.2, 0.2], [1.3, 0.2, 0.3]])


def test_match_features_by_hand():
    a = np.array([[1.0, 0.0], [2.0, 0.0], [5.0, 5.0]])
    b = a[[2, 0]] + 0.1
    s, t = match_features(a, b)
    np.testing.assert_array_equal(s, [0, 2])
    np.testing.assert_array_equal(t, [1, 0])
    s, t = match_features(a, b, mutual=False)           # source 1 also picks target 1
    np.testing.assert_array_equal(s, [0, 1, 2])
    np.testing.assert_array_equal(t, [1, 1, 0])
    s, t = match_features(np.zeros((3, 2)), b)          # no neighbourhood, no match
    assert s.size == 0 and t.size == 0


# --- layer 2: invariants ------------------------------------------------------------------------


def test_fpfh_is_rotation_and_translation_invariant():
    pts = blob(1500, 3)
    f = fpfh(pts)
    rng = np.random.default_rng(7)
    for _ in range(3):
        moved = move(pts, random_rotation(rng), rng.uniform(-5, 5, 3))
        np.testing.assert_allclose(fpfh(moved), f, rtol=0, atol=1e-8)


def test_fpfh_follows_the_order_of_the_points():
    pts = blob(800, 4)
    perm = np.random.default_rng(1).permutation(800)
    np.testing.assert_allclose(fpfh(pts[perm]), fpfh(pts)[perm], rtol=0, atol=1e-8)


def test_histograms_sum_to_200_per_block():
    f = fpfh(blob(1000, 5))
    assert (f >= 0).all()
    np.testing.assert_allclose(f.reshape(-1, 3, 11).sum(axis=2), 200.0, rtol=1e-12)


def test_max_neighbors_caps_the_neighbourhood():
    pts = blob(200, 6)
    tree = cKDTree(pts)
    normals = feature_normals(pts, tree, 10)
    assert tree.query_ball_point(pts, 0.8, return_length=True).max() > 16   # the cap binds
    ours = _fpfh(pts, normals, tree, 0.8, 15)
    np.testing.assert_allclose(ours, _o3d_fpfh(pts, normals, 0.8, 15), rtol=0, atol=1e-9)


def test_normals_are_oriented_outwards_on_a_sphere():
    rng = np.random.default_rng(2)
    u = rng.standard_normal((700, 3))
    sphere = u / np.linalg.norm(u, axis=1, keepdims=True)
    signs = rng.choice([-1.0, 1.0], size=(700, 1))
    _, idx = cKDTree(sphere).query(sphere, k=11)
    out = orient_normals(sphere, sphere * signs, idx)
    np.testing.assert_allclose(out, sphere, atol=1e-15)


def test_estimated_normals_are_consistent_on_the_blob():
    pts = blob(2000, 8)
    normals = feature_normals(pts, cKDTree(pts), 10)
    outward = np.einsum("ij,ij->i", normals, pts - pts.mean(axis=0))
    assert (outward > 0).mean() > 0.97


# --- layer 3: agreement with Open3D's algorithm, transcribed --------------------------------------


def test_agrees_with_open3d_transcription():
    seed = 0
    pts = blob(150, seed) + np.random.default_rng(seed).normal(0, 0.01, (150, 3))
    tree = cKDTree(pts)
    normals = feature_normals(pts, tree, 10)
    radius = 5 * point_spacing(pts)
    np.testing.assert_allclose(_fpfh(pts, normals, tree, radius, 100),
                               _o3d_fpfh(pts, normals, radius, 100), rtol=0, atol=1e-9)


def test_matching_pairs_corresponding_points_of_a_moved_copy():
    pts = blob(1000, 9)
    rng = np.random.default_rng(3)
    perm = rng.permutation(1000)
    moved = move(pts, random_rotation(rng), [1.0, 2.0, 3.0])[perm]
    s, t = match_features(fpfh(pts), fpfh(moved))
    assert s.size > 900
    np.testing.assert_array_equal(perm[t], s)   # identical features: every pair is right


# --- errors -----------------------------------------------------------------------------------


@pytest.mark.parametrize("kwargs, field, fragment", [
    ({"points": np.zeros((10, 2))}, "points", "(n, 3)"),
    ({"points": np.eye(3)}, "points", "at least 4"),
    ({"points": blob(50), "radius": -1.0}, "radius", "> 0"),
    ({"points": blob(50), "max_neighbors": 0}, "max_neighbors", ">= 1"),
    ({"points": blob(50), "normals": np.ones((49, 3))}, "normals", "one normal per"),
    ({"points": blob(50), "normals": np.zeros((50, 3))}, "normals", "non-zero"),
    ({"points": np.ones((10, 3))}, "points", "coincident"),
])
def test_errors_name_the_input(kwargs, field, fragment):
    with pytest.raises(InvalidInputError, match=None) as info:
        fpfh(**kwargs)
    assert info.value.field == field
    assert fragment in str(info.value)


def test_voxel_size_must_be_positive():
    with pytest.raises(InvalidInputError, match="voxel_size") as info:
        voxel_downsample(blob(10), 0.0)
    assert info.value.field == "voxel_size"


def test_max_neighbors_counts_the_point_itself():
    # Open3D's max_nn counts the query point: a cap of (most others within radius) + 1
    # never binds, a cap of (most others) does
    pts = blob(200, 6)
    tree = cKDTree(pts)
    normals = feature_normals(pts, tree, 10)
    most = int(tree.query_ball_point(pts, 0.5, return_length=True).max()) - 1  # others
    free = _fpfh(pts, normals, tree, 0.5, 10 ** 6)
    np.testing.assert_array_equal(_fpfh(pts, normals, tree, 0.5, most + 1), free)
    assert np.abs(_fpfh(pts, normals, tree, 0.5, most) - free).max() > 1e-6
    # a cap of 1 is the point alone: no neighbour enters, every histogram is empty
    assert not _fpfh(pts, normals, tree, 0.5, 1).any()


def test_radius_is_strict_as_open3ds():
    # Open3D's KDTreeSearchParamHybrid keeps the points strictly closer than the radius
    # (squared distance below the squared radius); measured with Open3D 0.20 on a grid of
    # step h with radius h: every feature zero. On a grid of step 0.5 (exact in binary)
    # the four nearest sit exactly at the radius: no neighbour, as there
    pts = _grid(5, 0.5)
    normals = np.tile([0.0, 0.0, 1.0], (25, 1))
    assert not fpfh(pts, radius=0.5, normals=normals).any()
    np.testing.assert_array_equal(_o3d_fpfh(pts, normals, 0.5, 100), 0.0)
    # a hair more and the four are neighbours: every block sums to 200
    f = fpfh(pts, radius=0.5 * (1 + 1e-12), normals=normals)
    np.testing.assert_allclose(f.reshape(25, 3, 11).sum(axis=2), 200.0)
