"""The clients: :class:`Client` and :class:`AsyncClient`, with their jobs.

The HTTP contract is written once, in :class:`_Protocol`, as *flows*: generators that yield
the requests they need (or a pause) and receive the responses, without doing any I/O
themselves ("sans-IO", as h11 and httpcore do). :class:`Client` runs a flow over
``httpx.Client`` and ``time.sleep``; :class:`AsyncClient` runs the very same flow over
``httpx.AsyncClient`` and ``asyncio.sleep``. So the two clients cannot drift apart: each public
method of either is one line that picks a flow.
"""

from __future__ import annotations

import asyncio
import concurrent.futures
import math
import os
import time
from collections.abc import (
    AsyncIterator,
    Callable,
    Generator,
    Iterable,
    Iterator,
    Mapping,
    Sequence,
)
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path
from types import TracebackType
from typing import Any, Generic, TypeVar, cast, overload
from urllib.parse import quote, unquote

import httpx

from ._batch import BatchItem, batch_inputs, item_flow
from ._exceptions import (
    APIError,
    JobDismissed,
    JobFailed,
    MorphserveError,
    ProtocolError,
    ResultNotReady,
    TransportError,
    WaitTimeout,
    problem_from_response,
)
from ._geometry import needs_description, prepare_inputs
from ._models import (
    JOB_STATES,
    JobStatus,
    ProcessDescription,
    ProcessSummary,
    Results,
    dumps,
    npy_bytes,
    split_npy_parts,
    to_json_value,
)
from ._progress import ProgressDisplay, make_progress
from ._typed import AsyncTypedCalls, TypedCalls

__all__ = ["DEFAULT_URL", "MAX_LISTED_JOBS", "AsyncClient", "AsyncJob", "Client", "Job",
           "as_completed"]

try:
    __version__ = version("morphserve")
except PackageNotFoundError:  # running from a source tree that was never installed
    __version__ = "0.0.0"

DEFAULT_URL = "http://127.0.0.1:8000"
"""Where ``morphserve serve`` listens by default."""
MAX_LISTED_JOBS = 1000
"""The most jobs ``jobs()`` gathers when no ``limit`` is given."""
_PAGE_SIZE = 100
"""Jobs asked for per page of ``GET /jobs``."""
_WAIT_MARGIN = 10.0
"""Seconds added to ``Prefer: wait=N`` for the read timeout of that request."""
_MAX_POLL_INTERVAL = 1.0

T = TypeVar("T")


@dataclass(frozen=True)
class _Sleep:
    """A step of a flow: pause this long before the next request."""

    seconds: float


_Flow = Generator["httpx.Request | _Sleep", Any, T]
"""A flow yields requests (answered with an ``httpx.Response``, or a TransportError thrown in)
and pauses (answered with None), and returns its result."""


@dataclass(frozen=True)
class _Submitted:
    """What the service said about a job just created or looked up."""

    job_id: str
    process_id: str | None
    status: JobStatus | None = None
    results: Results | None = None


def _waits_hint(error: ResultNotReady, call: str) -> ResultNotReady:
    """The service's "not ready" with what a Python caller does instead of polling: the
    same problem, its detail ending with the call that waits; the service's own error is
    its ``__cause__`` (what the CLI prints)."""
    return ResultNotReady(error.status, error.type, error.title,
                          f"{error.detail} ({call} waits for it)".lstrip(),
                          errors=error.errors, instance=error.instance, response=error.response)


def _document(response: httpx.Response) -> dict[str, Any]:
    """The JSON object of a success; the problem it stands for, raised, otherwise."""
    if response.status_code >= 400:
        raise problem_from_response(response)
    try:
        document = response.json()
    except ValueError:
        document = None
    if not isinstance(document, dict):
        raise ProtocolError(
            f"Expected a JSON object from {response.request.method} {response.request.url}, "
            f"got {response.headers.get('Content-Type', 'no content type')}: "
            f"{response.text[:200]!r}"
        )
    return document


def _job_id_from(url: str | None, header: str) -> str:
    """The job id in ``/jobs/{jobID}`` or ``/jobs/{jobID}/results``, relative or absolute."""
    segments = [s for s in httpx.URL(url or "").path.split("/") if s]
    for here in range(len(segments) - 2, -1, -1):  # the last "jobs" followed by an id
        if segments[here] == "jobs":
            return unquote(segments[here + 1])
    raise ProtocolError(f"Expected a `{header}: /jobs/{{jobID}}...` header, got {url!r}.")


def _link(document: Mapping[str, Any], rel: str) -> str | None:
    for link in document.get("links") or ():
        if isinstance(link, Mapping) and link.get("rel") == rel and link.get("href"):
            return str(link["href"])
    return None


def _names(value: str | Iterable[str] | None) -> list[str]:
    if value is None:
        return []
    return [value] if isinstance(value, str) else list(value)


#: The largest piece a request body is handed to httpx in.
PIECE_BYTES = 1 << 20


