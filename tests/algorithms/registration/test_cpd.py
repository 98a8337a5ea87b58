"""Tests for registration.cpd: the posterior by hand and against a dense reference (blocks of
any size give the same sums to 1e-12, underflowing rows stay exact), recovery of rigid
(scaled or not, any dimension), affine and nonrigid maps on generated shapes, outliers, the
low-rank kernel, bounded memory, progress and cancellation, every error branch, and agreement
with pycpd iteration by iteration."""

from __future__ import annotations

import sys
import tracemalloc
import warnings

import numpy as np
import pytest
from scipy.linalg import expm
from scipy.spatial.transform import Rotation
from scipy.special import logsumexp, softmax

from algorithms.core import Cancelled, ConvergenceWarning, DegenerateInputError, InvalidInputError
from algorithms.registration import CPDResult, cpd
from algorithms.registration.cpd import _kernel, _low_rank, _Posterior
from tests.algorithms.registration._real_meshes import real_mesh
from tests.algorithms.registration._shapes import angle_deg, bent_bar, blob, move, rotation_about

cpd_mod = sys.modules["algorithms.registration.cpd"]


def quiet(*args, **kw) -> CPDResult:  # noqa: ANN002, ANN003
    """cpd without the ConvergenceWarning of runs stopped by max_iterations on purpose."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        return cpd(*args, **kw)


def dense_posterior(x, ty, sigma2, w):  # noqa: ANN001, ANN201
    """The paper's E-step written out with the whole M×N matrix, in log space."""
    m, d = ty.shape
    n = x.shape[0]
    a = -((x[None, :, :] - ty[:, None, :]) ** 2).sum(axis=2) / (2 * sigma2)   # M×N
    log_c = (0.5 * d * np.log(2 * np.pi * sigma2) + np.log(w / (1 - w)) + np.log(m / n)
             if w > 0 else -np.inf)
    log_den = np.logaddexp(logsumexp(a, axis=0), log_c)                        # N
    p = np.exp(a - log_den[None, :])
    return p.sum(axis=1), p.sum(axis=0), p @ x, float(log_den.sum())


# --- layer 1: by hand -----------------------------------------------------------------------


def test_hand_posterior_of_two_centroids_and_one_point():
    # One target point at 0, centroids at 1 and 2, σ² = 1, w = 0: P = softmax(-1/2, -2).
    x = np.array([[0.0, 0.0]])
    ty = np.array([[1.0, 0.0], [2.0, 0.0]])
    p1, pt1, px, log_den = _Posterior(x, 2, 1 << 20)(ty, 1.0, -np.inf)
    e1, e2 = np.exp(-0.5), np.exp(-2.0)
    np.testing.assert_allclose(p1, [e1 / (e1 + e2), e2 / (e1 + e2)], rtol=1e-15)
    np.testing.assert_allclose(pt1, [1.0], rtol=1e-15)
    np.testing.assert_allclose(px, [[0, 0], [0, 0]], atol=0)
    assert log_den == pytest.approx(np.log(e1 + e2), rel=1e-15)
    # With the outlier weight w, c = 2πσ² w/(1-w) M/N joins the denominator.
    c = 2 * np.pi * 0.25 / 0.75 * 2
    p1, pt1, _, _ = _Posterior(x, 2, 1 << 20)(ty, 1.0, float(np.log(c)))
    np.testing.assert_allclose(p1, [e1 / (e1 + e2 + c), e2 / (e1 + e2 + c)], rtol=1e-14)
    np.testing.assert_allclose(pt1, [(e1 + e2) / (e1 + e2 + c)], rtol=1e-14)


def test_hand_shift_is_recovered_exactly():
    src = np.array([[0, 0], [10, 0], [0, 10], [3, 7]], float)
    res = cpd(src, src[::-1] + [0.5, 0.2])
    np.testing.assert_allclose(res.transform, [[1, 0, 0.5], [0, 1, 0.2], [0, 0, 1]],
                               atol=1e-9)
    assert res.converged and res.scale == pytest.approx(1.0, abs=1e-9)
    np.testing.assert_allclose(res.moved, src + [0.5, 0.2], atol=1e-9)
    assert res.rmse < 1e-9


