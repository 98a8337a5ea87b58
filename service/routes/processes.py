"""``/processes``: the catalog as OGC processes, and execution."""

from __future__ import annotations

import dataclasses
import hashlib
import math
import sqlite3
import time
import uuid
from dataclasses import dataclass
from typing import Annotated, Any, Literal, get_args
from urllib.parse import urlencode

import numpy as np
from fastapi import APIRouter, Query, Request
from pydantic import ValidationError
from starlette.responses import Response

from algorithms.core.errors import InvalidInputError
from algorithms.core.params import Kind
from service import jsonio
from service.auth import owner_of
from service.binary import LIFT_CHARS, Lifted, decode_arrays, lift_base64, owned
from service.catalog import Process, processes
from service.errors import ServiceError, input_errors, unknown_input_message
from service.geometry_io import (
    DecodeLimits,
    decode_in_thread,
    parse_multipart,
    place_upload,
    resolve_refs,
)
from service.jobs.spool import Spool
from service.jobs.status import JobStatus, Outcome
from service.jobs.store import JobRecord, JobRequest
from service.jsonio import JSONResponse
from service.representation import html_alternate, process_description, process_summary
from service.routes import docs
from service.routes.common import (
    PageFormat,
    State,
    Wanted,
    base_url,
    get_process,
    job_response,
    parse_prefer,
    read_body,
    state,
    with_html,
)

router = APIRouter(tags=["processes"])

_BODY_MEMBERS = {"inputs", "outputs", "response", "subscriber", "mode", "timeLimit"}
_MODES = get_args(docs.ExecutionMode)


@router.get("/processes", operation_id="getProcesses", summary="List the processes",
            description="The processes, in the catalog's order, a page at a time: `limit` "
            "processes from `offset` on, with `next` and `prev` links to the pages around.",
            responses=with_html(docs.responses(docs.ProcessList, 422)))
async def list_processes(
    request: Request,
    limit: Annotated[int, Query(ge=1, le=10_000, description="Processes per page; by "
                                "default all of them (up to 1000).")] = 1000,
    offset: Annotated[int, Query(ge=0, le=10**6, description="Processes to skip.")] = 0,
    f: PageFormat = None,
) -> JSONResponse:
    st = state(request)
    base = base_url(request)
    every = processes(test_processes=st.settings.test_processes)
    items = [process_summary(p, base) for p in every[offset:offset + limit]]

    def page(off: int) -> dict[str, str]:
        return {"href": f"{base}/processes?" + urlencode({"limit": limit, "offset": off}),
                "type": "application/json"}

    links = [{**page(offset), "rel": "self"},
             html_alternate(page(offset)["href"], "this list as a web page")]
    if offset + limit < len(every):
        links.append({**page(offset + limit), "rel": "next"})
    if offset > 0:
        links.append({**page(max(0, offset - limit)), "rel": "prev"})
    return JSONResponse({"processes": items, "links": links, "numberMatched": len(every)})


@router.get("/processes/{processId}", operation_id="getProcessDescription",
            summary="Describe a process: its inputs and outputs",
            responses=with_html(docs.responses(docs.ProcessDescription, 404)))
async def describe_process(processId: str, request: Request,  # noqa: N803
                           f: PageFormat = None) -> JSONResponse:
    return JSONResponse(process_description(get_process(state(request), processId),
                                            base_url(request)))


def _invalid(field: str, message: str) -> ServiceError:
    return ServiceError("invalid-input", f"{field}: {message}",
                        errors=[{"input": field, "message": message}])


def _unwrap(value: Any) -> Any:
    """OGC qualified input values: ``{"value": x}`` is ``x``."""
    if isinstance(value, dict) and "value" in value and set(value) <= {
            "value", "mediaType", "encoding", "schema"}:
        return value["value"]
    return value


def _json_body(raw: bytes | bytearray, what: str = "The body", part: str | None = None
               ) -> Any:
    """The JSON document ``raw`` (a body, or the multipart ``part``); 400 naming it when it
    is not JSON or is nested too deeply (:func:`service.jsonio.loads`)."""
    try:
        return jsonio.loads(raw) if raw and not raw.isspace() else {}  # strip() copies
    except (ValueError, UnicodeDecodeError) as exc:
        errors = [{"input": part, "message": f"not valid JSON: {exc}"}] if part else None
        raise ServiceError("malformed-body", f"{what} is not valid JSON: {exc}.",
                           errors=errors) from None


