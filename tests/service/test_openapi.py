"""The OpenAPI document: committed copy up to date, stable operation ids, problem+json errors,
one execute operation per process (its input model, its example, which runs), and /docs, the
Swagger UI the service serves itself."""

from __future__ import annotations

import json
from html.parser import HTMLParser
from pathlib import Path
from typing import Any

import httpx
import pytest

from service.catalog import FAMILIES, Process, processes, registry
from service.openapi import GENERIC_EXECUTE, operation_id, render
from service.routes import apidocs
from tests.live import LiveServer

COMMITTED = Path(__file__).resolve().parents[2] / "openapi" / "openapi.json"

OPERATION_IDS = {"getLandingPage", "getConformanceClasses", "getHealth", "getReadiness",
                 "getMetrics", "getProcesses", "getProcessDescription", "execute", "getJobs",
                 "getStatus", "getResult", "getResultOutput", "dismiss"}

_METHODS = {"get", "put", "post", "delete", "options", "head", "patch", "trace"}


@pytest.fixture(scope="module")
def rendered() -> str:
    return render()


@pytest.fixture(scope="module")
def doc(rendered: str) -> dict[str, Any]:
    return json.loads(rendered)


def _operations(doc: dict[str, Any]) -> list[tuple[str, str, dict[str, Any]]]:
    return [(method, path, op) for path, item in doc["paths"].items()
            for method, op in item.items() if method in _METHODS]


def _error_responses(doc: dict[str, Any]) -> list[tuple[str, str, dict[str, Any]]]:
    return [(op.get("operationId", f"{method} {path}"), code, response)
            for method, path, op in _operations(doc)
            for code, response in op.get("responses", {}).items()
            if code[0] in "45"]


def test_committed_document_is_current(rendered: str) -> None:
    assert COMMITTED.is_file(), "openapi/openapi.json is missing: run `make openapi`"
    committed = COMMITTED.read_text(encoding="utf-8")
    if committed != rendered:
        pytest.fail("openapi/openapi.json is stale: run `make openapi`", pytrace=False)


def test_render_is_deterministic(rendered: str) -> None:
    assert render() == rendered
    assert rendered.endswith("}\n")


def test_document_basics(doc: dict[str, Any]) -> None:
    assert doc["openapi"].startswith("3.")
    assert doc["info"]["title"] == "morphserve" and doc["info"]["version"]
    assert "Problem" in doc["components"]["schemas"]


def test_operation_ids_are_the_stable_set(doc: dict[str, Any]) -> None:
    ops = _operations(doc)
    missing = [f"{m.upper()} {p}" for m, p, op in ops if not op.get("operationId")]
    assert not missing, f"operations without an operationId: {missing}"
    ids = [op["operationId"] for _, _, op in ops]
    assert len(ids) == len(set(ids)), f"duplicate operationIds: {sorted(ids)}"
    assert set(ids) == OPERATION_IDS | {f"execute_{p.id}" for p in processes()}


def test_operations_where_expected(doc: dict[str, Any]) -> None:
    where = {op["operationId"]: (m, p) for m, p, op in _operations(doc)}
    assert where["execute"] == ("post", "/processes/{processId}/execution")
    assert where["getProcessDescription"] == ("get", "/processes/{processId}")
    assert where["getJobs"] == ("get", "/jobs")
    assert where["getStatus"] == ("get", "/jobs/{jobId}")
    assert where["getResult"] == ("get", "/jobs/{jobId}/results")
    assert where["dismiss"] == ("delete", "/jobs/{jobId}")
    assert where["getLandingPage"] == ("get", "/")
    assert where["getConformanceClasses"] == ("get", "/conformance")


def test_error_responses_documented(doc: dict[str, Any]) -> None:
    codes: dict[str, set[str]] = {op["operationId"]: set() for _, _, op in _operations(doc)}
    for op, code, _ in _error_responses(doc):
        codes[op].add(code)
    assert {"400", "404", "413", "415", "422", "429"} <= codes["execute"]
    assert {"404", "410"} <= codes["getResult"]
    assert "404" in codes["getStatus"] and "404" in codes["dismiss"]
    assert "503" in codes["getReadiness"]


