"""embedding.pca: a hand case, invariants, scikit-learn's PCA (equal, same signs), errors."""

from __future__ import annotations

import numpy as np
import pytest
from sklearn.datasets import load_digits, make_blobs, make_swiss_roll
from sklearn.decomposition import PCA

from algorithms.core.errors import InvalidInputError
from algorithms.embedding import pca

DATA = {
    "swiss_roll": make_swiss_roll(300, random_state=0)[0],
    "blobs": make_blobs(200, 5, centers=3, random_state=0)[0],
    "digits": load_digits().data[:300],
}


def test_hand_case_diagonal_line() -> None:
    res = pca([[0, 0], [1, 1], [2, 2], [3, 3]], n_components=1)
    np.testing.assert_allclose(res.components, [[2 ** -0.5, 2 ** -0.5]])
    np.testing.assert_allclose(res.embedding.ravel(), np.array([-1.5, -0.5, 0.5, 1.5]) * 2 ** 0.5)
    assert res.explained_variance_ratio[0] == pytest.approx(1.0)
    assert res.eigenvalues[0] == pytest.approx(np.var([0, 1, 2, 3], ddof=1) * 2)


@pytest.mark.parametrize("name", DATA)
def test_equals_scikit_learn(name: str) -> None:
    x = DATA[name]
    res = pca(x, n_components=3)
    sk = PCA(3, svd_solver="full").fit(x)
    np.testing.assert_allclose(res.embedding, sk.transform(x), atol=1e-9)  # same signs too
    np.testing.assert_allclose(res.components, sk.components_, atol=1e-12)
    np.testing.assert_allclose(res.eigenvalues, sk.explained_variance_, rtol=1e-10)
    np.testing.assert_allclose(res.explained_variance_ratio, sk.explained_variance_ratio_,
                               rtol=1e-10)
    assert 0.5 < res.trustworthiness <= 1.0


def test_invariants_rotation_translation_sign() -> None:
    rng = np.random.default_rng(3)
    x = rng.normal(size=(50, 4)) * [5, 3, 1, 0.5]
    q, _ = np.linalg.qr(rng.normal(size=(4, 4)))
    a, b = pca(x, n_components=2), pca(x @ q.T + 7.0, n_components=2)
    np.testing.assert_allclose(np.abs(a.embedding), np.abs(b.embedding), atol=1e-9)
    np.testing.assert_allclose(a.embedding.T @ a.embedding, np.diag(a.eigenvalues * 49),
                               atol=1e-8)  # uncorrelated scores
    big = np.argmax(np.abs(b.components), axis=1)
    assert np.all(b.components[np.arange(2), big] > 0)


def test_errors() -> None:
    with pytest.raises(InvalidInputError, match=r"n_components.*<= 2 \(the dimension of `points`"):
        pca(np.zeros((10, 2)) + np.arange(10)[:, None], n_components=3)
    with pytest.raises(InvalidInputError, match="at least 2 points"):
        pca([[1.0, 2.0]])
    with pytest.raises(InvalidInputError, match="row 1"):
        pca([[0, 0], [np.nan, 1], [2, 2]])
