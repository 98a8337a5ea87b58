"""JSON representations: statusInfo, results documents, process summaries/descriptions.

Every ``href`` is ``base`` + a path: ``base`` is the service's public root URL as the client
reached it (:func:`service.routes.common.base_url`), so that links are absolute, as OGC API –
Processes clients expect; an empty ``base`` leaves them relative to the service's root.

The documents that also have an HTML page (the landing page, the process list, a process
description, the job list, a job's status) link to it with an ``alternate`` link
(:func:`html_alternate`), as the standard asks of a response in every other media type the
service offers (``/req/core/pl-links``, OGC API – Common).
"""

from __future__ import annotations

import json
from datetime import UTC, datetime
from typing import Any
from urllib.parse import parse_qsl, urlencode, urlsplit, urlunsplit

from service.catalog import Process
from service.jobs.status import JobStatus
from service.jobs.store import JobRecord, JobRequest

__all__ = ["status_info", "results_document", "process_summary", "process_description",
           "ogc_schema", "iso", "html_alternate", "REL_RESULTS", "REL_EXECUTE", "REL_JOB_LIST",
           "REL_PROCESSES", "REL_CONFORMANCE"]

_OGC_REL = "http://www.opengis.net/def/rel/ogc/1.0/"
#: Link relations registered by OGC API – Processes (Part 1, 1.0).
REL_RESULTS = _OGC_REL + "results"
REL_EXECUTE = _OGC_REL + "execute"
REL_JOB_LIST = _OGC_REL + "job-list"
REL_PROCESSES = _OGC_REL + "processes"
REL_CONFORMANCE = _OGC_REL + "conformance"


def iso(t: float | None) -> str | None:
    if t is None:
        return None
    return datetime.fromtimestamp(t, UTC).isoformat(timespec="milliseconds").replace(
        "+00:00", "Z")


def _link(href: str, rel: str, title: str, type_: str = "application/json") -> dict[str, str]:
    return {"href": href, "rel": rel, "type": type_, "title": title}


def html_alternate(href: str, title: str) -> dict[str, str]:
    """The ``alternate`` link to the HTML page of the JSON document at ``href``: the same URL
    with the query parameter ``f=html`` (in place of any ``f`` it had), which the HTML pages
    answer whatever the client's Accept header says."""
    parts = urlsplit(href)
    query = [(k, v) for k, v in parse_qsl(parts.query, keep_blank_values=True) if k != "f"]
    query.append(("f", "html"))
    return _link(urlunsplit(parts._replace(query=urlencode(query))), "alternate", title,
                 "text/html")


def status_info(job: JobRecord, base: str = "") -> dict[str, Any]:
    """The statusInfo document of a job. Members without a value yet (``started`` of a job
    still accepted, ``finished`` of one under way, an empty ``message``) are left out: the
    standard's schema types them as strings, not null."""
    links = [
        _link(f"{base}/jobs/{job.id}", "self", "this job's status"),
        # "monitor" and "status" are the standard's names for the job's status; the
        # process is "up" from the job
        _link(f"{base}/jobs/{job.id}", "monitor", "this job's status"),
        _link(f"{base}/processes/{job.process}", "up", "the process"),
        html_alternate(f"{base}/jobs/{job.id}", "this job's status as a web page"),
    ]
    if job.status is JobStatus.SUCCESSFUL:
        for rel in (REL_RESULTS, "results"):  # "results": the short form older clients read
            links.append(_link(f"{base}/jobs/{job.id}/results", rel, "the job's results"))
    info: dict[str, Any] = {
        "jobID": job.id,
        "processID": job.process,
        "type": "process",
        "status": str(job.status),
        "message": job.message or None,
        "created": iso(job.created),
        "started": iso(job.started),
        "finished": iso(job.finished),
        "updated": iso(job.updated),
        "progress": job.progress,
    }
    info = {k: v for k, v in info.items() if v is not None}
    info["links"] = links
    return info


def results_document(outputs: dict[str, Any], request: JobRequest) -> Any:
    """The results of a job as the client asked: the requested outputs (all by default), as a
    document ``{name: value}``, or for ``response: raw`` with one output, the value alone.
    Values stay numpy; :mod:`service.jsonio` writes them."""
    wanted = request.outputs or list(outputs)
    doc = {name: outputs[name] for name in wanted if name in outputs}
    if request.response == "raw" and len(doc) == 1:
        return next(iter(doc.values()))
    return doc


def process_summary(p: Process, base: str = "") -> dict[str, Any]:
    # The standard: a process offering both modes answers a request without a Prefer header
    # synchronously. A long process answers it asynchronously, so it offers async-execute
    # (a client's Prefer: wait=N or respond-sync is still honoured).
    modes = ["async-execute"] if p.long else ["sync-execute", "async-execute"]
    return {
        "id": p.id,
        "title": p.title,
        "description": p.description,
        "version": p.version,
        "keywords": list(p.keywords),
        "jobControlOptions": [*modes, "dismiss"],
        "outputTransmission": ["value"],
        "links": [
            _link(f"{base}/processes/{p.id}", "self", "process description"),
            html_alternate(f"{base}/processes/{p.id}", "this description as a web page"),
            _link(f"{base}/processes/{p.id}/execution", REL_EXECUTE, "execute"),
        ],
    }


