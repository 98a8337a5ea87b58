"""JSON representations: statusInfo, results documents, process summaries/descriptions."""

from __future__ import annotations

from datetime import UTC, datetime
from typing import Any

from service.catalog import Process
from service.jobs.status import JobStatus
from service.jobs.store import JobRecord, JobRequest

__all__ = ["status_info", "results_document", "process_summary",
           "process_description", "iso"]


def iso(t: float | None) -> str | None:
    if t is None:
        return None
    return datetime.fromtimestamp(t, UTC).isoformat(timespec="milliseconds").replace(
        "+00:00", "Z")


def status_info(job: JobRecord) -> dict[str, Any]:
    links = [
        {"href": f"/jobs/{job.id}", "rel": "self", "type": "application/json",
         "title": "this job's status"},
        {"href": f"/processes/{job.process}", "rel": "up", "type": "application/json",
         "title": "the process"},
    ]
    if job.status is JobStatus.SUCCESSFUL:
        links.append({"href": f"/jobs/{job.id}/results", "rel": "results",
                      "type": "application/json", "title": "the job's results"})
    return {
        "jobID": job.id,
        "processID": job.process,
        "type": "process",
        "status": str(job.status),
        "message": job.message,
        "created": iso(job.created),
        "started": iso(job.started),
        "finished": iso(job.finished),
        "updated": iso(job.updated),
        "progress": job.progress,
        "links": links,
    }


def results_document(outputs: dict[str, Any], request: JobRequest) -> Any:
    """The results of a job as the client asked: the requested outputs (all by default), as a
    document ``{name: value}``, or for ``response: raw`` with one output, the value alone.
    Values stay numpy; :mod:`service.jsonio` writes them."""
    wanted = request.outputs or list(outputs)
    doc = {name: outputs[name] for name in wanted if name in outputs}
    if request.response == "raw" and len(doc) == 1:
        return next(iter(doc.values()))
    return doc


def process_summary(p: Process) -> dict[str, Any]:
    return {
        "id": p.id,
        "title": p.title,
        "description": p.description,
        "version": p.version,
        "keywords": list(p.keywords),
        "jobControlOptions": ["async-execute", "sync-execute", "dismiss"],
        "outputTransmission": ["value"],
        "links": [
            {"href": f"/processes/{p.id}", "rel": "self", "type": "application/json",
             "title": "process description"},
            {"href": f"/processes/{p.id}/execution",
             "rel": "http://www.opengis.net/def/rel/ogc/1.0/execute",
             "type": "application/json", "title": "execute"},
        ],
    }


def _input_description(name: str, schema: dict[str, Any], required: bool) -> dict[str, Any]:
    schema = dict(schema)
    title = schema.pop("title", name.replace("_", " "))
    desc = schema.get("description", "")
    return {"title": title, "description": desc, "schema": schema,
            "minOccurs": 1 if required else 0, "maxOccurs": 1}


def process_description(p: Process) -> dict[str, Any]:
    schema = p.params.model_json_schema(mode="validation")
    required = set(schema.get("required", []))
    defs = schema.get("$defs")
    inputs = {}
    for name, prop in schema.get("properties", {}).items():
        if defs and "$ref" in str(prop):
            prop = {**prop, "$defs": defs}
        inputs[name] = _input_description(name, prop, name in required)
    outputs = {o.name: {"title": o.title, "description": o.description, "schema": o.schema}
               for o in p.outputs.values()}
    out = process_summary(p)
    if p.reference:
        out["reference"] = p.reference
    out["inputs"] = inputs
    out["outputs"] = outputs
    return out
