"""Spectral clustering: a hand-made case, invariants, and scikit-learn's ARI on blobs and
two moons."""

from __future__ import annotations

import numpy as np
import pytest
from sklearn.cluster import SpectralClustering
from sklearn.datasets import make_blobs, make_moons
from sklearn.metrics import adjusted_rand_score

from algorithms.clustering import markov, spectral
from algorithms.core.errors import InvalidInputError
from algorithms.core.graphs import NEIGHBORS, WEIGHTINGS
from algorithms.core.params import declarations


def test_two_triangles_by_hand() -> None:
    pts = [[0, 0], [0, 1], [1, 0], [10, 10], [10, 11], [11, 10]]
    res = spectral(pts, n_clusters=2, n_neighbors=2)
    assert res.labels.tolist() == [0, 0, 0, 1, 1, 1]
    assert res.sizes.tolist() == [3, 3]
    # two components: two zero eigenvalues, rows of one group embed at one point
    np.testing.assert_allclose(res.eigenvalues, [0, 0], atol=1e-12)
    assert res.graph_components == 2
    assert np.ptp(res.embedding[:3], axis=0).max() < 1e-12


@pytest.mark.parametrize("name, data, k", [
    ("blobs", make_blobs(400, centers=4, random_state=2), 4),
    ("blobs3", make_blobs(300, centers=3, random_state=3), 3),
    ("moons", make_moons(300, noise=0.05, random_state=0), 2),
])
def test_ari_at_least_scikit_learn(name, data, k) -> None:
    x, y = data
    ours = spectral(x, n_clusters=k, n_neighbors=10, seed=0)
    ref = SpectralClustering(k, affinity="nearest_neighbors", n_neighbors=10,
                             random_state=0).fit(x)
    a, b = adjusted_rand_score(y, ours.labels), adjusted_rand_score(y, ref.labels_)
    assert a >= b - 1e-12, (name, a, b)
    assert ours.sizes.sum() == x.shape[0] and ours.sizes.shape == (k,)


def test_same_seed_same_labels_and_signs_fixed() -> None:
    x, _ = make_blobs(200, centers=3, random_state=5)
    a, b = spectral(x, n_clusters=3, seed=3), spectral(x, n_clusters=3, seed=3)
    assert np.array_equal(a.labels, b.labels) and np.array_equal(a.embedding, b.embedding)
    big = np.abs(a.embedding).argmax(axis=0)
    assert (a.embedding[big, range(3)] > 0).all()
    np.testing.assert_allclose(np.linalg.norm(a.embedding, axis=1), 1.0)


def test_radius_heat_and_sparse_solver_agree_with_dense(monkeypatch) -> None:
    x, y = make_blobs(300, centers=[[0, 0], [8, 0], [0, 8]], random_state=0)
    dense = spectral(x, n_clusters=3, neighbors="radius", radius=2.0, weighting="heat")
    assert adjusted_rand_score(y, dense.labels) == 1.0
    import sys

    monkeypatch.setattr(sys.modules["algorithms.clustering.spectral"], "DENSE_BELOW", 10)
    sparse = spectral(x, n_clusters=3, neighbors="radius", radius=2.0, weighting="heat")
    np.testing.assert_allclose(sparse.eigenvalues, dense.eigenvalues, atol=1e-8)
    assert np.array_equal(sparse.labels, dense.labels)


def test_more_components_than_clusters_warns() -> None:
    pts = [[0, 0], [0, 1], [10, 0], [10, 1], [20, 0], [20, 1]]
    with pytest.warns(UserWarning, match="3 connected components"):
        res = spectral(pts, n_clusters=2, n_neighbors=2)  # itself and one other
    assert res.graph_components == 3


@pytest.mark.parametrize("kwargs, field, match", [
    ({"n_neighbors": 10}, "n_neighbors", "at most the number of `points` minus one"),
    ({"n_clusters": 7}, "n_clusters", r"<= 6"),
    ({"neighbors": "radius"}, "radius", "Expected `radius`"),
    ({"neighbors": "grid"}, "neighbors", "one of"),
    ({"weighting": "cotangent"}, "weighting", "one of"),
    ({"n_init": 0}, "n_init", ">= 1"),
    ({"n_neighbors": 0}, "n_neighbors", ">= 1"),
    ({"radius": -1.0}, "radius", "> 0"),
    ({"sigma": 0.0}, "sigma", "> 0"),
    ({"seed": -1}, "seed", ">= 0"),
])
def test_bad_input(kwargs, field, match) -> None:
    pts = np.arange(12.0).reshape(6, 2)
    with pytest.raises(InvalidInputError, match=match) as err:
        spectral(pts, **{"n_clusters": 2, "n_neighbors": 2, **kwargs})
    assert err.value.field == field


def test_bad_points() -> None:
    with pytest.raises(InvalidInputError, match="row 1") as err:
        spectral([[0, 0], [np.nan, 1], [2, 2]], n_clusters=2, n_neighbors=1)
    assert err.value.field == "points"


def test_neighbour_graph_choices_are_those_of_core() -> None:
    """The declared choices are the ones algorithms.core.graphs.neighbour_graph accepts."""
    for method in (spectral, markov):
        declared = declarations(method)
        assert declared["neighbors"].scalars[0].choices == NEIGHBORS
        assert declared["weighting"].scalars[0].choices == WEIGHTINGS
