"""NCA: the gradient against finite differences, a hand-made case, agreement with
scikit-learn's NeighborhoodComponentsAnalysis, determinism, progress and cancellation."""

from __future__ import annotations

import numpy as np
import pytest
from sklearn.datasets import load_digits, make_blobs
from sklearn.model_selection import train_test_split
from sklearn.neighbors import KNeighborsClassifier, NeighborhoodComponentsAnalysis

from algorithms.classification import nca
from algorithms.core.errors import Cancelled, InvalidInputError

STRIPES = [[0, 0], [0, 3], [0.2, 0.1], [0.2, 3.1], [0.4, -0.1], [0.4, 2.9]]


def test_separates_classes_the_start_mixes() -> None:
    # projected on x (the identity start) the classes interleave; along y they separate
    res = nca(STRIPES, [0, 1, 0, 1, 0, 1], n_components=1, init="identity")
    z = res.embedding[:, 0]
    assert max(z[0::2]) < min(z[1::2]) or max(z[1::2]) < min(z[0::2])
    assert res.accuracy == 1.0 and res.objective > 5.99


@pytest.mark.parametrize("name, n, k", [("digits", 450, 2), ("blobs", 400, 2)])
def test_classifies_as_well_as_scikit_learn(name, n, k) -> None:
    if name == "digits":
        x, y = load_digits(return_X_y=True)
        x, y = x[:n], y[:n]
    else:
        x, y = make_blobs(n, centers=5, n_features=6, cluster_std=3, random_state=0)
    xtr, xte, ytr, yte = train_test_split(x, y, test_size=0.3, random_state=0)
    ours = nca(xtr, ytr, n_components=k, query=xte)
    ref = NeighborhoodComponentsAnalysis(n_components=k, random_state=0).fit(xtr, ytr)
    acc = KNeighborsClassifier(5).fit(ours.embedding, ytr).score(ours.query_embedding, yte)
    acc_ref = KNeighborsClassifier(5).fit(ref.transform(xtr), ytr).score(ref.transform(xte),
                                                                          yte)
    assert acc >= acc_ref - 0.01, (acc, acc_ref)
    np.testing.assert_allclose(np.abs(ours.transform), np.abs(ref.components_), atol=1e-3)


def test_gradient_matches_finite_differences() -> None:
    rng = np.random.default_rng(0)
    x = rng.normal(size=(20, 3))
    y = rng.integers(0, 3, 20)
    seen = {}

    import scipy.optimize as so

    original = so.minimize

    def spy(fun, x0, **kw):
        seen["fun"], seen["x0"] = fun, x0
        return original(fun, x0, **kw)

    import sys

    import algorithms.classification.nca as mod  # noqa: F401

    m = sys.modules["algorithms.classification.nca"]
    old = m.minimize
    m.minimize = spy
    try:
        nca(x, y, n_components=2, init="random", max_iterations=1)
    finally:
        m.minimize = old
    a = rng.normal(size=6)
    f, g = seen["fun"](a)
    h = 1e-6
    num = np.array([(seen["fun"](a + h * e)[0] - seen["fun"](a - h * e)[0]) / (2 * h)
                    for e in np.eye(6)])
    np.testing.assert_allclose(g, num, rtol=1e-5, atol=1e-7)


def test_seed_progress_cancel() -> None:
    x, y = make_blobs(80, centers=3, n_features=4, random_state=2)
    seen = []
    a = nca(x, y, init="random", seed=4, progress=lambda *p: seen.append(p))
    b = nca(x, y, init="random", seed=4)
    assert np.array_equal(a.transform, b.transform)
    assert seen and [s[0] for s in seen] == list(range(1, len(seen) + 1))
    assert len(seen) == a.iterations

    def stop(done, total, message=""):
        raise Cancelled("stop")

    with pytest.raises(Cancelled):
        nca(x, y, progress=stop)


@pytest.mark.parametrize("kwargs, field, match", [
    ({"labels": [0, 1]}, "labels", r"one label per row of `points` \(6\), got 2"),
    ({"n_components": 3}, "n_components", "<= 2"),
    ({"init": "magic"}, "init", "one of"),
    ({"query": [[1, 2, 3]]}, "query", "same dimension"),
])
def test_bad_input(kwargs, field, match) -> None:
    with pytest.raises(InvalidInputError, match=match) as err:
        nca(**{"points": STRIPES, "labels": [0, 1, 0, 1, 0, 1], **kwargs})
    assert err.value.field == field
