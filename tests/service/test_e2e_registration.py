"""registration.icp over HTTP against a live server: it runs its example, runs as a job
with progress (it is a long process: asynchronous without a preference), reports a
non-overlapping pair as converged=false with a reason (never a silent identity), and every
input error is a 422 problem+json naming the input."""

from __future__ import annotations

import time

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from tests.live import example, execute

pytestmark = pytest.mark.e2e

NAN = float("nan")
CUBE = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]
FLAT = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [2, 1, 0], [1, 2, 0], [3, 0, 0]]


def _cloud(n: int = 200, seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return rng.gamma(2.0, size=(n, 3)) * [1.0, 0.6, 0.3]   # skewed, no symmetry


def test_icp_solves_its_example(http) -> None:
    given = example(http, "registration.icp")
    r = execute(http, "registration.icp", {k: given[k] for k in ("source", "target")})
    assert r.status_code == 200, r.text
    doc = r.json()
    c, s = np.cos(np.radians(10.0)), np.sin(np.radians(10.0))
    np.testing.assert_allclose(doc["rotation"], [[c, -s, 0], [s, c, 0], [0, 0, 1]], atol=1e-9)
    np.testing.assert_allclose(doc["translation"], [0.1, 0, 0], atol=1e-9)
    assert doc["converged"] is True and doc["fitness"] == 1.0 and doc["scale"] == 1.0
    assert len(doc["rmse_history"]) == doc["iterations"]


def test_icp_options_over_http(http) -> None:
    src = _cloud()
    truth = Rotation.from_rotvec([0.1, 0.2, -0.1]).as_matrix()
    dst = 1.5 * src @ truth.T + [0.2, 0.0, 0.1]
    r = execute(http, "registration.icp", {"source": src.tolist(), "target": dst.tolist(),
                                           "model": "similarity", "init": "pca",
                                           "max_iterations": 50})
    assert r.status_code == 200, r.text
    doc = r.json()
    assert doc["scale"] == pytest.approx(1.5, rel=1e-6)
    np.testing.assert_allclose(doc["rotation"], truth, atol=1e-6)
    r = execute(http, "registration.icp", {"source": src.tolist(), "target": dst.tolist(),
                                           "model": "affine", "metric": "point_to_plane",
                                           "init": "pca", "max_iterations": 50})
    assert r.status_code == 200, r.text
    assert r.json()["rotation"] is None and r.json()["scale"] is None


def test_icp_runs_as_a_job_with_progress(http) -> None:
    src = _cloud(300, 1)
    dst = src @ Rotation.from_rotvec([0, 0, 0.3]).as_matrix().T
    r = execute(http, "registration.icp", {"source": src.tolist(), "target": dst.tolist(),
                                           "max_iterations": 5, "tolerance": 0},
                prefer=None)  # no preference: long → async
    assert r.status_code == 201, r.text
    job = r.headers["Location"]
    for _ in range(600):
        status = http.get(job).json()
        if status["status"] in ("successful", "failed", "dismissed"):
            break
        time.sleep(0.05)
    assert status["status"] == "successful", status
    assert status["progress"] == 100
    doc = http.get(f"{job}/results").json()
    assert 1 <= doc["iterations"] <= 5


def test_no_overlap_is_reported_not_hidden(http) -> None:
    r = execute(http, "registration.icp", {"source": CUBE,
                                           "target": (np.array(CUBE) + 50.0).tolist(),
                                           "max_correspondence_distance": 1.0})
    assert r.status_code == 200, r.text
    doc = r.json()
    assert doc["converged"] is False and "no source point" in doc["reason"]
    assert doc["fitness"] == 0.0 and doc["rmse"] == 0.0


@pytest.mark.parametrize("inputs, field, fragment", [
    ({"source": CUBE[:2], "target": CUBE}, "source", "at least 3"),
    ({"source": CUBE, "target": [[0, 0], [1, 1], [2, 0]]}, "target", "same dimension"),
    ({"source": FLAT, "target": FLAT, "metric": "point_to_plane"}, "target", "coplanar"),
    ({"source": [[0, 0], [1, 0], [0, 1]], "target": [[0, 0], [1, 0], [0, 1]],
      "metric": "point_to_plane"}, "metric", "3-D"),
    ({"source": CUBE, "target": CUBE, "metric": "symmetric", "model": "affine"}, "model",
     "rigid"),
    ({"source": CUBE, "target": CUBE, "init": "random"}, "init", ""),
    ({"source": CUBE, "target": CUBE, "init": [[1, 0], [0, 1]]}, "init", "(4, 4)"),
    ({"source": CUBE, "target": CUBE, "overlap": 0}, "overlap", ""),
    ({"source": CUBE, "target": CUBE, "max_correspondence_distance": -1},
     "max_correspondence_distance", ""),
    ({"source": CUBE, "target": CUBE, "kernel": "cauchy"}, "kernel", ""),
    ({"source": FLAT, "target": FLAT, "metric": "point_to_plane",
      "target_normals": [[0, 0, 1]] * 3}, "target_normals", "one normal per"),
    ({"source": [[0, 0, 0], [1, NAN, 0], [0, 1, 0], [0, 0, 1]], "target": CUBE}, "source",
     "row 1"),
])
def test_invalid_inputs_are_422_naming_the_input(http, inputs, field, fragment) -> None:
    r = execute(http, "registration.icp", inputs)
    assert r.status_code == 422, r.text
    assert r.headers["content-type"] == "application/problem+json"
    body = r.json()
    assert body["status"] == 422
    assert body["errors"][0]["input"] == field, body
    assert fragment in body["errors"][0]["message"], body


def test_icp_is_listed(http) -> None:
    ids = {p["id"] for p in http.get("/processes").json()["processes"]}
    assert "registration.icp" in ids
    desc = http.get("/processes/registration.icp").json()
    assert desc["inputs"]["metric"]["schema"]["enum"] == ["point_to_point", "point_to_plane",
                                                          "symmetric"]
    assert {"transform", "rotation", "scale", "translation", "rmse", "fitness", "iterations",
            "converged", "reason", "rmse_history"} <= set(desc["outputs"])
