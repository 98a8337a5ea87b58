"""embedding.laplacian_eigenmaps: a path graph by hand, the generalized eigen-equations,
scikit-learn's SpectralEmbedding on the same weights (Procrustes < 1e-6), the symmetric
variant (y = D^½ v), disconnected graphs, errors."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial import procrustes
from sklearn.datasets import load_digits, make_blobs, make_swiss_roll
from sklearn.manifold import SpectralEmbedding

from algorithms.core.errors import DegenerateInputError, InvalidInputError
from algorithms.embedding import laplacian_eigenmaps
from algorithms.embedding.laplacian_eigenmaps import similarity_graph, spectral_embedding

DATA = {
    "swiss_roll": make_swiss_roll(400, random_state=0)[0],
    "blobs": make_blobs(300, 5, centers=3, cluster_std=4.0, random_state=0)[0],
    "digits": load_digits().data[:400],
}


def test_hand_case_path_graph_unnormalized() -> None:
    # the path 0-1-2-3-4: L's eigenvalues are 2 - 2cos(πj/5), eigenvectors cos(πj(i+½)/5)
    x = np.c_[np.arange(5.0), np.zeros(5)]
    # n_neighbors counts the point itself (scikit-learn's SpectralEmbedding): one other
    res = laplacian_eigenmaps(x, n_components=2, n_neighbors=2, laplacian="unnormalized")
    j = np.array([1, 2])
    np.testing.assert_allclose(res.eigenvalues, 2 - 2 * np.cos(np.pi * j / 5), atol=1e-12)
    v = np.cos(np.pi * np.outer(np.arange(5) + 0.5, j) / 5)
    v /= np.linalg.norm(v, axis=0)
    np.testing.assert_allclose(np.abs(res.embedding), np.abs(v), atol=1e-12)


@pytest.mark.parametrize("kind", ["random_walk", "symmetric", "unnormalized"])
def test_generalized_eigen_equations(kind: str) -> None:
    x = DATA["swiss_roll"][:150]
    w = similarity_graph(x, "knn", 8, None, "heat", None, method="test").toarray()
    d = w.sum(axis=1)
    lap = np.diag(d) - w
    y, vals = spectral_embedding(w, 3, kind)
    if kind == "random_walk":
        np.testing.assert_allclose(lap @ y, (d[:, None] * y) * vals, atol=1e-9)
        np.testing.assert_allclose(y.T @ (d[:, None] * y), np.eye(3), atol=1e-9)
    elif kind == "symmetric":
        s = 1 / np.sqrt(d)
        np.testing.assert_allclose((s[:, None] * lap * s) @ y, y * vals, atol=1e-9)
    else:
        np.testing.assert_allclose(lap @ y, y * vals, atol=1e-9)
    assert np.all(np.diff(vals) >= 0) and vals[0] > 1e-9


@pytest.mark.parametrize("name", DATA)
def test_equals_scikit_learn_on_the_same_weights(name: str) -> None:
    x = DATA[name]
    w = similarity_graph(x, "knn", 10, None, "uniform", None, method="test")
    res = laplacian_eigenmaps(x, n_neighbors=10)
    sk = SpectralEmbedding(affinity="precomputed", random_state=0).fit_transform(w.toarray())
    assert procrustes(res.embedding, sk)[2] < 1e-6


def test_heat_kernel_on_all_pairs_is_scikit_learns_rbf_and_sparse_path() -> None:
    x = DATA["blobs"][:200]
    sigma = 6.0
    res = laplacian_eigenmaps(x, neighbors="all", weighting="heat", sigma=sigma)
    sk = SpectralEmbedding(affinity="rbf", gamma=1 / (2 * sigma ** 2),
                           random_state=0).fit_transform(x)
    assert procrustes(res.embedding, sk)[2] < 1e-6
    big = make_swiss_roll(1300, random_state=2)[0]          # the shift-invert Lanczos path
    w = similarity_graph(big, "knn", 10, None, "uniform", None, method="test")
    res = laplacian_eigenmaps(big, n_neighbors=10)
    sk = SpectralEmbedding(affinity="precomputed", eigen_solver="arpack",
                           random_state=0).fit_transform(w.toarray())
    assert procrustes(res.embedding, sk)[2] < 1e-6


def test_disconnected_and_errors() -> None:
    x = np.r_[np.zeros((10, 2)) + np.arange(10)[:, None], np.arange(10)[:, None] + [100, 0]]
    with pytest.raises(DegenerateInputError, match="2 connected components"):
        laplacian_eigenmaps(x, n_neighbors=2)
    with pytest.raises(InvalidInputError, match="n_neighbors"):
        laplacian_eigenmaps(x[:5], n_neighbors=5)
    with pytest.raises(InvalidInputError, match="laplacian"):
        laplacian_eigenmaps(x, laplacian="normalized")
    with pytest.raises(DegenerateInputError, match="distance 0"):
        laplacian_eigenmaps(np.r_[x[:5], x[:1]], n_neighbors=2, weighting="distance")
