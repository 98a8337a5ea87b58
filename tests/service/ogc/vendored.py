"""The standard's own schema files (``standard_schemas/``, vendored with their licence), as a
validator of the service's documents.

OGC API – Processes 1.0 names one schema file of ``core/openapi/schemas/`` for each document
(``statusInfo.yaml`` for a job's status, ``results.yaml`` for a results document, ...). Those
files are OpenAPI 3.0 schema objects, which are JSON Schema of draft 4's kind (a boolean
``exclusiveMinimum``, a ``$ref`` that overrides its siblings; ``nullable`` and ``example``
are annotations a draft 4 validator ignores), so they are read here as draft 4 with
``jsonschema_rs``, their relative ``$ref``\\ s resolved against the URI they are published at,
from the vendored copies (no network).

Some of them are broken as written, and :data:`RELAXED` lists each place and why; what is
changed there is the smallest change that makes the file say what the standard's text says
(a ``oneOf`` whose alternatives overlap becomes an ``anyOf``; a misspelt required member is
spelt as the member is named). The change is made in memory when a file is loaded: the files
themselves stay as the OGC publishes them. :func:`validator` with ``as_written=True`` gives
the files unrelaxed, so that the tests can show that each relaxation is needed.

:func:`tests.service.ogc.schemas.errors`, which every ported test of the suite uses, checks a
document against these files (relaxed) as well as against our own definitions.
"""

from __future__ import annotations

import copy
from functools import cache
from pathlib import Path
from typing import Any

import jsonschema_rs
import yaml

__all__ = ["BASE", "DIRECTORY", "FILES", "RELAXED", "errors", "load", "validator"]

DIRECTORY = Path(__file__).resolve().with_name("standard_schemas")

#: Where the OGC publishes the files: the base URI of their ``$ref``\ s.
BASE = "http://schemas.opengis.net/ogcapi/processes/part1/1.0/openapi/schemas/"

#: The standard's file (and place in it) for each definition of
#: :data:`tests.service.ogc.schemas.DEFINITIONS`; ``links`` (a list of links, our shorthand)
#: has none of its own.
FILES: dict[str, str] = {
    "link": "link.yaml",
    "landing_page": "landingPage.yaml",
    "conformance": "confClasses.yaml",
    "metadata": "metadata.yaml",
    "additional_parameter": "additionalParameter.yaml",
    "described": "descriptionType.yaml",
    "job_control": "jobControlOptions.yaml",
    "transmission": "transmissionMode.yaml",
    "process_summary": "processSummary.yaml",
    "process_list": "processList.yaml",
    "process": "process.yaml",
    "input_description": "inputDescription.yaml",
    "output_description": "outputDescription.yaml",
    "schema_or_reference": "schema.yaml",
    "reference": "reference.yaml",
    "schema": "schema.yaml#/oneOf/1",
    "bbox": "bbox.yaml",
    "bare_value": "inputValueNoObject.yaml",
    "any_value": "inputValue.yaml",
    "format": "format.yaml",
    "qualified_value": "qualifiedInputValue.yaml",
    "inline_or_reference": "inlineOrRefData.yaml",
    "output": "output.yaml",
    "subscriber": "subscriber.yaml",
    "execute": "execute.yaml",
    "results": "results.yaml",
    "status_info": "statusInfo.yaml",
    "job_list": "jobList.yaml",
    "exception": "exception.yaml",
}

_SCHEMA_OBJECT = "/oneOf/1/properties"
_NESTED_REFERENCE = (
    "a nested schema that is a reference matches both alternatives (schema.yaml admits a "
    "reference itself, and reference.yaml is one), so every nested $ref is refused; meant: "
    "a schema object or a reference")