class _Pieces(httpx.SyncByteStream, httpx.AsyncByteStream):
    """A request body handed to httpx in pieces of at most :data:`PIECE_BYTES` (views, no
    copies; the Content-Length stays the body's). httpcore writes a piece by ``send()``
    after ``send()``, slicing off what was sent: a copy of all that remains each time,
    so that one 60 MB piece cost ~150 ms of copying (a 1 MiB one, nothing to speak of)."""

    def __init__(self, stream: httpx.SyncByteStream | httpx.AsyncByteStream) -> None:
        self._stream = stream

    @staticmethod
    def _split(chunk: bytes) -> Iterator[bytes]:
        if len(chunk) <= PIECE_BYTES:
            yield chunk
            return
        view = memoryview(chunk)
        for start in range(0, len(view), PIECE_BYTES):
            # a view, not bytes as httpx's stream types say: httpcore writes any buffer
            yield view[start:start + PIECE_BYTES]  # type: ignore[misc]

    def __iter__(self) -> Iterator[bytes]:
        # iterated synchronously by a sync client, whose request stream is a sync one
        for chunk in cast(httpx.SyncByteStream, self._stream):
            yield from self._split(chunk)

    async def __aiter__(self) -> AsyncIterator[bytes]:
        async for chunk in cast(httpx.AsyncByteStream, self._stream):
            for piece in self._split(chunk):
                yield piece


