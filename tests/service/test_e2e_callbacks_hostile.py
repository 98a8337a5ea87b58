"""Hostile subscribers (service.callbacks): URLs httpx cannot send to are a 422 at submission
naming the member; deliveries that fail are retried a bounded number of times with backoff and
counted in /metrics; a subscriber's answer is read only up to a cap; a subscriber that never
answers costs one bounded attempt each time. Receivers are real HTTP servers on loopback;
every wait is bounded in count and time and no test asserts how long anything took."""

from __future__ import annotations

import asyncio
import json
import socket
import threading
import time
from collections.abc import Callable, Iterator
from datetime import UTC, datetime, timedelta
from email.utils import format_datetime
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer

import httpx
import numpy as np
import pytest
from prometheus_client.parser import text_string_to_metric_families

from service.callbacks import MAX_RESPONSE_BYTES, Deliveries, Notifier
from tests.live import execute

pytestmark = pytest.mark.e2e

SOURCE = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]
TARGET = [[0, 0, 0], [0, 1, 0], [-1, 0, 0], [0, 0, 1]]  # SOURCE turned 90° about z


@pytest.mark.parametrize(("member", "uri"), [
    ("successUri", "http://127.0.0.1:8000/a\tb"),  # urllib drops the TAB; httpx refuses it
    ("successUri", "http://127.0.0.1\t:8000/x"),
    ("inProgressUri", "http://127.0.0.1:8000/\nx"),
    ("failedUri", "http://127.0.0.1:8000/ x"),
    ("successUri", "http://127.0.0.1:abc/"),
    ("successUri", "http://127.0.0.1:99999/"),
    ("failedUri", "http://127.0.0.1:0/"),
    ("successUri", "http://127.0.0.1:+80/"),
    ("successUri", "http://127.0.0.1:\uff18\uff10/"),  # fullwidth digits: httpx drops them
    ("inProgressUri", "http://[::1/"),
    ("successUri", "http://127.0.0.1/" + "a" * 70_000),  # longer than httpx sends
    ("successUri", "ftp://127.0.0.1/x"),
])
def test_unsendable_subscriber_url_is_422_naming_it(http: httpx.Client, member: str,
                                                    uri: str) -> None:
    r = execute(http, "alignment.rigid", {"source": SOURCE, "target": TARGET},
                prefer="respond-async", subscriber={member: uri})
    assert r.status_code == 422, r.text
    assert r.headers["content-type"] == "application/problem+json"
    body = r.json()
    assert body["errors"][0]["input"] == f"subscriber.{member}"
    assert body["detail"].startswith(f"subscriber.{member}: ")


