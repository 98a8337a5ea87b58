"""Geometry formats over HTTP: multipart uploads (PLY, OBJ, STL, OFF, GLB, NPY), inputs by
reference to earlier results, and results as typed binary arrays, .npy and glTF binary — every
GLB kind checked by the Khronos glTF-Validator."""

from __future__ import annotations

import base64
import io
import json
from typing import Any

import numpy as np
import pytest
import trimesh
from scipy.spatial.transform import Rotation

from service.gltf import read_glb
from tests.gltf_check import glb_with, problems, validate

pytestmark = pytest.mark.e2e

MULTI = "multipart/form-data"


def disk(side: int = 6) -> trimesh.Trimesh:
    """A side × side grid bent into a shallow dome: a disk with a convex boundary."""
    x, y = np.meshgrid(np.linspace(0, 1, side), np.linspace(0, 1, side))
    v = np.column_stack([x.ravel(), y.ravel(), 0.2 * np.sin(np.pi * x.ravel()) *
                         np.sin(np.pi * y.ravel())])
    f = []
    for i in range(side - 1):
        for j in range(side - 1):
            a = i * side + j
            f += [[a, a + 1, a + side + 1], [a, a + side + 1, a + side]]
    return trimesh.Trimesh(v, np.array(f), process=False)


def exported(mesh: trimesh.Trimesh, fmt: str) -> bytes:
    data = mesh.export(file_type=fmt)
    return data.encode() if isinstance(data, str) else data


def npy(a: np.ndarray) -> bytes:
    buf = io.BytesIO()
    np.save(buf, a)
    return buf.getvalue()


def post_multipart(http, process: str, files: dict[str, tuple[str, bytes, str]],  # noqa: ANN001
                   spec: dict[str, Any] | None = None, headers: dict[str, str] | None = None):
    parts = dict(files)
    if spec is not None:
        parts["spec"] = ("spec.json", json.dumps(spec).encode(), "application/json")
    return http.post(f"/processes/{process}/execution", files=parts,
                     headers={"Prefer": "wait=60", **(headers or {})})


@pytest.mark.parametrize("fmt", ["ply", "obj", "stl", "off", "glb"])
def test_uploaded_mesh_is_the_mesh_trimesh_loads(http, fmt: str) -> None:  # noqa: ANN001
    data = exported(disk(), fmt)
    r = post_multipart(http, "parameterization.tutte", {"mesh": (f"scan.{fmt}", data,
                                                                 "application/octet-stream")},
                       headers={"Prefer": "wait=60, arrays=binary"})
    assert r.status_code == 200, r.text
    assert "arrays=binary" in r.headers["preference-applied"]
    # what a user gets loading the same file locally: the file's vertex order (STL, which has
    # no shared vertices, merged as trimesh merges them by default)
    local = trimesh.load(io.BytesIO(data), file_type=fmt, process=fmt == "stl", force="mesh")
    mesh = r.json()["mesh"]
    vertices = decode(mesh["vertices"])
    faces = decode(mesh["faces"])
    np.testing.assert_array_equal(vertices, np.asarray(local.vertices, dtype=np.float64))
    np.testing.assert_array_equal(faces, local.faces)
    if fmt != "stl":  # the file order is the mesh's own
        np.testing.assert_allclose(vertices, disk().vertices, atol=1e-6)
        np.testing.assert_array_equal(faces, disk().faces)


