"""Helpers shared by the routers: app state, request bodies, Prefer headers, responses."""

from __future__ import annotations

from dataclasses import dataclass, field
from difflib import SequenceMatcher
from functools import lru_cache
from ipaddress import IPv4Network, IPv6Network, ip_address
from typing import Annotated, Any, Literal
from urllib.parse import quote

import numpy as np
from fastapi import Query, Request
from starlette.responses import Response

from service.auth import KeyRing, owner_of
from service.binary import encode_arrays
from service.catalog import Process, lookup, processes
from service.errors import ServiceError, problem_response
from service.geometry_io import (
    MEDIA_GLB,
    MEDIA_JSON,
    MEDIA_NPY,
    negotiate,
    npy_bytes,
)
from service.jobs.engine import Engine
from service.jobs.spool import Spool
from service.jobs.status import JobStatus, Outcome
from service.jobs.store import JobRecord, JobStore
from service.jsonio import JSONResponse
from service.metrics import Metrics
from service.representation import results_document, status_info
from service.settings import Settings, forwarded_networks

__all__ = ["State", "state", "owner", "get_process", "read_body", "parse_prefer", "job_response",
           "get_job", "Wanted", "results_response", "base_url", "PageFormat", "with_html"]


@dataclass
class State:
    settings: Settings
    store: JobStore
    engine: Engine
    keyring: KeyRing | None = None
    metrics: Metrics = field(default_factory=Metrics)


def state(request: Request) -> State:
    st: State = request.app.state.morphserve
    return st


@lru_cache(maxsize=8)
def _trusted_networks(value: str) -> tuple[IPv4Network | IPv6Network, ...] | None:
    return forwarded_networks(value)


def _from_a_trusted_proxy(request: Request) -> bool:
    """Whether the peer that sent ``request`` is in ``forwarded_allow_ips``."""
    networks = _trusted_networks(state(request).settings.forwarded_allow_ips)
    if networks is None:
        return True
    try:
        peer = ip_address(request.client.host if request.client else "")
    except ValueError:  # no peer address (a Unix socket, a test client)
        return False
    return any(peer in net for net in networks)


def _forwarded(request: Request, name: str) -> str | None:
    """The first value of an ``X-Forwarded-*`` header (a chain of proxies lists several,
    the client's first)."""
    value = request.headers.get(name)
    first = value.split(",", 1)[0].strip() if value else ""
    return first or None


def base_url(request: Request) -> str:
    """The service's root URL as the client reached it, without a final slash: the setting
    ``public_url`` when set, else the request's scheme and host, replaced by the
    ``X-Forwarded-Proto``/``X-Forwarded-Host`` a proxy sets, followed by its
    ``X-Forwarded-Prefix`` (a service mounted at ``/morphserve`` behind the proxy); those
    headers count only from the clients of ``forwarded_allow_ips``.
    Every link and ``Location`` the service answers starts with it."""
    public: str | None = state(request).settings.public_url
    if public:
        return public.rstrip("/")
    if not _from_a_trusted_proxy(request):
        return f"{request.url.scheme}://{request.url.netloc}"
    scheme = _forwarded(request, "x-forwarded-proto") or request.url.scheme
    host = _forwarded(request, "x-forwarded-host") or request.url.netloc
    prefix = (_forwarded(request, "x-forwarded-prefix") or "").strip("/")
    if scheme not in ("http", "https") or any(c in host for c in "/?#@ \\"):
        scheme, host = request.url.scheme, request.url.netloc  # not a URL's parts: ignored
    prefix = "/" + quote(prefix, safe="/-._~") if prefix else ""
    return f"{scheme}://{host}{prefix}"


#: The ``f`` query parameter of the documents that have an HTML page (/, /processes,
#: /processes/{id}, /jobs, /jobs/{id}). :class:`service.html.middleware.HtmlMiddleware`
#: answers ``f=html`` (and a browser's Accept header) before the route runs; ``f=json``, or
#: no ``f`` and an Accept header that does not prefer HTML, reaches the route, which answers
#: JSON. Declared on the routes so that the API definition shows it.
PageFormat = Annotated[Literal["json", "html"] | None, Query(
    description="The representation, instead of the Accept header: json (the document) or "
    "html (the page a browser shows).")]


