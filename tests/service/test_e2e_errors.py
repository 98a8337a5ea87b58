"""Every error is RFC 9457 problem+json with a stable type and, for inputs, the field."""

from __future__ import annotations

import json

import pytest

from service.problems import OGC_EXCEPTIONS

pytestmark = pytest.mark.e2e

RIGID = "/processes/alignment.rigid/execution"
SOURCE = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]
TARGET = [[1, 2, 3], [1, 3, 3], [0, 2, 3], [1, 2, 4]]


def _problem(r, status: int, slug: str) -> dict:  # noqa: ANN001
    assert r.status_code == status, r.text
    assert r.headers["content-type"] == "application/problem+json"
    body = r.json()
    # the errors OGC API - Processes defines have its type URIs; the others are ours
    ogc = slug in ("no-such-process", "no-such-job", "result-not-ready")
    assert body["type"] == (OGC_EXCEPTIONS + slug if ogc else f"/problems/{slug}")
    assert body["status"] == status
    assert body["title"] and body["detail"]
    return body


def _field(body: dict) -> str:
    return body["errors"][0]["input"]


@pytest.mark.parametrize("inputs, field, fragment", [
    ({"target": TARGET}, "source", "Field required"),
    ({"source": SOURCE, "target": TARGET, "bogus": 1}, "bogus", "Unknown input `bogus`"),
    ({"source": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, float("nan")]], "target": TARGET},
     "source", "row 3"),
    ({"source": [[0, 0, 0], [1, 0, float("inf")], [0, 1, 0], [0, 0, 1]], "target": TARGET},
     "source", "row 1"),
    ({"source": SOURCE, "target": TARGET[:3]}, "target", "got 3"),
    ({"source": [[0, 0], [1, 0]], "target": TARGET[:2]}, "target", ""),
    ({"source": "abc", "target": TARGET}, "source", ""),
    ({"source": [[0, 0, 0], [1, 0]], "target": TARGET}, "source", ""),
    ({"source": [], "target": []}, "source", ""),
    ({"source": SOURCE, "target": TARGET, "allow_reflection": "yes"}, "allow_reflection", ""),
    ({"source": SOURCE, "target": TARGET, "allow_reflection": 1}, "allow_reflection", ""),
    ({"source": SOURCE, "target": TARGET, "weights": [1, 1, 1]}, "weights", ""),
    ({"source": SOURCE, "target": TARGET, "weights": [1, -1, 1, 1]}, "weights", ""),
    ({"source": SOURCE, "target": TARGET, "weights": [[1, 1, 1, 1]]}, "weights", ""),
])
def test_invalid_inputs_name_the_field(http, inputs, field, fragment) -> None:
    # Python's json writes NaN/Infinity tokens, as many clients do; the service reads them
    # so that the error can name the row.
    raw = json.dumps({"inputs": inputs})
    r = http.post(RIGID, content=raw, headers={"Content-Type": "application/json"})
    body = _problem(r, 422, "invalid-input")
    assert _field(body) == field, body
    assert fragment in body["errors"][0]["message"], body


@pytest.mark.parametrize("source, fragment", [
    ([[0, 0, 0]] * 4, "determine"),                                  # coincident
    ([[0, 0, 0], [1, 0, 0], [2, 0, 0], [3, 0, 0]], "determine"),    # collinear in 3-D
    ([[0, 0, 0], [1, 0, 0]], "at least 3"),                          # fewer than d points
])
def test_degenerate_geometry_is_422_naming_source(http, source, fragment) -> None:
    body = _problem(http.post(RIGID, json={"inputs": {"source": source,
                                                       "target": source}}),
                    422, "invalid-input")
    assert _field(body) == "source"
    assert fragment in body["detail"].lower() or fragment in body["errors"][0]["message"]


@pytest.mark.parametrize("inputs, field", [
    ({"source": [[0.0, 0.0]], "target": [[0.0, 0.0]], "k": 0}, "k"),
    ({"source": [[0.0, 0.0]], "target": [[0.0, 0.0]], "k": 2}, "k"),
    ({"source": [[0.0, 0.0]], "target": [[0.0, 0.0]], "direction": "sideways"}, "direction"),
    ({"source": [[0.0, 0.0]], "target": [[0.0, 0.0, 0.0]]}, "target"),
    ({"source": [[0.0, 0.0]], "target": [[0.0, 0.0]], "max_distance": -1.0}, "max_distance"),
])
def test_nearest_bad_params(http, inputs, field) -> None:
    r = http.post("/processes/assignment.nearest/execution", json={"inputs": inputs})
    assert _field(_problem(r, 422, "invalid-input")) == field


