"""`morphserve serve` claims its port before starting anything else."""

from __future__ import annotations

import platform
import socket
import subprocess
import sys

import pytest

from tests.live import REPO, free_port


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


def test_listening_socket_is_tcp_so_responses_are_not_delayed() -> None:
    """asyncio turns Nagle off (TCP_NODELAY) only for sockets whose proto is TCP; a socket
    made with proto 0 answered every request ~40 ms late (delayed ACK)."""
    import asyncio

    from service.server import bind

    sock = bind("127.0.0.1", free_port())
    try:
        assert sock.proto == socket.IPPROTO_TCP

        async def accepted_nodelay() -> int:
            result: asyncio.Future[int] = asyncio.get_running_loop().create_future()

            def on_connect(reader, writer) -> None:  # noqa: ANN001
                s = writer.get_extra_info("socket")
                result.set_result(s.getsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY))
                writer.close()

            server = await asyncio.start_server(on_connect, sock=sock)
            _, writer = await asyncio.open_connection(*sock.getsockname())
            value = await asyncio.wait_for(result, 5)
            writer.close()
            server.close()
            return value

        assert asyncio.run(accepted_nodelay()) == 1
    finally:
        sock.close()


_FAULTS = """
import resource, sys
from service.server import keep_freed_memory
kept = keep_freed_memory(int(sys.argv[1]))
faults = lambda: resource.getrusage(resource.RUSAGE_SELF).ru_minflt
body = bytearray(48 << 20)  # a body's worth of memory, filled and freed
del body
before = faults()
for _ in range(5):
    body = bytearray(48 << 20)
    del body
print(kept, faults() - before)
"""


@pytest.mark.skipif(not sys.platform.startswith("linux") or platform.libc_ver()[0] != "glibc",
                    reason="glibc's malloc only")
def test_freed_memory_is_kept_for_the_next_body() -> None:
    """With keep_freed_memory, a 48 MB buffer freed and allocated again reuses the pages it
    had (no page faults); with glibc's defaults each one is mapped and faulted in anew."""
    counts = {}
    for keep in (0, 256 * 2**20):
        done = subprocess.run([sys.executable, "-c", _FAULTS, str(keep)], cwd=REPO,
                              capture_output=True, text=True, timeout=60, check=True)
        kept, faults = done.stdout.split()
        assert kept == str(bool(keep))
        counts[keep] = int(faults)
    assert counts[256 * 2**20] < 500 < counts[0]