class Receiver:
    """An HTTP server on loopback answering each POST with ``answer(n)``'s status (n: the
    POST's number, from 1), recording what it received and how its answer went."""

    def __init__(self, answer: Callable[[int], int], body_bytes: int = 0) -> None:
        self.posts: list[tuple[str, dict]] = []
        self.broken_answers = 0
        receiver = self

        class Handler(BaseHTTPRequestHandler):
            def do_POST(self) -> None:  # noqa: N802
                n = int(self.headers["Content-Length"])
                receiver.posts.append((self.path, json.loads(self.rfile.read(n))))
                self.send_response(answer(len(receiver.posts)))
                self.send_header("Content-Length", str(body_bytes))
                self.end_headers()
                try:
                    block = b"x" * 2**16
                    for _ in range(body_bytes // len(block)):
                        self.wfile.write(block)
                except (BrokenPipeError, ConnectionResetError):
                    receiver.broken_answers += 1  # the service hung up before the end
                    self.close_connection = True

            def log_message(self, *args: object) -> None:
                pass

        self.server = ThreadingHTTPServer(("127.0.0.1", 0), Handler)
        self.server.daemon_threads = True
        threading.Thread(target=self.server.serve_forever, daemon=True).start()
        self.base = f"http://127.0.0.1:{self.server.server_port}"

    def wait_for(self, n: int, timeout: float = 30.0) -> None:
        deadline = time.monotonic() + timeout
        while len(self.posts) < n and time.monotonic() < deadline:
            time.sleep(0.05)

    def close(self) -> None:
        self.server.shutdown()
        self.server.server_close()


@pytest.fixture
def receiver_factory() -> Iterator[Callable[..., Receiver]]:
    made: list[Receiver] = []

    def make(answer: Callable[[int], int], body_bytes: int = 0) -> Receiver:
        made.append(Receiver(answer, body_bytes))
        return made[-1]

    yield make
    for r in made:
        r.close()


def counters(http: httpx.Client) -> dict[str, float]:
    """The callback counters of /metrics, read with Prometheus's own parser."""
    text = http.get("/metrics").text
    out: dict[str, float] = {}
    for family in text_string_to_metric_families(text):
        for sample in family.samples:
            if sample.name == "morphserve_callbacks_total":
                out[sample.labels["outcome"]] = sample.value
            elif sample.name == "morphserve_callback_retries_total":
                out["retries"] = sample.value
    return out


def wait_counters(http: httpx.Client, expected: dict[str, float],
                  timeout: float = 30.0) -> dict[str, float]:
    deadline = time.monotonic() + timeout
    while True:
        got = counters(http)
        if all(got[k] >= v for k, v in expected.items()) or time.monotonic() > deadline:
            return got
        time.sleep(0.1)


def submit(http: httpx.Client, uri: str) -> str:
    r = execute(http, "alignment.rigid", {"source": SOURCE, "target": TARGET},
                prefer="respond-async", subscriber={"successUri": uri})
    assert r.status_code == 201, r.text
    return str(r.json()["jobID"])


def test_failed_deliveries_are_retried_then_delivered_and_counted(
        http: httpx.Client, receiver_factory: Callable[..., Receiver]) -> None:
    """503, 503, then 204: three POSTs of the same results, two retries, one delivery."""
    recv = receiver_factory(lambda n: 503 if n <= 2 else 204)
    before = counters(http)
    submit(http, recv.base + "/ok")
    after = wait_counters(http, {"delivered": before["delivered"] + 1})
    assert len(recv.posts) == 3
    assert recv.posts[0] == recv.posts[1] == recv.posts[2]
    np.testing.assert_allclose(recv.posts[0][1]["rotation"], [[0, -1, 0], [1, 0, 0], [0, 0, 1]], atol=1e-12)
    assert after["delivered"] - before["delivered"] == 1
    assert after["retries"] - before["retries"] == 2
    assert after["failed"] == before["failed"]


def test_a_subscriber_that_keeps_failing_is_given_up_after_bounded_attempts(
        http: httpx.Client, receiver_factory: Callable[..., Receiver]) -> None:
    recv = receiver_factory(lambda n: 500)
    before = counters(http)
    submit(http, recv.base + "/down")
    after = wait_counters(http, {"failed": before["failed"] + 1})
    attempts = Notifier().attempts
    assert len(recv.posts) == attempts
    time.sleep(1.0)  # room for a POST too many, were the count not bounded
    assert len(recv.posts) == attempts
    assert after["failed"] - before["failed"] == 1
    assert after["retries"] - before["retries"] == attempts - 1


def test_a_refusal_is_not_retried(http: httpx.Client,
                                  receiver_factory: Callable[..., Receiver]) -> None:
    """A 4xx other than 408/425/429 says the subscriber will not take it: one POST only."""
    recv = receiver_factory(lambda n: 404)
    before = counters(http)
    submit(http, recv.base + "/gone")
    after = wait_counters(http, {"failed": before["failed"] + 1})
    assert len(recv.posts) == 1
    assert after["retries"] == before["retries"]


def test_a_huge_answer_is_not_read_past_the_cap(
        http: httpx.Client, receiver_factory: Callable[..., Receiver]) -> None:
    """A subscriber answering 200 with 256 MiB: the service reads its cap and hangs up, so
    the receiver's writes fail well before the end; the delivery counts as delivered."""
    assert MAX_RESPONSE_BYTES < 2**20
    recv = receiver_factory(lambda n: 200, body_bytes=256 * 2**20)
    before = counters(http)
    submit(http, recv.base + "/big")
    after = wait_counters(http, {"delivered": before["delivered"] + 1})
    deadline = time.monotonic() + 30
    while recv.broken_answers == 0 and time.monotonic() < deadline:
        time.sleep(0.05)
    assert recv.broken_answers == 1
    assert len(recv.posts) == 1
    assert after["delivered"] - before["delivered"] == 1


def test_a_subscriber_that_never_answers_costs_bounded_attempts() -> None:
    """A server that accepts connections and never answers: each attempt ends at the
    notifier's deadline, and after ``attempts`` of them the delivery is given up."""
    listener = socket.create_server(("127.0.0.1", 0))
    accepted: list[socket.socket] = []

    def accept() -> None:
        listener.settimeout(20)
        for _ in range(5):  # bounded: never more than the attempts below
            try:
                conn, _ = listener.accept()
            except (TimeoutError, OSError):
                return
            accepted.append(conn)  # read nothing, answer nothing

    threading.Thread(target=accept, daemon=True).start()
    counts = Deliveries()
    notifier = Notifier(timeout=0.3, attempts=3, backoff=0.01, deliveries=counts)

    async def run() -> None:
        notifier.send(f"http://127.0.0.1:{listener.getsockname()[1]}/slow", {"a": 1})
        await asyncio.wait_for(asyncio.gather(*notifier._tasks), 20)
        await notifier.close()

    try:
        asyncio.run(run())
    finally:
        listener.close()
        for conn in accepted:
            conn.close()
    assert len(accepted) == 3
    assert (counts.delivered, counts.failed, counts.retries) == (0, 1, 2)


@pytest.mark.parametrize(("retry_after", "low", "high"), [
    ("40", 40.0, 40.0),  # delay-seconds
    (None, 0.005, 0.01),  # not said: the backoff, with its jitter
    # an HTTP-date (RFC 9110, 10.2.3) 60 s from now: waited until then (1 s resolution)
    ("in 60 s", 58.0, 60.0),
])
def test_retry_after_is_read_as_seconds_or_an_http_date(
        monkeypatch: pytest.MonkeyPatch, retry_after: str | None, low: float,
        high: float) -> None:
    """The wait before a retry is what the subscriber's ``Retry-After`` asks, in either of
    the standard's forms (within ``max_backoff``)."""
    if retry_after == "in 60 s":
        retry_after = format_datetime(datetime.now(UTC) + timedelta(seconds=60), usegmt=True)
    answers = iter([503, 200])

    def answer(request: httpx.Request) -> httpx.Response:
        status = next(answers)
        headers = {"Retry-After": retry_after} if status == 503 and retry_after else {}
        return httpx.Response(status, headers=headers, stream=httpx.ByteStream(b"ok"))

    waits: list[float] = []

    async def sleep(seconds: float) -> None:
        waits.append(seconds)

    monkeypatch.setattr("service.callbacks.asyncio.sleep", sleep)
    counts = Deliveries()
    notifier = Notifier(attempts=2, backoff=0.01, max_backoff=300, deliveries=counts)

    async def run() -> None:
        notifier._client = httpx.AsyncClient(transport=httpx.MockTransport(answer))
        notifier.send("http://subscriber.example/done", {"a": 1})
        await asyncio.wait_for(asyncio.gather(*notifier._tasks), 20)
        await notifier.close()

    asyncio.run(run())
    assert (counts.delivered, counts.retries) == (1, 1)
    assert len(waits) == 1 and low <= waits[0] <= high, waits
