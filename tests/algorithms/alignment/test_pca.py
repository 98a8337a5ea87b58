"""Tests for alignment.pca: a hand case, recovery of known similarities on skewed clouds in
both modes, the sign rules, reflections, sizes that differ, agreement with numpy's SVD and
the assignment family's Chamfer distance."""

from __future__ import annotations

import dataclasses
import itertools
import sys

import numpy as np
import pytest
from scipy.spatial import cKDTree
from scipy.stats import special_ortho_group

from algorithms.alignment import PCAResult, pca
from algorithms.assignment import nearest
from algorithms.core import DegenerateInputError, InvalidInputError

SEEDS = range(100)

# Six points, centroid 0: variances 1 along x and 1/4 along y, no covariance; third
# moments +1 along x (a long tail to the right) and -1/8 along y (a tail downwards).
SKEWED = np.array([[-1, 0], [-1, 0], [2, 0], [0, 0.5], [0, 0.5], [0, -1]])
QUARTER = np.array([[0.0, -1.0], [1.0, 0.0]])


def rotation_2d(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s], [s, c]])


def random_rotation(rng: np.random.Generator, d: int, *, proper: bool = True) -> np.ndarray:
    """Haar-random: a rotation, or a rotation times a mirror (det -1)."""
    q = special_ortho_group.rvs(d, random_state=rng)
    return q if proper else q @ np.diag([1.0] * (d - 1) + [-1.0])


def skewed_cloud(rng: np.random.Generator, n: int, d: int) -> np.ndarray:
    """Gamma-distributed (skewed along every axis), distinct spreads, randomly turned."""
    spreads = np.linspace(3.0, 1.0, d)
    return (rng.gamma(2.0, size=(n, d)) * spreads) @ random_rotation(rng, d).T + 5.0


def similar_copy(rng: np.random.Generator, x: np.ndarray, *, proper: bool = True):  # noqa: ANN201
    """Shuffled rows, moved by a random similarity (s R, t)."""
    d = x.shape[1]
    rot, s, t = random_rotation(rng, d, proper=proper), float(np.exp(rng.uniform(-1, 1))), \
        rng.standard_normal(d) * 10
    return s * x[rng.permutation(len(x))] @ rot.T + t, s, rot, t


# --- layer 1: by hand ------------------------------------------------------------------------


@pytest.mark.parametrize("mode", ["oriented", "unoriented"])
def test_hand_quarter_turn_triple_and_shift(mode):
    # y = 3 R90 x + (1, 2), rows reversed. Target variances 9/4 along x and 9 along y: the
    # major axes pair x with y. Skews: source +x, -y; target +y (3 p_x) and +x (-3 p_y).
    # E = [x, -y], E' = [y, x]: R = E' Eᵀ = R90, K = (√(9/1), √(2.25/0.25)) = (3, 3).
    y = (3 * SKEWED @ QUARTER.T + [1, 2])[::-1]
    res = pca(SKEWED, y, mode=mode)
    np.testing.assert_allclose(res.rotation, QUARTER, atol=1e-14)
    np.testing.assert_allclose(res.scale, [3, 3], atol=1e-14)
    np.testing.assert_allclose(res.linear, 3 * QUARTER, atol=1e-14)
    np.testing.assert_allclose(res.translation, [1, 2], atol=1e-14)
    np.testing.assert_allclose(res.axes, [[1, 0], [0, -1]], atol=1e-14)
    np.testing.assert_allclose(res.rotation @ res.axes, [[0, 1], [1, 0]], atol=1e-14)
    np.testing.assert_allclose(res.transform, [[0, -3, 1], [3, 0, 2], [0, 0, 1]], atol=1e-14)
    assert res.rmse < 1e-14 and res.chamfer < 1e-13 and res.reflection is False


