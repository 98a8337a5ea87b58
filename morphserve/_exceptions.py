"""The exceptions the SDK raises.

Every error answer of the service is an RFC 9457 ``application/problem+json`` document whose
``type`` ends in a stable slug: the service's own types (``/problems/invalid-input``) and the
types OGC API – Processes defines
(``http://www.opengis.net/def/exceptions/ogcapi-processes-1/1.0/no-such-job``) alike, and
either form of a type maps to the same class. Each slug has its own class, named after it, so
callers catch exactly what they mean::

    MorphserveError
     ├── TransportError            the server could not be reached, or the connection broke
     │                             (wraps the httpx error as ``__cause__``)
     ├── ProtocolError             the server answered something outside the HTTP contract
     ├── WaitTimeout               ``Job.wait(timeout=...)`` expired  (also a TimeoutError)
     └── APIError                  a problem document: status, type, title, detail, errors,
          │                        instance, response
          ├── InvalidInput         422 invalid-input  (also a ValueError)
          ├── IdempotencyConflict  422 idempotency-conflict
          ├── MalformedBody        400 malformed-body
          ├── BadRequest           400 bad-request  (not valid HTTP)
          ├── Unauthorized         401 unauthorized
          ├── NotFound             404 not-found, and any other 404 without a known slug
          │    ├── NoSuchProcess   404 no-such-process
          │    ├── NoSuchJob       404 no-such-job
          │    ├── NoSuchOutput    404 no-such-output
          │    └── ResultNotReady  404 result-not-ready
          ├── MethodNotAllowed     405 method-not-allowed
          ├── NotAcceptable        406 not-acceptable
          ├── RequestTimeout       408 request-timeout
          ├── JobDismissed         410 job-dismissed
          ├── PayloadTooLarge      413 payload-too-large
          ├── UnsupportedMediaType 415 unsupported-media-type
          ├── QueueFull            429 queue-full
          ├── HeaderTooLarge       431 header-too-large
          ├── JobFailed            job-failed: the job ran and raised
          │    ├── TimeLimitExceeded  time-limit-exceeded: the job ran out of time
          │    └── WorkerLost      worker-lost: its worker died more often than allowed
          ├── InternalError        500 internal-error
          ├── ServiceUnavailable   503 service-unavailable
          └── InsufficientStorage  507 insufficient-storage  (free_bytes)

Every :class:`APIError` has ``retry_after``: the seconds the ``Retry-After`` header asks to
wait (429, 503 and 507 answers carry one), None when it is absent.

A problem whose slug this SDK does not know is raised as the class that owns its HTTP status
when exactly one does (any 404 is a :class:`NotFound`, any 429 a :class:`QueueFull`), else as a
plain :class:`APIError`. An error answer that is not a problem document at all (an HTML page of
a proxy) is handled the same way, with the reason phrase as the title.
"""

from __future__ import annotations

import json
import time
from email.utils import parsedate_to_datetime
from typing import Any, ClassVar

import httpx

__all__ = [
    "APIError",
    "BadRequest",
    "HeaderTooLarge",
    "IdempotencyConflict",
    "InsufficientStorage",
    "InternalError",
    "InvalidInput",
    "JobDismissed",
    "JobFailed",
    "MalformedBody",
    "MethodNotAllowed",
    "MorphserveError",
    "NoSuchJob",
    "NoSuchOutput",
    "NoSuchProcess",
    "NotAcceptable",
    "NotFound",
    "PayloadTooLarge",
    "ProtocolError",
    "QueueFull",
    "RequestTimeout",
    "ResultNotReady",
    "ServiceUnavailable",
    "TimeLimitExceeded",
    "TransportError",
    "Unauthorized",
    "UnsupportedMediaType",
    "WaitTimeout",
    "WorkerLost",
]


class MorphserveError(Exception):
    """Base class of every exception the SDK raises."""


class TransportError(MorphserveError):
    """The request did not get an answer: connection refused, reset, timed out, bad TLS.

    The httpx exception is the ``__cause__``; ``request`` is the request that failed.
    """

    def __init__(self, message: str, *, request: httpx.Request | None = None) -> None:
        super().__init__(message)
        self.request = request

    @classmethod
    def from_httpx(cls, error: httpx.HTTPError) -> TransportError:
        """Wrap an httpx error, naming the request it hit."""
        try:
            request: httpx.Request | None = error.request
        except RuntimeError:  # httpx raises when the error carries no request
            request = None
        where = f" ({request.method} {request.url})" if request is not None else ""
        wrapped = cls(f"{type(error).__name__}: {error}{where}", request=request)
        wrapped.__cause__ = error
        return wrapped


