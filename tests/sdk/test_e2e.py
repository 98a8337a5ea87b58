"""The SDK (``Client`` and ``AsyncClient``) against a live server: uvicorn + a Dask cluster.

The unit tests beside this file play the service with an ``httpx.MockTransport``; these run the
real thing, so they catch any drift between the SDK and what the service actually answers.
"""

from __future__ import annotations

import asyncio
import re
import time
from collections.abc import Iterator
from typing import TYPE_CHECKING

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from morphserve import (
    AsyncClient,
    AsyncJob,
    Client,
    InvalidInput,
    Job,
    JobDismissed,
    JobStatus,
    MorphserveError,
    NoSuchJob,
    NoSuchProcess,
    ProcessDescription,
    ResultNotReady,
    Results,
    TimeLimitExceeded,
    TransportError,
    WaitTimeout,
)
from tests.live import free_port

pytestmark = pytest.mark.e2e

#: A sleep long enough never to end during a test, in slices short enough (0.01 s) that a
#: dismissal stops it at once and frees its worker for the other tests.
LONG_SLEEP = {"seconds": 60, "steps": 6000}

if TYPE_CHECKING:
    import trimesh


@pytest.fixture
def client(server) -> Iterator[Client]:  # noqa: ANN001
    with Client(server.url, timeout=30) as c:
        yield c


