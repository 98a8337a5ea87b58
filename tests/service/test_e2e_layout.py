"""The layout processes over HTTP against a live server: one run of each on a hand-checked
input, a long stress majorization that reports progress and is dismissed while running,
and every input error as a 422 problem+json naming the input."""

from __future__ import annotations

import time

import numpy as np
import pytest

from tests.live import execute, wait_for_status

pytestmark = pytest.mark.e2e

NAN, INF = float("nan"), float("inf")
SQUARE = {"vertices": [[0, 0], [1, 0], [1, 1], [0, 1], [0.5, 0.5]],
          "faces": [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]}
PATH = {"nodes": 3, "edges": [[0, 1], [1, 2]]}
PIN = {"indices": [0], "positions": [[0.0, 0.0]]}
TRIANGLE = [[0, 3, 4], [3, 0, 5], [4, 5, 0]]
LINE = [[0, 1, 2], [1, 0, 1], [2, 1, 0]]


def _pairwise(x: np.ndarray) -> np.ndarray:
    return np.linalg.norm(x[:, None] - x[None], axis=-1)


# -- one run of each -------------------------------------------------------------------------
def test_tutte_layout_over_http(http) -> None:
    r = execute(http, "layout.laplacian", {"mesh": SQUARE, "weighting": "tangent"})
    assert r.status_code == 200, r.text
    doc = r.json()
    np.testing.assert_allclose(doc["positions"], [[1, 0], [0, 1], [-1, 0], [0, -1], [0, 0]],
                               atol=1e-14)
    assert doc["pinned"] == [0, 1, 2, 3]
    assert doc["flipped_faces"] == 0 and doc["degenerate_faces"] == 0


def test_graph_layout_with_pins_over_http(http) -> None:
    g = {**PATH, "weights": [1.0, 3.0]}
    r = execute(http, "layout.laplacian", {"graph": g, "pins": {"indices": [0, 2],
                                                                "positions": [[0, 0], [4, 8]]}})
    assert r.status_code == 200, r.text
    np.testing.assert_allclose(r.json()["positions"], [[0, 0], [3, 6], [4, 8]], atol=1e-14)
    assert r.json()["energy"] == pytest.approx(60.0, rel=1e-13)


def test_poisson_over_http(http) -> None:
    r = execute(http, "layout.poisson", {"graph": PATH, "vectors": [[-1, 0], [-1, 0]],
                                         "anchors": PIN, "anchor_weights": [2.0]})
    assert r.status_code == 200, r.text
    doc = r.json()
    np.testing.assert_allclose(doc["positions"], [[0, 0], [1, 0], [2, 0]], atol=1e-13)
    assert doc["edge_rmse"] < 1e-12 and doc["free_components"] == 0


def test_mds_over_http_with_missing_distances(http) -> None:
    r = execute(http, "layout.mds", {"distances": TRIANGLE})
    assert r.status_code == 200, r.text
    np.testing.assert_allclose(_pairwise(np.array(r.json()["positions"])), TRIANGLE, atol=1e-12)
    # 30 points, about a fifth of the pairs unknown (null): completed
    rng = np.random.default_rng(0)
    x = rng.standard_normal((30, 2))
    full = _pairwise(x)
    holes = np.triu(rng.random(full.shape) < 0.2, 1)
    d = [[None if (holes[i, j] or holes[j, i]) else float(full[i, j]) for j in range(30)]
         for i in range(30)]
    r = execute(http, "layout.mds", {"distances": d})
    assert r.status_code == 200, r.text
    doc = r.json()
    assert doc["missing_pairs"] == int(holes.sum()) and doc["converged"] is True
    np.testing.assert_allclose(_pairwise(np.array(doc["positions"])), full, atol=1e-4)
    # the same as a list of known pairs
    pairs = [[i, j, float(full[i, j])] for i in range(30) for j in range(i + 1, 30)
             if not holes[i, j]]
    r2 = execute(http, "layout.mds", {"distance_pairs": pairs})
    assert r2.status_code == 200, r2.text
    np.testing.assert_allclose(r2.json()["positions"], doc["positions"], atol=1e-9)


