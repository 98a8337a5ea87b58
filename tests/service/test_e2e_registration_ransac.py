"""registration.ransac over HTTP against a live server: it solves its example (a 120° turn
no local method finds), runs as a job with progress (long: asynchronous without a
preference), gives the same bits for the same seed, reports a failure as converged=false
with a reason, and every input error is a 422 problem+json naming the input."""

from __future__ import annotations

import time
from typing import Any

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from tests.live import example, execute

pytestmark = pytest.mark.e2e

NAN = float("nan")
SIX = [[0, 0, 0], [2, 0, 0], [0, 1, 0], [0, 0, 0.5], [1, 1, 0.2], [0.5, 0.2, 0.4]]
LINE = [[k, 2 * k, 0] for k in range(8)]


def _blob(n: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    u = rng.standard_normal((n, 3))
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    x, y, z = u.T
    r = 1.0 + 0.3 * x + 0.15 * y * z + 0.2 * x * y + 0.1 * z ** 3 + 0.12 * y
    return u * r[:, None] * [1.3, 1.0, 0.8]


def _angle(a: Any, b: np.ndarray) -> float:
    c = (np.trace(np.asarray(a) @ b.T) - 1.0) / 2.0
    return float(np.degrees(np.arccos(np.clip(c, -1.0, 1.0))))


def test_ransac_solves_its_example(http) -> None:
    given = example(http, "registration.ransac")
    r = execute(http, "registration.ransac", {
        k: given[k] for k in ("source", "target", "features", "max_correspondence_distance")})
    assert r.status_code == 200, r.text
    doc = r.json()
    c, s = np.cos(np.radians(120.0)), np.sin(np.radians(120.0))
    np.testing.assert_allclose(doc["rotation"], [[c, -s, 0], [s, c, 0], [0, 0, 1]], atol=1e-9)
    np.testing.assert_allclose(doc["translation"], [1.0, -0.5, 0.0], atol=1e-9)
    assert doc["converged"] is True and doc["fitness"] == 1.0 and doc["inlier_count"] == 6


def test_ransac_runs_as_a_job_with_progress_and_is_reproducible(http) -> None:
    truth = Rotation.from_rotvec([2.0, -1.0, 0.5]).as_matrix()
    src = _blob(1500, 1)
    dst = _blob(1500, 2) @ truth.T + [0.5, 0.2, -0.3]
    inputs = {"source": src.round(9).tolist(), "target": dst.round(9).tolist(),
              "voxel_size": 0.15, "seed": 3}
    r = execute(http, "registration.ransac", inputs, prefer=None)  # no preference: async
    assert r.status_code == 201, r.text
    job = r.headers["Location"]
    for _ in range(1200):
        status = http.get(job).json()
        if status["status"] in ("successful", "failed", "dismissed"):
            break
        time.sleep(0.05)
    assert status["status"] == "successful", status
    assert status["progress"] == 100
    doc = http.get(f"{job}/results").json()
    assert _angle(doc["rotation"], truth) < 2.0 and doc["converged"] is True
    again = execute(http, "registration.ransac", inputs)
    assert again.status_code == 200, again.text
    assert again.json()["transform"] == doc["transform"]
    assert again.json()["iterations"] == doc["iterations"]


def test_failure_is_reported_not_hidden(http) -> None:
    # a target three times larger: no rigid sample passes the edge-length check
    r = execute(http, "registration.ransac", {"source": SIX,
                                              "target": (3 * np.array(SIX) + 10).tolist(),
                                              "features": "none", "max_iterations": 500})
    assert r.status_code == 200, r.text
    doc = r.json()
    assert doc["converged"] is False and "no hypothesis" in doc["reason"]
    assert doc["fitness"] == 0.0 and doc["iterations"] == 500


@pytest.mark.parametrize("inputs, field, fragment", [
    ({"source": [[0, 0], [1, 0], [0, 1], [1, 2]], "target": [[0, 0], [1, 0], [0, 1], [1, 2]]},
     "features", "3-D"),
    ({"source": SIX[:3], "target": SIX}, "source", "at least 4"),
    ({"source": LINE, "target": SIX}, "source", "collinear"),
    ({"source": SIX, "target": [[0, 0], [1, 1], [2, 0]]}, "target", "same dimension"),
    ({"source": SIX, "target": SIX, "features": "sift"}, "features", ""),
    ({"source": SIX, "target": SIX, "voxel_size": 10.0}, "voxel_size", "leave at least"),
    ({"source": SIX, "target": SIX, "voxel_size": -1}, "voxel_size", ""),
    ({"source": SIX, "target": SIX, "confidence": 0}, "confidence", ""),
    ({"source": SIX, "target": SIX, "max_iterations": 0}, "max_iterations", ""),
    ({"source": SIX, "target": SIX, "seed": -1}, "seed", ""),
    ({"source": [[0, 0, 0], [1, NAN, 0], [0, 1, 0], [0, 0, 1]], "target": SIX}, "source",
     "row 1"),
])
def test_invalid_inputs_are_422_naming_the_input(http, inputs, field, fragment) -> None:
    r = execute(http, "registration.ransac", inputs)
    assert r.status_code == 422, r.text
    assert r.headers["content-type"] == "application/problem+json"
    body = r.json()
    assert body["status"] == 422
    assert body["errors"][0]["input"] == field, body
    assert fragment in body["errors"][0]["message"], body


def test_ransac_is_listed(http) -> None:
    ids = {p["id"] for p in http.get("/processes").json()["processes"]}
    assert "registration.ransac" in ids
    desc = http.get("/processes/registration.ransac").json()
    assert desc["inputs"]["features"]["schema"]["enum"] == ["fpfh", "none"]
    assert {"transform", "rotation", "translation", "rmse", "fitness", "inlier_count",
            "correspondence_count", "iterations", "converged", "reason"} == \
        set(desc["outputs"])