#: The places where a file is broken as written: (file, JSON pointer, change, why). The
#: change is ``"anyOf"`` (the ``oneOf`` at the pointer becomes an ``anyOf``) or
#: ``"successUri"`` (the required member's name).
RELAXED: tuple[tuple[str, str, str, str], ...] = (
    ("inputValueNoObject.yaml", "", "anyOf",
     "every string is a string and a binary (base64) string, every integer a number and an "
     "integer: an ordinary string or integer value matches two alternatives and is refused; "
     "meant: a value of any of these kinds"),
    ("inputValue.yaml", "", "anyOf",
     "a bounding box is a bare value (inputValueNoObject.yaml) and an object: it matches "
     "both and is refused; meant: any value"),
    ("additionalParameter.yaml", "/properties/value/items", "anyOf",
     "an integer parameter value is a number and an integer; meant: any of these kinds"),
    ("execute.yaml", "/properties/inputs/additionalProperties", "anyOf",
     "an input whose value is an array (a point set) is one value and a list of values: "
     "it matches both and is refused; meant: either"),
    ("schema.yaml", f"{_SCHEMA_OBJECT}/not", "anyOf", _NESTED_REFERENCE),
    ("schema.yaml", f"{_SCHEMA_OBJECT}/allOf/items", "anyOf", _NESTED_REFERENCE),
    ("schema.yaml", f"{_SCHEMA_OBJECT}/oneOf/items", "anyOf", _NESTED_REFERENCE),
    ("schema.yaml", f"{_SCHEMA_OBJECT}/anyOf/items", "anyOf", _NESTED_REFERENCE),
    ("schema.yaml", f"{_SCHEMA_OBJECT}/items", "anyOf", _NESTED_REFERENCE),
    ("schema.yaml", f"{_SCHEMA_OBJECT}/properties/additionalProperties", "anyOf",
     _NESTED_REFERENCE),
    ("schema.yaml", f"{_SCHEMA_OBJECT}/additionalProperties", "anyOf", _NESTED_REFERENCE),
    ("subscriber.yaml", "/required", "successUri",
     "the file requires `successUrl` while it names the member `successUri` (as the "
     "standard's text does): no subscriber can be valid; meant: `successUri`"),
)


def _at(document: Any, pointer: str) -> Any:
    node = document
    for part in filter(None, pointer.split("/")):
        node = node[int(part)] if isinstance(node, list) else node[part]
    return node


@cache
def _files(as_written: bool, unrelaxed: int | None = None) -> dict[str, Any]:
    """Every vendored file by its published URI, relaxed unless ``as_written`` (all but the
    relaxation ``RELAXED[unrelaxed]``, when given)."""
    out = {BASE + path.name: yaml.safe_load(path.read_text(encoding="utf-8"))
           for path in sorted(DIRECTORY.glob("*.yaml"))}
    if not as_written:
        out = copy.deepcopy(out)
        for i, (name, pointer, change, _why) in enumerate(RELAXED):
            if i == unrelaxed:
                continue
            node = _at(out[BASE + name], pointer)
            if change == "anyOf":
                # the file must still say what the relaxation is about: a changed upstream
                # file is noticed here, not silently relaxed elsewhere
                assert isinstance(node, dict) and "oneOf" in node, (name, pointer)
                node["anyOf"] = node.pop("oneOf")
            else:
                assert node == ["successUrl"], (name, pointer, node)
                node[:] = [change]
    return out


def load(name: str, as_written: bool = False) -> Any:
    """The content of the vendored file ``name`` (``"statusInfo.yaml"``)."""
    return _files(as_written)[BASE + name]


@cache
def validator(name: str, as_written: bool = False, unrelaxed: int | None = None) -> Any:
    """A draft 4 validator of the standard's document ``name`` (a key of :data:`FILES`, or a
    file name with an optional ``#`` pointer), checking formats too; the files as written,
    or relaxed as :data:`RELAXED` says (all but ``RELAXED[unrelaxed]``, when given)."""
    target = FILES.get(name, name)
    files = _files(as_written, unrelaxed)

    def retrieve(uri: str) -> Any:
        try:
            return files[uri]
        except KeyError:
            raise ValueError(f"not a vendored file of the standard: {uri}") from None

    return jsonschema_rs.Draft4Validator({"$ref": BASE + target}, retriever=retrieve,
                                         base_uri=BASE, validate_formats=True)


def errors(name: str, document: Any, as_written: bool = False,
           unrelaxed: int | None = None) -> list[str]:
    """What makes ``document`` invalid as the standard's file for ``name`` says: one line
    per error, ``path: [file] message``; empty when it is valid, and when ``name`` has no
    file of its own (``links``)."""
    if name not in FILES:
        return []
    where = FILES[name]
    return [f"{'/'.join(map(str, e.instance_path))}: [{where}] {e.message}"
            for e in validator(name, as_written, unrelaxed).iter_errors(document)]
