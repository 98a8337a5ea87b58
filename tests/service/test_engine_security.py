"""The embedded Dask cluster is no back door (service.jobs.engine): its scheduler, nannies and
workers speak only mutual TLS with the certificate the service made at start-up, so a local
user's plain ``Client("tcp://127.0.0.1:PORT")`` (which could ``run`` code on the workers) and
a TLS client with a certificate of its own are both refused; no Dask process answers HTTP
with anything (no dashboard, no JSON of task keys); and jobs still run through Dask."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import httpx
import numpy as np
import psutil
import pytest

from tests.live import REPO, LiveServer, execute

pytestmark = pytest.mark.e2e

SOURCE = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]
TARGET = [[0, 0, 0], [0, 1, 0], [-1, 0, 0], [0, 0, 1]]  # SOURCE turned 90° about z

#: A would-be intruder: for each (address, mode), connect with a bounded timeout and, if that
#: works, run code on the workers. Prints what came of each, as JSON.
INTRUDER = """
import json, sys
from distributed import Client
from distributed.security import Security
out = []
for address, mode in json.loads(sys.argv[1]):
    security = Security.temporary() if mode == "own-certificate" else None
    try:
        client = Client(address, timeout=3, security=security)
    except Exception as exc:
        out.append(f"refused: {type(exc).__name__}")
        continue
    out.append(f"ran: {client.run(lambda: 'pwned')}")
    client.close()
print(json.dumps(out))
"""


def dask_ports(srv: LiveServer, *, service_only: bool = False) -> list[int]:
    """The TCP ports the server's process tree listens on (``service_only``: the service's
    own process, where the nannies are; the scheduler has a process of its own), the API's
    excepted."""
    assert srv.proc is not None
    root = psutil.Process(srv.proc.pid)
    ports = set()
    for proc in [root] if service_only else [root, *root.children(recursive=True)]:
        try:
            conns = proc.net_connections(kind="tcp")
        except psutil.Error:
            continue
        ports |= {c.laddr.port for c in conns if c.status == psutil.CONN_LISTEN}
        assert all(c.laddr.ip == "127.0.0.1" for c in conns if c.status == psutil.CONN_LISTEN)
    ports.discard(srv.port)
    return sorted(ports)


def speaks_http(port: int) -> bool:
    try:
        httpx.get(f"http://127.0.0.1:{port}/", timeout=5)
    except httpx.HTTPError:
        return False  # a Dask comm: TLS, which closes on a plain HTTP request
    return True


def intrude(attempts: list[tuple[str, str]]) -> list[str]:
    result = subprocess.run([sys.executable, "-c", INTRUDER, json.dumps(attempts)], cwd=REPO,
                            capture_output=True, text=True, timeout=60)
    assert result.returncode == 0, result.stderr
    return list(json.loads(result.stdout.splitlines()[-1]))


def test_dask_listens_only_on_loopback_and_refuses_strangers(server: LiveServer) -> None:
    """Every Dask port refuses a plain client and a TLS client with a certificate of its own
    (mutual TLS: the server checks the client's certificate too)."""
    ports = dask_ports(server)
    comms = [port for port in ports if not speaks_http(port)]
    # two nannies in the service's process, the scheduler in its own, one worker in each of
    # two processes; each worker also has an HTTP server, answering nothing (below)
    assert set(dask_ports(server, service_only=True)) <= set(comms)  # no scheduler HTTP
    assert len(comms) == 5 and len(ports) == 7, (comms, ports)
    attempts = [(f"tcp://127.0.0.1:{port}", "plain") for port in comms]
    attempts += [(f"tls://127.0.0.1:{port}", "own-certificate") for port in comms]
    outcomes = intrude(attempts)
    assert len(outcomes) == len(attempts)
    assert all(o.startswith("refused: ") for o in outcomes), list(zip(attempts, outcomes))


def test_no_dask_process_answers_http(server: LiveServer) -> None:
    """Dask's scheduler serves /json/identity.json (task keys: job ids), /info and its
    Prometheus metrics; its workers /metrics. None of it is served."""
    for port in dask_ports(server):
        for path in ("/json/identity.json", "/info/main/workers.html", "/metrics", "/health"):
            try:
                r = httpx.get(f"http://127.0.0.1:{port}{path}", timeout=5)
            except httpx.HTTPError:
                continue  # not HTTP at all: a TLS comm port
            assert r.status_code == 404, (port, path, r.status_code)


def test_jobs_still_run_through_dask(tmp_path: Path) -> None:
    """With nothing on the fast path every job goes through the TLS cluster."""
    srv = LiveServer(tmp_path / "data", {"MORPHSERVE_FAST_PATH_BYTES": "0"}).start()
    try:
        with srv.client() as http:
            r = execute(http, "alignment.rigid", {"source": SOURCE, "target": TARGET})
            assert r.status_code == 200, r.text
            np.testing.assert_allclose(r.json()["rotation"], [[0, -1, 0], [1, 0, 0], [0, 0, 1]], atol=1e-12)
        service = dask_ports(srv, service_only=True)  # the nannies
        outcomes = intrude([(f"tcp://127.0.0.1:{p}", "plain") for p in service])
        assert len(outcomes) == 2 and all(o.startswith("refused: ") for o in outcomes)
    finally:
        srv.stop()
