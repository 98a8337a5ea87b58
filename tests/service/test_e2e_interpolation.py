"""The interpolation processes over HTTP against a live server: each runs its example and
returns frames that start at the source and end at the target, arap runs as a job with
progress, and every input error (other connectivity, bad times, malformed transforms,
NaN, reflections) is a 422 problem+json naming the input."""

from __future__ import annotations

import time
from typing import Any

import numpy as np
import pytest

from tests.live import execute

pytestmark = pytest.mark.e2e

NAN = float("nan")
SQUARE = [[0, 0], [1, 0], [1, 1], [0, 1]]
QUARTER = [[0, -1, 2], [1, 0, 1], [0, 0, 1]]
STRIP_V = [[0.0, -0.5], [1.0, -0.5], [2.0, -0.5], [3.0, -0.5], [4.0, -0.5],
           [0.0, 0.5], [1.0, 0.5], [2.0, 0.5], [3.0, 0.5], [4.0, 0.5]]
STRIP_F = [[0, 1, 6], [0, 6, 5], [1, 2, 7], [1, 7, 6], [2, 3, 8], [2, 8, 7], [3, 4, 9],
           [3, 9, 8]]


def _bent(angle: float) -> list[list[float]]:
    v = np.array(STRIP_V)
    r = 4.0 / angle
    phi = v[:, 0] / r
    return np.stack([(r - v[:, 1]) * np.sin(phi), r - (r - v[:, 1]) * np.cos(phi)],
                    axis=1).tolist()


STRIP = {"vertices": STRIP_V, "faces": STRIP_F}
BENT = {"vertices": _bent(np.pi), "faces": STRIP_F}
METHODS = ("affine", "rigid", "arap", "poisson")


def _ok(r) -> dict[str, Any]:  # noqa: ANN001
    assert r.status_code == 200, r.text
    doc = r.json()
    assert {"frames", "times", "faces", "max_edge_error"} <= set(doc)
    return doc


@pytest.mark.parametrize("method", ["arap", "poisson"])
def test_mesh_methods_bend_the_strip_keeping_its_lengths(http, method) -> None:
    doc = _ok(execute(http, f"interpolation.{method}", {"source": STRIP, "target": BENT}))
    frames = np.array(doc["frames"])
    assert frames.shape == (11, 10, 2) and doc["faces"] == STRIP_F
    np.testing.assert_allclose(doc["times"], np.linspace(0, 1, 11), atol=1e-15)
    np.testing.assert_allclose(frames[0], STRIP_V, atol=1e-10)
    np.testing.assert_allclose(frames[-1], BENT["vertices"], atol=1e-10)
    assert max(doc["max_edge_error"]) < 0.05 and min(doc["min_det"]) > 0.5


@pytest.mark.parametrize("method", ["affine", "rigid"])
def test_whole_shape_methods_turn_by_the_short_way(http, method) -> None:
    doc = _ok(execute(http, f"interpolation.{method}", {"source": SQUARE, "transform": QUARTER,
                                                       "times": [0, 0.5, 1]}))
    assert doc["angle"] == pytest.approx(np.pi / 2)
    frames = np.array(doc["frames"])
    np.testing.assert_allclose(frames[-1], np.array(SQUARE) @ np.array(QUARTER)[:2, :2].T
                               + [2, 1], atol=1e-12)
    assert doc["faces"] == []
    if method == "affine":
        assert doc["det"] == pytest.approx([1, 1, 1]) and doc["reflection"] is False


def test_arap_runs_as_a_job_with_progress(http) -> None:
    r = execute(http, "interpolation.arap", {"source": STRIP, "target": BENT,
                                             "times": np.linspace(0, 1, 31).tolist()},
                prefer="respond-async")
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
    assert np.array(doc["frames"]).shape == (31, 10, 2)


def test_every_interpolation_method_is_listed(http) -> None:
    ids = {p["id"] for p in http.get("/processes").json()["processes"]}
    assert {f"interpolation.{m}" for m in METHODS} <= ids
    desc = http.get("/processes/interpolation.affine").json()
    assert desc["inputs"]["reflection"]["schema"]["enum"] == ["refuse", "flip"]
    assert {"frames", "times", "faces", "det", "rotation", "stretch"} <= set(desc["outputs"])


# -- every input error is a 422 naming the input ----------------------------------------------
@pytest.mark.parametrize("method, inputs, field, fragment", [
    ("arap", {"source": STRIP, "target": {"vertices": BENT["vertices"],
                                          "faces": STRIP_F[::-1]}},
     "target.faces", "same connectivity"),
    ("poisson", {"source": STRIP, "target": {"vertices": BENT["vertices"][:9],
                                             "faces": STRIP_F[:6]}},
     "target.vertices", "shape of `source.vertices`"),
    ("arap", {"source": STRIP, "target": BENT, "times": [0, 0.5, 0.5]}, "times",
     "strictly increasing"),
    ("poisson", {"source": STRIP, "target": BENT, "times": [0, 1.2]}, "times", "[0, 1]"),
    ("affine", {"source": SQUARE, "transform": QUARTER, "times": []}, "times", "at least 1"),
    ("arap", {"source": STRIP}, "target", "neither"),
    ("arap", {"source": STRIP_V, "target": BENT}, "source", "mesh"),
    ("arap", {"source": STRIP, "target": BENT, "anchor": 10}, "anchor", "<= 9 (a vertex index of `source`)"),
    ("affine", {"source": SQUARE, "transform": [[1, 0], [0, 1]]}, "transform", "(3, 3)"),
    ("affine", {"source": SQUARE, "transform": [[-1, 0, 0], [0, 1, 0], [0, 0, 1]]},
     "transform", "reflection"),
    ("affine", {"source": [[0, 0], [1, 1], [2, 2], [3, 3]], "target": SQUARE}, "source", ""),
    ("affine", {"source": SQUARE, "target": SQUARE, "transform": QUARTER}, "transform",
     "both"),
    ("rigid", {"source": SQUARE, "transform": [[2, 0, 0], [0, 1, 0], [0, 0, 1]]},
     "transform", "scaled rotation"),
    ("rigid", {"source": [[0, 0], [NAN, 0], [1, 1]], "target": SQUARE[:3]}, "source", "row 1"),
    ("poisson", {"source": {"vertices": STRIP_V, "faces": [[0, 1, 10]]}, "target": BENT},
     "source.faces", "below 10"),
])
def test_invalid_inputs_are_422_naming_the_input(http, method, inputs, field, fragment) -> None:
    r = execute(http, f"interpolation.{method}", inputs)
    assert r.status_code == 422, r.text
    assert r.headers["content-type"] == "application/problem+json"
    body = r.json()
    assert body["status"] == 422
    assert body["errors"][0]["input"] == field, body
    assert fragment in body["errors"][0]["message"], body