def decode(obj: dict[str, Any]) -> np.ndarray:
    assert set(obj) == {"dtype", "shape", "data"}, obj
    return np.frombuffer(base64.b64decode(obj["data"]), dtype=obj["dtype"]).reshape(obj["shape"])


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_npy_uploads_are_bit_exact_and_give_the_json_answer(http, dtype) -> None:  # noqa: ANN001
    rng = np.random.default_rng(3)
    source = rng.normal(size=(500, 3)).astype(dtype)
    rot = Rotation.from_euler("xyz", [10, 20, 30], degrees=True).as_matrix()
    target = (source.astype(np.float64) @ rot.T + [1, 2, 3]).astype(dtype)
    r = post_multipart(http, "alignment.rigid", {
        "source": ("source.npy", npy(source), "application/x-npy"),
        "target": ("target.npy", npy(target), "application/x-npy")}, {"inputs": {}})
    assert r.status_code == 200, r.text
    by_json = http.post("/processes/alignment.rigid/execution", json={"inputs": {
        "source": source.astype(np.float64).tolist(),
        "target": target.astype(np.float64).tolist()}})
    assert r.json() == by_json.json()  # float32 widens exactly: the same numbers, same answer
    np.testing.assert_allclose(r.json()["rotation"], rot, atol=1e-5 if dtype == np.float32
                               else 1e-12)


def test_npy_member_of_a_mesh_and_spec_inputs_together(http) -> None:  # noqa: ANN001
    mesh = disk()
    r = post_multipart(http, "parameterization.harmonic", {
        "mesh.vertices": ("v.npy", npy(mesh.vertices), MULTI + "-ignored"),
        "mesh.faces": ("f.npy", npy(mesh.faces.astype(np.int32)), "application/x-npy")},
        {"inputs": {"boundary": "square"}})
    assert r.status_code == 200, r.text
    by_json = http.post("/processes/parameterization.harmonic/execution", json={"inputs": {
        "mesh": {"vertices": mesh.vertices.tolist(), "faces": mesh.faces.tolist()},
        "boundary": "square"}})
    assert r.json()["uv"] == by_json.json()["uv"]


def test_point_cloud_file_gives_points_not_a_mesh(http) -> None:  # noqa: ANN001
    cloud = trimesh.PointCloud(disk().vertices)
    ply = exported(cloud, "ply")
    r = post_multipart(http, "embedding.pca", {"points": ("cloud.ply", ply, "")},
                       {"inputs": {"n_components": 2}})
    assert r.status_code == 200, r.text
    assert np.asarray(r.json()["embedding"]).shape == (36, 2)
    # a mesh input refuses it, naming the part
    r = post_multipart(http, "parameterization.tutte", {"mesh": ("cloud.ply", ply, "")})
    assert r.status_code == 422
    assert r.json()["errors"][0]["input"] == "mesh"
    assert "point cloud" in r.json()["errors"][0]["message"]
    # an input that takes points or a mesh gets points from a point cloud, a mesh from a mesh
    moved = trimesh.PointCloud(disk().vertices + [1.0, 0.0, 0.0])
    r = post_multipart(http, "interpolation.rigid", {
        "source": ("a.ply", ply, ""), "target": ("b.ply", exported(moved, "ply"), "")},
        {"inputs": {"times": [0, 0.5, 1]}})
    assert r.status_code == 200, r.text
    np.testing.assert_allclose(np.asarray(r.json()["frames"])[1],
                               disk().vertices + [0.5, 0, 0], atol=1e-6)
    assert r.json()["faces"] == []  # a point set: no faces
    mesh = exported(disk(), "ply")
    r = post_multipart(http, "interpolation.arap", {"source": ("a.ply", mesh, ""),
                                                    "target": ("b.ply", mesh, "")})
    assert r.status_code == 200, r.text
    np.testing.assert_array_equal(r.json()["faces"], disk().faces)


@pytest.mark.parametrize(("files", "spec", "status", "field"), [
    ({"sauce": ("a.npy", npy(np.zeros((3, 3))), "")}, None, 422, "sauce"),
    ({"source": ("a.npy", b"\x93NUMPY junk", "")}, {"inputs": {"target": [[0, 0, 0]]}}, 422,
     "source"),
    ({"source": ("a.bin", b"\x00\x01\x02", "")}, None, 422, "source"),
    ({"source": ("a.ply", b"ply\nformat ascii 1.0\nelement vertex 99\n", "")}, None, 422,
     "source"),
    ({"source": ("a.npy", npy(np.array(["a", "b"])), "")}, None, 422, "source"),
    ({"source": ("a.npy", npy(np.zeros((3, 3))), "")}, {"inputs": {"source": [[0, 0, 0]]}},
     422, "source"),
    ({"source": ("a.npy", npy(np.zeros((3, 3))), "")}, {"inputs": "no"}, 422, "inputs"),
])
def test_bad_parts_are_named(http, files, spec, status, field) -> None:  # noqa: ANN001
    r = post_multipart(http, "alignment.rigid", files, spec)
    assert r.status_code == status, r.text
    assert r.headers["content-type"] == "application/problem+json"
    assert r.json()["errors"][0]["input"].startswith(field), r.json()


