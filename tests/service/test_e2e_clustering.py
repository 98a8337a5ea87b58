"""Clustering and classification over HTTP against a live server: each method runs its
example and a planted case, and bad input (labels of the wrong length, fewer points than
neighbours, n_components too large) is a 422 problem+json naming the input."""

from __future__ import annotations

import numpy as np
import pytest

from tests.live import execute

pytestmark = pytest.mark.e2e

GROUPS = [[0, 0], [0, 1], [1, 0], [1, 1], [10, 10], [10, 11], [11, 10], [11, 11]]
LABELS = ["a", "a", "a", "a", "b", "b", "b", "b"]
POINTS = [[0, 0], [1, 0], [0, 1], [1, 1.5], [5, 5], [6, 5], [5, 6], [6.5, 6]]


def test_spectral_and_markov_find_two_groups(http) -> None:
    for process, extra in (("clustering.spectral", {"n_clusters": 2}),
                           ("clustering.markov", {})):
        r = execute(http, process, {"points": GROUPS, "n_neighbors": 3, **extra}, prefer="wait=30")
        assert r.status_code == 200, r.text
        doc = r.json()
        assert doc["labels"] == [0, 0, 0, 0, 1, 1, 1, 1] and doc["sizes"] == [4, 4]


def test_markov_recovers_a_planted_partition(http) -> None:
    rng = np.random.default_rng(0)
    y = np.repeat([0, 1, 2], 20)
    p = np.where(y[:, None] == y[None, :], 0.6, 0.02)
    edges = np.argwhere(np.triu(rng.random(p.shape) < p, 1)).tolist()
    r = execute(http, "clustering.markov", {"graph": {"nodes": 60, "edges": edges}},
                prefer="wait=30")
    assert r.status_code == 200, r.text
    assert r.json()["labels"] == y.tolist()


def test_lda_and_nca_classify_queries(http) -> None:
    for process in ("classification.lda", "classification.nca"):
        r = execute(http, process, {"points": POINTS, "labels": LABELS,
                                    "query": [[0.5, 0.5], [5.5, 5.0]]}, prefer="wait=30")
        assert r.status_code == 200, r.text
        doc = r.json()
        assert doc["query_predictions"] == ["a", "b"], process
        assert len(doc["embedding"]) == 8 and 0 <= doc["trustworthiness"] <= 1


@pytest.mark.parametrize("process, inputs, field, fragment", [
    ("classification.lda", {"points": POINTS, "labels": LABELS[:5]}, "labels",
     "one label per row"),
    ("classification.nca", {"points": POINTS, "labels": LABELS[:3]}, "labels",
     "one label per row"),
    ("classification.lda", {"points": POINTS, "labels": LABELS, "n_components": 2},
     "n_components", "<= 1 (min(classes - 1, dimension)"),
    ("classification.nca", {"points": POINTS, "labels": LABELS, "n_components": 3},
     "n_components", "<= 2 (the dimension of `points`)"),
    ("classification.lda", {"points": POINTS, "labels": ["a"] * 8}, "labels",
     "at least 2 classes"),
    ("classification.lda", {"points": POINTS, "labels": [0, "a"] * 4}, "labels", "mix"),
    ("clustering.spectral", {"points": GROUPS, "n_neighbors": 8}, "n_neighbors",
     "minus one"),
    ("clustering.spectral", {"points": GROUPS, "n_clusters": 9, "n_neighbors": 2},
     "n_clusters", "<= 8 (the number of `points`)"),
    ("clustering.spectral", {"points": GROUPS, "neighbors": "radius"}, "radius", "radius"),
    ("clustering.markov", {"points": GROUPS, "n_neighbors": 20}, "n_neighbors", "minus one"),
    ("clustering.markov", {"n_neighbors": 2}, "points", "exactly one"),
    ("clustering.markov", {"graph": {"nodes": 3, "edges": [[0, 7]]}}, "graph.edges", ""),
])
def test_invalid_inputs_are_422_naming_the_input(http, process, inputs, field,
                                                 fragment) -> None:
    r = execute(http, process, inputs, prefer="wait=30")
    assert r.status_code == 422, r.text
    assert r.headers["content-type"] == "application/problem+json"
    body = r.json()
    assert body["errors"][0]["input"] == field, body
    assert fragment in body["errors"][0]["message"], body