def test_stress_over_http(http) -> None:
    r = execute(http, "layout.stress", {"distances": LINE, "n_components": 1})
    assert r.status_code == 200, r.text
    doc = r.json()
    assert np.sort(np.ravel(doc["positions"])) == pytest.approx([-1, 0, 1], abs=1e-9)
    assert doc["stress"] < 1e-18 and doc["converged"] is True
    assert len(doc["stress_history"]) == doc["iterations"] + 1
    g = {"nodes": 9, "edges": [[i, i + 1] for i in range(8)]}
    r = execute(http, "layout.stress", {"graph": g, "weighting": "uniform", "init": "random",
                                        "seed": 1})
    assert r.status_code == 200, r.text
    hist = r.json()["stress_history"]
    assert all(b <= a * (1 + 1e-12) for a, b in zip(hist, hist[1:], strict=False))


def test_long_stress_reports_progress_and_is_dismissed(http) -> None:
    n = 40  # a 40×40 grid graph: 1,600 nodes, shortest paths computed by the worker
    edges = [[i * n + j, i * n + j + 1] for i in range(n) for j in range(n - 1)]
    edges += [[i * n + j, (i + 1) * n + j] for i in range(n - 1) for j in range(n)]
    r = execute(http, "layout.stress", {"graph": {"nodes": n * n, "edges": edges}, "init": "random",
                                        "max_iterations": 100000, "tolerance": 0.0},
                prefer="respond-async")
    assert r.status_code == 201, r.text
    job = r.json()["jobID"]
    wait_for_status(http, job, ("running",), timeout=60)
    deadline = time.monotonic() + 60
    info = http.get(f"/jobs/{job}").json()
    while time.monotonic() < deadline and not (info["message"] or "").startswith("stress"):
        time.sleep(0.2)
        info = http.get(f"/jobs/{job}").json()
    assert info["status"] == "running" and info["message"].startswith("stress"), info
    r = http.delete(f"/jobs/{job}")
    assert r.status_code == 200 and r.json()["status"] == "dismissed"
    assert wait_for_status(http, job)["status"] == "dismissed"


def test_every_layout_method_is_listed(http) -> None:
    ids = {p["id"] for p in http.get("/processes").json()["processes"]}
    assert {f"layout.{m}" for m in ("laplacian", "poisson", "mds", "stress")} <= ids
    desc = http.get("/processes/layout.stress").json()
    assert desc["inputs"]["weighting"]["schema"]["enum"] == ["inverse_square", "inverse",
                                                             "uniform"]
    assert {"positions", "stress", "stress_history", "iterations"} <= set(desc["outputs"])


