"""Run the service with uvicorn: ``morphserve serve`` and ``make serve`` end here."""

from __future__ import annotations

import ctypes
import logging
import platform
import socket
import sys
from typing import Any

import uvicorn

from service.app import create_app
from service.settings import Settings

__all__ = ["run", "bind", "keep_freed_memory"]

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
                            lifespan="on", log_level="info", access_log=False,
                            timeout_graceful_shutdown=10)
    uvicorn.Server(config).run(sockets=[sock])