class _Protocol:
    """The HTTP contract as flows: what to ask, in which order, and what the answers mean.

    ``build_request`` is the ``build_request`` method of the httpx client, which applies its
    base URL, headers and timeout.
    """

    def __init__(self, build_request: Callable[..., httpx.Request], timeout: float | None) -> None:
        self._build_request = build_request
        self._timeout = timeout
        self._descriptions: dict[str, ProcessDescription] = {}
        """Process descriptions already fetched, to read what their inputs take."""

    def _get(self, url: str, **kwargs: Any) -> httpx.Request:
        return self._build_request("GET", url, **kwargs)

    def processes(self) -> _Flow[list[ProcessSummary]]:
        document = _document((yield self._get("/processes")))
        return [ProcessSummary.from_json(p) for p in document.get("processes") or ()]

    def describe(self, process_id: str) -> _Flow[ProcessDescription]:
        document = _document((yield self._get(f"/processes/{quote(process_id, safe='')}")))
        description = ProcessDescription.from_json(document)
        self._descriptions[process_id] = description
        return description

    def _input_schemas(self, process_id: str) -> _Flow[dict[str, Any]]:
        """The JSON Schema of each input of the process (its description fetched once)."""
        description = self._descriptions.get(process_id)
        if description is None:
            description = yield from self.describe(process_id)
        return {name: spec.get("schema") for name, spec in description.inputs.items()
                if isinstance(spec, Mapping)}

    def execute(
        self,
        process_id: str,
        inputs: Mapping[str, Any],
        *,
        wait: float | None,
        outputs: Iterable[str] | Mapping[str, Any] | None,
        idempotency_key: str | None,
        time_limit: float | None = None,
    ) -> _Flow[_Submitted]:
        # what each input takes (points, a mesh, a choice) decides how geometry objects and
        # strings go: the description is asked for once, and only when that matters
        schemas = (yield from self._input_schemas(process_id)) \
            if needs_description(inputs) else None
        values, files = prepare_inputs(inputs, schemas)
        rest, arrays = split_npy_parts(values)
        body: dict[str, Any] = {
            "inputs": {name: to_json_value(value, name) for name, value in rest.items()}
        }
        if time_limit is not None:
            body["timeLimit"] = time_limit
        if outputs is not None:
            if isinstance(outputs, Mapping):
                body["outputs"] = {name: dict(spec or {}) for name, spec in outputs.items()}
            else:
                body["outputs"] = {name: {} for name in _names(outputs)}
        headers = {}
        extra: dict[str, Any] = {}
        if wait is None:
            headers["Prefer"] = "respond-async"
        else:
            if wait < 0:
                raise ValueError(f"Expected `wait` to be 0 or more seconds, got {wait}.")
            headers["Prefer"] = f"wait={math.ceil(wait)}, arrays=binary"
            if self._timeout is not None:
                extra["timeout"] = max(self._timeout, math.ceil(wait) + _WAIT_MARGIN)
        if idempotency_key is not None:
            headers["Idempotency-Key"] = idempotency_key
        url = f"/processes/{quote(process_id, safe='')}/execution"
        if files or arrays:  # multipart: geometry files and large arrays (.npy) as parts,
            parts = {"spec": ("spec.json", dumps(body), "application/json")}  # the rest: spec
            for name, path in files.items():
                parts[name] = (path.name, path.read_bytes(), "application/octet-stream")
            for name, array in arrays.items():
                parts[name] = (f"{name}.npy", npy_bytes(array), "application/x-npy")
            request = self._build_request("POST", url, files=parts, headers=headers, **extra)
        else:
            headers["Content-Type"] = "application/json"
            request = self._build_request("POST", url, content=dumps(body), headers=headers,
                                          **extra)
        request.stream = _Pieces(request.stream)
        response = yield request
        document = _document(response)
        if response.status_code == 200:  # done within the wait: the results document
            job_id = _job_id_from(response.headers.get("Content-Location"), "Content-Location")
            return _Submitted(job_id, process_id, results=Results(document))
        status = JobStatus.from_json(document)
        location = response.headers.get("Location")
        job_id = _job_id_from(location, "Location") if location else status.job_id
        return _Submitted(job_id, status.process_id or process_id, status=status)

    def status(self, job_id: str) -> _Flow[JobStatus]:
        document = _document((yield self._get(f"/jobs/{quote(job_id, safe='')}")))
        return JobStatus.from_json(document)

    def lookup(self, job_id: str) -> _Flow[_Submitted]:
        status = yield from self.status(job_id)
        return _Submitted(status.job_id, status.process_id, status=status)

    def jobs(
        self,
        status: str | Iterable[str] | None,
        process: str | Iterable[str] | None,
        limit: int | None,
    ) -> _Flow[list[JobStatus]]:
        wanted = _names(status)
        for name in wanted:
            if name not in JOB_STATES:
                raise ValueError(f"Expected `status` among {', '.join(JOB_STATES)}, got {name!r}.")
        if limit is not None and limit < 1:
            raise ValueError(f"Expected `limit` to be 1 or more, got {limit}.")
        most = MAX_LISTED_JOBS if limit is None else limit
        params = [("status", s) for s in wanted] + [("processID", p) for p in _names(process)]
        request = self._get("/jobs", params=[*params, ("limit", min(most, _PAGE_SIZE))])
        found: list[JobStatus] = []
        followed: set[str] = set()
        while True:
            document = _document((yield request))
            found.extend(JobStatus.from_json(job) for job in document.get("jobs") or ())
            following = _link(document, "next")
            if len(found) >= most or following is None or following in followed:
                return found[:most]
            followed.add(following)
            request = self._get(following)

    def results(self, job: _JobBase) -> _Flow[Results]:
        if job._results is None:
            job._results = yield from self.fetch_results(job.id)
        return job._results

    def fetch_results(self, job_id: str) -> _Flow[Results]:
        url = f"/jobs/{quote(job_id, safe='')}/results"
        return Results(_document((yield self._get(url, headers={"Prefer": "arrays=binary"}))))

    def as_completed(
        self, jobs: list[_JobBase], *, timeout: float | None, poll_interval: float
    ) -> Generator[httpx.Request | _Sleep | _JobBase, Any, None]:
        """Poll the unfinished ``jobs`` in turn; yield each job (not a request) as soon as
        it is seen finished, its final status kept. Raises TimeoutError when ``timeout``
        seconds pass first."""
        if poll_interval <= 0:
            raise ValueError(f"Expected `poll_interval` above 0 s, got {poll_interval}.")
        deadline = None if timeout is None else time.monotonic() + timeout
        pending = []
        for job in jobs:
            if job._results is not None or (job._final is not None):
                yield job
            else:
                pending.append(job)
        interval = poll_interval
        while pending:
            still = []
            for job in pending:
                status = yield from self.status(job.id)
                if status.done:
                    job._final = status
                    yield job
                else:
                    still.append(job)
            pending = still
            if not pending:
                return
            pause = interval
            if deadline is not None:
                remaining = deadline - time.monotonic()
                if remaining <= 0:
                    raise TimeoutError(f"{len(pending)} of {len(jobs)} jobs did not end within "
                                       f"{timeout:g} s.")
                pause = min(pause, remaining)
            yield _Sleep(pause)
            interval = min(interval * 1.5, max(poll_interval, _MAX_POLL_INTERVAL))

    def download(self, job_id: str, fmt: str, output: str | None) -> _Flow[bytes]:
        """The results (or one output) as glTF binary (``glb``) or ``.npy``."""
        url = f"/jobs/{quote(job_id, safe='')}/results"
        if output is not None:
            url += f"/{quote(output, safe='')}"
        media = {"glb": "model/gltf-binary", "npy": "application/x-npy"}[fmt]
        response: httpx.Response = yield self._get(url, headers={"Accept": media})
        if response.status_code >= 400:
            _document(response)  # raises the problem
        return response.content

    def dismiss(self, job_id: str) -> _Flow[JobStatus]:
        request = self._build_request("DELETE", f"/jobs/{quote(job_id, safe='')}")
        return JobStatus.from_json(_document((yield request)))

    def wait(
        self,
        job_id: str,
        *,
        timeout: float | None,
        progress: bool | ProgressDisplay,
        poll_interval: float,
    ) -> _Flow[JobStatus]:
        if poll_interval <= 0:
            raise ValueError(f"Expected `poll_interval` above 0 s, got {poll_interval}.")
        deadline = None if timeout is None else time.monotonic() + timeout
        bar = make_progress(progress)
        interval = poll_interval
        try:
            while True:
                status = yield from self.status(job_id)
                if bar is not None:
                    bar.update(status.progress, status.message or status.status)
                if status.done:
                    break
                pause = interval
                if deadline is not None:
                    remaining = deadline - time.monotonic()
                    if remaining <= 0:
                        raise WaitTimeout(job_id, float(timeout or 0), status)
                    pause = min(pause, remaining)
                yield _Sleep(pause)
                interval = min(interval * 1.5, max(poll_interval, _MAX_POLL_INTERVAL))
        finally:
            if bar is not None:
                bar.close()
        if status.status != "successful":
            yield from self._raise_outcome(status)
        return status

    def _raise_outcome(self, status: JobStatus) -> _Flow[None]:
        """Raise why a job failed or was dismissed: the problem its results URL answers."""
        response = yield self._get(f"/jobs/{quote(status.job_id, safe='')}/results")
        if response.status_code >= 400:
            raise problem_from_response(response)
        cls = JobDismissed if status.status == "dismissed" else JobFailed
        raise cls(
            response.status_code,
            f"/problems/{cls.slug}",
            f"Job {status.status}",
            status.message or f"Job {status.job_id} ended {status.status}.",
        )


