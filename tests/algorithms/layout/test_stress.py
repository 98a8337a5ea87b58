"""Tests for layout.stress (SMACOF): hand cases, the stress definition against
scikit-learn's, stress never above scikit-learn's SMACOF from the same start, monotone
history, weights, missing distances, graphs, progress and cancellation, and every error
branch."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from scipy.spatial.distance import cdist
from sklearn.manifold import smacof

from algorithms.core import Cancelled, ConvergenceWarning, DegenerateInputError, InvalidInputError
from algorithms.layout import StressResult, mds, stress

LINE = [[0, 1, 2], [1, 0, 1], [2, 1, 0]]


def weighted_stress(x: np.ndarray, d: np.ndarray, w: np.ndarray) -> float:
    """Σ_{i<j} w (|x_i - x_j| - d)² by a loop over pairs (NaN d: unknown, skipped)."""
    total = 0.0
    for i in range(len(x)):
        for j in range(i + 1, len(x)):
            if not np.isnan(d[i, j]):
                total += w[i, j] * (np.linalg.norm(x[i] - x[j]) - d[i, j]) ** 2
    return total


def noisy_distances(rng: np.random.Generator, n: int, dim: int = 5) -> np.ndarray:
    """Distances of points in ``dim`` dimensions: not embeddable in 2-D."""
    x = rng.standard_normal((n, dim))
    return cdist(x, x)


# --- layer 1: by hand -----------------------------------------------------------------------
def test_hand_line_is_exact():
    res = stress(LINE, n_components=1)
    assert isinstance(res, StressResult)
    np.testing.assert_allclose(np.sort(res.positions.ravel()), [-1, 0, 1], atol=1e-12)
    assert res.stress < 1e-24 and res.converged


def test_hand_square_with_wrong_diagonals():
    # A unit square asked for diagonals of 1 too: by symmetry the optimum is a square of
    # side s: 4 (s - 1)² + 2 (s√2 - 1)², minimal at s = (4 + 2√2) / (4 + 4) (uniform weights).
    d = np.ones((4, 4)) - np.eye(4)
    start = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    with pytest.warns(ConvergenceWarning):  # tolerance 0: every iteration runs
        res = stress(d, weighting="uniform", initial_positions=start, tolerance=0.0,
                     max_iterations=200)
    s = (4 + 2 * np.sqrt(2)) / 8
    expected = 4 * (s - 1) ** 2 + 2 * (s * np.sqrt(2) - 1) ** 2
    assert res.stress == pytest.approx(expected, rel=1e-9)
    side = np.linalg.norm(res.positions[0] - res.positions[1])
    assert side == pytest.approx(s, rel=1e-6)


# --- the stress definition and scikit-learn -------------------------------------------------
def test_stress_definition_matches_sklearn():
    rng = np.random.default_rng(0)
    d = noisy_distances(rng, 40)
    init = rng.standard_normal((40, 2))
    x, sk_stress = smacof(d, init=init, n_init=1, max_iter=5, eps=0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")   # nothing to converge: no warning
        ours = stress(d, weighting="uniform", initial_positions=x, max_iterations=0)
    assert ours.iterations == 0 and not ours.converged
    assert ours.stress == pytest.approx(sk_stress, rel=1e-12)
    assert ours.stress == pytest.approx(weighted_stress(x, d, np.ones_like(d)), rel=1e-12)


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("start", ["classical", "random"])
def test_stress_not_above_sklearn_smacof_from_the_same_start(seed, start):
    rng = np.random.default_rng(seed)
    n = 60 + 20 * seed
    d = noisy_distances(rng, n)
    init = mds(d).positions if start == "classical" else rng.standard_normal((n, 2))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        ours = stress(d, weighting="uniform", initial_positions=init)
    _, sk_stress = smacof(d, init=init, n_init=1)   # scikit-learn's defaults
    assert ours.stress <= sk_stress * (1 + 1e-12)


def test_same_iterations_give_sklearns_layout():
    rng = np.random.default_rng(4)
    d = noisy_distances(rng, 80)
    init = rng.standard_normal((80, 2))
    x_sk, s_sk = smacof(d, init=init, n_init=1, max_iter=25, eps=0)
    with pytest.warns(ConvergenceWarning):
        ours = stress(d, weighting="uniform", initial_positions=init, max_iterations=25,
                      tolerance=0.0)
    assert ours.iterations == 25
    np.testing.assert_allclose(ours.positions, x_sk - x_sk.mean(axis=0), atol=1e-9)
    assert ours.stress == pytest.approx(s_sk, rel=1e-10)


# --- invariants -----------------------------------------------------------------------------
@pytest.mark.parametrize("weighting", ["inverse_square", "inverse", "uniform"])
def test_history_never_increases_and_stress_is_as_defined(weighting):
    rng = np.random.default_rng(1)
    d = noisy_distances(rng, 50)
    res = stress(d, weighting=weighting, init="random", seed=3)
    h = res.stress_history
    assert len(h) == res.iterations + 1 and res.converged
    assert np.all(np.diff(h) <= 1e-12 * h[0])
    power = {"inverse_square": -2.0, "inverse": -1.0, "uniform": 0.0}[weighting]
    with np.errstate(divide="ignore"):
        w = np.where(d > 0, d ** power, 0.0)
    assert res.stress == pytest.approx(weighted_stress(res.positions, d, w), rel=1e-10)
    assert res.stress == h[-1]
    total = sum(w[i, j] * d[i, j] ** 2 for i in range(50) for j in range(i + 1, 50))
    assert res.normalized_stress == pytest.approx(np.sqrt(res.stress / total), rel=1e-12)
    np.testing.assert_allclose(res.positions.mean(axis=0), 0, atol=1e-10)


@pytest.mark.parametrize("weighting", ["uniform", "inverse_square"])
def test_relaxed_update_is_monotone_and_faster(weighting):
    rng = np.random.default_rng(8)
    d = noisy_distances(rng, 80)
    init = rng.standard_normal((80, 2))
    plain = stress(d, weighting=weighting, initial_positions=init, max_iterations=5000)
    fast = stress(d, weighting=weighting, initial_positions=init, max_iterations=5000,
                  relaxation=1.9)
    assert np.all(np.diff(fast.stress_history) <= 1e-12 * fast.stress_history[0])
    assert fast.iterations < plain.iterations
    assert fast.stress <= plain.stress * (1 + 1e-4)


@pytest.mark.parametrize("seed", range(10))
def test_embeddable_distances_are_reproduced(seed):
    rng = np.random.default_rng(seed)
    x = rng.standard_normal((25, 2))
    res = stress(cdist(x, x), init="random", seed=seed, max_iterations=3000, tolerance=1e-12)
    # from a random start SMACOF may stop in a local minimum; from these it does not
    assert res.normalized_stress < 1e-6


def test_missing_distances_count_nothing():
    rng = np.random.default_rng(2)
    x = rng.standard_normal((40, 2))
    d = cdist(x, x)
    holes = np.triu(rng.random(d.shape) < 0.5, 1)
    d[holes | holes.T] = np.nan
    res = stress(d)
    assert res.normalized_stress < 1e-6
    with np.errstate(divide="ignore"):
        w = np.where(np.isnan(d), 0.0, 1.0 / np.where(np.isnan(d), 1.0, d) ** 2)
    np.fill_diagonal(w, 0)
    assert res.stress == pytest.approx(weighted_stress(res.positions, d, w), rel=1e-8, abs=1e-20)
    pairs = np.c_[np.argwhere(np.triu(~np.isnan(d), 1)), d[np.triu(~np.isnan(d), 1)]]
    res2 = stress(distance_pairs=pairs)
    np.testing.assert_allclose(res2.positions, res.positions, atol=1e-10)


def test_graph_drawing_of_gansner_koren_north():
    # a 4×4 grid graph: shortest paths are Manhattan distances, not Euclidean ones
    n = 4
    edges = [[i * n + j, i * n + j + 1] for i in range(n) for j in range(n - 1)]
    edges += [[i * n + j, (i + 1) * n + j] for i in range(n - 1) for j in range(n)]
    res = stress(graph={"nodes": n * n, "edges": edges})
    h = res.stress_history
    assert res.converged and h[-1] <= h[0]
    # neighbours end up closer than non-neighbours on average
    x = res.positions
    e = np.array(edges)
    near = np.linalg.norm(x[e[:, 0]] - x[e[:, 1]], axis=1).mean()
    assert near < cdist(x, x)[np.triu_indices(n * n, 1)].mean()


@pytest.mark.filterwarnings("ignore::algorithms.core.errors.ConvergenceWarning")
def test_random_start_is_deterministic_by_seed():
    d = noisy_distances(np.random.default_rng(0), 30)
    a = stress(d, init="random", seed=5).positions
    b = stress(d, init="random", seed=5).positions
    c = stress(d, init="random", seed=6).positions
    np.testing.assert_array_equal(a, b)
    assert not np.allclose(a, c)


def test_coincident_points_in_the_start_are_handled():
    d = noisy_distances(np.random.default_rng(3), 10)
    start = np.random.default_rng(3).standard_normal((10, 2))
    start[1] = start[0]  # b_01 = 0 where the points coincide
    res = stress(d, weighting="uniform", initial_positions=start)
    assert np.isfinite(res.positions).all()
    assert res.stress <= res.stress_history[0]


def test_progress_is_reported_and_can_cancel():
    d = noisy_distances(np.random.default_rng(0), 30)
    seen = []
    res = stress(d, progress=lambda done, total, msg="": seen.append((done, total, msg)))
    assert [s[0] for s in seen] == list(range(1, res.iterations + 1))
    assert all(s[1] == 300 for s in seen) and seen[-1][2].startswith("stress ")

    def stop(done, total, msg=""):  # noqa: ANN001, ANN202
        if done == 3:
            raise Cancelled("stop")

    with pytest.raises(Cancelled):
        stress(d, progress=stop)


def test_iteration_limit_warns():
    d = noisy_distances(np.random.default_rng(0), 30)
    with pytest.warns(ConvergenceWarning, match="stopped after 2 iterations"):
        res = stress(d, max_iterations=2, init="random")
    assert not res.converged and res.iterations == 2


# --- errors ---------------------------------------------------------------------------------
@pytest.mark.parametrize("kwargs, error, field, match", [
    ({"distances": [[0, 0, 1], [0, 0, 1], [1, 1, 0]]}, InvalidInputError, "distances",
     "positive between distinct points .* got 0 between points 0 and 1; use "
     "weighting='uniform'"),
    ({"distances": LINE, "initial_positions": [[0, 0], [1, 1]]}, InvalidInputError,
     "initial_positions", r"one row per point \(3\), got 2"),
    ({"distances": LINE, "initial_positions": [[0, 0, 0]] * 3}, InvalidInputError,
     "initial_positions", r"\(n, 2\)"),
    ({"distances": LINE, "initial_positions": [[1, 1]] * 3}, DegenerateInputError,
     "initial_positions", "all at one point"),
    ({"distances": LINE, "initial_positions": [[1, 1], [0, np.nan], [2, 2]]},
     InvalidInputError, "initial_positions", "nan at row 1"),
    ({"distances": LINE, "weighting": "sammon"}, InvalidInputError, "weighting", "one of"),
    ({"distances": LINE, "init": "spectral"}, InvalidInputError, "init", "one of"),
    ({"distances": LINE, "max_iterations": 1.5}, InvalidInputError, "max_iterations",
     "integer"),
    ({"distances": LINE, "tolerance": -1}, InvalidInputError, "tolerance", ">= 0"),
    ({"distances": LINE, "relaxation": 2.0}, InvalidInputError, "relaxation", "< 2.0"),
    ({"distances": LINE, "relaxation": 0.5}, InvalidInputError, "relaxation", ">= 1.0"),
    ({"distances": LINE, "seed": -1}, InvalidInputError, "seed", ">= 0"),
    ({"distances": LINE, "n_components": 0}, InvalidInputError, "n_components", ">= 1"),
    ({"distances": [[0, 1], [1, 0], [2, 2]]}, InvalidInputError, "distances", "square"),
    ({"distances": [[0, -1], [-1, 0]]}, InvalidInputError, "distances", "non-negative"),
    ({"distance_pairs": [[0, 1, 1.0], [2, 3, 1.0]]}, DegenerateInputError, "distance_pairs",
     "2 groups"),
    ({"graph": {"nodes": 3, "edges": [[0, 1], [1, 3]]}}, InvalidInputError, "graph.edges",
     "below 3"),
])
def test_errors(kwargs, error, field, match):
    with pytest.raises(error, match=match) as info:
        stress(**kwargs)
    assert info.value.field == field