def test_hand_scale_options():
    # Target stretched by (2, 1/2) along the source's own axes: variances 4 and 1/16.
    y = SKEWED * [2.0, 0.5]
    aniso = pca(SKEWED, y, scale="anisotropic")
    np.testing.assert_allclose(aniso.linear, np.diag([2.0, 0.5]), atol=1e-14)
    # isotropic: √((4 + 1/16)/(1 + 1/4)) = √3.25
    iso = pca(SKEWED, y, scale="isotropic")
    np.testing.assert_allclose(iso.scale, [np.sqrt(3.25)] * 2, atol=1e-14)
    np.testing.assert_allclose(iso.rotation, np.eye(2), atol=1e-14)
    # none: the skews still orient the axes (the Chamfer rule would prefer the half turn for
    # these unscaled shapes, 7.3 against 10)
    rigid_only = pca(SKEWED, y, scale="none", mode="oriented")
    np.testing.assert_allclose(rigid_only.linear, np.eye(2), atol=1e-14)
    assert pca(SKEWED, y, scale="none").chamfer < rigid_only.chamfer


def test_hand_rotation_rule_picks_the_smaller_angle():
    # Turned by 150°: in 2-D the two proper sign choices are R and -R (150° and -30°). The
    # rotation rule takes the larger trace, 2cos(-30°) > 2cos(150°): the wrong one here;
    # the residual rule and the oriented mode get it right.
    y = SKEWED @ rotation_2d(np.radians(150)).T
    by_trace = pca(SKEWED, y, choose="rotation")
    np.testing.assert_allclose(by_trace.rotation, rotation_2d(np.radians(-30)), atol=1e-14)
    for res in (pca(SKEWED, y), pca(SKEWED, y, mode="oriented")):
        np.testing.assert_allclose(res.rotation, rotation_2d(np.radians(150)), atol=1e-14)
        assert res.rmse < 1e-14
    assert by_trace.rmse > 0.1


def test_result_fields():
    names = [f.name for f in dataclasses.fields(PCAResult)]
    assert names == ["transform", "linear", "rotation", "scale", "axes", "translation",
                     "rmse", "chamfer", "reflection"]
    for name in names:
        assert f"\n    {name} : " in PCAResult.__doc__


# --- layer 2: recovery and invariants ---------------------------------------------------------


@pytest.mark.parametrize("d", [2, 3, 5])
@pytest.mark.parametrize("mode", ["oriented", "unoriented"])
def test_recovers_known_similarity_on_skewed_clouds(d, mode):
    for seed in SEEDS:
        rng = np.random.default_rng(seed)
        x = skewed_cloud(rng, 60 + seed, d)
        y, s, rot, t = similar_copy(rng, x)
        scale = ("isotropic", "anisotropic")[seed % 2]
        res = pca(x, y, mode=mode, scale=scale)
        msg = f"seed {seed}"
        np.testing.assert_allclose(res.rotation, rot, atol=1e-8, err_msg=msg)
        np.testing.assert_allclose(res.scale, s, rtol=1e-8, err_msg=msg)
        np.testing.assert_allclose(res.linear, s * rot, atol=1e-8, err_msg=msg)
        np.testing.assert_allclose(res.translation, t, atol=1e-7, err_msg=msg)
        assert res.reflection is False and res.rmse < 1e-8
        if seed % 10 == 0:  # rigid copies with scale="none"
            y1 = (y - t) / s + t
            np.testing.assert_allclose(pca(x, y1, mode=mode, scale="none").rotation, rot,
                                       atol=1e-8)


@pytest.mark.parametrize("d", [2, 3, 5])
def test_rotation_rule_is_the_largest_trace_and_recovers_small_turns(d):
    for seed in range(40):
        rng = np.random.default_rng(seed)
        x = skewed_cloud(rng, 80, d)
        k = rng.standard_normal((d, d)) * 0.15
        small = np.linalg.solve(np.eye(d) - (k - k.T), np.eye(d) + (k - k.T))  # a small turn
        y = x[::-1] @ small.T
        res = pca(x, y, choose="rotation", scale="none")
        np.testing.assert_allclose(res.rotation, small, atol=1e-8, err_msg=f"seed {seed}")
        # brute force: no proper sign choice has a larger trace
        e = np.linalg.eigh(np.cov(x.T))[1]
        f = np.linalg.eigh(np.cov(y.T))[1]
        traces = [np.trace(f[:, ::-1] @ np.diag(sg) @ e[:, ::-1].T)
                  for sg in itertools.product((1, -1), repeat=d)
                  if np.linalg.det(f @ np.diag(sg) @ e.T) > 0]
        assert np.trace(res.rotation) >= max(traces) - 1e-10


