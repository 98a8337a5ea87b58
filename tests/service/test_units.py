"""Small pure functions of the service: Prefer headers, subscriber checks, JSON in and out,
problem bodies, statusInfo and results documents (no server, no Dask)."""

from __future__ import annotations

import json
import math
import struct
from typing import Any, get_args

import numpy as np
import pytest
from pydantic import ValidationError

from algorithms.core.errors import DegenerateInputError, InvalidInputError
from service import jsonio
from service.callbacks import check_subscriber
from service.catalog import registry
from service.errors import ServiceError
from service.jobs.status import JobStatus
from service.jobs.store import JobRecord, JobRequest, Subscriber
from service.problems import PROBLEMS, geometry_error_problem, problem_body, pydantic_errors
from service.representation import iso, results_document, status_info
from service.routes import docs
from service.routes.common import parse_prefer


# -- Prefer (RFC 7240) ---------------------------------------------------------------------
@pytest.mark.parametrize(("headers", "expected"), [
    ([], {}),
    ([""], {}),
    (["respond-async"], {"respond-async": None}),
    (["wait=10"], {"wait": "10"}),
    (["respond-async, wait=5"], {"respond-async": None, "wait": "5"}),
    (["respond-async,wait=5"], {"respond-async": None, "wait": "5"}),
    (["respond-async", "wait=7"], {"respond-async": None, "wait": "7"}),
    (["respond-async; foo=bar"], {"respond-async": None}),
    (["wait=3; unit=s, respond-async ;x"], {"wait": "3", "respond-async": None}),
    (['wait="12"'], {"wait": "12"}),
    (["handling=strict"], {"handling": "strict"}),
    (["wait=1, wait=2"], {"wait": "1"}),
    (["wait=1", "wait=2"], {"wait": "1"}),
    (["return=minimal", "return=representation"], {"return": "minimal"}),
    (["Respond-Async, WAIT=4"], {"respond-async": None, "wait": "4"}),
    (["  respond-async  ,  wait = 9 "], {"respond-async": None, "wait": "9"}),
    ([" , ,respond-async,, "], {"respond-async": None}),
    (["wait="], {"wait": None}),
])
def test_parse_prefer(headers: list[str], expected: dict[str, str | None]) -> None:
    assert parse_prefer(headers) == expected


def test_parse_prefer_keeps_value_case() -> None:
    assert parse_prefer(["Return=Minimal"]) == {"return": "Minimal"}


# -- subscriber URIs -----------------------------------------------------------------------
HOSTS = ["cb.example", "hooks.example:8443", "127.0.0.1"]


def _refused(subscriber: Any, field: str, hosts: list[str] = HOSTS) -> ServiceError:
    with pytest.raises(ServiceError) as info:
        check_subscriber(subscriber, hosts)
    err = info.value
    assert err.problem.slug == "invalid-input" and err.status == 422
    assert err.errors and err.errors[0]["input"] == field, err.errors
    assert err.errors[0]["message"]
    assert err.detail.startswith(f"{field}:")
    return err


def test_subscriber_none() -> None:
    assert check_subscriber(None, HOSTS) is None
    assert check_subscriber(None, []) is None
    assert check_subscriber({}, HOSTS) is None


def test_subscriber_allowed_hosts() -> None:
    sub = {"successUri": "https://cb.example/done?job=1",
           "inProgressUri": "http://cb.example:9000/progress",  # a bare host allows any port
           "failedUri": "http://127.0.0.1/failed"}
    got = check_subscriber(sub, HOSTS)
    assert got == Subscriber(success_uri="https://cb.example/done?job=1",
                             in_progress_uri="http://cb.example:9000/progress",
                             failed_uri="http://127.0.0.1/failed")
    assert got.to_json() == sub  # as the request named them, and as the store keeps them


def test_subscriber_host_port_entry() -> None:
    assert check_subscriber({"successUri": "https://hooks.example:8443/x"}, HOSTS) == \
        Subscriber(success_uri="https://hooks.example:8443/x")
    # a host:port entry allows that port only
    err = _refused({"successUri": "https://hooks.example/x"}, "subscriber.successUri")
    assert "hooks.example" in err.errors[0]["message"]
    _refused({"successUri": "https://hooks.example:8444/x"}, "subscriber.successUri")


