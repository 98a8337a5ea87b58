"""Fixtures of the container tests: the image (built once per session) and a compose stack.

The tests need podman and podman-compose (``../shared/tools/container-runtime`` installs podman
and the base image; podman-compose is a test dependency). Without them the tests are skipped,
with the reason; with ``MORPHSERVE_REQUIRE_CONTAINERS=1`` (CI) a missing runtime fails them.

The stack under test never touches the user's own: its own image tag, its own compose project
(so its own containers, pod, network and data volume) and its own host port on 127.0.0.1. It is
always taken down, volume included, even when a test fails.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import httpx
import pytest

from tests.live import free_port

ROOT = Path(__file__).resolve().parents[2]
COMPOSE = ROOT / "docker" / "compose.yaml"
BASE_IMAGE = "docker.io/library/python:3.11-slim-bookworm"
IMAGE = "localhost/morphserve:pytest"
#: the stack's MORPHSERVE_FORWARDED_ALLOW_IPS, passed through compose.yaml: the private ranges
#: that podman's (10.88.0.0/16, 10.89.x.0/24) and Docker's (172.17.0.0/16 ...) networks use,
#: so that a client of the published port, which the API sees as the network's gateway, is
#: believed as a proxy (tests/deploy/test_stack.py)
PROXY_NETWORKS = "10.0.0.0/8,172.16.0.0/12,192.168.0.0/16"
# `--format docker`: podman's default OCI format has no HEALTHCHECK (podman drops it, warning)
BUILD = ["build", "--format", "docker", "-f", "docker/Dockerfile", "-t", IMAGE, "."]

#: figures for the closing note, printed at the end of the session (never asserted)
FIGURES: dict[str, Any] = {}


def _problem() -> str | None:
    """Why the container tests cannot run here, or None."""
    if shutil.which("podman") is None:
        return "podman is not installed (../shared/tools/container-runtime installs it)"
    if _compose_executable() is None:
        return "podman-compose is not installed (it is in the test extra: pip install -e '.[test]')"
    info = subprocess.run(["podman", "info"], capture_output=True, text=True, timeout=60)
    if info.returncode != 0:
        return f"podman does not work here: {info.stderr.strip()[-300:]}"
    if subprocess.run(["podman", "image", "exists", BASE_IMAGE], timeout=60).returncode != 0:
        return (f"the base image {BASE_IMAGE} is missing (no registry is reachable; "
                "../shared/tools/container-runtime builds a local stand-in)")
    return None


def _compose_executable() -> str | None:
    candidate = Path(sys.executable).parent / "podman-compose"
    return str(candidate) if candidate.is_file() else shutil.which("podman-compose")


def podman(*args: str, check: bool = True, timeout: float = 120) -> subprocess.CompletedProcess[str]:
    proc = subprocess.run(["podman", *args], capture_output=True, text=True, timeout=timeout)
    if check and proc.returncode != 0:
        raise AssertionError(f"podman {' '.join(args)} exited {proc.returncode}:\n"
                             f"{proc.stdout[-2000:]}\n{proc.stderr[-2000:]}")
    return proc


@pytest.fixture(scope="session")
def runtime() -> None:
    problem = _problem()
    if problem is not None:
        if os.environ.get("MORPHSERVE_REQUIRE_CONTAINERS") == "1":
            pytest.fail(f"MORPHSERVE_REQUIRE_CONTAINERS=1 but {problem}")
        pytest.skip(problem)


@pytest.fixture(scope="session")
def image(runtime: None) -> str:
    """The image, built from the working tree once per session (podman reuses cached layers:
    the dependencies' layer is rebuilt only when pyproject.toml changes)."""
    start = time.monotonic()
    proc = subprocess.run(["podman", *BUILD], cwd=ROOT, capture_output=True, text=True,
                          timeout=900)
    assert proc.returncode == 0, f"podman build failed:\n{proc.stdout[-4000:]}\n{proc.stderr[-3000:]}"
    FIGURES["image build (s, layers cached where possible)"] = round(time.monotonic() - start, 1)
    size = int(podman("image", "inspect", "--format", "{{.Size}}", IMAGE).stdout.strip())
    FIGURES["image size (MB)"] = round(size / 1e6)
    return IMAGE


def wait_ready(url: str, *, workers: int = 1, timeout: float = 120.0) -> float:
    """Poll /readyz until it reports ``workers`` workers; the seconds it took."""
    start = time.monotonic()
    last = ""
    while time.monotonic() - start < timeout:
        try:
            response = httpx.get(url + "/readyz", timeout=3)
            last = f"{response.status_code} {response.text[:200]}"
            if response.status_code == 200 and response.json()["workers"] >= workers:
                return time.monotonic() - start
        except httpx.HTTPError as exc:
            last = repr(exc)
        time.sleep(0.25)
    raise AssertionError(f"{url}/readyz not ready with {workers} workers in {timeout} s: {last}")


class Stack:
    """docker/compose.yaml run by podman-compose as project ``project`` on 127.0.0.1:``port``,
    with an override file that turns on the diagnostic processes (``diagnostics.sleep``)."""

    def __init__(self, workdir: Path, image: str, *, name: str = "",
                 extra_files: tuple[Path, ...] = (), env: dict[str, str] | None = None) -> None:
        self.project = f"morphserve-pytest{name}-{os.getpid()}"
        self.extra_files = extra_files
        self.env = {**(env or {}), "MORPHSERVE_IMAGE": image}
        # the anonymous volumes of the image's VOLUME /data (the scheduler mounts nothing
        # there), which `down -v` leaves behind: removed by destroy()
        self.anonymous: set[str] = set()
        self.port = free_port()
        self.url = f"http://127.0.0.1:{self.port}"
        self.image = image
        self.override = workdir / "compose.override.yaml"
        self.override.write_text(
            "services:\n  api:\n    environment:\n      MORPHSERVE_TEST_PROCESSES: \"1\"\n")

    def compose(self, *args: str, timeout: float = 300) -> subprocess.CompletedProcess[str]:
        proc = subprocess.run(self._argv(*args), cwd=ROOT, env=self._env(), capture_output=True,
                              text=True, timeout=timeout)
        assert proc.returncode == 0, (f"podman-compose {' '.join(args)} exited "
                                      f"{proc.returncode}:\n{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}")
        return proc

    def _argv(self, *args: str) -> list[str]:
        executable = _compose_executable()
        assert executable is not None
        files = [COMPOSE, *self.extra_files, self.override]
        return [executable, "-p", self.project, *(a for f in files for a in ("-f", str(f))),
                *args]

    def _env(self) -> dict[str, str]:
        return {**os.environ, **self.env, "MORPHSERVE_PORT": str(self.port)}

    def up(self) -> float:
        """Start the stack; seconds until the API is ready with both workers."""
        start = time.monotonic()
        self.compose("up", "-d", "--no-build")
        wait_ready(self.url, workers=2)
        return time.monotonic() - start

    def down(self) -> None:
        self._note_anonymous_volumes()
        self.compose("down")

    def _note_anonymous_volumes(self) -> None:
        label = f"label=io.podman.compose.project={self.project}"
        ids = podman("ps", "-aq", "--filter", label, check=False).stdout.split()
        if ids:
            out = podman("inspect", "--format",
                         '{{range .Mounts}}{{if eq .Type "volume"}}{{.Name}} {{end}}{{end}}',
                         *ids, check=False).stdout
            self.anonymous |= set(out.split()) - {self.volume}

    def containers(self, service: str) -> list[str]:
        out = podman("ps", "--filter", f"label=io.podman.compose.project={self.project}",
                     "--filter", f"label=com.docker.compose.service={service}",
                     "--format", "{{.Names}}").stdout
        return sorted(out.split())

    @property
    def network(self) -> str:
        return f"{self.project}_default"

    @property
    def volume(self) -> str:
        return f"{self.project}_data"

    def logs(self) -> str:
        parts = []
        for service in ("api", "scheduler", "worker"):
            for name in self.containers(service):
                log = podman("logs", "--tail", "40", name, check=False)
                parts.append(f"--- {name}\n{log.stdout}{log.stderr}")
        return "\n".join(parts)

    @contextmanager
    def running(self) -> Iterator[float]:
        """The stack up (yields the seconds it took to be ready), its logs printed when what
        runs inside fails, and destroyed after, whatever happened."""
        try:
            yield self.up()
        except BaseException:
            print(self.logs(), file=sys.stderr)
            raise
        finally:
            self.destroy()

    def destroy(self) -> None:
        """Everything of the project, whatever state a failed test left: containers, pod,
        network and volumes."""
        self._note_anonymous_volumes()
        if _compose_executable() is not None:
            subprocess.run(self._argv("down", "-v", "-t", "2"), cwd=ROOT, env=self._env(),
                           capture_output=True, timeout=300)
        label = f"label=io.podman.compose.project={self.project}"
        ids = podman("ps", "-aq", "--filter", label, check=False).stdout.split()
        if ids:
            podman("rm", "-f", "-v", "-t", "0", *ids, check=False)
        podman("pod", "rm", "-f", f"pod_{self.project}", check=False)
        for volume in sorted(self.anonymous | {self.volume}):
            podman("volume", "rm", "-f", volume, check=False)
        podman("network", "rm", "-f", self.network, check=False)


@pytest.fixture(scope="session")
def stack(image: str, tmp_path_factory: pytest.TempPathFactory) -> Iterator[Stack]:
    stack = Stack(tmp_path_factory.mktemp("stack"), image,
                  env={"MORPHSERVE_FORWARDED_ALLOW_IPS": PROXY_NETWORKS})
    with stack.running() as seconds:
        FIGURES["stack up to ready with 2 workers (s)"] = round(seconds, 1)
        yield stack


def pytest_terminal_summary(terminalreporter: Any) -> None:
    if FIGURES:
        terminalreporter.section("container figures")
        terminalreporter.write_line(json.dumps(FIGURES, indent=1))