@pytest.mark.parametrize("d", [2, 3])
@pytest.mark.parametrize("mode", ["oriented", "unoriented"])
def test_reflections_only_when_allowed(d, mode):
    for seed in range(40):
        rng = np.random.default_rng(seed)
        x = skewed_cloud(rng, 80, d)
        y, s, mirror, t = similar_copy(rng, x, proper=False)
        proper = pca(x, y, mode=mode)
        assert proper.reflection is False
        assert np.linalg.det(proper.rotation) == pytest.approx(1.0)
        assert proper.rmse > 1e-3
        kept = pca(x, y, mode=mode, allow_reflection=True)
        assert kept.reflection is True
        np.testing.assert_allclose(kept.linear, s * mirror, atol=1e-8, err_msg=f"seed {seed}")


def test_oriented_reflection_fix_flips_the_smallest_axis():
    # The fix flips the eigenvector of the smallest eigenvalue. A mirror across the
    # minor axis (y -> -y) keeps the major axis and reverses the minor one.
    y = SKEWED * [1, -1]
    res = pca(SKEWED, y, mode="oriented")
    np.testing.assert_allclose(res.rotation, np.eye(2), atol=1e-14)
    kept = pca(SKEWED, y, mode="oriented", allow_reflection=True)
    np.testing.assert_allclose(kept.rotation, np.diag([1, -1]), atol=1e-14)


def test_sizes_may_differ_covariances_are_normalised():
    rng = np.random.default_rng(1)
    x = skewed_cloud(rng, 200, 3)
    y, s, rot, t = similar_copy(rng, x)
    once = pca(x, y)
    twice = pca(x, np.r_[y, y])  # m = 2n: unnormalised covariances would give √2 s
    np.testing.assert_allclose(twice.transform, once.transform, atol=1e-10)
    np.testing.assert_allclose(twice.scale, s, rtol=1e-10)
    # different samples of one distribution, of different sizes: close, not exact
    big = skewed_cloud(np.random.default_rng(2), 20000, 3)
    y = 2.0 * big[:15000] @ rot.T
    res = pca(big[15000:], y, scale="isotropic")
    np.testing.assert_allclose(res.rotation, rot, atol=0.05)
    assert res.scale[0] == pytest.approx(2.0, rel=0.05)


def test_symmetric_counts_the_inverse_residuals():
    rng = np.random.default_rng(4)
    x = skewed_cloud(rng, 50, 2)
    y = skewed_cloud(rng, 70, 2)
    fwd = pca(x, y)
    sym = pca(x, y, symmetric=True)
    np.testing.assert_array_equal(sym.transform, fwd.transform)
    moved = x @ fwd.linear.T + fwd.translation
    back = np.linalg.solve(fwd.linear, (y - fwd.translation).T).T
    forward = cKDTree(y).query(moved)[0]
    inverse = cKDTree(x).query(back)[0]
    assert fwd.rmse == pytest.approx(np.sqrt(np.mean(forward**2)), rel=1e-12)
    assert sym.rmse == pytest.approx(np.sqrt((np.mean(forward**2) + np.mean(inverse**2)) / 2),
                                     rel=1e-12)


# --- layer 3: peers ---------------------------------------------------------------------------