# -- errors ----------------------------------------------------------------------------------
@pytest.mark.parametrize("method, inputs, field, fragment", [
    # edges out of range, self-loops, bad weights, bad structure
    ("laplacian", {"graph": {"nodes": 3, "edges": [[0, 1], [1, 3]]}, "pins": PIN},
     "graph.edges", "below 3, got 3 at row 1"),
    ("laplacian", {"graph": {"nodes": 3, "edges": [[0, 1], [1, 1]]}, "pins": PIN},
     "graph.edges", "two distinct nodes"),
    ("laplacian", {"graph": {"nodes": 3, "edges": [[0, 1], [1, 2]], "weights": [1, -2]},
                   "pins": PIN}, "graph.weights", "non-negative"),
    ("laplacian", {"graph": {"nodes": 3, "links": []}, "pins": PIN}, "graph", "'edges'"),
    ("laplacian", {"graph": PATH}, "pins", "Expected `pins` with a `graph`"),
    ("laplacian", {}, "mesh", "exactly one of `mesh` and `graph`, got none"),
    ("laplacian", {"mesh": SQUARE, "graph": PATH}, "graph", "got `mesh` and `graph`"),
    # pins missing for a component (found by the worker), out of range, NaN
    ("laplacian", {"graph": {"nodes": 4, "edges": [[0, 1], [2, 3]]}, "pins": PIN}, "pins",
     "component of 2 vertices"),
    ("laplacian", {"mesh": {"vertices": [[0, 0], [1, 0], [0, 1], [5, 0], [6, 0], [5, 1]],
                            "faces": [[0, 1, 2], [3, 4, 5]]}}, "mesh", "component of 3"),
    ("laplacian", {"graph": PATH, "pins": {"indices": [7], "positions": [[0, 0]]}},
     "pins.indices", "below 3"),
    ("laplacian", {"graph": PATH, "pins": {"indices": [0], "positions": [[0, NAN]]}},
     "pins.positions", "nan at row 0"),
    ("laplacian", {"mesh": {"vertices": SQUARE["vertices"], "faces": [[0, 1, 9]]}},
     "mesh.faces", "below 5"),
    ("laplacian", {"mesh": {"vertices": [[0, 0], [1, 0], [2, 0]], "faces": [[0, 1, 2]]}},
     "mesh.faces", "zero-area"),
    ("laplacian", {"graph": PATH, "pins": PIN, "weighting": "cotangent"}, "weighting",
     "need a mesh"),
    ("laplacian", {"mesh": SQUARE, "weighting": "mean"}, "weighting", ""),
    # poisson
    ("poisson", {"graph": PATH, "vectors": [[1, 0]]}, "vectors", "one row per edge"),
    ("poisson", {"graph": PATH, "vectors": [[1, 0], [1, INF]]}, "vectors", "inf at row 1"),
    ("poisson", {"graph": PATH, "vectors": [[1, 0], [1, 0]],
                 "anchors": {"indices": [0], "positions": [[0, 0, 0]]}}, "anchors.positions",
     "dimension of `vectors`"),
    ("poisson", {"graph": PATH, "vectors": [[1, 0], [1, 0]], "anchor_weights": [1.0]},
     "anchor_weights", "only together with `anchors`"),
    # distance matrices: non-square, negative, NaN where not allowed, structure
    ("mds", {"distances": [[0, 1, 2], [1, 0, 3]]}, "distances", "square"),
    ("mds", {"distances": [[0, -1], [-1, 0]]}, "distances", "non-negative distances, got -1.0"),
    ("mds", {"distances": [[0, 1], [1, INF]]}, "distances", "finite numbers, got inf"),
    ("mds", {"distances": [[0, 1, 2], [1, 0.5, 1], [2, 1, 0]]}, "distances", "diagonal"),
    ("mds", {"distances": [[0, None, None], [None, 0, 1], [None, 1, 0]]}, "distances",
     "got none for point 0"),
    ("mds", {"distance_pairs": [[0, 1, NAN], [1, 2, 1]]}, "distance_pairs", "nan at row 0"),
    ("mds", {"distance_pairs": [[0, 1, -1.0]]}, "distance_pairs", "non-negative"),
    ("mds", {"distance_pairs": [[0, 4, 1.0]], "n_points": 3}, "distance_pairs", "below 3"),
    ("mds", {"distance_pairs": [[0, 1, 1.0], [2, 3, 1.0]]}, "distance_pairs", "2 groups"),
    ("mds", {"distances": TRIANGLE, "n_points": 3}, "n_points", "only together"),
    ("mds", {"distances": TRIANGLE, "n_components": 4}, "n_components",
     "<= 3 (the number of points)"),
    ("mds", {}, "distances", "exactly one of"),
    ("mds", {"graph": {"nodes": 4, "edges": [[0, 1], [2, 3]]}}, "graph", "2 components"),
    ("stress", {"distances": [[0, 0, 1], [0, 0, 1], [1, 1, 0]]}, "distances",
     "weighting='uniform'"),
    ("stress", {"distances": LINE, "initial_positions": [[0, 0], [1, 1]]},
     "initial_positions", "one row per point"),
    ("stress", {"distances": LINE, "initial_positions": [[0, 0, 0]] * 3},
     "initial_positions", "an (n, 2) array"),
    ("stress", {"distances": LINE, "relaxation": 2.0}, "relaxation", ""),
    ("stress", {"distances": [[0, "x"], ["x", 0]]}, "distances", ""),
])
def test_invalid_inputs_are_422_naming_the_input(http, method, inputs, field, fragment) -> None:
    r = execute(http, f"layout.{method}", inputs)
    assert r.status_code == 422, r.text
    assert r.headers["content-type"] == "application/problem+json"
    body = r.json()
    assert body["type"] == "/problems/invalid-input" and body["status"] == 422
    assert body["errors"][0]["input"] == field, body
    assert fragment in body["errors"][0]["message"], body
