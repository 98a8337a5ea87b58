"""What ``n_neighbors`` means, checked against scikit-learn on the same input: the spectral
methods count the point itself (``kneighbors_graph(..., include_self=True)``), Isomap and
LLE do not; given the same graph, Isomap's embedding is scikit-learn's."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from sklearn.cluster import SpectralClustering
from sklearn.datasets import load_digits, make_blobs
from sklearn.manifold import Isomap, SpectralEmbedding
from sklearn.metrics import adjusted_rand_score
from sklearn.neighbors import kneighbors_graph

from algorithms.clustering import spectral
from algorithms.core.graphs import knn_graph, nearest_sorted, neighbour_graph
from algorithms.embedding import isomap


def _structure(g) -> set[tuple[int, int]]:
    coo = sp.coo_array(g)
    return {(int(i), int(j)) for i, j in zip(coo.row, coo.col, strict=True) if i != j}


@pytest.mark.parametrize("include_self", [False, True])
def test_knn_graph_is_scikit_learns(include_self) -> None:
    x, _ = make_blobs(300, centers=4, n_features=5, random_state=3)  # no tied distances
    ref = kneighbors_graph(x, 7, mode="distance", include_self=include_self)
    ref = ref.maximum(ref.T)
    ours = knn_graph(x, 7, include_self=include_self)
    assert _structure(ours) == _structure(ref)
    np.testing.assert_allclose(ours.toarray(), ref.toarray() * (1 - np.eye(300)), rtol=1e-12)


def test_include_self_by_hand() -> None:
    # on a line 0, 1, 3, 7: with the point itself counted, 2 neighbours = 1 other
    x = [[0.0], [1.0], [3.0], [7.0]]
    g = knn_graph(x, 2, include_self=True)
    assert _structure(g) == {(0, 1), (1, 0), (2, 1), (1, 2), (3, 2), (2, 3)}
    assert _structure(knn_graph(x, 1)) == _structure(g)


def test_nearest_sorted_breaks_ties_by_index() -> None:
    # a 3 x 3 grid: the centre (4) has four neighbours at distance 1 (1, 3, 5, 7)
    x = np.array([[i, j] for i in range(3) for j in range(3)], float)
    d, i = nearest_sorted(x, 3)
    assert i[4].tolist() == [4, 1, 3] and d[4].tolist() == [0.0, 1.0, 1.0]
    d, i = nearest_sorted(x, 5)
    assert i[4].tolist() == [4, 1, 3, 5, 7]
    assert i[0].tolist() == [0, 1, 3, 4, 2]  # 4 at √2 before 2 and 6 at 2; 2 before 6


# scikit-learn: sklearn/cluster/tests/test_spectral.py::test_affinities (its first case)
def test_spectral_affinities_two_tight_blobs() -> None:
    x, y = make_blobs(n_samples=20, random_state=0, centers=[[1, 1], [-1, -1]],
                      cluster_std=0.01)
    ref = SpectralClustering(n_clusters=2, affinity="nearest_neighbors",
                             random_state=0).fit(x)
    assert adjusted_rand_score(y, ref.labels_) == 1
    # n_neighbors=10 counts the point itself: 9 others, each blob of 10 on its own
    ours = spectral(x, n_clusters=2)
    assert adjusted_rand_score(y, ours.labels) == 1
    # the same edges as scikit-learn's affinity (which also stores the diagonal)
    g = neighbour_graph(x, neighbors="knn", n_neighbors=10, include_self=True)
    assert _structure(g) == _structure(ref.affinity_matrix_)


@pytest.mark.parametrize("n_neighbors", [5, 12])
def test_spectral_embedding_graph_is_scikit_learns(n_neighbors) -> None:
    x, _ = make_blobs(200, centers=3, n_features=4, random_state=5)
    ref = SpectralEmbedding(n_neighbors=n_neighbors, affinity="nearest_neighbors",
                            random_state=0).fit(x)
    g = neighbour_graph(x, neighbors="knn", n_neighbors=n_neighbors, include_self=True)
    assert _structure(g) == _structure(ref.affinity_matrix_)


def test_isomap_on_digits_equals_scikit_learn_on_the_same_graph() -> None:
    x = load_digits().data[:600]
    ours = isomap(x, n_neighbors=10, n_components=2)
    g = knn_graph(x, 10)
    ref = Isomap(n_neighbors=None, radius=1e9, metric="precomputed", n_components=2,
                 eigen_solver="dense").fit_transform(sp.csr_matrix(g))
    np.testing.assert_allclose(np.abs(ours.embedding), np.abs(ref), rtol=1e-7, atol=1e-7)
