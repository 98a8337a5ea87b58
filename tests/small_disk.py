"""A small filesystem of its own (a tmpfs), and filling it up, for the tests of a full disk.

Mounting needs root: CI runs as root, and there (or wherever ``MORPHSERVE_REQUIRE_CONTAINERS=1``
asks for every test to run) a tmpfs that cannot be mounted fails the test; elsewhere an
unprivileged user skips it with the reason.
"""

from __future__ import annotations

import contextlib
import errno
import os
import subprocess
from collections.abc import Iterator
from pathlib import Path

import pytest

__all__ = ["small_disk", "fill", "free_bytes"]


def _required() -> bool:
    return os.geteuid() == 0 or os.environ.get("MORPHSERVE_REQUIRE_CONTAINERS") == "1"


@contextlib.contextmanager
def small_disk(where: Path, size: str = "30m") -> Iterator[Path]:
    """A tmpfs of ``size`` mounted at ``where`` (made if missing), unmounted afterwards."""
    if os.geteuid() != 0 and not _required():
        pytest.skip("mounting a tmpfs needs root (CI runs these tests as root)")
    where.mkdir(parents=True, exist_ok=True)
    done = subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={size}", "tmpfs", str(where)],
                          capture_output=True, text=True, check=False)
    if done.returncode != 0:
        pytest.fail(f"could not mount a tmpfs at {where}: {done.stderr.strip()}")
    try:
        yield where
    finally:
        subprocess.run(["umount", "--lazy", str(where)], check=False)


def free_bytes(directory: Path) -> int:
    st = os.statvfs(directory)
    return st.f_bavail * st.f_frsize


def fill(directory: Path, name: str = "filler") -> Path:
    """Write ``directory/name`` until the filesystem refuses a single byte more (ENOSPC);
    blocks of 1 MiB, then of a page, then bytes, so that no room at all is left."""
    path = directory / name
    fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_APPEND, 0o600)
    try:
        for size in (2**20, 4096, 1):
            block = bytes(size)
            while True:  # bounded: the filesystem is finite
                try:
                    os.write(fd, block)
                except OSError as exc:
                    if exc.errno != errno.ENOSPC:
                        raise
                    break
    finally:
        os.close(fd)
    return path
