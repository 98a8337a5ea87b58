"""Problem details (RFC 9457) for every error the service answers.

One registry of problem types (:data:`PROBLEMS`), one exception class for errors raised by
the service itself (:class:`ServiceError`), and one handler per error base class:

==============================  ===========================================================
raised                          answered
==============================  ===========================================================
``ServiceError``                its own type and status
``algorithms`` InvalidInputError  422 ``invalid-input`` naming the input (``field``)
``RequestValidationError``      422 ``invalid-input`` (query/path parameters)
store's ``StorageFull``         507 ``insufficient-storage``, with ``free_bytes``
Starlette ``ClientDisconnect``   nothing (the client is gone); one INFO line
Starlette ``HTTPException``     404 ``not-found``, 405 ``method-not-allowed``, ...
anything else                   500 ``internal-error`` (a bug; logged with its traceback)
==============================  ===========================================================

Each type is a page the service serves at ``/problems/{slug}``.
"""

from __future__ import annotations

import difflib
import html
import logging
import re
from collections.abc import Iterable, Sequence
from typing import Any

from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import HTMLResponse, Response
from starlette.exceptions import HTTPException as StarletteHTTPException
from starlette.requests import ClientDisconnect

from algorithms.core.errors import GeometryError
from service.jobs.store import StorageFull
from service.jsonio import JSONResponse
from service.problems import (
    PROBLEMS,
    ProblemType,
    geometry_error_problem,
    problem_body,
    pydantic_errors,
)

__all__ = [
    "PROBLEMS",
    "ProblemType",
    "ServiceError",
    "problem_body",
    "problem_response",
    "install_handlers",
    "PROBLEM_JSON",
    "closest",
    "input_errors",
    "unknown_input_message",
]

log = logging.getLogger("morphserve")

PROBLEM_JSON = "application/problem+json"


class ServiceError(Exception):
    """An error the service answers with the problem type ``slug``."""

    def __init__(
        self,
        slug: str,
        detail: str,
        *,
        errors: list[dict[str, str]] | None = None,
        status: int | None = None,
        headers: dict[str, str] | None = None,
        members: dict[str, Any] | None = None,
    ) -> None:
        super().__init__(detail)
        self.problem = PROBLEMS[slug]
        self.detail = detail
        self.errors = errors
        self.status = status or self.problem.status
        self.headers = headers or {}
        self.members = members or {}
        """Extension members of the problem document (RFC 9457 §3.2)."""


def closest(name: str, choices: Iterable[str], n: int = 1) -> list[str]:
    """The ``n`` choices most like ``name`` (a typo's likely meaning), best first; none when
    nothing is close (difflib's ratio under 0.6)."""
    return difflib.get_close_matches(name, list(choices), n=n, cutoff=0.6)


def unknown_input_message(name: str, valid: Sequence[str], hidden: Iterable[str] = ()) -> str:
    """The refusal of an input the process does not have, naming the closest of its inputs
    and listing them all: "Unknown input `max_iter`; did you mean `max_iterations`? ..."."""
    listed = ", ".join(f"`{v}`" for v in valid)
    if name in set(hidden):
        return (f"`{name}` is a setting of the method that this service does not offer; "
                f"the inputs are {listed}.")
    guess = closest(name, valid)
    hint = f"; did you mean `{guess[0]}`?" if guess else "."
    return f"Unknown input `{name}`{hint} The inputs are {listed}."


def input_errors(errors: list[Any], valid: Sequence[str],
                 hidden: Iterable[str] = ()) -> list[dict[str, str]]:
    """pydantic's errors of an execute request's inputs as problem ``errors`` entries
    (:func:`pydantic_errors`), an unknown input (pydantic's "Extra inputs are not
    permitted") told as :func:`unknown_input_message` says."""
    out = pydantic_errors(errors)
    for entry, error in zip(out, errors, strict=True):
        loc = tuple(error.get("loc", ()))
        if error.get("type") == "extra_forbidden" and len(loc) == 1:
            entry["message"] = unknown_input_message(str(loc[0]), valid, hidden)
    return out


def problem_response(body: dict[str, Any], headers: dict[str, str] | None = None) -> JSONResponse:
    return JSONResponse(body, status_code=body["status"], media_type=PROBLEM_JSON,
                        headers=headers)


