"""Cases ported from scikit-learn's own tests of LinearDiscriminantAnalysis
(sklearn/tests/test_discriminant_analysis.py) and NeighborhoodComponentsAnalysis
(sklearn/neighbors/tests/test_nca.py); each test names the original. Our code, their
inputs and their expected answers."""

from __future__ import annotations

import numpy as np
from scipy.spatial.distance import cdist

from algorithms.classification import lda, nca

# scikit-learn's module-level data: 6 separable points in the plane, and 1-D variants
X = np.array([[-2, -1], [-1, -1], [-1, -2], [1, 1], [1, 2], [2, 1]], float)
Y = np.array([1, 1, 1, 2, 2, 2])
Y3 = np.array([1, 1, 2, 2, 3, 3])
X1 = np.array([[-2], [-1], [-1], [1], [1], [2]], float)


# scikit-learn: test_discriminant_analysis.py::test_lda_predict (the svd solver)
def test_lda_predict() -> None:
    assert lda(X, Y).predictions == Y.tolist()
    assert lda(X1, Y).predictions == Y.tolist()  # 1-D data
    # LDA cannot separate these three classes
    assert lda(X, Y3).predictions != Y3.tolist()


# scikit-learn: test_discriminant_analysis.py::test_lda_transform
def test_lda_transform() -> None:
    assert lda(X, Y, n_components=1).embedding.shape[1] == 1


# scikit-learn: test_discriminant_analysis.py::test_lda_explained_variance_ratio
def test_lda_explained_variance_ratio() -> None:
    state = np.random.RandomState(0)
    x = state.normal(loc=0, scale=100, size=(40, 20))
    y = state.randint(0, 3, size=(40,))
    res = lda(x, y)
    assert res.explained_variance_ratio.shape == (2,)
    np.testing.assert_almost_equal(res.explained_variance_ratio.sum(), 1.0, 3)


# scikit-learn: test_discriminant_analysis.py::test_lda_orthogonality
def test_lda_orthogonality() -> None:
    # four classes with their means in a kite: the longer distance on the first
    # component, the shorter on the second
    means = np.array([[0, 0, -1], [0, 2, 0], [0, -2, 0], [0, 0, 5]], float)
    scatter = np.array([[0.1, 0, 0], [-0.1, 0, 0], [0, 0.1, 0], [0, -0.1, 0],
                        [0, 0, 0.1], [0, 0, -0.1]])
    x = (means[:, None, :] + scatter[None, :, :]).reshape((-1, 3))
    y = np.repeat(np.arange(4), 6)
    res = lda(x, y, query=np.vstack([means, scatter]))
    means_t, scatter_t = res.query_embedding[:4], res.query_embedding[4:]
    d1 = means_t[3] - means_t[0]
    d2 = means_t[2] - means_t[1]
    d1 /= np.linalg.norm(d1)
    d2 /= np.linalg.norm(d2)
    # the transformed ML within-class covariance is the identity
    np.testing.assert_almost_equal(np.cov(scatter_t.T, bias=True),
                                   np.eye(scatter_t.shape[1]))
    np.testing.assert_almost_equal(abs(d1[:2] @ [1, 0]), 1.0)
    np.testing.assert_almost_equal(abs(d2[:2] @ [0, 1]), 1.0)


# scikit-learn: test_discriminant_analysis.py::test_lda_scaling
def test_lda_scaling() -> None:
    n = 100
    rng = np.random.RandomState(1234)
    x1 = rng.uniform(-1, 1, (n, 3)) + [-10, 0, 0]
    x2 = rng.uniform(-1, 1, (n, 3)) + [10, 0, 0]
    x = np.vstack((x1, x2)) * [1, 100, 10000]
    assert lda(x, [-1] * n + [1] * n).accuracy == 1.0


# scikit-learn: test_discriminant_analysis.py::test_lda_priors (priors are the class
# proportions here, scikit-learn's default): a 1-point class is still predicted
def test_lda_one_element_class() -> None:
    x6 = np.array([[0, 0], [-2, -2], [-2, -1], [-1, -1], [-1, -2], [1, 3], [1, 2], [2, 1],
                   [2, 2]], float)
    y6 = np.array([1, 1, 1, 1, 1, 2, 2, 2, 2])
    assert lda(x6, y6).predictions == y6.tolist()


# scikit-learn: test_nca.py::test_simple_example
def test_nca_simple_example() -> None:
    x = np.array([[0, 0], [0, 1], [2, 0], [2, 1]], float)
    y = np.array([1, 0, 1, 0])
    res = nca(x, y, n_components=2, init="identity", seed=42)
    order = cdist(res.embedding, res.embedding).argsort()[:, 1]
    np.testing.assert_array_equal(order, [2, 3, 0, 1])


# scikit-learn: test_nca.py::test_toy_example_collapse_points
def test_nca_toy_example_collapse_points() -> None:
    rng = np.random.RandomState(42)
    two = rng.randn(2, 5)
    x = np.vstack([two, two.mean(axis=0)[None, :]])
    res = nca(x, [0, 0, 1], seed=42)
    # the objective 2 / (1 + exp(d / 2)) is largest at d = 0: the points collapse
    np.testing.assert_array_almost_equal(res.embedding - res.embedding[0], 0.0)


# scikit-learn: test_nca.py::test_transformation_dimensions / test_n_components
def test_nca_transformation_dimensions() -> None:
    rng = np.random.RandomState(0)
    x = rng.randn(30, 5)
    y = rng.randint(0, 3, 30)
    res = nca(x, y, n_components=3, max_iterations=5)
    assert res.transform.shape == (3, 5) and res.embedding.shape == (30, 3)
    np.testing.assert_allclose(res.embedding, x @ res.transform.T, atol=1e-10)
