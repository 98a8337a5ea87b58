"""A real morphserve server on loopback for end-to-end tests.

The server runs as ``python -m service.cli serve`` in its own process group (its Dask workers
included), so a test can kill the lot with one ``SIGKILL``, as a crash or OOM would.
"""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import httpx

__all__ = ["LiveServer", "free_port", "execute", "example", "wait_for_status", "TERMINAL"]

TERMINAL = ("successful", "failed", "dismissed")
REPO = Path(__file__).resolve().parents[1]


def free_port() -> int:
    """A free port below the kernel's ephemeral range, where the Dask clusters of the servers
    under test (which bind port 0) and outgoing connections never pick theirs."""
    import random

    for _ in range(200):
        port = random.randint(20000, 32000)
        with socket.socket() as s:
            try:
                s.bind(("127.0.0.1", port))
            except OSError:
                continue
            return port
    raise RuntimeError("no free port in 20000-32000")


def default_sigint() -> None:
    """In a child process before it runs: SIGINT at its default disposition. A process that
    a non-interactive shell starts in the background ignores SIGINT, and its children
    inherit that (Python then installs no KeyboardInterrupt handler); the servers and CLI
    runs of the tests get Ctrl-C as a terminal would send it, wherever pytest was started."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


class LiveServer:
    def __init__(self, data_dir: Path, env: dict[str, str] | None = None,
                 port: int | None = None) -> None:
        self.data_dir = Path(data_dir)
        self.port = port or free_port()
        self.url = f"http://127.0.0.1:{self.port}"
        self.env = {
            "MORPHSERVE_TEST_PROCESSES": "1",
            "MORPHSERVE_WORKERS": "2",
            "MORPHSERVE_CALLBACK_HOSTS": json.dumps(["127.0.0.1"]),
            "MORPHSERVE_MAX_REQUEST_BYTES": str(64 * 2**20),
            **(env or {}),
        }
        self.proc: subprocess.Popen[bytes] | None = None
        self.log = self.data_dir.parent / f"server-{self.port}.log"

    def start(self, timeout: float = 90.0) -> LiveServer:
        env = {**os.environ, **self.env}
        env.pop("MORPHSERVE_SCHEDULER", None) if "MORPHSERVE_SCHEDULER" not in self.env else None
        self.data_dir.mkdir(parents=True, exist_ok=True)
        with open(self.log, "ab") as log:
            self.proc = subprocess.Popen(
                [sys.executable, "-m", "service.cli", "serve", "--host", "127.0.0.1",
                 "--port", str(self.port), "--data-dir", str(self.data_dir)],
                cwd=REPO, env=env, stdout=log, stderr=subprocess.STDOUT,
                start_new_session=True, preexec_fn=default_sigint)
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            if self.proc.poll() is not None:
                raise RuntimeError(f"server exited with {self.proc.returncode}:\n{self.tail()}")
            try:
                if httpx.get(self.url + "/readyz", timeout=2).status_code == 200:
                    return self
            except httpx.HTTPError:
                pass
            time.sleep(0.2)
        self.kill()
        raise RuntimeError(f"server not ready within {timeout} s:\n{self.tail()}")

    def tail(self, n: int = 60) -> str:
        try:
            return "\n".join(self.log.read_text(errors="replace").splitlines()[-n:])
        except FileNotFoundError:
            return ""

    def kill(self) -> None:
        """SIGKILL the server and its workers, like a crash."""
        if self.proc is None:
            return
        try:
            os.killpg(self.proc.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        self.proc.wait(timeout=30)
        self.proc = None

    def stop(self) -> None:
        if self.proc is None:
            return
        try:
            os.killpg(self.proc.pid, signal.SIGTERM)
            self.proc.wait(timeout=20)
        except (ProcessLookupError, subprocess.TimeoutExpired):
            pass
        self.kill()

    def client(self, **kw: Any) -> httpx.Client:
        return httpx.Client(base_url=self.url, timeout=kw.pop("timeout", 60), **kw)


def wait_for_status(client: httpx.Client, job_id: str, statuses: tuple[str, ...] = TERMINAL,
                    timeout: float = 60.0) -> dict[str, Any]:
    deadline = time.monotonic() + timeout
    while True:
        info = client.get(f"/jobs/{job_id}").json()
        if info["status"] in statuses:
            return info
        if time.monotonic() > deadline:
            raise AssertionError(f"job {job_id} still {info['status']} after {timeout} s")
        time.sleep(0.05)


def execute(http: httpx.Client, process_id: str, inputs: dict[str, Any], *,
            prefer: str | None = "wait=60", **body: Any) -> httpx.Response:
    """POST an execute request, ``{"inputs": inputs, **body}``, to the process named by its
    full id (``"alignment.rigid"``, not ``"rigid"``).

    ``body`` takes the other members of an execute request (``outputs=``, ``response=``);
    ``prefer`` is the ``Prefer`` header, ``None`` for none at all (a long process then runs
    as a job, any other one synchronously).

    The body is written with :func:`json.dumps`, not httpx's ``json=`` (which refuses them):
    a NaN or infinity goes out as the bare token ``NaN``, ``Infinity`` or ``-Infinity``, as
    many clients write it, and the service reads those tokens so that its error can name the
    row that holds one. Tests of non-finite inputs depend on that.
    """
    headers = {"Content-Type": "application/json"}
    if prefer is not None:
        headers["Prefer"] = prefer
    return http.post(f"/processes/{process_id}/execution",
                     content=json.dumps({"inputs": inputs, **body}), headers=headers)


def example(http: httpx.Client, process_id: str) -> dict[str, Any]:
    """The example inputs of a process, as a client finds them: in the service's OpenAPI
    document, on the process's own execute operation (what Swagger's "Try it out" sends)."""
    doc = http.get("/openapi.json").json()
    content = doc["paths"][f"/processes/{process_id}/execution"]["post"]["requestBody"][
        "content"]["application/json"]
    inputs: dict[str, Any] = next(iter(content["examples"].values()))["value"]["inputs"]
    return inputs
