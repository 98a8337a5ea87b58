"""The files the service serves from ``service/static`` are in the repository: a pattern of
``.gitignore`` (``build/``) once kept three.js's ``build/three.module.js`` out of every clone,
and the workbench loaded nothing there while it worked in the tree it was written in."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
STATIC = ROOT / "service" / "static"


def test_no_static_file_is_git_ignored() -> None:
    if shutil.which("git") is None or not (ROOT / ".git").exists():
        pytest.fail("the repository's own checkout (with git) is needed to check .gitignore")
    files = [str(p.relative_to(ROOT)) for p in STATIC.rglob("*") if p.is_file()]
    assert any(f.endswith("three.module.js") for f in files)
    ignored = subprocess.run(["git", "check-ignore", "--no-index", *files], cwd=ROOT,
                             capture_output=True, text=True)
    assert ignored.stdout.split() == [], ignored.stdout
