"""Cases ported from scikit-learn's own tests of PCA (sklearn/decomposition/tests/
test_pca.py), Isomap (sklearn/manifold/tests/test_isomap.py), locally linear embedding
(sklearn/manifold/tests/test_locally_linear.py) and spectral clustering
(sklearn/cluster/tests/test_spectral.py); each test names the original."""

from __future__ import annotations

from itertools import product

import numpy as np
import pytest
from numpy.testing import assert_allclose
from sklearn.datasets import make_blobs
from sklearn.metrics import adjusted_rand_score
from sklearn.neighbors import kneighbors_graph, radius_neighbors_graph

from algorithms.clustering import spectral
from algorithms.embedding import isomap, lle, pca


# scikit-learn: test_pca.py::test_pca_check_projection
def test_pca_check_projection() -> None:
    rng = np.random.RandomState(0)
    x = rng.randn(100, 3) * 0.1
    x[:10] += np.array([3, 4, 5])
    xt = 0.1 * rng.randn(1, 3) + np.array([3, 4, 5])
    res = pca(x, n_components=2)
    yt = (xt - res.mean) @ res.components.T
    yt /= np.sqrt((yt ** 2).sum())
    assert_allclose(np.abs(yt[0][0]), 1.0, rtol=5e-3)


# scikit-learn: test_pca.py::test_pca_inverse (nearly rank-2 data is reconstructed)
def test_pca_inverse() -> None:
    rng = np.random.RandomState(0)
    x = rng.randn(50, 3)
    x[:, 1] *= 0.00001
    x += [5, 4, 3]
    res = pca(x, n_components=2)
    assert_allclose(x, res.embedding @ res.components + res.mean, rtol=5e-6)


# scikit-learn: test_pca.py::test_pca_explained_variance_empirical
def test_pca_explained_variance_empirical() -> None:
    rng = np.random.RandomState(0)
    x = rng.randn(1000, 30) * np.linspace(1, 3, 30)
    res = pca(x, n_components=2)
    assert_allclose(res.eigenvalues, np.var(res.embedding, ddof=1, axis=0))
    expected = sorted(np.linalg.eigvalsh(np.cov(x, rowvar=False)), reverse=True)[:2]
    assert_allclose(res.eigenvalues, expected, rtol=5e-3)


# scikit-learn: test_pca.py::test_pca_singular_values
def test_pca_singular_values() -> None:
    rng = np.random.RandomState(0)
    x = rng.randn(100, 80)
    res = pca(x, n_components=2)
    assert_allclose(np.sum(res.singular_values ** 2), np.linalg.norm(res.embedding) ** 2)
    assert_allclose(res.singular_values, np.sqrt(np.sum(res.embedding ** 2, axis=0)))
    # set the singular values and get them back
    x = rng.randn(100, 110)
    res = pca(x, n_components=3)
    scores = res.embedding / np.sqrt(np.sum(res.embedding ** 2, axis=0))
    scores[:, 0] *= 3.142
    scores[:, 1] *= 2.718
    again = pca(scores @ res.components, n_components=3)
    assert_allclose(again.singular_values, [3.142, 2.718, 1.0])


def _grid() -> np.ndarray:
    # scikit-learn: test_isomap.py::create_sample_data (a 5 x 5 grid)
    return np.array(list(product(range(5), repeat=2)), float)


# scikit-learn: test_isomap.py::test_isomap_simple_grid (all neighbours: distances kept)
@pytest.mark.parametrize("n_neighbors, radius", [(24, None), (None, np.inf)])
def test_isomap_simple_grid(n_neighbors, radius) -> None:  # noqa: ANN001
    x = _grid()
    if n_neighbors is not None:
        res = isomap(x, n_neighbors=n_neighbors, n_components=2)
        g = kneighbors_graph(x, n_neighbors, mode="distance")
        g_iso = kneighbors_graph(res.embedding, n_neighbors, mode="distance")
    else:
        # radius=inf is every pair: our neighbors="all" (a radius must be finite here)
        res = isomap(x, neighbors="all", n_components=2)
        g = radius_neighbors_graph(x, radius, mode="distance")
        g_iso = radius_neighbors_graph(res.embedding, radius, mode="distance")
    assert_allclose(g.toarray(), g_iso.toarray(), atol=1e-10)


