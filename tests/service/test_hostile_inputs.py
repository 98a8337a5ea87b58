"""Hostile inputs, without a server: JSON nested deeper than any parser or walk may go, and
geometry files whose scene graph, header or data lie (cycles, long chains, one mesh drawn by
thousands of nodes, counts that the bytes do not hold). Each is refused with an
``InvalidInputError`` (or ``ValueError`` for JSON) that names the input; none raises
anything else. The GLB files are built by hand (struct + json), a few hundred bytes each."""

from __future__ import annotations

import json
import random
import struct
from typing import Any

import numpy as np
import pytest

import service.jsonio as jsonio
from algorithms.core.errors import InvalidInputError
from service.binary import decode_arrays
from service.geometry_io import DecodeLimits, Upload, decode_upload, place_upload, resolve_refs
from service.gltf import mesh_glb

# -- JSON nesting -------------------------------------------------------------------------


def nested(depth: int, kind: str, inner: bytes = b"1") -> bytes:
    """``depth`` levels of arrays (``[[[1]]]``) or objects (``{"a":{"a":1}}``)."""
    if kind == "array":
        return b"[" * depth + inner + b"]" * depth
    return b'{"a":' * depth + inner + b"}" * depth


def reference_depth(value: Any) -> int:
    """Levels of arrays and objects, by plain recursion (fine for the small documents it is
    given)."""
    if isinstance(value, list):
        return 1 + max((reference_depth(v) for v in value), default=0)
    if isinstance(value, dict):
        return 1 + max((reference_depth(v) for v in value.values()), default=0)
    return 0


@pytest.mark.parametrize("depth", [1_025, 1_500, 10_000])
@pytest.mark.parametrize("kind", ["array", "object"])
@pytest.mark.parametrize("inner", [b"1", b"NaN"])
def test_json_deeper_than_the_parsers_limit_is_a_value_error(depth: int, kind: str,
                                                              inner: bytes) -> None:
    with pytest.raises(ValueError, match="nested deeper than"):
        jsonio.loads(nested(depth, kind, inner))


@pytest.mark.parametrize("depth", [1_500, 10_000])
def test_a_non_finite_token_before_deep_nesting_is_no_recursion_error(depth: int) -> None:
    # orjson stops at the NaN, before the depth: the lenient reading must not recurse
    with pytest.raises(ValueError, match="nested deeper than 512"):
        jsonio.loads(b"[NaN, " + nested(depth, "array") + b"]")


def _chain_depth(value: Any) -> int:
    """Levels of a chain of one-member arrays and objects, counted without recursion."""
    depth = 0
    while isinstance(value, (list, dict)):
        value = value[0] if isinstance(value, list) else value["a"]
        depth += 1
    return depth


def test_json_at_the_limit_still_parses() -> None:
    assert _chain_depth(jsonio.loads(nested(1_024, "array"))) == 1_024
    lenient = jsonio.loads(b"[NaN, " + nested(400, "object", b"Infinity") + b"]")
    assert np.isnan(lenient[0]) and _chain_depth(lenient[1]) == 400
    assert lenient[1]["a"]["a"]["a"] is not None


def test_a_syntax_error_keeps_its_position() -> None:
    with pytest.raises(ValueError, match=r"line 1 column 9 \(char 8\)"):
        jsonio.loads(b'{"a": 1,}')
    assert jsonio.loads(b"[1e999, 123456789012345678901234567890]") == [
        float("inf"), 123456789012345678901234567890]


def _random_document(rng: random.Random, depth: int = 0) -> Any:
    """Arrays and objects whose strings hold brackets, quotes and runs of backslashes."""
    r = rng.random()
    if depth > 10 or r < 0.3:
        return rng.choice([1, 2.5, None, "[[", "}}", '\\"[', "\\\\", '"{', "\\\\\\]"])
    if r < 0.65:
        return [_random_document(rng, depth + 1) for _ in range(rng.randint(0, 3))]
    return {rng.choice(["k", "[", '\\"', "}"]) + str(i): _random_document(rng, depth + 1)
            for i in range(rng.randint(0, 3))}


@pytest.mark.parametrize("chunk", [1, 7, 1 << 20])
def test_the_depth_count_agrees_with_recursion(chunk: int, monkeypatch: pytest.MonkeyPatch
                                               ) -> None:
    monkeypatch.setattr(jsonio, "_CHUNK", chunk)  # chunk borders inside strings and escapes
    rng = random.Random(chunk)
    for _ in range(300):
        doc = _random_document(rng)
        raw = json.dumps(doc).encode()
        depth = reference_depth(doc)
        assert not jsonio.deeper_than(raw, depth), raw
        assert depth == 0 or jsonio.deeper_than(raw, depth - 1), raw


