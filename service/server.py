"""Run the service with uvicorn: ``morphserve serve`` and ``make serve`` end here.

HTTP is spoken by :class:`LimitedHttpProtocol`, uvicorn's httptools protocol with the limits
nginx and Apache keep and uvicorn does not: a request head (request line and headers) larger
than ``max_header_bytes`` is answered 431; a head that has not arrived ``header_timeout``
seconds after its first byte (or a connection that sends nothing for as long) and a body
that goes ``body_timeout`` seconds without a byte while the service waits for it are answered
408, and the connection is closed. Those answers, and the 400 of a request httptools cannot
parse, are problem+json documents, as every other error of the service.
"""

from __future__ import annotations

import asyncio
import ctypes
import logging
import platform
import socket
import sys
from typing import Any, ClassVar, Literal

import uvicorn
from uvicorn.protocols.http.httptools_impl import STATUS_LINE, HttpToolsProtocol

from service.app import create_app
from service.jsonio import dumps
from service.problems import problem_body
from service.settings import Settings

__all__ = ["run", "bind", "keep_freed_memory", "LimitedHttpProtocol", "limited_protocol"]

# mallopt(3) parameters
_M_TRIM_THRESHOLD = -1
_M_MMAP_THRESHOLD = -3


def bind(host: str, port: int) -> socket.socket:
    """The listening socket, bound before anything else starts: a port already in use fails
    at once, and the embedded Dask cluster's own (random) ports can never take it."""
    family = socket.AF_INET6 if ":" in host else socket.AF_INET
    # proto must say TCP: asyncio sets TCP_NODELAY only on sockets whose proto is TCP, and
    # without it every response waits ~40 ms for a delayed ACK.
    sock = socket.socket(family, socket.SOCK_STREAM, socket.IPPROTO_TCP)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    try:
        sock.bind((host, port))
    except OSError as exc:
        sock.close()
        raise SystemExit(f"morphserve: cannot listen on {host}:{port}: {exc.strerror}") from None
    sock.listen(2048)
    sock.set_inheritable(True)
    return sock


def keep_freed_memory(nbytes: int) -> bool:
    """Have glibc's malloc serve blocks of up to ``nbytes`` from its heap and keep up to
    ``nbytes`` of freed heap for reuse; True if it was set (Linux with glibc only).

    By default glibc maps every block above its threshold (at most 32 MiB) afresh and unmaps
    it when freed, and trims freed heap at once: each request body then lands in new pages,
    and faulting them in costs more than copying into them (receiving 48 MB took ~130 ms,
    ~50 ms with the pages kept). The price is that up to ``nbytes`` of freed memory stays
    with the process after a large request, to be reused by the next."""
    if nbytes <= 0 or not sys.platform.startswith("linux") or platform.libc_ver()[0] != "glibc":
        return False
    mallopt = ctypes.CDLL(None).mallopt  # the C library this process already runs on
    mallopt.argtypes, mallopt.restype = (ctypes.c_int, ctypes.c_int), ctypes.c_int
    return bool(mallopt(_M_MMAP_THRESHOLD, nbytes)) & bool(mallopt(_M_TRIM_THRESHOLD, nbytes))


def run(host: str = "127.0.0.1", port: int = 8000, **overrides: Any) -> None:
    """Serve on ``host:port``; ``overrides`` (``data_dir``, ``scheduler``, ``workers``, ...)
    replace the settings read from the environment where not ``None``."""
    settings = Settings(**{k: v for k, v in overrides.items() if v is not None})
    logging.basicConfig(level=logging.INFO, format="%(asctime)s %(levelname)s %(name)s: "
                        "%(message)s")
    if settings.api_keys_file is None and host not in ("127.0.0.1", "localhost", "::1"):
        logging.getLogger("morphserve").warning(
            "listening on %s without API keys: anyone who reaches this address can run and "
            "read every job; set MORPHSERVE_API_KEYS_FILE (see `morphserve keys add`)", host)
    sock = bind(host, port)
    keep_freed_memory(settings.keep_freed_bytes)
    # One uvicorn process per embedded cluster; the asyncio loop is the one Dask is tested on.
    config = uvicorn.Config(create_app(settings), host=host, port=port, loop="asyncio",
                            http=limited_protocol(settings), lifespan="on", log_level="info",
                            access_log=False, timeout_graceful_shutdown=10)
    uvicorn.Server(config).run(sockets=[sock])


#: The problems the HTTP layer answers itself, before any route sees the request.
_PROTOCOL_PROBLEMS = {400: "bad-request", 408: "request-timeout", 431: "header-too-large"}


