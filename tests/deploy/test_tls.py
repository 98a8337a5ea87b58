"""docker/compose.tls.yaml: the scheduler, the workers and the API talk over mutual TLS, with
certificates from mounted secrets, and a peer without a certificate of the CA is refused."""

from __future__ import annotations

import re
import subprocess
from collections.abc import Iterator
from pathlib import Path

import httpx
import pytest

from tests.deploy.conftest import ROOT, Stack, podman
from tests.live import execute

pytestmark = [pytest.mark.container, pytest.mark.e2e, pytest.mark.timeout(600)]

TLS_OVERRIDE = ROOT / "docker" / "compose.tls.yaml"


def make_ca_and_cert(directory: Path) -> None:
    """ca.pem, and dask.pem + dask-key.pem signed by it (openssl, as a user would)."""
    directory.mkdir()

    def openssl(*args: str) -> None:
        subprocess.run(["openssl", *args], cwd=directory, check=True, capture_output=True,
                       timeout=60)

    openssl("req", "-x509", "-newkey", "rsa:2048", "-nodes", "-days", "2", "-subj",
            "/CN=morphserve test CA", "-keyout", "ca-key.pem", "-out", "ca.pem")
    openssl("req", "-newkey", "rsa:2048", "-nodes", "-subj", "/CN=morphserve-dask",
            "-keyout", "dask-key.pem", "-out", "dask.csr")
    openssl("x509", "-req", "-in", "dask.csr", "-CA", "ca.pem", "-CAkey", "ca-key.pem",
            "-CAcreateserial", "-days", "2", "-out", "dask.pem")
    # readable by the containers' user 10001 (a real deployment would chown the key instead)
    for name in ("ca.pem", "dask.pem", "dask-key.pem"):
        (directory / name).chmod(0o644)


@pytest.fixture(scope="module")
def tls_dirs(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    base = tmp_path_factory.mktemp("tls")
    make_ca_and_cert(base / "good")
    make_ca_and_cert(base / "rogue")  # same names, another CA
    return base / "good", base / "rogue"


@pytest.fixture(scope="module")
def tls_stack(image: str, tls_dirs: tuple[Path, Path],
              tmp_path_factory: pytest.TempPathFactory) -> Iterator[Stack]:
    stack = Stack(tmp_path_factory.mktemp("tls-stack"), image, name="-tls",
                  extra_files=(TLS_OVERRIDE,), env={"MORPHSERVE_TLS_DIR": str(tls_dirs[0])})
    with stack.running():
        yield stack


CONNECT = """
import sys
from distributed import Client
try:
    Client(sys.argv[1], timeout=8).close()
except Exception as exc:
    print(type(exc).__name__, exc)
    sys.exit(3)
"""


def connect(stack: Stack, address: str, certs: Path | None) -> int:
    """Try a Dask client from a fresh container on the stack's network; its exit code."""
    args = ["run", "--rm", "--network", stack.network]
    if certs is not None:
        args += ["-v", f"{certs}:/certs:ro",
                 "-e", "DASK_DISTRIBUTED__COMM__TLS__CA_FILE=/certs/ca.pem",
                 "-e", "DASK_DISTRIBUTED__COMM__TLS__CLIENT__CERT=/certs/dask.pem",
                 "-e", "DASK_DISTRIBUTED__COMM__TLS__CLIENT__KEY=/certs/dask-key.pem"]
    args += [stack.image, "python", "-c", CONNECT, address]
    return podman(*args, check=False, timeout=90).returncode


def test_jobs_run_on_workers_over_tls(tls_stack: Stack) -> None:
    with httpx.Client(base_url=tls_stack.url, timeout=60) as http:
        assert http.get("/readyz").json()["workers"] == 2
        response = execute(http, "diagnostics.sleep", {"seconds": 0, "steps": 1})
        assert response.status_code == 200, response.text
        (scheduler,) = tls_stack.containers("scheduler")
        logs = podman("logs", scheduler)
        assert re.search(r"Scheduler at:\s+tls://", logs.stdout + logs.stderr), "not on TLS"


def test_the_scheduler_refuses_peers_without_the_cas_certificate(
        tls_stack: Stack, tls_dirs: tuple[Path, Path]) -> None:
    good, rogue = tls_dirs
    # the control: with the stack's certificate a client gets in, so the refusals below are TLS
    assert connect(tls_stack, "tls://scheduler:8786", good) == 0
    assert connect(tls_stack, "tcp://scheduler:8786", None) != 0, "plain TCP got in"
    assert connect(tls_stack, "tls://scheduler:8786", rogue) != 0, "another CA's cert got in"
