"""A catalogue of malformed requests across every family: each is answered 4xx with a
problem+json that names the offending field, and the service keeps serving.

Each row: (label, process, body (a dict sent as JSON, or bytes sent as they are), extra
headers, expected status, expected field — the first ``errors[].input`` must start with it).
Python's json writes NaN and Infinity tokens, as many clients do; the service reads them so
that the error names the row.
"""

from __future__ import annotations

import io
import json
import struct
from typing import Any

import numpy as np
import pytest

from service.gltf import mesh_glb
from tests.gltf_check import glb_with

pytestmark = pytest.mark.e2e

NAN, INF = float("nan"), float("inf")
SQ = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]
MOVED = [[1, 2, 3], [1, 3, 3], [0, 2, 3], [1, 2, 4]]
STRIP = {"vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], "faces": [[0, 1, 2], [1, 3, 2]]}
LIFT = {"indices": [0, 3], "positions": [[0, 0, 0], [1, 1, 1]]}
D3 = [[0, 1, 2], [1, 0, 1], [2, 1, 0]]
# ICP is a long process (asynchronous by default); the point count its model and metric
# need is checked inside the job, and a client that waits gets that 422 problem directly
WAIT = {"Prefer": "wait=30"}


def _mesh(**change: Any) -> dict:
    return {**STRIP, **change}


def _multipart(parts: dict[str, tuple[str, bytes]], cut: int | None = None
               ) -> tuple[bytes, dict[str, str]]:
    """A multipart/form-data body of file parts and its Content-Type header; ``cut`` drops
    everything after that many bytes of the last part, as a dropped connection would."""
    boundary = "morphserve-test-boundary"
    body = b""
    for name, (filename, data) in parts.items():
        body += (f"--{boundary}\r\nContent-Disposition: form-data; name=\"{name}\"; "
                 f"filename=\"{filename}\"\r\n\r\n").encode() + data + b"\r\n"
    body = body[:len(body) - len(data) - 2 + cut] if cut is not None else \
        body + f"--{boundary}--\r\n".encode()
    return body, {"Content-Type": f"multipart/form-data; boundary={boundary}"}


def _npy(a: np.ndarray, allow_pickle: bool = False) -> bytes:
    buf = io.BytesIO()
    np.save(buf, a, allow_pickle=allow_pickle)
    return buf.getvalue()


_NPY = _npy(np.arange(12.0).reshape(4, 3))


def _pickled_npy() -> bytes:
    return _npy(np.array([{"a": 1}, None], dtype=object), allow_pickle=True)


def _huge_glb() -> bytes:
    """A valid little GLB whose JSON then claims a 1 TiB buffer."""
    glb = mesh_glb(np.array(STRIP["vertices"], float), np.array(STRIP["faces"]))
    return glb_with(glb, lambda doc: doc["buffers"][0].update(byteLength=2 ** 40))


# -- nesting and hostile files (issue 17) ------------------------------------------------

def _deep(depth: int, kind: str = "array", inner: bytes = b"1") -> bytes:
    """``depth`` levels of arrays or of objects ``{"a": ...}`` around ``inner``."""
    if kind == "array":
        return b"[" * depth + inner + b"]" * depth
    return b'{"a":' * depth + inner + b"}" * depth


def _body(inputs: bytes) -> bytes:
    return b'{"inputs": ' + inputs + b"}"


def _request(**members: Any) -> bytes:
    """A good alignment.rigid request with the members ``members`` besides its inputs."""
    return json.dumps({"inputs": {"source": SQ, "target": MOVED}, **members}).encode()


def _glb(doc: dict[str, Any], binary: bytes) -> bytes:
    """A GLB packed by hand: header, JSON chunk, binary chunk."""
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    binary += b"\0" * (-len(binary) % 4)
    chunks = struct.pack("<II", len(text), 0x4E4F534A) + text + \
        struct.pack("<II", len(binary), 0x004E4942) + binary
    return struct.pack("<III", 0x46546C67, 2, 12 + len(chunks)) + chunks


def _scene_glb(nodes: list[dict[str, Any]], roots: list[int], n_vertices: int = 3) -> bytes:
    """A mesh of ``n_vertices`` vertices (a fan of triangles) placed by ``nodes``."""
    v = np.zeros((n_vertices, 3), np.float32)
    v[:, 0] = np.arange(n_vertices)
    v[1::2, 1] = 1
    f = np.array([[0, i, i + 1] for i in range(1, n_vertices - 1)], np.uint32)
    doc = {"asset": {"version": "2.0"}, "buffers": [{"byteLength": v.nbytes + f.nbytes}],
           "bufferViews": [{"buffer": 0, "byteLength": v.nbytes},
                           {"buffer": 0, "byteOffset": v.nbytes, "byteLength": f.nbytes}],
           "accessors": [{"bufferView": 0, "componentType": 5126, "count": n_vertices,
                          "type": "VEC3", "min": v.min(0).tolist(), "max": v.max(0).tolist()},
                         {"bufferView": 1, "componentType": 5125, "count": f.size,
                          "type": "SCALAR"}],
           "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
           "nodes": nodes, "scenes": [{"nodes": roots}], "scene": 0}
    return _glb(doc, v.tobytes() + f.tobytes())


def _spec_part(spec: bytes, parts: dict[str, tuple[str, bytes]]) -> tuple[bytes, dict[str, str]]:
    return _multipart({"spec": ("spec.json", spec), **parts})


_PLY_LIES = (b"ply\nformat ascii 1.0\nelement vertex 1000000000\nproperty float x\n"
             b"property float y\nproperty float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n")


CATALOGUE: list[tuple[str, str, Any, dict[str, str], int, str]] = [
    # -- alignment ---------------------------------------------------------------------------
    ("missing target", "alignment.rigid", {"source": SQ}, {}, 422, "target"),
    ("source is a string", "alignment.rigid", {"source": "points", "target": SQ}, {}, 422,
     "source"),
    ("source is a flat list", "alignment.rigid", {"source": [1, 2, 3], "target": SQ}, {}, 422,
     "source"),
    ("ragged rows", "alignment.rigid", {"source": [[0, 0, 0], [1, 0]], "target": SQ}, {}, 422,
     "source"),
    ("booleans as coordinates", "alignment.rigid", {"source": [[True, False]] * 4,
                                                    "target": SQ}, {}, 422, "source"),
    ("NaN in source", "alignment.rigid", {"source": [[0, 0, 0], [NAN, 0, 0], [0, 1, 0],
                                                     [0, 0, 1]], "target": SQ}, {}, 422, "source"),
    ("Infinity in target", "alignment.similarity", {"source": SQ, "target": [
        [0, 0, 0], [1, 0, 0], [0, INF, 0], [0, 0, 1]]}, {}, 422, "target"),
    ("huge number overflows", "alignment.rigid", b'{"inputs": {"source": [[0,0,0],[1,0,0],'
     b'[0,1,0],[0,0,1]], "target": [[1e999,0,0],[1,0,0],[0,1,0],[0,0,1]]}}', {}, 422, "target"),
    ("finite but too large to square", "alignment.rigid", {"source": [
        [0, 0, 0], [1e300, 0, 0], [0, 1, 0], [0, 0, 1]], "target": SQ}, {}, 422, "source"),
    ("mismatched counts", "alignment.affine", {"source": SQ, "target": MOVED[:3]}, {}, 422,
     "target"),
    ("mismatched dimensions", "alignment.rigid", {"source": SQ, "target": [[0, 0]] * 4}, {}, 422,
     "target"),
    ("coincident points", "alignment.rigid", {"source": [[1, 1, 1]] * 4, "target": SQ}, {}, 422,
     "source"),
    ("too few points for an affine map", "alignment.affine", {"source": SQ[:2],
                                                              "target": MOVED[:2]}, {}, 422,
     "source"),
    ("negative weight", "alignment.similarity", {"source": SQ, "target": MOVED,
                                                 "weights": [1, -1, 1, 1]}, {}, 422, "weights"),
    ("weights of the wrong length", "alignment.rigid", {"source": SQ, "target": MOVED,
                                                        "weights": [1, 1]}, {}, 422, "weights"),
    ("unknown parameter", "alignment.rigid", {"source": SQ, "target": MOVED, "scale": True}, {},
     422, "scale"),
    ("bool given as string", "alignment.rigid", {"source": SQ, "target": MOVED,
                                                 "allow_reflection": "yes"}, {}, 422,
     "allow_reflection"),
    ("unknown option", "alignment.pca", {"source": SQ, "target": MOVED, "mode": "sideways"}, {},
     422, "mode"),
    ("empty source", "alignment.rigid", {"source": [], "target": SQ}, {}, 422, "source"),
    # -- assignment --------------------------------------------------------------------------
    ("negative k", "assignment.nearest", {"source": SQ, "target": MOVED, "k": -1}, {}, 422, "k"),
    ("k above the target size", "assignment.nearest", {"source": SQ, "target": MOVED, "k": 9},
     {}, 422, "k"),
    ("fractional k", "assignment.nearest", {"source": SQ, "target": MOVED, "k": 1.5}, {}, 422,
     "k"),
    ("unknown direction", "assignment.nearest", {"source": SQ, "target": MOVED,
                                                 "direction": "sideways"}, {}, 422, "direction"),
    ("negative max_distance", "assignment.nearest", {"source": SQ, "target": MOVED,
                                                     "max_distance": -1}, {}, 422, "max_distance"),
    ("unknown metric", "assignment.bipartite", {"source": SQ, "target": MOVED,
                                                "metric": "cosine"}, {}, 422, "metric"),
    ("zero regularisation", "assignment.optimal_transport", {"source": SQ, "target": MOVED,
                                                             "method": "sinkhorn", "reg": 0}, {},
     422, "reg"),
    ("masses all zero", "assignment.optimal_transport", {"source": SQ, "target": MOVED,
                                                         "source_weights": [0, 0, 0, 0]}, {},
     422, "source_weights"),
    ("NaN mass", "assignment.optimal_transport", {"source": SQ, "target": MOVED,
                                                  "target_weights": [1, NAN, 1, 1]}, {}, 422,
     "target_weights"),
    ("empty target", "assignment.distance", {"source": SQ, "target": []}, {}, 422, "target"),
    # -- deformation -------------------------------------------------------------------------
    ("face index out of range", "deformation.arap", {"mesh": _mesh(faces=[[0, 1, 9]]),
                                                     "handles": LIFT}, {}, 422, "mesh"),
    ("negative face index", "deformation.harmonic", {"mesh": _mesh(faces=[[0, -1, 2]]),
                                                     "handles": LIFT}, {}, 422, "mesh"),
    ("zero-area face", "deformation.laplacian", {"mesh": _mesh(
        vertices=[[0, 0, 0], [1, 0, 0], [2, 0, 0], [1, 1, 0]]), "handles": LIFT}, {}, 422,
     "mesh"),
    ("faces with two corners", "deformation.biharmonic", {"mesh": _mesh(faces=[[0, 1]]),
                                                          "handles": LIFT}, {}, 422, "mesh"),
    ("NaN vertex", "deformation.arap", {"mesh": _mesh(vertices=[[0, 0, 0], [1, 0, 0],
                                                                [0, NAN, 0], [1, 1, 0]]),
                                        "handles": LIFT}, {}, 422, "mesh"),
    ("handle index out of range", "deformation.arap", {"mesh": STRIP, "handles": {
        "indices": [0, 7], "positions": [[0, 0, 0], [1, 1, 1]]}}, {}, 422, "handles"),
    ("handles without positions", "deformation.harmonic", {"mesh": STRIP,
                                                           "handles": {"indices": [0]}}, {}, 422,
     "handles"),
    ("handle positions of the wrong width", "deformation.laplacian", {"mesh": STRIP, "handles": {
        "indices": [0, 3], "positions": [[0, 0], [1, 1]]}}, {}, 422, "handles"),
    ("mesh is a list", "deformation.arap", {"mesh": [[0, 0, 0]], "handles": LIFT}, {}, 422,
     "mesh"),
    ("zero iterations", "deformation.arap", {"mesh": STRIP, "handles": LIFT,
                                             "max_iterations": 0}, {}, 422, "max_iterations"),
    # -- layout ------------------------------------------------------------------------------
    ("distance matrix not square", "layout.mds", {"distances": [[0, 1, 2], [1, 0, 1]]}, {}, 422,
     "distances"),
    ("negative distance", "layout.stress", {"distances": [[0, -1, 2], [-1, 0, 1], [2, 1, 0]]},
     {}, 422, "distances"),
    ("distances hold a string", "layout.mds", {"distances": [[0, "far"], ["far", 0]]}, {},
     422, "distances"),
    ("too many components", "layout.mds", {"distances": D3, "n_components": 0}, {}, 422,
     "n_components"),
    ("graph edge out of range", "layout.laplacian", {"graph": {"nodes": 3, "edges": [[0, 9]]},
                                                     "pins": {"indices": [0], "positions": [
                                                         [0, 0]]}}, {}, 422, "graph"),
    # -- registration ------------------------------------------------------------------------
    ("unknown model", "registration.icp", {"source": SQ, "target": MOVED, "model": "rubber"}, {},
     422, "model"),
    ("overlap above one", "registration.icp", {"source": SQ, "target": MOVED, "overlap": 1.5},
     {}, 422, "overlap"),
    ("init matrix of the wrong size", "registration.icp", {"source": SQ, "target": MOVED,
                                                           "init": [[1, 0], [0, 1]]},
     {}, 422, "init"),
    ("normals of the wrong count", "registration.icp", {"source": SQ * 2, "target": MOVED * 2,
                                                        "metric": "point_to_plane",
                                                        "target_normals": [[0, 0, 1]]},
     {}, 422, "target_normals"),
    ("too few points for point-to-plane", "registration.icp", {
        "source": SQ, "target": MOVED, "metric": "point_to_plane"}, WAIT, 422, "source"),
    ("RANSAC features on 2-D points", "registration.ransac", {
        "source": [[0, 0], [1, 0], [0, 1], [1, 2]], "target": [[0, 0], [1, 0], [0, 1], [1, 2]]},
     {}, 422, "features"),
    ("unknown feature kind", "registration.ransac", {"source": SQ, "target": MOVED,
                                                     "features": "sift"}, {}, 422, "features"),
    ("collinear source for RANSAC", "registration.ransac", {
        "source": [[0, 0, 0], [1, 1, 1], [2, 2, 2], [3, 3, 3]], "target": MOVED}, {}, 422,
     "source"),
    ("voxel leaves too few points", "registration.ransac", {
        "source": SQ, "target": MOVED, "voxel_size": 100}, WAIT, 422, "voxel_size"),
    ("outlier weight of one", "registration.cpd", {"source": SQ, "target": MOVED, "w": 1.0}, {},
     422, "w"),
    ("unknown cpd model", "registration.cpd", {"source": SQ, "target": MOVED,
                                               "model": "similarity"}, {}, 422, "model"),
    ("NaN in one set", "registration.multiway", {"sets": [SQ, SQ, [
        [0, 0, 0], [1, NAN, 0], [0, 1, 0], [0, 0, 1]]]}, {}, 422, "sets[2]"),
    ("sets of different lengths", "registration.multiway", {"sets": [SQ, SQ[:3]]}, {}, 422,
     "sets[1]"),
    ("a single set", "registration.multiway", {"sets": [SQ]}, {}, 422, "sets"),
    # -- parameterization --------------------------------------------------------------------
    ("closed mesh is not a disk", "parameterization.harmonic", {"mesh": {
        "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]],
        "faces": [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]}}, {}, 422, "mesh"),
    ("unknown boundary shape", "parameterization.tutte", {"mesh": STRIP, "boundary": "star"}, {},
     422, "boundary"),
    ("stretch power not positive", "parameterization.stretch_minimizing", {
        "mesh": STRIP, "power": 0}, {}, 422, "power"),
    ("bijective zero iterations", "parameterization.bijective", {
        "mesh": STRIP, "max_iterations": 0}, {}, 422, "max_iterations"),
    # -- embedding, clustering, classification ------------------------------------------------
    ("more components than dimensions", "embedding.pca", {"points": SQ, "n_components": 5}, {},
     422, "n_components"),
    ("more neighbours than points", "embedding.isomap", {"points": SQ, "n_neighbors": 9}, {}, 422,
     "n_neighbors"),
    ("perplexity not below n", "embedding.tsne", {"points": SQ, "perplexity": 30}, {}, 422,
     "perplexity"),
    ("fft gradient in 3-D", "embedding.tsne", {"points": SQ, "method": "fft", "perplexity": 1,
                                               "n_components": 3}, {}, 422, "n_components"),
    ("SNE perplexity not below n", "embedding.sne", {"points": SQ, "perplexity": 4}, {}, 422,
     "perplexity"),
    ("zero clusters", "clustering.spectral", {"points": SQ, "n_clusters": 0}, {}, 422,
     "n_clusters"),
    ("labels of the wrong length", "classification.lda", {"points": SQ, "labels": [0, 1]}, {},
     422, "labels"),
    # -- interpolation -----------------------------------------------------------------------
    ("target mesh with other faces", "interpolation.arap", {"source": STRIP, "target": _mesh(
        faces=[[0, 1, 3], [0, 3, 2]])}, {}, 422, "target.faces"),
    ("target with fewer vertices", "interpolation.poisson", {"source": STRIP, "target": _mesh(
        vertices=STRIP["vertices"][:3], faces=[[0, 1, 2]])}, {}, 422, "target.vertices"),
    ("time outside [0, 1]", "interpolation.poisson", {"source": STRIP, "target": STRIP,
                                                      "times": [0, 0.5, 2]}, {}, 422, "times"),
    ("times not increasing", "interpolation.affine", {"source": SQ, "target": MOVED,
                                                      "times": [0.5, 0.25]}, {}, 422, "times"),
    ("NaN time", "interpolation.rigid", {"source": SQ, "target": MOVED, "times": [0, NAN]}, {},
     422, "times"),
    ("transform of the wrong size", "interpolation.affine", {"source": SQ, "transform": [
        [1, 0, 0], [0, 1, 0], [0, 0, 1]]}, {}, 422, "transform"),
    ("neither target nor transform", "interpolation.affine", {"source": SQ}, {}, 422, "target"),
    ("mirroring transform refused", "interpolation.affine", {"source": SQ, "transform": [
        [-1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]}, {}, 422, "transform"),
    # -- uploads (multipart/form-data) -------------------------------------------------------
    ("truncated upload", "alignment.rigid", *_multipart({"source": ("a.npy", _NPY)}, cut=40),
     400, ""),
    ("GLB declaring a huge buffer", "parameterization.tutte",
     *_multipart({"mesh": ("big.glb", _huge_glb())}), 422, "mesh"),
    ("upload for no such input", "alignment.rigid",
     *_multipart({"sauce": ("a.npy", _NPY)}), 422, "sauce"),
    ("pickled object array", "alignment.rigid",
     *_multipart({"source": ("a.npy", _pickled_npy())}), 422, "source"),
    ("file of unknown format", "alignment.rigid",
     *_multipart({"source": ("a.bin", b"\x00\x01garbage")}), 422, "source"),
    ("point cloud for a mesh", "parameterization.tutte",
     *_multipart({"mesh": ("pts.ply", b"ply\nformat ascii 1.0\nelement vertex 3\nproperty "
                           b"float x\nproperty float y\nproperty float z\nend_header\n"
                           b"0 0 0\n1 0 0\n0 1 0\n")}), 422, "mesh"),
    ("multipart without boundary", "alignment.rigid", b"--x--",
     {"Content-Type": "multipart/form-data"}, 400, ""),
    # -- nesting (issue 17): deeper than the JSON parser's 1024 levels, or than the walks
    # over an input go (max_input_depth, 32) ---------------------------------------------
    ("body nested 1500 arrays deep", "alignment.rigid", _body(b'{"source": ' + _deep(1500)
                                                              + b"}"), {}, 400, ""),
    ("body nested 10000 objects deep", "alignment.rigid", _deep(10_000, "object"), {}, 400, ""),
    ("NaN before 10000 levels", "alignment.rigid", _body(b'{"source": [NaN, ' + _deep(10_000)
                                                         + b"]}"), {}, 400, ""),
    ("input nested 1000 objects deep", "alignment.rigid", _body(
        b'{"target": [[0,0],[1,0],[0,1]], "source": ' + _deep(1000, "object") + b"}"), {},
     422, "source"),
    ("href inside 900 objects", "parameterization.tutte", _body(b'{"mesh": ' + _deep(
        900, "object", b'{"href": "/jobs/x/results/mesh"}') + b"}"), {}, 422, "mesh"),
    ("spec nested 1500 arrays deep", "alignment.rigid",
     *_spec_part(_deep(1500), {"source": ("a.npy", _NPY)}), 400, "spec"),
    ("spec nested 10000 objects deep", "alignment.rigid",
     *_spec_part(_deep(10_000, "object"), {"source": ("a.npy", _NPY)}), 400, "spec"),
    ("JSON part nested 10000 deep", "alignment.rigid",
     *_multipart({"source": ("a.json", _deep(10_000))}), 422, "source"),
    ("JSON part nested 1000 objects deep", "alignment.rigid",
     *_multipart({"source": ("a.json", _deep(1000, "object"))}), 422, "source"),
    ("part name nested 1000 members deep", "deformation.arap",
     *_multipart({"mesh" + ".a" * 1000: ("a.npy", _NPY)}), 422, "mesh"),
    # -- hostile geometry files (issue 17) --------------------------------------------------
    ("GLB scene with a cycle", "parameterization.tutte", *_multipart({"mesh": (
        "cycle.glb", _scene_glb([{"mesh": 0, "children": [1]}, {"children": [0]}], [0]))}),
     422, "mesh"),
    ("GLB chain of 100 nested nodes", "parameterization.tutte", *_multipart({"mesh": (
        "chain.glb", _scene_glb([{"children": [i + 1]} for i in range(99)] + [{"mesh": 0}],
                                [0]))}), 422, "mesh"),
    ("GLB of 10001 nodes", "parameterization.tutte", *_multipart({"mesh": (
        "nodes.glb", _scene_glb([{"mesh": 0}] * 10_001, [0]))}), 422, "mesh"),
    ("GLB instancing to 10M vertices", "parameterization.tutte", *_multipart({"mesh": (
        "instanced.glb", _scene_glb([{"mesh": 0}], [0] * 10_001, n_vertices=1000))}),
     422, "mesh"),
    ("GLB accessor out of range", "parameterization.tutte", *_multipart({"mesh": (
        "acc.glb", _scene_glb([{"mesh": 7}], [0]))}), 422, "mesh"),
    ("truncated GLB", "parameterization.tutte", *_multipart({"mesh": (
        "cut.glb", _scene_glb([{"mesh": 0}], [0])[:-10])}), 422, "mesh"),
    ("PLY header lies about its count", "alignment.rigid",
     *_multipart({"source": ("lies.ply", _PLY_LIES)}), 422, "source"),
    ("OBJ face index out of range", "parameterization.tutte", *_multipart({"mesh": (
        "oob.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")}), 422, "mesh"),
    ("OBJ with a NaN vertex", "parameterization.tutte", *_multipart({"mesh": (
        "nan.obj", b"v 0 0 0\nv nan 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n")}),
     422, "mesh"),
    # -- no silent acceptance (issue 17, class 9) ---------------------------------------------
    ("asymmetric distances", "layout.mds", {"distances": [[0, 3, 4], [3.5, 0, 5], [4, 5, 0]]},
     {}, 422, "distances"),
    ("nonzero diagonal", "layout.stress", {"distances": [[0, 3, 4], [3, 0.5, 5], [4, 5, 0]]},
     {}, 422, "distances"),
    ("a pair given twice with two distances", "layout.mds", {"distance_pairs": [
        [0, 1, 3.0], [1, 0, 3.5], [0, 2, 4.0], [1, 2, 5.0]]}, {}, 422, "distance_pairs"),
    ("more components than points", "layout.mds", {"distances": D3, "n_components": 4}, {},
     422, "n_components"),
    ("more LLE components than dimensions", "embedding.lle", {"points": [
        [0, 0], [1, 0.2], [0.3, 1], [1.2, 1.1], [0.5, 0.4], [2, 0.1]], "n_components": 3,
        "n_neighbors": 3}, {}, 422, "n_components"),
    ("unknown mode", "alignment.rigid", _request(mode="fast"), {}, 422, "mode"),
    # -- callbacks (issue 17, class 6): subscriber URLs httpx cannot send to ---------------------
    ("subscriber URL with a TAB", "alignment.rigid", _request(subscriber={
        "successUri": "http://127.0.0.1:8000/a\tb"}), {}, 422, "subscriber.successUri"),
    ("subscriber URL with a bad port", "alignment.rigid", _request(subscriber={
        "failedUri": "http://127.0.0.1:99999/"}), {}, 422, "subscriber.failedUri"),
    # -- results by reference ------------------------------------------------------------------
    ("href to another host", "parameterization.tutte", {"mesh": {
        "href": "http://example.com/jobs/x/results/mesh"}}, {}, 422, "mesh"),
    ("href to no job", "parameterization.tutte", {"mesh": {
        "href": "/jobs/nope/results/mesh"}}, {}, 422, "mesh"),
    # -- the request itself ------------------------------------------------------------------
    ("not JSON", "alignment.rigid", b"source=1&target=2", {}, 400, ""),
    ("truncated JSON", "alignment.rigid", b'{"inputs": {"source": [[0, 0, 0], [1, 0', {}, 400,
     ""),
    ("inputs is a list", "alignment.rigid", b'{"inputs": [1, 2]}', {}, 422, "inputs"),
    ("unknown body member", "alignment.rigid", b'{"inputs": {}, "priority": 9}', {}, 422,
     "priority"),
    ("form content type", "alignment.rigid", {"source": SQ, "target": MOVED},
     {"Content-Type": "application/x-www-form-urlencoded"}, 415, ""),
    ("negative timeLimit", "alignment.rigid", b'{"inputs": {"source": [[0,0],[1,0],[0,1]], '
     b'"target": [[0,0],[1,0],[0,1]]}, "timeLimit": -1}', {}, 422, "timeLimit"),
    ("bad Prefer wait", "alignment.rigid", {"source": SQ, "target": MOVED},
     {"Prefer": "wait=soon"}, 422, "Prefer"),
]


def _ids(row: tuple) -> str:
    return row[0].replace(" ", "-")


@pytest.mark.parametrize("row", CATALOGUE, ids=[_ids(r) for r in CATALOGUE])
def test_malformed_request_is_a_4xx_problem_naming_the_field(http, server, row) -> None:
    label, process, body, headers, status, field = row
    logged = server.log.stat().st_size
    if isinstance(body, dict):
        raw = json.dumps({"inputs": body}).encode()
    else:
        raw = body
    r = http.post(f"/processes/{process}/execution", content=raw,
                  headers={"Content-Type": "application/json", **headers})
    assert r.status_code == status, (label, r.status_code, r.text)
    assert r.headers["content-type"] == "application/problem+json", (label, r.headers)
    problem = r.json()
    assert problem["status"] == status and problem["type"].startswith("/problems/")
    assert problem["detail"], label
    if field:
        names = [e.get("input", "") for e in problem.get("errors", [])]
        assert names and names[0].startswith(field), (label, names, problem)
    assert http.get("/healthz").status_code == 200
    with open(server.log, "rb") as log:  # a client's error is no traceback in the log
        log.seek(logged)
        assert b"Traceback" not in log.read(), (label, server.tail())


def test_the_catalogue_covers_every_family_and_has_forty_rows() -> None:
    from service.catalog import registry

    families = {p.split(".")[0] for p in registry}
    covered = {row[1].split(".")[0] for row in CATALOGUE}
    # a new family must bring its malformed rows here
    assert covered == families - {"diagnostics"}
    assert len(CATALOGUE) >= 40


def test_the_service_still_serves_after_the_catalogue(http) -> None:
    r = http.post("/processes/alignment.rigid/execution",
                  json={"inputs": {"source": SQ, "target": MOVED}})
    assert r.status_code == 200 and r.json()["rmse"] < 1e-12