def test_subscriber_refused_host() -> None:
    err = _refused({"successUri": "http://evil.example/steal"}, "subscriber.successUri")
    assert "evil.example" in err.errors[0]["message"]
    _refused({"successUri": "http://169.254.169.254/latest/meta-data"},
             "subscriber.successUri")
    # nothing is allowed when the allow-list is empty
    _refused({"successUri": "http://cb.example/"}, "subscriber.successUri", hosts=[])
    # a host that merely contains an allowed one
    _refused({"successUri": "http://cb.example.evil.example/"}, "subscriber.successUri")
    _refused({"successUri": "http://cb.example@evil.example/"}, "subscriber.successUri")


def test_subscriber_refusal_names_the_bad_member() -> None:
    _refused({"successUri": "http://cb.example/ok", "failedUri": "http://evil.example/"},
             "subscriber.failedUri")
    _refused({"inProgressUri": "http://evil.example/"}, "subscriber.inProgressUri")


@pytest.mark.parametrize("uri", ["ftp://cb.example/x", "file:///etc/passwd",
                                 "javascript:alert(1)", "cb.example/x", "http://", "",
                                 "//cb.example/x"])
def test_subscriber_non_http(uri: str) -> None:
    _refused({"successUri": uri}, "subscriber.successUri")


def test_subscriber_unknown_member() -> None:
    err = _refused({"successUri": "http://cb.example/", "otherUri": "http://cb.example/"},
                   "subscriber.otherUri")
    assert "successUri" in err.errors[0]["message"]


@pytest.mark.parametrize("value", [123, None, ["http://cb.example/"], {"u": 1}])
def test_subscriber_uri_not_a_string(value: Any) -> None:
    _refused({"successUri": value}, "subscriber.successUri")


@pytest.mark.parametrize("subscriber", ["http://cb.example/", ["http://cb.example/"], 1,
                                        True])
def test_subscriber_not_an_object(subscriber: Any) -> None:
    _refused(subscriber, "subscriber")


@pytest.mark.parametrize("uri", ["http://cb.example:abc/", "http://cb.example:99999/"])
def test_subscriber_bad_port(uri: str) -> None:
    _refused({"successUri": uri}, "subscriber.successUri")


# -- JSON in -------------------------------------------------------------------------------
def test_loads_standard_json() -> None:
    assert jsonio.loads(b'{"inputs": {"k": 3, "x": [1.5, -2e-3], "b": true, "n": null}}') == \
        {"inputs": {"k": 3, "x": [1.5, -0.002], "b": True, "n": None}}
    assert jsonio.loads('"text é"'.encode()) == "text é"
    assert jsonio.loads(b"[]") == []


def test_loads_nan_and_infinity_leniently() -> None:
    got = jsonio.loads(b'{"source": [[NaN, Infinity, -Infinity], [1, 2, 3]]}')
    row = got["source"][0]
    assert math.isnan(row[0]) and row[1] == math.inf and row[2] == -math.inf
    assert got["source"][1] == [1, 2, 3]
    # what Python's json.dumps writes is read back
    assert jsonio.loads(json.dumps({"x": math.inf}).encode()) == {"x": math.inf}


@pytest.mark.parametrize("raw", [b"{", b'{"a": }', b"[1, 2,]", b"nope", b"{'a': 1}",
                                 b'{"a": 1} trailing', b"", b"\xff\xfe"])
def test_loads_syntax_error(raw: bytes) -> None:
    with pytest.raises(ValueError):
        jsonio.loads(raw)


# -- JSON out ------------------------------------------------------------------------------
def test_dumps_numpy_arrays() -> None:
    f = np.array([[0.5, -1.25], [3.0, 1e-300]])
    i = np.arange(6, dtype=np.int64).reshape(3, 2)
    assert json.loads(jsonio.dumps({"f": f, "i": i})) == {"f": f.tolist(), "i": i.tolist()}
    assert jsonio.dumps(np.array([], dtype=np.float64)) == b"[]"
    assert json.loads(jsonio.dumps(np.array([True, False]))) == [True, False]
    assert json.loads(jsonio.dumps(np.array([1, 2], dtype=np.int32))) == [1, 2]
    assert json.loads(jsonio.dumps(np.array([0.5], dtype=np.float32))) == [0.5]


