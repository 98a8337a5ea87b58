"""Subscriber callbacks (OGC API – Processes, callback conformance class).

An execute request may name ``subscriber.successUri``, ``inProgressUri`` and ``failedUri``.
They are checked when the job is submitted (:func:`check_subscriber`): URLs that httpx, the
client that will send them, can send to, http(s) only, to a host on the ``callback_hosts``
allow-list only (the service must not be made to call into networks the client could not
reach itself). Anything else is a 422 naming the member, so that nothing accepted can fail
later for want of a valid address.

On the job's start and end the :class:`Notifier` POSTs the statusInfo (and, on success, the
results document). Each delivery is bounded: every attempt has a deadline of its own (connect,
send and answer together), only the first :data:`MAX_RESPONSE_BYTES` of the subscriber's answer
are read (only its status matters), and redirects are not followed. A delivery that fails for a
reason that may pass (no connection, a timeout, 408, 425, 429 or 5xx) is tried again after an
exponential backoff with jitter, up to ``attempts`` times in all, as Celery retries a task; any
other answer ends it. :data:`DELIVERIES` counts the outcomes for ``/metrics``.
"""

from __future__ import annotations

import asyncio
import logging
import random
import threading
from typing import Any
from urllib.parse import urlsplit

import httpx

from morphserve._exceptions import retry_after_seconds
from service.errors import ServiceError
from service.jobs.store import Subscriber
from service.jsonio import dumps

__all__ = ["check_subscriber", "Notifier", "Deliveries", "DELIVERIES", "MAX_RESPONSE_BYTES"]

log = logging.getLogger("morphserve.callbacks")

_URIS = ("successUri", "inProgressUri", "failedUri")

MAX_RESPONSE_BYTES = 64 * 1024
"""Most bytes of a subscriber's answer that are read; the rest is never received."""

_RETRY_STATUSES = frozenset({408, 425, 429, 500, 502, 503, 504})
"""Answers after which a delivery is tried again (the others end it: 2xx delivered, any
other failed)."""


def _uri_problem(uri: str, allowed_hosts: list[str]) -> str | None:
    """Why ``uri`` may not be called back, or None if it may."""
    bad = next((i for i, ch in enumerate(uri)
                if ch.isspace() or ord(ch) < 0x20 or ord(ch) == 0x7F), None)
    if bad is not None:
        return (f"expected a URL without spaces or control characters, got {uri!r} "
                f"({uri[bad]!r} at position {bad})")
    try:
        url = httpx.URL(uri)  # what the notifier will send to
        port = urlsplit(uri).port  # digits only ("h: 80", "h:+80", "h:99999" raise)
    except (httpx.InvalidURL, ValueError) as exc:
        return f"expected an http(s) URL, got {uri!r} ({exc})"
    if url.scheme not in ("http", "https") or not url.host:
        return f"expected an http(s) URL, got {uri!r}"
    if port != url.port or (port is not None and not 1 <= port <= 65535):
        return f"expected a port from 1 to 65535, got {uri!r}"
    hostport = f"{url.host}:{port}" if port else url.host
    if url.host not in allowed_hosts and hostport not in allowed_hosts:
        return (f"callbacks to {hostport!r} are not allowed; the service's "
                "MORPHSERVE_CALLBACK_HOSTS lists the hosts it may call")
    return None


def check_subscriber(subscriber: Any, allowed_hosts: list[str]) -> Subscriber | None:
    """The request's subscriber object if every URI is allowed (None if it names none),
    else a 422 naming the bad one (``subscriber.successUri`` ...)."""
    if subscriber is None:
        return None
    if not isinstance(subscriber, dict):
        raise ServiceError("invalid-input", "subscriber: expected an object.",
                           errors=[{"input": "subscriber", "message": "expected an object"}])
    out: dict[str, str] = {}
    for name, uri in subscriber.items():
        field = f"subscriber.{name}"
        if name not in _URIS:
            msg: str | None = f"unknown member; expected some of {list(_URIS)}"
        elif not isinstance(uri, str):
            msg = "expected a URL string"
        else:
            msg = _uri_problem(uri, allowed_hosts)
        if msg is None:
            out[name] = uri
            continue
        raise ServiceError("invalid-input", f"{field}: {msg}.",
                           errors=[{"input": field, "message": msg}])
    return Subscriber.from_json(out) if out else None