def test_every_error_response_uses_problem_json(doc: dict[str, Any]) -> None:
    """Every documented 4xx/5xx response is problem+json with the Problem schema, and only
    that (FastAPI's own 422 model included); the operations with an HTML page (service.html)
    also answer a browser's errors as a page."""
    problem = {"application/problem+json": {"schema": {"$ref": "#/components/schemas/Problem"}}}
    pages = {"getLandingPage", "getProcesses", "getProcessDescription", "getJobs", "getStatus"}
    page = {"text/html": {"schema": {"type": "string"}}}
    bad = [f"{op} {code}" for op, code, response in _error_responses(doc)
           if response.get("content") != ({**problem, **page} if op in pages else problem)]
    assert not bad, f"error responses not documented as problem+json: {bad}"
    assert "HTTPValidationError" not in doc["components"]["schemas"]


def test_help_prints_usage_and_writes_nothing(tmp_path: Path, monkeypatch,  # noqa: ANN001
                                              capsys: pytest.CaptureFixture[str]) -> None:
    from service.openapi import main

    monkeypatch.chdir(tmp_path)
    with pytest.raises(SystemExit) as done:
        main(["--help"])
    assert done.value.code == 0
    assert "usage: python -m service.openapi" in capsys.readouterr().out
    assert list(tmp_path.iterdir()) == []  # not a document written to a file named --help
    assert main([str(tmp_path / "doc.json")]) == 0
    assert json.loads((tmp_path / "doc.json").read_text()) == json.loads(render())


# -- one execute operation per process ------------------------------------------------------
def _visible() -> list[Process]:
    return processes(test_processes=False)


def _process_op(doc: dict[str, Any], p: Process) -> dict[str, Any]:
    item = doc["paths"].get(f"/processes/{p.id}/execution")
    assert item is not None and set(item) == {"post"}, f"no execute operation for {p.id}"
    op: dict[str, Any] = item["post"]
    return op


def _resolve(doc: dict[str, Any], schema: dict[str, Any]) -> dict[str, Any]:
    ref = schema.get("$ref")
    if ref is None:
        return schema
    assert ref.startswith("#/components/schemas/"), ref
    resolved: dict[str, Any] = doc["components"]["schemas"][ref.rsplit("/", 1)[1]]
    return resolved


def _body_schema(op: dict[str, Any]) -> dict[str, Any]:
    schema: dict[str, Any] = op["requestBody"]["content"]["application/json"]["schema"]
    return schema


def _example(op: dict[str, Any]) -> dict[str, Any]:
    examples = op["requestBody"]["content"]["application/json"]["examples"]
    assert len(examples) == 1
    value: dict[str, Any] = next(iter(examples.values()))["value"]
    return value


def _validator(doc: dict[str, Any], schema: dict[str, Any]) -> Any:
    """A JSON Schema 2020-12 validator (OpenAPI 3.1's dialect) of ``schema``, whose
    ``#/components/schemas/...`` references resolve in ``doc``."""
    import jsonschema_rs

    return jsonschema_rs.Draft202012Validator({**schema, "components": doc["components"]})


def test_every_visible_process_has_its_operation(doc: dict[str, Any]) -> None:
    per_process = {p: op for p, item in doc["paths"].items()
                   for m, op in item.items() if m == "post" and p != GENERIC_EXECUTE
                   and p.startswith("/processes/")}
    assert set(per_process) == {f"/processes/{p.id}/execution" for p in _visible()}
    for p in _visible():
        op = _process_op(doc, p)
        assert op["operationId"] == f"execute_{p.id}" == operation_id(p)
        assert op["tags"] == [p.family]
        assert op["summary"] == p.title


def test_test_processes_are_not_documented(doc: dict[str, Any]) -> None:
    from service.diagnostics import diagnostics

    assert diagnostics, "no diagnostic process to check"
    text = json.dumps(doc["paths"])
    for pid in diagnostics:
        assert f"/processes/{pid}/" not in text


def test_families_are_tags_in_catalog_order(doc: dict[str, Any]) -> None:
    names = [t["name"] for t in doc["tags"]]
    assert len(names) == len(set(names))
    families = [n for n in names if n in FAMILIES]
    assert families == [f for f in FAMILIES if any(p.family == f for p in _visible())]
    assert names[:3] == ["service", "processes", "jobs"]  # the API's own operations first


def test_request_schema_is_the_input_model(doc: dict[str, Any]) -> None:
    for p in _visible():
        body = _body_schema(_process_op(doc, p))
        assert body["additionalProperties"] is False
        inputs = _resolve(doc, body["properties"]["inputs"])
        assert inputs == p.params.model_json_schema(mode="validation"), p.id
        required = inputs.get("required", [])
        assert set(required) == {n for n, f in p.params.model_fields.items()
                                 if f.is_required()}, p.id
        assert body.get("required", []) == (["inputs"] if required else []), p.id
        wanted = body["properties"]["outputs"]["anyOf"][0]
        assert set(wanted["properties"]) == set(p.outputs), p.id
        assert body["properties"]["response"]["enum"] == ["document", "raw"]