class _Stepper(Generic[T]):
    """Runs one flow: iterate to get the steps it asks for, ``send`` back each outcome.

    Used as a context manager so that the flow is closed (its progress bar ended) even when
    the driver is interrupted.
    """

    def __init__(self, flow: _Flow[T]) -> None:
        self._flow = flow
        self._outcome: Any = None
        self.result: T

    def __iter__(self) -> Iterator[httpx.Request | _Sleep]:
        try:
            step = next(self._flow)
            while True:
                yield step
                outcome, self._outcome = self._outcome, None
                if isinstance(outcome, BaseException):
                    step = self._flow.throw(outcome)
                else:
                    step = self._flow.send(outcome)
        except StopIteration as stop:
            self.result = stop.value

    def send(self, outcome: httpx.Response | MorphserveError | None) -> None:
        self._outcome = outcome

    def __enter__(self) -> _Stepper[T]:
        return self

    def __exit__(self, *exc_info: object) -> None:
        self._flow.close()


def _http_options(base_url: str, api_key: str | None, timeout: float | None) -> dict[str, Any]:
    """Keyword arguments shared by the httpx client of either flavour."""
    if api_key is None:
        api_key = os.environ.get("MORPHSERVE_API_KEY")
    headers = {
        "Accept": "application/json, application/problem+json",
        "User-Agent": f"morphserve-python/{__version__}",
    }
    if api_key:
        headers["Authorization"] = f"Bearer {api_key}"
    return {"base_url": base_url, "headers": headers, "timeout": timeout}


class _JobBase:
    """What a job of either client flavour knows about itself."""

    def __init__(self, client: Any, submitted: _Submitted) -> None:
        self._client = client
        self._protocol: _Protocol = client._protocol
        self._id = submitted.job_id
        self._process_id = submitted.process_id
        self._results = submitted.results
        self.submitted_status = submitted.status
        """The status the service answered when the job was created or looked up, if any."""
        status = submitted.status
        self._final: JobStatus | None = status if status is not None and status.done else None
        """The job's last status once seen finished (successful, failed or dismissed)."""

    @property
    def id(self) -> str:
        """The job id (``jobID``) the service gave."""
        return self._id

    @property
    def process_id(self) -> str | None:
        """The process this job runs."""
        return self._process_id

    def __repr__(self) -> str:
        return f"<{type(self).__name__} {self._id} of {self._process_id}>"

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, _JobBase):
            return NotImplemented
        return (self._client.base_url, self._id) == (other._client.base_url, other._id)

    def __hash__(self) -> int:
        return hash(self._id)


class _ClientBase:
    """Configuration shared by both client flavours."""

    _http: httpx.Client | httpx.AsyncClient

    def __init__(self, http: httpx.Client | httpx.AsyncClient, timeout: float | None) -> None:
        self._http = http
        self._protocol = _Protocol(http.build_request, timeout)

    @property
    def base_url(self) -> str:
        """The service URL every request is relative to."""
        return str(self._http.base_url)

    def __repr__(self) -> str:
        return f"<{type(self).__name__} {self.base_url}>"


