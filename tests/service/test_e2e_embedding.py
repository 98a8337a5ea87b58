"""The embedding methods (PCA, MDS, random projection, Isomap, Laplacian eigenmaps, LPP, LLE)
over HTTP against a live server: each runs on a small input and agrees with the library
call; bad inputs (fewer points than neighbours, n_components above the dimension, unknown
options, NaN) and a disconnected graph are 4xx problem+json naming the input."""

from __future__ import annotations

import json
from typing import Any

import numpy as np
import pytest
from sklearn.datasets import make_swiss_roll

from algorithms import embedding
from tests.live import execute

pytestmark = pytest.mark.e2e

NAN = float("nan")
ROLL = make_swiss_roll(60, random_state=0)[0]
POINTS = ROLL.tolist()
TWO_CLUMPS = np.r_[ROLL[:10] * 0.01, ROLL[:10] * 0.01 + 100].tolist()


@pytest.mark.parametrize("method, inputs", [
    ("pca", {}),
    ("mds", {}),
    ("mds", {"metric": True}),
    ("random_projection", {"seed": 3}),
    ("random_projection", {"kind": "sparse", "density": 0.5}),
    ("isomap", {"n_neighbors": 8}),
    ("laplacian_eigenmaps", {"n_neighbors": 8, "weighting": "heat"}),
    ("lpp", {"n_neighbors": 8, "laplacian": "symmetric"}),
    ("lle", {"n_neighbors": 8}),
])
def test_methods_agree_with_the_library(http, method: str, inputs: dict[str, Any]) -> None:
    r = execute(http, f"embedding.{method}", {"points": POINTS, **inputs})
    assert r.status_code == 200, r.text
    doc = r.json()
    expected = getattr(embedding, method)(ROLL, **inputs)
    np.testing.assert_allclose(doc["embedding"], expected.embedding, atol=1e-8)
    assert doc["trustworthiness"] == pytest.approx(expected.trustworthiness)
    assert np.shape(doc["embedding"]) == (60, 2)


@pytest.mark.parametrize("method, inputs, field, fragment", [
    ("isomap", {"points": POINTS[:5], "n_neighbors": 5}, "n_neighbors", "<= 4, at most"),
    ("lle", {"points": POINTS[:5], "n_neighbors": 7}, "n_neighbors", "minus one"),
    ("laplacian_eigenmaps", {"points": POINTS[:4], "n_neighbors": 4}, "n_neighbors",
     "minus one"),
    ("lpp", {"points": POINTS, "n_neighbors": 60}, "n_neighbors", "minus one"),
    ("pca", {"points": POINTS, "n_components": 4}, "n_components", "dimension"),
    ("random_projection", {"points": POINTS, "n_components": 5}, "n_components", "dimension"),
    ("lpp", {"points": POINTS, "n_components": 4}, "n_components", "dimension"),
    ("mds", {"points": POINTS[:3], "n_components": 4}, "n_components", "number of"),
    ("isomap", {"points": POINTS, "neighbors": "radius"}, "radius", "radius"),
    ("isomap", {"points": POINTS, "weighting": "heat"}, "weighting", ""),
    ("lle", {"points": POINTS, "neighbors": "all"}, "neighbors", ""),
    ("pca", {"points": [[0, 0], [1, NAN], [2, 2]]}, "points", "row 1"),
    ("random_projection", {"points": POINTS, "density": 0.5}, "density", "sparse"),
])
def test_invalid_inputs_are_422_naming_the_input(http, method, inputs, field, fragment) -> None:
    r = execute(http, f"embedding.{method}", inputs)
    assert r.status_code == 422, r.text
    assert r.headers["content-type"] == "application/problem+json"
    body = r.json()
    assert body["errors"][0]["input"] == field, body
    assert fragment in body["errors"][0]["message"], body


@pytest.mark.parametrize("method", ["isomap", "laplacian_eigenmaps", "lle", "lpp"])
def test_disconnected_graph_is_a_problem_naming_the_components(http, method: str) -> None:
    r = execute(http, f"embedding.{method}", {"points": TWO_CLUMPS, "n_neighbors": 3})
    assert 400 <= r.status_code < 500, r.text
    body = r.json()
    assert r.headers["content-type"] == "application/problem+json"
    text = json.dumps(body)
    assert "2 connected components" in text and "n_neighbors" in text


def test_every_embedding_method_is_listed(http) -> None:
    ids = {p["id"] for p in http.get("/processes").json()["processes"]}
    assert {f"embedding.{m}" for m in ("pca", "mds", "random_projection", "isomap",
                                       "laplacian_eigenmaps", "lpp", "lle")} <= ids
    desc = http.get("/processes/embedding.laplacian_eigenmaps").json()
    assert desc["inputs"]["neighbors"]["schema"]["enum"] == ["knn", "radius", "all"]
    assert {"embedding", "eigenvalues", "trustworthiness"} <= set(desc["outputs"])
    assert "reconstruction_error" in http.get("/processes/embedding.lle").json()["outputs"]
    assert "stress" in http.get("/processes/embedding.mds").json()["outputs"]