def with_html(responses: dict[int | str, dict[str, Any]]) -> dict[int | str, dict[str, Any]]:
    """``responses`` (:func:`service.routes.docs.responses`) whose 200 may also be the
    document's HTML page (``text/html``), as for a :data:`PageFormat` route."""
    ok = dict(responses.get(200, {"description": "OK"}))
    ok["content"] = {**ok.get("content", {}),
                     "text/html": {"schema": {"type": "string"}}}
    return {**responses, 200: ok}


def owner(st: State, request: Request) -> str | None:
    """Whose jobs this request may see: its key's owner, or None (all) on an open service."""
    return owner_of(request) if st.keyring is not None else None


def closest_processes(wanted: str, offered: list[str], n: int = 3) -> list[str]:
    """The ids of ``offered`` a mistyped process id most likely meant, best first (at most
    ``n``, none when nothing is close). An id scores the better of its likeness to ``wanted``
    as a whole (``registraton.icp``) and its method name's likeness to the one wanted
    (``icp``, ``alignment.icp``), the latter a little less outside the family named; only
    ids scoring nearly as well as the best are kept, so a clear match comes alone."""
    wanted = wanted.lower()
    family, _, method = wanted.rpartition(".")

    def score(candidate: str) -> float:
        their_family, _, their_method = candidate.lower().partition(".")
        by_method = SequenceMatcher(None, method, their_method).ratio()
        if their_family != family:
            by_method -= 0.05
        return max(SequenceMatcher(None, wanted, candidate.lower()).ratio(), by_method)

    scored = sorted(((score(c), c) for c in offered), key=lambda sc: -sc[0])
    if not scored or scored[0][0] < 0.6:
        return []
    best = scored[0][0]
    return [c for sc, c in scored[:n] if sc >= max(0.6, best - 0.05)]


def get_process(st: State, process_id: str) -> Process:
    process = lookup(process_id, test_processes=st.settings.test_processes)
    if process is None:
        offered = [p.id for p in processes(test_processes=st.settings.test_processes)]
        guesses = closest_processes(process_id, offered)
        hint = (" Did you mean " + " or ".join(f"`{g}`" for g in guesses) + "?"
                if guesses else "")
        raise ServiceError("no-such-process", f"No process `{process_id}`.{hint} "
                           "GET /processes lists the processes offered.")
    return process


def get_job(st: State, job_id: str, request: Request) -> JobRecord:
    """The job, if this request's key owns it: another key's job is as absent as a missing
    one (404), so that ids cannot be probed."""
    job = st.store.get(job_id)
    who = owner(st, request)
    if job is None or (who is not None and job.owner != who):
        raise ServiceError("no-such-job", f"No job {job_id!r}.")
    return job


async def read_body(request: Request, limit: int, spool: Spool | None = None) -> bytearray:
    """The request body, refused with 413 as soon as it passes ``limit`` bytes; each chunk
    also goes to ``spool`` (written to disk as it arrives) when one is given."""
    declared = request.headers.get("content-length")
    if declared is not None and declared.isdigit() and int(declared) > limit:
        raise ServiceError("payload-too-large",
                           f"The body has {int(declared)} bytes; the limit is {limit}.")
    chunks, size = [], 0
    async for chunk in request.stream():
        size += len(chunk)
        if size > limit:
            raise ServiceError("payload-too-large", f"The body exceeds the limit of {limit} "
                               "bytes.")
        chunks.append(chunk)
        if spool is not None:
            spool.write(chunk)
    # a bytearray: arrays of an uploaded .npy part are views of it, writable, not copies
    return bytearray().join(chunks)


def parse_prefer(values: list[str]) -> dict[str, str | None]:
    """RFC 7240 preferences: ``respond-async, wait=10`` -> {"respond-async": None, "wait": "10"}.
    Parameters after ``;`` are ignored; the first occurrence of a preference wins."""
    prefs: dict[str, str | None] = {}
    for header in values:
        for item in header.split(","):
            token = item.split(";", 1)[0].strip()
            if not token:
                continue
            name, _, value = token.partition("=")
            prefs.setdefault(name.strip().lower(), value.strip().strip('"') or None)
    return prefs


@dataclass(frozen=True)
class Wanted:
    """How the client wants results: ``fmt`` json, glb or npy (:func:`negotiate`),
    whether JSON should carry arrays as typed binary arrays (``Prefer: arrays=binary``), and
    ``base``, the root URL the client reached the service at (:func:`base_url`), which the
    ``Location`` and ``Link`` headers of the answer start with."""

    fmt: str = "json"
    binary_arrays: bool = False
    base: str = ""

    @classmethod
    def of(cls, request: Request, f: str | None = None) -> Wanted:
        prefs = parse_prefer(request.headers.getlist("prefer"))
        return cls(negotiate(request.headers.get("accept"), f),
                   prefs.get("arrays") == "binary", base_url(request))