def test_truncated_multipart_is_400(http) -> None:  # noqa: ANN001
    boundary = "xyz"
    body = (f"--{boundary}\r\nContent-Disposition: form-data; name=\"source\"; "
            f"filename=\"a.npy\"\r\n\r\n").encode() + npy(np.zeros((10, 3)))[:60]
    r = http.post("/processes/alignment.rigid/execution", content=body,
                  headers={"Content-Type": f"{MULTI}; boundary={boundary}"})
    assert r.status_code == 400, r.text
    assert r.json()["type"] == "/problems/malformed-body"
    assert "cut short" in r.json()["detail"]
    r = http.post("/processes/alignment.rigid/execution", content=b"--x\r\n",
                  headers={"Content-Type": MULTI})
    assert r.status_code == 400 and "boundary" in r.json()["detail"]


def test_glb_declaring_a_huge_buffer_is_refused(http) -> None:  # noqa: ANN001
    out = glb_with(exported(disk(), "glb"),
                   lambda doc: doc["buffers"][0].update(byteLength=2 ** 40))
    r = post_multipart(http, "parameterization.tutte", {"mesh": ("big.glb", out, "")})
    assert r.status_code == 422, r.text
    assert r.json()["errors"][0]["input"] == "mesh"


def test_per_input_limit_is_413_naming_the_input(tmp_path) -> None:  # noqa: ANN001
    from tests.live import LiveServer

    srv = LiveServer(tmp_path / "data", {"MORPHSERVE_MAX_INPUT_BYTES": "4096"}).start()
    try:
        with srv.client() as c:
            small = npy(np.random.default_rng(0).normal(size=(10, 3)))
            big = npy(np.zeros((1000, 3)))
            r = post_multipart(c, "alignment.rigid", {"source": ("a.npy", small, ""),
                                                      "target": ("b.npy", big, "")})
            assert r.status_code == 413, r.text
            assert r.json()["errors"][0]["input"] == "target"
            r = post_multipart(c, "alignment.rigid", {"source": ("a.npy", small, ""),
                                                      "target": ("b.npy", small, "")})
            assert r.status_code == 200, r.text
    finally:
        srv.stop()


def test_spooled_uploads_become_the_inputs_file(spooling_server) -> None:  # noqa: ANN001
    """A large multipart body is written to disk as it arrives and sealed into the job's
    inputs file (its .npy parts not written twice); the worker reads the same bits. A body
    that fails validation, or one that runs in-process, leaves no file behind."""
    from algorithms.alignment import rigid
    from service.jobs.spool import MAGIC

    data = spooling_server.data_dir
    with spooling_server.client() as c:
        rng = np.random.default_rng(3)
        X = rng.normal(size=(5000, 3))
        Y = np.ascontiguousarray(X[:, [1, 0, 2]] * [1, -1, 1] + 2.0)  # C order: a view
        body = {"source": ("a.npy", npy(X), ""), "target": ("b.npy", npy(Y), "")}
        r = post_multipart(c, "alignment.rigid", body)
        assert r.status_code == 200, r.text
        mine = rigid(X, Y)
        np.testing.assert_array_equal(r.json()["rotation"], mine.rotation)
        np.testing.assert_array_equal(r.json()["translation"], mine.translation)
        files = list((data / "inputs").iterdir())
        assert len(files) == 1 and files[0].read_bytes()[-len(MAGIC):] == MAGIC
        assert files[0].stat().st_size < 2 * X.nbytes + 4096  # the parts, once
        bad = X.copy()
        bad[7, 1] = np.nan
        r = post_multipart(c, "alignment.rigid", {"source": ("a.npy", npy(bad), ""),
                                                  "target": ("b.npy", npy(Y), "")})
        assert r.status_code == 422 and r.json()["errors"][0]["input"] == "source"
        assert list((data / "inputs").iterdir()) == files