# The keywords of OpenAPI 3.0's schema object that the OGC process description allows
# (the standard's schema.yaml); any other keyword makes the description invalid.
_OAS30 = {"title", "multipleOf", "maximum", "exclusiveMaximum", "minimum", "exclusiveMinimum",
          "maxLength", "minLength", "pattern", "maxItems", "minItems", "uniqueItems",
          "maxProperties", "minProperties", "required", "enum", "type", "not", "allOf", "oneOf",
          "anyOf", "items", "properties", "additionalProperties", "description", "format",
          "default", "nullable", "readOnly", "writeOnly", "example", "deprecated",
          "contentMediaType", "contentEncoding", "contentSchema"}


def ogc_schema(schema: Any, defs: dict[str, Any] | None = None,
               expanding: frozenset[str] = frozenset()) -> Any:
    """A JSON Schema as pydantic writes it (2020-12) made an OpenAPI 3.0 schema object, the
    form the OGC process description requires (its ``schema.yaml``):

    - ``$ref`` into ``$defs`` inlined (the description has no place for ``$defs``);
    - ``anyOf`` with ``{"type": "null"}`` becomes ``nullable``, and ``"default": null`` is
      dropped (an input left out is None);
    - the other unions use ``oneOf`` (/req/ogc-process-description/input-mixed-type);
    - numeric ``exclusiveMinimum``/``exclusiveMaximum`` become ``minimum``/``maximum`` with
      the boolean flag; ``const`` becomes a one-value ``enum``; ``prefixItems`` (a tuple)
      becomes ``items`` with its length bounds;
    - ``examples`` are left out: the per-process OpenAPI document carries them; so is any
      other keyword OpenAPI 3.0 lacks (the inputs' model still checks what they say).

    A definition that refers to itself is inlined once, its inner reference left as an
    object (``expanding`` names the definitions being inlined).
    """
    if not isinstance(schema, dict):
        return schema
    defs = {**(defs or {}), **schema.get("$defs", {})}
    if "$ref" in schema:
        name = str(schema["$ref"]).rsplit("/", 1)[-1]
        target = defs.get(name)
        if name in expanding:
            return {"type": "object"}
        if target is not None:
            rest = {k: v for k, v in schema.items() if k not in ("$ref", "$defs")}
            return ogc_schema({**target, **rest}, defs, expanding | {name})

    def inner(value: Any) -> Any:
        return ogc_schema(value, defs, expanding)

    out: dict[str, Any] = {}
    for key, value in schema.items():
        if key in ("properties",) and isinstance(value, dict):
            out[key] = {n: inner(v) for n, v in value.items()}
        elif key in ("items", "additionalProperties", "not") and isinstance(value, dict):
            out[key] = inner(value)
        elif key in ("anyOf", "oneOf", "allOf"):
            out[key] = [inner(v) for v in value]
        else:
            out[key] = value
    if "const" in out:
        out["enum"] = [out.pop("const")]
    if "prefixItems" in out:
        items = out.pop("prefixItems")
        distinct = [json.loads(t) for t in
                    dict.fromkeys(json.dumps(inner(i), sort_keys=True) for i in items)]
        out["items"] = distinct[0] if len(distinct) == 1 else {"oneOf": distinct}
        out.setdefault("minItems", len(items))
        out.setdefault("maxItems", len(items))
    for bound, flag in (("exclusiveMinimum", "minimum"), ("exclusiveMaximum", "maximum")):
        value = out.get(bound)
        if isinstance(value, int | float) and not isinstance(value, bool):
            out[flag] = value
            out[bound] = True
    if isinstance(out.get("type"), list):
        types = out.pop("type")
        if "null" in types:
            out["nullable"] = True
        types = [t for t in types if t != "null"]
        if len(types) == 1:
            out["type"] = types[0]
        else:
            out["oneOf"] = [{"type": t} for t in types]
    for union in ("anyOf", "oneOf"):
        if union in out:
            given = out.pop(union)
            alternatives = [a for a in given if a != {"type": "null"}]
            if len(alternatives) < len(given):
                out["nullable"] = True
            if len(alternatives) == 1:
                out = {**alternatives[0], **out}
            elif alternatives:
                out["oneOf"] = alternatives
    if out.get("default", 0) is None:
        del out["default"]
    return {k: v for k, v in out.items() if k in _OAS30}


def _input_description(name: str, schema: dict[str, Any], required: bool) -> dict[str, Any]:
    schema = ogc_schema(schema)
    title = schema.pop("title", name.replace("_", " "))
    desc = schema.get("description", "")
    return {"title": title, "description": desc, "schema": schema,
            "minOccurs": 1 if required else 0, "maxOccurs": 1}


def process_description(p: Process, base: str = "") -> dict[str, Any]:
    schema = p.params.model_json_schema(mode="validation")
    required = set(schema.get("required", []))
    defs = schema.get("$defs")
    inputs = {}
    for name, prop in schema.get("properties", {}).items():
        if defs and "$ref" in str(prop):
            prop = {**prop, "$defs": defs}
        inputs[name] = _input_description(name, prop, name in required)
    outputs = {o.name: {"title": o.title, "description": o.description,
                        "schema": ogc_schema(o.schema)}
               for o in p.outputs.values()}
    out = process_summary(p, base)
    if p.reference:
        out["reference"] = p.reference
    out["inputs"] = inputs
    out["outputs"] = outputs
    return out
