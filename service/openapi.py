"""Write the service's OpenAPI document: ``python -m service.openapi [PATH]`` (``make openapi``).

The document depends only on the code (the routes and the catalog), not on settings, so the
committed ``openapi/openapi.json`` can be checked against it in a test.

Besides the generic ``POST /processes/{processId}/execution`` that OGC API – Processes
requires, the document has one execute operation per process of the catalog
(:func:`add_process_operations`), as pygeoapi's has: ``POST /processes/registration.icp/execution``
with that process's exact request body (its inputs are the process's input model) and the
catalog's example, so that an OpenAPI client, Swagger UI's "Try it out" or a fuzzer sends
that process a body it can run. The generic handler serves these paths; they are documents
only. The diagnostic processes of ``MORPHSERVE_TEST_PROCESSES`` are never listed.
"""

from __future__ import annotations

import copy
import json
import sys
from collections.abc import Iterable
from typing import Any

from service.catalog import FAMILIES, Process, processes

__all__ = ["document", "render", "add_process_operations", "operation_id", "inputs_schema",
           "GENERIC_EXECUTE"]

GENERIC_EXECUTE = "/processes/{processId}/execution"
"""The path of the generic execute operation (the one OGC requires)."""

PREFER = {
    "in": "header", "name": "Prefer", "required": False,
    "description": "How long to wait for the job (RFC 7240): `respond-async` answers 201 with "
    "the job's status at once; `wait=N` answers 200 with the results if the job ends within N "
    "seconds (capped by the service), else 201; `respond-sync` waits for the end. Without "
    "it, short processes wait and long ones answer 201.",
    "schema": {"type": "string"},
    "example": "wait=60",
}
"""The ``Prefer`` header of an execute request, as :func:`service.routes.common.parse_prefer`
reads it."""

_INVALID = ("The request was refused: an input is missing or malformed, or describes geometry "
            "the method cannot use although each input is well formed on its own (point sets "
            "that must be paired but differ in length, rows of different lengths, face "
            "indices beyond the vertices, more components than dimensions, a callback host "
            "the service does not allow …), or an Idempotency-Key was reused with another "
            "body. The problem's `errors` name each input and say what was expected.")

_FAILED = {"500": "The job failed for a reason that is not the input's fault (synchronous "
                  "execution).",
           "504": "The job ran longer than its time limit and was stopped (synchronous "
                  "execution)."}


_TAGS = {"service": "The landing page, conformance classes, health and metrics.",
         "processes": "The processes: list them, describe one, execute one by its id (the "
         "generic operation of OGC API – Processes; the operations by family below are the "
         "same, one per process, with its inputs and an example).",
         "jobs": "Jobs: their status, results and dismissal."}

_DEFAULT_WAIT = {True: "the job runs asynchronously (201).",
                 False: "the request waits for the results (200)."}


def operation_id(process: Process) -> str:
    """The stable operation id of a process's execute operation: ``execute_registration.icp``."""
    return f"execute_{process.id}"


def inputs_schema(process: Process) -> dict[str, Any]:
    """The JSON Schema of a process's ``inputs``: its input model's, as pydantic writes it."""
    return process.params.model_json_schema(mode="validation",
                                            ref_template="#/components/schemas/{model}")


def _request_schema(process: Process, inputs_ref: str, generic: dict[str, Any]
                    ) -> dict[str, Any]:
    """The body of a process's execute request, exactly what the generic handler accepts
    for it (:func:`service.routes.processes._parse_execute`)."""
    members = generic.get("properties", {})
    outputs = {name: {"description": out.title or name} for name, out in process.outputs.items()}
    schema: dict[str, Any] = {
        "type": "object",
        "title": f"Execute {process.id}",
        "additionalProperties": False,
        "properties": {
            "inputs": {"$ref": inputs_ref},
            "outputs": {"anyOf": [
                {"type": "object", "properties": outputs, "additionalProperties": False,
                 "minProperties": 1},
                {"type": "null"}],
                "description": "The outputs wanted, by name (all when absent); each output's "
                "options are read but not used: outputs are sent by value."},
            "response": copy.deepcopy(members.get("response", {"enum": ["document", "raw"]})),
            "subscriber": {"anyOf": [
                {"type": "object", "additionalProperties": False,
                 "properties": {name: {"type": "string", "format": "uri",
                                       "pattern": "^https?://[^/?#]"}
                                for name in ("successUri", "inProgressUri", "failedUri")}},
                {"type": "null"}],
                "description": "URLs the service POSTs to when the job starts, succeeds or "
                "fails; only hosts the service allows (MORPHSERVE_CALLBACK_HOSTS)."},
            "timeLimit": {"type": "number", "exclusiveMinimum": 0,
                          "description": "Lower the job's time limit (seconds); never raises "
                          "it above the service's."},
        },
    }
    if process.params.model_json_schema().get("required"):
        schema["required"] = ["inputs"]
    return schema


