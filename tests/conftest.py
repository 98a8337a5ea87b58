from __future__ import annotations

import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

# tests/ holds `live.py`; appended after the repository root (pytest's `pythonpath`) so that
# tests/service and tests/algorithms never shadow the real packages.
sys.path.append(str(Path(__file__).parent))

from live import LiveServer  # noqa: E402


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