def _random_pair(seed: int, n: int = 50) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Source points, target = R source + t, and the rotation R and translation t."""
    rng = np.random.default_rng(seed)
    source = rng.normal(size=(n, 3))
    rotation = Rotation.random(random_state=seed).as_matrix()
    translation = rng.normal(size=3) * 10
    return source, source @ rotation.T + translation, rotation, translation


def _assert_alignment(results: Results, rotation: np.ndarray, translation: np.ndarray,
                      atol: float = 1e-10) -> None:
    for name in ("transform", "linear", "rotation", "translation"):
        assert isinstance(results[name], np.ndarray), (name, type(results[name]))
        assert results[name].dtype == np.float64
    assert results["transform"].shape == (4, 4)
    np.testing.assert_allclose(results["rotation"], rotation, atol=atol)
    np.testing.assert_allclose(results["linear"], rotation, atol=atol)
    np.testing.assert_allclose(results["translation"], translation, atol=atol)
    np.testing.assert_allclose(results["transform"][:3, :3], rotation, atol=atol)
    np.testing.assert_allclose(results["transform"][:3, 3], translation, atol=atol)
    np.testing.assert_array_equal(results["transform"][3], [0, 0, 0, 1])
    assert results["reflection"] is False
    assert results["scale"] == 1.0
    assert isinstance(results["rmse"], float) and results["rmse"] < atol


# -- catalog -----------------------------------------------------------------------------


def test_processes_lists_the_catalog(client: Client) -> None:
    processes = {p.id: p for p in client.processes()}
    assert {"alignment.rigid", "assignment.nearest"} <= set(processes)
    rigid = processes["alignment.rigid"]
    assert rigid.title and rigid.version
    assert {"sync-execute", "async-execute", "dismiss"} <= set(rigid.job_control_options)


def test_describe_gives_inputs_with_schemas(client: Client) -> None:
    rigid = client.describe("alignment.rigid")
    assert isinstance(rigid, ProcessDescription) and rigid.id == "alignment.rigid"
    assert set(rigid.inputs) == {"source", "target", "weights", "allow_reflection"}
    for spec in rigid.inputs.values():
        assert isinstance(spec["schema"], dict), spec
    assert rigid.inputs["source"]["schema"]["type"] == "array"
    assert rigid.inputs["source"]["minOccurs"] == 1
    assert rigid.inputs["allow_reflection"]["schema"]["type"] == "boolean"
    assert rigid.inputs["allow_reflection"]["schema"]["default"] is False
    assert rigid.inputs["allow_reflection"]["minOccurs"] == 0
    assert {"transform", "linear", "rotation", "translation", "scale", "rmse",
            "reflection"} == set(rigid.outputs)
    assert rigid.raw["id"] == "alignment.rigid"

    nearest = client.describe("assignment.nearest")
    assert {"source", "target", "k", "direction", "max_distance"} <= set(nearest.inputs)
    assert {"pairs", "distances", "rmse", "n_pairs"} <= set(nearest.outputs)


def test_unknown_process(client: Client) -> None:
    with pytest.raises(NoSuchProcess) as caught:
        client.describe("no.such.process")
    assert caught.value.status == 404
    with pytest.raises(NoSuchProcess):
        client.execute("no.such.process", source=[[0, 0]])


# -- execution ---------------------------------------------------------------------------


def test_execute_with_wait_recovers_a_random_rigid_motion(client: Client) -> None:
    source, target, rotation, translation = _random_pair(seed=7)
    job = client.execute("alignment.rigid", source=source, target=target, wait=10)
    assert isinstance(job, Job) and job.process_id == "alignment.rigid"
    results = job.results()
    assert results is job.results()  # answered with the 200: kept, not fetched again
    _assert_alignment(results, rotation, translation)
    # the synchronous job is a job like any other: it can be looked up and waited for
    assert client.job(job.id).status().status == "successful"
    assert job.wait(timeout=10).status == "successful"


def test_execute_without_wait_gives_a_job_to_wait_for(client: Client) -> None:
    source, target, rotation, translation = _random_pair(seed=8)
    job = client.execute("alignment.rigid", source=source, target=target)
    assert isinstance(job, Job) and job.id
    assert job.submitted_status is not None
    assert job.submitted_status.job_id == job.id
    assert job.submitted_status.status in ("accepted", "running", "successful")
    status = job.wait(timeout=20)
    assert isinstance(status, JobStatus)
    assert status.status == "successful" and status.done and status.progress == 100
    assert status.created <= status.started <= status.finished
    _assert_alignment(job.results(), rotation, translation)
    # a fresh handle on the same job fetches the same results
    again = client.job(job.id)
    assert again == job and again.process_id == "alignment.rigid"
    _assert_alignment(again.results(), rotation, translation)


def test_outputs_subset(client: Client) -> None:
    source, target, rotation, _ = _random_pair(seed=9)
    job = client.execute("alignment.rigid", source=source, target=target,
                         outputs=["rotation", "rmse"], wait=10)
    results = job.results()
    assert set(results) == {"rotation", "rmse"}
    np.testing.assert_allclose(results["rotation"], rotation, atol=1e-10)


def test_float32_input_is_accepted(client: Client) -> None:
    source, target, rotation, translation = _random_pair(seed=10)
    job = client.execute("alignment.rigid", source=source.astype(np.float32),
                         target=target.astype(np.float32), wait=10)
    results = job.results()
    np.testing.assert_allclose(results["rotation"], rotation, atol=1e-5)
    np.testing.assert_allclose(results["translation"], translation, atol=1e-4)
    # float32 values travel exactly: against a target computed from them in float64, the
    # motion is recovered to float64 precision
    exact = source.astype(np.float32).astype(np.float64)
    job = client.execute("alignment.rigid", source=source.astype(np.float32),
                         target=exact @ rotation.T + translation, wait=10)
    _assert_alignment(job.results(), rotation, translation)


def test_nearest_assignment(client: Client) -> None:
    job = client.execute("assignment.nearest", source=np.array([[0.0, 0.0], [1.0, 0.0],
                                                                [2.0, 0.1]]),
                         target=np.array([[0.1, 0.0], [2.0, 0.0]]), wait=10)
    results = job.results()
    # by hand: 0 -> 0 (0.1), 1 -> 0 (0.9), 2 -> 1 (0.1)
    assert results["pairs"].dtype.kind == "i"
    np.testing.assert_array_equal(results["pairs"], [[0, 0], [1, 0], [2, 1]])
    np.testing.assert_allclose(results["distances"], [0.1, 0.9, 0.1], atol=1e-12)
    assert results["n_pairs"] == 3


def test_empty_assignment_pairs_keep_their_shape(client: Client) -> None:
    # the SDK asks for arrays as typed binary arrays (Prefer: arrays=binary): an empty one
    # keeps its shape and dtype, which a JSON [] cannot carry
    for job in (client.execute("assignment.nearest", source=[[0.0, 0.0]],
                               target=[[5.0, 5.0]], max_distance=0.1, wait=10),
                client.execute("assignment.nearest", source=[[0.0, 0.0]],
                               target=[[5.0, 5.0]], max_distance=0.1)):
        job.wait(timeout=20)
        results = job.results()
        assert results["n_pairs"] == 0
        assert results["pairs"].shape == (0, 2) and results["pairs"].dtype.kind == "i"
        points = np.zeros((1, 2))
        assert points[results["pairs"][:, 0]].shape == (0, 2)  # as for any non-empty answer


def _disk() -> trimesh.Trimesh:
    import trimesh

    x, y = np.meshgrid(np.linspace(0, 1, 5), np.linspace(0, 1, 5))
    v = np.column_stack([x.ravel(), y.ravel(), 0.1 * x.ravel() * y.ravel()])
    f = [[i * 5 + j, i * 5 + j + 1, i * 5 + j + 6] for i in range(4) for j in range(4)] + \
        [[i * 5 + j, i * 5 + j + 6, i * 5 + j + 5] for i in range(4) for j in range(4)]
    return trimesh.Trimesh(v, np.array(f), process=False)


def test_files_and_trimesh_objects_as_inputs(client: Client, tmp_path) -> None:  # noqa: ANN001
    import trimesh

    mesh = _disk()
    by_arrays = client.execute("parameterization.tutte", mesh={
        "vertices": mesh.vertices, "faces": mesh.faces}, wait=30).results()
    by_trimesh = client.execute("parameterization.tutte", mesh=mesh, wait=30).results()
    np.testing.assert_array_equal(by_trimesh["uv"], by_arrays["uv"])
    for suffix in (".ply", ".obj", ".off", ".glb"):
        path = tmp_path / f"disk{suffix}"
        mesh.export(path)
        for given in (path, str(path)):
            uploaded = client.execute("parameterization.tutte", mesh=given, wait=30).results()
            np.testing.assert_allclose(uploaded["uv"], by_arrays["uv"], atol=1e-6)
    np.save(tmp_path / "points.npy", mesh.vertices)
    pca = client.execute("embedding.pca", points=tmp_path / "points.npy", n_components=2,
                         wait=30).results()
    assert pca["embedding"].shape == (25, 2)
    cloud = client.execute("embedding.pca", points=trimesh.PointCloud(mesh.vertices),
                           n_components=2, wait=30).results()
    np.testing.assert_array_equal(cloud["embedding"], pca["embedding"])


def test_large_arrays_travel_as_npy_parts(client: Client) -> None:
    """Arrays of 1 MiB and more go as .npy parts of a multipart request (inputs and members
    of a mesh); the service gets them bit-exact: the results equal those of the same job
    sent as typed binary arrays, and the in-process method's."""
    from algorithms.alignment import rigid
    from algorithms.parameterization import tutte
    from morphserve._models import NPY_ABOVE, split_npy_parts

    rng = np.random.default_rng(5)
    X = rng.normal(size=(NPY_ABOVE // 24 + 10, 3))
    Y = X @ Rotation.from_euler("z", 30, degrees=True).as_matrix().T + 1.0
    rest, parts = split_npy_parts({"source": X, "target": Y[:10], "allow_reflection": False})
    assert list(parts) == ["source"] and set(rest) == {"target", "allow_reflection"}
    big = client.execute("alignment.rigid", source=X, target=Y, wait=30).results()
    mine = rigid(X, Y)
    np.testing.assert_array_equal(big["rotation"], mine.rotation)
    np.testing.assert_array_equal(big["translation"], mine.translation)

    n = 220  # a grid mesh of 48,400 vertices: its vertices (1.2 MB) go as mesh.vertices
    u, v = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n))
    verts = np.column_stack([u.ravel(), v.ravel(), 0.1 * np.sin(3 * u.ravel())])
    idx = np.arange(n * n).reshape(n, n)
    a, b = idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel()
    c, d = idx[1:, 1:].ravel(), idx[1:, :-1].ravel()
    faces = np.concatenate([np.column_stack([a, b, c]), np.column_stack([a, c, d])])
    _, parts = split_npy_parts({"mesh": {"vertices": verts, "faces": faces}})
    assert set(parts) == {"mesh.vertices", "mesh.faces"}
    uv = client.execute("parameterization.tutte", mesh={"vertices": verts, "faces": faces},
                        wait=60).results()["uv"]
    np.testing.assert_allclose(uv, tutte({"vertices": verts, "faces": faces}).uv, atol=1e-12)


