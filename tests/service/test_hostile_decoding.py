"""Uploaded files are decoded off the event loop, within a time limit: a real server (uvicorn
on loopback, in this process so that a test can hold the decoder on an event) answers
``/healthz`` while a file is being read, refuses a file that takes longer than
``decode_time_limit`` with a 422 naming the input, and logs no traceback for any client's
error (nesting, hostile files).

Nothing here measures time: the decoder is held on an event until the test has seen what it
wants to see, so the order of events is certain."""

from __future__ import annotations

import json
import logging
import threading
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import httpx
import pytest

from service import geometry_io
from service.settings import Settings
from tests.live import free_port
from tests.service.test_e2e_malformed import CATALOGUE, _multipart

pytestmark = pytest.mark.e2e

SQ = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]
PLY = (b"ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
       b"property float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n")


class InProcessServer:
    """uvicorn serving :func:`service.app.create_app` in a thread of this process."""

    def __init__(self, settings: Settings) -> None:
        import uvicorn

        from service.app import create_app

        self.settings = settings
        self.port = free_port()
        self.url = f"http://127.0.0.1:{self.port}"
        config = uvicorn.Config(create_app(settings), host="127.0.0.1", port=self.port,
                                log_level="warning", lifespan="on")
        self.server = uvicorn.Server(config)
        self.thread = threading.Thread(target=self.server.run, daemon=True)

    def __enter__(self) -> InProcessServer:
        self.thread.start()
        for _ in range(1200):  # the embedded cluster starts first; bounded by count
            if self.server.started:
                return self
            self.thread.join(0.1)
            if not self.thread.is_alive():
                break
        raise RuntimeError("the in-process server did not start")

    def __exit__(self, *_: Any) -> None:
        self.server.should_exit = True
        self.thread.join(60)


@pytest.fixture(scope="module")
def live(tmp_path_factory: pytest.TempPathFactory) -> Iterator[InProcessServer]:
    settings = Settings(data_dir=Path(tmp_path_factory.mktemp("decoding")) / "data",
                        workers=1, decode_time_limit=600.0, fsync=False)
    with InProcessServer(settings) as srv:
        yield srv


@pytest.fixture
def held(monkeypatch: pytest.MonkeyPatch) -> Iterator[tuple[threading.Event, threading.Event]]:
    """The decoder held on an event: ``entered`` is set when a part named ``source`` is
    being decoded, which then waits until ``release`` is set (60 s at most, so that a
    broken service fails the test instead of hanging it)."""
    entered, release = threading.Event(), threading.Event()

    def hold(upload: geometry_io.Upload) -> None:
        if upload.name == "source":
            entered.set()
            release.wait(60)

    monkeypatch.setattr(geometry_io, "before_decode", hold)
    yield entered, release
    release.set()


def _upload(url: str, out: dict[str, Any]) -> None:
    body, headers = _multipart({"spec": ("spec.json", b'{"inputs": {"target": %s}}' %
                                         str(SQ).encode()), "source": ("cloud.ply", PLY)})
    with httpx.Client(base_url=url, timeout=120) as c:
        out["response"] = c.post("/processes/alignment.rigid/execution", content=body,
                                 headers={**headers, "Prefer": "wait=60"})


def test_healthz_answers_while_an_upload_is_being_decoded(live: InProcessServer, held) -> None:
    entered, release = held
    out: dict[str, Any] = {}
    upload = threading.Thread(target=_upload, args=(live.url, out))
    upload.start()
    try:
        assert entered.wait(60), "the upload never reached the decoder"
        with httpx.Client(base_url=live.url, timeout=30) as c:
            health = c.get("/healthz")
            ready = c.get("/readyz")
        # the decoder is still held: the upload has no answer yet
        assert upload.is_alive() and "response" not in out
        assert health.status_code == 200 and health.json() == {"status": "ok"}
        assert ready.status_code == 200
    finally:
        release.set()
        upload.join(120)
    r = out["response"]
    assert r.status_code == 200, r.text
    assert r.json()["rmse"] < 1e-9  # the file's points are the target's


def test_a_file_that_takes_too_long_is_a_422_naming_it(live: InProcessServer, held,
                                                       monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(live.settings, "decode_time_limit", 0.5)  # read on every request
    entered, release = held
    out: dict[str, Any] = {}
    upload = threading.Thread(target=_upload, args=(live.url, out))
    upload.start()
    assert entered.wait(60)
    upload.join(120)  # answered while the decoder is still held: the limit cut it off
    assert not release.is_set()
    r = out["response"]
    assert r.status_code == 422, r.text
    problem = r.json()
    assert problem["errors"][0]["input"] == "source"
    assert "took longer than 0.5 s" in problem["detail"]
    release.set()


_HOSTILE = [row for row in CATALOGUE if any(w in row[0] for w in (
    "nested", "deep", "GLB", "PLY", "OBJ", "NaN"))]


def test_no_traceback_is_logged_for_a_clients_error(live: InProcessServer,
                                                    caplog: pytest.LogCaptureFixture) -> None:
    assert len(_HOSTILE) >= 15
    caplog.set_level(logging.INFO)
    with httpx.Client(base_url=live.url, timeout=60) as c:
        for label, process, body, headers, status, _ in _HOSTILE:
            raw = body if isinstance(body, bytes) else json.dumps({"inputs": body}).encode()
            r = c.post(f"/processes/{process}/execution", content=raw,
                       headers={"Content-Type": "application/json", **headers})
            assert r.status_code == status, (label, r.text)
        assert c.get("/healthz").status_code == 200
    errors = [rec for rec in caplog.records if rec.exc_info or rec.levelno >= logging.ERROR]
    assert not errors, [(rec.getMessage(), rec.exc_info) for rec in errors]
    # what the service logs for a 500 would have reached caplog
    from service import errors as service_errors

    assert service_errors.log.propagate and service_errors.log.isEnabledFor(logging.ERROR)