# -- inputs by reference ------------------------------------------------------------------

def test_href_chains_a_deformation_into_a_parameterization(http) -> None:  # noqa: ANN001
    mesh = disk()
    first = http.post("/processes/deformation.harmonic/execution", json={"inputs": {
        "mesh": {"vertices": mesh.vertices.tolist(), "faces": mesh.faces.tolist()},
        "handles": {"indices": [0, 35], "positions": [[0, 0, 0], [1.2, 1.1, 0.3]]}}})
    assert first.status_code == 200, first.text
    job = first.headers["content-location"].split("/")[2]
    deformed = first.json()["mesh"]
    second = http.post("/processes/parameterization.tutte/execution", json={"inputs": {
        "mesh": {"href": f"/jobs/{job}/results/mesh"}}})
    assert second.status_code == 200, second.text
    by_value = http.post("/processes/parameterization.tutte/execution",
                         json={"inputs": {"mesh": deformed}})
    assert second.json() == by_value.json()
    # a member may be a reference too, and an absolute URL of this service
    base = str(http.base_url).rstrip("/")
    third = http.post("/processes/alignment.rigid/execution", json={"inputs": {
        "source": mesh.vertices.tolist(),
        "target": {"href": f"{base}/jobs/{job}/results/mesh"}}})
    assert third.status_code == 422  # a mesh is not points: named, not a 500
    assert third.json()["errors"][0]["input"].startswith("target")
    r = http.get(f"/jobs/{job}/results/mesh")
    assert r.status_code == 200 and r.json() == deformed


@pytest.mark.parametrize(("href", "fragment"), [
    ("http://example.com/jobs/x/results/mesh", "never fetches"),
    ("/jobs/no-such-job/results/mesh", "does not exist"),
    ("/processes/alignment.rigid", "expected /jobs/"),
    (42, "string"),
])
def test_bad_references_are_named(http, href, fragment) -> None:  # noqa: ANN001
    r = http.post("/processes/parameterization.tutte/execution",
                  json={"inputs": {"mesh": {"href": href}}})
    assert r.status_code == 422, r.text
    assert r.json()["errors"][0]["input"] == "mesh"
    assert fragment in r.json()["detail"]


def test_reference_to_a_missing_output_or_unfinished_job(http) -> None:  # noqa: ANN001
    r = http.post("/processes/diagnostics.sleep/execution", json={"inputs": {"seconds": 20}},
                  headers={"Prefer": "respond-async"})
    running = r.json()["jobID"]
    try:
        r = http.post("/processes/parameterization.tutte/execution",
                      json={"inputs": {"mesh": {"href": f"/jobs/{running}/results/mesh"}}})
        assert r.status_code == 422 and "only results of successful jobs" in r.text
    finally:
        http.delete(f"/jobs/{running}")
    done = http.post("/processes/alignment.rigid/execution", json={"inputs": {
        "source": [[0, 0], [1, 0], [0, 1]], "target": [[0, 0], [1, 0], [0, 1]]}})
    job = done.headers["content-location"].split("/")[2]
    r = http.post("/processes/parameterization.tutte/execution",
                  json={"inputs": {"mesh": {"href": f"/jobs/{job}/results/nothing"}}})
    assert r.status_code == 422 and "which has only" in r.text


# -- results: binary arrays, npy, raw ----------------------------------------------------

def _rigid(http, **extra: Any):  # noqa: ANN001, ANN202
    return http.post("/processes/alignment.rigid/execution", json={"inputs": {
        "source": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]],
        "target": [[1, 2, 3], [1, 3, 3], [0, 2, 3], [1, 2, 4]]}, **extra})