class ProtocolError(MorphserveError):
    """The server answered, but not as the HTTP contract says (no JSON, a missing header)."""


class WaitTimeout(MorphserveError, TimeoutError):
    """``Job.wait(timeout=...)`` expired before the job ended. The job goes on running.

    ``job_id`` and ``timeout`` say which wait expired; ``status`` is the last
    :class:`~morphserve.JobStatus` seen.
    """

    def __init__(self, job_id: str, timeout: float, status: Any = None) -> None:
        seen = f" (last seen {status.status}, {status.progress}%)" if status is not None else ""
        super().__init__(f"Job {job_id} did not end within {timeout:g} s{seen}.")
        self.job_id = job_id
        self.timeout = timeout
        self.status = status

    def __reduce__(self) -> tuple[Any, ...]:
        return (type(self), (self.job_id, self.timeout, self.status))


_BY_SLUG: dict[str, type[APIError]] = {}
_BY_STATUS: dict[int, type[APIError]] = {}


class APIError(MorphserveError):
    """The service answered with a problem document (RFC 9457).

    Attributes
    ----------
    status : int
        The HTTP status of the answer.
    type : str
        The problem type, a URI reference such as ``/problems/invalid-input``.
    title, detail : str
        A short summary of the problem type and the explanation of this occurrence.
    errors : list of dict
        Per-input errors, ``[{"input": "source", "message": "Expected ..."}]``; often empty.
    instance : str or None
        The URI of this occurrence, when the service gave one.
    response : httpx.Response or None
        The answer itself; None when the SDK made the error up from a job status.
    """

    slug: ClassVar[str | None] = None
    """The problem slug this class stands for (the last path segment of ``type``)."""
    http_status: ClassVar[int | None] = None
    """The HTTP status that belongs to this class alone, used for problems of unknown slug."""

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        if cls.slug is not None:
            _BY_SLUG[cls.slug] = cls
        if "http_status" in cls.__dict__ and cls.http_status is not None:
            _BY_STATUS[cls.http_status] = cls

    def __init__(
        self,
        status: int,
        type: str,  # noqa: A002 - the problem+json member's name (RFC 9457)
        title: str,
        detail: str = "",
        *,
        errors: list[dict[str, Any]] | None = None,
        instance: str | None = None,
        response: httpx.Response | None = None,
    ) -> None:
        self.status = status
        self.type = type
        self.title = title
        self.detail = detail
        self.errors = list(errors or [])
        self.instance = instance
        self.response = response
        super().__init__(self._message())

    def _message(self) -> str:
        text = f"{self.title} ({self.status})"
        if self.detail:
            text += f": {self.detail}"
        for error in self.errors:
            text += f"\n  {error.get('input', '?')}: {error.get('message', '')}"
        return text

    @property
    def retry_after(self) -> float | None:
        """Seconds to wait before retrying, from the ``Retry-After`` header (None: not said)."""
        if self.response is None:
            return None
        return retry_after_seconds(self.response.headers.get("Retry-After"))

    def __reduce__(self) -> tuple[Any, ...]:
        # Picklable (Dask, multiprocessing); the response does not travel.
        args = (self.status, self.type, self.title, self.detail)
        kwargs = {"errors": self.errors, "instance": self.instance}
        return (_rebuild, (type(self), args, kwargs))


def _rebuild(cls: type[APIError], args: tuple[Any, ...], kwargs: dict[str, Any]) -> APIError:
    return cls(*args, **kwargs)


class InvalidInput(APIError, ValueError):
    """An input is missing, of the wrong shape, or out of range; see ``errors``."""

    slug = "invalid-input"


class IdempotencyConflict(APIError):
    """The ``Idempotency-Key`` was already used with another request body."""

    slug = "idempotency-conflict"


class MalformedBody(APIError):
    """The request body could not be parsed."""

    slug = "malformed-body"
    http_status = 400


class BadRequest(APIError):
    """The request was not valid HTTP (a proxy or the SDK's transport garbled it)."""

    slug = "bad-request"


class Unauthorized(APIError):
    """No API key, or a wrong one (set ``api_key`` or ``MORPHSERVE_API_KEY``)."""

    slug = "unauthorized"
    http_status = 401


