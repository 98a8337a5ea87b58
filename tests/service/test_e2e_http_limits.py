"""HTTP limits of the service (service.server.LimitedHttpProtocol), sent over raw sockets to a
real server: an oversized request head is a 431, a head or body sent too slowly is cut off
with a 408, a request that is not HTTP is a 400, each a problem+json followed by the
connection's close, while /healthz keeps answering. Every loop here is bounded in count and
in time; nothing asserts how long anything took, only what came back and in which order."""

from __future__ import annotations

import json
import socket
import time
from collections.abc import Iterator
from pathlib import Path

import httpx
import numpy as np
import pytest

from tests.live import LiveServer

pytestmark = pytest.mark.e2e

HEAD_LIMIT = 64 * 2**10  # the default of max_header_bytes
RIGID = "/processes/alignment.rigid/execution"


@pytest.fixture(scope="module")
def limited(tmp_path_factory: pytest.TempPathFactory) -> Iterator[LiveServer]:
    """A server whose clients must send a head within 1 s and a body's bytes at most 1 s
    apart (the defaults, 20 s, would make the tests wait)."""
    srv = LiveServer(tmp_path_factory.mktemp("limits") / "data", {
        "MORPHSERVE_HEADER_TIMEOUT": "1", "MORPHSERVE_BODY_TIMEOUT": "1"}).start()
    try:
        yield srv
    finally:
        srv.stop()


def connect(srv: LiveServer) -> socket.socket:
    sock = socket.create_connection(("127.0.0.1", srv.port), timeout=15)
    sock.settimeout(15)  # no test waits on a socket longer than this
    return sock


def read_all(sock: socket.socket, limit: int = 2**20) -> bytes:
    """Everything the server sends until it closes the connection (at most ``limit``)."""
    out = b""
    while len(out) < limit:
        try:
            chunk = sock.recv(65536)
        except ConnectionResetError:
            break
        if not chunk:
            break
        out += chunk
    return out


def parse(raw: bytes) -> tuple[int, dict[str, str], bytes]:
    head, _, body = raw.partition(b"\r\n\r\n")
    lines = head.decode("latin-1").split("\r\n")
    status = int(lines[0].split()[1])
    headers = {k.strip().lower(): v.strip() for k, v in
               (line.split(":", 1) for line in lines[1:] if ":" in line)}
    return status, headers, body


def problem(raw: bytes, status: int, slug: str) -> dict:
    """The one response in ``raw``: a problem+json of ``status`` and type ``slug``, with
    ``Connection: close``."""
    got, headers, body = parse(raw)
    assert got == status, raw[:300]
    assert headers["content-type"] == "application/problem+json"
    assert headers["connection"] == "close"
    doc = json.loads(body[:int(headers["content-length"])])
    assert doc["status"] == status and doc["type"].endswith("/" + slug), doc
    assert body[int(headers["content-length"]):] == b""  # nothing follows: the end
    return doc


def healthy(srv: LiveServer) -> None:
    assert httpx.get(srv.url + "/healthz", timeout=10).status_code == 200


def test_head_over_the_limit_is_431(limited: LiveServer) -> None:
    with connect(limited) as sock:
        sock.sendall(b"GET /healthz HTTP/1.1\r\nHost: x\r\nX-Big: " + b"a" * (HEAD_LIMIT + 10)
                     + b"\r\n\r\n")
        doc = problem(read_all(sock), 431, "header-too-large")
    assert str(HEAD_LIMIT) in doc["detail"]
    healthy(limited)


def test_many_small_headers_over_the_limit_sent_piecemeal_are_431(limited: LiveServer) -> None:
    """The head is counted as it arrives, across reads: 200 headers of 400 bytes each, one
    send each (80 kB in all), are refused before the head ends."""
    with connect(limited) as sock:
        sock.sendall(b"GET /healthz HTTP/1.1\r\nHost: x\r\n")
        refused = False
        for i in range(200):
            try:
                sock.sendall(b"X-H%d: %s\r\n" % (i, b"b" * 400))
            except (BrokenPipeError, ConnectionResetError):
                refused = True
                break
        raw = read_all(sock)
    assert refused or raw  # the server answered before the end, or the answer waited
    problem(raw, 431, "header-too-large")


def test_head_just_under_the_limit_is_served(limited: LiveServer) -> None:
    """A head of nearly 64 kB, then a body in the same send: only the head counts."""
    body = json.dumps({"inputs": {"source": [[0, 0, 0], [1, 0, 0], [0, 1, 0]],
                                  "target": [[0, 0, 0], [1, 0, 0], [0, 1, 0]]}}).encode()
    body += b" " * 200_000  # JSON allows trailing whitespace: a body far above the head's limit
    start = b"POST %s HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n" % RIGID.encode()
    tail = b"Content-Length: %d\r\nConnection: close\r\n\r\n" % len(body)
    pad = HEAD_LIMIT - len(start) - len(tail) - len(b"X-Pad: \r\n") - 100
    with connect(limited) as sock:
        sock.sendall(start + b"X-Pad: " + b"p" * pad + b"\r\n" + tail + body)
        status, _, answer = parse(read_all(sock))
    assert status == 200, answer[:300]
    np.testing.assert_allclose(json.loads(answer)["rotation"], np.eye(3), atol=1e-12)


