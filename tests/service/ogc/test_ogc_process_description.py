"""Port of the suite's ``OGCProcessDescription`` class (/conf/ogc-process-description).

The suite checks at most five processes; these tests check every process the service
offers."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import pytest

from service.catalog import processes
from tests.service.ogc.standard import errors, json_of

pytestmark = pytest.mark.e2e

OFFERED = [p.id for p in processes(test_processes=True)]
_TYPES = {"array", "boolean", "integer", "number", "object", "string"}


@pytest.fixture(scope="module")
def descriptions(server) -> dict[str, dict[str, Any]]:  # noqa: ANN001
    with server.client() as http:
        return {pid: json_of(http.get(f"/processes/{pid}",
                                      headers={"Accept": "application/json"}))
                for pid in OFFERED}


def _schemas(schema: Any) -> Iterator[dict[str, Any]]:
    """``schema`` and every schema nested in it."""
    if not isinstance(schema, dict):
        return
    yield schema
    for key in ("items", "additionalProperties", "not"):
        yield from _schemas(schema.get(key))
    for key in ("oneOf", "anyOf", "allOf"):
        for sub in schema.get(key, []):
            yield from _schemas(sub)
    for sub in schema.get("properties", {}).values():
        yield from _schemas(sub)


def test_ogc_process_description_json(descriptions) -> None:  # noqa: ANN001
    """/req/ogc-process-description/json-encoding: every process description is valid
    against the standard's process.yaml (whose input and output schemas must be OpenAPI 3.0
    schema objects, schema.yaml: no `examples`, no `const`, no `$defs`, no
    `{"type": "null"}`, boolean `exclusiveMinimum`)."""
    bad = {pid: found[:3] for pid, doc in descriptions.items()
           if (found := errors("process", doc))}
    assert not bad, bad


def test_ogc_process_description_inputs_def(descriptions) -> None:  # noqa: ANN001
    """/req/ogc-process-description/inputs-def: each description has an ``inputs`` member,
    an object of input descriptions keyed by input id, with the ``minOccurs`` and
    ``maxOccurs`` of each."""
    for pid, doc in descriptions.items():
        assert isinstance(doc.get("inputs"), dict) and doc["inputs"], pid
        for name, inp in doc["inputs"].items():
            assert inp["minOccurs"] in (0, 1) and inp["maxOccurs"] == 1, (pid, name)


def test_ogc_process_description_input_def(descriptions) -> None:  # noqa: ANN001
    """/req/ogc-process-description/input-def: each input has a ``schema`` (an OpenAPI 3.0
    schema object); an optional input says what it takes when left out (a default, or its
    description) and never as ``"default": null``."""
    for pid, doc in descriptions.items():
        for name, inp in doc["inputs"].items():
            assert "schema" in inp, (pid, name)
            assert not errors("schema_or_reference", inp["schema"]), (pid, name)
            for s in _schemas(inp["schema"]):
                assert "examples" not in s and s.get("type", "string") in _TYPES, (pid, name)
                assert "default" not in s or s["default"] is not None, (pid, name)


def test_ogc_process_description_input_definition_of_mixed_type(descriptions) -> None:  # noqa: ANN001
    """/req/ogc-process-description/input-mixed-type: an input that takes values of more
    than one kind declares them with ``oneOf`` (never ``anyOf`` or a list of types). The
    suite skips when the tested processes have no such input; the service has some (a
    point set or a mesh), and this test fails if none were found."""
    mixed = []
    for pid, doc in descriptions.items():
        for name, inp in doc["inputs"].items():
            for s in _schemas(inp["schema"]):
                assert "anyOf" not in s and not isinstance(s.get("type"), list), (pid, name)
            if "oneOf" in inp["schema"]:
                mixed.append((pid, name))
                assert len(inp["schema"]["oneOf"]) >= 2, (pid, name)
    assert ("interpolation.affine", "source") in mixed, mixed


def test_ogc_process_description_outputs_def(descriptions) -> None:  # noqa: ANN001
    """/req/ogc-process-description/outputs-def: each description has an ``outputs``
    member, an object of output descriptions keyed by output id."""
    for pid, doc in descriptions.items():
        assert isinstance(doc.get("outputs"), dict) and doc["outputs"], pid


def test_ogc_process_description_output_def(descriptions) -> None:  # noqa: ANN001
    """/req/ogc-process-description/output-def: each output has a ``schema``, an OpenAPI
    3.0 schema object (schema.yaml)."""
    for pid, doc in descriptions.items():
        for name, out in doc["outputs"].items():
            assert "schema" in out, (pid, name)
            assert not errors("schema_or_reference", out["schema"]), (pid, name)


def test_ogc_process_description_output_definition_of_mixed_type(descriptions) -> None:  # noqa: ANN001
    """/req/ogc-process-description/output-mixed-type: an output of more than one kind
    declares them with ``oneOf``. No output of the service is of more than one kind (each
    names one type, possibly nullable): the requirement applies to none, which this test
    checks, so that an output of mixed type added later must come with ``oneOf``."""
    for pid, doc in descriptions.items():
        for name, out in doc["outputs"].items():
            schema = out["schema"]
            for s in _schemas(schema):
                assert "anyOf" not in s and not isinstance(s.get("type"), list), (pid, name)
            assert schema.get("type") in _TYPES or len(schema.get("oneOf", [])) >= 2, \
                (pid, name, schema)
