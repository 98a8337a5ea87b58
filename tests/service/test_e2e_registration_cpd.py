"""registration.cpd over HTTP against a live server: it solves its example (rotation, scale
and shift), the nonrigid model returns the moved points with null transform parts, it runs as
a job with progress (a long process: asynchronous without a preference), and every input
error is a 422 problem+json naming the input."""

from __future__ import annotations

import time

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from tests.live import example, execute

pytestmark = pytest.mark.e2e

NAN = float("nan")
CUBE = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 1]]


def _cloud(n: int = 200, seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return rng.gamma(2.0, size=(n, 3)) * [1.0, 0.6, 0.3]   # skewed, no symmetry


def test_cpd_solves_its_example(http) -> None:
    given = example(http, "registration.cpd")
    r = execute(http, "registration.cpd", {k: given[k] for k in ("source", "target")})
    assert r.status_code == 200, r.text
    doc = r.json()
    c, s = np.cos(np.radians(10.0)), np.sin(np.radians(10.0))
    np.testing.assert_allclose(doc["rotation"], [[c, -s, 0], [s, c, 0], [0, 0, 1]], atol=1e-9)
    np.testing.assert_allclose(doc["translation"], [0.1, 0, 0], atol=1e-9)
    assert doc["scale"] == pytest.approx(1.5, rel=1e-9)
    assert doc["converged"] is True
    np.testing.assert_allclose(doc["moved"], given["target"], atol=1e-9)


def test_cpd_models_over_http(http) -> None:
    src = _cloud()
    truth = Rotation.from_rotvec([0.1, 0.2, -0.1]).as_matrix()
    dst = src @ truth.T + [0.2, 0.0, 0.1]
    r = execute(http, "registration.cpd", {"source": src.tolist(), "target": dst.tolist(),
                                           "scale": False, "w": 0.1})
    assert r.status_code == 200, r.text
    doc = r.json()
    assert doc["scale"] == 1.0
    np.testing.assert_allclose(doc["rotation"], truth, atol=1e-6)
    r = execute(http, "registration.cpd", {"source": src.tolist(), "target": dst.tolist(),
                                           "model": "nonrigid", "beta": 1.0, "alpha": 3.0})
    assert r.status_code == 200, r.text
    doc = r.json()
    assert doc["transform"] is None and doc["rotation"] is None and doc["scale"] is None
    moved = np.array(doc["moved"])
    assert moved.shape == src.shape
    assert np.sqrt(np.mean(np.sum((moved - dst) ** 2, axis=1))) < 0.02 * np.ptp(dst, axis=0).max()


def test_cpd_runs_as_a_job_with_progress(http) -> None:
    src = _cloud(300, 1)
    dst = src @ Rotation.from_rotvec([0, 0, 0.3]).as_matrix().T
    r = execute(http, "registration.cpd", {"source": src.tolist(), "target": dst.tolist(),
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
    assert doc["iterations"] == 5 and doc["converged"] is False


@pytest.mark.parametrize("inputs, field, fragment", [
    ({"source": CUBE[:2], "target": CUBE}, "source", "at least 3"),
    ({"source": CUBE, "target": CUBE[:3], "model": "affine"}, "target", "at least 4"),
    ({"source": CUBE, "target": [[0, 0], [1, 1], [2, 0]]}, "target", "same dimension"),
    ({"source": [[0, 0, 0], [1, NAN, 0], [0, 1, 0], [0, 0, 1]], "target": CUBE}, "source",
     "row 1"),
    ({"source": CUBE, "target": CUBE, "w": 1.0}, "w", ""),
    ({"source": CUBE, "target": CUBE, "w": -0.5}, "w", ""),
    ({"source": CUBE, "target": CUBE, "model": "similarity"}, "model", ""),
    ({"source": CUBE, "target": CUBE, "beta": 0}, "beta", ""),
    ({"source": CUBE, "target": CUBE, "sigma2": -1}, "sigma2", ""),
    ({"source": CUBE, "target": CUBE, "low_rank": 0}, "low_rank", ""),
    ({"source": [[0, 0, 0], [1, 0, 0], [2, 0, 0], [3, 0, 0]], "target": CUBE}, "source",
     "collinear"),
])
def test_invalid_inputs_are_422_naming_the_input(http, inputs, field, fragment) -> None:
    r = execute(http, "registration.cpd", inputs)
    assert r.status_code == 422, r.text
    assert r.headers["content-type"] == "application/problem+json"
    body = r.json()
    assert body["status"] == 422
    assert body["errors"][0]["input"] == field, body
    assert fragment in body["errors"][0]["message"], body


def test_cpd_is_listed(http) -> None:
    ids = {p["id"] for p in http.get("/processes").json()["processes"]}
    assert "registration.cpd" in ids
    desc = http.get("/processes/registration.cpd").json()
    assert desc["inputs"]["model"]["schema"]["enum"] == ["rigid", "affine", "nonrigid"]
    assert {"transform", "rotation", "scale", "translation", "moved", "sigma2", "rmse",
            "iterations", "converged", "reason"} <= set(desc["outputs"])