def test_walks_over_inputs_stop_at_their_depth_limit() -> None:
    deep: Any = {"vertices": [[0, 0, 0]]}
    for _ in range(40):
        deep = {"a": deep}
    with pytest.raises(InvalidInputError) as err:
        decode_arrays(deep, "mesh", max_depth=32)
    assert err.value.field == "mesh" and "mesh.a.a" in str(err.value)
    assert decode_arrays(deep, "mesh", max_depth=41) == deep

    def fetch(*_: str) -> Any:
        raise AssertionError("a reference this deep is never fetched")

    ref: Any = {"href": "/jobs/j/results/x"}
    for _ in range(900):  # more levels than Python's own recursion allows in a walk
        ref = {"a": ref}
    with pytest.raises(InvalidInputError) as err:
        resolve_refs(ref, "source", fetch, "http://h", max_depth=32)
    assert err.value.field == "source"
    with pytest.raises(InvalidInputError) as err:
        place_upload({}, "mesh" + ".a" * 5_000, np.zeros(3), max_depth=32)
    assert err.value.field == "mesh"
    inputs: dict[str, Any] = {}
    place_upload(inputs, "mesh.vertices", 1)
    place_upload(inputs, "mesh.faces", 2)
    assert inputs == {"mesh": {"vertices": 1, "faces": 2}}


# -- hostile geometry files ---------------------------------------------------------------

LIMITS = DecodeLimits(max_bytes=1 << 20, max_points=1_000, max_nodes=100, max_depth=16)

_TRIANGLE = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32).tobytes()
_INDICES = np.array([0, 1, 2], np.uint16).tobytes() + b"\0\0"


def glb(doc: dict[str, Any], binary: bytes = b"") -> bytes:
    """A GLB of the JSON ``doc`` and the binary chunk ``binary``, packed by hand."""
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    binary += b"\0" * (-len(binary) % 4)
    chunks = struct.pack("<II", len(text), 0x4E4F534A) + text
    if binary:
        chunks += struct.pack("<II", len(binary), 0x004E4942) + binary
    return struct.pack("<III", 0x46546C67, 2, 12 + len(chunks)) + chunks


def triangle_glb(nodes: list[dict[str, Any]], roots: list[int] | None = None,
                 **change: Any) -> bytes:
    """One triangle mesh (3 vertices, 1 face) placed by ``nodes``; ``roots``: the scene's
    root nodes (default: node 0)."""
    doc = {"asset": {"version": "2.0"}, "buffers": [{"byteLength": 44}],
           "bufferViews": [{"buffer": 0, "byteLength": 36},
                           {"buffer": 0, "byteOffset": 36, "byteLength": 6}],
           "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3,
                          "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
                         {"bufferView": 1, "componentType": 5123, "count": 3,
                          "type": "SCALAR"}],
           "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
           "nodes": nodes, "scenes": [{"nodes": [0] if roots is None else roots}],
           "scene": 0, **change}
    return glb(doc, _TRIANGLE + _INDICES)


def refused(data: bytes, filename: str, takes: str = "mesh",
            limits: DecodeLimits = LIMITS) -> str:
    """The message of the InvalidInputError that decoding ``data`` raises (naming the part
    ``mesh``); anything else raised fails the test."""
    with pytest.raises(InvalidInputError) as err:
        decode_upload(Upload("mesh", filename, None, data), takes=takes, limits=limits)
    assert err.value.field == "mesh"
    return str(err.value)


def test_the_hand_built_glb_is_read() -> None:
    mesh = decode_upload(Upload("mesh", "t.glb", None, triangle_glb([{"mesh": 0}])),
                         takes="mesh", limits=LIMITS)
    np.testing.assert_array_equal(mesh["vertices"], [[0, 0, 0], [1, 0, 0], [0, 1, 0]])
    np.testing.assert_array_equal(mesh["faces"], [[0, 1, 2]])


@pytest.mark.parametrize(("nodes", "roots", "expected"), [
    ([{"mesh": 0, "children": [0]}], None, "is its own child"),
    ([{"mesh": 0, "children": [1]}, {"children": [0]}], None, "nodes[0] is its own ancestor"),
    # no root at all: 1 -> 2 -> 1, the mesh hangs off the loop
    ([{"mesh": 0}, {"children": [2]}, {"children": [1, 3]}, {"mesh": 0}], None,
     "nodes[1] is its own ancestor"),
    ([{"children": [1, 2]}, {"children": [3]}, {"children": [3]}, {"mesh": 0}], None,
     "nodes[3] as a child of both"),
])
def test_a_scene_that_is_no_forest_is_refused(nodes: list[dict[str, Any]],
                                              roots: list[int] | None, expected: str) -> None:
    message = refused(triangle_glb(nodes, roots), "scene.glb")
    assert "cycle" in message or "trees" in message
    assert expected in message


