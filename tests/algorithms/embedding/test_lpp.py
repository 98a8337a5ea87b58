"""embedding.lpp: the generalized eigen-equations, the reduction to Laplacian eigenmaps
when every function is linear, invariance to rigid motions, errors."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial import procrustes
from sklearn.datasets import make_swiss_roll

from algorithms.core.errors import DegenerateInputError, InvalidInputError
from algorithms.embedding import lpp
from algorithms.embedding.laplacian_eigenmaps import spectral_embedding
from algorithms.embedding.lpp import lpp_from_weights

X = make_swiss_roll(200, random_state=0)[0]


def _random_weights(n: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    w = rng.random((n, n)) * (rng.random((n, n)) < 0.5)
    w = np.triu(w, 1)
    w = w + w.T
    w[np.arange(n - 1), np.arange(1, n)] += 1.0   # a path keeps it connected
    w[np.arange(1, n), np.arange(n - 1)] += 1.0
    return w


@pytest.mark.parametrize("kind", ["random_walk", "symmetric", "unnormalized"])
def test_generalized_eigen_equations(kind: str) -> None:
    w = _random_weights(60, 1)
    x = np.random.default_rng(2).normal(size=(60, 5))
    comps, vals, mu = lpp_from_weights(x, w, 3, kind)
    d = w.sum(axis=1)
    lap = np.diag(d) - w
    xc = x - mu
    if kind == "symmetric":
        s = 1 / np.sqrt(d)
        a, b = xc.T @ (s[:, None] * lap * s) @ xc, xc.T @ xc
    elif kind == "random_walk":
        a, b = xc.T @ lap @ xc, xc.T @ np.diag(d) @ xc
        np.testing.assert_allclose(d @ xc, 0.0, atol=1e-9)     # degree-weighted centre
    else:
        a, b = xc.T @ lap @ xc, xc.T @ xc
    np.testing.assert_allclose(a @ comps.T, b @ comps.T * vals, atol=1e-9)
    np.testing.assert_allclose(comps @ b @ comps.T, np.eye(3), atol=1e-9)


@pytest.mark.parametrize("seed", range(3))
def test_affinely_independent_points_give_laplacian_eigenmaps(seed: int) -> None:
    n = 12
    x = np.random.default_rng(seed).normal(size=(n, n - 1))   # every function is linear
    w = _random_weights(n, seed + 10)
    comps, vals, mu = lpp_from_weights(x, w, 3, "random_walk")
    y, lam = spectral_embedding(w, 3, "random_walk")
    np.testing.assert_allclose(vals, lam, rtol=1e-8)
    np.testing.assert_allclose(np.abs((x - mu) @ comps.T), np.abs(y), atol=1e-8)


def test_rigid_motion_invariance_and_projection() -> None:
    q, _ = np.linalg.qr(np.random.default_rng(5).normal(size=(3, 3)))
    a = lpp(X, n_neighbors=8)
    b = lpp(X @ q.T + [3.0, -2.0, 9.0], n_neighbors=8)
    assert procrustes(a.embedding, b.embedding)[2] < 1e-12
    np.testing.assert_allclose(a.embedding, (X - a.mean) @ a.components.T, atol=1e-12)
    assert 0.5 < a.trustworthiness <= 1


def test_errors() -> None:
    with pytest.raises(InvalidInputError, match=r"n_components.*<= 3 \(the dimension of `points`"):
        lpp(X, n_components=4)
    flat = np.c_[X[:, :2], np.zeros(200)]
    with pytest.raises(DegenerateInputError, match="rank 2"):
        lpp(flat, n_neighbors=8)
    with pytest.raises(InvalidInputError, match="n_neighbors"):
        lpp(X[:5], n_neighbors=9)
