"""Geometry objects in, geometry objects out (morphserve._geometry).

trimesh objects are the real ones; Open3D and PyVista objects are small fakes with the
attributes those libraries give (``points``; ``vertices`` + ``triangles``; ``points`` + a
flat ``faces`` array ``[3, i, j, k, ...]``), so that neither library is needed. End to end, a
job given any of them gives the very results of the same job given numpy arrays.
"""

from __future__ import annotations

import asyncio
import pickle
import sys
import types
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import httpx
import numpy as np
import pytest
import trimesh

from morphserve import AsyncClient, Client, InvalidInput, MorphserveError, NoSuchFile, Results
from morphserve._geometry import as_geometry, geometry_forms, prepare_inputs
from tests.sdk.test_client import FakeServer

# -- fakes of Open3D and PyVista objects -------------------------------------------------


class FakeVector:
    """Open3D's Vector3dVector / Vector3iVector: a sequence numpy reads (not an ndarray)."""

    def __init__(self, rows: Any) -> None:
        self._rows = np.array(rows)

    def __array__(self, dtype: Any = None, copy: Any = None) -> np.ndarray:
        return self._rows if dtype is None else self._rows.astype(dtype)

    def __len__(self) -> int:
        return len(self._rows)


class FakeO3dPointCloud:
    def __init__(self, points: Any) -> None:
        self.points = FakeVector(points)
        self.colors = FakeVector(np.zeros((0, 3)))
        self.normals = FakeVector(np.zeros((0, 3)))


class FakeO3dTriangleMesh:
    def __init__(self, vertices: Any, triangles: Any) -> None:
        self.vertices = FakeVector(vertices)
        self.triangles = FakeVector(triangles)
        self.vertex_normals = FakeVector(np.zeros((0, 3)))


class FakePolyData:
    """PyVista's PolyData: ``points`` and the padded ``faces`` array."""

    def __init__(self, points: Any, faces: Any = None) -> None:
        self.points = np.asarray(points, dtype=np.float32)
        self.faces = np.asarray([] if faces is None else faces, dtype=np.int64)
        self.n_points = len(self.points)


def polydata_faces(triangles: np.ndarray) -> np.ndarray:
    return np.hstack([np.full((len(triangles), 1), 3), triangles]).ravel()


def grid_mesh(n: int = 4) -> tuple[np.ndarray, np.ndarray]:
    """An n x n grid of vertices in the plane z = 0, two triangles per cell: a disk."""
    xs, ys = np.meshgrid(np.arange(n, dtype=np.float64), np.arange(n, dtype=np.float64))
    vertices = np.column_stack([xs.ravel(), ys.ravel(), np.zeros(n * n)])
    faces = []
    for row in range(n - 1):
        for col in range(n - 1):
            a = row * n + col
            faces += [[a, a + 1, a + n + 1], [a, a + n + 1, a + n]]
    return vertices, np.array(faces)


# -- objects as geometry -----------------------------------------------------------------


def test_trimesh_objects() -> None:
    vertices, faces = grid_mesh(3)
    mesh = as_geometry(trimesh.Trimesh(vertices, faces, process=False))
    assert mesh is not None and mesh.what == "Trimesh"
    np.testing.assert_array_equal(mesh.vertices, vertices)
    np.testing.assert_array_equal(mesh.faces, faces)
    cloud = as_geometry(trimesh.PointCloud(vertices))
    assert cloud is not None and cloud.faces is None
    np.testing.assert_array_equal(cloud.vertices, vertices)


def test_open3d_like_objects() -> None:
    vertices, faces = grid_mesh(3)
    mesh = as_geometry(FakeO3dTriangleMesh(vertices, faces))
    assert mesh is not None and mesh.faces is not None
    np.testing.assert_array_equal(mesh.faces, faces)
    assert mesh.faces.dtype == np.int64 and mesh.vertices.dtype == np.float64
    cloud = as_geometry(FakeO3dPointCloud(vertices))
    assert cloud is not None and cloud.faces is None
    np.testing.assert_array_equal(cloud.vertices, vertices)
    # a TriangleMesh without triangles is its vertices
    bare = as_geometry(FakeO3dTriangleMesh(vertices, np.zeros((0, 3), dtype=np.int32)))
    assert bare is not None and bare.faces is None


