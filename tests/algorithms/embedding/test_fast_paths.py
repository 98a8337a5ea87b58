"""The faster paths of the embeddings give what the definitions give.

* PCA of tall data through the scatter matrix: the same axes and scores as the SVD of the
  centred data (NumPy's), whether the kept eigenvalues are separated or not;
* trustworthiness counted from kd-tree balls: the rank of every embedded neighbour by
  brute force, on data full of exact ties (integer grids) and of near-ties;
* the sparse shift-invert eigensolver (Cholesky of the shifted matrix): the dense
  eigenpairs of the same Laplacian.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as la
import scipy.sparse as sp

from algorithms.embedding import laplacian_eigenmaps, pca, trustworthiness
from algorithms.embedding.laplacian_eigenmaps import similarity_graph, spectral_embedding


def _svd_pca(x: np.ndarray, k: int) -> tuple[np.ndarray, np.ndarray]:
    xc = x - x.mean(axis=0)
    _, s, vt = np.linalg.svd(xc, full_matrices=False)
    v = vt[:k]
    at = np.argmax(np.abs(v), axis=1)
    v = v * np.sign(v[np.arange(k), at])[:, None]
    return xc @ v.T, s[:k]


@pytest.mark.parametrize("scales", [[9.0, 4.0, 2.0, 1.0, 0.5, 0.1],      # separated
                                    [3.0, 3.0 + 1e-9, 2.0, 1.5, 1.0, 0.5]])  # a near-tie
@pytest.mark.parametrize("k", [1, 2, 4])
def test_pca_tall_equals_svd(scales: list[float], k: int) -> None:
    rng = np.random.default_rng(3)
    q, _ = np.linalg.qr(rng.standard_normal((6, 6)))
    x = (rng.standard_normal((600, 6)) * scales) @ q.T + 5.0
    res = pca(x, n_components=k)
    y, s = _svd_pca(x, k)
    assert np.allclose(res.singular_values, s, rtol=1e-12, atol=0)
    if scales[0] != scales[1] or k != 1:
        # a pair of equal variances has no unique axes: only compare determined ones
        determined = [c for c in range(k) if not (c < 2 and scales[0] == 3.0)]
        assert np.allclose(res.embedding[:, determined], y[:, determined],
                           rtol=0, atol=1e-9 * np.abs(y).max())
    assert np.isclose(res.explained_variance_ratio.sum(), (s ** 2).sum() / (
        ((x - x.mean(axis=0)) ** 2).sum()), rtol=1e-12)


def _brute_trustworthiness(x: np.ndarray, y: np.ndarray, k: int) -> float:
    n = x.shape[0]
    dx = ((x[:, None, :] - x[None, :, :]) ** 2).sum(axis=2)
    dy = ((y[:, None, :] - y[None, :, :]) ** 2).sum(axis=2)
    np.fill_diagonal(dy, np.inf)
    total = 0.0
    for i in range(n):
        row = dx[i].copy()
        row[i] = -1.0          # the point itself: closer than all, removed below
        for j in np.lexsort((np.arange(n), dy[i]))[:k]:
            rank = int((row < row[j]).sum())   # 1 + #{l != i : d_il < d_ij}
            total += max(0, rank - k)
    return 1.0 - 2.0 * total / (n * k * (2.0 * n - 3.0 * k - 1.0))


@pytest.mark.parametrize("case", ["grid", "grid_folded", "near_ties", "bad"])
def test_trustworthiness_ball_counts_equal_brute_force(case: str) -> None:
    rng = np.random.default_rng(5)
    g = np.stack(np.meshgrid(np.arange(18.0), np.arange(18.0)), -1).reshape(-1, 2)
    x = np.c_[g, np.zeros(len(g))]
    if case == "grid":                       # many exact ties of distance
        y = g[:, ::-1] + rng.integers(0, 2, g.shape)
    elif case == "grid_folded":
        y = np.c_[np.abs(g[:, 0] - 8.5), g[:, 1]]
    elif case == "near_ties":                # ties broken by 1e-12: inside the margin
        x = x + rng.uniform(-1e-12, 1e-12, x.shape)
        y = g + rng.uniform(-0.4, 0.4, g.shape)
    else:                                    # neighbours in the embedding far in the input
        y = rng.standard_normal(g.shape)
    # the embedding's own neighbours must be unambiguous for the brute force's order
    y = y + rng.uniform(-1e-6, 1e-6, y.shape)
    for k in (1, 5, 9):
        assert trustworthiness(x, y, n_neighbors=k) == pytest.approx(
            _brute_trustworthiness(x, y, k), abs=1e-15)


def test_sparse_eigensolver_equals_dense() -> None:
    rng = np.random.default_rng(2)
    t = rng.uniform(0, 3 * np.pi, 1500)
    x = np.c_[t * np.cos(t), rng.uniform(0, 10, t.size), t * np.sin(t)]
    res = laplacian_eigenmaps(x, n_neighbors=10, n_components=2)   # 1,500 > dense limit
    w = sp.csr_array(similarity_graph(x, "knn", 10, None, "uniform", None,
                                      method="Laplacian eigenmaps"))
    d = np.asarray(w.sum(axis=1)).ravel()
    lap = (sp.diags_array(d) - w).toarray()
    vals, vecs = la.eigh(lap, np.diag(d), subset_by_index=[0, 2])
    assert np.allclose(res.eigenvalues, vals[1:], rtol=1e-9, atol=1e-14)
    ours, _ = spectral_embedding(w, 2)
    for c in range(2):
        v = vecs[:, c + 1] * np.sign(vecs[np.argmax(np.abs(vecs[:, c + 1])), c + 1])
        assert np.allclose(ours[:, c], v, atol=1e-7 * np.abs(v).max())