def test_npy_and_binary_results_equal_the_json_values_exactly(http) -> None:  # noqa: ANN001
    r = _rigid(http)
    job = r.headers["content-location"].split("/")[2]
    doc = r.json()
    one = http.get(f"/jobs/{job}/results/rotation", headers={"Accept": "application/x-npy"})
    assert one.status_code == 200 and one.headers["content-type"] == "application/x-npy"
    np.testing.assert_array_equal(np.load(io.BytesIO(one.content)), doc["rotation"])
    assert http.get(f"/jobs/{job}/results/rotation?f=npy").content == one.content
    binary = http.get(f"/jobs/{job}/results", headers={"Prefer": "arrays=binary"}).json()
    for name, value in doc.items():
        if isinstance(value, list):
            np.testing.assert_array_equal(decode(binary[name]), value)
        else:
            assert binary[name] == value
    # several arrays cannot be one .npy; a process without geometry has no glTF
    r = http.get(f"/jobs/{job}/results", headers={"Accept": "application/x-npy"})
    assert r.status_code == 406 and "/results/{output}" in r.json()["detail"]
    assert http.get(f"/jobs/{job}/results", headers={"Accept": "image/png"}).status_code == 406
    assert http.get(f"/jobs/{job}/results/nothing").status_code == 404


def test_raw_response_and_single_output_npy(http) -> None:  # noqa: ANN001
    r = _rigid(http, outputs={"transform": {}}, response="raw")
    assert r.status_code == 200
    np.testing.assert_allclose(np.asarray(r.json()), [[0, -1, 0, 1], [1, 0, 0, 2],
                                                     [0, 0, 1, 3], [0, 0, 0, 1]], atol=1e-12)
    job = r.headers["content-location"].split("/")[2]
    raw = http.get(f"/jobs/{job}/results", headers={"Accept": "application/x-npy"})
    assert raw.status_code == 200
    np.testing.assert_array_equal(np.load(io.BytesIO(raw.content)), r.json())


def test_empty_arrays_keep_their_shape_as_binary(http) -> None:  # noqa: ANN001
    r = http.post("/processes/assignment.nearest/execution", json={"inputs": {
        "source": [[0.0, 0.0]], "target": [[5.0, 5.0]], "max_distance": 0.1}},
        headers={"Prefer": "arrays=binary"})
    pairs = decode(r.json()["pairs"])
    assert pairs.shape == (0, 2) and pairs.dtype.kind == "i"


# -- glTF binary of every kind ------------------------------------------------------------

def _glb_cases() -> dict[str, tuple[str, dict[str, Any]]]:
    mesh = disk()
    m = {"vertices": mesh.vertices.tolist(), "faces": mesh.faces.tolist()}
    rng = np.random.default_rng(0)
    pts = rng.normal(size=(60, 3))
    labels = (pts[:, 0] > 0).astype(int).tolist()
    return {
        "alignment": ("alignment.rigid", {"source": pts.tolist(),
                                          "target": (pts + [1, 0, 0]).tolist()}),
        "registration": ("registration.icp", {"source": pts.tolist(),
                                              "target": (pts + [0.01, 0, 0]).tolist()}),
        "cpd": ("registration.cpd", {"source": pts.tolist(), "target": (pts * 1.1).tolist(),
                                     "model": "affine"}),
        "multiway": ("registration.multiway", {"sets": [pts.tolist(), (pts + 1).tolist(),
                                                        (pts - 1).tolist()]}),
        "parameterization": ("parameterization.tutte", {"mesh": m}),
        "abf": ("parameterization.abf", {"mesh": m}),
        "deformation": ("deformation.harmonic", {"mesh": m, "handles": {
            "indices": [0, 35], "positions": [[0, 0, 0], [1, 1, 0.5]]}}),
        "layout": ("layout.laplacian", {"mesh": m}),
        "embedding": ("classification.lda", {"points": pts.tolist(), "labels": labels,
                                             "n_components": 1}),
        "clustering": ("clustering.spectral", {"points": pts.tolist(), "n_clusters": 2}),
        "interpolation": ("interpolation.arap", {"source": m, "target": {
            "vertices": (mesh.vertices * [1, 1, -1]).tolist(), "faces": m["faces"]}}),
        "interpolation of points": ("interpolation.rigid", {
            "source": pts.tolist(), "target": (pts + [1, 0, 0]).tolist(), "times": [0, 0.5, 1]}),
        "tetrahedra": ("interpolation.poisson", {"source": TET, "target": {
            "vertices": (np.array(TET["vertices"]) * 2).tolist(), "faces": TET["faces"]}}),
    }


