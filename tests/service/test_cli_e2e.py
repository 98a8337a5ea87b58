"""The installed ``morphserve`` console script against a live server, as a user runs it."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from tests.live import default_sigint, free_port, wait_for_status

pytestmark = pytest.mark.e2e

MORPHSERVE = Path(sys.executable).with_name("morphserve")
JOB_ID = re.compile(r"^[0-9a-f]{8}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{12}$")


def morphserve(*args: str | Path, url: str | None = None,
               env: dict[str, str] | None = None) -> subprocess.CompletedProcess[str]:
    """Run the console script; ``url`` goes first as ``--url``, when given."""
    base = {k: v for k, v in os.environ.items()
            if k not in ("MORPHSERVE_URL", "MORPHSERVE_API_KEY")}
    argv = [str(MORPHSERVE), *(["--url", url] if url else []), *map(str, args)]
    return subprocess.run(argv, capture_output=True, text=True, timeout=60,
                          env={**base, **(env or {})})


def together(*runs: tuple[Any, ...], url: str | None = None,
             ) -> list[subprocess.CompletedProcess[str]]:
    """Run several independent commands at once (each one mostly imports numpy and httpx)."""
    with ThreadPoolExecutor(max_workers=len(runs)) as pool:
        return list(pool.map(lambda args: morphserve(*args, url=url), runs))


def _ok(done: subprocess.CompletedProcess[str]) -> subprocess.CompletedProcess[str]:
    assert done.returncode == 0, f"exit {done.returncode}\n{done.stdout}\n{done.stderr}"
    return done


@pytest.fixture(scope="module")
def motion() -> tuple[list[list[float]], np.ndarray, np.ndarray, np.ndarray]:
    """Source points (a JSON list), target (an array), and the rotation and translation."""
    rng = np.random.default_rng(42)
    source = rng.normal(size=(30, 3))
    rotation = Rotation.random(random_state=42).as_matrix()
    translation = np.array([1.0, -2.0, 3.5])
    return source.tolist(), source @ rotation.T + translation, rotation, translation


@pytest.fixture
def files(tmp_path: Path, motion) -> tuple[Path, Path]:  # noqa: ANN001
    source, target, _, _ = motion
    a, b = tmp_path / "a.json", tmp_path / "b.npy"
    a.write_text(json.dumps(source), encoding="utf-8")
    np.save(b, target)
    return a, b



def test_processes_and_describe(server) -> None:  # noqa: ANN001
    listed, described, unknown = together(
        ("--url", server.url, "processes"),
        ("describe", "alignment.rigid", "--url", server.url),  # --url after the command too
        ("--url", server.url, "describe", "no.such.process"),
    )
    lines = _ok(listed).stdout.splitlines()
    assert lines[0].split() == ["ID", "TITLE"]
    ids = [line.split()[0] for line in lines[1:]]
    assert "alignment.rigid" in ids and "assignment.nearest" in ids

    out = _ok(described).stdout
    assert out.startswith("alignment.rigid: ")
    _, _, rest = out.partition("\ninputs:\n")
    inputs, _, outputs = rest.partition("\noutputs:\n")
    rows = {line.split()[0]: line.split() for line in inputs.splitlines()[1:]}
    assert set(rows) == {"source", "target", "weights", "allow_reflection"}
    assert rows["source"][1:3] == ["array[array[number]]", "required"]
    assert rows["target"][2] == "required"
    assert rows["allow_reflection"][1:4] == ["boolean", "default", "false"]
    out_names = {line.split()[0] for line in outputs.splitlines()[1:]}
    assert out_names == {"transform", "linear", "rotation", "translation", "scale", "rmse",
                         "reflection"}

    assert unknown.returncode == 4 and unknown.stdout == ""  # not found
    assert unknown.stderr.startswith("error: No such process")


def test_execute_wait_prints_results(server, files, motion) -> None:  # noqa: ANN001
    a, b = files
    _, _, rotation, translation = motion
    done = _ok(morphserve("execute", "alignment.rigid", "--input", f"source={a}",
                          "--input", f"target={b}", "--wait", url=server.url))
    results = json.loads(done.stdout)  # stdout holds the results alone
    np.testing.assert_allclose(results["rotation"], rotation, atol=1e-10)
    np.testing.assert_allclose(results["translation"], translation, atol=1e-10)
    np.testing.assert_allclose(np.array(results["transform"])[:3, :3], rotation, atol=1e-10)
    assert results["reflection"] is False and results["rmse"] < 1e-10
    # the progress bar goes to stderr, and ends at 100%
    assert done.stderr.splitlines()[-1].startswith("[" + "#" * 30 + "] 100%"), done.stderr


def test_execute_param_and_output_file(server, tmp_path: Path) -> None:  # noqa: ANN001
    rng = np.random.default_rng(5)
    source = rng.normal(size=(20, 3))
    mirror = np.diag([-1.0, 1.0, 1.0])  # a reflection: no rotation fits it exactly
    np.save(tmp_path / "s.npy", source)
    np.save(tmp_path / "t.npy", source @ mirror.T + [0.5, 0, 0])
    out = tmp_path / "out.json"
    common = ("execute", "alignment.rigid", "--input", f"source={tmp_path / 's.npy'}",
              "--input", f"target={tmp_path / 't.npy'}", "--wait", "--no-progress")
    proper, mirrored = together(
        (*common, "--param", "allow_reflection=false"),
        (*common, "--param", "allow_reflection=true", "--output", out),
        url=server.url)

    results = json.loads(_ok(proper).stdout)
    assert results["reflection"] is False
    assert np.linalg.det(results["rotation"]) == pytest.approx(1.0, abs=1e-10)
    assert results["rmse"] > 0.1

    assert _ok(mirrored).stdout == ""
    assert mirrored.stderr.strip() == f"results written to {out}"
    results = json.loads(out.read_text(encoding="utf-8"))
    assert results["reflection"] is True
    np.testing.assert_allclose(results["rotation"], mirror, atol=1e-10)
    np.testing.assert_allclose(results["translation"], [0.5, 0, 0], atol=1e-10)
    assert results["rmse"] < 1e-10


def test_job_commands(server, http, tmp_path: Path) -> None:  # noqa: ANN001
    done = _ok(morphserve("execute", "diagnostics.sleep", "--param", "seconds=0.2",
                          "--param", "steps=2", url=server.url))
    job = done.stdout.strip()
    assert JOB_ID.match(job), done.stdout
    assert wait_for_status(http, job, timeout=20)["status"] == "successful"

    out = tmp_path / "r.json"
    status, results, written, listed = together(
        ("status", job), ("results", job), ("results", job, "--output", out),
        ("jobs", "--process", "diagnostics.sleep"), url=server.url)

    fields = dict(line.split(None, 1) for line in _ok(status).stdout.splitlines() if " " in line)
    assert fields["job"] == job and fields["process"] == "diagnostics.sleep"
    assert fields["status"] == "successful" and fields["progress"] == "100%"

    document = json.loads(_ok(results).stdout)
    assert document["steps"] == 2 and document["slept"] >= 0.2
    assert _ok(written).stdout == ""
    assert json.loads(out.read_text(encoding="utf-8")) == document

    lines = _ok(listed).stdout.splitlines()
    assert lines[0].split()[:4] == ["JOB", "PROCESS", "STATUS", "PROGRESS"]
    row = next(line.split() for line in lines[1:] if line.startswith(job))
    assert row[1:4] == ["diagnostics.sleep", "successful", "100%"]
    assert all(line.split()[1] == "diagnostics.sleep" for line in lines[1:])

    # dismissing a finished job removes it
    assert _ok(morphserve("dismiss", job, url=server.url)).stdout.split() == [job, "dismissed"]
    gone = morphserve("status", job, url=server.url)
    assert gone.returncode == 4 and gone.stderr.startswith("error: No such job")


def test_wait_timeout_then_dismiss_the_running_job(server, http) -> None:  # noqa: ANN001
    done = morphserve("execute", "diagnostics.sleep", "--param", "seconds=60",
                      "--param", "steps=6000", "--wait", "--timeout", "0.3", "--no-progress",
                      url=server.url)
    match = re.search(r"Job (\S+) did not end within 0.3 s .* It goes on: "
                      r"'morphserve status \1' follows it", done.stderr)
    assert match, done.stderr
    job = match[1]
    try:
        assert done.returncode == 7 and done.stderr.startswith("error: ")  # timeout
        wait_for_status(http, job, ("running",), timeout=20)  # --timeout left it running
    finally:
        dismissed = morphserve("dismiss", job, url=server.url)
    assert _ok(dismissed).stdout.split() == [job, "dismissed"]
    results = morphserve("results", job, url=server.url)
    assert results.returncode == 6 and results.stderr.startswith("error: Job dismissed")


def test_invalid_input(server, files, tmp_path: Path) -> None:  # noqa: ANN001
    a, _ = files
    np.save(tmp_path / "short.npy", np.zeros((3, 3)))
    done = morphserve("execute", "alignment.rigid", "--input", f"source={a}",
                      "--input", f"target={tmp_path / 'short.npy'}", "--wait", url=server.url)
    assert done.returncode == 3 and done.stdout == ""  # invalid input
    assert done.stderr.startswith("error: Invalid input")
    assert "\n  target: " in done.stderr  # the field, on a line of its own


@pytest.mark.parametrize("bad", ["nan.json", "strings.npy"])
def test_unsendable_input_is_an_error_not_a_traceback(
    server, files, tmp_path: Path, bad: str  # noqa: ANN001
) -> None:
    _, b = files
    path = tmp_path / bad
    if bad.endswith(".json"):  # json.load reads NaN; an .npy holding NaN fails the same way
        path.write_text("[[NaN, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]", encoding="utf-8")
    else:
        np.save(path, np.array([["a", "b", "c"]] * 4))
    done = morphserve("execute", "alignment.rigid", "--input", f"source={path}",
                      "--input", f"target={b}", "--wait", url=server.url)
    assert "Traceback" not in done.stderr, done.stderr
    assert done.returncode == 3 and done.stderr.startswith("error: Invalid input")
    assert "\n  source: " in done.stderr


def test_usage_errors_exit_2(server) -> None:  # noqa: ANN001
    unknown, no_wait = together(
        ("frobnicate",),
        ("execute", "alignment.rigid", "--output", "out.json"),  # --output needs --wait
        url=server.url)
    for done in (unknown, no_wait):
        assert done.returncode == 2, (done.returncode, done.stderr)
        assert done.stdout == ""
        assert "usage: morphserve" in done.stderr and "error:" in done.stderr
    assert "invalid choice: 'frobnicate'" in unknown.stderr
    assert "--timeout and --output need --wait" in no_wait.stderr


def test_closed_port() -> None:
    url = f"http://127.0.0.1:{free_port()}"
    done = morphserve("processes", url=url)
    assert done.returncode == 5 and done.stdout == ""  # unreachable
    assert done.stderr.startswith(f"error: cannot reach {url}: ")
    assert "Connect" in done.stderr
    assert "Traceback" not in done.stderr and len(done.stderr.splitlines()) == 1


def test_execute_mesh_file_to_glb(server, tmp_path: Path) -> None:  # noqa: ANN001
    import trimesh

    x, y = np.meshgrid(np.linspace(0, 1, 4), np.linspace(0, 1, 4))
    vertices = np.column_stack([x.ravel(), y.ravel(), 0.1 * x.ravel() ** 2])
    faces = [[i * 4 + j, i * 4 + j + 1, i * 4 + j + 5] for i in range(3) for j in range(3)]
    faces += [[i * 4 + j, i * 4 + j + 5, i * 4 + j + 4] for i in range(3) for j in range(3)]
    trimesh.Trimesh(vertices, faces, process=False).export(tmp_path / "scan.ply")
    out = tmp_path / "result.glb"
    done = _ok(morphserve("execute", "parameterization.tutte", "--input",
                          f"mesh={tmp_path / 'scan.ply'}", "--wait", "--no-progress",
                          "--output", out, url=server.url))
    assert done.stderr.strip().endswith(f"results written to {out}")
    scene = trimesh.load(out, file_type="glb", process=False)
    mesh = next(iter(scene.geometry.values()))
    np.testing.assert_allclose(mesh.vertices, vertices, atol=1e-6)  # float32 in glTF
    np.testing.assert_array_equal(mesh.faces, faces)
    assert mesh.visual.uv.shape == (16, 2)  # TEXCOORD_0
    # several arrays cannot go in one .npy: a usage error, not a traceback
    npy = morphserve("execute", "parameterization.tutte", "--input",
                     f"mesh={tmp_path / 'scan.ply'}", "--wait", "--no-progress",
                     "--output", tmp_path / "r.npy", url=server.url)
    assert npy.returncode == 2 and "Name the output" in npy.stderr, npy.stderr
    missing = morphserve("execute", "parameterization.tutte", "--input",
                         f"mesh={tmp_path / 'nope.ply'}", "--wait", url=server.url)
    assert missing.returncode == 2 and "no such file" in missing.stderr


# -- scripts: --json, exit statuses, Ctrl-C, geometry files ------------------------------


def test_json_output_for_scripts(server, files, motion) -> None:  # noqa: ANN001
    a, b = files
    _, _, rotation, _ = motion
    listed, described, started, waited = together(
        ("processes", "--json"), ("describe", "alignment.rigid", "--json"),
        ("execute", "diagnostics.sleep", "--param", "seconds=0.1", "--param", "steps=1",
         "--json"),
        ("execute", "alignment.rigid", "--input", f"source={a}", "--input", f"target={b}",
         "--wait", "--no-progress", "--json"),
        url=server.url)
    ids = [p["id"] for p in json.loads(_ok(listed).stdout)]
    assert "alignment.rigid" in ids and "registration.icp" in ids
    description = json.loads(_ok(described).stdout)
    assert description["id"] == "alignment.rigid"
    assert set(description["inputs"]) == {"source", "target", "weights", "allow_reflection"}
    job = json.loads(_ok(started).stdout)
    assert JOB_ID.match(job["jobID"]) and job["status"] in ("accepted", "running", "successful")
    done = json.loads(_ok(waited).stdout)
    assert done["status"] == "successful" and JOB_ID.match(done["jobID"])
    np.testing.assert_allclose(done["results"]["rotation"], rotation, atol=1e-10)

    status, jobs = together(("status", job["jobID"], "--json"),
                            ("jobs", "--process", "diagnostics.sleep", "--json"),
                            url=server.url)
    assert json.loads(_ok(status).stdout)["jobID"] == job["jobID"]
    listed_jobs = json.loads(_ok(jobs).stdout)
    assert job["jobID"] in [j["jobID"] for j in listed_jobs]
    assert {j["processID"] for j in listed_jobs} == {"diagnostics.sleep"}


def test_mistakes_get_their_exit_status_and_a_suggestion(server, files) -> None:  # noqa: ANN001
    a, b = files
    patch = Path(__file__).resolve().parents[2] / "examples" / "meshes" / "patch.ply"
    typo_process, typo_part, typo_input, failed = together(
        ("describe", "registration.icpp"),
        ("execute", "parameterization.tutte", "--input", f"mseh={patch}", "--wait"),
        ("execute", "registration.icp", "--input", f"source={a}", "--input", f"target={b}",
         "--param", "max_iter=5", "--wait"),
        ("execute", "diagnostics.sleep", "--param", "seconds=60", "--param", "steps=6000",
         "--time-limit", "0.5", "--wait", "--no-progress"),
        url=server.url)
    assert typo_process.returncode == 4, typo_process.stderr
    assert "Did you mean `registration.icp`?" in typo_process.stderr
    assert typo_input.returncode == 3, typo_input.stderr
    assert "  max_iter: Unknown input `max_iter`; did you mean `max_iterations`?" in \
        typo_input.stderr
    assert typo_part.returncode == 3, typo_part.stderr  # a file sent as an unknown input
    assert "  mseh: Unknown input `mseh`; did you mean `mesh`?" in typo_part.stderr
    assert failed.returncode == 6, failed.stderr  # the job ran out of time: it failed
    assert failed.stderr.startswith("error: ") and "Traceback" not in failed.stderr


def _wait_for(path: Path, text: str, timeout: float = 30.0) -> None:
    import time

    deadline = time.monotonic() + timeout
    while text not in path.read_text(encoding="utf-8", errors="replace"):
        assert time.monotonic() < deadline, path.read_text(encoding="utf-8", errors="replace")
        time.sleep(0.05)


def test_ctrl_c_while_waiting_leaves_the_job_running(server, http, tmp_path: Path) -> None:  # noqa: ANN001
    """Ctrl-C (SIGINT to the command's process group, as a terminal sends it) ends
    ``execute --wait`` with status 130, a line saying the job goes on, no traceback."""
    import signal

    err = tmp_path / "stderr"
    with open(err, "w") as stderr:
        proc = subprocess.Popen(
            [str(MORPHSERVE), "--url", server.url, "execute", "diagnostics.sleep", "--param",
             "seconds=60", "--param", "steps=6000", "--wait"],
            stdout=subprocess.PIPE, stderr=stderr, text=True, start_new_session=True,
            preexec_fn=default_sigint,
            env={k: v for k, v in os.environ.items() if k != "MORPHSERVE_API_KEY"})
    try:
        _wait_for(err, "%")  # the progress bar is up: the command is waiting
        os.killpg(proc.pid, signal.SIGINT)
        out, _ = proc.communicate(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
    text = err.read_text(encoding="utf-8")
    match = re.search(r"interrupted; job (\S+) goes on \(morphserve dismiss \1 stops it\)", text)
    assert proc.returncode == 130 and out == "" and match, text
    assert "Traceback" not in text and "KeyboardInterrupt" not in text
    try:
        assert wait_for_status(http, match[1], ("running",), timeout=20)["status"] == "running"
    finally:
        _ok(morphserve("dismiss", match[1], url=server.url))


def test_ctrl_c_stops_the_service_cleanly(tmp_path: Path) -> None:
    """Ctrl-C to ``morphserve serve`` (the whole process group: the service and its Dask
    workers) shuts it down with no traceback from any process."""
    import signal

    from tests.live import LiveServer

    srv = LiveServer(tmp_path / "data").start()
    assert srv.proc is not None
    os.killpg(srv.proc.pid, signal.SIGINT)
    try:
        code = srv.proc.wait(timeout=60)
    finally:
        if srv.proc.poll() is None:
            srv.kill()
    log = srv.log.read_text(encoding="utf-8", errors="replace")
    assert "Application shutdown complete" in log, log
    assert "Traceback" not in log and "KeyboardInterrupt" not in log, log
    assert code == 130, log


@pytest.mark.parametrize("suffix", [".ply", ".obj", ".off", ".stl", ".glb"])
def test_execute_takes_each_geometry_file(server, tmp_path: Path, suffix: str) -> None:  # noqa: ANN001
    """The mesh files the SDK uploads, from the command line: a disk of 16 vertices is
    unwrapped with every vertex inside the unit circle and no face flipped."""
    import trimesh

    x, y = np.meshgrid(np.linspace(0, 1, 4), np.linspace(0, 1, 4))
    vertices = np.column_stack([x.ravel(), y.ravel(), 0.1 * x.ravel() ** 2])
    faces = [[i * 4 + j, i * 4 + j + 1, i * 4 + j + 5] for i in range(3) for j in range(3)]
    faces += [[i * 4 + j, i * 4 + j + 5, i * 4 + j + 4] for i in range(3) for j in range(3)]
    path = tmp_path / f"disk{suffix}"
    trimesh.Trimesh(vertices, faces, process=False).export(path)
    done = _ok(morphserve("execute", "parameterization.tutte", "--input", f"mesh={path}",
                          "--wait", "--no-progress", "--json", url=server.url))
    results = json.loads(done.stdout)["results"]
    uv = np.asarray(results["uv"])
    assert uv.shape == (16, 2) and results["flipped_faces"] == 0
    assert np.all(np.linalg.norm(uv, axis=1) <= 1 + 1e-9)