def test_dumps_non_contiguous_arrays() -> None:
    a = np.arange(12, dtype=np.float64).reshape(3, 4)
    for view in (a.T, a[:, ::2], a[::-1], a[1:, 1:3], np.broadcast_to(a[0], (2, 4))):
        assert not view.flags.c_contiguous or view is a
        assert json.loads(jsonio.dumps(view)) == view.tolist()
    fortran = np.asfortranarray(a)
    assert json.loads(jsonio.dumps(fortran)) == a.tolist()


def test_dumps_numpy_scalars() -> None:
    got = json.loads(jsonio.dumps({
        "f64": np.float64(0.1), "f32": np.float32(0.5), "i64": np.int64(-7),
        "u8": np.uint8(200), "b": np.bool_(True), "i32": np.int32(2**31 - 1)}))
    assert got == {"f64": 0.1, "f32": 0.5, "i64": -7, "u8": 200, "b": True, "i32": 2**31 - 1}
    assert isinstance(got["i64"], int) and isinstance(got["b"], bool)


def test_dumps_nested() -> None:
    doc = {"a": {"b": [np.eye(2), {"c": np.int64(1)}], "d": None, "e": "é"},
           "t": (1, 2)}
    assert json.loads(jsonio.dumps(doc)) == {"a": {"b": [[[1.0, 0.0], [0.0, 1.0]],
                                                         {"c": 1}], "d": None, "e": "é"},
                                             "t": [1, 2]}


def test_dumps_refuses_unknown_types() -> None:
    with pytest.raises(TypeError):
        jsonio.dumps({"x": object()})


_TRICKY = [0.1, 0.2, 1 / 3, 2 / 3, math.pi, -math.e, 5e-324, 2.2250738585072014e-308,
           1.7976931348623157e308, -0.0, 0.0, 1e16, 123456789.12345678, 1e-7, 9007199254740993.0,
           float(np.nextafter(1.0, 2.0)), float(np.nextafter(1.0, 0.0))]


def test_dumps_float64_round_trip_bit_exact() -> None:
    rng = np.random.default_rng(7)
    values = np.concatenate([
        np.array(_TRICKY),
        rng.standard_normal(500) * 10.0 ** rng.integers(-300, 300, 500),
        rng.random(500),
    ])
    for encoded in (jsonio.dumps(values), jsonio.dumps(values.tolist()),
                    jsonio.dumps([np.float64(v) for v in values])):
        back = np.array(json.loads(encoded), dtype=np.float64)
        assert back.tobytes() == values.tobytes()
        back = np.array(jsonio.loads(encoded), dtype=np.float64)
        assert back.tobytes() == values.tobytes()
    for x in _TRICKY:  # shortest repr: each number is written as Python writes it
        text = jsonio.dumps(x).decode()
        assert struct.pack("<d", float(text)) == struct.pack("<d", x), (x, text)


def test_json_response_renders_numpy() -> None:
    r = jsonio.JSONResponse({"a": np.arange(3)}, status_code=201)
    assert r.status_code == 201 and r.media_type == "application/json"
    assert json.loads(r.body) == {"a": [0, 1, 2]}


# -- problems ------------------------------------------------------------------------------
def test_problem_body() -> None:
    body = problem_body("no-such-job", "No job 'x'.")
    assert body == {"type": "http://www.opengis.net/def/exceptions/ogcapi-processes-1/1.0/"
                            "no-such-job", "title": "No such job", "status": 404,
                    "detail": "No job 'x'."}
    body = problem_body("invalid-input", "bad", instance="/processes/a/execution",
                        errors=[{"input": "k", "message": "too small"}], status=400)
    assert body["status"] == 400 and body["instance"] == "/processes/a/execution"
    assert body["errors"] == [{"input": "k", "message": "too small"}]
    assert "errors" not in problem_body("invalid-input", "bad", errors=[])
    with pytest.raises(KeyError):
        problem_body("no-such-slug", "x")
    json.dumps(body)


