"""The alignment methods over HTTP against a live server: each runs its example, and each
error branch (too few points, flat or coincident sets, points not in general position,
mismatched counts, NaN/Inf, bad options) is a 422 problem+json naming the input."""

from __future__ import annotations

import numpy as np
import pytest

from tests.live import execute

pytestmark = pytest.mark.e2e

NAN, INF = float("nan"), float("inf")
CUBE = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]
FLAT = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]
LINE3 = [[0, 0, 0], [1, 1, 1], [2, 2, 2], [3, 3, 3]]
SQUARE = [[0, 0], [1, 0], [1, 1], [0, 1]]
THREE_IN_A_ROW = [[0, 0], [1, 0], [2, 0], [0, 1]]
LINE2 = [[0, 0], [1, 1], [2, 2], [3, 3]]
SKEWED = [[-1, 0], [-1, 0], [2, 0], [0, 0.5], [0, 0.5], [0, -1]]


@pytest.mark.parametrize("process, inputs, expected", [
    ("similarity", {"source": CUBE, "target": [[1, 2, 3], [1, 4, 3], [-1, 2, 3], [1, 2, 5]]},
     [[0, -2, 0, 1], [2, 0, 0, 2], [0, 0, 2, 3], [0, 0, 0, 1]]),
    ("affine", {"source": CUBE, "target": [[1, 0, 0], [3, 0, 0], [2, 1, 0], [1, 0, 3]]},
     [[2, 1, 0, 1], [0, 1, 0, 0], [0, 0, 3, 0], [0, 0, 0, 1]]),
    ("principal_scaling", {"source": [[0.5, 0.5], [-0.5, 0.5], [-0.5, -0.5], [0.5, -0.5]],
                           "target": [[2.5, 1.25], [-0.5, 1.25], [-0.5, 0.75], [2.5, 0.75]]},
     [[3, 0, 1], [0, 0.5, 1], [0, 0, 1]]),
    ("homography", {"source": SQUARE, "target": [[0, 0], [0.5, 0], [0.5, 0.5], [0, 1]]},
     [[1, 0, 0], [0, 1, 0], [1, 0, 1]]),
    ("pca", {"source": SKEWED, "target": [[4, 2], [-0.5, 2], [-0.5, 2], [1, 8], [1, -1],
                                          [1, -1]], "mode": "oriented"},
     [[0, -3, 1], [3, 0, 2], [0, 0, 1]]),
])
def test_methods_solve_their_examples(http, process, inputs, expected) -> None:
    r = execute(http, f"alignment.{process}", inputs, prefer="wait=30")
    assert r.status_code == 200, r.text
    doc = r.json()
    np.testing.assert_allclose(doc["transform"], expected, atol=1e-9)
    assert doc["rmse"] < 1e-9
    assert {"transform", "linear", "translation", "rmse"} <= set(doc)


def test_symmetric_and_weights_over_http(http) -> None:
    target = [[1, 0, 0], [3, 0, 0], [2, 1, 0], [1, 0, 3], [9, 9, 9]]
    r = execute(http, "alignment.affine", {"source": [*CUBE, [1, 1, 1]], "target": target,
                                           "weights": [1, 1, 1, 1, 0], "symmetric": True},
                prefer="wait=30")
    assert r.status_code == 200, r.text
    doc = r.json()
    np.testing.assert_allclose(doc["linear"], [[2, 1, 0], [0, 1, 0], [0, 0, 3]], atol=1e-9)
    assert doc["converged"] is True


@pytest.mark.parametrize("process, inputs, field, fragment", [
    # affine: d + 1 affinely independent points
    ("affine", {"source": CUBE[:3], "target": CUBE[:3]}, "source", "at least 4 points"),
    ("affine", {"source": FLAT, "target": CUBE}, "source", "coplanar"),
    ("affine", {"source": CUBE, "target": CUBE[:3]}, "target", "as many points"),
    ("affine", {"source": [[0, 0, 0], [1, NAN, 0], [0, 1, 0], [0, 0, 1]], "target": CUBE},
     "source", "row 1"),
    ("affine", {"source": CUBE, "target": CUBE, "weights": [1, 1]}, "weights", ""),
    ("affine", {"source": CUBE, "target": FLAT, "symmetric": True}, "target", "symmetric"),
    ("affine", {"source": CUBE, "target": CUBE, "symmetric": "yes"}, "symmetric", ""),
    # similarity: the rotation must be determined
    ("similarity", {"source": [[1, 1, 1]] * 4, "target": CUBE}, "source", "coincident"),
    ("similarity", {"source": CUBE, "target": LINE3}, "target", "collinear"),
    ("similarity", {"source": CUBE, "target": [[0, 0, 0], [1, 0, 0], [0, INF, 0], [0, 0, 1]]},
     "target", "row 2"),
    ("similarity", {"source": CUBE, "target": CUBE, "weights": [1, -1, 1, 1]}, "weights", ""),
    ("similarity", {"source": CUBE[:2], "target": CUBE[:2]}, "source", "at least 3"),
    # principal scaling
    ("principal_scaling", {"source": [[2, 2]] * 3, "target": SQUARE[:3]}, "source",
     "coincident"),
    ("principal_scaling", {"source": SQUARE, "target": SQUARE[:2]}, "target", "as many"),
    # homography: d + 2 points in general position
    ("homography", {"source": SQUARE[:3], "target": SQUARE[:3]}, "source", "at least 4"),
    ("homography", {"source": THREE_IN_A_ROW, "target": SQUARE}, "source", "general position"),
    ("homography", {"source": SQUARE, "target": LINE2}, "target", "collinear"),
    ("homography", {"source": SQUARE, "target": [[0, 0], [1, 0], [1, NAN], [0, 1]]}, "target",
     "row 2"),
    ("homography", {"source": SQUARE, "target": [[0, 0], [1, 0], [1, 1]]}, "target", "got 3"),
    # pca: no correspondences, but the same dimension and spread-out sets
    ("pca", {"source": SKEWED, "target": CUBE}, "target", "same dimension"),
    ("pca", {"source": SKEWED, "target": [[3, 3]] * 5}, "target", "coincident"),
    ("pca", {"source": SKEWED[:1], "target": SKEWED}, "source", "at least 2"),
    ("pca", {"source": SKEWED, "target": SKEWED, "mode": "sideways"}, "mode", ""),
    ("pca", {"source": SKEWED, "target": SKEWED, "scale": "huge"}, "scale", ""),
    ("pca", {"source": [[NAN, 0], [1, 1], [2, 0]], "target": SKEWED}, "source", "row 0"),
])
def test_invalid_inputs_are_422_naming_the_input(http, process, inputs, field, fragment) -> None:
    r = execute(http, f"alignment.{process}", inputs, prefer="wait=30")
    assert r.status_code == 422, r.text
    assert r.headers["content-type"] == "application/problem+json"
    body = r.json()
    assert body["type"] == "/problems/invalid-input" and body["status"] == 422
    assert body["errors"][0]["input"] == field, body
    assert fragment in body["errors"][0]["message"], body


def test_every_alignment_method_is_listed(http) -> None:
    ids = {p["id"] for p in http.get("/processes").json()["processes"]}
    assert {f"alignment.{m}" for m in ("rigid", "similarity", "affine", "principal_scaling",
                                       "homography", "pca")} <= ids
    desc = http.get("/processes/alignment.pca").json()
    assert desc["inputs"]["mode"]["schema"]["enum"] == ["unoriented", "oriented"]
    assert {"rotation", "scale", "axes", "chamfer", "reflection"} <= set(desc["outputs"])