async def _multipart_body(process: Process, raw: bytes | bytearray, content_type: str,
                          st: State, identify: bool) -> tuple[Any, bytes]:
    """The execute request of a multipart body, its uploads decoded into its inputs, and,
    when ``identify`` (an Idempotency-Key came with it), the bytes that identify it (the
    spec and each part's name and digest: the boundary differs between retries); else
    b"" (hashing a 48 MB body takes 35 ms). Files are decoded in worker threads, bounded
    in size and time (:func:`service.geometry_io.decode_in_thread`)."""
    spec_raw, uploads = parse_multipart(raw, content_type,
                                        max_input_bytes=st.settings.max_input_bytes)
    body = _json_body(spec_raw or b"", "The part 'spec'", part="spec")
    identity = hashlib.sha256(spec_raw or b"")
    if not isinstance(body, dict) or not uploads:
        return body, identity.digest()  # _parse_execute names what is wrong with it
    inputs = body.setdefault("inputs", {})
    if not isinstance(inputs, dict):
        raise _invalid("inputs", f"Expected an object of named inputs, got "
                       f"{type(inputs).__name__}.")
    fields = process.params.model_fields
    settings = st.settings
    limits = DecodeLimits(max_bytes=settings.max_input_bytes, max_points=settings.max_points,
                          max_nodes=settings.max_file_nodes, max_depth=settings.max_file_depth)
    for name, upload in sorted(uploads.items()):
        head = name.split(".", 1)[0]
        if head not in fields:
            raise _invalid(name, unknown_input_message(head, list(fields), process.hidden)
                           + " (A part named `spec` holds the rest of the request.)")
        if name == head and head in inputs:
            raise _invalid(name, "Given both in the spec and as a part.")
        takes = _takes(process, head) if name == head else "points"  # a member: an array
        value = await decode_in_thread(upload, takes=takes, limits=limits,
                                       time_limit=settings.decode_time_limit,
                                       threads=settings.decode_threads)
        place_upload(inputs, name, value, max_depth=settings.max_input_depth)
        if identify:
            identity.update(name.encode() + b"\0" + hashlib.sha256(upload.data).digest())
    return body, identity.digest() if identify else b""


_TAKES = {Kind.MESH: "mesh", Kind.SHAPE: "either"}


def _takes(process: Process, name: str) -> str:
    """What an uploaded geometry file gives the input ``name``: ``"mesh"`` for a mesh input,
    ``"either"`` for one that takes a mesh or points (a shape), else ``"points"`` (its
    vertices); read from the input's declared kind."""
    kind = process.kinds.get(name)
    return "points" if kind is None else _TAKES.get(kind, "points")


def _fetch_output(st: State, who: str | None) -> Any:
    """How inputs by reference read an earlier job's output: a job of the same key, finished
    successfully, and an output it has."""
    def fetch(job_id: str, output: str, field: str) -> Any:
        job = st.store.get(job_id)
        if job is None or (st.keyring is not None and job.owner != who):
            raise InvalidInputError(f"`{field}` refers to job {job_id!r}, which does not "
                                    "exist.", field=field)
        if job.status is not JobStatus.SUCCESSFUL:
            raise InvalidInputError(f"`{field}` refers to job {job_id}, which is "
                                    f"{job.status}; only results of successful jobs can be "
                                    "inputs.", field=field)
        outputs = st.store.result(job.id)
        if output not in outputs:
            raise InvalidInputError(f"`{field}` refers to the output {output!r} of job "
                                    f"{job_id}, which has only {sorted(outputs)}.", field=field)
        return outputs[output]
    return fetch


def _lifted_json_body(raw: bytearray) -> tuple[Any, Lifted | None]:
    """The JSON body, its long base64 strings cut out first (:func:`lift_base64`) when it
    is long enough to hold any; if what is left does not parse, the body itself is parsed,
    so that the error is the one it gives."""
    skeleton, lifted = lift_base64(raw) if len(raw) > LIFT_CHARS else (raw, None)
    if lifted is not None:
        try:
            return jsonio.loads(skeleton), lifted
        except (ValueError, UnicodeDecodeError):
            pass
    return _json_body(raw), None