class Job(_JobBase):
    """A job of the service, as seen from a :class:`Client`.

    Get one from :meth:`Client.execute` or :meth:`Client.job`.
    """

    _client: Client

    def status(self) -> JobStatus:
        """Ask the service where the job stands."""
        return self._client._run(self._protocol.status(self._id))

    def wait(
        self,
        *,
        timeout: float | None = None,
        progress: bool | ProgressDisplay = False,
        poll_interval: float = 0.05,
    ) -> JobStatus:
        """Poll until the job ends; return its final status when successful.

        Parameters
        ----------
        timeout : float, optional
            Seconds to wait at most; then :class:`WaitTimeout` is raised (the job goes on).
            None waits for as long as it takes.
        progress : bool or ProgressBar
            Draw a progress bar on stderr (or on the given bar's stream) while waiting.
        poll_interval : float
            Seconds between the first polls; the interval grows by half each time, up to 1 s
            (or ``poll_interval`` when larger).

        Raises
        ------
        JobFailed
            The job failed (``TimeLimitExceeded`` when it ran out of time, ``WorkerLost`` when
            its worker kept dying). What is raised is the problem the service answers for the
            job's results, so a job that found its input degenerate raises ``InvalidInput``.
        JobDismissed
            The job was dismissed.
        WaitTimeout
            ``timeout`` expired first.
        """
        flow = self._protocol.wait(
            self._id, timeout=timeout, progress=progress, poll_interval=poll_interval
        )
        return self._client._run(flow)

    def results(self) -> Results:
        """The outputs of the successful job; fetched once, then kept.

        Raises :class:`ResultNotReady` while the job runs, :class:`JobFailed` or
        :class:`JobDismissed` for a job that ended otherwise. ``results().save("out.glb")``
        writes the result's geometry (see :meth:`Results.save`).
        """
        try:
            results = self._client._run(self._protocol.results(self))
        except ResultNotReady as error:
            raise _waits_hint(error, "job.result()") from error
        results._download = self._download
        return results

    def result(self, timeout: float | None = None) -> Results:
        """The outputs, once the job has ended: waits for it as a
        ``concurrent.futures.Future`` does.

        Raises :class:`WaitTimeout` (a ``TimeoutError``) when ``timeout`` seconds pass first
        (the job goes on), and the job's own error when it failed (:class:`JobFailed`,
        :class:`InvalidInput` ...) or was dismissed (:class:`JobDismissed`).
        """
        if self._results is None:
            self.wait(timeout=timeout)
        return self.results()

    def exception(self, timeout: float | None = None) -> APIError | None:
        """The error the job ended with (None when it succeeded), once it has ended.
        Raises :class:`WaitTimeout` when ``timeout`` seconds pass first, and what keeps
        the SDK from knowing (:class:`TransportError`)."""
        try:
            self.result(timeout)
        except APIError as error:
            return error
        return None

    def done(self) -> bool:
        """Whether the job has ended (asks the service unless it was seen ended)."""
        if self._results is None and self._final is None:
            status = self.status()
            if status.done:
                self._final = status
        return self._results is not None or self._final is not None

    def _download(self, fmt: str, output: str | None) -> bytes:
        return self._client._run(self._protocol.download(self._id, fmt, output))

    def save(self, path: str | os.PathLike[str], output: str | None = None) -> Path:
        """Write the job's results to ``path`` (.glb, .ply, .obj, .stl, .off, .npy or .json; see
        :meth:`Results.save`)."""
        return self.results().save(path, output)

    def dismiss(self) -> JobStatus:
        """Cancel the job if queued or running, or remove it if finished (``DELETE``)."""
        return self._client._run(self._protocol.dismiss(self._id))


class AsyncJob(_JobBase):
    """A job of the service, as seen from an :class:`AsyncClient`; see :class:`Job`."""

    _client: AsyncClient

    async def status(self) -> JobStatus:
        """Ask the service where the job stands (see :meth:`Job.status`)."""
        return await self._client._run(self._protocol.status(self._id))

    async def wait(
        self,
        *,
        timeout: float | None = None,
        progress: bool | ProgressDisplay = False,
        poll_interval: float = 0.05,
    ) -> JobStatus:
        """Poll until the job ends (see :meth:`Job.wait`)."""
        flow = self._protocol.wait(
            self._id, timeout=timeout, progress=progress, poll_interval=poll_interval
        )
        return await self._client._run(flow)

    async def results(self) -> Results:
        """The outputs of the successful job (see :meth:`Job.results`)."""
        try:
            return await self._client._run(self._protocol.results(self))
        except ResultNotReady as error:
            raise _waits_hint(error, "await job.result()") from error

    async def result(self, timeout: float | None = None) -> Results:
        """The outputs, once the job has ended (see :meth:`Job.result`); ``await job`` is
        the same as ``await job.result()``."""
        if self._results is None:
            await self.wait(timeout=timeout)
        return await self.results()

    def __await__(self) -> Generator[Any, None, Results]:
        return self.result().__await__()

    async def exception(self, timeout: float | None = None) -> APIError | None:
        """The error the job ended with, None when it succeeded (see :meth:`Job.exception`).
        """
        try:
            await self.result(timeout)
        except APIError as error:
            return error
        return None

    async def done(self) -> bool:
        """Whether the job has ended (see :meth:`Job.done`)."""
        if self._results is None and self._final is None:
            status = await self.status()
            if status.done:
                self._final = status
        return self._results is not None or self._final is not None

    async def save(self, path: str | os.PathLike[str], output: str | None = None) -> Path:
        """Write the job's results to ``path`` (.glb, .ply, .obj, .stl, .off, .npy or .json; see
        :meth:`Results.save`)."""
        results = await self.results()
        if Path(path).suffix.lower() != ".glb":
            return results.save(path, output)
        data = await self._client._run(self._protocol.download(self._id, "glb", output))
        Path(path).write_bytes(data)
        return Path(path)

    async def dismiss(self) -> JobStatus:
        """Cancel or remove the job (see :meth:`Job.dismiss`)."""
        return await self._client._run(self._protocol.dismiss(self._id))