def test_prefer_header_and_responses_as_the_generic_operation(doc: dict[str, Any]) -> None:
    generic = doc["paths"][GENERIC_EXECUTE]["post"]
    prefer = [q for q in generic["parameters"] if q["in"] == "header"]
    assert [q["name"] for q in prefer] == ["Prefer"]
    for p in _visible():
        op = _process_op(doc, p)
        assert [q for q in op["parameters"] if q["in"] == "header"] == prefer, p.id
        assert not [q for q in op["parameters"] if q["in"] == "path"], p.id
        assert set(op["responses"]) == set(generic["responses"]), p.id
        assert op["security"] == generic["security"], p.id


def test_examples_are_the_catalogs_and_valid(doc: dict[str, Any]) -> None:
    for p in _visible():
        op = _process_op(doc, p)
        example = _example(op)
        assert example == {"inputs": json.loads(json.dumps(dict(p.examples)))}, p.id
        validator = _validator(doc, _body_schema(op))
        errors = [e.message for e in validator.iter_errors(example)]
        assert not errors, (p.id, errors[:3])
        for response in op["responses"].values():  # each a valid JSON Schema (or raises)
            for media in response.get("content", {}).values():
                _validator(doc, media["schema"])


def _bad_bodies(good: dict[str, Any]) -> list[dict[str, Any]]:
    """Bodies of registration.icp that break one member the service checks on its own."""
    inputs = good["inputs"]
    return [{**good, "unknown": 1},
            {**good, "inputs": {**inputs, "no_such_input": 1}},
            {**good, "inputs": {k: v for k, v in inputs.items() if k != "source"}},
            {**good, "inputs": {**inputs, "max_iterations": 0}},
            {**good, "inputs": {**inputs, "max_iterations": "30"}},
            {**good, "inputs": {**inputs, "model": "projective"}},
            {**good, "outputs": {"no_such_output": {}}},
            {**good, "outputs": {}},
            {**good, "response": "everything"},
            {**good, "timeLimit": 0},
            {**good, "timeLimit": None},
            {**good, "subscriber": {"successUri": "ftp://x"}},
            {**good, "subscriber": {"successUri": None}},
            {**good, "subscriber": {"elseUri": "http://127.0.0.1/x"}}]


def test_schemas_reject_what_the_service_refuses(doc: dict[str, Any]) -> None:
    """The request schema is as strict as the service on the members it checks alone: an
    unknown member or input, a missing input, a value out of its bounds or choices, an
    unknown output, a wrong response or time limit, a subscriber that is no http(s) URL."""
    op = _process_op(doc, registry["registration.icp"])
    validator = _validator(doc, _body_schema(op))
    good = _example(op)
    assert validator.is_valid(good)
    for bad in _bad_bodies(good):
        assert not validator.is_valid(bad), bad


@pytest.mark.e2e
def test_the_service_refuses_what_the_schema_refuses(live_doc: dict[str, Any],
                                                      http: httpx.Client) -> None:
    """... and the service refuses each of those bodies with 422 naming the member, so that
    a body the schema calls invalid is never run."""
    good = _example(_process_op(live_doc, registry["registration.icp"]))
    for bad in _bad_bodies(good):
        answer = http.post("/processes/registration.icp/execution", json=bad,
                           headers={"Prefer": "wait=60"})
        assert answer.status_code == 422, (bad, answer.text[:500])
        assert answer.headers["content-type"].startswith("application/problem+json")


def test_document_is_openapi_3_1_valid(doc: dict[str, Any]) -> None:
    """The whole document against the OpenAPI 3.1 schema (the OAI's, as schemathesis ships
    it)."""
    import jsonschema_rs
    from schemathesis.specs.openapi.definitions import OPENAPI_31

    errors = [e.message for e in jsonschema_rs.validator_for(OPENAPI_31).iter_errors(doc)]
    assert not errors, errors[:5]


# -- the examples run ---------------------------------------------------------------------
@pytest.fixture(scope="module")
def live_doc(server: LiveServer) -> dict[str, Any]:
    with server.client() as c:
        answer = c.get("/openapi.json")
    assert answer.status_code == 200
    document: dict[str, Any] = answer.json()
    return document