def test_agrees_with_numpy_svd_and_assignment_chamfer():
    for seed in range(20):
        rng = np.random.default_rng(seed)
        x = skewed_cloud(rng, 100, 3)
        y = skewed_cloud(rng, 130, 3)
        res = pca(x, y)
        # principal axes = right singular vectors of the centred data, up to sign
        vt = np.linalg.svd(x - x.mean(0))[2]
        np.testing.assert_allclose(np.abs(res.axes.T @ vt.T), np.eye(3), atol=1e-10)
        sx = np.linalg.svd(x - x.mean(0), compute_uv=False) / np.sqrt(len(x))
        sy = np.linalg.svd(y - y.mean(0), compute_uv=False) / np.sqrt(len(y))
        np.testing.assert_allclose(res.scale, sy / sx, rtol=1e-10)
        moved = x @ res.linear.T + res.translation
        both = nearest(moved, y, direction="both")
        assert res.chamfer == pytest.approx(both.distances.sum(), rel=1e-12)
        assert res.rmse == pytest.approx(nearest(moved, y).rmse, rel=1e-12)
        # the residual rule took the sign choice of least Chamfer distance
        for other in itertools.product((1.0, -1.0), repeat=3):
            lin = res.rotation @ res.axes @ np.diag(np.array(other) * res.scale) @ res.axes.T
            if np.linalg.det(lin) < 0:
                continue
            alt = nearest((x - x.mean(0)) @ lin.T + y.mean(0), y, direction="both")
            assert alt.distances.sum() >= res.chamfer - 1e-9


# --- errors ----------------------------------------------------------------------------------


def test_error_inputs():
    x = SKEWED
    with pytest.raises(InvalidInputError, match=r"`target` to have the same dimension as "
                       r"`source` \(2\)") as info:
        pca(x, np.zeros((5, 3)))
    assert info.value.field == "target"
    with pytest.raises(InvalidInputError, match=r"`source` to hold at least 2 points, got 1"):
        pca(x[:1], x)
    with pytest.raises(InvalidInputError, match=r"d >= 2 coordinates per point"):
        pca(x[:, :1], x[:, :1])
    bad = x.copy()
    bad[3, 0] = np.nan
    with pytest.raises(InvalidInputError, match=r"`target` to hold finite numbers, got nan at "
                       r"row 3") as info:
        pca(x, bad)
    assert info.value.field == "target"


@pytest.mark.parametrize(("option", "value"), [("mode", "sideways"), ("choose", "random"),
                                               ("scale", "huge")])
def test_error_unknown_options(option, value):
    with pytest.raises(InvalidInputError, match=rf"`{option}` to be one of .*, got '{value}'") \
            as info:
        pca(SKEWED, SKEWED, **{option: value})
    assert info.value.field == option


def test_error_flags():
    with pytest.raises(InvalidInputError, match=r"`symmetric` to be true or false"):
        pca(SKEWED, SKEWED, symmetric="no")
    with pytest.raises(InvalidInputError, match=r"`allow_reflection` to be true or false"):
        pca(SKEWED, SKEWED, allow_reflection=0)


def test_degenerate_sets():
    with pytest.raises(DegenerateInputError, match=r"`target` to span at least 2 dimensions .* "
                       r"got 0: the points are coincident and the principal axes are "
                       r"undetermined") as info:
        pca(SKEWED, np.ones((4, 2)))
    assert info.value.field == "target"
    line3 = np.linspace(0, 1, 5)[:, None] ** 2 * [1.0, 2.0, 3.0]
    with pytest.raises(DegenerateInputError, match=r"`source` .* collinear and the principal "
                       r"axes are undetermined") as info:
        pca(line3, skewed_cloud(np.random.default_rng(0), 20, 3), scale="none")
    assert info.value.field == "source"


def test_degenerate_flat_set_only_where_it_matters():
    line = np.c_[np.array([0.0, 1.0, 1.5, 4.0]), np.zeros(4)]
    moved = line @ QUARTER.T * 2
    res = pca(line, moved, scale="isotropic")  # a 2-D line still has its axes
    np.testing.assert_allclose(res.linear, 2 * QUARTER, atol=1e-12)
    with pytest.raises(DegenerateInputError, match=r"collinear and the anisotropic scale "
                       r"divides by every variance"):
        pca(line, moved)
    with pytest.raises(DegenerateInputError, match=r"collinear and a reflection across the flat"):
        pca(line, moved, scale="none", allow_reflection=True)
    with pytest.raises(DegenerateInputError, match=r"collinear and the inverse map"):
        pca(line, moved, scale="none", symmetric=True)


def test_docstring_examples_run():
    import doctest

    assert doctest.testmod(sys.modules["algorithms.alignment.pca"]).failed == 0
