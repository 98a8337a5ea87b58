"""Schemathesis against the live service's own OpenAPI document: every check, a fixed seed,
a bounded time. Every operation tested (the generic execute and one per process), zero
failures, and no unhandled error in the server's log.

One worker: with two, schemathesis's threads call ``ast.parse`` at once (hypothesis describes
its filter lambdas from their source), which CPython 3.11 can fail with a SystemError
("AST constructor recursion depth mismatch", python/cpython#106905): an error of the
fuzzer, not of the service, that made the run flaky."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import httpx
import pytest

from service.catalog import processes
from tests.live import REPO, LiveServer

pytestmark = [pytest.mark.e2e, pytest.mark.slow]

CONFIG = REPO / "tests" / "schemathesis" / "schemathesis.toml"
SECONDS = 75
_METHODS = {"get", "put", "post", "delete", "options", "head", "patch", "trace"}


def test_schemathesis_finds_nothing(tmp_path: Path) -> None:
    # The diagnostic processes stay off: diagnostics.crash would be fuzzed into killing workers.
    # Every job is capped at 10 s, so that an execute request that waits for a fuzzed job
    # (10 million iterations) answers in time (see the toml).
    srv = LiveServer(tmp_path / "data", env={"MORPHSERVE_TEST_PROCESSES": "0",
                                             "MORPHSERVE_JOB_TIME_LIMIT": "10"}).start()
    try:
        st = Path(sys.executable).with_name("schemathesis")
        done = subprocess.run(
            [str(st), "--no-color", "--config-file", str(CONFIG), "run",
             f"{srv.url}/openapi.json", "--checks", "all", "--seed", "1",
             "--exclude-checks", "use_after_free",  # why: tests/schemathesis/schemathesis.toml
             "--max-time", str(SECONDS), "--workers", "1", "--request-timeout", "30"],
            capture_output=True, text=True, timeout=SECONDS + 180, cwd=tmp_path)
        report = done.stdout + done.stderr
        assert done.returncode == 0, report[-6000:]
        operations = sum(1 for item in httpx.get(f"{srv.url}/openapi.json").json()[
            "paths"].values() for method in item if method in _METHODS)
        assert operations > len(processes()), operations  # the per-process ones are there
        assert f"Tested: {operations}\n" in report, report[-3000:]
        assert " passed" in report and " failed" not in report, report[-3000:]
        log = srv.log.read_text(errors="replace")
        assert "unhandled error" not in log and "Traceback" not in log, log[-6000:]
    finally:
        srv.stop()
