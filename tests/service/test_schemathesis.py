"""Schemathesis against the live service's own OpenAPI document: every check, a fixed seed,
a bounded time. Zero failures, and no unhandled error in the server's log."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from tests.live import REPO, LiveServer

pytestmark = [pytest.mark.e2e, pytest.mark.slow]

CONFIG = REPO / "tests" / "schemathesis" / "schemathesis.toml"
SECONDS = 75


def test_schemathesis_finds_nothing(tmp_path: Path) -> None:
    # The diagnostic processes stay off: diagnostics.crash would be fuzzed into killing workers.
    srv = LiveServer(tmp_path / "data", env={"MORPHSERVE_TEST_PROCESSES": "0"}).start()
    try:
        st = Path(sys.executable).with_name("schemathesis")
        done = subprocess.run(
            [str(st), "--no-color", "--config-file", str(CONFIG), "run",
             f"{srv.url}/openapi.json", "--checks", "all", "--seed", "1",
             "--max-time", str(SECONDS), "--workers", "2", "--request-timeout", "30"],
            capture_output=True, text=True, timeout=SECONDS + 180, cwd=tmp_path)
        report = done.stdout + done.stderr
        assert done.returncode == 0, report[-6000:]
        assert "Tested: " in report and " passed" in report, report[-3000:]
        log = srv.log.read_text(errors="replace")
        assert "unhandled error" not in log and "Traceback" not in log, log[-6000:]
    finally:
        srv.stop()
