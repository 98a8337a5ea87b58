"""Tests for layout.mds: hand cases, exact recovery up to a rigid motion, agreement with
scikit-learn's ClassicalMDS and with numpy's eigendecomposition of the double-centred
matrix, completion of partial matrices (NaN, null, listed pairs), graph distances, and
every error branch."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from scipy.spatial.distance import cdist
from sklearn.manifold import ClassicalMDS

from algorithms.core import ConvergenceWarning, DegenerateInputError, InvalidInputError
from algorithms.layout import MDSResult, mds

TRIANGLE = [[0, 3, 4], [3, 0, 5], [4, 5, 0]]  # a 3-4-5 right triangle


def rigid_residual(x: np.ndarray, y: np.ndarray) -> float:
    """RMS distance between x and y after the best orthogonal map (reflections allowed) and
    translation of x onto y."""
    xc, yc = x - x.mean(axis=0), y - y.mean(axis=0)
    u, _, vt = np.linalg.svd(xc.T @ yc)
    return float(np.sqrt(np.mean(np.sum((xc @ u @ vt - yc) ** 2, axis=1))))


def with_holes(d: np.ndarray, fraction: float, rng: np.random.Generator) -> np.ndarray:
    """A copy of ``d`` with about ``fraction`` of its pairs set to NaN, symmetrically."""
    n = len(d)
    out = d.copy()
    holes = np.triu(rng.random((n, n)) < fraction, 1)
    holes |= holes.T
    out[holes] = np.nan
    return out


# --- layer 1: by hand -----------------------------------------------------------------------
def test_hand_right_triangle():
    res = mds(TRIANGLE)
    assert isinstance(res, MDSResult)
    np.testing.assert_allclose(cdist(res.positions, res.positions), TRIANGLE, atol=1e-12)
    np.testing.assert_allclose(res.positions.mean(axis=0), 0, atol=1e-14)
    # eigenvalues of X Xᵀ = those of the centred coordinates' scatter matrix
    x = np.array([[0.0, 0.0], [3.0, 0.0], [0.0, 4.0]])
    xc = x - x.mean(axis=0)
    np.testing.assert_allclose(res.eigenvalues, np.linalg.eigvalsh(xc.T @ xc)[::-1],
                               rtol=1e-12)
    assert res.stress < 1e-24 and res.normalized_stress < 1e-12
    assert res.missing_pairs == 0 and res.completion_iterations == 0 and res.converged


def test_hand_collinear_points_in_two_dimensions():
    # three points on a line: the second eigenvalue is 0 and its column is zero
    res = mds([[0, 1, 2], [1, 0, 1], [2, 1, 0]])
    np.testing.assert_allclose(res.eigenvalues, [2.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(np.abs(res.positions[:, 0]), [1, 0, 1], atol=1e-12)
    np.testing.assert_allclose(res.positions[:, 1], 0, atol=1e-7)


# --- layer 2: recovery ------------------------------------------------------------------
@pytest.mark.parametrize("seed", range(20))
@pytest.mark.parametrize("k", [1, 2, 3])
def test_points_are_recovered_up_to_rigid_motion(seed, k):
    rng = np.random.default_rng(seed)
    x = rng.standard_normal((30, k)) * np.linspace(3, 1, k)
    res = mds(cdist(x, x), n_components=k)
    assert rigid_residual(res.positions, x) < 1e-10
    assert res.normalized_stress < 1e-10


def test_asymmetric_input_is_refused():
    """As scikit-learn's ClassicalMDS refuses it ("Array must be symmetric"); a matrix
    symmetric to its tolerance (rtol 1e-5) is averaged."""
    x = np.random.default_rng(1).standard_normal((10, 2))
    d = cdist(x, x)
    noisy = d * (1 + 0.1 * np.triu(np.ones_like(d), 1) - 0.1 * np.tril(np.ones_like(d), -1))
    with pytest.raises(InvalidInputError, match="symmetric") as info:
        mds(noisy)
    assert info.value.field == "distances"
    with pytest.raises(ValueError, match="symmetric"):
        ClassicalMDS(n_components=2, metric="precomputed").fit(noisy)
    close = d * (1 + 1e-7 * np.triu(np.ones_like(d), 1))
    np.testing.assert_allclose(mds(close).positions, mds(d).positions, atol=1e-6)


# --- layer 3: agreement with scikit-learn and numpy -----------------------------------------
@pytest.mark.parametrize("n, k", [(50, 2), (120, 3), (450, 2)])  # 450: the Lanczos path
def test_matches_sklearn_classical_mds(n, k):
    rng = np.random.default_rng(n)
    x = rng.standard_normal((n, 6))          # 6-D data: the 2-D layout is a true projection
    d = cdist(x, x)
    ours = mds(d, n_components=k)
    sk = ClassicalMDS(n_components=k, metric="precomputed")
    theirs = sk.fit_transform(d)
    assert rigid_residual(ours.positions, theirs) < 1e-9
    np.testing.assert_allclose(ours.positions, theirs, atol=1e-9)  # same sign convention
    np.testing.assert_allclose(ours.eigenvalues, sk.eigenvalues_, rtol=1e-10)


def test_matches_numpy_double_centring():
    rng = np.random.default_rng(5)
    d = cdist(rng.random((40, 4)), rng.random((40, 4)))
    d = 0.5 * (d + d.T)
    np.fill_diagonal(d, 0)                   # not a Euclidean matrix: negative eigenvalues
    n = len(d)
    j = np.eye(n) - 1 / n
    w, u = np.linalg.eigh(-0.5 * j @ (d * d) @ j)
    ours = mds(d, n_components=3)
    np.testing.assert_allclose(ours.eigenvalues, w[::-1][:3], rtol=1e-10)
    expected = u[:, ::-1][:, :3] * np.sqrt(np.maximum(w[::-1][:3], 0))
    assert rigid_residual(ours.positions, expected) < 1e-10


# --- completion -----------------------------------------------------------------------------
@pytest.mark.parametrize("seed", range(5))
def test_partial_matrix_is_completed(seed):
    rng = np.random.default_rng(seed)
    x = rng.standard_normal((120, 2))
    d = with_holes(cdist(x, x), 0.6, rng)
    res = mds(d)
    assert res.converged and res.completion_iterations > 0
    assert res.missing_pairs == int(np.isnan(np.triu(d, 1)).sum())
    assert rigid_residual(res.positions, x) < 1e-5
    # the one-shot estimate of Drineas et al. alone is much rougher
    one_shot = mds(d, max_iterations=0)
    assert one_shot.completion_iterations == 0
    assert rigid_residual(one_shot.positions, x) > 100 * rigid_residual(res.positions, x)


def test_three_dimensional_completion_and_rank():
    rng = np.random.default_rng(11)
    x = rng.standard_normal((100, 3))
    d = with_holes(cdist(x, x), 0.5, rng)
    res = mds(d, n_components=3)
    assert rigid_residual(res.positions, x) < 1e-5
    assert mds(d, n_components=3, rank=6).positions.shape == (100, 3)


def test_null_pairs_and_listed_pairs_agree():
    rng = np.random.default_rng(2)
    x = rng.standard_normal((30, 2))
    d = with_holes(cdist(x, x), 0.3, rng)
    as_null = [[None if np.isnan(v) else float(v) for v in row] for row in d]
    iu = np.argwhere(np.triu(~np.isnan(d), 1))
    pairs = np.c_[iu, d[iu[:, 0], iu[:, 1]]]
    a = mds(d).positions
    np.testing.assert_array_equal(mds(as_null).positions, a)
    np.testing.assert_allclose(mds(distance_pairs=pairs).positions, a, atol=1e-12)
    np.testing.assert_allclose(mds(distance_pairs=pairs[:, [1, 0, 2]], n_points=30).positions,
                               a, atol=1e-12)


def test_one_sided_entries_and_repeated_pairs():
    x = np.array([[0.0, 0.0], [3.0, 0.0], [0.0, 4.0]])
    d = cdist(x, x)
    d[np.tril_indices(3, -1)] = np.nan       # only the upper triangle is given
    np.testing.assert_allclose(cdist(*[mds(d).positions] * 2), TRIANGLE, atol=1e-12)
    # a pair listed twice (either order) with one distance counts once
    pairs = [[0, 1, 3.0], [1, 0, 3.0], [1, 2, 5.0], [0, 2, 4.0]]
    np.testing.assert_allclose(cdist(*[mds(distance_pairs=pairs).positions] * 2), TRIANGLE,
                               atol=1e-12)


def test_unconverged_completion_warns():
    rng = np.random.default_rng(0)
    x = rng.standard_normal((60, 2))
    d = with_holes(cdist(x, x), 0.5, rng)
    with pytest.warns(ConvergenceWarning, match="stopped after 2 iterations"):
        res = mds(d, max_iterations=2)
    assert not res.converged and res.completion_iterations == 2


def test_graph_distances():
    # a path graph: shortest paths 0..n-1 along a line
    g = {"nodes": 6, "edges": [[i, i + 1] for i in range(5)]}
    res = mds(graph=g, n_components=1)
    np.testing.assert_allclose(np.abs(res.positions[:, 0] - res.positions[0, 0]),
                               np.arange(6), atol=1e-12)
    # edge lengths: the repeated edge's shortest length counts
    g2 = {"nodes": 3, "edges": [[0, 1], [1, 2], [0, 1]], "weights": [3.0, 4.0, 5.0]}
    res2 = mds(graph=g2, n_components=1)
    np.testing.assert_allclose(cdist(res2.positions, res2.positions),
                               [[0, 3, 7], [3, 0, 4], [7, 4, 0]], atol=1e-12)


# --- errors ---------------------------------------------------------------------------------
NAN = float("nan")


@pytest.mark.parametrize("kwargs, error, field, match", [
    ({}, InvalidInputError, "distances", "exactly one of .* got none"),
    ({"distances": TRIANGLE, "graph": {"nodes": 3, "edges": [[0, 1]]}}, InvalidInputError,
     "graph", "got `distances` and `graph`"),
    ({"distances": TRIANGLE, "n_points": 3}, InvalidInputError, "n_points",
     "only together with `distance_pairs`"),
    ({"distances": [[0, 1, 2], [1, 0, 3]]}, InvalidInputError, "distances",
     r"square \(n, n\) matrix .* got shape \(2, 3\)"),
    ({"distances": [0, 1, 2]}, InvalidInputError, "distances", r"got shape \(3,\)"),
    ({"distances": [[0, 1], [1, 0, 2]]}, InvalidInputError, "distances", "ragged"),
    ({"distances": [[True, False], [False, True]]}, InvalidInputError, "distances",
     "dtype bool"),
    ({"distances": [[0, "a"], ["a", 0]]}, InvalidInputError, "distances", "dtype"),
    ({"distances": [[0]]}, InvalidInputError, "distances", "at least 2 points, got 1"),
    ({"distances": [[0, -1, 2], [-1, 0, 3], [2, 3, 0]]}, InvalidInputError, "distances",
     "non-negative distances, got -1.0 at row 0, column 1"),
    ({"distances": [[0, 1, 2], [1, 0, float("inf")], [2, 3, 0]]}, InvalidInputError,
     "distances", "finite numbers, got inf at row 1, column 2"),
    ({"distances": [[0, 1, 2], [1, 0.5, 3], [2, 3, 0]]}, InvalidInputError, "distances",
     "diagonal of `distances` to be zero .*, got 0.5 at row 1, column 1"),
    ({"distances": [[0, NAN, NAN], [NAN, 0, 3], [NAN, 3, 0]]}, DegenerateInputError,
     "distances", "at least one known distance, got none for point 0"),
    ({"distances": [[0, 1, NAN, NAN], [1, 0, NAN, NAN], [NAN, NAN, 0, 1],
                    [NAN, NAN, 1, 0]]}, DegenerateInputError, "distances",
     "2 groups with no known distance between them"),
    ({"distances": TRIANGLE, "n_components": 4}, InvalidInputError, "n_components",
     "<= 3"),
    ({"distances": TRIANGLE, "n_components": 0}, InvalidInputError, "n_components", ">= 1"),
    ({"distances": TRIANGLE, "rank": 1}, InvalidInputError, "rank", ">= 2"),
    ({"distances": TRIANGLE, "rank": 0}, InvalidInputError, "rank", "integer >= 1, got 0"),
    ({"distances": TRIANGLE, "rank": 4}, InvalidInputError, "rank", "<= 3"),
    ({"distances": TRIANGLE, "max_iterations": -1}, InvalidInputError, "max_iterations",
     ">= 0"),
    ({"distances": TRIANGLE, "tolerance": NAN}, InvalidInputError, "tolerance", "finite"),
    ({"distance_pairs": [[0, 1, NAN], [1, 2, 1.0]]}, InvalidInputError, "distance_pairs",
     "finite numbers, got nan at row 0"),
    ({"distance_pairs": [[0, 1, -2.0], [1, 2, 1.0]]}, InvalidInputError, "distance_pairs",
     "non-negative distances \\(column 2\\), got -2.0 at row 0"),
    ({"distance_pairs": [[0, 0, 1.0], [1, 2, 1.0]]}, InvalidInputError, "distance_pairs",
     "point 0 with itself at row 0"),
    ({"distance_pairs": [[0, 1.5, 1.0]]}, InvalidInputError, "distance_pairs",
     "integer point indices"),
    ({"distance_pairs": [[0, 5, 1.0]], "n_points": 3}, InvalidInputError, "distance_pairs",
     "below 3"),
    ({"distance_pairs": [[0, 1]]}, InvalidInputError, "distance_pairs", r"\(n, 3\)"),
    ({"distance_pairs": [[0, 1, 1.0]], "n_points": 3}, DegenerateInputError,
     "distance_pairs", "none for point 2"),
    ({"distance_pairs": [[0, 1, 1.0]], "n_points": 1}, InvalidInputError, "n_points",
     ">= 2"),
    ({"distance_pairs": [[0, 1, 1.0]], "n_points": 5000}, InvalidInputError, "n_points",
     "at most 4,000 points"),
    ({"graph": {"nodes": 4, "edges": [[0, 1], [2, 3]]}}, DegenerateInputError, "graph",
     "2 components"),
    ({"graph": {"nodes": 3, "edges": [[0, 1], [1, 2]], "weights": [1.0, 0.0]}},
     InvalidInputError, "graph.weights", "positive \\(edge lengths\\)"),
    ({"graph": {"nodes": 1, "edges": []}}, InvalidInputError, "graph.nodes", "at least 2"),
    ({"graph": {"nodes": 3, "edges": []}}, DegenerateInputError, "graph", "no edges"),
])
def test_errors(kwargs, error, field, match):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(error, match=match) as info:
            mds(**kwargs)
    assert info.value.field == field


def test_too_many_points():
    with pytest.raises(InvalidInputError, match="at most 4,000 points") as info:
        mds(np.zeros((4001, 4001)))
    assert info.value.field == "distances"