@pytest.mark.parametrize("w", [0.0, 0.3])
def test_blocks_of_any_size_give_the_dense_posterior(w):
    rng = np.random.default_rng(3)
    x, ty = rng.normal(size=(53, 3)), rng.normal(size=(41, 3))
    want = dense_posterior(x, ty, 0.4, w)
    log_c = (1.5 * np.log(2 * np.pi * 0.4) + np.log(w / (1 - w)) + np.log(41 / 53)
             if w else -np.inf)
    for chunk in (8 * 41 * 1, 8 * 41 * 7, 8 * 41 * 53, 1 << 30):     # 1, 7, 53, all rows
        got = _Posterior(x, 41, chunk)(ty, 0.4, log_c)
        for a, b in zip(got[:3], want[:3]):
            np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-15)
        assert got[3] == pytest.approx(want[3], rel=1e-12)


@pytest.mark.parametrize("sigma2, w", [(0.0005, 0.0), (0.002, 0.2)])
def test_truncated_sums_equal_the_dense_posterior(sigma2, w):
    # σ small against the sets: each block of target points meets only the nearby source
    # points; what is left out is below rounding, so the sums are the dense ones to 1e-12.
    rng = np.random.default_rng(4)
    ty = blob(900, 1)
    x = np.vstack([blob(700, 2), rng.uniform(-2, 2, (20, 3))])    # some far from everything
    want = dense_posterior(x, ty, sigma2, w)
    log_c = (1.5 * np.log(2 * np.pi * sigma2) + np.log(w / (1 - w)) + np.log(900 / 720)
             if w else -np.inf)
    post = _Posterior(x, 900, 1 << 24)
    plan = list(post._plan(ty, sigma2))
    assert all(idx is not None for _, _, idx in plan)
    assert sum(idx.size * (hi - lo) for lo, hi, idx in plan) < 0.5 * 900 * 720
    got = post(ty, sigma2, log_c)
    # rtol 1e-10: the exponents come from |x|² + |t|² - 2 x·t, whose rounding (1e-16 of
    # |x|² ≈ 1) is divided by 2σ² = 1e-3 here; truncation itself adds below 1e-16.
    for a, b in zip(got[:3], want[:3]):
        np.testing.assert_allclose(a, b, rtol=1e-10, atol=1e-300)
    assert got[3] == pytest.approx(want[3], rel=1e-12)


def test_underflowing_rows_stay_exact():
    # σ² tiny: every exponent of the far target point underflows; its posterior is still the
    # softmax over the centroids (all mass on the nearest), not zero.
    x = np.array([[0.0, 0.0], [50.0, 0.0]])
    ty = np.array([[0.0, 0.1], [1.0, 0.0], [49.0, 0.0]])
    sigma2 = 1e-3
    p1, pt1, px, log_den = _Posterior(x, 3, 1 << 20)(ty, sigma2, -np.inf)
    a = -((x[None] - ty[:, None]) ** 2).sum(axis=2) / (2 * sigma2)
    p = softmax(a, axis=0)
    # (posteriors below 1e-54 are only exact to 1e-54 absolute: exponents are clipped)
    np.testing.assert_allclose(p1, p.sum(axis=1), rtol=1e-12, atol=1e-54)
    np.testing.assert_allclose(pt1, [1.0, 1.0], rtol=1e-12)
    np.testing.assert_allclose(px, p @ x, rtol=1e-12, atol=1e-52)
    assert log_den == pytest.approx(float(logsumexp(a, axis=0).sum()), rel=1e-12)


def test_small_blocks_change_nothing_in_a_whole_run(monkeypatch):
    rng = np.random.default_rng(0)
    src = blob(150, 1)
    dst = move(blob(140, 2), rotation_about([1, 1, 0], 25), [0.2, 0.0, 0.1], rng)
    for model in ("rigid", "affine", "nonrigid"):
        whole = quiet(src, dst, model=model, w=0.1, max_iterations=15, tolerance=0)
        monkeypatch.setattr(cpd_mod, "CHUNK_BYTES", 8 * 150 * 11)   # 11 rows: 13 blocks
        small = quiet(src, dst, model=model, w=0.1, max_iterations=15, tolerance=0)
        monkeypatch.undo()
        np.testing.assert_allclose(small.moved, whole.moved, rtol=0, atol=1e-12)
        assert small.sigma2 == pytest.approx(whole.sigma2, rel=1e-12)
        assert small.iterations == whole.iterations == 15