def test_a_long_chain_of_nodes_is_refused_at_the_depth_limit() -> None:
    chain = [{"children": [i + 1]} for i in range(40)] + [{"mesh": 0}]
    assert "more than 16 levels deep" in refused(triangle_glb(chain), "chain.glb")
    # 16 levels (15 parents above the mesh's node) are fine
    short = [{"children": [i + 1]} for i in range(15)] + [{"mesh": 0}]
    decode_upload(Upload("mesh", "chain.glb", None, triangle_glb(short)), takes="mesh",
                  limits=LIMITS)


def test_too_many_nodes_are_refused_before_loading() -> None:
    many = [{"mesh": 0} for _ in range(101)]
    assert "101 nodes, more than the limit of 100" in refused(
        triangle_glb(many, list(range(101))), "many.glb")


def test_instancing_is_counted_before_it_is_expanded() -> None:
    # 50 nodes draw the 3-vertex mesh, each listed 7 times as a root: 1050 vertices > 1000,
    # from a file of a few hundred bytes
    nodes = [{"mesh": 0} for _ in range(50)]
    data = triangle_glb(nodes, list(range(50)) * 7)
    assert len(data) < 3_000
    assert "would make 1050 vertices" in refused(data, "instanced.glb")
    # nested instancing: a parent listed 400 times carries its child along each time
    assert "would make 1200 vertices" in refused(
        triangle_glb([{"children": [1]}, {"mesh": 0}], [0] * 400), "nested.glb")
    # GPU instancing (EXT_mesh_gpu_instancing): 3 translations, so 3 copies of 3 vertices
    instanced = [{"mesh": 0, "extensions": {"EXT_mesh_gpu_instancing": {
        "attributes": {"TRANSLATION": 2}}}}]
    accessors = [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                  "min": [0, 0, 0], "max": [1, 1, 0]},
                 {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"},
                 {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}]
    data = triangle_glb(instanced, accessors=accessors)
    assert "would make 9 vertices" in refused(data, "gpu.glb",
                                              limits=DecodeLimits(1 << 20, 8, 100, 16))


def _truncated_glb() -> bytes:
    return triangle_glb([{"mesh": 0}])[:-8]


def _bad_json_chunk() -> bytes:
    good = triangle_glb([{"mesh": 0}])
    return good[:20] + b'{"asset": [' + good[31:]


def _accessor_out_of_range() -> bytes:
    doc_nodes = [{"mesh": 0}]
    return triangle_glb(doc_nodes, meshes=[{"primitives": [
        {"attributes": {"POSITION": 7}, "indices": 1}]}])


def _deep_json_chunk() -> bytes:
    """A GLB whose JSON nests 5000 arrays in its extras."""
    text = b'{"asset": {"version": "2.0"}, "extras": ' + b"[" * 5000 + b"]" * 5000 + b"}"
    text += b" " * (-len(text) % 4)
    return struct.pack("<III", 0x46546C67, 2, 20 + len(text)) + \
        struct.pack("<II", len(text), 0x4E4F534A) + text


_PLY_HEAD = b"ply\nformat %s 1.0\nelement vertex %d\nproperty float x\nproperty float y\n" \
    b"property float z\nelement face %d\nproperty list uchar int vertex_indices\nend_header\n"

