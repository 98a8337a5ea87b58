"""The standard's own schema files, vendored in ``standard_schemas/`` with their licence: they
are the standard's, every ``$ref`` in them resolves to one of them, each definition of ours
has its file, and each relaxation of :data:`tests.service.ogc.vendored.RELAXED` is needed
(the file as written refuses a document the standard's text allows) and is only that (the
relaxed files still refuse what the standard forbids). No server."""

from __future__ import annotations

import re
from typing import Any

import pytest

from tests.service.ogc import vendored
from tests.service.ogc.schemas import DEFINITIONS

#: The files of core/openapi/schemas/ (branch 1.0.0-maintenance), the swagger/ variants apart.
STANDARD_FILES = {
    "additionalParameter", "bbox", "binaryInputValue", "confClasses", "descriptionType",
    "exception", "execute", "format", "inlineOrRefData", "inputDescription", "inputValue",
    "inputValueNoObject", "jobControlOptions", "jobList", "landingPage", "link", "metadata",
    "output", "outputDescription", "process", "processList", "processSummary",
    "qualifiedInputValue", "reference", "results", "schema", "statusCode", "statusInfo",
    "subscriber", "transmissionMode",
}


def _refs(node: Any) -> set[str]:
    if isinstance(node, dict):
        found = {node["$ref"]} if isinstance(node.get("$ref"), str) else set()
        for key, value in node.items():
            if key != "example":
                found |= _refs(value)
        return found
    if isinstance(node, list):
        return set().union(*map(_refs, node)) if node else set()
    return set()


def test_the_files_are_the_standards_with_their_licence() -> None:
    assert {p.stem for p in vendored.DIRECTORY.glob("*.yaml")} == STANDARD_FILES
    licence = (vendored.DIRECTORY / "LICENSE").read_text(encoding="utf-8")
    assert licence.startswith('Permission is hereby granted by the Open Geospatial Consortium')
    readme = (vendored.DIRECTORY / "README.md").read_text(encoding="utf-8")
    assert "opengeospatial/ogcapi-processes" in readme and "1.0.0-maintenance" in readme
    assert re.search(r"commit `[0-9a-f]{40}`", readme)


def test_every_reference_resolves_to_a_vendored_file() -> None:
    """Every ``$ref`` of every file names a vendored file (relative to the published base),
    so validation never needs the network; and every file is reached from a definition."""
    reached: set[str] = set()
    todo = [target.split("#")[0] for target in vendored.FILES.values()]
    while todo:
        name = todo.pop()
        if name in reached:
            continue
        assert (vendored.DIRECTORY / name).is_file(), name
        reached.add(name)
        for ref in _refs(vendored.load(name, as_written=True)):
            assert not ref.startswith(("http:", "https:", "#")), (name, ref)
            todo.append(ref)
    assert {n.removesuffix(".yaml") for n in reached} == STANDARD_FILES


def test_every_definition_of_ours_has_the_standards_file() -> None:
    assert set(vendored.FILES) == set(DEFINITIONS) - {"links"}
    for name in vendored.FILES:
        vendored.validator(name)
        vendored.validator(name, as_written=True)


_ARRAY_WITH = {"type": "array", "items": {"type": "number"}}
_REF = {"$ref": "#/components/schemas/Point"}


def _process(schema: dict[str, Any]) -> dict[str, Any]:
    return {"id": "p", "version": "1.0.0",
            "inputs": {"points": {"title": "Points", "schema": schema}},
            "outputs": {"n": {"schema": {"type": "integer"}}}}


#: For each entry of RELAXED, in its order: a document the standard's text allows that the
#: file, with that relaxation alone undone, refuses.
NEEDS = [
    ("bare_value", 3),  # inputValueNoObject.yaml: an integer (also "abc", below)
    ("any_value", {"bbox": [0.0, 0.0, 1.0, 1.0]}),  # inputValue.yaml
    ("additional_parameter", {"name": "n", "value": [3]}),  # additionalParameter.yaml
    ("execute", {"inputs": {"points": [[0.0, 1.0], [2.0, 3.0]]}}),  # execute.yaml
    ("process", _process({"not": _REF})),  # schema.yaml, nested references
    ("process", _process({"allOf": [_REF]})),
    ("process", _process({"oneOf": [_REF, _ARRAY_WITH]})),
    ("process", _process({"anyOf": [_REF, _ARRAY_WITH]})),
    ("process", _process({"type": "array", "items": _REF})),
    ("process", _process({"type": "object", "properties": {"p": _REF}})),
    ("process", _process({"type": "object", "additionalProperties": _REF})),
    ("subscriber", {"successUri": "http://h/done"}),  # subscriber.yaml
]


def test_one_case_for_each_relaxation() -> None:
    assert len(NEEDS) == len(vendored.RELAXED)


@pytest.mark.parametrize("index", range(len(NEEDS)),
                         ids=[f"{r[0]}{r[1] or '/'}" for r in vendored.RELAXED])
def test_each_relaxation_is_needed(index: int) -> None:
    name, document = NEEDS[index]
    assert vendored.errors(name, document) == []
    assert vendored.errors(name, document, unrelaxed=index), (vendored.RELAXED[index][3])
    assert vendored.errors(name, document, as_written=True)


def test_the_overlaps_as_written() -> None:
    """The overlaps :mod:`tests.service.ogc.schemas` names, in the standard's files as they
    are: an integer and a string output, and an array input, are refused as written."""
    for value in (3, "abc"):
        assert vendored.errors("results", {"o": value}, as_written=True), value
        assert vendored.errors("results", {"o": value}) == []
    assert vendored.errors("results", {"o": 0.5, "b": True, "a": [1.5]}, as_written=True) == []


_STATUS = {"jobID": "j1", "status": "running", "type": "process"}


@pytest.mark.parametrize(("name", "document", "where"), [
    ("status_info", {**_STATUS, "started": None}, "started"),
    ("status_info", {**_STATUS, "status": "done"}, "status"),
    ("status_info", {**_STATUS, "progress": 101}, "progress"),
    ("status_info", {**_STATUS, "created": "2 January 2026"}, "created"),
    ("status_info", {"status": "running", "type": "process"}, ""),
    ("results", {"n": None}, "n"),
    ("results", {"mesh": {"vertices": [[0.0, 0.0, 0.0]], "faces": []}}, "mesh"),
    ("process", _process({"type": "array", "examples": [[1.0]]}), "inputs/points/schema"),
    ("process", _process({"type": "null"}), "inputs/points/schema"),
    ("process", _process({"type": ["number", "null"]}), "inputs/points/schema"),
    ("process", _process({"type": "number", "exclusiveMinimum": 0}), "inputs/points/schema"),
    ("process_list", {"processes": []}, ""),
    ("subscriber", {"successUrl": "http://h/done"}, ""),
    ("exception", {"title": "no type"}, ""),
])
def test_the_relaxed_files_still_refuse(name: str, document: Any, where: str) -> None:
    found = vendored.errors(name, document)
    assert any(line.startswith(where + ":") or line.startswith(where + "/")
               for line in found), found