def _parse_lifted(process: Process, body: Any, raw: bytearray, lifted: Lifted | None,
                  st: State, fetch: Any, origin: str) -> tuple[ExecuteSpec, Lifted | None]:
    """:func:`_parse_execute` of a body whose base64 strings were cut out; if it fails, or
    a cut-out string was not the data of a typed binary array, the body itself is parsed
    and executed again, so that what it gives (and any error) is exactly what the body
    says."""
    if lifted is not None:
        try:
            spec = _parse_execute(process, body, st, fetch, origin, lifted)
            if lifted.complete:
                return spec, lifted
        except (ServiceError, InvalidInputError):
            pass
        body = _json_body(raw)
    return _parse_execute(process, body, st, fetch, origin), None


@dataclass(frozen=True)
class ExecuteSpec:
    """An execute request, checked: what :func:`_parse_execute` makes of its body."""

    inputs: dict[str, Any]
    """The inputs, validated, as the method's keyword arguments (arrays may be views of
    the request body)."""
    input_bytes: int
    """The inputs' size, roughly (:func:`input_size`): what the fast path's
    ``fast_path_bytes`` is compared with."""
    cost: float
    """The job's estimated cost (:func:`job_cost`): what the fast path's ``fast_path_cost``
    is compared with."""
    time_limit: float
    """Seconds the job may run: the least of the family's (else the service's) limit, the
    process's and the request's ``timeLimit``."""
    request: JobRequest
    """What the client asked for besides the inputs (outputs, response, subscriber)."""
    mode: Literal["sync", "async"] | None
    """The body's ``mode`` (OGC API – Processes 1.0), which a ``Prefer`` header overrides;
    None when absent or neither of these."""


def input_size(value: Any, levels: int = 2) -> int:
    """The size of one validated input, in bytes, roughly: an array's bytes; for a mesh,
    graph or handles (a dataclass), or a list of arrays (point sets), the bytes of the arrays
    in it (a graph of 2M nodes is its edges' 32 MB, not one small value); 64 for anything
    else and for every member. Looks ``levels`` levels deep, no deeper."""
    if isinstance(value, np.ndarray):
        return int(value.nbytes)
    if levels > 0 and dataclasses.is_dataclass(value) and not isinstance(value, type):
        return 64 + sum(input_size(getattr(value, f.name), levels - 1)
                        for f in dataclasses.fields(value))
    if levels > 0 and isinstance(value, (list, tuple)):
        return 64 + sum(input_size(v, levels - 1) for v in value)
    return 64


def _rows(a: np.ndarray) -> int:
    return int(a.shape[0]) if a.ndim else 1


def _dimension(values: Any) -> int:
    """The dimension of a job's points: the most columns of its 2-D array inputs (or of the
    arrays in a list input), 1 if none."""
    arrays = [a for v in values for a in (v if isinstance(v, (list, tuple)) else (v,))
              if isinstance(a, np.ndarray) and a.ndim == 2]
    return max((int(a.shape[1]) for a in arrays), default=1)


def _structure_cost(value: Any) -> float:
    """A mesh, graph or handles (a dataclass): its numbers (its arrays' elements and its
    counts, such as a graph's node count) times the square root of its size (its most rows
    or its largest count), the cost of a sparse factorization on its vertices or nodes."""
    numbers, size = 0, 1
    for f in dataclasses.fields(value):
        member = getattr(value, f.name)
        if isinstance(member, np.ndarray):
            numbers += member.size
            size = max(size, _rows(member))
        elif isinstance(member, int) and not isinstance(member, bool):
            numbers += member
            size = max(size, member)
    return numbers * math.sqrt(size)


def job_cost(inputs: dict[str, Any]) -> float:
    """The estimated cost of a job on ``inputs`` (its validated keyword arguments), in rough
    operations: what decides whether it may run on the fast path (``fast_path_cost``).

    An array costs its elements times d², d the points' dimension (the most columns of any
    2-D array input): the closed forms of the fast path work in dimension d (a d×d SVD per
    point set, least squares with d + 1 unknowns), and ``alignment.homography``'s DLT, with
    (d + 1)² unknowns, grows faster still, so a high-dimensional job leaves the fast path
    at a few thousand numbers. A mesh or graph costs its numbers times the square root of
    its vertex or node count (a sparse factorization); a list of arrays, the sum of its
    arrays'. Scalars cost nothing. Not a formula per method: an estimate that sends every
    big job to the workers, the fast path's own time budget (``fast_path_seconds``)
    catching what it misjudges."""
    d2 = _dimension(inputs.values()) ** 2

    def cost(value: Any) -> float:
        if isinstance(value, np.ndarray):
            return float(value.size) * d2
        if dataclasses.is_dataclass(value) and not isinstance(value, type):
            return _structure_cost(value)
        if isinstance(value, (list, tuple)):
            return sum(float(v.size) * d2 for v in value if isinstance(v, np.ndarray))
        return 0.0

    return sum(cost(v) for v in inputs.values())


