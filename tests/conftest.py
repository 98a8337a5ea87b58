from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.live import LiveServer


@pytest.fixture(scope="session")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[LiveServer]:
    """One live server (uvicorn + embedded Dask cluster of 2 workers) for the session."""
    srv = LiveServer(tmp_path_factory.mktemp("server") / "data").start()
    yield srv
    srv.stop()


@pytest.fixture
def http(server: LiveServer):  # noqa: ANN201
    with server.client() as c:
        yield c


@pytest.fixture
def spooling_server(tmp_path: Path) -> Iterator[LiveServer]:
    """A live server of its own whose every job leaves an inputs file to look at: bodies of
    1000 bytes and more are spooled, inputs of more than 1000 bytes go to a file, and
    nothing runs in the service's process."""
    srv = LiveServer(tmp_path / "data", {
        "MORPHSERVE_SPOOL_BYTES": "1000", "MORPHSERVE_FAST_PATH_BYTES": "0",
        "MORPHSERVE_INLINE_INPUT_BYTES": "1000"}).start()
    try:
        yield srv
    finally:
        srv.stop()