def test_results_save_and_to_trimesh(client: Client, tmp_path) -> None:  # noqa: ANN001
    import trimesh

    mesh = _disk()
    job = client.execute("parameterization.tutte", mesh=mesh, wait=30)
    results = job.results()
    glb = results.save(tmp_path / "out.glb")
    scene = trimesh.load(glb, file_type="glb", process=False)
    loaded = next(iter(scene.geometry.values()))
    np.testing.assert_allclose(loaded.vertices, mesh.vertices, atol=1e-6)  # float32 in glTF
    np.testing.assert_array_equal(loaded.faces, mesh.faces)
    uv = results.to_trimesh().visual.uv
    np.testing.assert_array_equal(uv, results["uv"])
    results.save(tmp_path / "uv.npy", output="uv")
    np.testing.assert_array_equal(np.load(tmp_path / "uv.npy"), results["uv"])
    results.save(tmp_path / "out.json")
    import json

    assert json.loads((tmp_path / "out.json").read_text())["flipped_faces"] == 0
    with pytest.raises(ValueError, match="Name the output"):
        results.save(tmp_path / "x.npy")
    with pytest.raises(ValueError, match=r"\.glb, \.ply, \.obj, \.stl, \.off, \.npy or \.json"):
        results.save(tmp_path / "x.png")
    distance = client.execute("assignment.distance", source=[[0.0, 0.0]], target=[[1.0, 1.0]],
                              wait=10)
    from morphserve import NotAcceptable

    with pytest.raises(NotAcceptable):
        distance.save(tmp_path / "none.glb")


