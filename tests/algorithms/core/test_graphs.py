"""Tests for algorithms.core.graphs: edge, kNN and radius graphs and their weights, against
brute force and scikit-learn."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.spatial.distance import cdist
from sklearn.neighbors import kneighbors_graph, radius_neighbors_graph

from algorithms.core import DegenerateInputError, InvalidInputError
from algorithms.core.graphs import edge_graph, knn_graph, radius_graph, weight


def cloud(n=150, d=3, seed=0):
    return np.random.default_rng(seed).standard_normal((n, d))


def same_graph(a, b):
    a, b = sp.csr_array(a), sp.csr_array(b)
    assert (a != 0).toarray().tolist() == (b != 0).toarray().tolist() or \
        np.array_equal(a.toarray() != 0, b.toarray() != 0)
    np.testing.assert_allclose(a.toarray(), b.toarray(), rtol=1e-12, atol=0)


# --- edge_graph ---------------------------------------------------------------------------


def test_edge_graph_by_hand():
    g = edge_graph(4, [[0, 1], [2, 1], [1, 0]], [2.0, 3.0, 9.0])
    assert isinstance(g, sp.csr_array)
    np.testing.assert_array_equal(g.toarray(), [[0, 2, 0, 0], [2, 0, 3, 0], [0, 3, 0, 0],
                                                [0, 0, 0, 0]])


def test_edge_graph_uniform_and_empty():
    g = edge_graph(3, [[0, 1], [1, 0]])
    assert g.toarray().tolist() == [[0, 1, 0], [1, 0, 0], [0, 0, 0]]
    assert edge_graph(3, np.zeros((0, 2), dtype=int)).nnz == 0


def test_edge_graph_keeps_zero_weights_as_edges():
    g = edge_graph(2, [[0, 1]], [0.0])
    assert g.nnz == 2 and g.indices.tolist() == [1, 0]


def test_edge_graph_rejects_bad_edges():
    with pytest.raises(InvalidInputError, match=r"`edges` to hold vertex indices below 3, got 3 "
                       r"at row 1\.") as info:
        edge_graph(3, [[0, 1], [1, 3]])
    assert info.value.field == "edges"
    with pytest.raises(InvalidInputError, match=r"`edges` to be an \(e, 2\) array of vertex "
                       r"indices, got shape \(1, 3\)\."):
        edge_graph(3, [[0, 1, 2]])
    with pytest.raises(InvalidInputError, match=r"`edges` to join two distinct vertices, got "
                       r"\[2, 2\] at row 1\."):
        edge_graph(3, [[0, 1], [2, 2]])


def test_edge_graph_rejects_bad_weights():
    with pytest.raises(InvalidInputError, match=r"`weights` to be an \(2,\) array, one per edge, "
                       r"got shape \(3,\)\.") as info:
        edge_graph(3, [[0, 1], [1, 2]], [1.0, 2.0, 3.0])
    assert info.value.field == "weights"
    with pytest.raises(InvalidInputError, match=r"`weights` to hold finite numbers, got nan at "
                       r"position 1\."):
        edge_graph(3, [[0, 1], [1, 2]], [1.0, np.nan])
    with pytest.raises(InvalidInputError, match=r"`weights` to be an \(2,\) array of numbers, got"):
        edge_graph(3, [[0, 1], [1, 2]], ["a", object()])


# --- knn_graph ----------------------------------------------------------------------------


@pytest.mark.parametrize("k", [1, 5, 12])
def test_knn_union_matches_sklearn(k):
    x = cloud()
    ref = kneighbors_graph(x, k, mode="distance")
    same_graph(knn_graph(x, k), ref.maximum(ref.T))


@pytest.mark.parametrize("k", [1, 5])
def test_knn_mutual_matches_sklearn(k):
    x = cloud(seed=1)
    ref = kneighbors_graph(x, k, mode="distance")
    both = (ref != 0).multiply(ref.T != 0)
    same_graph(knn_graph(x, k, mode="mutual"), ref.multiply(both))


def test_knn_matches_brute_force():
    x = cloud(60, 2, seed=4)
    d = cdist(x, x)
    np.fill_diagonal(d, np.inf)
    k = 4
    nbr = np.argsort(d, axis=1)[:, :k]
    dense = np.zeros_like(d)
    rows = np.repeat(np.arange(len(x)), k)
    dense[rows, nbr.ravel()] = d[rows, nbr.ravel()]
    dense = np.maximum(dense, dense.T)
    np.testing.assert_allclose(knn_graph(x, k).toarray(), dense, rtol=1e-12)
    g = knn_graph(x, k)
    assert ((g != 0).sum(axis=1) >= k).all()


def test_knn_with_coincident_points_keeps_zero_length_edges():
    x = np.array([[0.0, 0], [0, 0], [0, 0], [5, 5]])
    g = knn_graph(x, 1)
    assert g.shape == (4, 4)
    assert (g.diagonal() == 0).all()
    # every point has a neighbour; the three coincident ones are joined by explicit zeros
    assert (np.diff(g.indptr) >= 1).all()
    assert set(g[[0]].indices.tolist()) <= {1, 2}


def test_knn_rejects_bad_input():
    with pytest.raises(InvalidInputError, match=r"`k` to be an integer >= 1 and <= 9 \(the number "
                       r"of `points` minus one\), got 10\.") as info:
        knn_graph(cloud(10), 10)
    assert info.value.field == "k"
    with pytest.raises(InvalidInputError, match=r"`mode` to be one of 'union', 'mutual'"):
        knn_graph(cloud(10), 2, mode="both")
    with pytest.raises(InvalidInputError, match=r"`points` to hold finite numbers"):
        knn_graph([[0.0, np.nan], [1, 1]], 1)
    with pytest.raises(InvalidInputError, match=r"`points` to hold at least 2 points, got 1"):
        knn_graph([[0.0, 0.0]], 1)


# --- radius_graph -------------------------------------------------------------------------


@pytest.mark.parametrize("r", [0.3, 0.8, 1.5])
def test_radius_matches_sklearn(r):
    x = cloud(seed=2)
    same_graph(radius_graph(x, r), radius_neighbors_graph(x, r, mode="distance"))


def test_radius_graph_brute_force_and_empty():
    x = cloud(40, 2, seed=3)
    d = cdist(x, x)
    r = 0.7
    dense = np.where((d <= r) & ~np.eye(len(x), dtype=bool), d, 0.0)
    np.testing.assert_allclose(radius_graph(x, r).toarray(), dense, rtol=1e-12)
    assert radius_graph(x * 1e6, 1e-3).nnz == 0


def test_radius_rejects_non_positive():
    with pytest.raises(InvalidInputError, match=r"`r` to be a number > 0.0, got 0.0\.") as info:
        radius_graph(cloud(5), 0)
    assert info.value.field == "r"


# --- weight -------------------------------------------------------------------------------


def test_weights_by_hand():
    g = edge_graph(3, [[0, 1], [1, 2]], [2.0, 4.0])
    assert weight(g, "uniform").toarray().tolist() == [[0, 1, 0], [1, 0, 1], [0, 1, 0]]
    assert weight(g, "distance").toarray()[1].tolist() == [0.5, 0.0, 0.25]
    heat = weight(g, "heat", sigma=2.0).toarray()
    np.testing.assert_allclose(heat[0, 1], np.exp(-4 / 8))
    np.testing.assert_allclose(heat[1, 2], np.exp(-16 / 8))
    default = weight(g, "heat").toarray()                          # sigma = mean length 3
    np.testing.assert_allclose(default[0, 1], np.exp(-4 / 18))


def test_heat_weights_match_sklearn_rbf():
    from sklearn.metrics.pairwise import rbf_kernel

    x = cloud(30, 3, seed=6)
    g = radius_graph(x, 10.0)                                      # complete graph
    sigma = 0.9
    ref = rbf_kernel(x, gamma=1 / (2 * sigma**2))
    np.fill_diagonal(ref, 0)
    np.testing.assert_allclose(weight(g, "heat", sigma=sigma).toarray(), ref, rtol=1e-12)


def test_weight_keeps_structure_and_does_not_modify_input():
    g = knn_graph(cloud(50), 4)
    before = g.data.copy()
    for kind in ("uniform", "distance", "heat"):
        w = weight(g, kind)
        assert np.array_equal(w.indices, g.indices) and (w.data > 0).all()
    np.testing.assert_array_equal(g.data, before)


def test_distance_weight_rejects_zero_length():
    g = knn_graph(np.array([[0.0, 0], [0, 0], [1, 1]]), 1)
    with pytest.raises(DegenerateInputError, match=r"distinct `points` for inverse-distance "
                       r"weights, got points 0 and 1 at distance 0\.") as info:
        weight(g, "distance")
    assert info.value.field == "points"


def test_weight_rejects_bad_input():
    with pytest.raises(InvalidInputError, match=r"`kind` to be one of 'uniform', 'distance', 'heat'"):
        weight(edge_graph(2, [[0, 1]]), "gaussian")
    with pytest.raises(InvalidInputError, match=r"`sigma` to be a number > 0.0, got -1.0\."):
        weight(edge_graph(2, [[0, 1]]), "heat", sigma=-1.0)
    with pytest.raises(InvalidInputError, match=r"`adjacency` to hold finite non-negative edge "
                       r"lengths, got -2.0\.") as info:
        weight(edge_graph(2, [[0, 1]], [-2.0]), "heat")
    assert info.value.field == "adjacency"