def _parse_execute(process: Process, body: Any, st: State, fetch: Any = None,
                   origin: str = "", lifted: Lifted | None = None) -> ExecuteSpec:
    if not isinstance(body, dict):
        raise ServiceError("malformed-body", "Expected a JSON object "
                           '{"inputs": {...}}, got ' + type(body).__name__ + ".")
    unknown = sorted(set(body) - _BODY_MEMBERS)
    if unknown:
        raise _invalid(unknown[0], f"Unknown member of the execute request; expected some of "
                       f"{sorted(_BODY_MEMBERS)}.")
    inputs = body.get("inputs", {})
    if not isinstance(inputs, dict):
        raise _invalid("inputs", f"Expected an object of named inputs, got "
                       f"{type(inputs).__name__}.")
    if "spec" in inputs:
        raise _invalid("spec", "'spec' names the JSON part of a multipart request, not an "
                       "input.")
    depth = st.settings.max_input_depth
    if fetch is not None:  # inputs by reference to earlier results
        inputs = {k: resolve_refs(_unwrap(v), k, fetch, origin, max_depth=depth)
                  for k, v in inputs.items()}
    try:  # typed binary arrays are decoded first: their errors name the input path
        params = process.params.model_validate(
            {k: decode_arrays(_unwrap(v), k, lifted, max_depth=depth)
             for k, v in inputs.items()},
            context={"max_points": st.settings.max_points})
    except ValidationError as exc:
        errors = input_errors(exc.errors(), list(process.params.model_fields), process.hidden)
        detail = "; ".join(f"{e['input']}: {e['message']}" for e in errors)
        raise ServiceError("invalid-input", detail, errors=errors) from None

    asked_outputs = body.get("outputs")
    outputs: tuple[str, ...] | None = None
    if asked_outputs is not None:
        if not isinstance(asked_outputs, dict) or not asked_outputs:
            raise _invalid("outputs", "Expected an object naming some of the outputs "
                           f"{sorted(process.outputs)}.")
        bad = sorted(set(asked_outputs) - set(process.outputs))
        if bad:
            raise _invalid(f"outputs.{bad[0]}", f"No such output; expected some of "
                           f"{sorted(process.outputs)}.")
        outputs = tuple(name for name in process.outputs if name in asked_outputs)
    response = body.get("response", "document")
    if response not in ("document", "raw"):
        raise _invalid("response", f"Expected 'document' or 'raw', got {response!r}.")
    family_limit = st.settings.family_time_limits.get(process.family,
                                                      st.settings.job_time_limit)
    time_limit = min(family_limit, process.time_limit or math.inf)
    if "timeLimit" in body:
        asked = body["timeLimit"]
        if isinstance(asked, bool) or not isinstance(asked, (int, float)) or \
                not math.isfinite(asked) or asked <= 0:
            raise _invalid("timeLimit", f"Expected a positive number of seconds, got {asked!r}.")
        time_limit = min(time_limit, float(asked))
    from service.callbacks import check_subscriber

    subscriber = check_subscriber(body.get("subscriber"), st.settings.callback_hosts)
    mode = body.get("mode")
    if mode is not None and mode not in _MODES:
        raise _invalid("mode", f"Expected one of {list(_MODES)}, got {mode!r}.")
    kwargs = process.kwargs(params)
    return ExecuteSpec(
        inputs=kwargs, input_bytes=sum(input_size(v) for v in kwargs.values()),
        cost=job_cost(kwargs),
        time_limit=time_limit,
        request=JobRequest(outputs=outputs, response=response, subscriber=subscriber),
        mode=mode if mode == "sync" or mode == "async" else None)