def test_threads_change_nothing(monkeypatch):
    # The blocks go to fixed partitions summed in a fixed order: one thread or four give
    # bit-identical results.
    rng = np.random.default_rng(2)
    src = blob(700, 1)
    dst = move(blob(650, 2), rotation_about([0, 1, 1], 20), [0.1, 0.2, 0.0], rng)
    runs = []
    for cores in (1, 4):
        # forced, whatever the blocks' size (the policy would keep small ones serial)
        monkeypatch.setattr(cpd_mod, "block_workers",
                            lambda block, total, parts, cores=cores: min(parts, cores))
        runs.append(quiet(src, dst, w=0.05, max_iterations=20, tolerance=0))
    np.testing.assert_array_equal(runs[0].moved, runs[1].moved)
    assert runs[0].sigma2 == runs[1].sigma2


def test_memory_stays_within_the_block_budget(monkeypatch):
    # 2000 × 2000 points: the posterior would take 32 MB; with 2 MB blocks the peak of
    # everything numpy allocates stays far below it.
    rng = np.random.default_rng(1)
    src = rng.normal(size=(2000, 3))
    dst = src @ rotation_about([0, 0, 1], 5).T
    monkeypatch.setattr(cpd_mod, "CHUNK_BYTES", 2 * 2**20)
    tracemalloc.start()
    try:
        quiet(src, dst, max_iterations=2, tolerance=0)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < 6 * 2**20, peak


# --- layer 2: recovery and invariants -------------------------------------------------------


@pytest.mark.parametrize("seed", range(5))
def test_rigid_recovers_scale_and_rotation(seed):
    rng = np.random.default_rng(seed)
    src = blob(250, seed)
    # CPD is a local method: any axis, angles up to 60° (its basin on this shape)
    rot = rotation_about(rng.normal(size=3), float(rng.uniform(10.0, 60.0)))
    s = float(rng.uniform(0.5, 2.0))
    dst = move(src, s * rot, rng.normal(size=3), rng)
    res = cpd(src, dst)
    assert res.converged
    assert angle_deg(res.rotation, rot) < 1e-5      # arccos resolves ~1e-6° at best
    assert res.scale == pytest.approx(s, rel=1e-8)
    np.testing.assert_allclose(res.rotation @ res.rotation.T, np.eye(3), atol=1e-12)
    assert np.linalg.det(res.rotation) == pytest.approx(1.0)
    np.testing.assert_allclose(res.transform[:3, :3], s * rot, atol=1e-7)
    np.testing.assert_allclose(res.moved, src @ (s * rot).T + res.translation, atol=1e-12)


def test_rigid_with_noise_and_without_scale():
    rng = np.random.default_rng(7)
    src = blob(400, 3)
    rot = rotation_about([0, 1, 1], 35)
    dst = move(src, rot, [0.3, -0.1, 0.2], rng) + rng.normal(0, 0.005, (400, 3))
    res = cpd(src, dst, scale=False)
    assert res.scale == 1.0 and angle_deg(res.rotation, rot) < 0.2
    np.testing.assert_allclose(res.linear, res.rotation, atol=0)
    assert res.rmse < 0.02 and 0 < res.sigma2 < 1e-3


@pytest.mark.parametrize("d", [2, 4, 5])
def test_rigid_in_any_dimension(d):
    rng = np.random.default_rng(d)
    src = rng.gamma(2.0, size=(120, d)) * np.linspace(1.0, 0.4, d)   # skewed, no symmetry
    # a modest turn about a random plane mix, so that the start is in the basin (CPD is a
    # local method): the exponential of a small skew-symmetric matrix
    k = rng.normal(size=(d, d))
    rot = expm(0.15 * (k - k.T))
    dst = move(src, 1.2 * rot, np.arange(d) * 0.1, rng)
    res = cpd(src, dst)
    np.testing.assert_allclose(res.linear, 1.2 * rot, atol=1e-7)
    assert res.transform.shape == (d + 1, d + 1)


