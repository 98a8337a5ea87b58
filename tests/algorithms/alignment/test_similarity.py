"""Tests for alignment.similarity: hand cases (the plain trace vs Umeyama's), recovery
invariants, the symmetric fit, agreement with scipy, trimesh and an independent Umeyama."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from scipy.optimize import least_squares
from scipy.spatial.transform import Rotation
from scipy.stats import special_ortho_group

from algorithms.alignment import SimilarityResult, rigid, similarity
from algorithms.core import DegenerateInputError, InvalidInputError

SEEDS = range(100)


def random_rotation(rng: np.random.Generator, d: int, *, proper: bool = True) -> np.ndarray:
    """Haar-random: a rotation, or a rotation times a mirror (det -1)."""
    q = special_ortho_group.rvs(d, random_state=rng)
    return q if proper else q @ np.diag([1.0] * (d - 1) + [-1.0])


def umeyama(x: np.ndarray, y: np.ndarray, *, reflection: bool = False):  # noqa: ANN201
    """Umeyama (1991), eqs. (34)-(42), written from the paper independently of the code
    under test: Σxy = (1/n) Σ (y - μy)(x - μx)ᵀ, S = diag(1, ..., det(U)det(V)),
    c = tr(DS)/σx²."""
    n, d = x.shape
    mx, my = x.mean(0), y.mean(0)
    sxx = ((x - mx) ** 2).sum() / n
    sxy = (y - my).T @ (x - mx) / n
    u, dd, vt = np.linalg.svd(sxy)
    s = np.eye(d)
    if not reflection and np.linalg.det(u) * np.linalg.det(vt) < 0:
        s[-1, -1] = -1
    r = u @ s @ vt
    c = np.trace(np.diag(dd) @ s) / sxx
    return c, r, my - c * r @ mx


# --- layer 1: by hand ------------------------------------------------------------------------


def test_hand_quarter_turn_double_and_shift():
    # (a, b) -> 2 (-b, a) + (3, 4): (0,0) -> (3,4); (1,0) -> (3,6); (0,2) -> (-1,4).
    res = similarity([[0, 0], [1, 0], [0, 2]], [[3, 4], [3, 6], [-1, 4]])
    np.testing.assert_allclose(res.rotation, [[0, -1], [1, 0]], atol=1e-12)
    assert res.scale == pytest.approx(2.0, abs=1e-12)
    np.testing.assert_allclose(res.linear, [[0, -2], [2, 0]], atol=1e-12)
    np.testing.assert_allclose(res.translation, [3, 4], atol=1e-12)
    np.testing.assert_allclose(res.transform, [[0, -2, 3], [2, 0, 4], [0, 0, 1]], atol=1e-12)
    assert res.rmse < 1e-12 and res.reflection is False


def test_hand_mirror_scale_uses_umeyamas_trace_not_the_plain_one():
    # Diamond mirrored across the x-axis. Centroids 0; C = (1/4) Σ y xᵀ = diag(2, -1/2),
    # σx² = (4 + 1 + 4 + 1)/4 = 5/2. U Vᵀ = diag(1, -1) is a reflection, so R = I and
    # tr(DΣ) = 2 - 1/2 = 3/2: s = (3/2)/(5/2) = 0.6 (Umeyama). The plain tr(Σ)/σx² = 1.
    x = np.array([[2, 0], [0, 1], [-2, 0], [0, -1]], dtype=float)
    y = x * [1, -1]
    res = similarity(x, y)
    np.testing.assert_allclose(res.rotation, np.eye(2), atol=1e-15)
    assert res.scale == pytest.approx(0.6, abs=1e-15)
    # Residuals 0.6 x - y: (-0.8, 0), (0, 1.6), (0.8, 0), (0, -1.6): mean square 6.4/4 = 1.6.
    assert res.rmse == pytest.approx(np.sqrt(1.6), abs=1e-14)
    # The plain trace's scale (1.0, i.e. the rigid fit) has mean square 8/4 = 2: worse.
    assert rigid(x, y).rmse == pytest.approx(np.sqrt(2.0), abs=1e-14)
    kept = similarity(x, y, allow_reflection=True)
    assert kept.scale == pytest.approx(1.0) and kept.reflection is True and kept.rmse < 1e-15


def test_hand_weights_and_symmetric_on_exact_data():
    # Third pair (weight 0) contradicts the first two: y = 3 x.
    res = similarity([[0, 0], [1, 0], [0, 5]], [[0, 0], [3, 0], [9, 9]], weights=[1, 1, 0],
                     symmetric=True)
    np.testing.assert_allclose(res.linear, 3 * np.eye(2), atol=1e-14)
    assert res.rmse == 0.0


def test_result_fields():
    names = [f.name for f in dataclasses.fields(SimilarityResult)]
    assert names == ["transform", "linear", "rotation", "translation", "scale", "rmse",
                     "reflection"]
    for name in names:
        assert f"\n    {name} : " in SimilarityResult.__doc__
    res = similarity(np.eye(3), np.eye(3) * 2)
    assert isinstance(res.scale, float) and isinstance(res.reflection, bool)
    with pytest.raises(dataclasses.FrozenInstanceError):
        res.scale = 1.0  # type: ignore[misc]


# --- layer 2: invariants and recovery -------------------------------------------------------


@pytest.mark.parametrize("d", [2, 3, 5])
@pytest.mark.parametrize("symmetric", [False, True])
def test_recovers_random_similarity(d, symmetric):
    for seed in SEEDS:
        rng = np.random.default_rng(seed)
        n = d + seed % 7
        x = rng.standard_normal((n, d)) * 3 + (1000.0 if seed % 2 else 0.0)
        rot = random_rotation(rng, d)
        s = float(np.exp(rng.uniform(-2, 2)))
        t = rng.standard_normal(d) * 10
        y = s * x @ rot.T + t
        res = similarity(x, y, symmetric=symmetric)
        msg = f"seed {seed}"
        np.testing.assert_allclose(res.rotation, rot, atol=1e-8, err_msg=msg)
        assert res.scale == pytest.approx(s, rel=1e-8), msg
        np.testing.assert_allclose(res.translation, t, atol=1e-8 * (1 + s * 1000), err_msg=msg)
        assert res.reflection is False and np.linalg.det(res.rotation) == pytest.approx(1.0)
        assert res.rmse < 1e-8 * (1 + s * 1000)
        np.testing.assert_allclose(res.transform[:d, :d], s * rot, atol=1e-8, err_msg=msg)


@pytest.mark.parametrize("d", [2, 3, 5])
def test_reflections_only_when_allowed(d):
    for seed in SEEDS:
        rng = np.random.default_rng(seed)
        x = rng.standard_normal((2 * d + 3, d))
        refl = random_rotation(rng, d, proper=False)
        y = 1.5 * x @ refl.T + 1.0
        proper = similarity(x, y)
        assert proper.reflection is False
        assert np.linalg.det(proper.rotation) == pytest.approx(1.0, abs=1e-12)
        assert proper.rmse > 1e-3
        kept = similarity(x, y, allow_reflection=True)
        assert kept.reflection is True and kept.rmse < 1e-10
        np.testing.assert_allclose(kept.rotation, refl, atol=1e-10)
        assert kept.scale == pytest.approx(1.5, rel=1e-12)


def test_reflection_fix_beats_the_plain_traces_scale():
    # Whenever the fix applies, tr(DΣ)/σx² gives a smaller residual than tr(Σ)/σx² with the
    # same rotation (the plain-trace formula); where it does not apply they agree.
    fixed = 0
    for seed in SEEDS:
        rng = np.random.default_rng(seed)
        x = rng.standard_normal((12, 3))
        y = x @ random_rotation(rng, 3, proper=bool(seed % 2)).T * 2 + rng.normal(size=(12, 3))
        res = similarity(x, y)
        xc, yc = x - x.mean(0), y - y.mean(0)
        sigma = np.linalg.svd(yc.T @ xc / 12, compute_uv=False)
        seed_scale = sigma.sum() / np.mean(np.sum(xc**2, axis=1))
        seed_rmse = np.sqrt(np.mean(np.sum((seed_scale * xc @ res.rotation.T - yc) ** 2, 1)))
        if np.isclose(res.scale, seed_scale, rtol=1e-12):
            assert res.rmse == pytest.approx(seed_rmse, rel=1e-9)
        else:
            fixed += 1
            assert res.scale < seed_scale and res.rmse < seed_rmse
    assert fixed > 10


def test_symmetric_is_the_inverse_of_the_swapped_fit():
    # Swapping source and target swaps the forward and inverse residuals: the symmetric
    # objective is the same, so the fits are inverse to each other (weights too).
    for seed in range(20):
        rng = np.random.default_rng(seed)
        x = rng.standard_normal((15, 3))
        y = 2.5 * x @ random_rotation(rng, 3).T + 4 + rng.standard_normal((15, 3)) * 0.3
        w = rng.uniform(0.2, 2.0, 15)
        fwd = similarity(x, y, weights=w, symmetric=True)
        back = similarity(y, x, weights=w, symmetric=True)
        np.testing.assert_allclose(fwd.transform @ back.transform, np.eye(4), atol=1e-10)
        assert fwd.rmse == pytest.approx(back.rmse, rel=1e-10)
        one_sided = similarity(y, x, weights=w)
        assert one_sided.scale * similarity(x, y, weights=w).scale < 1 - 1e-6


def test_symmetric_minimises_its_objective():
    rng = np.random.default_rng(5)
    x = rng.standard_normal((25, 3))
    y = 0.7 * x @ random_rotation(rng, 3).T + rng.standard_normal((25, 3)) * 0.2

    def objective(s: float, r: np.ndarray, t: np.ndarray) -> float:
        e = s * x @ r.T + t - y
        g = (y - t) @ r / s - x
        return float(np.mean(np.sum(e**2, 1)) + np.mean(np.sum(g**2, 1)))

    res = similarity(x, y, symmetric=True)
    best = objective(res.scale, res.rotation, res.translation)
    assert res.rmse == pytest.approx(np.sqrt(best / 2), rel=1e-12)
    for ds in (-1e-4, 1e-4):
        assert objective(res.scale + ds, res.rotation, res.translation) > best
    for _ in range(5):
        dt = rng.standard_normal(3) * 1e-4
        assert objective(res.scale, res.rotation, res.translation + dt) > best
    assert res.scale != pytest.approx(similarity(x, y).scale, rel=1e-6)


@pytest.mark.parametrize("d", [2, 3, 5])
def test_zero_weight_outliers_and_duplicates(d):
    for seed in range(30):
        rng = np.random.default_rng(seed)
        n = 3 * d
        x = rng.standard_normal((n, d))
        rot, s, t = random_rotation(rng, d), 0.5 + seed / 10, rng.standard_normal(d)
        y = s * x @ rot.T + t
        bad = rng.choice(n, size=d, replace=False)
        y[bad] += rng.standard_normal((d, d)) * 50
        w = np.ones(n)
        w[bad] = 0.0
        res = similarity(x, y, weights=w)
        np.testing.assert_allclose(res.linear, s * rot, atol=1e-9)
        np.testing.assert_allclose(res.translation, t, atol=1e-9)
    rng = np.random.default_rng(1)
    x = rng.standard_normal((8, 3))
    y = x @ random_rotation(rng, 3).T * 3 + rng.standard_normal((8, 3)) * 0.2
    k = rng.integers(1, 4, size=8)
    weighted = similarity(x, y, weights=k.astype(float))
    repeated = similarity(np.repeat(x, k, axis=0), np.repeat(y, k, axis=0))
    np.testing.assert_allclose(weighted.transform, repeated.transform, atol=1e-12)
    assert weighted.rmse == pytest.approx(repeated.rmse, rel=1e-12)


# --- layer 3: peers --------------------------------------------------------------------------


@pytest.mark.parametrize("d", [2, 3, 5])
def test_agrees_with_independent_umeyama(d):
    for seed in SEEDS:
        rng = np.random.default_rng(seed)
        x = rng.standard_normal((10 + d, d))
        proper = seed % 3 != 0
        y = 2 * x @ random_rotation(rng, d, proper=proper).T + rng.normal(size=(10 + d, d))
        for allow in (False, True):
            c, r, t = umeyama(x, y, reflection=allow)
            res = similarity(x, y, allow_reflection=allow)
            np.testing.assert_allclose(res.rotation, r, atol=1e-10)
            assert res.scale == pytest.approx(c, rel=1e-10)
            np.testing.assert_allclose(res.translation, t, atol=1e-10)


def test_agrees_with_scipy_align_vectors_and_least_squares():
    for seed in range(30):
        rng = np.random.default_rng(seed)
        x = rng.standard_normal((20, 3))
        y = 1.8 * x @ Rotation.random(random_state=rng).as_matrix().T + [1, 2, 3]
        y += rng.standard_normal((20, 3)) * 0.1
        w = rng.uniform(0.2, 2.0, 20)
        res = similarity(x, y, weights=w)
        xc = x - w @ x / w.sum()
        yc = y - w @ y / w.sum()
        rot, _ = Rotation.align_vectors(yc, xc, weights=w)
        np.testing.assert_allclose(res.rotation, rot.as_matrix(), atol=1e-10)

        # a generic solver on (log s, rotation vector, t) from a perturbed start
        def resid(v: np.ndarray, x: np.ndarray = x, y: np.ndarray = y,
                  w: np.ndarray = w) -> np.ndarray:
            r = Rotation.from_rotvec(v[1:4]).as_matrix()
            return ((np.exp(v[0]) * x @ r.T + v[4:] - y) * np.sqrt(w)[:, None]).ravel()

        start = np.r_[np.log(res.scale) + 0.1, rot.as_rotvec() + 0.05, res.translation + 0.1]
        opt = least_squares(resid, start, xtol=1e-15, ftol=1e-15, gtol=1e-15)
        assert res.scale == pytest.approx(np.exp(opt.x[0]), rel=1e-7)
        np.testing.assert_allclose(res.translation, opt.x[4:], atol=1e-7)


def test_agrees_with_trimesh_on_exact_data_and_beats_it_on_noisy():
    import trimesh.registration as registration
    for seed in range(20):
        rng = np.random.default_rng(seed)
        x = rng.standard_normal((15, 3))
        y = 2.0 * x @ Rotation.random(random_state=rng).as_matrix().T + 1.0
        matrix, _, _ = registration.procrustes(x, y, reflection=False, scale=True)
        np.testing.assert_allclose(similarity(x, y).transform, matrix, atol=1e-10)
        # trimesh's scale is |Ỹ|/|X̃| (the shortcut): not least squares once noisy
        noisy = y + rng.standard_normal((15, 3)) * 0.5
        matrix, _, cost = registration.procrustes(x, noisy, reflection=False, scale=True,
                                                  return_cost=True)
        res = similarity(x, noisy)
        assert res.rmse**2 <= cost + 1e-12
        assert res.scale <= np.linalg.norm(matrix[:3, 0]) + 1e-12


# --- errors ----------------------------------------------------------------------------------


def test_error_too_few_points():
    with pytest.raises(InvalidInputError, match=r"`source` to hold at least 3 points .*got 2") \
            as info:
        similarity(np.zeros((2, 3)), np.zeros((2, 3)))
    assert info.value.field == "source"


def test_error_counts_and_dimensions_differ():
    with pytest.raises(InvalidInputError, match=r"`target` to hold as many points as `source`"):
        similarity(np.eye(4, 3), np.eye(3))
    with pytest.raises(InvalidInputError, match=r"d >= 2 coordinates per point"):
        similarity(np.zeros((3, 1)), np.zeros((3, 1)))


@pytest.mark.parametrize("which", ["source", "target"])
def test_error_nonfinite(which):
    x = np.random.default_rng(0).standard_normal((5, 3))
    bad = x.copy()
    bad[2, 1] = np.nan
    args = (bad, x) if which == "source" else (x, bad)
    with pytest.raises(InvalidInputError, match=rf"`{which}` to hold finite numbers, got nan at "
                       r"row 2") as info:
        similarity(*args)
    assert info.value.field == which


def test_error_weights_and_flags():
    x = np.eye(3)
    with pytest.raises(InvalidInputError, match=r"`weights` to be non-negative"):
        similarity(x, x, weights=[1, -1, 1])
    with pytest.raises(InvalidInputError, match=r"`symmetric` to be true or false"):
        similarity(x, x, symmetric="yes")
    with pytest.raises(InvalidInputError, match=r"`allow_reflection` to be true or false"):
        similarity(x, x, allow_reflection=1)


def test_degenerate_coincident_and_collinear():
    rng = np.random.default_rng(0)
    with pytest.raises(DegenerateInputError, match=r"`source` .* coincident") as info:
        similarity(np.ones((5, 3)), rng.standard_normal((5, 3)))
    assert info.value.field == "source"
    line = np.linspace(0, 1, 6)[:, None] * [1.0, 2.0, 3.0]
    with pytest.raises(DegenerateInputError, match=r"`target` .* collinear .* undetermined") \
            as info:
        similarity(rng.standard_normal((6, 3)), line)
    assert info.value.field == "target"


def test_degenerate_zero_scale_mirror_with_equal_singular_values():
    # C = (1/4) diag(2, -2): both singular values 1/2 and U Vᵀ a reflection, so
    # tr(DΣ) = 1/2 - 1/2 = 0: no proper rotation correlates the sets at all.
    x = np.array([[1, 0], [0, 1], [-1, 0], [0, -1]], dtype=float)
    with pytest.raises(DegenerateInputError, match=r"best scale of zero: .*collapsing") as info:
        similarity(x, x * [1, -1])
    assert info.value.field is None
    assert similarity(x, x * [1, -1], allow_reflection=True).rmse < 1e-15


def test_docstring_examples_run():
    import doctest
    import sys

    assert doctest.testmod(sys.modules["algorithms.alignment.similarity"]).failed == 0
