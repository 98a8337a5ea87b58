"""Fisher LDA: a hand-made case, and agreement with scikit-learn's
LinearDiscriminantAnalysis on load_digits and blobs."""

from __future__ import annotations

import numpy as np
import pytest
from sklearn.datasets import load_digits, make_blobs
from sklearn.discriminant_analysis import LinearDiscriminantAnalysis
from sklearn.manifold import trustworthiness
from sklearn.model_selection import train_test_split
from sklearn.neighbors import KNeighborsClassifier

from algorithms.classification import lda
from algorithms.core.errors import DegenerateInputError, InvalidInputError


def test_two_classes_by_hand() -> None:
    # classes along x = y; the within-class spread is isotropic, so the direction is (1, 1)
    pts = [[0, 0], [1, 0], [0, 1], [1, 1], [5, 5], [6, 5], [5, 6], [6, 6]]
    res = lda(pts, ["a"] * 4 + ["b"] * 4, query=[[0.2, 0.1], [5.5, 6.5]])
    d = res.scalings[:, 0] / np.linalg.norm(res.scalings[:, 0])
    np.testing.assert_allclose(d * np.sign(d[0]), [2 ** -0.5, 2 ** -0.5], atol=1e-12)
    assert res.predictions == ["a"] * 4 + ["b"] * 4 and res.accuracy == 1.0
    assert res.query_predictions == ["a", "b"] and res.classes == ["a", "b"]
    # whitened: unit within-class variance along the direction
    within = res.embedding[:, 0] - np.repeat([res.embedding[:4, 0].mean(),
                                              res.embedding[4:, 0].mean()], 4)
    np.testing.assert_allclose(np.mean(within ** 2), 1.0)


@pytest.mark.parametrize("name", ["digits", "blobs"])
def test_classifies_as_well_as_scikit_learn(name) -> None:
    if name == "digits":
        x, y = load_digits(return_X_y=True)
    else:
        x, y = make_blobs(600, centers=5, n_features=6, cluster_std=3, random_state=0)
    xtr, xte, ytr, yte = train_test_split(x, y, test_size=0.3, random_state=0)
    ours = lda(xtr, ytr, query=xte)
    ref = LinearDiscriminantAnalysis().fit(xtr, ytr)
    acc = KNeighborsClassifier(5).fit(ours.embedding, ytr).score(ours.query_embedding, yte)
    acc_ref = KNeighborsClassifier(5).fit(ref.transform(xtr), ytr).score(ref.transform(xte),
                                                                          yte)
    assert abs(acc - acc_ref) <= 0.01
    assert np.array_equal(ours.query_predictions, ref.predict(xte))
    # the same projection up to the sign of each direction
    np.testing.assert_allclose(np.abs(ours.embedding), np.abs(ref.transform(xtr)), atol=1e-8)
    np.testing.assert_allclose(ours.explained_variance_ratio, ref.explained_variance_ratio_)
    assert abs(ours.trustworthiness - trustworthiness(xtr, ours.embedding)) < 1e-4


def test_signs_and_n_components() -> None:
    x, y = make_blobs(200, centers=4, n_features=5, random_state=1)
    res = lda(x, y, n_components=2)
    assert res.embedding.shape == (200, 2) and res.scalings.shape == (5, 2)
    big = np.abs(res.embedding).argmax(axis=0)
    assert (res.embedding[big, [0, 1]] > 0).all()
    np.testing.assert_allclose(res.embedding, (x - res.mean) @ res.scalings)


@pytest.mark.parametrize("kwargs, field, match", [
    ({"labels": [0, 1, 0]}, "labels", r"one label per row of `points` \(6\), got 3"),
    ({"labels": [0] * 6}, "labels", "at least 2 classes"),
    ({"n_components": 2}, "n_components", r"min\(classes - 1, dimension\)"),
    ({"query": [[0, 0, 0]]}, "query", "same dimension"),
    ({"labels": [0, 1, 0.5, 1, 0, 1]}, "labels", "position 2"),
])
def test_bad_input(kwargs, field, match) -> None:
    pts = [[0, 0], [1, 0.2], [0, 1], [5, 5], [6, 5], [5, 6.3]]
    with pytest.raises(InvalidInputError, match=match) as err:
        lda(**{"points": pts, "labels": [0, 0, 0, 1, 1, 1], **kwargs})
    assert err.value.field == field


def test_no_within_class_spread() -> None:
    with pytest.raises(DegenerateInputError, match="within their classes"):
        lda([[0, 0], [0, 0], [1, 1], [1, 1]], [0, 0, 1, 1])


def _means_in_a_plane() -> tuple[np.ndarray, np.ndarray]:
    # 4 classes in 3-D whose means lie in the plane z = 0: the between-class scatter has
    # rank 2 although min(c - 1, d) = 3
    rng = np.random.default_rng(0)
    centres = np.array([[0, 0, 0], [4, 0, 0], [0, 4, 0], [4, 4, 0]], float)
    y = np.repeat(np.arange(4), 50)
    x = centres[y] + rng.normal(size=(200, 3))
    x -= np.vstack([x[y == c].mean(axis=0) - centres[c] for c in range(4)])[y]  # exact means
    return x, y


@pytest.mark.parametrize("n_components", [None, 3])
def test_means_of_lower_rank_give_only_the_directions_with_rank(n_components) -> None:
    x, y = _means_in_a_plane()
    res = lda(x, y, n_components=n_components, query=x[:5])
    ref = LinearDiscriminantAnalysis(n_components=n_components).fit(x, y)
    # scikit-learn's transform returns min(rank, n_components) = 2 columns; so do we
    assert ref.transform(x).shape == (200, 2)
    assert res.embedding.shape == (200, 2) and res.scalings.shape == (3, 2)
    assert res.query_embedding.shape == (5, 2) and res.explained_variance_ratio.shape == (2,)
    np.testing.assert_allclose(np.abs(res.embedding), np.abs(ref.transform(x)), atol=1e-8)
    np.testing.assert_allclose(res.explained_variance_ratio,
                               ref.explained_variance_ratio_[:2], rtol=1e-10)
    assert ref.explained_variance_ratio_[2:].sum() < 1e-8  # the share sklearn keeps besides
    # no constant column: unit within-class variance along every direction, as promised
    within = res.embedding - np.vstack([res.embedding[y == c].mean(axis=0)
                                        for c in range(4)])[y]
    np.testing.assert_allclose(np.mean(within ** 2, axis=0), 1.0, rtol=1e-10)
    assert np.array_equal(res.predictions, ref.predict(x))