@router.post(
    "/processes/{processId}/execution", operation_id="execute",
    summary="Execute a process",
    description="Runs the process on the inputs. `Prefer: respond-async` answers 201 with the "
    "job's statusInfo at once; `Prefer: wait=N` answers 200 with the results if the job ends "
    "within N seconds, else 201; `Prefer: respond-sync` (and no preference on a short process) "
    "waits for the end. `Idempotency-Key` makes retries safe.",
    openapi_extra={"requestBody": {"required": True, "content": {"application/json": {
        "schema": docs.ExecuteRequest.model_json_schema(
            ref_template="#/components/schemas/{model}")}}}},
    responses={**docs.responses(None, 400, 404, 413, 415, 422, 429, 507),
               200: {"description": "The results document (synchronous execution): "
                     "output name -> value; with response raw and one output, its value "
                     "alone.", "content": {"application/json": {"schema": {}}}},
               201: {"description": "The job was accepted; its statusInfo.",
                     "content": {"application/json": {"schema": {
                         "$ref": "#/components/schemas/StatusInfo"}}}}},
)
async def execute(processId: str, request: Request) -> Response:  # noqa: N803
    st = state(request)
    process = get_process(st, processId)
    header = request.headers.get("content-type", "application/json")
    ctype = header.split(";")[0].strip().lower()
    multipart = ctype == "multipart/form-data"
    if ctype not in ("application/json", "") and not ctype.endswith("+json") and not multipart:
        raise ServiceError("unsupported-media-type",
                           f"Expected an application/json or multipart/form-data body, got "
                           f"{ctype!r}; send the header 'Content-Type: application/json'.")
    declared = request.headers.get("content-length", "")
    spool = st.store.spool() if st.settings.spool_bytes and declared.isdigit() \
        and int(declared) >= st.settings.spool_bytes else None
    try:  # a large body is written to disk as it arrives; sealed into the job's inputs
        return await _execute(st, process, request, header, multipart, spool)
    finally:
        if spool is not None:
            spool.discard()  # nothing if it was sealed


async def _execute(st: State, process: Process, request: Request, header: str,
                   multipart: bool, spool: Spool | None) -> Response:
    raw = await read_body(request, st.settings.max_request_bytes, spool)
    key = request.headers.get("idempotency-key")
    lifted = None
    identity: bytes | bytearray  # what identifies the request for an Idempotency-Key
    if multipart:
        body, identity = await _multipart_body(process, raw, header, st,
                                               identify=bool(key))
    else:
        body, lifted = _lifted_json_body(raw)
        identity = raw
    digest = hashlib.sha256(process.id.encode() + b"\0" + identity).hexdigest() if key else None
    prefer = parse_prefer(request.headers.getlist("prefer"))
    wanted = Wanted.of(request)  # an Accept the results cannot meet: 406 before any work

    who = owner_of(request)
    if key:
        earlier = st.store.by_idempotency_key(key, who)
        if earlier is not None:
            return await _answer_existing(st, earlier, digest, prefer, process, wanted)

    origin = f"{request.url.scheme}://{request.url.netloc}"
    spec, lifted = _parse_lifted(process, body, raw, lifted, st, _fetch_output(st, who),
                                 origin)
    active = st.engine.active
    if active >= st.settings.max_queue:
        raise ServiceError("queue-full", f"{active} jobs are waiting or running; the limit is "
                           f"{st.settings.max_queue}.", headers={"Retry-After": "5"})
    if st.keyring is not None:
        mine = st.store.count_active(who)
        if mine >= st.settings.max_queue_per_key:
            raise ServiceError("queue-full", f"This API key has {mine} jobs waiting or "
                               f"running; the limit per key is "
                               f"{st.settings.max_queue_per_key}.", headers={"Retry-After": "5"})
    # the fast path takes what is cheap by size and by estimated cost, while its workers
    # are up; everything else goes to the Dask workers
    fast = (process.fast_path and spec.input_bytes <= st.settings.fast_path_bytes
            and spec.cost <= st.settings.fast_path_cost and st.engine.fast_path_ready)
    # arrays may be views of the body: pickled on their way to a worker (or to the store),
    # copied out of it there
    inputs = spec.inputs
    wait, applied = _wait_for(prefer, process, spec.mode, st)
    # the job's record but for its id and times, as JobStore.create takes it
    args: dict[str, Any] = {"process": process.id, "request": spec.request,
                            "time_limit": spec.time_limit, "idempotency_key": key,
                            "request_hash": digest, "owner": who}
    direct = (not fast and spool is None and spec.input_bytes <= st.settings.inline_input_bytes
              and st.engine.direct(process.id))
    try:
        if (fast or direct) and wait > 0 and spec.request.subscriber is None:
            job, outcome = await _run_first(st, args, inputs, wait, direct=direct)
            if job.active:
                applied = "respond-async" if applied else None
            return job_response(st, job, outcome, applied, wanted=wanted)
        job_id = str(uuid.uuid4())
        # announced before its row is readable: a retry that finds the row before the job
        # is submitted (below) waits for the job instead of answering "still running"
        st.engine.expect(job_id)
        try:
            job = await st.store.write(st.store.create, **args, job_id=job_id, inputs=inputs,
                                       spool=spool, body=raw,
                                       encoded=lifted.decoded if lifted else ())
        except BaseException:
            st.engine.forget(job_id)
            raise
    except sqlite3.IntegrityError:  # the same key raced in from another request
        earlier = st.store.by_idempotency_key(key or "", who)
        assert earlier is not None
        return await _answer_existing(st, earlier, digest, prefer, process, wanted)
    # large inputs went to the store's file as they were (views of the body: no copy on the
    # way to the disk) and the worker reads them from there; small ones travel inline
    st.engine.submit(job, owned(inputs) if job.inputs_file is None
                     else st.store.payload(job), fast=fast)
    return await _answer(st, job.id, prefer, process, spec.mode, wanted)