class Client(_ClientBase, TypedCalls):
    """A synchronous client of a morphserve service.

    Parameters
    ----------
    base_url : str
        Where the service answers.
    api_key : str, optional
        Sent as ``Authorization: Bearer <key>``; defaults to the ``MORPHSERVE_API_KEY``
        environment variable, and to no header when that is unset or empty.
    timeout : float or None
        Seconds to wait for any one answer (None: forever). A request with ``wait=N`` waits
        at least N + 10 s.
    transport : httpx.BaseTransport, optional
        Replaces the network, e.g. with ``httpx.MockTransport`` in tests.

    Examples
    --------
    >>> with Client("http://127.0.0.1:8000") as client:  # doctest: +SKIP
    ...     job = client.execute("alignment.rigid", source=a, target=b)
    ...     job.wait(progress=True)
    ...     job.results()["transform"]
    """

    _http: httpx.Client

    def __init__(
        self,
        base_url: str = DEFAULT_URL,
        *,
        api_key: str | None = None,
        timeout: float | None = 30.0,
        transport: httpx.BaseTransport | None = None,
    ) -> None:
        http = httpx.Client(transport=transport, **_http_options(base_url, api_key, timeout))
        super().__init__(http, timeout)

    def _perform(self, step: httpx.Request | _Sleep) -> httpx.Response | MorphserveError | None:
        if isinstance(step, _Sleep):
            time.sleep(step.seconds)
            return None
        try:
            return self._http.send(step)
        except httpx.HTTPError as error:
            return TransportError.from_httpx(error)

    def _run(self, flow: _Flow[T]) -> T:
        with _Stepper(flow) as stepper:
            for step in stepper:
                stepper.send(self._perform(step))
        return stepper.result

    def processes(self) -> list[ProcessSummary]:
        """Every process the service offers."""
        return self._run(self._protocol.processes())

    def describe(self, process_id: str) -> ProcessDescription:
        """A process with its inputs (JSON Schema, defaults) and outputs."""
        return self._run(self._protocol.describe(process_id))

    def execute(
        self,
        process_id: str,
        /,
        *,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
        **inputs: Any,
    ) -> Job:
        """Start a job of ``process_id`` on ``inputs``.

        Parameters
        ----------
        process_id : str
            The process to run, such as ``"alignment.rigid"``.
        wait : float, optional
            Ask the service to answer with the results if the job ends within this many
            seconds (``Prefer: wait=N``, rounded up to whole seconds); the results are kept
            so :meth:`Job.results` needs no other request. None (default): answer at once.
        outputs : names, optional
            Only these outputs are wanted.
        idempotency_key : str, optional
            Retrying with the same key returns the first job instead of starting another.
        time_limit : float, optional
            Stop the job after this many seconds of running (never more than the service's
            own limit); it then fails with :class:`TimeLimitExceeded`.
        **inputs
            The inputs of the process: numpy arrays (from 1,024 numbers sent as typed
            binary arrays, bit-exact; from 1 MiB, also as members of a mesh, as ``.npy``
            parts of a multipart request, which the service accepts fastest), numbers,
            strings, lists and dicts; mesh and point cloud objects of trimesh, Open3D and
            PyVista (a mesh goes as ``{vertices, faces}`` to an input that takes a mesh, as
            its vertices to one that takes points, as the process description says); and
            geometry files — a ``pathlib.Path``, or a string that is not a choice of the
            input, naming a ``.ply``, ``.obj``, ``.stl``, ``.off``, ``.glb`` or ``.npy``
            file — uploaded as they are (multipart).

        Raises
        ------
        NoSuchFile
            A path (or a string that is no choice of its input) names no file; raised
            before anything is sent. Also a ``FileNotFoundError``.
        InvalidInput
            An input is missing or wrong; ``errors`` says which.
        QueueFull
            Too many jobs queued; retry after ``retry_after`` seconds.
        """
        flow = self._protocol.execute(
            process_id, inputs, wait=wait, outputs=outputs, idempotency_key=idempotency_key,
            time_limit=time_limit,
        )
        return Job(self, self._run(flow))

    def job(self, job_id: str) -> Job:
        """The job of this id; asks for its status once, so an unknown id raises NoSuchJob."""
        return Job(self, self._run(self._protocol.lookup(job_id)))

    def jobs(
        self,
        status: str | Iterable[str] | None = None,
        process: str | Iterable[str] | None = None,
        limit: int | None = None,
    ) -> list[JobStatus]:
        """The jobs of the service, newest first as the service orders them.

        ``status`` and ``process`` filter (one value or several); ``limit`` is the most jobs
        to return. Pages are followed through the ``next`` links; without a ``limit`` at most
        :data:`MAX_LISTED_JOBS` (1000) jobs are gathered.
        """
        return self._run(self._protocol.jobs(status, process, limit))

    def map(
        self,
        process_id: str,
        inputs: Iterable[Mapping[str, Any]],
        /,
        *,
        max_in_flight: int = 8,
        progress: bool | ProgressDisplay = False,
        batch_id: str | None = None,
        keys: Sequence[str] | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        time_limit: float | None = None,
        timeout: float | None = None,
        poll_interval: float = 0.05,
        **common: Any,
    ) -> list[BatchItem[Job]]:
        """Run ``process_id`` once per item of ``inputs``, many jobs at a time; one
        :class:`BatchItem` per item, in their order, holding its results or its error.

        Parameters
        ----------
        process_id : str
            The process to run.
        inputs : iterable of dict
            One dict of named inputs per job (each as :meth:`execute` takes them).
        max_in_flight : int
            Jobs sent and not yet finished at any time: enough to keep every worker of the
            service busy (default 8).
        progress : bool or progress bar
            One bar for the batch: jobs done of all, elapsed time, rate and time left.
        batch_id : str, optional
            Names the batch: job ``i`` is sent with the Idempotency-Key
            ``{batch_id}:{process_id}:{i}``, so running the batch again with the same id
            (after a crash, a lost connection) gives back the jobs already made, finished or
            not, instead of starting them again. A random id when None (retries within the
            call are safe all the same).
        keys : sequence of str, optional
            One Idempotency-Key per item, instead of ``batch_id``.
        outputs, time_limit
            As for :meth:`execute`, for every job.
        timeout : float, optional
            Seconds to wait for each job at most; a job still running then is an item whose
            error is :class:`WaitTimeout` (the job goes on).
        poll_interval : float
            Seconds between the first polls of a job that outlasts its first request.
        **common
            Inputs shared by every job; an item's own inputs take precedence.

        Returns
        -------
        list of BatchItem
            ``item.ok``, ``item.results`` (``item.result()`` raises the item's error),
            ``item.error``, ``item.job``, ``item.key``.

        Raises
        ------
        NoSuchProcess
            There is no such process (checked once, before any job is sent).
        """
        items, item_keys = batch_inputs(process_id, inputs, common, batch_id, keys,
                                        max_in_flight)
        self._run(self._protocol._input_schemas(process_id))  # the process exists: once
        out: list[BatchItem[Job] | None] = [None] * len(items)
        bar = make_progress(progress, total=max(len(items), 1), unit="jobs", desc=process_id)
        failed = 0
        pool = ThreadPoolExecutor(max_workers=max_in_flight, thread_name_prefix="morphserve")
        try:
            futures = {
                pool.submit(self._run, item_flow(
                    self._protocol, process_id, item, item_keys[index], outputs=outputs,
                    time_limit=time_limit, timeout=timeout, poll_interval=poll_interval)): index
                for index, item in enumerate(items)}
            for done, future in enumerate(concurrent.futures.as_completed(futures), 1):
                index = futures[future]
                submitted, error = future.result()
                job = None if submitted is None else Job(self, submitted)
                out[index] = BatchItem(index, item_keys[index], job,
                                       None if job is None else job._results, error)
                failed += error is not None
                if bar is not None:
                    bar.update(done, f"{failed} failed" if failed else None)
        except BaseException:  # Ctrl-C: the jobs still running go on, unwatched
            pool.shutdown(wait=False, cancel_futures=True)
            raise
        else:
            pool.shutdown()
        finally:
            if bar is not None:
                bar.close()
        return [item for item in out if item is not None]

    def as_completed(
        self,
        jobs: Iterable[Job],
        *,
        timeout: float | None = None,
        progress: bool | ProgressDisplay = False,
        poll_interval: float = 0.05,
    ) -> Iterator[Job]:
        """Yield each of ``jobs`` as it ends (successful, failed or dismissed), as
        ``concurrent.futures.as_completed`` does: ``job.result()`` then gives its results
        or raises its error. Raises ``TimeoutError`` when ``timeout`` seconds pass first.
        """
        pending = list(jobs)
        bar = make_progress(progress, total=max(len(pending), 1), unit="jobs")
        flow = self._protocol.as_completed(list(pending), timeout=timeout,
                                           poll_interval=poll_interval)
        try:
            with _Stepper(cast(_Flow[None], flow)) as stepper:
                done = 0
                for step in stepper:
                    if isinstance(step, Job):
                        done += 1
                        if bar is not None:
                            bar.update(done)
                        yield step
                    else:
                        stepper.send(self._perform(step))
        finally:
            if bar is not None:
                bar.close()

    def close(self) -> None:
        """Close the connections."""
        self._http.close()

    def __enter__(self) -> Client:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()