@pytest.mark.e2e
@pytest.mark.parametrize("p", _visible(), ids=lambda p: p.id)
def test_example_runs(p: Process, live_doc: dict[str, Any], http: httpx.Client) -> None:
    """The document's example of each process, sent as it stands to the process's own path
    (what Swagger UI's "Try it out" sends), succeeds: 200 and a results document with every
    output of the process."""
    op = _process_op(live_doc, p)
    (prefer,) = [q["example"] for q in op["parameters"] if q["name"] == "Prefer"]
    answer = http.post(f"/processes/{p.id}/execution", json=_example(op),
                       headers={"Prefer": prefer})
    assert answer.status_code == 200, (p.id, answer.text[:2000])
    results = answer.json()
    assert set(results) == set(p.outputs), p.id
    schema = op["responses"]["200"]["content"]["application/json"]["schema"]
    document = schema["anyOf"][0]  # the results document, not a raw value
    errors = [e.message for e in _validator(live_doc, document).iter_errors(results)]
    assert not errors, (p.id, errors[:3])


# -- /docs: Swagger UI from the service itself -------------------------------------------
class _Refs(HTMLParser):
    """The URLs a page loads: ``src`` and ``href`` attributes, and its inline scripts."""

    def __init__(self) -> None:
        super().__init__()
        self.urls: list[tuple[str, str]] = []  # (tag, url)
        self.scripts: list[str] = []
        self._in_script = False

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        self.urls += [(tag, v) for k, v in attrs if k in ("src", "href") and v is not None]
        self._in_script = tag == "script"

    def handle_endtag(self, tag: str) -> None:
        self._in_script = False

    def handle_data(self, data: str) -> None:
        if self._in_script and data.strip():
            self.scripts.append(data)


_MEDIA = {".js": "text/javascript", ".css": "text/css", ".png": "image/png"}


@pytest.mark.e2e
def test_docs_page_loads_only_local_assets(http: httpx.Client) -> None:
    """/docs is Swagger UI loaded from the service: no absolute URL in the page, every asset
    it names served with 200 and its media type (the vendored file's bytes), the validator
    badge off (it would fetch an image from validator.swagger.io), the document it loads
    served."""
    page = http.get("/docs")
    assert page.status_code == 200
    assert page.headers["content-type"].startswith("text/html")
    assert "http://" not in page.text and "https://" not in page.text
    refs = _Refs()
    refs.feed(page.text)
    assets = [url for _, url in refs.urls]
    assert {a.rsplit("/", 1)[1] for a in assets} == set(apidocs.ASSETS)
    for url in assets:
        assert url.startswith("/") and not url.startswith("//"), url
        answer = http.get(url)
        assert answer.status_code == 200, url
        suffix = Path(url).suffix
        assert answer.headers["content-type"].split(";")[0] == _MEDIA[suffix], url
        assert answer.content == (apidocs.SWAGGER / Path(url).name).read_bytes(), url
    (script,) = refs.scripts
    config = json.loads(script.split("const config = ", 1)[1].split(";\n", 1)[0])
    assert config["validatorUrl"] is None
    assert config["url"] == "/openapi.json"
    assert http.get(config["url"]).status_code == 200
    slash = http.get("/docs/")
    assert slash.status_code == 308 and slash.headers["location"] == "/docs"
    for gone in ("/redoc", "/docs/oauth2-redirect", "/docs/assets/index.html",
                 "/docs/assets/..%2Fswagger%2FLICENSE", "/docs/assets/LICENSE"):
        answer = http.get(gone)
        assert answer.status_code == 404, gone
        assert answer.headers["content-type"].startswith("application/problem+json"), gone


def test_docs_pages_stay_out_of_the_document(doc: dict[str, Any]) -> None:
    assert not [p for p in doc["paths"] if p.startswith(("/docs", "/redoc"))]


def test_swagger_files_are_package_data_with_their_licence() -> None:
    """Every file the page loads, the licence and the version note are in the wheel:
    they match the package-data globs of pyproject.toml."""
    import tomllib

    root = Path(__file__).resolve().parents[2]
    globs = tomllib.loads((root / "pyproject.toml").read_text())["tool"]["setuptools"][
        "package-data"]["service"]
    service = root / "service"
    packaged = {f for g in globs for f in service.glob(g) if f.is_file()}
    for name in (*apidocs.ASSETS, "LICENSE", "NOTICE", "VERSION"):
        assert apidocs.SWAGGER / name in packaged, name
    version = (apidocs.SWAGGER / "VERSION").read_text()
    assert version.startswith("swagger-ui-dist ")
    for name in apidocs.ASSETS:
        assert name in version, name