class NotFound(APIError):
    """Nothing at this URL."""

    slug = "not-found"
    http_status = 404


class NoSuchProcess(NotFound):
    """The service offers no process of this id."""

    slug = "no-such-process"


class NoSuchJob(NotFound):
    """The service knows no job of this id (never created, or dismissed and removed)."""

    slug = "no-such-job"


class NoSuchOutput(NotFound):
    """The job has no output of this name."""

    slug = "no-such-output"


class ResultNotReady(NotFound):
    """The job is still accepted or running; wait for it first."""

    slug = "result-not-ready"


class MethodNotAllowed(APIError):
    """This URL does not answer this HTTP method."""

    slug = "method-not-allowed"
    http_status = 405


class NotAcceptable(APIError):
    """The service cannot answer in the media type asked for."""

    slug = "not-acceptable"
    http_status = 406


class JobDismissed(APIError):
    """The job was dismissed before it ended."""

    slug = "job-dismissed"
    http_status = 410


class RequestTimeout(APIError):
    """The request's head or body reached the service too slowly; it closed the connection."""

    slug = "request-timeout"
    http_status = 408


class HeaderTooLarge(APIError):
    """The request's headers exceed the service's limit (64 KiB by default)."""

    slug = "header-too-large"
    http_status = 431


class PayloadTooLarge(APIError):
    """The request body is larger than the service accepts."""

    slug = "payload-too-large"
    http_status = 413


class UnsupportedMediaType(APIError):
    """The request body is of a media type the service does not read."""

    slug = "unsupported-media-type"
    http_status = 415


class QueueFull(APIError):
    """Too many jobs are queued; try again after ``retry_after`` seconds (None: not said)."""

    slug = "queue-full"
    http_status = 429


class JobFailed(APIError):
    """The job ran and failed; ``detail`` says why."""

    slug = "job-failed"


class TimeLimitExceeded(JobFailed):
    """The job ran longer than its time limit and was stopped."""

    slug = "time-limit-exceeded"


class WorkerLost(JobFailed):
    """The worker running the job died (crash, memory limit) more often than allowed."""

    slug = "worker-lost"


class InternalError(APIError):
    """The service failed; this is a bug of the service, worth reporting."""

    slug = "internal-error"
    http_status = 500


class ServiceUnavailable(APIError):
    """The service is starting, stopping, or has no workers."""

    slug = "service-unavailable"
    http_status = 503


class InsufficientStorage(APIError):
    """The service's data dir is full: it refuses new jobs (reads and finished jobs still
    work) until its operator frees space; ``free_bytes`` is what was left."""

    slug = "insufficient-storage"
    http_status = 507

    @property
    def free_bytes(self) -> int | None:
        """Bytes free in the data dir when the job was refused (None: not said)."""
        try:
            value = self.response.json().get("free_bytes") if self.response else None
        except (ValueError, AttributeError):
            return None
        return value if isinstance(value, int) else None


def retry_after_seconds(value: str | None) -> float | None:
    """``Retry-After`` as seconds: delay-seconds or an HTTP-date (RFC 9110, 10.2.3)."""
    if value is None:
        return None
    value = value.strip()
    if value.isdigit():
        return float(value)
    try:
        when = parsedate_to_datetime(value)
    except (TypeError, ValueError):
        return None
    return max(0.0, when.timestamp() - time.time())


def error_class(problem_type: str | None, status: int) -> type[APIError]:
    """The exception class for a problem ``type`` (by its last path segment) and HTTP status."""
    slug = (problem_type or "").rstrip("/").rsplit("/", 1)[-1]
    return _BY_SLUG.get(slug) or _BY_STATUS.get(status) or APIError


def problem_from_response(response: httpx.Response) -> APIError:
    """The exception an error answer stands for; never raises itself."""
    try:
        body = json.loads(response.content)
    except ValueError:
        body = None
    if not isinstance(body, dict):
        body = {"detail": response.text[:500].strip()}
    errors = body.get("errors")
    problem_type = str(body.get("type") or "about:blank")
    cls = error_class(problem_type, response.status_code)
    return cls(
        response.status_code,
        problem_type,
        str(body.get("title") or response.reason_phrase or "Error"),
        str(body.get("detail") or ""),
        errors=[e for e in errors if isinstance(e, dict)] if isinstance(errors, list) else [],
        instance=body.get("instance"),
        response=response,
    )
