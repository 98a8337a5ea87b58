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

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
BIN = Path(sys.executable).parent
PATCH = ROOT / "examples" / "meshes" / "patch.ply"


def blocks(lang: str) -> list[str]:
    return re.findall(rf"```{lang}\n(.*?)```", README.read_text(), flags=re.S)


def test_the_two_commands_are_at_the_top() -> None:
    first = blocks("sh")[0]
    assert README.read_text().index(first) < 200
    assert [ln.split("#")[0].strip() for ln in first.splitlines()] == ["make serve", "make test"]


def test_every_block_is_run_by_a_test() -> None:
    """The tour's blocks are the ones the tests below run (the two commands at the top
    aside): a block added to the README needs its test here."""
    assert len(blocks("sh")) == 1 + 4 + 1 + 1 + 1 + 1  # curl x4, CLI, scripts, upload, CLI file
    assert len(blocks("python")) == 2


def test_the_tour_starts_in_the_browser() -> None:
    tour = README.read_text().split("## A five-minute tour", 1)[1]
    first = tour.strip().split("\n\n", 1)[0]
    assert "open <http://127.0.0.1:8000/ui>" in first


def test_the_tour_mesh_ships_with_its_licence() -> None:
    """examples/meshes/patch.ply: small, one mesh with one boundary loop (a disk: V - E + F =
    1), its provenance and licence beside it."""
    import trimesh

    assert PATCH.stat().st_size < 300_000
    mesh = trimesh.load(PATCH, process=False)
    edges = {tuple(sorted(e)) for e in mesh.edges}
    assert len(mesh.vertices) - len(edges) + len(mesh.faces) == 1
    assert len(mesh.outline().entities) == 1
    assert "MIT License" in (PATCH.parent / "LICENSE-pyvista.txt").read_text()
    assert "airplane.ply" in (PATCH.parent / "README.md").read_text()
    if (ROOT / ".git").exists():  # and it is committed: no ignore rule hides it
        ignored = subprocess.run(["git", "check-ignore", "-q", str(PATCH)], cwd=ROOT)
        assert ignored.returncode == 1, "examples/meshes/patch.ply is git-ignored"


def _localise(text: str, url: str) -> str:
    return (text.replace("localhost:8000", url.removeprefix("http://"))
            .replace("http://127.0.0.1:8000", url).replace(".venv/bin/", f"{BIN}/"))


def _with_examples(tmp_path: Path) -> Path:
    """A directory to run the tour in, where ``examples/`` is the repository's."""
    (tmp_path / "examples").symlink_to(ROOT / "examples", target_is_directory=True)
    return tmp_path


def _run_sh(script: str, url: str, cwd: Path) -> str:
    env = {**os.environ, "MORPHSERVE_URL": url}
    out = subprocess.run(["bash", "-euo", "pipefail", "-c", _localise(script, url)], cwd=cwd,
                         env=env, capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, f"{script}\n--- stderr:\n{out.stderr}"
    return out.stdout


@pytest.mark.e2e
def test_curl_tour(server, tmp_path: Path) -> None:
    curl = [b for b in blocks("sh") if "curl" in b]
    assert len(curl) == 5  # the fifth uploads a file: test_geometry_tour
    acceptance = json.loads(_run_sh(curl[0], server.url, tmp_path))
    assert len(acceptance["transform"]) == 4 and acceptance["rmse"] < 1e-12
    # the async block, but for the lines that need a job id from the first one
    script = "\n".join(ln for ln in curl[1].replace("\\\n", " ").splitlines()
                       if "JOB_ID" not in ln)
    head = _run_sh(script, server.url, tmp_path)
    assert "201 Created" in head.splitlines()[0]
    job = re.search(r"^location: \S*/jobs/([0-9a-f-]+)", head, flags=re.I | re.M).group(1)
    for ln in curl[1].splitlines():
        if "JOB_ID" in ln:
            _run_sh(ln.replace("JOB_ID", job), server.url, tmp_path)
    problem = json.loads(_run_sh(curl[2], server.url, tmp_path))
    assert problem["type"] == "/problems/invalid-input"
    assert problem["errors"][0]["input"] == "source"
    # the two mistakes: an input name, then a process id
    text, decoder, found = _run_sh(curl[3], server.url, tmp_path), json.JSONDecoder(), []
    while text.strip():
        document, end = decoder.raw_decode(text.strip())
        found.append(document)
        text = text.strip()[end:]
    typo_input, typo_process = found
    assert typo_input["status"] == 422 and typo_input["errors"][0]["input"] == "max_iter"
    assert typo_input["errors"][0]["message"].startswith(
        "Unknown input `max_iter`; did you mean `max_iterations`? The inputs are `source`, ")
    assert typo_process["status"] == 404
    assert "Did you mean `registration.icp`?" in typo_process["detail"]


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
    # the scripts' block, with the files the block above wrote
    scripts = next(b for b in blocks("sh") if "--json" in b)
    out = _run_sh(scripts, server.url, tmp_path)
    assert out.strip().splitlines()[-1] == "exit status 4"  # no such process
    done = json.loads((tmp_path / "rigid.json").read_text())
    assert done["status"] == "successful"
    np.testing.assert_allclose(done["results"]["translation"], [1, 2, 3], atol=1e-12)


@pytest.mark.e2e
def test_geometry_tour(server, tmp_path: Path) -> None:
    """The file upload, glTF and CLI examples, on the mesh that ships with the repository."""
    import trimesh

    n = len(trimesh.load(PATCH, process=False).vertices)
    tmp_path = _with_examples(tmp_path)
    upload = [b for b in blocks("sh") if "curl" in b][4]
    results = json.loads(_run_sh(upload, server.url, tmp_path))
    uv = np.asarray(results["uv"])
    assert uv.shape == (n, 2) and results["flipped_faces"] == 0
    # a square boundary: every vertex in the square [-1, 1]², some on each of its sides
    assert np.abs(uv).max() <= 1 + 1e-12
    assert np.isclose(uv, -1).any(axis=0).all() and np.isclose(uv, 1).any(axis=0).all()

    code = blocks("python")[1]
    out = subprocess.run([sys.executable, "-c", _localise(code, server.url)], cwd=tmp_path,
                         capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    shape, fit = out.stdout.strip().splitlines()
    assert shape == f"({n}, 2)"
    converged, rmse = fit.split()
    assert converged == "True" and float(rmse) < 1e-6  # the turn undone exactly
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