class AsyncClient(_ClientBase, AsyncTypedCalls):
    """An asyncio client of a morphserve service; the API of :class:`Client`, awaited.

    ``transport`` takes an ``httpx.AsyncBaseTransport`` (``httpx.MockTransport`` serves both).
    """

    _http: httpx.AsyncClient

    def __init__(
        self,
        base_url: str = DEFAULT_URL,
        *,
        api_key: str | None = None,
        timeout: float | None = 30.0,
        transport: httpx.AsyncBaseTransport | None = None,
    ) -> None:
        http = httpx.AsyncClient(transport=transport, **_http_options(base_url, api_key, timeout))
        super().__init__(http, timeout)

    async def _perform(
        self, step: httpx.Request | _Sleep
    ) -> httpx.Response | MorphserveError | None:
        if isinstance(step, _Sleep):
            await asyncio.sleep(step.seconds)
            return None
        try:
            return await self._http.send(step)
        except httpx.HTTPError as error:
            return TransportError.from_httpx(error)

    async def _run(self, flow: _Flow[T]) -> T:
        with _Stepper(flow) as stepper:
            for step in stepper:
                stepper.send(await self._perform(step))
        return stepper.result

    async def processes(self) -> list[ProcessSummary]:
        """Every process the service offers."""
        return await self._run(self._protocol.processes())

    async def describe(self, process_id: str) -> ProcessDescription:
        """A process with its inputs and outputs (see :meth:`Client.describe`)."""
        return await self._run(self._protocol.describe(process_id))

    async def execute(
        self,
        process_id: str,
        /,
        *,
        wait: float | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        idempotency_key: str | None = None,
        time_limit: float | None = None,
        **inputs: Any,
    ) -> AsyncJob:
        """Start a job of ``process_id`` on ``inputs`` (see :meth:`Client.execute`)."""
        flow = self._protocol.execute(
            process_id, inputs, wait=wait, outputs=outputs, idempotency_key=idempotency_key,
            time_limit=time_limit,
        )
        return AsyncJob(self, await self._run(flow))

    async def job(self, job_id: str) -> AsyncJob:
        """The job of this id (see :meth:`Client.job`)."""
        return AsyncJob(self, await self._run(self._protocol.lookup(job_id)))

    async def jobs(
        self,
        status: str | Iterable[str] | None = None,
        process: str | Iterable[str] | None = None,
        limit: int | None = None,
    ) -> list[JobStatus]:
        """The jobs of the service (see :meth:`Client.jobs`)."""
        return await self._run(self._protocol.jobs(status, process, limit))

    async def map(
        self,
        process_id: str,
        inputs: Iterable[Mapping[str, Any]],
        /,
        *,
        max_in_flight: int = 8,
        progress: bool | ProgressDisplay = False,
        batch_id: str | None = None,
        keys: Sequence[str] | None = None,
        outputs: Iterable[str] | Mapping[str, Any] | None = None,
        time_limit: float | None = None,
        timeout: float | None = None,
        poll_interval: float = 0.05,
        **common: Any,
    ) -> list[BatchItem[AsyncJob]]:
        """Run ``process_id`` once per item of ``inputs``, many jobs at a time (see
        :meth:`Client.map`); the jobs are tasks of the running event loop."""
        items, item_keys = batch_inputs(process_id, inputs, common, batch_id, keys,
                                        max_in_flight)
        await self._run(self._protocol._input_schemas(process_id))
        out: list[BatchItem[AsyncJob] | None] = [None] * len(items)
        bar = make_progress(progress, total=max(len(items), 1), unit="jobs", desc=process_id)
        gate = asyncio.Semaphore(max_in_flight)

        async def one(index: int) -> tuple[int, _Submitted | None, Exception | None]:
            async with gate:
                submitted, error = await self._run(item_flow(
                    self._protocol, process_id, items[index], item_keys[index],
                    outputs=outputs, time_limit=time_limit, timeout=timeout,
                    poll_interval=poll_interval))
            return index, submitted, error

        tasks = [asyncio.ensure_future(one(index)) for index in range(len(items))]
        failed = 0
        try:
            for done, next_done in enumerate(asyncio.as_completed(tasks), 1):
                index, submitted, error = await next_done
                job = None if submitted is None else AsyncJob(self, submitted)
                out[index] = BatchItem(index, item_keys[index], job,
                                       None if job is None else job._results, error)
                failed += error is not None
                if bar is not None:
                    bar.update(done, f"{failed} failed" if failed else None)
        finally:
            for task in tasks:
                task.cancel()
            if bar is not None:
                bar.close()
        return [item for item in out if item is not None]

    async def as_completed(
        self,
        jobs: Iterable[AsyncJob],
        *,
        timeout: float | None = None,
        progress: bool | ProgressDisplay = False,
        poll_interval: float = 0.05,
    ) -> AsyncIterator[AsyncJob]:
        """Yield each of ``jobs`` as it ends (see :meth:`Client.as_completed`):
        ``async for job in client.as_completed(jobs)``."""
        pending = list(jobs)
        bar = make_progress(progress, total=max(len(pending), 1), unit="jobs")
        flow = self._protocol.as_completed(list(pending), timeout=timeout,
                                           poll_interval=poll_interval)
        try:
            with _Stepper(cast(_Flow[None], flow)) as stepper:
                done = 0
                for step in stepper:
                    if isinstance(step, AsyncJob):
                        done += 1
                        if bar is not None:
                            bar.update(done)
                        yield step
                    else:
                        stepper.send(await self._perform(step))
        finally:
            if bar is not None:
                bar.close()

    async def close(self) -> None:
        """Close the connections."""
        await self._http.aclose()

    aclose = close

    async def __aenter__(self) -> AsyncClient:
        return self

    async def __aexit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        await self.close()


