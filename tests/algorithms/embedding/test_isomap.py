"""embedding.isomap: a hand case (an arc unrolled), scikit-learn's Isomap on swiss roll, blobs
and digits (Procrustes disparity < 1e-6, same neighbours), disconnected graphs, errors; the
geodesics from a separator against scipy's Dijkstra from every point, the block Krylov
eigenpairs against a dense eigendecomposition."""

from __future__ import annotations

import importlib

import numpy as np
import pytest
import scipy.linalg as la
import scipy.sparse as sp
from scipy.sparse.csgraph import dijkstra
from scipy.spatial import procrustes
from sklearn.datasets import load_digits, make_blobs, make_swiss_roll
from sklearn.manifold import Isomap
from sklearn.manifold import trustworthiness as sk_trustworthiness

from algorithms.core.errors import DegenerateInputError, InvalidInputError
from algorithms.core.graphs import neighbour_graph
from algorithms.embedding import isomap
from algorithms.embedding.isomap import (
    _geodesic_distances,
    _min_plus,
    _principal_coordinates,
)

isomap_module = importlib.import_module("algorithms.embedding.isomap")  # not the function

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


def test_block_krylov_path_equals_dense_above_400_points() -> None:
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


def _graphs() -> dict[str, sp.csr_array]:
    roll = make_swiss_roll(600, random_state=2)[0]
    hops = neighbour_graph(roll, neighbors="knn", n_neighbors=7)
    hops.data = np.ones_like(hops.data)
    twins = np.r_[roll[:300], roll[:20]]           # coincident points: zero-length edges
    return {
        "knn": neighbour_graph(roll, neighbors="knn", n_neighbors=7),
        "uniform": hops,
        "radius_with_twins": neighbour_graph(twins, neighbors="radius", radius=2.5),
        "blobs": neighbour_graph(DATA["blobs"], neighbors="knn", n_neighbors=6),
    }


@pytest.mark.parametrize("name", ["knn", "uniform", "radius_with_twins", "blobs"])
@pytest.mark.parametrize("ball", [8, 40])
def test_geodesics_from_a_separator_equal_dijkstra_from_every_point(name: str,
                                                                   ball: int) -> None:
    g = _graphs()[name]
    if name == "radius_with_twins":
        assert (g.data == 0).any()
    expected = dijkstra(g, directed=False)
    got = _geodesic_distances(g, patched_from=0, ball=ball)
    np.testing.assert_allclose(got, expected, rtol=1e-12, atol=1e-12)


def test_geodesics_with_components_in_threads(monkeypatch: pytest.MonkeyPatch) -> None:
    # the threaded fill (large graphs only) gives the same bits as the serial one
    g = _graphs()["knn"]
    serial = _geodesic_distances(g, patched_from=0, ball=8)
    monkeypatch.setattr(isomap_module, "block_workers", lambda *_: 2)
    threaded = _geodesic_distances(g, patched_from=0, ball=8)
    np.testing.assert_array_equal(threaded, serial)
    np.testing.assert_allclose(threaded, dijkstra(g, directed=False), rtol=1e-12, atol=1e-12)


def test_min_plus_product_is_exact() -> None:
    rng = np.random.default_rng(3)
    a, b = rng.random((7, 5)), rng.random((5, 11))
    a[2] = np.inf                                           # a row that reaches no boundary
    b[:, 4] = np.inf                                        # a column no boundary reaches
    out = np.empty((7, 11))
    _min_plus(a, b, out)
    np.testing.assert_array_equal(out, np.min(a[:, :, None] + b[None], axis=1))
    assert np.isinf(out[2]).all() and np.isinf(out[:, 4]).all()


def test_geodesics_when_no_patch_pays_off(monkeypatch: pytest.MonkeyPatch) -> None:
    g = _graphs()["knn"]
    monkeypatch.setattr(isomap_module, "_DERIVE_RATIO", 0.0)  # every point by Dijkstra
    np.testing.assert_allclose(_geodesic_distances(g, patched_from=0, ball=8),
                               dijkstra(g, directed=False), rtol=1e-12, atol=1e-12)


def test_block_krylov_equals_dense_eigendecomposition() -> None:
    rng = np.random.default_rng(3)
    x = rng.normal(size=(500, 6)) * [5, 4, 3, 1, 1, 1]
    d = np.sqrt(((x[:, None] - x[None]) ** 2).sum(-1))
    squared = (d + rng.uniform(0, 0.5, d.shape) * (d > 0)) ** 2  # not Euclidean: B < 0 too
    squared = 0.5 * (squared + squared.T)
    np.fill_diagonal(squared, 0.0)
    n = squared.shape[0]
    j = np.eye(n) - 1.0 / n
    w, u = la.eigh(-0.5 * j @ squared @ j)
    assert w[0] < -1.0                             # negative eigenvalues are present
    for k in (1, 3, 20, 100):                      # 100: ARPACK on the explicit matrix
        y, eigenvalues = _principal_coordinates(squared, k)
        np.testing.assert_allclose(eigenvalues, w[::-1][:k], rtol=1e-10)
        top = u[:, ::-1][:, :k]
        top = top * np.sign(top[np.argmax(np.abs(top), axis=0), np.arange(k)])
        np.testing.assert_allclose(y, top * np.sqrt(w[::-1][:k]), atol=1e-8)
        assert np.all(np.abs(y.sum(axis=0)) < 1e-8)  # centred


def test_patched_path_equals_scikit_learn_at_1000_points() -> None:
    x = make_swiss_roll(1000, random_state=4)[0]
    res = isomap(x, n_neighbors=10)
    sk = Isomap(n_neighbors=10).fit(x)
    assert procrustes(res.embedding, sk.embedding_)[2] < 1e-6
    np.testing.assert_allclose(res.eigenvalues, sk.kernel_pca_.eigenvalues_, rtol=1e-8)
    assert res.trustworthiness == sk_trustworthiness(x, res.embedding, n_neighbors=5)
