"""Tests for algorithms.core.graphs: edge, kNN and radius graphs, their weights and the shared
neighbour graph of the point-cloud methods, against brute force and scikit-learn."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.spatial.distance import cdist
from sklearn.neighbors import kneighbors_graph, radius_neighbors_graph

from algorithms.core import DegenerateInputError, InvalidInputError
from algorithms.core.graphs import (
    MAX_COMPLETE,
    check_connected,
    check_n_neighbors,
    edge_graph,
    knn_graph,
    neighbour_graph,
    radius_graph,
    weight,
)


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
    # ties by lower index, and point 2 (hidden behind 0 and 1) drops its first column, as
    # scikit-learn's kneighbors does: 0-1, 1-0, 2-1, 3-0
    coo = g.tocoo()
    assert sorted(zip(coo.row.tolist(), coo.col.tolist())) == [
        (0, 1), (0, 3), (1, 0), (1, 2), (2, 1), (3, 0)]
    assert g[0, 1] == 0 and g[0, 3] == pytest.approx(np.sqrt(50))


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


# --- neighbour_graph, check_n_neighbors, check_connected ----------------------------------


def test_neighbour_graph_by_hand():
    x = [[0.0, 0], [1, 0], [3, 0]]
    knn = neighbour_graph(x, neighbors="knn", n_neighbors=1)
    assert knn.toarray().tolist() == [[0, 1, 0], [1, 0, 2], [0, 2, 0]]
    rad = neighbour_graph(x, neighbors="radius", radius=1.5, weighting="uniform")
    assert rad.toarray().tolist() == [[0, 1, 0], [1, 0, 0], [0, 0, 0]]
    full = neighbour_graph(x, neighbors="all", weighting="distance").toarray()
    np.testing.assert_allclose(full, [[0, 1, 1 / 3], [1, 0, 0.5], [1 / 3, 0.5, 0]])
    heat = neighbour_graph(x, neighbors="all", weighting="heat", sigma=1.0).toarray()
    np.testing.assert_allclose(heat[0, 2], np.exp(-9 / 2))


@pytest.mark.parametrize("neighbors, kw", [("knn", {"n_neighbors": 6}),
                                           ("radius", {"radius": 1.2}),
                                           ("all", {})])
@pytest.mark.parametrize("weighting", [None, "uniform", "distance", "heat"])
def test_neighbour_graph_is_the_core_builder_then_weight(neighbors, kw, weighting):
    x = cloud(60, 3, seed=7)
    lengths = {"knn": lambda: knn_graph(x, 6), "radius": lambda: radius_graph(x, 1.2),
               "all": lambda: radius_graph(x, 1e9)}[neighbors]()
    ref = lengths if weighting is None else weight(lengths, weighting)
    g = neighbour_graph(x, neighbors=neighbors, weighting=weighting, **kw)
    assert g.has_sorted_indices and (g != g.T).nnz == 0 and (g.diagonal() == 0).all()
    same_graph(g, ref)


def test_neighbour_graph_all_matches_sklearn_rbf():
    from sklearn.metrics.pairwise import rbf_kernel

    x = cloud(40, 2, seed=8)
    ref = rbf_kernel(x, gamma=1 / (2 * 0.7**2))
    np.fill_diagonal(ref, 0)
    g = neighbour_graph(x, neighbors="all", weighting="heat", sigma=0.7)
    np.testing.assert_allclose(g.toarray(), ref, rtol=1e-12)


def test_neighbour_graph_all_keeps_coincident_pairs_as_edges():
    g = neighbour_graph([[0.0, 0], [0, 0], [1, 1]], neighbors="all")
    assert g.nnz == 6 and g[0, 1] == 0
    assert neighbour_graph([[2.0, 3.0]], neighbors="all").shape == (1, 1)


def test_neighbour_graph_rejects_bad_input():
    x = cloud(6, 2)
    cases = [
        ({"neighbors": "grid"}, "neighbors", r"`neighbors` to be one of 'knn', 'radius', 'all'"),
        ({"neighbors": "knn", "n_neighbors": 6}, "n_neighbors",
         r"`n_neighbors` to be an integer <= 5, at most the number of `points` minus one, "
         r"got 6; give more points or fewer neighbours\."),
        ({"neighbors": "knn"}, "n_neighbors", r"`n_neighbors` to be an integer, got None"),
        ({"neighbors": "radius"}, "radius", r"Expected `radius` with neighbors='radius', got none"),
        ({"neighbors": "radius", "radius": 0.0}, "radius", r"`radius` to be a number > 0"),
        ({"neighbors": "all", "weighting": "cotangent"}, "weighting",
         r"`weighting` to be one of 'uniform', 'distance', 'heat'"),
        ({"neighbors": "all", "weighting": "uniform", "sigma": -1.0}, "sigma",
         r"`sigma` to be a number > 0"),
    ]
    for kw, field, match in cases:
        with pytest.raises(InvalidInputError, match=match) as info:
            neighbour_graph(x, **kw)
        assert info.value.field == field
    with pytest.raises(InvalidInputError, match=r"at most 10,000 `points` with neighbors='all'"
                       ) as info:
        neighbour_graph(np.zeros((MAX_COMPLETE + 1, 1)), neighbors="all")
    assert info.value.field == "neighbors"
    with pytest.raises(DegenerateInputError, match=r"got points 0 and 1 at distance 0"):
        neighbour_graph([[0.0, 0], [0, 0], [1, 1]], neighbors="all", weighting="distance")


def test_neighbour_graph_connected_checks_before_weighting():
    x = np.r_[cloud(10, 2, seed=1), cloud(10, 2, seed=2) + 100]
    x[1] = x[0]                                                     # a zero length as well
    with pytest.raises(DegenerateInputError, match=r"for spectral, got 2 connected "
                       r"components \(increase `n_neighbors`") as info:
        neighbour_graph(x, neighbors="knn", n_neighbors=3, weighting="distance",
                        connected="spectral")
    assert info.value.field == "n_neighbors"
    g = neighbour_graph(x, neighbors="knn", n_neighbors=3)          # no check by default
    assert g.shape == (20, 20)


def test_check_n_neighbors():
    assert check_n_neighbors(6, 5.0) == 5 and isinstance(check_n_neighbors(6, 5.0), int)
    with pytest.raises(InvalidInputError, match=r"`n_neighbors` to be an integer >= 1, got 0"):
        check_n_neighbors(6, 0)
    with pytest.raises(InvalidInputError, match=r"minus one, got 3") as info:
        check_n_neighbors(3, 3, name="nodes")
    assert "`nodes`" in str(info.value) and info.value.field == "n_neighbors"


@pytest.mark.parametrize("neighbors, field, hint", [("knn", "n_neighbors", "increase `n_neighbors`"),
                                                     ("radius", "radius", "increase `radius`"),
                                                     ("all", "points", "the points")])
def test_check_connected(neighbors, field, hint):
    check_connected(edge_graph(3, [[0, 1], [1, 2]]), neighbors=neighbors, method="isomap")
    check_connected(edge_graph(2, [[0, 1]], [0.0]), neighbors=neighbors, method="isomap")
    split = edge_graph(5, [[0, 1], [2, 3]])
    with pytest.raises(DegenerateInputError, match=rf"for isomap, got 3 connected components "
                       rf"\({hint}, or embed each part on its own\)\.") as info:
        check_connected(split, neighbors=neighbors, method="isomap")
    assert info.value.field == field


def test_check_neighbour_params():
    from algorithms.core.graphs import check_neighbour_params

    check_neighbour_params(5, "knn", None, None)  # a method that chooses n_neighbors itself
    check_neighbour_params(5, "radius", None, 0.5)
    check_neighbour_params(5, "all", None, None)
    with pytest.raises(InvalidInputError, match=r"`radius` with neighbors='radius', got none"):
        check_neighbour_params(5, "radius", 3, None)
    with pytest.raises(InvalidInputError, match=r"n_neighbors") as info:
        check_neighbour_params(5, "knn", 5, None)
    assert info.value.field == "n_neighbors"