@overload
def as_completed(jobs: Iterable[Job], *, timeout: float | None = None,
                 progress: bool | ProgressDisplay = False) -> Iterator[Job]: ...


@overload
def as_completed(jobs: Iterable[AsyncJob], *, timeout: float | None = None,
                 progress: bool | ProgressDisplay = False) -> AsyncIterator[AsyncJob]: ...


def as_completed(jobs: Iterable[Job] | Iterable[AsyncJob], *, timeout: float | None = None,
                 progress: bool | ProgressDisplay = False
                 ) -> Iterator[Job] | AsyncIterator[AsyncJob]:
    """Each of ``jobs`` as it ends, as ``concurrent.futures.as_completed`` gives futures:
    ``for job in as_completed(jobs)`` for jobs of a :class:`Client`, ``async for`` for jobs
    of an :class:`AsyncClient` (see :meth:`Client.as_completed`). The jobs must all be of
    one client."""
    given: list[Any] = list(jobs)
    clients = {id(job._client) for job in given}
    if len(clients) > 1:
        raise ValueError("Expected the jobs of one client, got jobs of several.")
    if not given:
        return iter(())
    client = given[0]._client
    if isinstance(client, AsyncClient):
        return client.as_completed(given, timeout=timeout, progress=progress)
    return cast(Client, client).as_completed(given, timeout=timeout, progress=progress)