def test_problem_registry() -> None:
    for slug, p in PROBLEMS.items():
        ogc = slug in ("no-such-process", "no-such-job", "result-not-ready")  # the standard's
        assert p.slug == slug and p.uri == (
            f"http://www.opengis.net/def/exceptions/ogcapi-processes-1/1.0/{slug}" if ogc
            else f"/problems/{slug}")
        assert 400 <= p.status < 600 and p.title and p.description
        assert problem_body(slug, "d")["status"] == p.status


def test_geometry_error_problem() -> None:
    body = geometry_error_problem(DegenerateInputError("All points coincide.", field="source"))
    assert body["status"] == 422 and body["type"] == "/problems/invalid-input"
    assert body["errors"] == [{"input": "source", "message": "All points coincide."}]
    assert "errors" not in geometry_error_problem(InvalidInputError("no field"))


def test_pydantic_errors_cross_input_names_its_field() -> None:
    p = registry["alignment.rigid"]
    square = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]
    with pytest.raises(ValidationError) as info:  # model_validator: paired shapes
        p.params.model_validate({"source": square, "target": [r[:2] for r in square]})
    errors = pydantic_errors(info.value.errors())
    assert len(errors) == 1 and errors[0]["input"] == "target"
    assert errors[0]["message"].startswith("Expected `target`")  # no "Value error, "
    with pytest.raises(ValidationError) as info:
        p.params.model_validate({"source": square, "target": square, "weights": [1, 2]})
    assert [e["input"] for e in pydantic_errors(info.value.errors())] == ["weights"]
    # with a prefix, as for a nested location
    assert pydantic_errors(info.value.errors(), prefix=("inputs",))[0]["input"] == \
        "inputs.weights"


def test_pydantic_errors_field_errors() -> None:
    p = registry["assignment.nearest"]
    with pytest.raises(ValidationError) as info:
        p.params.model_validate({"source": [[0.0, 0.0]], "target": [[1.0, 1.0]], "k": "2",
                                 "bogus": 1})
    errors = pydantic_errors(info.value.errors())
    assert {e["input"] for e in errors} == {"k", "bogus"}
    assert all(e["message"] and not e["message"].startswith("Value error") for e in errors)
    with pytest.raises(ValidationError) as info:
        p.params.model_validate({"source": [[0.0, math.nan]], "target": [[1.0, 1.0]]})
    (err,) = pydantic_errors(info.value.errors())
    assert err["input"] == "source" and "nan" in err["message"]


def test_pydantic_errors_request_locations() -> None:
    errors = [{"loc": ("query", "limit"), "msg": "Input should be greater than 0"},
              {"loc": ("body",), "msg": "Field required"},
              {"loc": ("path", "jobId", 0), "msg": "Value error, bad"}]
    assert pydantic_errors(errors) == [
        {"input": "limit", "message": "Input should be greater than 0"},
        {"input": "body", "message": "Field required"},
        {"input": "jobId.0", "message": "bad"}]


# -- statusInfo and results documents ------------------------------------------------------
def _record(**kw: Any) -> JobRecord:
    base = dict(id="j-1", process="alignment.rigid", status="accepted", message="",
                progress=0, created=1_700_000_000.0, started=None, finished=None,
                updated=1_700_000_000.25, request=JobRequest(), problem=None, time_limit=None,
                idempotency_key=None, request_hash=None, attempts=0, inputs_file=None)
    return JobRecord(**{**base, **kw})


def test_iso() -> None:
    assert iso(None) is None
    assert iso(0.0) == "1970-01-01T00:00:00.000Z"
    assert iso(1_700_000_000.25) == "2023-11-14T22:13:20.250Z"


@pytest.mark.parametrize("status", ["accepted", "running", "successful", "failed",
                                    "dismissed"])
