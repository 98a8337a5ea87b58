"""Typed binary arrays inline in JSON ({"dtype", "shape", "data": base64}) over HTTP: the
same answers as JSON lists, bit-exact values, float32 and integer dtypes, and errors that
name the input path; and the SDK's encoder against the service's decoder."""

from __future__ import annotations

import base64
import json

import numpy as np
import pytest

from morphserve._models import BINARY_ABOVE, binary_array, to_json_value
from service.binary import decode_arrays, owned
from tests.live import execute

pytestmark = pytest.mark.e2e


def b64(a: np.ndarray, dtype: str | None = None) -> dict:
    a = np.ascontiguousarray(a, dtype=dtype or a.dtype)
    return {"dtype": a.dtype.str, "shape": list(a.shape),
            "data": base64.b64encode(a.tobytes()).decode()}


def test_binary_and_list_inputs_give_the_same_answer(http) -> None:
    rng = np.random.default_rng(3)
    X = rng.normal(size=(1500, 3))
    Y = X @ np.array([[0, -1, 0], [1, 0, 0], [0, 0, 1.0]]).T + [1, 2, 3]
    as_lists = execute(http, "alignment.rigid", {"source": X.tolist(), "target": Y.tolist()},
                       prefer=None)
    as_binary = execute(http, "alignment.rigid", {"source": b64(X), "target": b64(Y)}, prefer=None)
    assert as_lists.status_code == as_binary.status_code == 200, as_binary.text
    assert as_binary.json()["transform"] == as_lists.json()["transform"]  # bit for bit


def test_values_arrive_bit_exact(http) -> None:
    # pinned positions come back exactly as sent: random doubles with every mantissa bit used
    rng = np.random.default_rng(5)
    pins = rng.normal(size=(3, 2)) * np.array([1e-300, 1e90])
    graph = {"nodes": 4, "edges": [[0, 1], [1, 2], [2, 0], [0, 3], [1, 3], [2, 3]]}
    r = execute(http, "layout.laplacian", {"graph": graph, "pins": {
        "indices": [0, 1, 2], "positions": b64(pins)}}, prefer=None)
    assert r.status_code == 200, r.text
    got = np.array(r.json()["positions"])[:3]
    assert got.tobytes() == pins.tobytes()


def test_float32_and_int32_inputs_are_accepted(http) -> None:
    strip = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], dtype=np.float32)
    faces = np.array([[0, 1, 2], [1, 3, 2]], dtype=np.int32)
    r = execute(http, "deformation.harmonic", {
        "mesh": {"vertices": b64(strip), "faces": b64(faces)},
        "handles": {"indices": b64(np.array([0, 3], np.int64)),
                    "positions": b64(np.array([[0, 0, 0], [1, 1, 1]], np.float32))}},
        prefer=None)
    assert r.status_code == 200, r.text
    out = np.array(r.json()["mesh"]["vertices"])
    np.testing.assert_array_equal(out[[0, 3]], [[0, 0, 0], [1, 1, 1]])
    np.testing.assert_array_equal(r.json()["mesh"]["faces"], faces)


GOOD = b64(np.zeros((4, 3)))