HOSTILE = [
    ("truncated GLB", "t.glb", _truncated_glb(), "truncated"),
    ("bad JSON chunk", "t.glb", _bad_json_chunk(), "JSON"),
    ("accessor out of range", "t.glb", _accessor_out_of_range(), "POSITION = 7"),
    ("JSON chunk nested 5000 deep", "t.glb", _deep_json_chunk(), "JSON"),
    ("GLB of random bytes", "t.glb", b"glTF" + bytes(random.Random(1).randbytes(200)), "GLB"),
    ("PLY header lies (huge)", "t.ply", _PLY_HEAD % (b"ascii", 10**9, 1) + b"0 0 0\n",
     "limit of 1000"),
    ("PLY header lies (more than the bytes)", "t.ply",
     _PLY_HEAD % (b"binary_little_endian", 900, 0) + b"\0" * 36, "bytes could hold"),
    ("PLY header lies (few)", "t.ply",
     _PLY_HEAD % (b"binary_little_endian", 5, 0) + b"\0" * 24, "PLY"),
    ("OBJ face index out of range", "t.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n", "OBJ"),
    ("OBJ of binary noise", "t.obj", b"v " + bytes(range(256)) * 4, "OBJ"),
    ("OFF header lies", "t.off", b"OFF\n3 99999999 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
     "limit of 1000"),
    ("OFF counts above its rows", "t.off", b"OFF\n30 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
     "OFF"),
    ("STL count lies", "t.stl", b"\0" * 80 + struct.pack("<I", 1000) + b"\0" * 50, "STL"),
    ("ASCII STL cut short", "t.stl", b"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0",
     "STL"),
    ("NPY header lies", "t.npy", b"\x93NUMPY\x01\x00v\x00{'descr': '<f8', 'fortran_order': "
     b"False, 'shape': (100000000, 3), }" + b" " * 46 + b"\n", ".npy"),
]


@pytest.mark.parametrize(("label", "filename", "data", "expected"), HOSTILE,
                         ids=[h[0] for h in HOSTILE])
def test_hostile_files_are_refused_naming_the_input(label: str, filename: str, data: bytes,
                                                    expected: str) -> None:
    assert expected in refused(data, filename)


@pytest.mark.parametrize("seed", range(40))
def test_corrupted_files_raise_only_input_errors(seed: int) -> None:
    """Bytes of good files flipped at random: read, or refused naming the input, nothing
    else (the fuzz runs each reader on 40 corruptions)."""
    rng = random.Random(seed)
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
    f = np.array([[0, 1, 2], [1, 3, 2]])
    good = {"t.glb": mesh_glb(v, f),
            "t.obj": b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n",
            "t.off": b"OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n3 0 1 2\n3 1 3 2\n",
            "t.ply": _PLY_HEAD % (b"ascii", 4, 2) + b"0 0 0\n1 0 0\n0 1 0\n1 1 0\n"
                     b"3 0 1 2\n3 1 3 2\n"}
    for filename, data in good.items():
        bad = bytearray(data)
        for _ in range(rng.randint(1, 4)):
            bad[rng.randrange(len(bad))] = rng.randrange(256)
        try:
            decode_upload(Upload("mesh", filename, None, bytes(bad)), takes="either",
                          limits=LIMITS)
        except InvalidInputError as exc:
            assert exc.field == "mesh"


def test_nan_vertices_reach_validation_as_nan() -> None:
    # the reader keeps them; the input's validation refuses them naming the input and row
    # (tests/service/test_hostile_e2e.py sends this file to a server)
    mesh = decode_upload(Upload("mesh", "t.obj", None,
                                b"v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"),
                         takes="mesh", limits=LIMITS)
    assert np.isnan(mesh["vertices"][1, 0])


# -- the size the fast path is chosen by --------------------------------------------------

def test_every_input_counts_its_real_size() -> None:
    from algorithms.core.graphs import Graph
    from algorithms.core.mesh import Mesh
    from service.routes.processes import input_size

    edges = np.zeros((1_000, 2), np.int64)  # 16,000 bytes
    assert input_size(Graph(n_nodes=1_001, edges=edges)) == 64 + 16_000 + 64 + 64
    mesh = Mesh(np.zeros((10, 3)), np.zeros((4, 3), np.int64))
    assert input_size(mesh) >= 240 + 96
    assert input_size([np.zeros(100), np.zeros(50)]) == 64 + 800 + 400
    assert input_size(3.5) == 64


def test_the_services_own_scenes_pass_the_scene_check() -> None:
    """GLBs as the service writes them (two parts, one node each; a root node turning z-up
    data) are read, both parts' vertices merged in order."""
    from service.gltf import scene_glb, y_up

    a = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
    b = a + 5
    data = y_up(scene_glb([{"vertices": a, "faces": np.array([[0, 1, 2]])},
                           {"vertices": b, "faces": np.array([[0, 1, 2]])}]))
    mesh = decode_upload(Upload("mesh", "s.glb", None, data), takes="mesh", limits=LIMITS)
    assert mesh["vertices"].shape == (6, 3) and mesh["faces"].shape == (2, 3)
    # +z up turned to +y: (x, y, z) -> (x, z, -y), so the second part's z = 5 became y = 5
    assert sorted(np.round(mesh["vertices"][:, 1], 6).tolist()) == [0, 0, 0, 5, 5, 5]