def test_pyvista_faces_layout() -> None:
    # two triangles by hand: [3, 0, 1, 2, 3, 0, 2, 3]
    square = FakePolyData([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]],
                          [3, 0, 1, 2, 3, 0, 2, 3])
    geometry = as_geometry(square)
    assert geometry is not None
    np.testing.assert_array_equal(geometry.faces, [[0, 1, 2], [0, 2, 3]])
    assert geometry.vertices.dtype == np.float64
    cloud = as_geometry(FakePolyData([[0, 0, 0], [1, 0, 0]]))  # points only: no faces
    assert cloud is not None and cloud.faces is None


def test_pyvista_polygons_must_be_triangulated() -> None:
    quad = FakePolyData([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [2, 0, 0]],
                        [3, 0, 1, 4, 4, 0, 1, 2, 3])
    with pytest.raises(ValueError, match=r"a face of 4 vertices; .*call \.triangulate\(\)"):
        as_geometry(quad)


def test_plain_values_are_not_geometry() -> None:
    for value in (np.zeros((2, 3)), [[0, 0, 0]], {"vertices": [], "faces": []}, "a.ply", 3,
                  None, Path("a.ply")):
        assert as_geometry(value) is None


def _schemas(process_id: str) -> dict[str, Any]:
    from service.catalog import registry
    from service.representation import process_description

    described = process_description(registry.get(process_id))
    return {name: spec["schema"] for name, spec in described["inputs"].items()}


def test_forms_read_from_every_description_of_the_catalog() -> None:
    """What each input takes, read from its JSON Schema, is what its declared kind says."""
    from algorithms.core.params import Kind
    from service.catalog import registry

    expected = {Kind.POINTS: {"points"}, Kind.MESH: {"mesh"}, Kind.SHAPE: {"points", "mesh"},
                Kind.WEIGHTS: set(), Kind.LABELS: set(), Kind.GRAPH: set(),
                Kind.HANDLES: set()}
    checked = 0
    for process in registry.values():
        schemas = _schemas(process.id)
        for name, kind in process.kinds.items():
            if kind in expected:
                assert geometry_forms(schemas[name]) == expected[kind], (process.id, name)
                checked += 1
    assert checked > 60


def test_a_mesh_goes_as_points_or_as_a_mesh_by_what_the_input_takes() -> None:
    vertices, faces = grid_mesh(3)
    mesh = trimesh.Trimesh(vertices, faces, process=False)
    values, files = prepare_inputs({"source": mesh, "target": mesh},
                                   _schemas("alignment.rigid"))
    assert files == {}
    np.testing.assert_array_equal(values["source"], vertices)  # points: its vertices
    values, _ = prepare_inputs({"mesh": mesh}, _schemas("parameterization.tutte"))
    assert set(values["mesh"]) == {"vertices", "faces"}
    np.testing.assert_array_equal(values["mesh"]["faces"], faces)
    values, _ = prepare_inputs({"source": mesh, "target": trimesh.PointCloud(vertices)},
                               _schemas("interpolation.rigid"))  # a shape: either
    assert set(values["source"]) == {"vertices", "faces"}
    np.testing.assert_array_equal(values["target"], vertices)


def test_a_point_cloud_for_a_mesh_input_is_refused() -> None:
    with pytest.raises(TypeError, match=r"Expected `mesh` to be a mesh with faces, got a "
                                        r"PointCloud of 9 points and no faces"):
        prepare_inputs({"mesh": trimesh.PointCloud(grid_mesh(3)[0])},
                       _schemas("parameterization.tutte"))