# -- waiting, progress, dismissal --------------------------------------------------------


def test_wait_with_progress_draws_a_bar_to_100(client: Client,
                                               capsys: pytest.CaptureFixture[str]) -> None:
    job = client.execute("diagnostics.sleep", seconds=0.6, steps=6)
    status = job.wait(timeout=20, progress=True)
    assert status.status == "successful"
    out, err = capsys.readouterr()
    assert out == ""
    lines = err.splitlines()
    assert lines, "no progress bar on stderr"
    percents = []
    for line in lines:
        match = re.match(r"\[([#-]{30})\] +(\d+)%", line)
        assert match, line
        percents.append(int(match[2]))
    assert percents == sorted(percents), lines
    assert percents[-1] == 100 and lines[-1].startswith("[" + "#" * 30 + "]"), lines
    assert len(set(percents)) >= 2, lines  # it moved while the job ran


def _until_running(job: Job, timeout: float = 20) -> None:
    deadline = time.monotonic() + timeout
    while (status := job.status()).status == "accepted":
        assert time.monotonic() < deadline, f"job {job.id} still accepted after {timeout} s"
        time.sleep(0.05)
    assert status.status == "running", status


def test_dismiss_a_running_job(client: Client) -> None:
    job = client.execute("diagnostics.sleep", **LONG_SLEEP)
    try:
        _until_running(job)
    finally:
        status = job.dismiss()
    assert status.job_id == job.id and status.status == "dismissed"
    assert job.status().status == "dismissed"
    with pytest.raises(JobDismissed) as caught:
        job.wait(timeout=10)
    assert caught.value.status == 410
    with pytest.raises(JobDismissed):
        job.results()