class Deliveries:
    """Counts of callback deliveries since the process started (Prometheus counters)."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self.delivered = 0
        """Deliveries the subscriber answered with a 2xx."""
        self.failed = 0
        """Deliveries given up: out of attempts, or answered with a status that ends them."""
        self.retries = 0
        """Attempts made again after a failed one."""

    def count(self, what: str) -> None:
        with self._lock:
            setattr(self, what, getattr(self, what) + 1)

    def exposition(self) -> list[str]:
        """The counters' lines in the Prometheus text format."""
        with self._lock:
            delivered, failed, retries = self.delivered, self.failed, self.retries
        return [
            "# HELP morphserve_callbacks_total Subscriber callbacks by outcome: delivered "
            "(a 2xx answer) or failed (given up).",
            "# TYPE morphserve_callbacks_total counter",
            f'morphserve_callbacks_total{{outcome="delivered"}} {delivered}',
            f'morphserve_callbacks_total{{outcome="failed"}} {failed}',
            "# HELP morphserve_callback_retries_total Callback attempts made again after a "
            "failed one.",
            "# TYPE morphserve_callback_retries_total counter",
            f"morphserve_callback_retries_total {retries}",
        ]


DELIVERIES = Deliveries()
"""The process's callback counters, rendered by ``/metrics``."""


class Notifier:
    """POSTs callbacks in the background; never lets a callback failure touch a job.

    Parameters
    ----------
    timeout : float
        Seconds one attempt may take in all: connecting, sending the document and reading
        the answer's first :data:`MAX_RESPONSE_BYTES`.
    attempts : int
        Most attempts of one delivery.
    backoff : float
        Seconds before the second attempt; each further one waits twice as long, at most
        ``max_backoff``, each wait drawn between half and all of that (jitter), or as long
        as the subscriber's ``Retry-After`` asks (seconds or an HTTP-date), within the same
        bound.
    max_backoff : float
        Longest wait between two attempts, in seconds.
    deliveries : Deliveries
        The counters to update (default: :data:`DELIVERIES`).
    """

    def __init__(self, timeout: float = 30.0, attempts: int = 4, backoff: float = 0.5,
                 max_backoff: float = 30.0, deliveries: Deliveries | None = None) -> None:
        self.timeout = timeout
        self.attempts = attempts
        self.backoff = backoff
        self.max_backoff = max_backoff
        self.deliveries = deliveries or DELIVERIES
        self._client: httpx.AsyncClient | None = None
        self._tasks: set[asyncio.Task[None]] = set()

    def send(self, uri: str, body: Any) -> None:
        task = asyncio.get_running_loop().create_task(self._deliver(uri, body))
        self._tasks.add(task)
        task.add_done_callback(self._tasks.discard)

    async def _deliver(self, uri: str, body: Any) -> None:
        content = dumps(body)
        for attempt in range(1, self.attempts + 1):
            status, retry_after = await self._attempt(uri, content)
            if status is not None and 200 <= status < 300:
                self.deliveries.count("delivered")
                return
            if status is not None and status not in _RETRY_STATUSES:
                log.warning("callback to %s answered %d; not sent again", uri, status)
                break
            if attempt == self.attempts:
                log.warning("callback to %s failed after %d attempts", uri, attempt)
                break
            self.deliveries.count("retries")
            await asyncio.sleep(self._delay(attempt, retry_after))
        self.deliveries.count("failed")

    def _delay(self, attempt: int, retry_after: float | None) -> float:
        """Seconds to wait after failed attempt number ``attempt`` (1, 2, ...)."""
        ceiling = min(self.max_backoff, self.backoff * 2 ** (attempt - 1))
        delay = ceiling * random.uniform(0.5, 1.0)
        if retry_after is not None:
            delay = max(delay, min(retry_after, self.max_backoff))
        return delay

    async def _attempt(self, uri: str, content: bytes) -> tuple[int | None, float | None]:
        """One POST: the answer's status and Retry-After seconds, or (None, None) when no
        answer came (no connection, a timeout, a broken answer)."""
        if self._client is None:
            self._client = httpx.AsyncClient(timeout=self.timeout, follow_redirects=False)
        try:
            async with asyncio.timeout(self.timeout):
                async with self._client.stream(
                        "POST", uri, content=content,
                        headers={"Content-Type": "application/json",
                                 "Accept-Encoding": "identity"}) as r:
                    received = 0
                    async for chunk in r.aiter_raw():
                        received += len(chunk)
                        if received >= MAX_RESPONSE_BYTES:
                            break  # the rest is never read: the connection is closed
                    return r.status_code, retry_after_seconds(r.headers.get("Retry-After"))
        except (httpx.HTTPError, httpx.InvalidURL, TimeoutError, OSError) as exc:
            log.info("callback to %s: %s", uri, type(exc).__name__)
            return None, None

    async def close(self) -> None:
        for task in list(self._tasks):
            task.cancel()
        if self._client is not None:
            await self._client.aclose()