def test_strings_are_choices_or_files(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    schemas = _schemas("registration.icp")
    np.save(tmp_path / "source.npy", np.zeros((4, 3)))
    (tmp_path / "rigid").write_text("a file named like a choice")
    values, files = prepare_inputs({"source": "source.npy", "model": "rigid", "init": "pca"},
                                   schemas)
    assert values == {"model": "rigid", "init": "pca"}  # choices, whatever files exist
    assert files == {"source": Path("source.npy")}
    # a wrong choice of an input that takes no geometry: the service names the choices
    values, files = prepare_inputs({"model": "rigidd"}, schemas)
    assert values == {"model": "rigidd"} and files == {}


def test_a_missing_file_is_named(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    schemas = _schemas("registration.icp")
    with pytest.raises(NoSuchFile, match=r"Expected `source` to be points or a geometry file; "
                                         r"got 'missing.ply', which names no file") as caught:
        prepare_inputs({"source": "missing.ply"}, schemas)
    assert isinstance(caught.value, FileNotFoundError)
    assert isinstance(caught.value, MorphserveError)
    assert caught.value.filename == "missing.ply" and caught.value.input == "source"
    with pytest.raises(NoSuchFile, match=r"got 'scan', which names no file"):
        prepare_inputs({"source": "scan"}, schemas)  # no suffix: the input takes no text
    with pytest.raises(NoSuchFile, match=r"`init` to be points or a geometry file, or one of "
                                         r"'identity', 'pca'; got 'pcaa'"):
        prepare_inputs({"init": "pcaa"}, schemas)
    with pytest.raises(NoSuchFile, match=r"got 'gone.obj'"):
        prepare_inputs({"source": Path("gone.obj")}, None)
    restored = pickle.loads(pickle.dumps(caught.value))
    assert str(restored) == str(caught.value) and restored.filename == "missing.ply"


def test_lists_of_point_sets_take_objects_and_files(tmp_path: Path) -> None:
    vertices, faces = grid_mesh(3)
    trimesh.Trimesh(vertices + 1, faces, process=False).export(tmp_path / "b.ply")
    np.save(tmp_path / "c.npy", vertices + 2)
    sets = [trimesh.Trimesh(vertices, faces, process=False), str(tmp_path / "b.ply"),
            tmp_path / "c.npy", FakeO3dPointCloud(vertices + 3), vertices + 4]
    values, files = prepare_inputs({"sets": sets}, _schemas("registration.multiway"))
    assert files == {}
    for shift, member in enumerate(values["sets"]):
        np.testing.assert_allclose(member, vertices + shift)
    with pytest.raises(NoSuchFile, match=r"`sets\[1\]`"):
        prepare_inputs({"sets": [vertices, "nope.ply"]}, _schemas("registration.multiway"))


# -- against the in-memory service ------------------------------------------------------


@pytest.fixture
def fake() -> FakeServer:
    return FakeServer()


@pytest.fixture
def fake_client(fake: FakeServer, monkeypatch: pytest.MonkeyPatch) -> Iterator[Client]:
    monkeypatch.delenv("MORPHSERVE_API_KEY", raising=False)
    with Client("http://morph.test", transport=httpx.MockTransport(fake)) as client:
        yield client


def test_a_missing_file_sends_nothing(fake_client: Client, fake: FakeServer,
                                      tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    with pytest.raises(NoSuchFile, match="missing.ply"):
        fake_client.execute("alignment.rigid", source="missing.ply", target=[[0, 0]])
    assert fake.requests_to("POST", r".*") == []  # only the description was asked for
    with pytest.raises(NoSuchFile):
        fake_client.execute("alignment.rigid", source=Path("missing.ply"), target=[[0, 0]])
    assert [r.method for r in fake.requests] == ["GET"]


def test_the_description_is_asked_once_and_only_when_needed(fake_client: Client,
                                                            fake: FakeServer) -> None:
    vertices, faces = grid_mesh(3)
    fake_client.execute("alignment.rigid", source=trimesh.PointCloud(vertices),
                        target=vertices)  # a point cloud is points anywhere: no need
    assert [r.method for r in fake.requests] == ["POST"]
    mesh = trimesh.Trimesh(vertices, faces, process=False)
    fake_client.execute("alignment.rigid", source=mesh, target=mesh)
    fake_client.execute("alignment.rigid", source=mesh, target=mesh)
    assert [r.method for r in fake.requests] == ["POST", "GET", "POST", "POST"]
    import json

    sent = json.loads(fake.requests[-1].content)["inputs"]
    np.testing.assert_array_equal(sent["source"], vertices)


# -- results back as objects -------------------------------------------------------------


MESH_RESULTS = {"mesh": {"vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]],
                         "faces": [[0, 1, 2], [1, 3, 2]]},
                "uv": [[0, 0], [1, 0], [0, 1], [1, 1]], "energy": 0.5}


def test_to_trimesh_and_save_in_mesh_formats(tmp_path: Path) -> None:
    results = Results(MESH_RESULTS)
    mesh = results.to_trimesh()
    assert isinstance(mesh, trimesh.Trimesh)
    np.testing.assert_array_equal(mesh.faces, MESH_RESULTS["mesh"]["faces"])
    for suffix in (".ply", ".obj", ".stl", ".off"):
        path = results.save(tmp_path / f"out{suffix}")
        if suffix == ".obj":  # read by hand: 4 vertices, 2 triangles
            lines = path.read_text().splitlines()
            assert [sum(line.startswith(tag) for line in lines) for tag in ("v ", "f ")] == \
                [4, 2]
            continue
        back = trimesh.load(path, process=False)
        assert len(back.faces) == 2, suffix
        # the same triangles in space (STL stores triangles, not shared vertices)
        np.testing.assert_allclose(np.sort(back.triangles.reshape(-1, 3), axis=0),
                                   np.sort(mesh.triangles.reshape(-1, 3), axis=0))
    cloud = results.to_trimesh("uv")  # 2-D coordinates lie in z = 0
    np.testing.assert_array_equal(cloud.vertices, [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]])
    results.save(tmp_path / "uv.ply", "uv")
    assert len(trimesh.load(tmp_path / "uv.ply").vertices) == 4
    with pytest.raises(ValueError, match=r"A \.stl file holds a mesh; these results give "
                                         r"points"):
        results.save(tmp_path / "uv.stl", "uv")
    with pytest.raises(ValueError, match=r"Expected a path ending in .glb, .ply, .obj, .stl"):
        results.save(tmp_path / "out.xyz")


def test_results_without_geometry_say_so() -> None:
    results = Results({"transform": np.eye(4).tolist(), "linear": np.eye(3).tolist()})
    with pytest.raises(ValueError, match="These results hold no mesh or points .*transform, "
                                         "linear"):
        results.to_trimesh()
    with pytest.raises(ValueError, match=r"The output 'transform' is not a mesh or \(n, 2\|3\)"):
        results.to_trimesh("transform")


class _Recorder:
    def __init__(self, name: str) -> None:
        self.name = name

    def __call__(self, *args: Any) -> tuple[str, tuple[Any, ...]]:
        return (self.name, args)


@pytest.fixture
def fake_open3d(monkeypatch: pytest.MonkeyPatch) -> types.ModuleType:
    o3d = types.ModuleType("open3d")
    o3d.utility = types.SimpleNamespace(  # type: ignore[attr-defined]
        Vector3dVector=_Recorder("Vector3dVector"), Vector3iVector=_Recorder("Vector3iVector"))
    o3d.geometry = types.SimpleNamespace(  # type: ignore[attr-defined]
        PointCloud=_Recorder("PointCloud"), TriangleMesh=_Recorder("TriangleMesh"))
    monkeypatch.setitem(sys.modules, "open3d", o3d)
    return o3d


def test_to_open3d(fake_open3d: types.ModuleType) -> None:
    name, (vertices, triangles) = Results(MESH_RESULTS).to_open3d()
    assert name == "TriangleMesh"
    np.testing.assert_array_equal(vertices[1][0], MESH_RESULTS["mesh"]["vertices"])
    np.testing.assert_array_equal(triangles[1][0], MESH_RESULTS["mesh"]["faces"])
    assert triangles[1][0].dtype == np.int32  # Vector3iVector takes int32 rows
    name, (points,) = Results(MESH_RESULTS).to_open3d("uv")
    assert name == "PointCloud" and points[1][0].shape == (4, 3)


def test_to_pyvista(monkeypatch: pytest.MonkeyPatch) -> None:
    pv = types.ModuleType("pyvista")
    pv.PolyData = FakePolyData  # type: ignore[attr-defined]
    monkeypatch.setitem(sys.modules, "pyvista", pv)
    poly = Results(MESH_RESULTS).to_pyvista()
    np.testing.assert_array_equal(poly.faces, [3, 0, 1, 2, 3, 1, 3, 2])
    back = as_geometry(poly)  # and back again, through the same layout
    assert back is not None
    np.testing.assert_array_equal(back.faces, MESH_RESULTS["mesh"]["faces"])
    assert Results(MESH_RESULTS).to_pyvista("uv").faces.size == 0


def test_converters_name_the_package_when_missing(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "open3d", None)
    monkeypatch.setitem(sys.modules, "pyvista", None)
    with pytest.raises(ImportError, match=r"This needs open3d.*`pip install open3d`"):
        Results(MESH_RESULTS).to_open3d()
    with pytest.raises(ImportError, match=r"This needs pyvista.*`pip install pyvista`"):
        Results(MESH_RESULTS).to_pyvista()


# -- end to end: the same job from each kind of object -----------------------------------


@pytest.fixture
def client(server: Any) -> Iterator[Client]:
    with Client(server.url, timeout=60) as c:
        yield c


def _pair(seed: int = 3, n: int = 40) -> tuple[np.ndarray, np.ndarray]:
    from scipy.spatial.transform import Rotation

    rng = np.random.default_rng(seed)
    source = rng.normal(size=(n, 3))
    return source, source @ Rotation.random(random_state=seed).as_matrix().T + [1.0, 2.0, 3.0]


@pytest.mark.e2e
def test_point_sets_from_every_library_give_the_same_job(client: Client,
                                                          tmp_path: Path) -> None:
    source, target = _pair()
    faces = np.array([[0, 1, 2], [2, 3, 4]])
    trimesh.PointCloud(source).export(tmp_path / "source.ply")
    np.save(tmp_path / "target.npy", target)
    reference = client.execute("alignment.rigid", source=source, target=target,
                               wait=30).result()
    givens = {
        "trimesh mesh": trimesh.Trimesh(source, faces, process=False),
        "trimesh cloud": trimesh.PointCloud(source),
        "open3d cloud": FakeO3dPointCloud(source),
        "open3d mesh": FakeO3dTriangleMesh(source, faces),
        "pyvista": FakePolyData(source.astype(np.float32).astype(np.float64),
                                polydata_faces(faces)),
        "path": str(tmp_path / "source.ply"),
        "Path": tmp_path / "source.ply",
    }
    for what, given in givens.items():
        results = client.execute("alignment.rigid", source=given,
                                 target=tmp_path / "target.npy", wait=30).result()
        expected = reference
        if what == "pyvista":  # PyVista keeps float32 points: the same job on those
            expected = client.execute("alignment.rigid",
                                      source=source.astype(np.float32).astype(np.float64),
                                      target=target, wait=30).result()
        if what in ("path", "Path"):  # PLY keeps float32 vertices as trimesh writes them
            loaded = np.asarray(trimesh.load(tmp_path / "source.ply").vertices)
            expected = client.execute("alignment.rigid", source=loaded, target=target,
                                      wait=30).result()
        np.testing.assert_array_equal(results["transform"], expected["transform"], what)


@pytest.mark.e2e
def test_meshes_from_every_library_give_the_same_job(client: Client, tmp_path: Path) -> None:
    vertices, faces = grid_mesh(4)
    reference = client.execute("parameterization.tutte",
                               mesh={"vertices": vertices, "faces": faces}, wait=30).result()
    trimesh.Trimesh(vertices, faces, process=False).export(tmp_path / "grid.off")
    for given in (trimesh.Trimesh(vertices, faces, process=False),
                  FakeO3dTriangleMesh(vertices, faces),
                  FakePolyData(vertices, polydata_faces(faces)),
                  tmp_path / "grid.off", str(tmp_path / "grid.off")):
        results = client.execute("parameterization.tutte", mesh=given, wait=30).result()
        np.testing.assert_allclose(results["uv"], reference["uv"], atol=1e-12,
                                   err_msg=type(given).__name__)
    mesh = reference.to_trimesh()
    assert isinstance(mesh, trimesh.Trimesh) and len(mesh.faces) == len(faces)
    for suffix in (".ply", ".obj", ".stl", ".off"):  # the result mesh, through trimesh
        reference.save(tmp_path / f"flat{suffix}")
        back = trimesh.load(tmp_path / f"flat{suffix}", process=False)
        assert len(back.faces) == len(faces), suffix


@pytest.mark.e2e
def test_choices_go_inline_and_a_wrong_choice_is_the_services_to_name(client: Client) -> None:
    source, target = _pair(n=60)
    job = client.execute("registration.icp", source=trimesh.PointCloud(source),
                         target=FakeO3dPointCloud(target), model="rigid", init="pca")
    assert job.result(timeout=60)["transform"].shape == (4, 4)
    with pytest.raises(InvalidInput) as caught:
        client.execute("registration.icp", source=source, target=target, model="rigidd")
    assert [e["input"] for e in caught.value.errors] == ["model"]


@pytest.mark.e2e
def test_async_client_takes_objects_and_paths(server: Any, tmp_path: Path) -> None:
    vertices, faces = grid_mesh(4)
    trimesh.Trimesh(vertices, faces, process=False).export(tmp_path / "grid.ply")

    async def scenario() -> tuple[Results, Results]:
        async with AsyncClient(server.url, timeout=60) as client:
            a = await (await client.execute("parameterization.tutte",
                                            mesh=FakeO3dTriangleMesh(vertices, faces)))
            b = await (await client.execute("parameterization.tutte", mesh=tmp_path / "grid.ply"))
            with pytest.raises(NoSuchFile):
                await client.execute("parameterization.tutte", mesh="no-such-mesh.ply")
            job = await client.execute("parameterization.tutte", mesh=tmp_path / "grid.ply",
                                       wait=30)
            for suffix in (".ply", ".obj", ".stl", ".off"):
                saved = await job.save(tmp_path / f"flat{suffix}")
                back = trimesh.load(saved, process=False)
                assert len(back.faces) == len(faces), suffix
            return a, b

    a, b = asyncio.run(scenario())
    np.testing.assert_allclose(a["uv"], b["uv"], atol=1e-6)  # PLY keeps float32 vertices
