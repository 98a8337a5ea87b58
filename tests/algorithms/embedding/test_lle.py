"""embedding.lle: weights by hand, the sum-to-one and null-vector invariants, scikit-learn's
LocallyLinearEmbedding on swiss roll, blobs and digits (Procrustes < 1e-6), errors."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial import procrustes
from sklearn.datasets import load_digits, make_blobs, make_swiss_roll
from sklearn.manifold import LocallyLinearEmbedding

from algorithms.core.errors import DegenerateInputError, InvalidInputError
from algorithms.embedding import lle
from algorithms.embedding.lle import barycenter_weights

DATA = {
    "swiss_roll": make_swiss_roll(400, random_state=0)[0],
    "blobs": make_blobs(300, 5, centers=3, cluster_std=4.0, random_state=0)[0],
    # integer pixels tie many distances: a tiny jitter makes the neighbours unambiguous
    "digits": load_digits().data[:400] + 1e-6 * np.random.default_rng(0).normal(size=(400, 64)),
}


def test_hand_case_square_weights() -> None:
    # unit square; each corner from its two edge neighbours: C = I, so w = (½, ½)
    x = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    nb = np.array([[1, 3], [0, 2], [1, 3], [0, 2]])
    w = barycenter_weights(x, nb, 0.0).toarray()
    np.testing.assert_allclose(w, [[0, .5, 0, .5], [.5, 0, .5, 0], [0, .5, 0, .5],
                                   [.5, 0, .5, 0]])
    # a corner from three points: x0 = x1 + x3 − x2 exactly (C singular without r)
    w3 = barycenter_weights(x, np.array([[1, 2, 3]] * 4), 1e-9).toarray()
    np.testing.assert_allclose(w3[0], [0, 1, -1, 1], atol=1e-6)


@pytest.mark.parametrize("name", DATA)
def test_equals_scikit_learn(name: str) -> None:
    x = DATA[name]
    res = lle(x, n_neighbors=12)
    sk = LocallyLinearEmbedding(n_neighbors=12, eigen_solver="dense").fit(x)
    assert procrustes(res.embedding, sk.embedding_)[2] < 1e-6
    assert res.reconstruction_error == pytest.approx(sk.reconstruction_error_, rel=1e-6,
                                                     abs=1e-12)
    np.testing.assert_allclose(res.embedding.T @ res.embedding, np.eye(2), atol=1e-9)


def test_sparse_path_and_radius_neighbours() -> None:
    x = make_swiss_roll(1100, random_state=3)[0]
    res = lle(x, n_neighbors=10)
    sk = LocallyLinearEmbedding(n_neighbors=10, eigen_solver="arpack", tol=1e-14,
                                max_iter=5000, random_state=0).fit_transform(x)
    assert procrustes(res.embedding, sk)[2] < 1e-6
    small = make_swiss_roll(300, random_state=4)[0]
    r = lle(small, neighbors="radius", radius=6.0)
    assert r.embedding.shape == (300, 2) and r.weight_error >= 0


def test_disconnected_and_errors() -> None:
    x = np.r_[np.random.default_rng(0).normal(size=(15, 3)),
              np.random.default_rng(1).normal(size=(15, 3)) + 50]
    with pytest.raises(DegenerateInputError, match="2 connected components"):
        lle(x, n_neighbors=4)
    with pytest.raises(DegenerateInputError, match="regularization"):
        lle(np.random.default_rng(0).normal(size=(20, 2)), n_neighbors=5, regularization=0.0)
    with pytest.raises(InvalidInputError, match="n_neighbors") as e:
        lle(x[:5], n_neighbors=5)
    assert e.value.field == "n_neighbors"
    with pytest.raises(InvalidInputError, match="neighbors"):
        lle(x, neighbors="all")
    with pytest.raises(DegenerateInputError, match="without"):
        lle(x, neighbors="radius", radius=0.01)