_STATUS_SLUG = {400: "malformed-body", 401: "unauthorized", 404: "not-found",
                405: "method-not-allowed", 406: "not-acceptable", 413: "payload-too-large",
                415: "unsupported-media-type", 429: "queue-full", 503: "service-unavailable"}


def _allowed_methods(request: Request) -> list[str]:
    """Every method the API documents on this path. (Starlette's own 405 names only the first
    matching route's methods, though GET and DELETE of one path are separate routes.)"""
    methods: set[str] = set()
    for template, operations in request.app.openapi()["paths"].items():
        pattern = re.sub(r"\\\{[^/]+?\\\}", "[^/]+", re.escape(template))
        if re.fullmatch(pattern, request.url.path):
            methods |= {m.upper() for m in operations}
    return sorted(methods)


def install_handlers(app: FastAPI) -> None:
    """Register one handler per error base class, and the ``/problems/{slug}`` pages."""

    @app.exception_handler(ServiceError)
    async def _service(request: Request, exc: ServiceError) -> JSONResponse:
        body = problem_body(exc.problem.slug, exc.detail, instance=str(request.url.path),
                            errors=exc.errors, status=exc.status)
        return problem_response({**exc.members, **body}, exc.headers)

    @app.exception_handler(StorageFull)
    async def _full(request: Request, exc: StorageFull) -> JSONResponse:
        log.warning("%s %s: %s", request.method, request.url.path, exc.strerror)
        body = problem_body("insufficient-storage", exc.strerror or "The data dir is full.",
                            instance=str(request.url.path))
        return problem_response({**body, "free_bytes": exc.free_bytes}, {"Retry-After": "30"})

    @app.exception_handler(ClientDisconnect)
    async def _gone(request: Request, exc: ClientDisconnect) -> Response:
        """The client went away, or was cut off (service.server), before its body ended:
        nobody to answer, nothing to log but a line."""
        log.info("%s %s: the client's body ended early", request.method, request.url.path)
        return Response(status_code=400)  # never sent: the connection is gone

    @app.exception_handler(GeometryError)
    async def _geometry(request: Request, exc: GeometryError) -> JSONResponse:
        body = geometry_error_problem(exc)
        body["instance"] = str(request.url.path)
        return problem_response(body)

    @app.exception_handler(RequestValidationError)
    async def _validation(request: Request, exc: RequestValidationError) -> JSONResponse:
        errors = pydantic_errors(list(exc.errors()))
        detail = "; ".join(f"{e['input']}: {e['message']}" for e in errors) or "invalid request"
        return problem_response(problem_body("invalid-input", detail,
                                             instance=str(request.url.path), errors=errors))

    @app.exception_handler(StarletteHTTPException)
    async def _http(request: Request, exc: StarletteHTTPException) -> JSONResponse:
        slug = _STATUS_SLUG.get(exc.status_code, "internal-error" if exc.status_code >= 500
                                else "malformed-body")
        detail = exc.detail if isinstance(exc.detail, str) else PROBLEMS[slug].title
        if exc.status_code == 404 and detail == "Not Found":
            detail = f"No resource at {request.url.path}."
        headers = dict(exc.headers or {})
        if exc.status_code == 405:
            detail = f"{request.method} is not allowed on {request.url.path}."
            headers["Allow"] = ", ".join(_allowed_methods(request))
        body = problem_body(slug, detail, instance=str(request.url.path),
                            status=exc.status_code)
        return problem_response(body, headers)

    @app.exception_handler(Exception)
    async def _unexpected(request: Request, exc: Exception) -> JSONResponse:
        log.exception("unhandled error on %s %s", request.method, request.url.path)
        body = problem_body("internal-error", f"Unexpected {type(exc).__name__}.",
                            instance=str(request.url.path))
        return problem_response(body)

    @app.get("/problems/{slug}", include_in_schema=False)
    async def problem_page(slug: str) -> HTMLResponse:
        p = PROBLEMS.get(slug)
        if p is None:
            raise ServiceError("not-found", f"No problem type {slug!r}.")
        page = (f"<!doctype html><title>{html.escape(p.title)}</title>"
                f"<h1>{html.escape(p.title)}</h1><p>HTTP status {p.status}.</p>"
                f"<p>{html.escape(p.description)}</p>")
        return HTMLResponse(page)
