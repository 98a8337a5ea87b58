"""Class ``labels`` given to an embedding or a clustering, for the display only: the method
does not read them, the GLB colours the points by class (the palette of
:func:`service.gltf.label_colors`), and a clustering's clusters take the colour of the class
they match best."""

from __future__ import annotations

from typing import Any

import httpx
import numpy as np
import pytest
from sklearn.datasets import load_iris

from service.gltf import label_colors, read_glb
from service.scenes import matched_classes
from tests.live import execute

pytestmark = pytest.mark.e2e

IRIS = load_iris()
POINTS = IRIS.data[::5]            # 30 flowers, 10 of each species
SPECIES = IRIS.target_names[IRIS.target[::5]].tolist()


def _glb_colours(http: httpx.Client, process_id: str, inputs: dict[str, Any]) -> tuple[
        np.ndarray, dict[str, Any]]:
    """The per-point colours (RGB) of the result's GLB, and its first node's extras."""
    r = execute(http, process_id, inputs)
    assert r.status_code == 200, r.text
    job = r.headers["content-location"].split("/")[2]
    glb = http.get(f"/jobs/{job}/results", headers={"Accept": "model/gltf-binary"})
    assert glb.status_code == 200 and glb.headers["content-type"] == "model/gltf-binary"
    doc = read_glb(glb.content)
    attributes = doc["json"]["meshes"][0]["primitives"][0]["attributes"]
    colours = np.asarray(doc["accessors"][attributes["COLOR_0"]], dtype=np.float64)
    if colours.max() > 1:           # normalised integers
        colours = colours / 255
    return colours[:, :3], doc["json"]["nodes"][0].get("extras", {})


def test_an_embedding_is_coloured_by_the_labels_given(http: httpx.Client) -> None:
    colours, extras = _glb_colours(http, "embedding.pca",
                                   {"points": POINTS.tolist(), "labels": SPECIES})
    np.testing.assert_allclose(colours, label_colors(SPECIES), atol=1 / 255)
    assert extras["colorBy"] == "labels"
    assert [e["label"] for e in extras["legend"]] == sorted(set(SPECIES))


def test_labels_change_no_number_of_the_result(http: httpx.Client) -> None:
    plain = execute(http, "embedding.pca", {"points": POINTS.tolist()}).json()
    labelled = execute(http, "embedding.pca",
                       {"points": POINTS.tolist(), "labels": SPECIES}).json()
    assert labelled == plain


def test_without_labels_an_embedding_is_coloured_by_index(http: httpx.Client) -> None:
    _, extras = _glb_colours(http, "embedding.pca", {"points": POINTS.tolist()})
    assert extras["colorBy"] == "index"


def test_clusters_take_the_colour_of_the_class_they_match(http: httpx.Client) -> None:
    # two far-apart groups that spectral clustering separates exactly; the classes are named
    # in the opposite order of the cluster numbers it is likely to give
    rng = np.random.default_rng(0)
    points = np.vstack([rng.normal(0, 0.1, (8, 2)), rng.normal(10, 0.1, (8, 2))])
    classes = ["right"] * 8 + ["left"] * 8
    colours, extras = _glb_colours(http, "clustering.spectral", {
        "points": points.tolist(), "n_clusters": 2, "n_neighbors": 4, "labels": classes})
    np.testing.assert_allclose(colours, label_colors(classes), atol=1 / 255)
    assert [e["label"] for e in extras["legend"]] == ["left", "right"]


def test_matched_classes_pairs_clusters_with_the_classes_most_points_share() -> None:
    clusters = np.array([2, 2, 2, 0, 0, 1, 1, 1, 1])
    classes = np.array([7, 7, 5, 5, 5, 9, 9, 9, 5])
    # contingency: cluster 2 ~ class 7 (2 points), cluster 0 ~ class 5 (2), cluster 1 ~ 9 (3)
    np.testing.assert_array_equal(matched_classes(clusters, classes),
                                  [7, 7, 7, 5, 5, 9, 9, 9, 9])
    # more clusters than classes: the cluster left over takes the next free integer
    np.testing.assert_array_equal(matched_classes(np.array([0, 0, 1, 2]), np.array([3, 3, 4, 4])),
                                  [3, 3, 4, 5])
    assert matched_classes(np.array([0, 1, 2]), np.array(["a", "a", "b"])).tolist() in (
        ["a", "b", "cluster 2"], ["a", "cluster 1", "b"])


@pytest.mark.parametrize(("labels", "fragment"), [
    (["setosa"] * 29, "one label per point of `points` (30), got 29"),
    ([0.5] * 30, "flat list of class labels"),
])
def test_labels_that_do_not_fit_are_422_naming_them(http: httpx.Client, labels: list[Any],
                                                    fragment: str) -> None:
    r = execute(http, "embedding.tsne", {"points": POINTS.tolist(), "labels": labels,
                                         "perplexity": 5})
    assert r.status_code == 422, r.text
    problem = r.json()
    assert problem["type"].endswith("/invalid-input")
    assert problem["errors"][0]["input"] == "labels"
    assert fragment in problem["errors"][0]["message"]


def test_labels_are_offered_where_they_are_shown_and_nowhere_else(http: httpx.Client) -> None:
    for process_id in ("embedding.tsne", "embedding.pca", "clustering.spectral",
                       "clustering.markov", "classification.lda"):
        inputs = http.get(f"/processes/{process_id}").json()["inputs"]
        assert "labels" in inputs, process_id
    for process_id in ("registration.icp", "layout.mds", "alignment.rigid"):
        assert "labels" not in http.get(f"/processes/{process_id}").json()["inputs"]
