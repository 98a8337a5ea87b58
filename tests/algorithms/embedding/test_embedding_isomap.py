"""embedding.isomap: a hand case (an arc unrolled), scikit-learn's Isomap on swiss roll, blobs
and digits (Procrustes disparity < 1e-6, same neighbours), disconnected graphs, errors."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial import procrustes
from sklearn.datasets import load_digits, make_blobs, make_swiss_roll
from sklearn.manifold import Isomap

from algorithms.core.errors import DegenerateInputError, InvalidInputError
from algorithms.embedding import isomap

DATA = {
    "swiss_roll": make_swiss_roll(400, random_state=0)[0],
    "blobs": make_blobs(300, 5, centers=3, cluster_std=4.0, random_state=0)[0],
    # integer pixels tie many distances: a tiny jitter makes the neighbours unambiguous
    "digits": load_digits().data[:400] + 1e-6 * np.random.default_rng(0).normal(size=(400, 64)),
}


def test_hand_case_arc_is_unrolled() -> None:
    t = np.linspace(0, np.pi, 20)                 # 19 equal chords of a half circle
    arc = np.c_[np.cos(t), np.sin(t)]
    y = isomap(arc, n_components=1, neighbors="radius", radius=0.2).embedding[:, 0]
    chord = 2 * np.sin(np.pi / 38)
    np.testing.assert_allclose(np.abs(np.diff(y)), chord, rtol=1e-9)  # geodesic spacing
    hops = isomap(arc, n_components=1, neighbors="radius", radius=0.2, weighting="uniform")
    np.testing.assert_allclose(np.abs(np.diff(hops.embedding[:, 0])), 1.0, rtol=1e-9)


@pytest.mark.parametrize("name", DATA)
def test_equals_scikit_learn(name: str) -> None:
    x = DATA[name]
    res = isomap(x, n_neighbors=10, n_components=2)
    sk = Isomap(n_neighbors=10, n_components=2, eigen_solver="dense").fit(x)
    assert procrustes(res.embedding, sk.embedding_)[2] < 1e-6
    np.testing.assert_allclose(res.eigenvalues, sk.kernel_pca_.eigenvalues_, rtol=1e-8)
    assert res.trustworthiness > 0.7


def test_lanczos_path_equals_dense_above_400_points() -> None:
    x = make_swiss_roll(700, random_state=1)[0]
    res = isomap(x, n_neighbors=8)
    sk = Isomap(n_neighbors=8, eigen_solver="dense").fit_transform(x)
    assert procrustes(res.embedding, sk)[2] < 1e-6


def test_disconnected_graph_names_component_count() -> None:
    x = np.r_[np.random.default_rng(0).normal(size=(20, 3)),
              np.random.default_rng(1).normal(size=(20, 3)) + 100]
    with pytest.raises(DegenerateInputError, match="2 connected components") as e:
        isomap(x, n_neighbors=3)
    assert e.value.field == "n_neighbors"


def test_errors() -> None:
    x = np.random.default_rng(0).normal(size=(6, 3))
    with pytest.raises(InvalidInputError, match="n_neighbors.*<= 5") as e:
        isomap(x, n_neighbors=6)
    assert e.value.field == "n_neighbors"
    with pytest.raises(InvalidInputError, match="radius"):
        isomap(x, neighbors="radius")
    with pytest.raises(InvalidInputError, match="weighting"):
        isomap(x, weighting="heat")
    with pytest.raises(InvalidInputError, match="n_components"):
        isomap(x, n_components=7)
