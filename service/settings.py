"""Service settings, read from ``MORPHSERVE_*`` environment variables.

One :func:`get_settings` dependency serves the routes; tests build their own
:class:`Settings` and pass it to :func:`service.app.create_app`.
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path
from typing import Annotated

from pydantic import Field
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
        description="Jobs of fast-path processes (closed forms) with inputs up to this size run "
        "in the service's own threads, skipping the scheduler's ~10 ms round trip. 0: never.",
    )
    fast_path_threads: int = Field(1, ge=1, description="Threads of the fast path.")
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


@lru_cache
def get_settings() -> Settings:
    """The settings of this process, read once from the environment."""
    return Settings()