def test_wait_timeout_leaves_the_job_running(client: Client) -> None:
    job = client.execute("diagnostics.sleep", **LONG_SLEEP)
    try:
        with pytest.raises(WaitTimeout) as caught:
            job.wait(timeout=0.3)
        error = caught.value
        assert isinstance(error, TimeoutError) and isinstance(error, MorphserveError)
        assert error.job_id == job.id and error.timeout == 0.3
        assert error.status is not None and error.status.status in ("accepted", "running")
        assert job.status().status in ("accepted", "running")
        with pytest.raises(ResultNotReady):
            job.results()
    finally:
        assert job.dismiss().status == "dismissed"


def test_time_limit_exceeded(client: Client, http) -> None:  # noqa: ANN001
    """A job that runs out of time raises TimeLimitExceeded from ``wait``.

    ``Client.execute`` has no way to send ``timeLimit`` (every keyword is an input), so the
    job is created over HTTP and then followed with the SDK.
    """
    r = http.post("/processes/diagnostics.sleep/execution",
                  headers={"Prefer": "respond-async"},
                  json={"inputs": LONG_SLEEP, "timeLimit": 0.5})
    assert r.status_code == 201, r.text
    job = client.job(r.json()["jobID"])
    with pytest.raises(TimeLimitExceeded) as caught:
        job.wait(timeout=20)
    assert caught.value.type.endswith("/time-limit-exceeded")
    assert job.status().status == "failed"


def test_time_limit_through_execute(client: Client) -> None:
    job = client.execute("diagnostics.sleep", seconds=30, steps=3000, time_limit=1)
    with pytest.raises(TimeLimitExceeded) as caught:
        job.wait(timeout=20)
    assert "time limit of 1 s exceeded" in caught.value.detail


# -- errors ------------------------------------------------------------------------------


def test_invalid_input_names_the_field(client: Client) -> None:
    with pytest.raises(InvalidInput) as caught:
        client.execute("alignment.rigid", source=np.zeros((4, 3)), target=np.zeros((5, 3)))
    error = caught.value
    assert error.status == 422 and isinstance(error, ValueError)
    assert error.errors[0]["input"] == "target", error.errors
    assert "target" in str(error)

    with pytest.raises(InvalidInput) as caught:
        client.execute("alignment.rigid", source=np.zeros((4, 3)), target=np.zeros((4, 2)),
                       wait=10)
    assert caught.value.errors[0]["input"] == "target"

    with pytest.raises(InvalidInput) as caught:
        client.execute("alignment.rigid", target=np.zeros((4, 3)))
    assert caught.value.errors[0]["input"] == "source"

    with pytest.raises(InvalidInput) as caught:
        client.execute("diagnostics.sleep", seconds=-1)
    assert caught.value.errors[0]["input"] == "seconds"


def test_nan_input_is_invalid_input_naming_the_row(client: Client) -> None:
    """The SDK sends NaN/Infinity as Python's json writes them; the service names the row."""
    source = np.eye(4, 3)
    source[1, 2] = np.nan
    with pytest.raises(InvalidInput) as caught:
        client.execute("alignment.rigid", source=source, target=np.eye(4, 3))
    assert caught.value.errors[0]["input"] == "source"
    assert "row 1" in caught.value.errors[0]["message"]
    with pytest.raises(InvalidInput) as caught:
        client.execute("alignment.rigid", source=np.eye(4, 3).tolist(),
                       target=[[0.0, float("inf"), 0.0]] * 4)
    assert caught.value.errors[0]["input"] == "target"


def test_unknown_job(client: Client) -> None:
    with pytest.raises(NoSuchJob) as caught:
        client.job("nope")
    assert caught.value.status == 404


