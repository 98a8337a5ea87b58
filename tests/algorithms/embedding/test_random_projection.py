"""embedding.random_projection: norms kept in expectation, the sparse matrix's values and
density as scikit-learn's, the same seed the same matrix, errors."""

from __future__ import annotations

import numpy as np
import pytest
from sklearn.random_projection import SparseRandomProjection

from algorithms.core.errors import InvalidInputError
from algorithms.embedding import random_projection


@pytest.mark.parametrize("kind", ["gaussian", "sparse"])
def test_squared_norms_kept_in_expectation(kind: str) -> None:
    x = np.random.default_rng(12345).normal(size=(20, 400))  # not the stream of any seed
    ratios = [np.sum(random_projection(x, n_components=20, kind=kind, seed=100 + s).embedding ** 2)
              / np.sum(x ** 2) for s in range(30)]
    assert np.mean(ratios) == pytest.approx(1.0, abs=0.05)


def test_sparse_matrix_like_scikit_learn() -> None:
    x = np.random.default_rng(1).normal(size=(30, 900))
    res = random_projection(x, n_components=25, kind="sparse", seed=4)
    sk = SparseRandomProjection(25, random_state=4).fit(x).components_.toarray()
    for r in (res.components, sk):
        values = np.unique(np.round(np.abs(r[r != 0]), 12))
        np.testing.assert_allclose(values, [np.sqrt(30 / 25)])  # s = √D = 30
        assert np.mean(r != 0) == pytest.approx(1 / 30, rel=0.15)


def test_seeded_and_linear() -> None:
    x = np.random.default_rng(2).normal(size=(40, 10))
    a, b = random_projection(x, seed=7), random_projection(x, seed=7)
    np.testing.assert_array_equal(a.embedding, b.embedding)
    np.testing.assert_allclose(a.embedding, x @ a.components.T)
    assert not np.array_equal(a.components, random_projection(x, seed=8).components)
    d = random_projection(x, n_components=10, seed=1)
    assert d.distortion >= 0 and 0 <= d.trustworthiness <= 1


def test_errors() -> None:
    x = np.zeros((10, 3))
    with pytest.raises(InvalidInputError, match=r"n_components.*<= 3 \(the dimension of `points`"):
        random_projection(x, n_components=4)
    with pytest.raises(InvalidInputError, match="density"):
        random_projection(x, kind="sparse", density=1.5)
    with pytest.raises(InvalidInputError, match="kind"):
        random_projection(x, kind="dense")
