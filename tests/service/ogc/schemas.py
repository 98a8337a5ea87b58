"""What OGC API – Processes – Part 1: Core (1.0) requires of its JSON documents, written
as JSON Schemas (draft 2020-12) of our own.

The standard states the content of each response and request body by naming one of its
OpenAPI 3.0 schema files (``core/openapi/schemas/*.yaml``, branch ``1.0.0-maintenance``).
Each definition below says the same thing about a document, in our own arrangement: one
``$defs`` table, read through :func:`validator`. The comment above each definition names
the requirement that calls for it and the standard's schema it corresponds to.

Where the standard's schema is broken as written, the definition asserts what the
standard means and its comment says so. Most of those breaks come from a ``oneOf`` whose
alternatives overlap, so that an ordinary value matches two of them and is refused:

* an input value may be a string or a binary (base64) string: every string is both;
* it may be a number or an integer: every integer is both;
* an input of an execute request is one value or a list of values, and a value may be an
  array: an array input (a point set) is both.

The standard lists *kinds* of value there; where they overlap a value of the overlap is
still of that kind. The definitions below say "any of these kinds".

Every document is also checked against the standard's own file for it, vendored with its
licence in ``standard_schemas/`` and read by :mod:`tests.service.ogc.vendored`, which lists
where it relaxes those files and why (the same overlaps): :func:`errors` answers both, so
a transcription error here cannot let a document through that the standard refuses.

The standard's documents are open: members it does not name are allowed, except in the
``schema`` object of an input or output description, which admits only the OpenAPI 3.0
schema keywords it lists. Where a member is named, ``null`` is never one of its values.
Members that the standard's files describe only by the schema of their members (``inputs``
and ``outputs`` of a description or a request, a results document) are JSON objects here,
as the standard's text says; its files leave the type open, which lets any non-object pass.
"""

from __future__ import annotations

from functools import cache
from typing import Any

import jsonschema_rs

from tests.service.ogc import vendored

__all__ = ["DEFINITIONS", "validator", "errors"]


def _ref(name: str) -> dict[str, Any]:
    return {"$ref": f"#/$defs/{name}"}


def _text() -> dict[str, Any]:
    return {"type": "string"}


def _list(item: dict[str, Any]) -> dict[str, Any]:
    return {"type": "array", "items": item}


def _map(value: dict[str, Any]) -> dict[str, Any]:
    """A JSON object whose every member is ``value`` (inputs, outputs, results by id)."""
    return {"type": "object", "additionalProperties": value}


def _record(*required: str, **members: dict[str, Any]) -> dict[str, Any]:
    """A JSON object with the named ``members``, of which ``required`` must be present;
    other members are allowed, as the standard allows them."""
    schema: dict[str, Any] = {"type": "object", "properties": members}
    if required:
        schema["required"] = list(required)
    return schema


def _moment() -> dict[str, Any]:
    """An instant, RFC 3339 ``date-time`` (statusInfo's created/started/finished/updated)."""
    return {"type": "string", "format": "date-time"}


_COUNT = {"type": "integer", "minimum": 0}
_SCHEMA_OR_REFERENCE = _ref("schema_or_reference")