def test_status_info(status: str) -> None:
    done = status in ("successful", "failed", "dismissed")
    job = _record(status=status, message=status, progress=100 if status == "successful" else 5,
                  started=None if status == "accepted" else 1_700_000_001.0,
                  finished=1_700_000_002.5 if done else None)
    info = status_info(job)
    assert info["jobID"] == "j-1" and info["processID"] == "alignment.rigid"
    assert info["type"] == "process" and info["status"] == status
    assert info["message"] == status and info["progress"] == job.progress
    for key in ("created", "started", "finished", "updated"):
        value = info.get(key)
        if getattr(job, key) is None:
            assert key not in info  # omitted, not null (the standard's statusInfo.yaml)
        else:
            assert value.endswith("Z") and "+" not in value, value
    assert info["created"] == "2023-11-14T22:13:20.000Z"
    rels = [link["rel"] for link in info["links"]]
    assert rels[:3] == ["self", "monitor", "up"]
    assert info["links"][0]["href"] == info["links"][1]["href"] == "/jobs/j-1"
    assert info["links"][2]["href"] == "/processes/alignment.rigid"
    # the job's page: one alternate, HTML, the status's URL with f=html
    assert [link for link in info["links"] if link["rel"] == "alternate"] == [
        {"href": "/jobs/j-1?f=html", "rel": "alternate", "type": "text/html",
         "title": "this job's status as a web page"}]
    if status == "successful":
        assert rels.count("results") == 1
        (results,) = [link for link in info["links"] if link["rel"] == "results"]
        assert results["href"] == "/jobs/j-1/results"
        ogc_rel = "http://www.opengis.net/def/rel/ogc/1.0/results"
        assert [link["href"] for link in info["links"] if link["rel"] == ogc_rel] == \
            ["/jobs/j-1/results"]
    else:
        assert "results" not in rels
    assert type(info["status"]) is str and isinstance(job.status, JobStatus)
    json.loads(jsonio.dumps(info))


def test_the_documented_statuses_are_the_enum() -> None:
    """The OpenAPI document's status enum (a Literal, so that it stays inline) is
    :class:`JobStatus`, in the same order."""
    assert list(get_args(docs.StatusName)) == [str(s) for s in JobStatus]


_OUTPUTS = {"rotation": np.eye(3), "translation": np.zeros(3), "rmse": 0.5,
            "reflection": False}


def test_results_document_all_outputs() -> None:
    for request in (JobRequest(), JobRequest(outputs=None, response="document"),
                    JobRequest(outputs=())):
        doc = results_document(_OUTPUTS, request)
        assert list(doc) == list(_OUTPUTS)
        assert doc["rotation"] is _OUTPUTS["rotation"]  # values stay numpy


def test_results_document_subset() -> None:
    doc = results_document(_OUTPUTS, JobRequest(outputs=("rmse", "rotation")))
    assert doc == {"rmse": 0.5, "rotation": _OUTPUTS["rotation"]}
    assert results_document(_OUTPUTS, JobRequest(outputs=("rmse", "nope"))) == {"rmse": 0.5}


def test_results_document_raw() -> None:
    assert results_document(_OUTPUTS, JobRequest(outputs=("rmse",), response="raw")) == 0.5
    raw = results_document(_OUTPUTS, JobRequest(outputs=("rotation",), response="raw"))
    assert raw is _OUTPUTS["rotation"]
    assert json.loads(jsonio.dumps(raw)) == np.eye(3).tolist()
    # raw with several outputs stays a document
    doc = results_document(_OUTPUTS, JobRequest(outputs=("rmse", "reflection"),
                                                 response="raw"))
    assert doc == {"rmse": 0.5, "reflection": False}
    assert results_document({"rmse": 1.0}, JobRequest(response="raw")) == 1.0


# -- results must be finite ------------------------------------------------------------------


def test_nan_anywhere_in_a_result_is_refused() -> None:
    from algorithms.core.mesh import Mesh
    from service.jobs.runner import _check_finite

    good = Mesh(vertices=np.zeros((3, 3)), faces=np.array([[0, 1, 2]]))
    _check_finite({"mesh": good, "energy": [1.0, 0.5], "rmse": 0.0, "pairs": np.ones((2, 2), int)})
    bad_vertices = np.zeros((3, 3))
    bad_vertices[1, 2] = np.nan
    cases = [
        ({"mesh": Mesh(vertices=bad_vertices, faces=good.faces)}, "'mesh.vertices'"),
        ({"energy": [1.0, float("inf")]}, "'energy'"),
        ({"rmse": float("nan")}, "'rmse'"),
        ({"transform": np.array([[1.0, np.inf]])}, "'transform'"),
    ]
    for outputs, name in cases:
        with pytest.raises(FloatingPointError, match=name):
            _check_finite(outputs)
