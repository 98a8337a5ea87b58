"""The schemas of :mod:`tests.service.ogc.schemas` refuse what the standard forbids and accept
what it means, by hand-written documents (no server)."""

from __future__ import annotations

from typing import Any

import jsonschema_rs
import pytest

from tests.service.ogc.schemas import DEFINITIONS, errors

_STATUS = {"jobID": "j1", "status": "running", "type": "process", "processID": "p",
           "created": "2026-01-02T03:04:05Z", "progress": 40,
           "links": [{"href": "http://h/jobs/j1", "rel": "self"}]}
_INPUT = {"title": "Points", "schema": {"type": "array", "items": {"type": "number"}},
          "minOccurs": 1, "maxOccurs": 1}
_PROCESS = {"id": "p", "version": "1.0.0", "jobControlOptions": ["sync-execute"],
            "outputTransmission": ["value"], "links": [{"href": "http://h/processes/p"}],
            "inputs": {"points": _INPUT},
            "outputs": {"n": {"schema": {"type": "integer", "minimum": 0}}}}


def _with(document: dict[str, Any], **members: Any) -> dict[str, Any]:
    return {**document, **members}


def _input(**schema: Any) -> dict[str, Any]:
    """:data:`_PROCESS` whose input ``points`` has ``schema``."""
    return _with(_PROCESS, inputs={"points": _with(_INPUT, schema=schema)})


@pytest.mark.parametrize(("name", "document"), [
    ("status_info", _STATUS),
    ("status_info", {"jobID": "j", "status": "accepted", "type": "process"}),
    ("job_list", {"jobs": [_STATUS], "links": []}),
    ("process", _PROCESS),
    # a nested reference, which schema.yaml as written refuses (module docstring)
    ("process", _input(type="array", items={"$ref": "#/components/schemas/Point"})),
    ("process", _with(_PROCESS, inputs={"points": _with(_INPUT, maxOccurs="unbounded")})),
    ("process", _input(type="number", minimum=0, exclusiveMinimum=True, nullable=True)),
    ("process_list", {"processes": [_PROCESS], "links": [{"href": "http://h/processes"}]}),
    ("landing_page", {"links": [{"href": "http://h/", "rel": "self"}]}),
    ("conformance", {"conformsTo": ["http://www.opengis.net/spec/ogcapi-processes-1/1.0/conf/core"]}),
    # an integer, a string, an array input: each matches two alternatives of the standard's
    # oneOf as written, and is what it means
    ("execute", {"inputs": {"k": 3, "name": "a", "points": [[0.0, 1.0]],
                            "many": [1, {"value": 2}, {"href": "http://h/x"}]}}),
    ("results", {"n": 3, "s": "text", "r": [1.5], "q": {"value": {"a": 1}}}),
    ("exception", {"type": "http://www.opengis.net/def/exceptions/ogcapi-processes-1/1.0/no-such-job",
                   "status": 404, "extra": [1]}),
])
def test_valid(name: str, document: Any) -> None:
    assert errors(name, document) == []