class LimitedHttpProtocol(HttpToolsProtocol):
    """uvicorn's httptools protocol, with a bound on the request head and on how slowly a
    client may send it and its body (see the module's docstring).

    One timer per connection: set when the connection opens and when a head starts (its
    deadline fixed then), and while a body is awaited (its deadline the last byte's arrival
    plus ``body_timeout``; a body the application is not reading yet, reading paused or a
    ``100 Continue`` not yet sent, is not the client's delay). The head's bytes are counted
    as they arrive, before httptools buffers them; a head that starts in the same read as the
    end of the request before it (pipelining) may exceed the limit by that read's share."""

    max_header_bytes: ClassVar[int] = 64 * 2**10
    header_timeout: ClassVar[float] = 20.0
    body_timeout: ClassVar[float] = 20.0

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self._phase: Literal["new", "head", "body", "between"] = "new"
        """new: no byte yet; head: reading a request head; body: reading its body; between:
        the request is read (uvicorn's keep-alive timeout covers the idle time after it)."""
        self._head_left = self.max_header_bytes
        self._last_byte = 0.0
        self._timer: asyncio.TimerHandle | None = None

    # -- the timer ---------------------------------------------------------------------------
    def _arm(self, deadline: float) -> None:
        if self._timer is not None:
            self._timer.cancel()
        self._timer = self.loop.call_at(deadline, self._expired)

    def _disarm(self) -> None:
        if self._timer is not None:
            self._timer.cancel()
            self._timer = None

    def _expired(self) -> None:
        self._timer = None
        if self.transport.is_closing() or self.transport.get_protocol() is not self:
            return  # closed, or handed over (a WebSocket upgrade)
        if self._phase == "new":
            self.transport.close()  # nothing was asked: nothing to answer
        elif self._phase == "head":
            self._refuse(408, f"The request's head did not arrive within "
                              f"{self.header_timeout:g} s of its first byte.")
        elif self._phase == "body":
            now = self.loop.time()
            waiting_for_us = self.flow.read_paused or (
                self.cycle is not None and self.cycle.waiting_for_100_continue)
            if waiting_for_us or now < self._last_byte + self.body_timeout:
                self._arm(max(now, self._last_byte) + self.body_timeout)
            else:
                self._refuse(408, f"No byte of the request body arrived for "
                                  f"{self.body_timeout:g} s.")

    # -- answering ---------------------------------------------------------------------------
    def _refuse(self, status: int, detail: str) -> None:
        """Answer ``status`` as problem+json, unless a response has begun, and close."""
        self._disarm()
        cycle = self.cycle
        if cycle is not None and not cycle.response_complete:
            if cycle.response_started:
                self.transport.close()
                return
            cycle.disconnected = True  # the application's own answer, if any, is dropped
            cycle.message_event.set()  # and its next read of the body says so
        body = dumps(problem_body(_PROTOCOL_PROBLEMS[status], detail))
        head = [STATUS_LINE[status]]
        for name, value in self.server_state.default_headers:
            head += [name, b": ", value, b"\r\n"]
        head += [b"content-type: application/problem+json\r\n",
                 b"content-length: %d\r\n" % len(body), b"connection: close\r\n\r\n"]
        self.transport.write(b"".join(head) + body)
        self.transport.close()

    def send_400_response(self, msg: str) -> None:
        """httptools could not parse the request (uvicorn's answer is plain text)."""
        self._refuse(400, "The request is not valid HTTP/1.1 (request line, headers or "
                          "chunked body).")

    # -- the protocol ------------------------------------------------------------------------
    def connection_made(self, transport: asyncio.Transport) -> None:  # type: ignore[override]
        super().connection_made(transport)
        self._arm(self.loop.time() + self.header_timeout)

    def connection_lost(self, exc: Exception | None) -> None:
        self._disarm()
        super().connection_lost(exc)

    def data_received(self, data: bytes) -> None:
        while data and not self.transport.is_closing():
            if self._phase == "body":
                self._last_byte = self.loop.time()
                super().data_received(data)
                return
            if self._phase == "between":  # the first byte of the next request
                self._phase = "head"
                self._arm(self.loop.time() + self.header_timeout)
            elif self._phase == "new":
                self._phase = "head"  # the deadline set at the connection stands
            if len(data) <= self._head_left:
                self._head_left -= len(data)
                super().data_received(data)
                return
            # feed what the head may still take; if it ends in there, go on with the rest
            chunk, data = data[:self._head_left], data[self._head_left:]
            self._head_left = 0
            super().data_received(chunk)
            if self._phase == "head" and not self.transport.is_closing():
                self._refuse(431, f"The request's head (request line and headers) is larger "
                                  f"than {self.max_header_bytes} bytes.")

    def on_message_begin(self) -> None:
        if self._phase == "between":  # a pipelined request, begun in its predecessor's read
            self._phase = "head"
            self._arm(self.loop.time() + self.header_timeout)
        super().on_message_begin()

    def on_headers_complete(self) -> None:
        self._phase = "body"
        self._last_byte = self.loop.time()
        self._arm(self._last_byte + self.body_timeout)
        super().on_headers_complete()

    def on_message_complete(self) -> None:
        self._phase = "between"
        self._head_left = self.max_header_bytes
        self._disarm()
        super().on_message_complete()


def limited_protocol(settings: Settings) -> type[LimitedHttpProtocol]:
    """:class:`LimitedHttpProtocol` with the limits of ``settings``."""
    return type("LimitedHttpProtocol", (LimitedHttpProtocol,), {
        "max_header_bytes": settings.max_header_bytes,
        "header_timeout": settings.header_timeout,
        "body_timeout": settings.body_timeout,
    })