# scikit-learn: test_isomap.py::test_isomap_reconstruction_error (a noisy third
# dimension: the 2-D embedding keeps the geodesic kernel up to that noise)
def test_isomap_reconstruction_error() -> None:
    x = _grid()
    x = np.c_[x, 0.1 * np.random.RandomState(0).randn(25, 1)]
    res = isomap(x, n_neighbors=24, n_components=2)
    g = kneighbors_graph(x, 24, mode="distance").toarray()
    g_iso = kneighbors_graph(res.embedding, 24, mode="distance").toarray()

    def centred(k: np.ndarray) -> np.ndarray:
        j = np.eye(25) - 1 / 25
        return j @ k @ j

    k, k_iso = centred(-0.5 * g ** 2), centred(-0.5 * g_iso ** 2)
    assert np.linalg.norm(k - k_iso) / 25 < 0.2  # sklearn: its reconstruction_error_


# scikit-learn: test_locally_linear.py::test_lle_simple_grid
def test_lle_simple_grid() -> None:
    rng = np.random.RandomState(42)
    x = np.array(list(product(range(5), repeat=2)), float)
    x = x + 1e-10 * rng.uniform(size=x.shape)
    res = lle(x, n_neighbors=5, n_components=2)
    assert res.embedding.shape[1] == 2
    assert res.weight_error < 0.1  # the barycentre weights reconstruct X
    assert res.reconstruction_error < 0.1


# scikit-learn: test_locally_linear.py::test_lle_manifold (a curved 2-D sheet in 3-D)
def test_lle_manifold() -> None:
    rng = np.random.RandomState(0)
    x = np.array(list(product(np.arange(18), repeat=2)), float)
    x = np.c_[x, x[:, 0] ** 2 / 18]
    x = x + 1e-10 * rng.uniform(size=x.shape)
    res = lle(x, n_neighbors=6, n_components=2)
    assert res.embedding.shape[1] == 2
    assert res.weight_error < 0.1 * x.shape[0] ** 0.5  # sklearn: tol * n_samples ** 0.5


# scikit-learn: test_spectral.py::test_spectral_clustering (three tight groups; labels up
# to their names)
def test_spectral_clustering_three_groups() -> None:
    x, y = make_blobs(n_samples=100, centers=[[1, 1], [-1, -1], [1, -1]],
                      cluster_std=0.1, random_state=42)
    res = spectral(x, n_clusters=3, n_neighbors=10)
    assert adjusted_rand_score(y, res.labels) == 1


# scikit-learn: test_spectral.py::test_affinities (the second case: an rbf-like kernel,
# here our heat weighting on all pairs)
def test_affinities_heat_kernel() -> None:
    x, y = make_blobs(n_samples=20, random_state=0, centers=[[1, 1], [-1, -1]],
                      cluster_std=0.01)
    res = spectral(x, n_clusters=2, neighbors="all", weighting="heat", sigma=1.0)
    assert adjusted_rand_score(y, res.labels) == 1


# scikit-learn: sklearn/manifold/tests/test_classical_mds.py::
# test_classical_mds_equivalent_to_pca
def test_classical_mds_equivalent_to_pca() -> None:
    from sklearn.datasets import load_iris

    from algorithms.embedding import mds

    x, _ = load_iris(return_X_y=True)
    z1 = mds(x, n_components=2)
    z2 = pca(x, n_components=2)
    signs = np.sign(z1.embedding[0]) * np.sign(z2.embedding[0])
    assert_allclose(z1.embedding, z2.embedding * signs, atol=1e-10)
    assert_allclose(np.sqrt(z1.eigenvalues), z2.singular_values)
