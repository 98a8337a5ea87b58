"""registration.multiway over HTTP against a live server: it solves its example (generalised
Procrustes, rigid and similarity), agrees with the algorithm called directly, runs the pose
graph as a job with progress (a long process: asynchronous without a preference), and every
input error is a 422 problem+json naming the input, down to the set (`sets[2]`)."""

from __future__ import annotations

import time
import warnings

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from algorithms.core import ConvergenceWarning
from algorithms.registration import multiway
from tests.live import example, execute

pytestmark = pytest.mark.e2e

NAN = float("nan")
SQ = [[0, 0], [1, 0], [0, 1], [1, 1]]
CUBE = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 0], [1, 0, 1], [0, 1, 1]]


def _cloud(n: int = 300, seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return rng.gamma(2.0, size=(n, 3)) * [1.0, 0.6, 0.3]   # skewed, no symmetry


def test_multiway_solves_its_example(http) -> None:
    # The example: an L of 5 points, the same turned by +90° and shifted by (5, 0), and the
    # same doubled and shifted by (0, 3). Similarity maps them back exactly.
    given = {"sets": example(http, "registration.multiway")["sets"], "model": "similarity"}
    r = execute(http, "registration.multiway", given)
    assert r.status_code == 200, r.text
    doc = r.json()
    np.testing.assert_allclose(doc["transforms"][1], [[0, 1, 0], [-1, 0, 5], [0, 0, 1]],
                               atol=1e-9)
    np.testing.assert_allclose(doc["transforms"][2], [[0.5, 0, 0], [0, 0.5, -1.5], [0, 0, 1]],
                               atol=1e-9)
    np.testing.assert_allclose(doc["scales"], [1, 1, 0.5], atol=1e-12)
    np.testing.assert_allclose(doc["mean_shape"], given["sets"][0], atol=1e-9)
    assert doc["converged"] is True and doc["edges"] == [] and doc["fitness"] == [1, 1, 1]
    # rigid cannot undo the doubling: a residual remains, set 0 stays the reference
    r = execute(http, "registration.multiway", {"sets": given["sets"]})
    assert r.status_code == 200, r.text
    doc = r.json()
    np.testing.assert_allclose(doc["transforms"][0], np.eye(3), atol=0)
    assert doc["scales"] == [1.0, 1.0, 1.0] and max(doc["rmse"]) > 0.1


def test_procrustes_over_http_matches_the_function(http) -> None:
    rng = np.random.default_rng(1)
    x = _cloud(40, 1)
    sets = [x @ Rotation.random(random_state=s).as_matrix().T + rng.normal(size=3)
            + 0.01 * rng.standard_normal(x.shape) for s in range(4)]
    r = execute(http, "registration.multiway", {"sets": [s.tolist() for s in sets],
                                                "model": "similarity"})
    assert r.status_code == 200, r.text
    doc = r.json()
    direct = multiway(sets, model="similarity")
    np.testing.assert_allclose(doc["transforms"], direct.transforms, atol=1e-12)
    np.testing.assert_allclose(doc["mean_shape"], direct.mean_shape, atol=1e-12)
    np.testing.assert_allclose(doc["rmse"], direct.rmse, atol=1e-12)
    assert doc["iterations"] == direct.iterations


def test_pose_graph_runs_as_a_job_with_progress(http) -> None:
    x = _cloud(300, 2)
    rng = np.random.default_rng(2)
    truth = [np.eye(3)] + [Rotation.from_rotvec(rng.uniform(-0.08, 0.08, 3)).as_matrix()
                           for _ in range(2)]
    sets = [(x @ r)[rng.permutation(len(x))] for r in truth]   # set i = R_iᵀ x, shuffled
    r = execute(http, "registration.multiway", {"sets": [s.tolist() for s in sets],
                                                "correspondences": False},
                prefer=None)  # no preference: async
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
    for i in range(3):
        np.testing.assert_allclose(np.array(doc["transforms"][i])[:3, :3], truth[i],
                                   atol=1e-6)
    assert doc["edges"] == [[0, 1], [0, 2], [1, 2]] and doc["edge_kept"] == [True] * 3
    assert doc["mean_shape"] is None and doc["converged"] is True
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        direct = multiway(sets, correspondences=False)
    np.testing.assert_allclose(doc["transforms"], direct.transforms, atol=1e-9)


@pytest.mark.parametrize("inputs, field, fragment", [
    ({"sets": [SQ]}, "sets", "at least 2"),
    ({"sets": [SQ, SQ, [[0, 0], [1, NAN], [0, 1], [1, 1]]]}, "sets[2]", "row 1"),
    ({"sets": [SQ, SQ[:3]]}, "sets[1]", "as many points"),
    ({"sets": [SQ, CUBE[:4]]}, "sets[1]", "dimension"),
    ({"sets": [SQ, SQ], "correspondences": False}, "sets", "3-D"),
    ({"sets": [CUBE, CUBE], "correspondences": False, "model": "similarity"}, "model",
     "rigid"),
    ({"sets": [SQ, SQ], "model": "affine"}, "model", ""),
    ({"sets": [SQ, SQ], "init": [np.eye(3).tolist()]}, "init", "(2, 3, 3)"),
    ({"sets": [CUBE, CUBE], "correspondences": False, "neighbors": 3}, "neighbors",
     "an integer >= 1 and <= 1 (the number of other sets)"),
    ({"sets": [SQ, SQ, [[1, 1]] * 4], "model": "similarity"}, "sets[2]", "coincident"),
    ({"sets": [CUBE, CUBE], "correspondences": False, "min_fitness": 2}, "min_fitness", ""),
    ({"sets": "nope"}, "sets", "list"),
])
def test_invalid_inputs_are_422_naming_the_input(http, inputs, field, fragment) -> None:
    r = execute(http, "registration.multiway", inputs)
    assert r.status_code == 422, r.text
    assert r.headers["content-type"] == "application/problem+json"
    body = r.json()
    assert body["status"] == 422
    assert body["errors"][0]["input"] == field, body
    assert fragment in body["errors"][0]["message"], body


def test_multiway_is_listed(http) -> None:
    ids = {p["id"] for p in http.get("/processes").json()["processes"]}
    assert "registration.multiway" in ids
    desc = http.get("/processes/registration.multiway").json()
    assert desc["inputs"]["sets"]["schema"]["minItems"] == 2
    assert desc["inputs"]["model"]["schema"]["enum"] == ["rigid", "similarity"]
    assert {"transforms", "rotations", "scales", "translations", "mean_shape", "rmse",
            "fitness", "edges", "edge_fitness", "edge_kept", "iterations", "converged",
            "reason"} <= set(desc["outputs"])