DEFINITIONS: dict[str, dict[str, Any]] = {
    # -- links and the service's entry documents ---------------------------------------------

    # A link (link.yaml; /req/core/pl-links, /req/core/landingpage-success, every `links`
    # member): the target is required; relation, media type, language and title are text.
    "link": _record("href", href=_text(), rel=_text(), type=_text(), hreflang=_text(),
                    title=_text()),
    "links": _list(_ref("link")),

    # The landing page (landingPage.yaml; /req/core/landingpage-success): its links are
    # required, its title and description optional text.
    "landing_page": _record("links", title=_text(), description=_text(),
                            links=_ref("links")),

    # The conformance declaration (confClasses.yaml; /req/core/conformance-success): the
    # URIs of the conformance classes, as text.
    "conformance": _record("conformsTo", conformsTo=_list(_text())),

    # What every process description and input/output description may say about itself
    # (descriptionType.yaml, metadata.yaml, additionalParameter.yaml).
    "metadata": _record(title=_text(), role=_text(), href=_text()),
    # additionalParameter.yaml's values are a oneOf of string, number, integer, array and
    # object: the integer overlap again (see the module's docstring). Meant: any of those
    # kinds; neither booleans nor null.
    "additional_parameter": _record(
        "name", "value", name=_text(),
        value=_list({"type": ["string", "number", "array", "object"]})),
    "described": _record(
        title=_text(), description=_text(), keywords=_list(_text()),
        metadata=_list(_ref("metadata")),
        additionalParameters={"allOf": [
            _ref("metadata"),
            _record(parameters=_list(_ref("additional_parameter")))]}),

    # -- processes ---------------------------------------------------------------------------

    # How a process may be run (jobControlOptions.yaml) and how it may hand back its outputs
    # (transmissionMode.yaml).
    "job_control": {"enum": ["sync-execute", "async-execute", "dismiss"]},
    "transmission": {"enum": ["value", "reference"]},

    # A process summary (processSummary.yaml; /req/core/process-list-success,
    # /req/core/process-summary-links): a described thing with a required id and version.
    "process_summary": {"allOf": [_ref("described"), _record(
        "id", "version", id=_text(), version=_text(),
        jobControlOptions=_list(_ref("job_control")),
        outputTransmission=_list(_ref("transmission")),
        links=_ref("links"))]},

    # The process list (processList.yaml; /req/core/process-list-success): summaries and
    # links, both required.
    "process_list": _record("processes", "links", processes=_list(_ref("process_summary")),
                            links=_ref("links")),

    # A process description (process.yaml; /req/core/process-description-success,
    # /req/ogc-process-description/json-encoding): a summary with its inputs and outputs,
    # each keyed by its id.
    "process": {"allOf": [_ref("process_summary"), _record(
        inputs=_map(_ref("input_description")),
        outputs=_map(_ref("output_description")))]},

    # An input's description (inputDescription.yaml; /req/ogc-process-description/input-def,
    # /req/ogc-process-description/inputs-def): its schema is required; it occurs a whole
    # number of times, at most a number or "unbounded".
    "input_description": {"allOf": [_ref("described"), _record(
        "schema", schema=_SCHEMA_OR_REFERENCE, minOccurs={"type": "integer"},
        maxOccurs={"oneOf": [{"type": "integer"}, {"const": "unbounded"}]})]},

    # An output's description (outputDescription.yaml; /req/ogc-process-description/
    # output-def): its schema is required.
    "output_description": {"allOf": [_ref("described"),
                                     _record("schema", schema=_SCHEMA_OR_REFERENCE)]},

    # The schema of an input or output value (schema.yaml, reference.yaml;
    # /req/ogc-process-description/input-def and output-def): an OpenAPI 3.0 schema object,
    # or a reference to one. The schema object admits the keywords listed here and no
    # other (no `examples`, `const`, `$defs`, `prefixItems`, `"type": "null"`); its bounds
    # are OpenAPI 3.0's (a number `minimum` with a boolean `exclusiveMinimum`).
    #
    # schema.yaml is broken as written where it nests schemas: each nested position is a
    # oneOf of schema.yaml and reference.yaml, but schema.yaml already admits a reference,
    # so a nested reference matches both and is refused. Meant: a schema object or a
    # reference, which are exclusive since a schema object has no `$ref`.
    "schema_or_reference": {"oneOf": [_ref("reference"), _ref("schema")]},
    "reference": _record("$ref", **{"$ref": {"type": "string", "format": "uri-reference"}}),
    "schema": {
        "type": "object",
        "additionalProperties": False,
        "properties": {
            "title": _text(), "description": _text(), "format": _text(),
            "type": {"enum": ["array", "boolean", "integer", "number", "object", "string"]},
            "enum": {"type": "array", "minItems": 1},
            "default": {}, "example": {},
            "multipleOf": {"type": "number", "exclusiveMinimum": 0},
            "minimum": {"type": "number"}, "maximum": {"type": "number"},
            "exclusiveMinimum": {"type": "boolean"}, "exclusiveMaximum": {"type": "boolean"},
            "minLength": _COUNT, "maxLength": _COUNT,
            "pattern": {"type": "string", "format": "regex"},
            "minItems": _COUNT, "maxItems": _COUNT, "uniqueItems": {"type": "boolean"},
            "minProperties": _COUNT, "maxProperties": _COUNT,
            "required": {"type": "array", "items": _text(), "minItems": 1,
                         "uniqueItems": True},
            "items": _SCHEMA_OR_REFERENCE,
            "properties": _map(_SCHEMA_OR_REFERENCE),
            "additionalProperties": {"anyOf": [_SCHEMA_OR_REFERENCE, {"type": "boolean"}]},
            "not": _SCHEMA_OR_REFERENCE,
            "allOf": _list(_SCHEMA_OR_REFERENCE),
            "oneOf": _list(_SCHEMA_OR_REFERENCE),
            "anyOf": _list(_SCHEMA_OR_REFERENCE),
            "nullable": {"type": "boolean"}, "readOnly": {"type": "boolean"},
            "writeOnly": {"type": "boolean"}, "deprecated": {"type": "boolean"},
            "contentMediaType": _text(), "contentEncoding": _text(),
            "contentSchema": _text(),
        },
    },

    # -- values: execute requests and results ------------------------------------------------

    # A bounding box (bbox.yaml; /req/core/process-execute-input-inline-bbox): four or six
    # numbers, in one of the two CRS the standard names.
    "bbox": _record(
        "bbox",
        bbox={"type": "array", "items": {"type": "number"},
              "oneOf": [{"minItems": n, "maxItems": n} for n in (4, 6)]},
        crs={"type": "string", "format": "uri",
             "enum": ["http://www.opengis.net/def/crs/OGC/1.3/CRS84",
                      "http://www.opengis.net/def/crs/OGC/0/CRS84h"]}),

    # A bare value (inputValueNoObject.yaml, binaryInputValue.yaml): a string (binary data
    # is a base64 string, /req/core/process-execute-input-inline-binary), a number, a
    # boolean, an array, or a bounding box; never null. The standard's oneOf overlaps
    # (string and binary string, number and integer): see the module's docstring.
    "bare_value": {"anyOf": [{"type": ["string", "number", "boolean", "array"]},
                             _ref("bbox")]},

    # The value of a qualified value (inputValue.yaml): a bare value or an object
    # (/req/core/process-execute-input-inline-object). Written as a oneOf of those two, a
    # bounding box is both; meant: any JSON value but null.
    "any_value": {"type": ["string", "number", "boolean", "array", "object"]},

    # The format a qualified value or a requested output is in (format.yaml).
    "format": _record(mediaType=_text(), encoding=_text(),
                      schema={"oneOf": [{"type": "string", "format": "uri"},
                                        {"type": "object"}]}),

    # A value with its format (qualifiedInputValue.yaml;
    # /req/core/process-execute-input-inline-mixed): the value is required.
    "qualified_value": {"allOf": [_ref("format"), _record("value", value=_ref("any_value"))]},

    # One input or output value (inlineOrRefData.yaml): bare, qualified, or by reference (a
    # link; /req/core/process-execute-input-by-reference). These are exclusive: a qualified
    # value has `value`, a link `href`, a bare value is no such object.
    "inline_or_reference": {"oneOf": [_ref("bare_value"), _ref("qualified_value"),
                                      _ref("link")]},

    # A requested output (output.yaml).
    "output": _record(format=_ref("format")),

    # Where to call back (subscriber.yaml; the Callback class). The standard's file
    # requires `successUrl` while naming the member `successUri`; meant: `successUri`.
    "subscriber": _record("successUri", successUri={"type": "string", "format": "uri"},
                          inProgressUri={"type": "string", "format": "uri"},
                          failedUri={"type": "string", "format": "uri"}),

    # An execute request (execute.yaml; /req/core/process-execute-request): each input is
    # one value or a list of values; each requested output says its format. Written as a
    # oneOf, an array value is both (see the module's docstring); meant: either.
    "execute": _record(
        inputs=_map({"anyOf": [_ref("inline_or_reference"),
                               _list(_ref("inline_or_reference"))]}),
        outputs=_map(_ref("output")),
        subscriber=_ref("subscriber")),

    # A results document (results.yaml; /req/core/process-execute-sync-many-json,
    # /req/core/job-results-success-sync, -async-many): each output by its id.
    "results": _map(_ref("inline_or_reference")),

    # -- jobs and errors ---------------------------------------------------------------------

    # A job's status (statusInfo.yaml; /req/core/job-success,
    # /req/core/process-execute-success-async): its id, its status from the standard's five
    # and its type are required; times are RFC 3339 instants; progress is a whole percent.
    # A member without a value yet is left out, never null.
    "status_info": _record(
        "jobID", "status", "type",
        jobID=_text(), processID=_text(), type={"const": "process"},
        status={"enum": ["accepted", "running", "successful", "failed", "dismissed"]},
        message=_text(), created=_moment(), started=_moment(), finished=_moment(),
        updated=_moment(), progress={"type": "integer", "minimum": 0, "maximum": 100},
        links=_ref("links")),

    # The job list (jobList.yaml; /req/job-list/job-list-success): statuses and links, both
    # required.
    "job_list": _record("jobs", "links", jobs=_list(_ref("status_info")),
                        links=_ref("links")),

    # An error (exception.yaml, RFC 7807; /req/core/process-exception-no-such-process,
    # /req/core/job-exception-no-such-job, …): its type is required.
    "exception": _record("type", type=_text(), title=_text(), status={"type": "integer"},
                         detail=_text(), instance=_text()),
}


@cache
def validator(name: str) -> Any:
    """A validator of the document ``name`` of :data:`DEFINITIONS` (``"status_info"``),
    checking formats (``date-time``, ``uri``, ``regex``) too."""
    if name not in DEFINITIONS:
        raise KeyError(f"no definition named {name!r}; known: {sorted(DEFINITIONS)}")
    return jsonschema_rs.Draft202012Validator(
        {"$schema": "https://json-schema.org/draft/2020-12/schema",
         "$defs": DEFINITIONS, "$ref": f"#/$defs/{name}"},
        validate_formats=True)


def errors(name: str, document: Any) -> list[str]:
    """What makes ``document`` invalid as the standard's document ``name``: one line per
    error, ``path: message``; empty when it is valid. The document is checked against the
    definition here and against the standard's own file for it, vendored in
    ``standard_schemas/`` (:mod:`tests.service.ogc.vendored`, which relaxes the files'
    broken ``oneOf``\\ s as the definitions here do): valid means valid under both."""
    own = [f"{'/'.join(map(str, e.instance_path))}: {e.message}"
           for e in validator(name).iter_errors(document)]
    return own + vendored.errors(name, document)