@pytest.mark.parametrize("bad, fragment", [
    ({**GOOD, "dtype": "complex128"}, "dtype of integers or floats"),
    ({**GOOD, "dtype": "object"}, "dtype of integers or floats"),
    ({**GOOD, "dtype": 8}, "dtype of integers or floats"),
    ({**GOOD, "dtype": "float128"}, "dtype of integers or floats"),
    ({**GOOD, "shape": [-4, 3]}, "non-negative integers"),
    ({**GOOD, "shape": "4x3"}, "non-negative integers"),
    ({**GOOD, "shape": []}, "non-negative integers"),
    ({**GOOD, "shape": [4, 3, 1, 1, 1]}, "non-negative integers"),
    ({**GOOD, "data": "not base64!"}, "valid base64"),
    ({**GOOD, "data": 12}, "base64 string"),
    ({**GOOD, "shape": [5, 3]}, "to hold 120 bytes, got 96"),
    ({**GOOD, "shape": [1, 1]}, "longer base64 string"),
])
def test_malformed_binary_arrays_name_the_input(http, bad: dict, fragment: str) -> None:
    r = execute(http, "alignment.rigid", {"source": bad, "target": GOOD}, prefer=None)
    assert r.status_code == 422, r.text
    assert r.headers["content-type"] == "application/problem+json"
    body = r.json()
    assert body["errors"][0]["input"] == "source" and fragment in body["detail"], body
    nested = execute(http, "deformation.arap", {
        "mesh": {"vertices": bad, "faces": [[0, 1, 2]]},
        "handles": {"indices": [0], "positions": [[0, 0, 0]]}}, prefer=None)
    assert nested.status_code == 422
    assert nested.json()["errors"][0]["input"] == "mesh.vertices", nested.json()


def test_nan_in_a_binary_array_names_its_row(http) -> None:
    X = np.zeros((4, 3))
    X[2, 1] = np.nan
    r = execute(http, "alignment.rigid", {"source": b64(X), "target": GOOD}, prefer=None)
    assert r.status_code == 422
    assert r.json()["errors"][0]["input"] == "source" and "row 2" in r.json()["detail"]


def test_the_sdk_encoder_and_the_service_decoder_agree() -> None:
    rng = np.random.default_rng(0)
    for a in (rng.normal(size=(BINARY_ABOVE, 3)), rng.normal(size=(2000, 2)).astype(">f8"),
              rng.integers(-9, 9, size=(700, 3)).astype(np.int32),
              np.empty((0, 3)), rng.random(5000).astype(np.float32)):
        sent = to_json_value(a, "x")
        assert isinstance(sent, dict) and sent == binary_array(a)
        back = decode_arrays(sent, "x")
        assert back.shape == a.shape and back.dtype == a.dtype.newbyteorder("=")
        mine = owned({"x": back})["x"]  # what a method in this process gets: it may work
        assert mine.flags.writeable and mine.flags.aligned  # in place on its inputs
        assert mine.tobytes() == back.tobytes()
        assert back.tobytes() == a.astype(a.dtype.newbyteorder("=")).tobytes()
    small = rng.normal(size=(10, 3))
    assert to_json_value(small, "x") == small.tolist()  # small arrays stay readable lists
    assert to_json_value(np.array([True, False]), "x") == [True, False]


def test_owned_copies_views_only() -> None:
    """Arrays that own writable, aligned memory are passed on as they are; read-only and
    misaligned views (of a body, of decoded bytes) are copied, in meshes too."""
    from algorithms.core.mesh import Mesh

    mine = np.arange(12.0).reshape(4, 3)
    body = bytearray(8 * 12 + 1)
    misaligned = np.frombuffer(body, dtype=np.float64, count=12, offset=1).reshape(4, 3)
    readonly = np.frombuffer(mine.tobytes(), dtype=np.float64).reshape(4, 3)
    assert not misaligned.flags.aligned and not readonly.flags.writeable
    faces = np.frombuffer(np.array([[0, 1, 2]], np.int64).tobytes(), dtype=np.int64)
    mesh = Mesh(vertices=mine, faces=faces.reshape(1, 3))
    out = owned({"a": mine, "b": misaligned, "c": readonly, "m": mesh, "k": 3})
    assert out["a"] is mine and out["k"] == 3
    for name, src in (("b", misaligned), ("c", readonly)):
        assert out[name] is not src and out[name].flags.writeable and out[name].flags.aligned
        np.testing.assert_array_equal(out[name], src)
    assert out["m"].vertices is mine and out["m"].faces.flags.writeable
    np.testing.assert_array_equal(out["m"].faces, [[0, 1, 2]])