def test_bad_json_is_400(http) -> None:
    r = http.post(RIGID, content=b'{"inputs": [1, 2', headers={"Content-Type": "application/json"})
    _problem(r, 400, "malformed-body")
    r = http.post(RIGID, content=b"[1, 2]", headers={"Content-Type": "application/json"})
    _problem(r, 400, "malformed-body")


def test_body_members(http) -> None:
    body = _problem(http.post(RIGID, json={"inputs": {"source": SOURCE, "target": TARGET},
                                           "extra": 1}), 422, "invalid-input")
    assert _field(body) == "extra"
    body = _problem(http.post(RIGID, json={"inputs": [1]}), 422, "invalid-input")
    assert _field(body) == "inputs"
    body = _problem(http.post(RIGID, json={"inputs": {"source": SOURCE, "target": TARGET},
                                           "outputs": {"nope": {}}}), 422, "invalid-input")
    assert _field(body) == "outputs.nope"
    body = _problem(http.post(RIGID, json={"inputs": {"source": SOURCE, "target": TARGET},
                                           "response": "weird"}), 422, "invalid-input")
    assert _field(body) == "response"
    body = _problem(http.post(RIGID, json={"inputs": {"source": SOURCE, "target": TARGET},
                                           "timeLimit": -3}), 422, "invalid-input")
    assert _field(body) == "timeLimit"


def test_bad_prefer_wait(http) -> None:
    r = http.post(RIGID, headers={"Prefer": "wait=soon"},
                  json={"inputs": {"source": SOURCE, "target": TARGET}})
    assert _field(_problem(r, 422, "invalid-input")) == "Prefer"


def test_subscriber_host_not_allowed(http) -> None:
    r = http.post(RIGID, json={"inputs": {"source": SOURCE, "target": TARGET},
                               "subscriber": {"successUri": "http://169.254.169.254/latest"}})
    body = _problem(r, 422, "invalid-input")
    assert _field(body) == "subscriber.successUri" and "not allowed" in body["detail"]
    r = http.post(RIGID, json={"inputs": {"source": SOURCE, "target": TARGET},
                               "subscriber": {"successUri": "file:///etc/passwd"}})
    assert _field(_problem(r, 422, "invalid-input")) == "subscriber.successUri"


def test_unsupported_media_type(http) -> None:
    r = http.post(RIGID, content=b"source=1", headers={"Content-Type": "text/plain"})
    assert "Content-Type: application/json" in _problem(r, 415, "unsupported-media-type")["detail"]


def test_payload_too_large(http, server) -> None:
    limit = int(server.env["MORPHSERVE_MAX_REQUEST_BYTES"])
    r = http.post(RIGID, content=b" " * (limit + 1), headers={"Content-Type": "application/json"})
    _problem(r, 413, "payload-too-large")


def test_not_found_and_method_not_allowed(http) -> None:
    _problem(http.get("/nowhere"), 404, "not-found")
    _problem(http.get("/processes/no.such"), 404, "no-such-process")
    _problem(http.post("/processes/no.such/execution", json={}), 404, "no-such-process")
    _problem(http.get("/jobs/not-a-job"), 404, "no-such-job")
    _problem(http.get("/jobs/not-a-job/results"), 404, "no-such-job")
    _problem(http.delete("/jobs/not-a-job"), 404, "no-such-job")
    r = http.delete("/processes")
    _problem(r, 405, "method-not-allowed")
    assert r.headers["allow"] == "GET"
    r = http.put(RIGID, json={})
    _problem(r, 405, "method-not-allowed")
    assert r.headers["allow"] == "POST"
    r = http.request("OPTIONS", "/jobs/some-job")  # GET and DELETE are separate routes
    _problem(r, 405, "method-not-allowed")
    assert r.headers["allow"] == "DELETE, GET"


def test_query_validation(http) -> None:
    body = _problem(http.get("/jobs", params={"status": "sleeping"}), 422, "invalid-input")
    assert _field(body) == "status.0" or _field(body).startswith("status")
    body = _problem(http.get("/jobs", params={"limit": 0}), 422, "invalid-input")
    assert _field(body) == "limit"
    body = _problem(http.get("/jobs", params={"processID": "true"}), 422, "invalid-input")
    assert _field(body).startswith("processID")
    ok = http.get("/jobs", params={"processID": "alignment.rigid"})
    assert ok.status_code == 200


def test_not_acceptable(http) -> None:
    job = http.post(RIGID, json={"inputs": {"source": SOURCE, "target": TARGET}})
    path = job.headers["content-location"]
    _problem(http.get(path, headers={"Accept": "image/png"}), 406, "not-acceptable")
    assert http.get(path, headers={"Accept": "application/json"}).status_code == 200


def test_problem_types_are_pages(http) -> None:
    r = http.get("/problems/invalid-input")
    assert r.status_code == 200 and "Invalid input" in r.text
