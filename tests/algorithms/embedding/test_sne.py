"""Symmetric SNE: a hand case, the gradient against finite differences, the descent lowers
the KL from its start and separates clusters, t-SNE beats it on clustered data (its heavy
tails keep neighbourhoods that SNE's Gaussian crowds), determinism, progress and
cancellation, errors."""

from __future__ import annotations

import numpy as np
import pytest
from sklearn.datasets import make_blobs
from sklearn.manifold import trustworthiness

from algorithms.core.errors import Cancelled, InvalidInputError
from algorithms.embedding import sne, tsne
from algorithms.embedding.sne import _sne_kl_gradient
from algorithms.embedding.tsne import affinities

BLOBS, LABELS = make_blobs(150, n_features=8, centers=3, cluster_std=1.0, random_state=0)


def _kl_gauss(p: np.ndarray, y: np.ndarray) -> float:
    """KL(P‖Q) with Gaussian Q, by hand."""
    w = np.exp(-((y[:, None, :] - y[None, :, :]) ** 2).sum(-1))
    np.fill_diagonal(w, 0.0)
    q = w / w.sum()
    m = p > 0
    return float((p[m] * np.log(p[m] / q[m])).sum())


def test_three_points_by_hand() -> None:
    # an equilateral triangle: all p_ij = 1/6, and Q is uniform for an equilateral
    # embedding too, so KL = 0 and the gradient vanishes
    x = np.array([[0.0, 0.0], [1.0, 0.0], [0.5, np.sqrt(3) / 2]])
    p = affinities(x, 2.0, dense=True)   # perplexity n − 1: the uniform row
    np.testing.assert_allclose(p, (1 - np.eye(3)) / 6, atol=1e-12)
    y = 0.3 * x
    kl, grad = _sne_kl_gradient(p, y)
    assert kl == pytest.approx(0.0, abs=1e-12)
    np.testing.assert_allclose(grad, 0.0, atol=1e-12)


@pytest.mark.parametrize("exaggeration", [1.0, 4.0])
def test_gradient_matches_finite_differences(exaggeration: float) -> None:
    rng = np.random.default_rng(1)
    x = rng.normal(size=(20, 5))
    p = affinities(x, 4.0, dense=True)
    y = rng.normal(size=(20, 2))
    kl, grad = _sne_kl_gradient(p, y, exaggeration)
    assert kl == pytest.approx(_kl_gauss(p, y), rel=1e-12)

    def cost(yy: np.ndarray) -> float:
        # α Σ p d² + log Z: KL up to a constant when α = 1, gradient 4 Σ (α p − q)(y_i − y_j)
        d2 = ((yy[:, None] - yy[None]) ** 2).sum(-1)
        w = np.exp(-d2)
        np.fill_diagonal(w, 0.0)
        return exaggeration * float((p * d2).sum()) + np.log(w.sum())

    h = 1e-6
    fd = np.zeros_like(y)
    for i in range(20):
        for k in range(2):
            e = np.zeros_like(y)
            e[i, k] = h
            fd[i, k] = (cost(y + e) - cost(y - e)) / (2 * h)
    np.testing.assert_allclose(grad, fd, rtol=1e-6, atol=1e-9)


def test_descent_lowers_kl_and_separates_clusters() -> None:
    res = sne(BLOBS, perplexity=15, max_iterations=400)
    p = affinities(BLOBS, 15.0, dense=True)
    start = sne(BLOBS, perplexity=15, max_iterations=1, exaggeration_iterations=0,
                learning_rate=1e-12)
    assert res.kl_divergence == pytest.approx(_kl_gauss(p, res.embedding), rel=1e-9)
    assert res.kl_divergence < 0.5 * start.kl_divergence
    assert res.trustworthiness == pytest.approx(trustworthiness(BLOBS, res.embedding))
    assert res.trustworthiness > 0.9
    # clusters: each point's nearest embedded neighbour has its label
    y = res.embedding
    d2 = ((y[:, None] - y[None]) ** 2).sum(-1)
    np.fill_diagonal(d2, np.inf)
    assert (LABELS[d2.argmin(axis=1)] == LABELS).mean() > 0.95


def test_tsne_keeps_neighbourhoods_better_than_sne() -> None:
    # the Student-t kernel's heavy tails keep apart what the Gaussian one crowds together
    x, _ = make_blobs(200, n_features=10, centers=4, random_state=0)
    a = sne(x, max_iterations=500)
    b = tsne(x, max_iterations=500)
    assert b.trustworthiness > a.trustworthiness


def test_same_seed_same_embedding_progress_and_cancel() -> None:
    seen: list[tuple] = []
    a = sne(BLOBS, init="random", seed=3, max_iterations=80, exaggeration_iterations=40,
            progress=lambda *m: seen.append(m))
    b = sne(BLOBS, init="random", seed=3, max_iterations=80, exaggeration_iterations=40)
    assert np.array_equal(a.embedding, b.embedding) and a.iterations == 80
    assert seen[-1][:2] == (80, 80) and "SNE" in seen[-1][2]

    def stop(done, total, message=""):  # noqa: ANN001, ANN202
        if done >= 3:
            raise Cancelled("stop")

    with pytest.raises(Cancelled):
        sne(BLOBS, progress=stop)


@pytest.mark.parametrize("kwargs, field, match", [
    ({"perplexity": 150}, "perplexity", "below the number of `points` \\(150\\)"),
    ({"init": "spectral"}, "init", "'pca'"),
    ({"learning_rate": 0}, "learning_rate", "learning_rate"),
    ({"n_components": 0}, "n_components", ">= 1"),
])
def test_bad_parameters(kwargs: dict, field: str, match: str) -> None:
    with pytest.raises(InvalidInputError, match=match) as err:
        sne(BLOBS, **kwargs)
    assert err.value.field == field


def test_too_many_points_names_the_bound() -> None:
    with pytest.raises(InvalidInputError, match="5,000") as err:
        sne(np.zeros((5001, 2)))
    assert err.value.field == "points"