def test_unreachable_service() -> None:
    with Client(f"http://127.0.0.1:{free_port()}", timeout=5) as client, \
            pytest.raises(TransportError) as caught:
        client.processes()
    assert isinstance(caught.value.__cause__, Exception)


# -- listing -----------------------------------------------------------------------------


def test_jobs_filtered_by_process(client: Client) -> None:
    job = client.execute("diagnostics.sleep", seconds=0.1, steps=1)
    job.wait(timeout=20)
    listed = client.jobs(process="diagnostics.sleep")
    assert job.id in [j.job_id for j in listed]
    assert all(j.process_id == "diagnostics.sleep" for j in listed)
    done = client.jobs(process="diagnostics.sleep", status="successful")
    assert job.id in [j.job_id for j in done]
    assert all(j.status == "successful" for j in done)
    assert job.id not in [j.job_id for j in client.jobs(process="alignment.rigid")]
    assert len(client.jobs(process="diagnostics.sleep", limit=1)) == 1


# -- the async client --------------------------------------------------------------------


def test_async_client_end_to_end(server) -> None:  # noqa: ANN001
    async def scenario() -> None:
        async with AsyncClient(server.url, timeout=30) as client:
            ids = {p.id for p in await client.processes()}
            assert {"alignment.rigid", "assignment.nearest"} <= ids
            described = await client.describe("alignment.rigid")
            assert described.inputs["source"]["schema"]["type"] == "array"

            # several jobs at once, some answered within the wait, some followed by polling
            pairs = [_random_pair(seed) for seed in (21, 22, 23)]
            jobs = await asyncio.gather(
                *(client.execute("alignment.rigid", source=s, target=t, wait=10)
                  for s, t, _, _ in pairs),
                *(client.execute("alignment.rigid", source=s.astype(np.float32),
                                 target=t) for s, t, _, _ in pairs),
            )
            assert all(isinstance(job, AsyncJob) for job in jobs)
            assert len({job.id for job in jobs}) == 6
            statuses = await asyncio.gather(*(job.wait(timeout=20) for job in jobs))
            assert all(s.status == "successful" for s in statuses)
            for job, (_, _, rotation, translation) in zip(jobs[:3], pairs, strict=True):
                _assert_alignment(await job.results(), rotation, translation)
            for job, (_, _, rotation, _) in zip(jobs[3:], pairs, strict=True):
                np.testing.assert_allclose((await job.results())["rotation"], rotation,
                                           atol=1e-5)

            sleeper = await client.execute("diagnostics.sleep", **LONG_SLEEP)
            try:
                with pytest.raises(WaitTimeout):
                    await sleeper.wait(timeout=0.2)
            finally:
                assert (await sleeper.dismiss()).status == "dismissed"
            with pytest.raises(JobDismissed):
                await sleeper.wait(timeout=10)
            listed = await client.jobs(process="diagnostics.sleep", status="dismissed")
            assert sleeper.id in [j.job_id for j in listed]

            with pytest.raises(InvalidInput) as caught:
                await client.execute("alignment.rigid", source=np.zeros((4, 3)),
                                     target=np.zeros((5, 3)))
            assert caught.value.errors[0]["input"] == "target"
            with pytest.raises(NoSuchJob):
                await client.job("nope")
            with pytest.raises(NoSuchProcess):
                await client.describe("no.such.process")

    asyncio.run(scenario())


def test_async_progress_bar(server, capsys: pytest.CaptureFixture[str]) -> None:  # noqa: ANN001
    async def scenario() -> JobStatus:
        async with AsyncClient(server.url) as client:
            job = await client.execute("diagnostics.sleep", seconds=0.3, steps=3)
            return await job.wait(timeout=20, progress=True)

    assert asyncio.run(scenario()).status == "successful"
    err = capsys.readouterr().err
    assert err.splitlines()[-1].startswith("[" + "#" * 30 + "] 100%"), err