def test_a_head_that_stalls_is_cut_off_with_408(limited: LiveServer) -> None:
    with connect(limited) as sock:
        sock.sendall(b"GET /healthz HTTP/1.1\r\nHost: x\r\n")  # and never the blank line
        healthy(limited)  # the stalled connection holds nothing up
        doc = problem(read_all(sock), 408, "request-timeout")
    assert "head" in doc["detail"]


def test_a_head_trickled_byte_by_byte_is_cut_off(limited: LiveServer) -> None:
    """Slowloris: a byte every 50 ms keeps the connection busy but never finishes the head;
    the server's deadline counts from the first byte, so it cuts the client off long before
    the 400 bytes (20 s) are out."""
    head = b"GET /healthz HTTP/1.1\r\nHost: x\r\nX-Slow: " + b"s" * 400
    sent, cut = 0, False
    with connect(limited) as sock:
        for byte in head:
            try:
                sock.sendall(bytes([byte]))
            except (BrokenPipeError, ConnectionResetError):
                cut = True
                break
            sent += 1
            time.sleep(0.05)
            if sent % 10 == 0:
                sock.setblocking(False)
                try:
                    peek = sock.recv(1, socket.MSG_PEEK)
                except BlockingIOError:
                    peek = b""
                finally:
                    sock.setblocking(True)
                    sock.settimeout(15)
                if peek:
                    cut = True
                    break
        raw = read_all(sock)
    assert cut and sent < len(head)
    problem(raw, 408, "request-timeout")


def test_a_connection_that_sends_nothing_is_closed_without_an_answer(
        limited: LiveServer) -> None:
    with connect(limited) as sock:
        assert read_all(sock) == b""  # closed by the server (else recv times out at 15 s)


def test_a_body_that_stalls_is_cut_off_with_408(limited: LiveServer) -> None:
    with connect(limited) as sock:
        sock.sendall(b"POST %s HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n"
                     b"Content-Length: 1000\r\n\r\n{\"inputs\": " % RIGID.encode())
        healthy(limited)
        doc = problem(read_all(sock), 408, "request-timeout")
    assert "body" in doc["detail"]
    healthy(limited)


def test_a_body_trickled_slowly_but_steadily_is_served(limited: LiveServer) -> None:
    """The body's limit is between bytes, as nginx's client_body_timeout: a body whose bytes
    come 0.3 s apart (well under the 1 s limit) for 2 s in all is read whole and answered."""
    body = json.dumps({"inputs": {"source": [[0, 0, 0], [1, 0, 0], [0, 1, 0]],
                                  "target": [[0, 0, 0], [1, 0, 0], [0, 1, 0]]}}).encode()
    pieces = [body[i:i + len(body) // 6 + 1] for i in range(0, len(body), len(body) // 6 + 1)]
    assert len(pieces) <= 7
    with connect(limited) as sock:
        sock.sendall(b"POST %s HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n"
                     b"Content-Length: %d\r\nConnection: close\r\n\r\n" % (RIGID.encode(),
                                                                         len(body)))
        for piece in pieces:
            time.sleep(0.3)
            sock.sendall(piece)
        status, _, answer = parse(read_all(sock))
    assert status == 200, answer[:300]


def test_pipelined_and_kept_alive_requests_are_served(limited: LiveServer) -> None:
    """Two requests in one send, then a third on the same connection: three answers."""
    get = b"GET /healthz HTTP/1.1\r\nHost: x\r\n\r\n"
    with connect(limited) as sock:
        sock.sendall(get + get)
        raw = b""
        for _ in range(100):  # bounded: two small answers
            if raw.count(b"HTTP/1.1 200") == 2:
                break
            raw += sock.recv(65536)
        sock.sendall(get[:-2] + b"Connection: close\r\n\r\n")
        raw += read_all(sock)
    assert raw.count(b"HTTP/1.1 200 OK") == 3, raw


@pytest.mark.parametrize("request_bytes", [
    b"GARBAGE\r\n\r\n",
    b"GET /healthz HTTP/1.1\r\nHost: x\r\nBad Header: v\r\n\r\n",
    b"GET /healthz HTTP/1.1\r\nHost: x\r\nX-A: a\x00b\r\n\r\n",
    b"POST /healthz HTTP/1.1\r\nHost: x\r\nContent-Length: abc\r\n\r\n",
    b"POST /healthz HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: chunked\r\n\r\nzz\r\n",
    b"GET /healthz HTTP/9.9\r\nHost: x\r\n\r\n",
], ids=["request-line", "space-in-name", "nul-in-value", "content-length", "chunk-size",
        "version"])
def test_protocol_errors_are_problem_json(limited: LiveServer, request_bytes: bytes) -> None:
    with connect(limited) as sock:
        sock.sendall(request_bytes)
        problem(read_all(sock), 400, "bad-request")
    healthy(limited)


def test_no_traceback_for_any_of_it(limited: LiveServer) -> None:
    """Run last in this module: the clients' misbehaviour above left no traceback in the
    server's log."""
    healthy(limited)
    assert "Traceback" not in Path(limited.log).read_text(errors="replace")