def results_response(st: State, job: JobRecord, outputs: dict[str, Any], wanted: Wanted,
                     headers: dict[str, str] | None = None, *,
                     only: str | None = None) -> Response:
    """The results of a successful job in the wanted format; ``only`` names a single output
    (``/jobs/{id}/results/{output}``), sent as its bare value."""
    headers = dict(headers or {})
    if only is not None:
        if only not in outputs:
            raise ServiceError("no-such-output", f"Job {job.id} has no output {only!r}; it "
                               f"has {sorted(outputs)}.")
        doc: Any = outputs[only]
    else:
        doc = results_document(outputs, job.request)
    if wanted.fmt == "glb":
        process = lookup(job.process, test_processes=st.settings.test_processes)
        glb = process.glb(outputs, st.store.inputs(job)) if process is not None else None
        if glb is None:
            raise ServiceError("not-acceptable", f"The results of {job.process} hold no "
                               f"geometry to send as {MEDIA_GLB}; ask for {MEDIA_JSON}.")
        return Response(glb, media_type=MEDIA_GLB, headers=headers)
    if wanted.fmt == "npy":
        # the document's values, or the one value of a raw response or a single output
        values = doc.values() if isinstance(doc, dict) and only is None else [doc]
        arrays = [v for v in values if isinstance(v, np.ndarray) and v.dtype.kind in "biuf"]
        if len(arrays) != 1:
            names = [k for k, v in outputs.items() if isinstance(v, np.ndarray)]
            raise ServiceError("not-acceptable", f"{MEDIA_NPY} holds one array; these "
                               f"results have {len(arrays)}. Ask for one output: "
                               f"/jobs/{job.id}/results/{{output}}, output one of {names}.")
        return Response(npy_bytes(arrays[0]), media_type=MEDIA_NPY,
                        headers=headers)
    if wanted.binary_arrays:
        doc = encode_arrays(doc)
        headers["Preference-Applied"] = ", ".join(
            p for p in (headers.get("Preference-Applied"), "arrays=binary") if p)
    return JSONResponse(doc, headers=headers)


def job_response(st: State, job: JobRecord, outcome: Outcome | None,
                 applied: str | None, *, waited: bool = True,
                 wanted: Wanted = Wanted()) -> Response:
    """How an execution request is answered once its job is as far as it will get: the
    results (200), the failure as a problem, or the statusInfo (201) of a job still under way
    or of one the client asked to run asynchronously (``waited`` false)."""
    base = wanted.base
    # rel=monitor as a bare token (RFC 8288 allows it, and clients that look for the text
    # "rel=monitor" find it): the job's status, for results answered synchronously too
    headers = {"Link": f"<{base}/jobs/{job.id}>; rel=monitor"}
    if not waited:
        headers["Location"] = f"{base}/jobs/{job.id}"
        if applied:
            headers["Preference-Applied"] = applied
        return JSONResponse(status_info(job, base), status_code=201, headers=headers)
    if job.status is JobStatus.SUCCESSFUL:
        outputs = outcome.outputs if outcome is not None and outcome.outputs is not None \
            else st.store.result(job.id)
        # relative, as RFC 9110 allows: clients take the job id from it; the links and
        # Location, which clients follow, are absolute
        headers["Content-Location"] = f"/jobs/{job.id}/results"
        if applied:
            headers["Preference-Applied"] = applied
        return results_response(st, job, outputs, wanted, headers)
    if job.status in (JobStatus.FAILED, JobStatus.DISMISSED):
        return failure_response(job, headers)
    headers["Location"] = f"{base}/jobs/{job.id}"
    if applied:
        headers["Preference-Applied"] = "respond-async"
    return JSONResponse(status_info(job, base), status_code=201, headers=headers)


def failure_response(job: JobRecord, headers: dict[str, str] | None = None) -> JSONResponse:
    """The problem a failed or dismissed job ended with."""
    from service.problems import dismissed_problem, problem_body

    if job.status is JobStatus.DISMISSED:
        body = dismissed_problem()
    else:
        body = dict(job.problem or problem_body("job-failed", job.message or "failed"))
    body["instance"] = f"/jobs/{job.id}"
    return problem_response(body, headers)
