"""Subscriber callbacks (OGC API – Processes, callback conformance class).

An execute request may name ``subscriber.successUri``, ``inProgressUri`` and ``failedUri``.
They are checked when the job is submitted: http(s) URLs to a host on the
``callback_hosts`` allow-list only (the service must not be made to call into networks the
client could not reach itself). On the job's start and end the service POSTs the statusInfo
(and, on success, the results document) with a timeout and a few retries.
"""

from __future__ import annotations

import asyncio
import logging
from typing import Any
from urllib.parse import urlsplit

import httpx

from service.errors import ServiceError
from service.jobs.store import Subscriber
from service.jsonio import dumps

__all__ = ["check_subscriber", "Notifier"]

log = logging.getLogger("morphserve.callbacks")

_URIS = ("successUri", "inProgressUri", "failedUri")


def check_subscriber(subscriber: Any, allowed_hosts: list[str]) -> Subscriber | None:
    """The request's subscriber object if every URI is allowed (None if it names none),
    else a 422 naming the bad one."""
    if subscriber is None:
        return None
    if not isinstance(subscriber, dict):
        raise ServiceError("invalid-input", "subscriber: expected an object.",
                           errors=[{"input": "subscriber", "message": "expected an object"}])
    out: dict[str, str] = {}
    for name, uri in subscriber.items():
        field = f"subscriber.{name}"
        if name not in _URIS:
            msg = f"unknown member; expected some of {list(_URIS)}"
        elif not isinstance(uri, str):
            msg = "expected a URL string"
        else:
            parts = urlsplit(uri)
            host = parts.hostname or ""
            try:
                port = parts.port
            except ValueError:  # "host:abc", "host:99999"
                port, host = None, ""
            hostport = f"{host}:{port}" if port else host
            if parts.scheme not in ("http", "https") or not host:
                msg = f"expected an http(s) URL, got {uri!r}"
            elif host not in allowed_hosts and hostport not in allowed_hosts:
                msg = (f"callbacks to {hostport!r} are not allowed; the service's "
                       "MORPHSERVE_CALLBACK_HOSTS lists the hosts it may call")
            else:
                out[name] = uri
                continue
        raise ServiceError("invalid-input", f"{field}: {msg}.",
                           errors=[{"input": field, "message": msg}])
    return Subscriber.from_json(out) if out else None


class Notifier:
    """POSTs callbacks in the background; never lets a callback failure touch a job."""

    def __init__(self, timeout: float = 10.0, retries: int = 3) -> None:
        self.timeout = timeout
        self.retries = retries
        self._client: httpx.AsyncClient | None = None
        self._tasks: set[asyncio.Task[None]] = set()

    def send(self, uri: str, body: Any) -> None:
        task = asyncio.get_running_loop().create_task(self._post(uri, body))
        self._tasks.add(task)
        task.add_done_callback(self._tasks.discard)

    async def _post(self, uri: str, body: Any) -> None:
        if self._client is None:
            self._client = httpx.AsyncClient(timeout=self.timeout, follow_redirects=False)
        for attempt in range(self.retries):
            try:
                r = await self._client.post(uri, content=dumps(body),
                                            headers={"Content-Type": "application/json"})
                if r.status_code < 500:
                    return
            except httpx.HTTPError:
                pass
            await asyncio.sleep(0.5 * 2**attempt)
        log.warning("callback to %s failed after %d attempts", uri, self.retries)

    async def close(self) -> None:
        for task in list(self._tasks):
            task.cancel()
        if self._client is not None:
            await self._client.aclose()
