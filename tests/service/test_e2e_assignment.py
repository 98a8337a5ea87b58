"""The assignment processes over HTTP against a live server: one run each, and every input
error as a 422 problem+json naming the input."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from tests.live import execute

pytestmark = pytest.mark.e2e

SRC = [[0.0, 0.0], [1.0, 0.0], [3.0, 0.0]]
DST = [[0.0, 0.2], [1.1, 0.0]]
NAN, INF = float("nan"), float("inf")


def _invalid(r) -> dict:  # noqa: ANN001
    assert r.status_code == 422, r.text
    assert r.headers["content-type"] == "application/problem+json"
    body = r.json()
    assert body["type"] == "/problems/invalid-input" and body["status"] == 422
    return body


# -- one run of each, results as documented ------------------------------------------------
def test_closest_pair_over_http(http) -> None:
    doc = execute(http, "assignment.closest_pair", {"source": SRC, "target": DST},
                  prefer=None).json()
    # hand: (1, 0)-(1.1, 0) at 0.1 beats (0, 0)-(0, 0.2) at 0.2
    assert (doc["source_index"], doc["target_index"]) == (1, 1)
    assert doc["pairs"] == [[1, 1]]
    assert doc["distance"] == pytest.approx(0.1, rel=1e-12)


def test_bipartite_over_http(http) -> None:
    doc = execute(http, "assignment.bipartite", {"source": SRC, "target": DST}, prefer=None).json()
    assert doc["pairs"] == [[0, 0], [1, 1]] and doc["unmatched_source"] == [2]
    assert doc["cost"] == pytest.approx(0.3, rel=1e-12)
    doc = execute(http, "assignment.bipartite", {"source": SRC, "target": DST, "max_cost": 0.15},
                  prefer=None).json()
    assert doc["pairs"] == [[1, 1]] and doc["n_pairs"] == 1


def test_optimal_transport_over_http(http) -> None:
    doc = execute(http, "assignment.optimal_transport", {
        "source": [[0.0], [1.0]], "target": [[0.0], [2.0]], "source_weights": [3, 1]},
        prefer=None).json()
    assert doc["pairs"] == [[0, 0], [0, 1], [1, 1]] and doc["solver"] == "network_simplex"
    np.testing.assert_allclose(doc["masses"], [0.5, 0.25, 0.25], atol=1e-14)
    assert doc["cost"] == pytest.approx(1.25, rel=1e-12) and doc["converged"] is True
    sk = execute(http, "assignment.optimal_transport", {"source": SRC, "target": DST,
                                                        "method": "sinkhorn", "reg": 0.1},
                 prefer=None).json()
    assert sk["solver"] == "sinkhorn" and sk["converged"] is True
    assert sum(sk["masses"]) == pytest.approx(1.0, rel=1e-8)


def test_sinkhorn_not_converging_still_succeeds(http) -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = execute(http, "assignment.optimal_transport", {"source": SRC, "target": DST,
                                                           "method": "sinkhorn", "reg": 0.01,
                                                           "max_iterations": 2}, prefer=None)
    assert r.status_code == 200, r.text
    assert r.json()["converged"] is False and r.json()["iterations"] == 2


def test_distance_over_http(http) -> None:
    doc = execute(http, "assignment.distance", {"source": SRC, "target": DST}, prefer=None).json()
    np.testing.assert_allclose(doc["forward_distances"], [0.2, 0.1, 1.9], rtol=1e-12)
    np.testing.assert_allclose(doc["backward_distances"], [0.2, 0.1], rtol=1e-12)
    assert doc["hausdorff"] == pytest.approx(1.9, rel=1e-12)
    assert doc["chamfer"] == pytest.approx(2.5, rel=1e-12)


# -- errors ----------------------------------------------------------------------------------
_COMMON = [  # (inputs, field, fragment of the message); every method takes these
    ({"source": [], "target": DST}, "source", "got shape (0,)"),  # no point at all
    ({"source": SRC, "target": []}, "target", "got shape (0,)"),
    ({"source": [[0.0, 0.0], [NAN, 0.0]], "target": DST}, "source", "nan at row 1"),
    ({"source": SRC, "target": [[0.0, 0.0], [0.0, INF]]}, "target", "inf at row 1"),
    ({"source": SRC, "target": [[0.0, 0.0, 0.0]]}, "target", "same dimension"),
    ({"source": [0.0, 1.0], "target": DST}, "source", "got shape (2,)"),
    ({"target": DST}, "source", "Field required"),
    ({"source": SRC, "target": DST, "bogus": 1}, "bogus", "Unknown input `bogus`"),
]


@pytest.mark.parametrize("method", ["closest_pair", "bipartite", "optimal_transport",
                                    "distance"])
@pytest.mark.parametrize("inputs, field, fragment", _COMMON)
def test_invalid_points_name_the_input(http, method, inputs, field, fragment) -> None:
    body = _invalid(execute(http, f"assignment.{method}", inputs, prefer=None))
    assert body["errors"][0]["input"] == field, body
    assert fragment in body["errors"][0]["message"], body


_BIG = [[float(i)] for i in range(4001)]  # 4,001 × 4,000 > 16 million pairs


@pytest.mark.parametrize("method, extra, field, fragment", [
    ("bipartite", {"metric": "cityblock"}, "metric", ""),
    ("bipartite", {"max_cost": 0}, "max_cost", ""),
    ("bipartite", {"max_cost": -1.5}, "max_cost", ""),
    ("bipartite", {"max_cost": "1"}, "max_cost", ""),
    ("optimal_transport", {"reg": 0}, "reg", ""),
    ("optimal_transport", {"reg": -0.1}, "reg", ""),
    ("optimal_transport", {"method": "simplex"}, "method", ""),
    ("optimal_transport", {"metric": "cosine"}, "metric", ""),
    ("optimal_transport", {"max_iterations": 0}, "max_iterations", ""),
    ("optimal_transport", {"max_iterations": 10.5}, "max_iterations", ""),
    ("optimal_transport", {"tolerance": 0}, "tolerance", ""),
    ("optimal_transport", {"source_weights": [1, 1]}, "source_weights", "(3,)"),
    ("optimal_transport", {"source_weights": [1, -1, 1]}, "source_weights", "non-negative"),
    ("optimal_transport", {"source_weights": [0, 0, 0]}, "source_weights", "positive sum"),
    ("optimal_transport", {"source_weights": [1, NAN, 1]}, "source_weights", "nan"),
    ("optimal_transport", {"source_weights": [[1, 1, 1]]}, "source_weights", "flat list"),
    ("optimal_transport", {"target_weights": [1, 1, 1]}, "target_weights", "(2,)"),
    ("optimal_transport", {"target_weights": [1, INF]}, "target_weights", "inf"),
    ("closest_pair", {"workers": 2}, "workers", "does not offer"),  # not offered over HTTP
])
def test_invalid_options_name_the_input(http, method, extra, field, fragment) -> None:
    body = _invalid(execute(http, f"assignment.{method}", {"source": SRC, "target": DST, **extra},
                            prefer=None))
    assert body["errors"][0]["input"] == field, body
    assert fragment in body["errors"][0]["message"], body


@pytest.mark.parametrize("method", ["bipartite", "optimal_transport"])
def test_cost_matrix_too_large(http, method) -> None:
    body = _invalid(execute(http, f"assignment.{method}", {"source": _BIG, "target": _BIG[:4000]},
                            prefer=None))
    assert body["errors"][0]["input"] == "source"
    assert "at most 16,000,000 point pairs" in body["errors"][0]["message"]


def test_reg_too_small_for_the_costs(http) -> None:
    body = _invalid(execute(http, "assignment.optimal_transport", {
        "source": [[0.0]], "target": [[1e100]], "method": "sinkhorn", "reg": 1e-300}, prefer=None))
    assert body["errors"][0]["input"] == "reg"