def test_affine_recovers_an_affine_map():
    rng = np.random.default_rng(2)
    src = blob(300, 4)
    lin = np.array([[1.2, 0.2, 0.0], [-0.1, 0.9, 0.15], [0.05, 0.0, 0.7]])
    dst = move(src, lin, [0.1, 0.2, -0.3], rng)
    res = cpd(src, dst, model="affine")
    np.testing.assert_allclose(res.linear, lin, atol=1e-7)
    np.testing.assert_allclose(res.translation, [0.1, 0.2, -0.3], atol=1e-7)
    assert res.rotation is None and res.scale is None


def test_outlier_weight_resists_clutter():
    rng = np.random.default_rng(5)
    src = blob(300, 5)
    rot = rotation_about([1, 0, 1], 30)
    dst = np.vstack([move(src, rot, [0.1, 0.0, 0.0]) + rng.normal(0, 0.01, (300, 3)),
                     rng.uniform(-3, 3, (120, 3))])                   # 29% clutter
    robust = cpd(src, dst, w=0.3)
    plain = quiet(src, dst, w=0.0)
    assert angle_deg(robust.rotation, rot) < 0.5
    assert angle_deg(robust.rotation, rot) < angle_deg(plain.rotation, rot)


def _size(points: np.ndarray) -> float:
    return float(np.linalg.norm(points.max(axis=0) - points.min(axis=0)))


def test_nonrigid_maps_a_bent_bar_onto_its_target():
    src, dst = bent_bar(400, 0, bend=0.9), bent_bar(400, 0, bend=0.1)   # same samples
    res = cpd(src, dst, model="nonrigid")
    size = _size(dst)
    assert res.rmse < 0.02 * size
    # and point by point (the sampling is the same), not only to the nearest target point
    assert np.sqrt(np.mean(np.sum((res.moved - dst) ** 2, axis=1))) < 0.02 * size
    assert res.transform is None and res.rotation is None and res.translation is None
    affine = cpd(src, dst, model="affine")
    assert affine.rmse > 5 * res.rmse          # the bend is not affine


def test_nonrigid_takes_a_flat_sheet():
    # A planar source is fine for the nonrigid model (only rigid and affine need a span).
    u, v = np.meshgrid(np.linspace(0, 1, 15), np.linspace(0, 1, 15))
    sheet = np.c_[u.ravel(), v.ravel(), np.zeros(u.size)]
    bent = sheet + np.c_[np.zeros((u.size, 2)), 0.15 * np.sin(3 * sheet[:, 0])]
    res = cpd(sheet, bent, model="nonrigid")
    assert np.sqrt(np.mean(np.sum((res.moved - bent) ** 2, axis=1))) < 0.02 * _size(bent)


def test_nonrigid_low_rank_agrees_with_the_exact_kernel():
    src, dst = bent_bar(300, 1, bend=0.9), bent_bar(300, 1, bend=0.2)
    exact = cpd(src, dst, model="nonrigid")
    fast = cpd(src, dst, model="nonrigid", low_rank=40)
    size = _size(dst)
    assert fast.rmse < 0.02 * size and exact.rmse < 0.02 * size
    assert np.abs(fast.moved - exact.moved).max() < 0.01 * size


def test_low_rank_eigenpairs_match_the_dense_decomposition():
    y = blob(200, 6) / 1.2
    g = _kernel(y, 0.8, 1 << 20)
    lam_all, vec_all = np.linalg.eigh(g)
    q, lam = _low_rank(y, 0.8, 12, 8 * 200 * 30, lambda *a: None, 1)
    np.testing.assert_allclose(lam, lam_all[::-1][:12], rtol=1e-5)
    np.testing.assert_allclose(q.T @ q, np.eye(12), atol=1e-12)
    # near the best rank-12 approximation, whose spectral error is the 13th eigenvalue
    err = np.linalg.norm(g - (q * lam) @ q.T, 2)
    assert err <= 1.01 * lam_all[::-1][12]


