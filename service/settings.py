"""Service settings, read from ``MORPHSERVE_*`` environment variables.

One :func:`get_settings` dependency serves the routes; tests build their own
:class:`Settings` and pass it to :func:`service.app.create_app`.
"""

from __future__ import annotations

from functools import lru_cache
from ipaddress import IPv4Network, IPv6Network, ip_network
from pathlib import Path
from typing import Annotated

from pydantic import Field, field_validator
from pydantic_settings import BaseSettings, SettingsConfigDict

from service.binary import MAX_DEPTH

__all__ = ["Settings", "get_settings"]


class Settings(BaseSettings):
    """Every knob of the service. Environment variable: ``MORPHSERVE_`` + the upper-case name."""

    model_config = SettingsConfigDict(env_prefix="MORPHSERVE_", extra="ignore")

    data_dir: Path = Field(Path("data"), description="Job store (SQLite) and result files.")
    scheduler: str | None = Field(
        None,
        description="Address of an external Dask scheduler (tcp://host:8786). "
        "Unset: an embedded LocalCluster is started with the service.",
    )
    workers: int = Field(2, ge=1, description="Worker processes of the embedded cluster.")
    worker_memory_limit: str = Field(
        "auto", description="Memory limit per embedded worker (the nanny restarts it above)."
    )
    job_time_limit: float = Field(
        600.0, gt=0, description="Default wall-clock limit of one job, in seconds."
    )
    family_time_limits: dict[str, Annotated[float, Field(gt=0)]] = Field(
        default_factory=dict,
        description="Time limits per process family, replacing job_time_limit for it, as "
        'JSON: {"registration": 3600, "alignment": 60}. A request\'s timeLimit may only '
        "lower the limit.",
    )
    max_request_bytes: int = Field(
        256 * 2**20, ge=1024, description="Largest request body accepted (413 above)."
    )
    max_input_bytes: int = Field(
        128 * 2**20, ge=1024, description="Largest single input of a multipart upload (one "
        "file part), in bytes (413 naming the input above)."
    )
    max_points: int = Field(
        10_000_000, ge=1, description="Most points (rows) in one array input (422 above)."
    )
    max_input_depth: int = Field(
        MAX_DEPTH, ge=2, le=256, description="Most levels of objects nested inside one input "
        "(`mesh.vertices` is one level), looked into for typed binary arrays and references "
        "to earlier results (422 naming the input above). Any JSON document may nest at most "
        "1024 levels of arrays and objects: a body or `spec` part nested deeper is a 400, a "
        "JSON file part a 422 naming it."
    )
    max_file_nodes: int = Field(
        10_000, ge=1, description="Most nodes in the scene of an uploaded GLB file (422 naming "
        "the input above)."
    )
    max_file_depth: int = Field(
        64, ge=1, description="Most levels of nested nodes in the scene of an uploaded GLB "
        "file (422 naming the input above)."
    )
    decode_time_limit: float = Field(
        30.0, gt=0, description="Longest time reading one uploaded file (GLB, PLY, OBJ, STL, "
        "OFF, NPY) may take, in seconds (422 naming the input above). Files are read in "
        "worker threads, never in the thread that answers requests."
    )
    decode_threads: int = Field(2, ge=1, description="Threads that read uploaded files.")
    max_queue: int = Field(
        10_000, ge=1, description="Most jobs accepted or running at once (429 above)."
    )
    max_queue_per_key: int = Field(
        1_000, ge=1, description="Most jobs one API key may have accepted or running at once "
        "(429 above); applies when API keys are on."
    )
    api_keys_file: Path | None = Field(
        None,
        description="File of API keys, stored hashed (`morphserve keys add NAME` writes it). "
        "Set: every route but /healthz and /readyz needs `Authorization: Bearer KEY`, and a "
        "job is visible to its own key only. Unset: open (bind to 127.0.0.1).",
    )
    max_wait: float = Field(
        600.0, ge=0, description="Largest honoured `Prefer: wait=N`, in seconds."
    )
    inline_input_bytes: int = Field(
        1 * 2**20,
        ge=0,
        description="Inputs up to this size travel to workers inside the task; larger ones "
        "as a file in the data dir.",
    )
    fast_path_bytes: int = Field(
        4 * 2**20,
        ge=0,
        description="Jobs of fast-path processes (closed forms) with inputs up to this size (and "
        "an estimated cost up to fast_path_cost) run in the fast path's worker processes, "
        "skipping the scheduler's ~10 ms round trip. 0: never.",
    )
    fast_path_threads: int = Field(1, ge=1, description="Worker processes of the fast path "
                                   "(service.jobs.fastpool).")
    spool_bytes: int = Field(
        8 * 2**20,
        ge=0,
        description="Multipart bodies of at least this size are written to the data dir "
        "while they arrive (large uploads are accepted sooner). 0: never.",
    )
    keep_freed_bytes: int = Field(
        256 * 2**20,
        ge=0,
        le=2**31 - 1,
        description="Freed memory the service keeps mapped for reuse instead of returning it "
        "to the system at once (glibc's malloc thresholds): a large request body is then "
        "received into pages already mapped, about twice as fast. 0: glibc's defaults.",
    )
    allowed_failures: int = Field(
        2, ge=0, description="Worker deaths a job may cause before it is marked failed."
    )
    callback_hosts: list[str] = Field(
        default_factory=list,
        description="Hosts (host or host:port) that subscriber callbacks may be sent to. "
        "Empty: callbacks are refused.",
    )
    test_processes: bool = Field(
        False,
        description="Also offer the diagnostic processes (diagnostics.sleep, diagnostics.crash) "
        "used by the end-to-end tests.",
    )
    fsync: bool = Field(True, description="fsync the store and result files on every write.")
    public_url: str | None = Field(
        None,
        pattern=r"^https?://[^/?#]+(/[^?#]*)?$",
        description="The service's public root URL (https://example.org/morphserve), used in "
        "every link and Location header and in the status documents sent to callbacks. "
        "Unset: links are built from each request (its Host and any X-Forwarded-Proto, "
        "X-Forwarded-Host and X-Forwarded-Prefix headers), and callbacks carry links "
        "relative to the service's root.",
    )
    forwarded_allow_ips: str = Field(
        "127.0.0.1,::1",
        description="The clients whose X-Forwarded-Proto, X-Forwarded-Host and "
        "X-Forwarded-Prefix headers are believed when links are built: comma-separated IP "
        "addresses or networks (10.0.0.0/8), or * for any (uvicorn's and gunicorn's "
        "forwarded_allow_ips, with their default). Anyone else's are ignored, so a client "
        "cannot make the service answer links to a host of its choosing; set it to the "
        "address of the proxy in front of the service, or set public_url.",
    )
    fast_path_cost: float = Field(
        2e6,
        ge=0,
        description="Largest estimated cost of a job run on the fast path: the numbers in its "
        "array inputs times the square of the points' dimension, a mesh's or graph's numbers "
        "times the square root of its vertex or node count (see "
        "service.routes.processes.job_cost). Costlier jobs go to the workers.",
    )
    fast_path_seconds: float = Field(
        1.0,
        gt=0,
        description="Longest a job may run on the fast path, in seconds: one still running "
        "then has its worker process killed and replaced and is run again on the Dask "
        "workers. A small job waits at most this long behind each job ahead of it.",
    )
    dashboard_address: str | None = Field(
        None,
        description="Address of the embedded Dask scheduler's HTTP server (its dashboard, "
        "with bokeh installed, and its JSON and Prometheus routes), such as 127.0.0.1:8787. "
        "Unset: the embedded scheduler and workers serve no HTTP; they speak Dask's protocol "
        "over mutual TLS, with a certificate made at start-up, to the service only.",
    )
    max_header_bytes: int = Field(
        64 * 2**10, ge=1024, description="Largest request head (request line and headers), "
        "in bytes (431 above)."
    )
    header_timeout: float = Field(
        20.0, gt=0, description="Seconds a client may take to send a request's head, from "
        "its first byte (408, and the connection closed, above). A connection that sends "
        "nothing at all is closed after as long."
    )
    body_timeout: float = Field(
        20.0, gt=0, description="Seconds a request body may go without a byte arriving while "
        "the service waits for it (408, and the connection closed, above)."
    )

    @field_validator("forwarded_allow_ips")
    @classmethod
    def _networks(cls, value: str) -> str:
        forwarded_networks(value)  # raises ValueError naming the entry that is no address
        return value


def forwarded_networks(value: str) -> tuple[IPv4Network | IPv6Network, ...] | None:
    """The networks of a ``forwarded_allow_ips`` value; None for ``*`` (any client)."""
    items = [item.strip() for item in value.split(",") if item.strip()]
    if "*" in items:
        return None
    try:
        return tuple(ip_network(item, strict=False) for item in items)
    except ValueError as error:
        raise ValueError(f"forwarded_allow_ips: {error}") from None


@lru_cache
def get_settings() -> Settings:
    """The settings of this process, read once from the environment."""
    return Settings()
