"""The README's commands really work: its tour runs against a live server."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

README = Path(__file__).resolve().parents[1] / "README.md"
BIN = Path(sys.executable).parent


def blocks(lang: str) -> list[str]:
    return re.findall(rf"```{lang}\n(.*?)```", README.read_text(), flags=re.S)


def test_the_two_commands_are_at_the_top() -> None:
    first = blocks("sh")[0]
    assert README.read_text().index(first) < 200
    assert "make serve" in first and "make test" in first


def _localise(text: str, url: str) -> str:
    return (text.replace("localhost:8000", url.removeprefix("http://"))
            .replace("http://127.0.0.1:8000", url).replace(".venv/bin/", f"{BIN}/"))


def _run_sh(script: str, url: str, cwd: Path) -> str:
    env = {**os.environ, "MORPHSERVE_URL": url}
    out = subprocess.run(["bash", "-euo", "pipefail", "-c", _localise(script, url)], cwd=cwd,
                         env=env, capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, f"{script}\n--- stderr:\n{out.stderr}"
    return out.stdout


@pytest.mark.e2e
def test_curl_tour(server, tmp_path: Path) -> None:
    curl = [b for b in blocks("sh") if "curl" in b]
    assert len(curl) == 3
    acceptance = json.loads(_run_sh(curl[0], server.url, tmp_path))
    assert len(acceptance["transform"]) == 4 and acceptance["rmse"] < 1e-12
    # the async block, but for the lines that need a job id from the first one
    script = "\n".join(ln for ln in curl[1].replace("\\\n", " ").splitlines()
                       if "JOB_ID" not in ln)
    head = _run_sh(script, server.url, tmp_path)
    assert "201 Created" in head.splitlines()[0] and "location: /jobs/" in head.lower()
    job = re.search(r"location: /jobs/([0-9a-f-]+)", head, flags=re.I).group(1)
    for ln in curl[1].splitlines():
        if "JOB_ID" in ln:
            _run_sh(ln.replace("JOB_ID", job), server.url, tmp_path)
    problem = json.loads(_run_sh(curl[2], server.url, tmp_path))
    assert problem["type"] == "/problems/invalid-input"
    assert problem["errors"][0]["input"] == "source"


@pytest.mark.e2e
def test_python_tour(server, tmp_path: Path) -> None:
    (code,) = blocks("python")
    out = subprocess.run([sys.executable, "-c", _localise(code, server.url)], cwd=tmp_path,
                         capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    assert "alignment.rigid" in out.stdout
    assert "[1. 2. 3.]" in out.stdout.replace("  ", " ")
    assert "100%" in out.stderr  # the progress bar finished


@pytest.mark.e2e
def test_cli_tour(server, tmp_path: Path) -> None:
    cli = next(b for b in blocks("sh") if "morphserve processes" in b)
    out = _run_sh(cli, server.url, tmp_path)
    assert "alignment.rigid" in out and "assignment.nearest" in out
    assert '"rotation"' in out and '"rmse"' in out


def test_every_process_is_in_the_methods_table() -> None:
    """The README's table of methods lists exactly the catalog (diagnostics aside)."""
    from service.catalog import registry

    table = README.read_text().split("## The methods", 1)[1].split("\n## ", 1)[0]
    listed = set(re.findall(r"^\| `([a-z_]+\.[a-z_]+)` \|", table, flags=re.M))
    assert listed == set(registry), (sorted(set(registry) - listed), sorted(listed - set(registry)))
