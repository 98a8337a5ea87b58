"""Problem types (RFC 9457) of the service, without web dependencies (workers import this).

Each type is a page the service serves at ``/problems/{slug}``; the SDK names its exception
classes after the slugs. The errors OGC API – Processes defines (no such process, no such job,
result not ready) have the standard's type URIs, which end in the same slugs
(``http://www.opengis.net/def/exceptions/ogcapi-processes-1/1.0/no-such-job``); the others
are ours, ``/problems/{slug}``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from algorithms.core.errors import GeometryError

__all__ = ["ProblemType", "PROBLEMS", "OGC_EXCEPTIONS", "problem_body", "geometry_error_problem",
           "dismissed_problem", "pydantic_errors"]


#: Where the exception types of OGC API – Processes – Part 1 (1.0) are registered.
OGC_EXCEPTIONS = "http://www.opengis.net/def/exceptions/ogcapi-processes-1/1.0/"


@dataclass(frozen=True)
class ProblemType:
    slug: str
    status: int
    title: str
    description: str
    ogc: bool = False
    """The type is one the standard defines: its URI is the standard's."""

    @property
    def uri(self) -> str:
        return OGC_EXCEPTIONS + self.slug if self.ogc else f"/problems/{self.slug}"


PROBLEMS: dict[str, ProblemType] = {
    p.slug: p
    for p in [
        ProblemType("invalid-input", 422, "Invalid input",
                    "An input is missing, malformed or describes degenerate geometry. The "
                    "`errors` member names each input and says what was expected and what came."),
        ProblemType("malformed-body", 400, "Malformed request body",
                    "The request body could not be parsed (not JSON, or not the execute "
                    "request's shape)."),
        ProblemType("no-such-process", 404, "No such process",
                    "No process has this id. `GET /processes` lists them.", ogc=True),
        ProblemType("no-such-job", 404, "No such job",
                    "No job has this id, or it was dismissed and removed.", ogc=True),
        ProblemType("no-such-output", 404, "No such output",
                    "The job has no output of this name; its results document lists them."),
        ProblemType("result-not-ready", 404, "Result not ready",
                    "The job has not finished yet. Poll `GET /jobs/{jobId}` until its status "
                    "is `successful`.", ogc=True),
        ProblemType("job-failed", 500, "Job failed",
                    "The job failed for a reason that is not the input's fault."),
        ProblemType("job-dismissed", 410, "Job dismissed",
                    "The job was dismissed before it finished; it has no results."),
        ProblemType("time-limit-exceeded", 504, "Time limit exceeded",
                    "The job ran longer than its time limit and was stopped."),
        ProblemType("worker-lost", 500, "Worker lost",
                    "The worker running the job died (crash or memory limit) more often than "
                    "allowed."),
        ProblemType("not-found", 404, "Not found", "No resource at this path."),
        ProblemType("method-not-allowed", 405, "Method not allowed",
                    "This resource does not answer this HTTP method."),
        ProblemType("payload-too-large", 413, "Payload too large",
                    "The request body exceeds the service's size limit."),
        ProblemType("unsupported-media-type", 415, "Unsupported media type",
                    "The request body's content type is not accepted here."),
        ProblemType("not-acceptable", 406, "Not acceptable",
                    "The result cannot be represented in any media type the request accepts."),
        ProblemType("idempotency-conflict", 422, "Idempotency key reused",
                    "This Idempotency-Key was already used with a different request body."),
        ProblemType("queue-full", 429, "Queue full",
                    "Too many jobs are waiting. Retry after the number of seconds in "
                    "Retry-After."),
        ProblemType("insufficient-storage", 507, "Insufficient storage",
                    "The service's data dir is full: it stores no new job (nor, while no "
                    "room is left, any change) until space is freed. Reading jobs and "
                    "results still works; `free_bytes` says how much room is left."),
        ProblemType("bad-request", 400, "Bad request",
                    "The request is not valid HTTP/1.1 (its request line, headers or framing); "
                    "the connection is closed."),
        ProblemType("request-timeout", 408, "Request timeout",
                    "The request's head, or its body, arrived too slowly; the connection is "
                    "closed."),
        ProblemType("header-too-large", 431, "Request header fields too large",
                    "The request's head (request line and headers) exceeds the service's limit; "
                    "the connection is closed."),
        ProblemType("unauthorized", 401, "Unauthorized", "A valid API key is required."),
        ProblemType("service-unavailable", 503, "Service unavailable",
                    "The service is starting, has no workers, or its data dir is full "
                    "(`/readyz` says which)."),
        ProblemType("internal-error", 500, "Internal error",
                    "An unexpected error. This is a bug: please report it with the instance id."),
    ]
}


def problem_body(
    slug: str,
    detail: str,
    *,
    instance: str | None = None,
    errors: list[dict[str, str]] | None = None,
    status: int | None = None,
) -> dict[str, Any]:
    p = PROBLEMS[slug]
    body: dict[str, Any] = {
        "type": p.uri,
        "title": p.title,
        "status": status or p.status,
        "detail": detail,
    }
    if instance is not None:
        body["instance"] = instance
    if errors:
        body["errors"] = errors
    return body


def dismissed_problem() -> dict[str, Any]:
    """The problem body of a job dismissed before it finished (without ``instance``)."""
    return problem_body("job-dismissed", "The job was dismissed before it finished.")


def geometry_error_problem(exc: GeometryError) -> dict[str, Any]:
    """The problem body of an algorithm's error (without ``instance``)."""
    errors = [{"input": exc.field, "message": exc.message}] if exc.field else None
    return problem_body("invalid-input", exc.message, errors=errors)


def _location(loc: tuple[Any, ...]) -> str:
    parts = [str(x) for x in loc if x not in ("body", "query", "path", "header")]
    return ".".join(parts) if parts else ".".join(str(x) for x in loc)


def pydantic_errors(errors: list[Any], prefix: tuple[Any, ...] = ()) -> list[dict[str, str]]:
    """pydantic's error list as problem ``errors`` entries naming the input."""
    out = []
    for e in errors:
        msg = e.get("msg", "invalid")
        if msg.startswith("Value error, "):
            msg = msg[len("Value error, "):]
        loc = prefix + tuple(e.get("loc", ()))
        cause = (e.get("ctx") or {}).get("error")
        if isinstance(cause, GeometryError) and cause.field:
            loc, msg = prefix + (cause.field,), cause.message  # a cross-input check names its input
        out.append({"input": _location(loc), "message": msg})
    return out
