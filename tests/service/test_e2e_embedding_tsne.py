"""t-SNE and SNE over HTTP against a live server: each runs on a small input and agrees with
the library call bit for bit (same seed); bad inputs (perplexity ≥ n, the FFT gradient in
3 dimensions, too many points for SNE, unknown options) are 422 problem+json naming the
input; both are listed with their outputs."""

from __future__ import annotations

import numpy as np
import pytest
from sklearn.datasets import make_blobs

from algorithms.embedding import sne, tsne
from tests.live import execute

pytestmark = pytest.mark.e2e

BLOBS = make_blobs(60, n_features=5, centers=3, random_state=0)[0]
POINTS = BLOBS.tolist()
FAST = {"perplexity": 8, "max_iterations": 120, "exaggeration_iterations": 50}


@pytest.mark.parametrize("method, function, inputs", [
    ("tsne", tsne, {}),
    ("tsne", tsne, {"method": "fft", "init": "random", "seed": 2}),
    ("tsne", tsne, {"n_components": 1, "learning_rate": 20.0}),
    ("sne", sne, {}),
])
def test_methods_agree_with_the_library(http, method, function, inputs) -> None:  # noqa: ANN001
    r = execute(http, f"embedding.{method}", {"points": POINTS, **FAST, **inputs})
    assert r.status_code == 200, r.text
    doc = r.json()
    expected = function(BLOBS, **FAST, **inputs)
    np.testing.assert_allclose(doc["embedding"], expected.embedding, atol=1e-12)
    assert doc["kl_divergence"] == pytest.approx(expected.kl_divergence)
    assert doc["trustworthiness"] == pytest.approx(expected.trustworthiness)
    assert doc["iterations"] == expected.iterations == 120
    assert np.shape(doc["embedding"]) == (60, inputs.get("n_components", 2))


@pytest.mark.parametrize("method, inputs, field, fragment", [
    ("tsne", {"points": POINTS[:10]}, "perplexity", "below the number of `points` (10)"),
    ("sne", {"points": POINTS, "perplexity": 60}, "perplexity", "below"),
    ("tsne", {"points": POINTS, "method": "fft", "n_components": 3}, "n_components", "<= 2"),
    ("tsne", {"points": POINTS, "method": "barnes_hut"}, "method", ""),
    ("tsne", {"points": POINTS, "learning_rate": "fast"}, "learning_rate", ""),
    ("tsne", {"points": POINTS, "perplexity": 0}, "perplexity", ""),
    ("sne", {"points": np.zeros((5001, 2)).tolist()}, "points", "5,000"),
    ("tsne", {"points": [[0, 0], [1, float("nan")], [2, 2]], "perplexity": 1}, "points",
     "row 1"),
])
def test_invalid_inputs_are_422_naming_the_input(http, method, inputs, field,  # noqa: ANN001
                                                 fragment) -> None:
    r = execute(http, f"embedding.{method}", inputs)
    assert r.status_code == 422, r.text
    assert r.headers["content-type"] == "application/problem+json"
    body = r.json()
    assert body["errors"][0]["input"] == field, body
    assert fragment in body["errors"][0]["message"], body


def test_tsne_and_sne_are_listed_with_their_outputs(http) -> None:  # noqa: ANN001
    ids = {p["id"] for p in http.get("/processes").json()["processes"]}
    assert {"embedding.tsne", "embedding.sne"} <= ids
    desc = http.get("/processes/embedding.tsne").json()
    assert {"embedding", "kl_divergence", "trustworthiness", "iterations"} <= set(
        desc["outputs"])
    assert desc["inputs"]["method"]["schema"]["enum"] == ["auto", "exact", "fft"]
    assert "kl_divergence" in http.get("/processes/embedding.sne").json()["outputs"]