@pytest.mark.parametrize(("name", "document", "where"), [
    # a member without a value yet is left out, never null
    ("status_info", _with(_STATUS, started=None), "started"),
    ("status_info", _with(_STATUS, finished=None), "finished"),
    ("status_info", _with(_STATUS, message=None), "message"),
    ("status_info", _with(_STATUS, status="done"), "status"),
    ("status_info", _with(_STATUS, type="job"), "type"),
    ("status_info", _with(_STATUS, progress=101), "progress"),
    ("status_info", _with(_STATUS, progress=-1), "progress"),
    ("status_info", _with(_STATUS, progress=40.5), "progress"),
    ("status_info", _with(_STATUS, created="2 January 2026"), "created"),
    ("status_info", _with(_STATUS, updated="2026-01-02"), "updated"),
    ("status_info", {"status": "running", "type": "process"}, ""),
    ("status_info", _with(_STATUS, links=[{"rel": "self"}]), "links/0"),
    ("job_list", {"jobs": [_with(_STATUS, started=None)], "links": []}, "jobs/0/started"),
    ("job_list", {"jobs": []}, ""),
    ("link", {"rel": "self", "type": "application/json"}, ""),
    ("link", {"href": None}, "href"),
    ("landing_page", {"links": [{"rel": "service-desc"}]}, "links/0"),
    ("landing_page", {"title": "no links"}, ""),
    ("conformance", {"conformsTo": [1]}, "conformsTo/0"),
    # input and output schemas are OpenAPI 3.0 schema objects, nothing else
    ("process", _input(type="array", examples=[[1.0]]), "inputs/points/schema"),
    ("process", _input(const="x"), "inputs/points/schema"),
    ("process", _input(type="null"), "inputs/points/schema"),
    ("process", _input(type=["string", "null"]), "inputs/points/schema"),
    ("process", _input(type="number", exclusiveMinimum=0), "inputs/points/schema"),
    ("process", _input(type="array", prefixItems=[{"type": "number"}]), "inputs/points/schema"),
    ("process", _input(type="array", items=[{"type": "number"}]), "inputs/points/schema"),
    ("process", _input(type="object", properties={"x": {"type": "number", "examples": [1]}}),
     "inputs/points/schema"),
    ("process", _input(type="object", **{"$defs": {}}), "inputs/points/schema"),
    ("process", _input(type="string", pattern="("), "inputs/points/schema"),
    ("process", _input(required=[]), "inputs/points/schema"),
    ("process", _with(_PROCESS, inputs={"points": {"title": "no schema"}}), "inputs/points"),
    ("process", _with(_PROCESS, outputs={"n": {"title": "no schema"}}), "outputs/n"),
    ("process", _with(_PROCESS, inputs={"points": _with(_INPUT, maxOccurs="many")}),
     "inputs/points/maxOccurs"),
    ("process", _with(_PROCESS, inputs={"points": _with(_INPUT, minOccurs=0.5)}),
     "inputs/points/minOccurs"),
    ("process", _with(_PROCESS, jobControlOptions=["run"]), "jobControlOptions/0"),
    ("process", _with(_PROCESS, outputTransmission=["stream"]), "outputTransmission/0"),
    ("process", {k: v for k, v in _PROCESS.items() if k != "version"}, ""),
    ("process", _with(_PROCESS, links=[{"rel": "self"}]), "links/0"),
    ("process_list", {"processes": [_with(_PROCESS, id=None)], "links": []},
     "processes/0/id"),
    ("process_list", {"processes": []}, ""),
    ("execute", {"inputs": {"k": None}}, "inputs/k"),
    ("execute", {"inputs": {"k": {"mediaType": "application/json"}}}, "inputs/k"),
    ("execute", {"inputs": {"k": {"bbox": [0, 0, 1, 1, 2]}}}, "inputs/k"),
    ("results", {"n": None}, "n"),
    ("exception", {"title": "no type", "status": 404}, ""),
    ("exception", {"type": "t", "status": "404"}, "status"),
])
def test_invalid(name: str, document: Any, where: str) -> None:
    """Each document breaks one rule of the standard, at ``where``."""
    found = errors(name, document)
    assert found, f"{name} accepted {document}"
    assert any(line.startswith(where + ":") or line.startswith(where + "/")
               for line in found), found


def test_standard_oneof_overlaps() -> None:
    """The overlaps the module's docstring names: written as ``oneOf``, an integer (number
    and integer), a string (string and binary string) and an array input (a value that is an
    array, and a list of values) each match two alternatives and are refused; ours accept
    them."""
    as_written = jsonschema_rs.Draft4Validator({"oneOf": [
        {"type": "string"}, {"type": "number"}, {"type": "integer"},
        {"type": "boolean"}, {"type": "array"}, {"type": "string", "format": "byte"}]})
    for value in (3, "abc"):
        assert not as_written.is_valid(value), value
    execute_input = jsonschema_rs.Draft4Validator({"oneOf": [
        {"type": "array"}, {"type": "array", "items": {}}]})
    assert not execute_input.is_valid([[0.0, 1.0]])
    assert not errors("execute", {"inputs": {"k": 3, "s": "abc", "p": [[0.0, 1.0]]}})


def test_definitions_are_well_formed() -> None:
    """Every definition is a valid JSON Schema and every ``$ref`` in them names one."""
    refs: set[str] = set()

    def walk(node: Any) -> None:
        if isinstance(node, dict):
            if isinstance(node.get("$ref"), str):
                refs.add(node["$ref"].removeprefix("#/$defs/"))
            for key, value in node.items():
                if key != "properties":
                    walk(value)
                else:
                    for sub in value.values():
                        walk(sub)
        elif isinstance(node, list):
            for item in node:
                walk(item)

    walk(DEFINITIONS)
    assert refs <= set(DEFINITIONS), refs - set(DEFINITIONS)
    for name, schema in DEFINITIONS.items():
        assert jsonschema_rs.meta.is_valid(
            {"$schema": "https://json-schema.org/draft/2020-12/schema", **schema}), name
