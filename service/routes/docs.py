"""Pydantic models of the response bodies, for the OpenAPI document only.

The routes build their JSON directly (no response_model validation on the hot path); these
models describe it for clients, schemathesis and the SDK. Shapes follow OGC API – Processes
Part 1 (1.0) and RFC 9457.
"""

from __future__ import annotations

from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field

from service.problems import PROBLEMS


class _Open(BaseModel):
    model_config = ConfigDict(extra="allow")


class Link(_Open):
    href: str
    rel: str | None = None
    type: str | None = None
    title: str | None = None


class LandingPage(_Open):
    title: str
    description: str
    links: list[Link]


class Conformance(_Open):
    conformsTo: list[str]


class ProcessSummary(_Open):
    id: str
    title: str
    description: str
    version: str
    keywords: list[str] = []
    jobControlOptions: list[Literal["sync-execute", "async-execute", "dismiss"]]
    outputTransmission: list[Literal["value", "reference"]]
    links: list[Link]


class ProcessList(_Open):
    processes: list[ProcessSummary]
    links: list[Link]
    numberMatched: int = Field(description="Processes offered, on every page together.")


class InputDescription(_Open):
    title: str
    description: str
    schema_: dict[str, Any] = Field(alias="schema")
    minOccurs: int
    maxOccurs: int


class OutputDescription(_Open):
    title: str
    description: str
    schema_: dict[str, Any] = Field(alias="schema")


class ProcessDescription(ProcessSummary):
    inputs: dict[str, InputDescription]
    outputs: dict[str, OutputDescription]


#: The names of :class:`service.jobs.status.JobStatus`, as a Literal: the OpenAPI document
#: keeps its inline enum (an Enum would become a component of its own); a test checks that
#: the two agree.
StatusName = Literal["accepted", "running", "successful", "failed", "dismissed"]


class StatusInfo(_Open):
    jobID: str
    processID: str
    type: Literal["process"]
    status: StatusName
    # members without a value yet (started of an accepted job) are left out, not null
    message: str = Field(default_factory=str, description="Left out when there is nothing to say.")
    created: str = Field(default_factory=str, description="Left out when unknown.")
    started: str = Field(default_factory=str, description="Left out until the job starts.")
    finished: str = Field(default_factory=str, description="Left out until the job ends.")
    updated: str = Field(default_factory=str, description="Left out when unknown.")
    progress: int = Field(ge=0, le=100)
    links: list[Link]


class JobList(_Open):
    jobs: list[StatusInfo]
    links: list[Link]
    numberMatched: int


class FieldError(_Open):
    input: str
    message: str


class Problem(_Open):
    type: str
    title: str
    status: int
    detail: str
    instance: str | None = None
    errors: list[FieldError] | None = None


class Subscriber(BaseModel):
    successUri: str | None = None
    inProgressUri: str | None = None
    failedUri: str | None = None


ExecutionMode = Literal["sync", "async", "auto"]
"""The execute request's ``mode`` (OGC drafts): ``auto`` lets the service choose."""


class ExecuteRequest(BaseModel):
    """The body of ``POST /processes/{processId}/execution``."""

    inputs: dict[str, Any] = Field(default_factory=dict,
                                   description="Named inputs, as the process describes them.")
    outputs: dict[str, dict[str, Any]] | None = Field(
        None, description="The outputs wanted (all when absent).")
    response: Literal["document", "raw"] = "document"
    subscriber: Subscriber | None = None
    mode: ExecutionMode | None = Field(
        None, description="Execution mode of OGC drafts; the Prefer header takes precedence.")
    timeLimit: float | None = Field(None, gt=0, description="Lower the job's time limit "
                                    "(seconds); never raises it above the service's.")


_STATUS_TEXT = {p.status: p.title for p in PROBLEMS.values()}


def responses(model: type[BaseModel] | None, *codes: int) -> dict[int | str, dict[str, Any]]:
    """OpenAPI ``responses`` for a route: 200 with ``model`` plus problem+json error codes."""
    out: dict[int | str, dict[str, Any]] = {}
    if model is not None:
        out[200] = {"model": model, "description": "OK"}
    for code in codes:
        out[code] = {"model": Problem, "description": _STATUS_TEXT.get(code, "Error"),
                     "content": {"application/problem+json": {}}}
    return out
