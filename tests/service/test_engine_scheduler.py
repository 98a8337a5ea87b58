"""The embedded scheduler in a process of its own (service/jobs/scheduler.py): jobs run
through it, it is not in the service's process, its comms send promptly, and it dies with
the service however the service ends."""

from __future__ import annotations

import asyncio
import os
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import psutil
import pytest
from distributed.batched import BatchedSend

from service.jobs.engine import Engine
from service.jobs.scheduler import SEND_INTERVAL, send_promptly
from service.jobs.status import JobStatus
from service.jobs.store import JobRequest, JobStore
from service.settings import Settings
from tests.live import REPO

pytestmark = pytest.mark.e2e


def test_send_promptly_lowers_distributeds_own_interval() -> None:
    """``interval`` is distributed's attribute, not ours: if an upgrade renames it or stops
    parsing it to a float, this fails instead of the tweak silently doing nothing."""
    for given, expected in (("10ms", SEND_INTERVAL), ("5ms", SEND_INTERVAL),
                            ("0.5ms", 0.0005)):
        comm = BatchedSend(interval=given)
        assert isinstance(comm.interval, float)
        send_promptly(comm)
        assert comm.interval == pytest.approx(expected)
    send_promptly(None)  # no comm yet: nothing to do


def _listeners(pid: int) -> set[int]:
    return {c.laddr.port for c in psutil.Process(pid).net_connections(kind="tcp")
            if c.status == psutil.CONN_LISTEN}


def test_jobs_run_through_a_scheduler_in_another_process() -> None:
    """Rigid alignment through the embedded cluster: the right rotation; the scheduler's
    port belongs to a child of the service, not to the service; the client's stream to it
    sends promptly."""

    async def scenario(data: Path) -> None:
        store = JobStore(data, fsync=False)
        engine = Engine(Settings(data_dir=data, fast_path_bytes=0, workers=1), store)
        await engine.start()
        try:
            assert engine.client is not None and engine.cluster is not None
            port = int(engine.cluster.scheduler_address.rsplit(":", 1)[1])
            assert port not in _listeners(os.getpid())
            owners = [p for p in psutil.Process().children(recursive=True)
                      if port in _listeners(p.pid)]
            assert [p.pid for p in owners] == [engine.cluster.scheduler.process.pid]
            scheduler = owners[0]
            assert engine.client.scheduler_comm.interval == SEND_INTERVAL
            rng = np.random.default_rng(0)
            x = rng.normal(size=(50, 3))
            c, s = np.cos(0.3), np.sin(0.3)
            rot = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
            inputs = {"source": x, "target": x @ rot.T}
            job = await store.write(store.create, process="alignment.rigid",
                                    request=JobRequest(), time_limit=60.0,
                                    idempotency_key=None, request_hash=None, owner="",
                                    job_id="j1", inputs=inputs, spool=None, body=b"",
                                    encoded=())
            engine.submit(job, inputs)
            outcome = await engine.wait(job.id, 120)
            assert outcome is not None and outcome.status is JobStatus.SUCCESSFUL
            np.testing.assert_allclose(outcome.outputs["rotation"], rot, atol=1e-12)
        finally:
            await engine.close()
        assert not scheduler.is_running()  # closed with the engine (and reaped)

    with tempfile.TemporaryDirectory() as tmp:
        asyncio.run(scenario(Path(tmp)))


#: A service stand-in: starts a scheduler process, prints its pid, then is killed with -9.
ORPHAN = """
import asyncio, os, signal, sys
from distributed.security import Security
from service.jobs.scheduler import SchedulerProcess

async def main():
    s = SchedulerProcess(host="127.0.0.1", port=0, protocol="tls://",
                         security=Security.temporary(), dashboard=False,
                         dashboard_address="127.0.0.1:0")
    await s
    print(s.process.pid, flush=True)
    os.kill(os.getpid(), signal.SIGKILL)

if __name__ == "__main__":
    asyncio.run(main())
"""


def test_the_scheduler_dies_with_a_killed_service(tmp_path: Path) -> None:
    """``kill -9`` of the service runs no clean-up: the scheduler's process notices its
    parent's end by itself (the parent's sentinel) and exits."""
    script = tmp_path / "orphan.py"
    script.write_text(ORPHAN)
    proc = subprocess.run([sys.executable, str(script)], cwd=REPO, capture_output=True,
                          text=True, timeout=120, env={**os.environ, "PYTHONPATH": str(REPO)})
    assert proc.returncode == -signal.SIGKILL, proc.stderr
    pid = int(proc.stdout.split()[0])
    deadline = time.monotonic() + 60  # a bound on a poll, not a timing assertion
    while time.monotonic() < deadline:
        try:
            if psutil.Process(pid).status() == psutil.STATUS_ZOMBIE:
                break
        except psutil.NoSuchProcess:
            break
        time.sleep(0.1)
    else:
        os.kill(pid, signal.SIGKILL)
        pytest.fail("the scheduler outlived its service")