def test_normalize_makes_nonrigid_unit_free():
    src, dst = bent_bar(200, 3, bend=0.8), bent_bar(200, 3, bend=0.3)
    a = cpd(src, dst, model="nonrigid")
    b = cpd(1000.0 * src + 7.0, 1000.0 * dst - 3.0, model="nonrigid")
    np.testing.assert_allclose(b.moved, 1000.0 * a.moved - 3.0, rtol=0, atol=1e-6 * 1000)
    assert b.sigma2 == pytest.approx(1e6 * a.sigma2, rel=1e-6)


def test_progress_each_iteration_and_cancellation():
    src = blob(100, 1)
    dst = src @ rotation_about([0, 0, 1], 20).T
    calls = []
    res = quiet(src, dst, max_iterations=6, tolerance=0,
                progress=lambda done, total, msg="": calls.append((done, total)))
    assert calls == [(k, 6) for k in range(1, res.iterations + 1)]

    def stop(done, total, msg=""):  # noqa: ANN001, ANN202
        if done >= 2:
            raise Cancelled("dismissed")

    with pytest.raises(Cancelled):
        cpd(src, dst, progress=stop)


def test_not_converging_is_reported_with_a_warning():
    src = blob(150, 1)
    dst = move(src, rotation_about([1, 0, 0], 40), [0.1, 0, 0])
    with pytest.warns(ConvergenceWarning, match="max_iterations = 2"):
        res = cpd(src, dst, max_iterations=2)
    assert res.converged is False and res.iterations == 2 and "max_iterations" in res.reason


def test_initial_sigma2_is_the_papers_default():
    # Giving the paper's σ² explicitly changes nothing.
    src, dst = blob(80, 1), blob(90, 2) + [0.5, 0, 0]
    xc, yc = dst - dst.mean(axis=0), src - src.mean(axis=0)
    s2 = ((xc[None] - yc[:, None]) ** 2).sum() / (3 * 80 * 90)
    a = quiet(src, dst, max_iterations=5, tolerance=0)
    b = quiet(src, dst, max_iterations=5, tolerance=0, sigma2=s2)
    np.testing.assert_allclose(a.moved, b.moved, atol=1e-12)


# --- errors ---------------------------------------------------------------------------------

CUBE = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 1]], float)


@pytest.mark.parametrize("kw, err, field, fragment", [
    ({"source": CUBE[:2]}, InvalidInputError, "source", "at least 3"),
    ({"source": CUBE[:3], "model": "affine"}, InvalidInputError, "source", "at least 4"),
    ({"target": CUBE[:3], "model": "affine"}, InvalidInputError, "target", "at least 4"),
    ({"source": CUBE[:1], "model": "nonrigid"}, InvalidInputError, "source", "at least 2"),
    ({"target": np.where(np.eye(5, 3) > 0, np.nan, CUBE)}, InvalidInputError, "target",
     "row 0"),
    ({"target": CUBE[:, :2]}, InvalidInputError, "target", "same dimension"),
    ({"source": CUBE[:, :1], "target": CUBE[:, :1]}, InvalidInputError, "source", ""),
    ({"w": 1.0}, InvalidInputError, "w", "1"),
    ({"w": -0.1}, InvalidInputError, "w", ""),
    ({"w": float("nan")}, InvalidInputError, "w", "finite"),
    ({"beta": 0.0, "model": "nonrigid"}, InvalidInputError, "beta", ""),
    ({"alpha": -1.0}, InvalidInputError, "alpha", ""),
    ({"sigma2": 0.0}, InvalidInputError, "sigma2", ""),
    ({"model": "similarity"}, InvalidInputError, "model", ""),
    ({"scale": "yes"}, InvalidInputError, "scale", ""),
    ({"max_iterations": 0}, InvalidInputError, "max_iterations", ""),
    ({"low_rank": 0, "model": "nonrigid"}, InvalidInputError, "low_rank", ""),
    ({"source": np.c_[np.arange(5.0), np.zeros(5), np.zeros(5)]}, DegenerateInputError,
     "source", "collinear"),
    ({"source": np.c_[CUBE[:, :2], np.zeros(5)], "model": "affine"}, DegenerateInputError,
     "source", "coplanar"),
])
def test_errors_name_the_input(kw, err, field, fragment):
    args = {"source": CUBE, "target": CUBE + 0.1, **kw}
    with pytest.raises(err, match=fragment or None) as info:
        cpd(args.pop("source"), args.pop("target"), **args)
    assert info.value.field == field


