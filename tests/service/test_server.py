"""`morphserve serve` claims its port before starting anything else."""

from __future__ import annotations

import socket
import subprocess
import sys

from live import REPO, free_port


def test_port_in_use_fails_at_once_with_a_clear_message() -> None:
    port = free_port()
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", port))
        taken.listen()
        done = subprocess.run([sys.executable, "-m", "service.cli", "serve", "--port",
                               str(port)], cwd=REPO, capture_output=True, text=True, timeout=60)
    assert done.returncode == 1
    assert done.stderr.strip().splitlines()[-1] == (
        f"morphserve: cannot listen on 127.0.0.1:{port}: Address already in use")
    assert "Traceback" not in done.stderr
