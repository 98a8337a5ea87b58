"""Run the service with uvicorn: ``morphserve serve`` and ``make serve`` end here."""

from __future__ import annotations

import logging
from typing import Any

import uvicorn

from service.app import create_app
from service.settings import Settings

__all__ = ["run"]


def run(host: str = "127.0.0.1", port: int = 8000, **overrides: Any) -> None:
    """Serve on ``host:port``; ``overrides`` (``data_dir``, ``scheduler``, ``workers``, ...)
    replace the settings read from the environment where not ``None``."""
    settings = Settings(**{k: v for k, v in overrides.items() if v is not None})
    logging.basicConfig(level=logging.INFO, format="%(asctime)s %(levelname)s %(name)s: "
                        "%(message)s")
    # One uvicorn process per embedded cluster; the asyncio loop is the one Dask is tested on.
    uvicorn.run(create_app(settings), host=host, port=port, loop="asyncio", lifespan="on",
                log_level="info", access_log=False, timeout_graceful_shutdown=10)
