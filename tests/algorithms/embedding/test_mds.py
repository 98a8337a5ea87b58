"""embedding.mds: distances kept exactly when they fit, equal to PCA and to scikit-learn's
ClassicalMDS up to sign; the metric refinement never raises the stress; errors."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.distance import pdist
from sklearn.datasets import load_digits, make_blobs, make_swiss_roll
from sklearn.manifold import ClassicalMDS

from algorithms.core.errors import InvalidInputError
from algorithms.embedding import mds, pca

DATA = {
    "swiss_roll": make_swiss_roll(250, random_state=0)[0],
    "blobs": make_blobs(200, 5, centers=3, random_state=0)[0],
    "digits": load_digits().data[:250],
}


def test_hand_case_planar_points_are_reproduced() -> None:
    x = [[0, 0, 0], [3, 0, 0], [0, 4, 0], [3, 4, 0]]   # a 3×4 rectangle in 3-D
    res = mds(x)
    np.testing.assert_allclose(pdist(res.embedding), pdist(np.asarray(x, float)), atol=1e-12)
    assert res.stress == pytest.approx(0.0, abs=1e-20)
    np.testing.assert_allclose(res.eigenvalues, [16.0, 9.0], rtol=1e-12)  # 4·2², 4·1.5²


@pytest.mark.parametrize("name", DATA)
def test_equals_classical_mds_of_scikit_learn_and_pca(name: str) -> None:
    x = DATA[name]
    res = mds(x, n_components=3)
    sk = ClassicalMDS(3).fit_transform(x)
    np.testing.assert_allclose(np.abs(res.embedding), np.abs(sk), atol=1e-8)
    np.testing.assert_allclose(np.abs(res.embedding), np.abs(pca(x, n_components=3).embedding),
                               atol=1e-8)


def test_metric_refinement_lowers_stress() -> None:
    x = DATA["swiss_roll"][:120]
    classical, metric = mds(x), mds(x, metric=True)
    assert metric.stress <= classical.stress
    assert metric.iterations > 0 and classical.iterations == 0


@pytest.mark.parametrize("name", ["iris", "gaussian"])
def test_metric_equals_scikit_learns_smacof_from_the_classical_start(name: str) -> None:
    # the Notes' "scikit-learn's names": metric=True is MDS(metric_mds=True,
    # init="classical_mds") with the same iteration limit and stopping rule
    from sklearn.datasets import load_iris
    from sklearn.manifold import MDS

    x = load_iris().data if name == "iris" else np.random.default_rng(0).normal(size=(80, 6))
    ours = mds(x, metric=True)
    ref = MDS(n_components=2, metric_mds=True, init="classical_mds", n_init=1, max_iter=300,
              eps=1e-6, normalized_stress=False)
    emb = ref.fit_transform(x)
    assert ours.iterations == ref.n_iter_
    assert ours.stress == pytest.approx(ref.stress_, rel=1e-12)
    np.testing.assert_allclose(np.abs(ours.embedding), np.abs(emb), atol=1e-12)


def test_errors() -> None:
    with pytest.raises(InvalidInputError, match=r"n_components.*<= 3 \(the number of `points`\)"):
        mds(np.eye(3), n_components=4)
    with pytest.raises(InvalidInputError, match="at most 4000 points"):
        mds(np.zeros((4001, 2)))
