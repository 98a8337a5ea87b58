"""No silent acceptance (issue 17.9): inputs that cannot mean what they say are refused over
HTTP with a 422 problem naming the input, where the peer libraries refuse them too; where a
peer accepts them, the service answers as the peer does.

Peers: scikit-learn's ``MDS``/``ClassicalMDS`` and scipy's ``squareform`` refuse an
asymmetric distance matrix; scikit-learn's ``PCA`` refuses more components than
``min(n_samples, n_features)``, its ``LinearDiscriminantAnalysis`` more than
``min(n_classes - 1, n_features)``; its ``TSNE`` embeds in any dimension.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from scipy.spatial.distance import squareform
from sklearn.decomposition import PCA
from sklearn.manifold import (
    TSNE,
    ClassicalMDS,
    Isomap,
    LocallyLinearEmbedding,
    SpectralEmbedding,
)

from tests.live import execute

pytestmark = pytest.mark.e2e

# a 3-4-5 right triangle, its distances
D = [[0, 3, 4], [3, 0, 5], [4, 5, 0]]
ASYMMETRIC = [[0, 3, 4], [3.5, 0, 5], [4, 5, 0]]   # d[1, 0] != d[0, 1]
DIAGONAL = [[0, 3, 4], [3, 0.5, 5], [4, 5, 0]]     # a point 0.5 away from itself
POINTS = [[0.0, 0.0], [1.0, 0.2], [0.3, 1.0], [1.2, 1.1], [0.5, 0.4], [2.0, 0.1]]


def _refused(r: Any, field: str) -> dict[str, Any]:
    assert r.status_code == 422, r.text
    assert r.headers["content-type"] == "application/problem+json"
    problem: dict[str, Any] = r.json()
    assert problem["type"] == "/problems/invalid-input", problem
    names = [e.get("input", "") for e in problem.get("errors", [])]
    assert names and names[0] == field, problem
    return problem


def test_peers_refuse_an_asymmetric_matrix() -> None:
    """What the service is held to: the peers on the same matrix."""
    with pytest.raises(ValueError, match="symmetric"):
        ClassicalMDS(n_components=2, metric="precomputed").fit(np.array(ASYMMETRIC))
    with pytest.raises(ValueError, match="symmetric"):
        squareform(np.array(ASYMMETRIC))
    with pytest.raises(ValueError, match="diagonal"):
        squareform(np.array(DIAGONAL))


@pytest.mark.parametrize("process", ["layout.mds", "layout.stress"])
def test_asymmetric_distances_are_refused(http, process: str) -> None:
    problem = _refused(execute(http, process, {"distances": ASYMMETRIC}), "distances")
    assert "symmetric" in problem["detail"] and "row 1, column 0" in problem["detail"]
    assert execute(http, process, {"distances": D}).status_code == 200  # the same, symmetric


@pytest.mark.parametrize("process", ["layout.mds", "layout.stress"])
def test_a_nonzero_diagonal_is_refused(http, process: str) -> None:
    problem = _refused(execute(http, process, {"distances": DIAGONAL}), "distances")
    assert "diagonal" in problem["detail"] and "row 1, column 1" in problem["detail"]


def test_a_pair_given_twice_with_two_distances_is_refused(http) -> None:
    pairs = [[0, 1, 3.0], [1, 0, 3.5], [0, 2, 4.0], [1, 2, 5.0]]
    problem = _refused(execute(http, "layout.mds", {"distance_pairs": pairs}), "distance_pairs")
    assert "one distance" in problem["detail"]
    pairs[1][2] = 3.0  # listed twice with one distance: fine
    assert execute(http, "layout.mds", {"distance_pairs": pairs}).status_code == 200


@pytest.mark.parametrize("process, inputs", [
    ("embedding.pca", {"points": POINTS, "n_components": 3}),          # > dimension 2
    ("embedding.lpp", {"points": POINTS, "n_components": 3, "n_neighbors": 3}),
    ("embedding.random_projection", {"points": POINTS, "n_components": 3}),
    ("embedding.mds", {"points": POINTS, "n_components": 7}),          # > 6 points
    ("embedding.isomap", {"points": POINTS, "n_components": 7, "n_neighbors": 3}),
    ("embedding.lle", {"points": POINTS, "n_components": 5, "n_neighbors": 3}),  # > n - 2
    ("embedding.lle", {"points": POINTS, "n_components": 3, "n_neighbors": 3}),  # > D
    ("embedding.laplacian_eigenmaps", {"points": POINTS, "n_components": 5,
                                       "n_neighbors": 3}),
    ("layout.mds", {"distances": D, "n_components": 4}),               # > 3 points
    ("layout.stress", {"distances": D, "n_components": 4}),
    ("classification.lda", {"points": POINTS, "labels": [0, 0, 0, 1, 1, 1],
                            "n_components": 2}),                        # > classes - 1
    ("classification.nca", {"points": POINTS, "labels": [0, 0, 0, 1, 1, 1],
                            "n_components": 3}),                        # > dimension
])
def test_more_components_than_the_method_can_produce_are_refused(http, process: str,
                                                                  inputs: dict) -> None:
    problem = _refused(execute(http, process, inputs), "n_components")
    assert f"got {inputs['n_components']}" in problem["detail"]


def test_pca_refuses_as_scikit_learn_does(http) -> None:
    with pytest.raises(ValueError, match="n_components=3"):
        PCA(n_components=3).fit(np.array(POINTS))
    _refused(execute(http, "embedding.pca", {"points": POINTS, "n_components": 3}),
             "n_components")


def test_lle_refuses_more_components_than_dimensions_as_scikit_learn_does(http) -> None:
    with pytest.raises(ValueError, match="output dimension"):
        LocallyLinearEmbedding(n_neighbors=3, n_components=3).fit(np.array(POINTS))
    problem = _refused(execute(http, "embedding.lle", {"points": POINTS, "n_components": 3,
                                                       "n_neighbors": 3}), "n_components")
    assert "the dimension of `points`" in problem["detail"]


@pytest.mark.parametrize("process", ["embedding.mds", "embedding.isomap",
                                     "embedding.laplacian_eigenmaps"])
def test_more_components_than_dimensions_where_peers_accept_them(http, process: str) -> None:
    """scikit-learn's ClassicalMDS, Isomap and SpectralEmbedding embed 2-D points in 3-D;
    so does the service (classical MDS's third column is zero: the points span 2)."""
    x = np.array(POINTS)
    peers = {"embedding.mds": ClassicalMDS(n_components=3),
             "embedding.isomap": Isomap(n_neighbors=3, n_components=3),
             "embedding.laplacian_eigenmaps": SpectralEmbedding(n_components=3,
                                                                n_neighbors=3)}
    assert peers[process].fit_transform(x).shape == (6, 3)
    r = execute(http, process, {"points": POINTS, "n_components": 3, "n_neighbors": 3}
                if process != "embedding.mds" else {"points": POINTS, "n_components": 3})
    assert r.status_code == 200, r.text
    y = np.asarray(r.json()["embedding"])
    assert y.shape == (6, 3)
    if process == "embedding.mds":
        # the third eigenvalue is 0 up to rounding, its column sqrt(0 + 1e-16)-small
        np.testing.assert_allclose(y[:, 2], 0, atol=1e-6)
        peer = ClassicalMDS(n_components=3).fit_transform(x)
        np.testing.assert_allclose(np.abs(y[:, :2]), np.abs(peer[:, :2]), atol=1e-9)


def test_tsne_embeds_in_more_dimensions_than_the_data_as_scikit_learn_does(http) -> None:
    """t-SNE's embedding dimension is free (the peer accepts 3 for 2-D data)."""
    x = np.array(POINTS * 2) + np.repeat([[0.0], [0.01]], 6, axis=0)
    peer = TSNE(n_components=3, perplexity=3.0, method="exact", random_state=0,
                init="random").fit_transform(x)
    assert peer.shape == (12, 3)
    r = execute(http, "embedding.tsne", {"points": x.tolist(), "n_components": 3,
                                         "perplexity": 3.0, "max_iterations": 300,
                                         "exaggeration_iterations": 100})
    assert r.status_code == 200, r.text
    assert np.asarray(r.json()["embedding"]).shape == (12, 3)


def test_density_without_sparse_matrix_is_refused(http) -> None:
    inputs = {"points": POINTS, "kind": "gaussian", "density": 0.5}
    _refused(execute(http, "embedding.random_projection", inputs), "density")


@pytest.mark.parametrize("mode", ["fast", 3, ""])
def test_an_unknown_mode_is_refused(http, mode: Any) -> None:
    r = execute(http, "alignment.rigid", {"source": D, "target": D}, mode=mode)
    assert r.status_code == 422, r.text
    problem = r.json()
    assert problem["type"] == "/problems/invalid-input"
    assert [e.get("input") for e in problem["errors"]][0] == "mode"