TET = {"vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 1]],
       "faces": [[0, 1, 2, 3], [1, 2, 3, 4]]}


def test_every_geometry_result_is_a_valid_glb(http, tmp_path) -> None:  # noqa: ANN001
    files = {}
    for kind, (process, inputs) in _glb_cases().items():
        r = http.post(f"/processes/{process}/execution", json={"inputs": inputs},
                      headers={"Prefer": "wait=60"})
        assert r.status_code == 200, (kind, r.text)
        job = r.headers["content-location"].split("/")[2]
        glb = http.get(f"/jobs/{job}/results", headers={"Accept": "model/gltf-binary"})
        assert glb.status_code == 200, (kind, glb.text)
        assert glb.headers["content-type"] == "model/gltf-binary"
        assert http.get(f"/jobs/{job}/results?f=glb").content == glb.content
        files[kind] = glb.content
        parsed = read_glb(glb.content)
        positions = [a for a in parsed["accessors"] if a.ndim == 2 and a.shape[1] == 3]
        assert positions, kind
        if kind == "parameterization":
            uv = next(a for a in parsed["accessors"] if a.ndim == 2 and a.shape[1] == 2)
            assert uv.min() >= -1e-6 and uv.max() <= 1 + 1e-6
    allowed = {("UNUSED_OBJECT", "/meshes/0/primitives/0/attributes/TEXCOORD_0")}
    for kind, report in validate(files, tmp_path).items():
        assert report["issues"]["numErrors"] == 0, (kind, report["issues"])
        assert not problems(report, allowed), (kind, report["issues"]["messages"])


def test_aligned_source_lands_on_the_target_in_the_glb(http) -> None:  # noqa: ANN001
    rng = np.random.default_rng(1)
    src = rng.normal(size=(40, 3))
    rot = Rotation.from_euler("z", 40, degrees=True).as_matrix()
    dst = src @ rot.T + [0.5, -1, 2]
    r = http.post("/processes/alignment.rigid/execution",
                  json={"inputs": {"source": src.tolist(), "target": dst.tolist()}},
                  headers={"Accept": "model/gltf-binary"})
    assert r.status_code == 200 and r.headers["content-type"] == "model/gltf-binary"
    doc = read_glb(r.content)
    names = [m["name"] for m in doc["json"]["meshes"]]
    assert names == ["source (moved)", "target", "source"]
    moved = doc["accessors"][doc["json"]["meshes"][0]["primitives"][0]["attributes"]["POSITION"]]
    target = doc["accessors"][doc["json"]["meshes"][1]["primitives"][0]["attributes"]["POSITION"]]
    np.testing.assert_allclose(moved, dst, atol=1e-5)  # float32 positions
    np.testing.assert_allclose(target, dst, atol=1e-5)


def test_glb_of_a_result_without_geometry_is_406(http) -> None:  # noqa: ANN001
    r = http.post("/processes/assignment.distance/execution", json={"inputs": {
        "source": [[0, 0]], "target": [[1, 1]]}})
    job = r.headers["content-location"].split("/")[2]
    r = http.get(f"/jobs/{job}/results?f=glb")
    assert r.status_code == 406
    assert r.headers["content-type"] == "application/problem+json"
