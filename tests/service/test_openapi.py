"""The OpenAPI document: committed copy up to date, stable operation ids, problem+json errors."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

from service.openapi import render

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
    assert set(ids) == OPERATION_IDS


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
    codes = {op: set() for op in OPERATION_IDS}
    for op, code, _ in _error_responses(doc):
        codes[op].add(code)
    assert {"400", "404", "413", "415", "422", "429"} <= codes["execute"]
    assert {"404", "410"} <= codes["getResult"]
    assert "404" in codes["getStatus"] and "404" in codes["dismiss"]
    assert "503" in codes["getReadiness"]


def test_every_error_response_uses_problem_json(doc: dict[str, Any]) -> None:
    """Every documented 4xx/5xx response is problem+json with the Problem schema, and only
    that (FastAPI's own 422 model included)."""
    bad = [f"{op} {code}" for op, code, response in _error_responses(doc)
           if response.get("content") != {"application/problem+json": {"schema": {
               "$ref": "#/components/schemas/Problem"}}}]
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