def test_exact_kernel_is_refused_for_many_points():
    src = np.random.default_rng(0).normal(size=(4001, 2))
    with pytest.raises(InvalidInputError, match="up to 4000") as info:
        cpd(src, src, model="nonrigid", low_rank=4001)
    assert info.value.field == "low_rank"


# --- layer 3: the peer ----------------------------------------------------------------------
# pycpd moves the raw source from the identity; ours starts with the centroids aligned (as
# the authors' code): on centred sets both run the same iterations.


def _centred_pair(seed: int) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    src = blob(200, seed)
    dst = 1.3 * blob(180, seed + 1) @ rotation_about([1, 2, 3], 30).T
    dst = dst + rng.normal(0, 0.01, dst.shape)
    return src - src.mean(axis=0), dst - dst.mean(axis=0)


@pytest.mark.parametrize("iterations", [3, 40])
def test_agrees_with_pycpd_rigid_and_affine(iterations):
    from pycpd import AffineRegistration, RigidRegistration  # noqa: PLC0415 - the peer

    src, dst = _centred_pair(1)
    ours = quiet(src, dst, max_iterations=iterations, tolerance=0)
    peer = RigidRegistration(X=dst, Y=src, max_iterations=iterations, tolerance=0)
    moved, (s, r, _) = peer.register()
    np.testing.assert_allclose(ours.moved, moved, atol=1e-9)
    assert ours.scale == pytest.approx(s, rel=1e-9)
    np.testing.assert_allclose(ours.rotation, r.T, atol=1e-9)      # pycpd: rows times R
    assert ours.sigma2 == pytest.approx(peer.sigma2, rel=1e-8)

    ours = quiet(src, dst, model="affine", max_iterations=iterations, tolerance=0)
    peer = AffineRegistration(X=dst, Y=src, max_iterations=iterations, tolerance=0)
    moved, (b, _) = peer.register()
    np.testing.assert_allclose(ours.moved, moved, atol=1e-9)
    np.testing.assert_allclose(ours.linear, b.T, atol=1e-9)


def test_agrees_with_pycpd_nonrigid():
    from pycpd import DeformableRegistration  # noqa: PLC0415 - the peer

    src, dst = bent_bar(150, 4, bend=0.9), bent_bar(150, 5, bend=0.3)   # other samples
    src, dst = src - src.mean(axis=0), dst - dst.mean(axis=0)
    ours = quiet(src, dst, model="nonrigid", normalize=False, beta=1.5, alpha=2.0,
                 max_iterations=30, tolerance=0)
    peer = DeformableRegistration(X=dst, Y=src, beta=1.5, alpha=2.0, max_iterations=30,
                                  tolerance=0)
    moved, _ = peer.register()
    np.testing.assert_allclose(ours.moved, moved, atol=1e-8)
    assert ours.sigma2 == pytest.approx(peer.sigma2, rel=1e-7)


# --- real meshes (pyvista's PLY files) ------------------------------------------------------


def test_cpd_rigid_recovers_scale_and_rotation_of_the_ant() -> None:
    src = np.asarray(real_mesh("ant.ply").vertices, dtype=np.float64)
    src = (src - src.mean(axis=0)) / np.linalg.norm(np.ptp(src, axis=0))
    rot = Rotation.from_euler("zyx", [35, -20, 15], degrees=True)
    dst = 1.4 * rot.apply(src) + [0.2, -0.1, 0.3]
    res = cpd(src, dst, model="rigid")
    assert res.scale == pytest.approx(1.4, rel=1e-4)
    assert angle_deg(res.rotation, rot.as_matrix()) < 0.05