def test_large_json_bodies_are_kept_as_sent(spooling_server) -> None:  # noqa: ANN001
    """A large JSON body is written to disk as it arrives: typed binary arrays stay in the
    job's inputs file as the base64 text they came as (no second copy of the arrays), JSON
    lists are not kept beside the arrays parsed from them; the worker reads the same bits,
    and a body that fails validation leaves nothing."""
    from algorithms.alignment import rigid
    from service.jobs.spool import MAGIC

    data = spooling_server.data_dir
    with spooling_server.client() as c:
        rng = np.random.default_rng(8)
        X = rng.normal(size=(5000, 3))
        Y = X[:, [1, 0, 2]] * [1, -1, 1] + 2.0
        mine = rigid(X, Y)
        for inputs, kept in (({"source": b64(X), "target": b64(Y)}, None),
                             ({"source": X.tolist(), "target": Y.tolist()}, 2 * X.nbytes)):
            body = json.dumps({"inputs": inputs}).encode()
            r = c.post("/processes/alignment.rigid/execution", content=body,
                       headers={"Content-Type": "application/json"})
            assert r.status_code == 200, r.text
            np.testing.assert_array_equal(r.json()["rotation"], mine.rotation)
            np.testing.assert_array_equal(r.json()["translation"], mine.translation)
            job = r.headers["content-location"].split("/")[2]
            path = data / "inputs" / f"{job}.pkl"
            assert path.read_bytes()[-len(MAGIC):] == MAGIC
            size = kept or len(body)  # the arrays' base64 text, as sent; the arrays
            assert size <= path.stat().st_size < size + 4096
        assert len(body) > 2 * X.nbytes + 4096  # the lists were not kept
        files = sorted((data / "inputs").iterdir())
        bad = X.copy()
        bad[7, 1] = np.nan
        r = execute(c, "alignment.rigid", {"source": b64(bad), "target": b64(Y)}, prefer=None)
        assert r.status_code == 422 and r.json()["errors"][0]["input"] == "source"
        assert sorted((data / "inputs").iterdir()) == files


def _escaped(body: bytes) -> bytes:
    """The same JSON document with its first 'A' in every string run of them written as an
    escape: nothing of it is cut out before parsing."""
    return body.replace(b'"AAAA', b'"\\u0041AAA')


@pytest.mark.parametrize("doc", [
    {"inputs": {"source": GOOD, "target": GOOD}, "data": "A" * 5000},  # unknown member
    {"inputs": {"source": {"shape": [4], "data": "A" * 5000}, "target": GOOD}},  # no dtype
    {"inputs": {"source": {"dtype": "<f8", "shape": [4, 3], "data": "A" * 5000},
                "target": GOOD}},  # too long for its shape
    {"inputs": {"source": {"dtype": "<f8", "shape": [1000, 3], "data": "A" * 5000 + "!"},
                "target": GOOD}},  # not base64
])
def test_bodies_with_long_strings_get_the_answer_their_document_gets(http, doc: dict) -> None:
    body = json.dumps(doc).encode()
    assert _escaped(body) != body
    r = http.post("/processes/alignment.rigid/execution", content=body,
                  headers={"Content-Type": "application/json"})
    same = http.post("/processes/alignment.rigid/execution", content=_escaped(body),
                     headers={"Content-Type": "application/json"})
    assert r.status_code == same.status_code == 422, r.text
    assert r.json() == same.json()


def test_base64_with_escaped_slashes_is_read(http) -> None:
    """JSON writers that escape every slash (PHP's json_encode) send base64 as 'a\\/b'."""
    rng = np.random.default_rng(9)
    X = rng.normal(size=(1500, 3))
    Y = X + [1.0, 2.0, 3.0]
    body = json.dumps({"inputs": {"source": b64(X), "target": b64(Y)}})
    assert "/" in body
    r = http.post("/processes/alignment.rigid/execution",
                  content=body.replace("/", "\\/").encode(),
                  headers={"Content-Type": "application/json"})
    plain = execute(http, "alignment.rigid", {"source": b64(X), "target": b64(Y)}, prefer=None)
    assert r.status_code == plain.status_code == 200, r.text
    assert r.json() == plain.json()