def _output_value(schema: dict[str, Any]) -> dict[str, Any]:
    """The JSON of an output of this schema (:attr:`service.catalog.Output.schema`) as the
    service writes it: a non-finite number as null (orjson), an array as a list or, with
    ``Prefer: arrays=binary``, a typed binary array object."""
    kind = schema.get("type")
    if not isinstance(kind, str):
        return {}
    types = {"number": ["number", "null"], "array": ["array", "object"]}.get(kind, [kind])
    if schema.get("nullable") and "null" not in types:
        types = [*types, "null"]
    # anyOf, not a list of types: schemathesis 4's link inference takes `type` to be a string
    return {"anyOf": [{"type": t} for t in types]} if len(types) > 1 else {"type": types[0]}


def _results_response(process: Process) -> dict[str, Any]:
    """The 200 answer of a process's execute operation: its results document (the outputs
    asked for, by name) or, with ``response: raw`` and one output, that output's value
    alone."""
    values = {name: _output_value(out.schema) for name, out in process.outputs.items()}
    document = {"type": "object", "title": f"Results of {process.id}",
                "additionalProperties": False,
                "properties": {name: {**values[name], "description": out.title or name}
                               for name, out in process.outputs.items()}}
    raw: list[dict[str, Any]] = []
    for value in values.values():
        if value not in raw:
            raw.append(value)
    return {"description": "The results (synchronous execution): the results document, or "
            "with `response: raw` and one output, its value alone.",
            "content": {"application/json": {"schema": {"anyOf": [document, *raw]}}}}


def add_process_operations(doc: dict[str, Any], catalog: Iterable[Process] | None = None
                           ) -> None:
    """Add to ``doc`` one execute operation per process (the catalog's, without the test
    processes, unless ``catalog`` is given), copied from the generic one (its responses,
    security and ``Prefer`` header), with the process's request schema and example; its
    input model goes to ``components/schemas``. The operations are tagged by family."""
    generic = doc["paths"][GENERIC_EXECUTE]["post"]
    generic.setdefault("parameters", []).append(copy.deepcopy(PREFER))
    for code, description in _FAILED.items():
        generic["responses"].setdefault(code, {"description": description})
    body = generic["requestBody"]["content"]["application/json"]["schema"]
    schemas = doc.setdefault("components", {}).setdefault("schemas", {})
    families: list[str] = []
    for process in processes() if catalog is None else catalog:
        name = process.params.__name__
        if name in schemas:
            raise ValueError(f"{process.id}: the component {name!r} exists already")
        schemas[name] = inputs_schema(process)
        example = {"inputs": dict(process.examples)}
        op = {
            "tags": [process.family],
            "summary": process.title,
            "description": f"{process.description}\n\nThe inputs are described at "
            f"[GET /processes/{process.id}](/processes/{process.id}). Without a `Prefer` "
            f"header {_DEFAULT_WAIT[process.long]}",
            "operationId": operation_id(process),
            "parameters": [copy.deepcopy(PREFER)],
            "requestBody": {"required": True, "content": {"application/json": {
                "schema": _request_schema(process, f"#/components/schemas/{name}", body),
                "examples": {"catalog": {"summary": "The catalog's example",
                                         "value": example}}}}},
            "responses": copy.deepcopy(generic["responses"]),
        }
        if "security" in generic:
            op["security"] = copy.deepcopy(generic["security"])
        op["responses"]["422"]["description"] = _INVALID
        op["responses"]["200"] = _results_response(process)
        doc["paths"][f"/processes/{process.id}/execution"] = {"post": op}
        if process.family not in families:
            families.append(process.family)
    order = {f: i for i, f in enumerate(FAMILIES)}
    tags = list(doc.get("tags", []))
    named = [t["name"] for t in tags]
    for item in list(doc["paths"].values()):  # the routers' tags first, as they come
        for op in item.values():
            for tag in op.get("tags", []):
                if tag not in named and tag not in families:
                    named.append(tag)
                    tags.append({"name": tag, **({"description": _TAGS[tag]}
                                                 if tag in _TAGS else {})})
    for family in sorted(families, key=lambda f: order.get(f, len(order))):
        if family not in named:
            tags.append({"name": family, "description": f"The {family} methods: one "
                         "execute operation per process, with its inputs and an example."})
    doc["tags"] = tags


def document() -> dict[str, Any]:
    from service.app import create_app
    from service.settings import Settings

    return create_app(Settings()).openapi()


def render() -> str:
    return json.dumps(document(), indent=2, sort_keys=True, ensure_ascii=False) + "\n"


def main(argv: list[str]) -> int:
    from service import generated

    return generated.main(argv, prog="python -m service.openapi",
                          description="Write the service's OpenAPI document.", render=render)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
