"""The README's commands really work: its tour runs against a live server."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
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
    assert len(curl) == 4  # the fourth uploads a file: test_geometry_tour
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
    code = blocks("python")[0]
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


@pytest.mark.e2e
def test_geometry_tour(server, tmp_path: Path) -> None:
    """The file upload, glTF and CLI examples, on a small disk saved as scan.ply."""
    import trimesh

    x, y = np.meshgrid(np.linspace(0, 1, 5), np.linspace(0, 1, 5))
    vertices = np.column_stack([x.ravel(), y.ravel(), 0.1 * x.ravel() * y.ravel()])
    faces = [[i * 5 + j, i * 5 + j + 1, i * 5 + j + 6] for i in range(4) for j in range(4)]
    faces += [[i * 5 + j, i * 5 + j + 6, i * 5 + j + 5] for i in range(4) for j in range(4)]
    trimesh.Trimesh(vertices, faces, process=False).export(tmp_path / "scan.ply")

    upload = [b for b in blocks("sh") if "curl" in b][3]
    results = json.loads(_run_sh(upload, server.url, tmp_path))
    assert np.asarray(results["uv"]).shape == (25, 2) and results["flipped_faces"] == 0

    code = blocks("python")[1]
    out = subprocess.run([sys.executable, "-c", _localise(code, server.url)], cwd=tmp_path,
                         capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    assert "(25, 2)" in out.stdout
    assert (tmp_path / "unwrapped.glb").read_bytes()[:4] == b"glTF"

    (tmp_path / "unwrapped.glb").unlink()
    cli = next(b for b in blocks("sh") if "--output unwrapped.glb" in b)
    _run_sh(cli, server.url, tmp_path)
    assert (tmp_path / "unwrapped.glb").read_bytes()[:4] == b"glTF"


def test_every_process_is_in_the_methods_table() -> None:
    """The README's table of methods lists exactly the catalog (diagnostics aside)."""
    from service.catalog import registry

    table = README.read_text().split("## The methods", 1)[1].split("\n## ", 1)[0]
    listed = set(re.findall(r"^\| `([a-z_]+\.[a-z_]+)` \|", table, flags=re.M))
    assert listed == set(registry), (sorted(set(registry) - listed), sorted(listed - set(registry)))


def test_every_setting_is_in_the_settings_table() -> None:
    """The README's table of settings lists exactly the service's settings, each with the
    default the service really has (sizes in MiB)."""
    from service.settings import Settings

    table = README.read_text().split("### Settings", 1)[1].split("\n## ", 1)[0]
    rows = dict(re.findall(r"^\| `MORPHSERVE_([A-Z_]+)` \| ([^|]+) \|", table, flags=re.M))
    assert set(rows) == {name.upper() for name in Settings.model_fields}
    for name, field in Settings.model_fields.items():
        listed, default = rows[name.upper()].strip().strip("`"), field.get_default(
            call_default_factory=True)
        if isinstance(default, bool):
            assert listed == str(default).lower(), name
        elif isinstance(default, int) and listed.endswith("MiB"):
            assert default == int(listed.removesuffix(" MiB")) * 2**20, name
        elif isinstance(default, (int, float)):
            assert float(listed.replace(",", "")) == default, name