async def _run_first(st: State, args: dict[str, Any], inputs: dict[str, Any], wait: float,
                     *, direct: bool = False) -> tuple[JobRecord, Outcome | None]:
    """A fast-path job the client waits for (with ``direct``: one sent to a Dask worker
    directly, ``Engine.direct``): run, then recorded with its outcome in one commit (or
    recorded accepted if it outlasts the wait; see ``Engine.run_first``).
    ``args`` are :meth:`JobStore.create`'s but the inputs, its id and its times."""
    job = JobRecord.accepted(**args, created=time.time())

    async def record(outcome: Outcome | None, started: float) -> JobRecord:
        create = dict(args, inputs=inputs, job_id=job.id, created=job.created)
        if outcome is None:
            return await st.store.write(st.store.create, **create)
        return await st.store.write(st.store.create_finished, outcome, started=started,
                                    **create)

    return await st.engine.run_first(job, inputs, wait if math.isfinite(wait) else 1e9,
                                     record, direct=direct)


def _wait_for(prefer: dict[str, str | None], process: Process, mode: str | None,
              st: State) -> tuple[float, str | None]:
    """Seconds to wait for the job before answering 201, and the preference applied."""
    if "wait" in prefer:
        try:
            wait = float(prefer["wait"] or "")
        except ValueError:
            wait = -1.0
        if not math.isfinite(wait) or wait < 0:
            raise _invalid("Prefer", f"Expected wait=N with N ≥ 0 seconds, got "
                           f"wait={prefer['wait']!r}.")
        wait = min(wait, st.settings.max_wait)
        return wait, f"wait={wait:g}"  # what was applied: a longer wait is cut to max_wait
    if "respond-async" in prefer or mode == "async":
        return 0.0, "respond-async"
    if "respond-sync" in prefer or mode == "sync":
        return math.inf, "respond-sync"
    return (0.0, None) if process.long else (math.inf, None)


async def _answer(st: State, job_id: str, prefer: dict[str, str | None], process: Process,
                  mode: str | None, wanted: Wanted) -> Response:
    wait, applied = _wait_for(prefer, process, mode, st)
    outcome = None
    if wait > 0:
        outcome = await st.engine.wait(job_id, wait if math.isfinite(wait) else 1e9)
    job = st.store.get(job_id)
    assert job is not None
    if job.active:
        applied = "respond-async" if applied else None
    return job_response(st, job, outcome, applied, waited=wait > 0, wanted=wanted)


async def _answer_existing(st: State, job: JobRecord, digest: str | None,
                           prefer: dict[str, str | None], process: Process,
                           wanted: Wanted) -> Response:
    if job.request_hash != digest:
        raise ServiceError("idempotency-conflict", "This Idempotency-Key was used for job "
                           f"{job.id} with a different request.",
                           errors=[{"input": "Idempotency-Key",
                                    "message": "reused with a different body"}])
    return await _answer(st, job.id, prefer, process, None, wanted)
