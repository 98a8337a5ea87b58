"""Geometry in and out of the service: uploads, references to earlier results, and the
formats a result can be sent in.

Inputs
    An execute request may be ``multipart/form-data``: a part named ``spec`` holds the JSON
    execute request (``{"inputs": {...}, "outputs": ..., "response": ...}``), and every other
    part is one input, named by the part (``mesh``, ``source``), or one member of an object
    input (``mesh.vertices``). A part is read by its file name's suffix, else its content type,
    else its first bytes:

    - ``.npy`` (``application/x-npy``): a numpy array (``allow_pickle=False``), bit-exact.
    - ``.ply``, ``.obj``, ``.off``, ``.glb``/``.gltf``: a mesh or point cloud loaded by trimesh
      with ``process=False``, so the vertices keep the file's order and indices in other
      inputs (handles, pins) still refer to them. A scene is merged into one mesh.
    - ``.stl``: loaded by trimesh with its default processing, which merges the triangles'
      repeated corners into shared vertices (an STL file has no vertex list of its own).

    A mesh file given for a point input gives its vertices; a point cloud given for a mesh
    input is refused (422). Every part is bounded by ``max_input_bytes`` (413 naming it).

    Files are decoded in worker threads (:func:`decode_in_thread`), never on the event loop,
    and a file that takes longer than ``decode_time_limit`` is refused. What a file declares
    is checked before a reader expands it (:class:`DecodeLimits`): a GLB's scene must be a
    forest (no cycles, one parent per node) of at most ``max_file_nodes`` nodes nested at
    most ``max_file_depth`` levels, and the vertices and faces its nodes would make by
    instancing their meshes, like the element counts of a PLY or OFF header, at most
    ``max_points``. Whatever a reader raises on a malformed file is a 422 naming the part.

    Any input, or member of an input, may instead be a reference to an output of an earlier
    job of the same API key: ``{"href": "/jobs/{jobId}/results/{output}"}`` (or the same path
    under this service's own URL). Other URLs are refused: the service never fetches from
    the network on a client's behalf.

Outputs
    JSON results documents (arrays as nested lists or, when the client prefers
    ``arrays=binary``, typed binary arrays, whose shape survives even when empty); a single
    array as ``.npy`` (``application/x-npy``); and geometry as glTF binary
    (``model/gltf-binary``, the scene its catalog entry declares: :mod:`service.scenes`),
    turned +z to +y for z-up data on request (:func:`turned_up`, ``?up=z``).
"""

from __future__ import annotations

import asyncio
import functools
import io
import re
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import PurePosixPath
from typing import Any
from urllib.parse import urlsplit

import numpy as np
from starlette.responses import Response

from algorithms.core.errors import InvalidInputError
from service.binary import MAX_DEPTH, too_deep
from service.errors import ServiceError

__all__ = ["Upload", "DecodeLimits", "parse_multipart", "decode_upload", "decode_in_thread",
           "place_upload", "resolve_refs", "REF_PATTERN", "npy_bytes", "MEDIA_GLB", "MEDIA_NPY",
           "MEDIA_JSON", "negotiate", "turned_up"]

MEDIA_JSON = "application/json"
MEDIA_GLB = "model/gltf-binary"
MEDIA_NPY = "application/x-npy"

#: File suffixes (and the content types that mean the same) read as inputs.
_SUFFIXES = {"npy": "npy", "ply": "ply", "obj": "obj", "stl": "stl", "off": "off",
             "glb": "glb", "gltf": "gltf"}
_CONTENT_TYPES = {MEDIA_NPY: "npy", "application/npy": "npy", MEDIA_GLB: "glb",
                  "model/gltf+json": "gltf", "model/stl": "stl", "application/sla": "stl",
                  "model/obj": "obj", "text/plain+obj": "obj", "application/ply": "ply",
                  "model/ply": "ply", "model/off": "off"}


@dataclass(frozen=True)
class Upload:
    """One file part of a multipart request."""

    name: str
    filename: str | None
    content_type: str | None
    data: bytes | bytearray | memoryview
    """The part's bytes: a view of the request body where possible (no copy)."""

    def head(self, n: int = 64) -> bytes:
        return bytes(self.data[:n])


def _malformed(detail: str) -> ServiceError:
    return ServiceError("malformed-body", detail)


def _invalid(field: str, message: str) -> ServiceError:
    return ServiceError("invalid-input", f"{field}: {message}",
                        errors=[{"input": field, "message": message}])


def parse_multipart(body: bytes | bytearray, content_type: str, *, max_input_bytes: int
                    ) -> tuple[bytes | None, dict[str, Upload]]:
    """The ``spec`` part's bytes (None when absent) and the other parts by name.

    Raises ServiceError: 400 for a body that is not complete multipart (no boundary, cut
    short, a part without a name), 413 for a part above ``max_input_bytes`` (naming it),
    422 for a part named twice.
    """
    from python_multipart import MultipartParser
    from python_multipart.multipart import parse_options_header

    _, options = parse_options_header(content_type)
    boundary = options.get(b"boundary")
    if not boundary:
        raise _malformed("A multipart/form-data body needs a boundary parameter in its "
                         "Content-Type header.")
    parts: list[dict[str, Any]] = []
    current: dict[str, Any] = {}
    header_field: list[bytes] = []
    header_value: list[bytes] = []
    ended = False

    def on_part_begin() -> None:
        current.clear()
        current.update(headers={}, chunks=[], size=0)

    def on_header_field(data: bytes, start: int, end: int) -> None:
        header_field.append(data[start:end])

    def on_header_value(data: bytes, start: int, end: int) -> None:
        header_value.append(data[start:end])

    def on_header_end() -> None:
        current["headers"][b"".join(header_field).decode("latin-1").lower()] = \
            b"".join(header_value).decode("latin-1")
        header_field.clear()
        header_value.clear()

    def on_headers_finished() -> None:
        disposition = current["headers"].get("content-disposition", "")
        _, params = parse_options_header(disposition)
        name = params.get(b"name")
        if not name:
            raise _malformed("Every part of a multipart body needs a Content-Disposition "
                             "with a name (the input it holds).")
        current["name"] = name.decode("utf-8", "replace")
        filename = params.get(b"filename")
        current["filename"] = filename.decode("utf-8", "replace") if filename else None

    def on_part_data(data: bytes, start: int, end: int) -> None:
        current["size"] += end - start
        if current["size"] > max_input_bytes:
            raise ServiceError(
                "payload-too-large", f"The part {current['name']!r} exceeds the limit of "
                f"{max_input_bytes} bytes per input.",
                errors=[{"input": current["name"],
                         "message": f"larger than {max_input_bytes} bytes"}])
        current["chunks"].append(memoryview(data)[start:end])  # a view, not a copy

    def on_part_end() -> None:
        parts.append(dict(current))

    def on_end() -> None:
        nonlocal ended
        ended = True

    parser = MultipartParser(boundary, {
        "on_part_begin": on_part_begin, "on_header_field": on_header_field,
        "on_header_value": on_header_value, "on_header_end": on_header_end,
        "on_headers_finished": on_headers_finished, "on_part_data": on_part_data,
        "on_part_end": on_part_end, "on_end": on_end})
    try:
        # python_multipart annotates `bytes`, but it only indexes, slices and searches the
        # data (and hands it to the callbacks above), all of which a bytearray supports
        parser.write(body)  # type: ignore[arg-type]
        parser.finalize()
    except ServiceError:
        raise
    except Exception as exc:  # python_multipart's parse errors
        raise _malformed(f"The multipart body could not be parsed: {exc}") from None
    if not ended:
        where = f" in the part {current.get('name')!r}" if current.get("name") else ""
        raise _malformed(f"The multipart body is cut short{where}: its closing boundary "
                         "never came.")
    spec: bytes | None = None
    uploads: dict[str, Upload] = {}
    for part in parts:
        chunks = part["chunks"]
        data = chunks[0] if len(chunks) == 1 else bytearray().join(chunks)
        name = part["name"]
        if name == "spec":
            if spec is not None:
                raise _invalid("spec", "The part 'spec' was sent twice.")
            spec = bytes(data)
            continue
        if name in uploads:
            raise _invalid(name, "This input was sent in two parts.")
        ctype = part["headers"].get("content-type")
        uploads[name] = Upload(name, part["filename"],
                               ctype.split(";")[0].strip().lower() if ctype else None, data)
    return spec, uploads


def _format_of(upload: Upload) -> str:
    if upload.filename:
        suffix = PurePosixPath(upload.filename).suffix.lower().lstrip(".")
        if suffix in _SUFFIXES:
            return _SUFFIXES[suffix]
    if upload.content_type in _CONTENT_TYPES:
        return _CONTENT_TYPES[upload.content_type]
    head = upload.head()
    if head.startswith(b"\x93NUMPY"):
        return "npy"
    if head.startswith(b"glTF"):
        return "glb"
    if head.startswith(b"ply"):
        return "ply"
    if head.lstrip().startswith(b"OFF"):
        return "off"
    if head.lstrip().startswith(b"{"):
        return "json"
    if re.match(rb"\s*(#|v |o |g |mtllib)", head):
        return "obj"
    if head.lstrip().lower().startswith(b"solid") or len(upload.data) >= 84 and \
            len(upload.data) == 84 + 50 * int.from_bytes(upload.head(84)[80:84], "little"):
        return "stl"
    raise InvalidInputError(
        f"Cannot tell the format of the part `{upload.name}`: give it a file name ending in "
        f"one of {sorted('.' + s for s in _SUFFIXES)}, or a content type such as "
        f"{MEDIA_NPY!r} or {MEDIA_GLB!r}.", field=upload.name)


@dataclass(frozen=True)
class DecodeLimits:
    """What one uploaded file may hold, checked before it is expanded: ``max_bytes`` of data
    (a GLB's accessors), ``max_points`` vertices and faces (the limit of any input, after a
    GLB's nodes have instanced their meshes), and a GLB scene of at most ``max_nodes`` nodes
    nested at most ``max_depth`` levels."""

    max_bytes: int
    max_points: int
    max_nodes: int
    max_depth: int


#: For tests: when set, called with the part in the thread that decodes it, before it is
#: read (a test blocks it on an event to see that the service answers meanwhile).
before_decode: Callable[[Upload], None] | None = None

_pools: dict[int, ThreadPoolExecutor] = {}


def _pool(threads: int) -> ThreadPoolExecutor:
    """The threads that decode uploads (one pool per size, made on first use)."""
    pool = _pools.get(threads)
    if pool is None:
        pool = _pools[threads] = ThreadPoolExecutor(threads, thread_name_prefix="decode")
    return pool


async def decode_in_thread(upload: Upload, *, takes: str, limits: DecodeLimits,
                           time_limit: float, threads: int = 2) -> Any:
    """:func:`decode_upload` in a worker thread, so that the event loop keeps answering
    other requests (``/healthz`` among them) while a file is read; a file that takes longer
    than ``time_limit`` seconds is refused with a 422 naming it (its thread runs on to the
    end of the bounded work it was given, and its result is dropped)."""
    loop = asyncio.get_running_loop()
    work = loop.run_in_executor(_pool(threads), functools.partial(
        _decode_hooked, upload, takes=takes, limits=limits))
    try:
        return await asyncio.wait_for(work, time_limit)
    except TimeoutError:
        raise InvalidInputError(
            f"Reading the part `{upload.name}` took longer than {time_limit:g} s, the limit "
            "for one file.", field=upload.name) from None


def _decode_hooked(upload: Upload, *, takes: str, limits: DecodeLimits) -> Any:
    if before_decode is not None:
        before_decode(upload)
    return decode_upload(upload, takes=takes, limits=limits)


def decode_upload(upload: Upload, *, takes: str, limits: DecodeLimits) -> Any:
    """The value of one uploaded part: an array (``.npy``), or from a geometry file what the
    input ``takes``: ``"points"`` its vertices, ``"mesh"`` ``{"vertices", "faces"}`` (a point
    cloud is refused), ``"either"`` the mesh when the file has faces, else its vertices.
    Errors name the part; whatever a reader raises on a malformed file is such an error."""
    fmt = _format_of(upload)
    name = upload.name
    if fmt == "json":
        from service import jsonio

        try:
            return jsonio.loads(bytes(upload.data))
        except (ValueError, UnicodeDecodeError) as exc:
            raise InvalidInputError(f"The part `{name}` is not valid JSON: {exc}.",
                                    field=name) from None
    if fmt == "npy":
        try:
            arr = _load_npy(upload.data)
        except (ValueError, OSError, EOFError) as exc:
            raise InvalidInputError(f"The part `{name}` is not a readable .npy array "
                                    f"(numeric, no pickled objects): {exc}", field=name) from None
        if not isinstance(arr, np.ndarray) or arr.dtype.kind not in "biuf":
            raise InvalidInputError(f"Expected the .npy part `{name}` to hold numbers, got "
                                    f"dtype {getattr(arr, 'dtype', type(arr).__name__)}.",
                                    field=name)
        return arr
    try:
        return _geometry_value(upload, fmt, takes, limits)
    except (InvalidInputError, ServiceError):
        raise
    except Exception as exc:  # trimesh (and numpy under it) raise many kinds on bad files
        raise InvalidInputError(f"The part `{name}` could not be read as {fmt.upper()}: "
                                f"{type(exc).__name__}: {str(exc)[:200]}", field=name) from None


def _geometry_value(upload: Upload, fmt: str, takes: str, limits: DecodeLimits) -> Any:
    name = upload.name
    geometry = _load_geometry(upload, fmt, limits)
    vertices = np.asarray(geometry.vertices, dtype=np.float64)
    faces = getattr(geometry, "faces", None)
    has_faces = faces is not None and len(faces) > 0
    if takes == "mesh" and not has_faces:
        raise InvalidInputError(f"The part `{name}` holds a point cloud of {len(vertices)} "
                                "points; this input needs a mesh with faces.", field=name)
    if takes == "points" or not has_faces:
        return vertices
    return {"vertices": vertices, "faces": np.asarray(faces, dtype=np.int64)}


def _load_npy(data: bytes | bytearray | memoryview) -> np.ndarray:
    """An .npy file's array: the header parsed by numpy, the data a view of ``data`` when
    the array is native and C-ordered, aligned or not (an upload's part is a view of the
    request body: no copy at all), else one copy. ``np.load`` on a byte stream reads in
    256 kB pieces, ~5× slower for 24 MB."""
    from numpy.lib import format as npy_format

    stream = io.BytesIO(bytes(data[:1 << 20]))  # the header is within its first MiB
    version = npy_format.read_magic(stream)
    if version == (1, 0):
        shape, fortran, dtype = npy_format.read_array_header_1_0(stream)
    elif version == (2, 0):
        shape, fortran, dtype = npy_format.read_array_header_2_0(stream)
    else:  # other versions: numpy's own reader
        loaded: np.ndarray = np.load(io.BytesIO(data), allow_pickle=False)
        return loaded
    if dtype.hasobject:
        raise ValueError("Object arrays cannot be loaded when allow_pickle=False")
    count = int(np.prod(shape, dtype=np.int64))
    offset = stream.tell()
    if len(data) - offset < count * dtype.itemsize:
        raise EOFError(f"the file holds {len(data) - offset} bytes of data; its header "
                       f"declares {count * dtype.itemsize} (shape {shape}, dtype {dtype.str})")
    flat = np.frombuffer(data, dtype=dtype, count=count, offset=offset)
    arr = flat.reshape(shape, order="F" if fortran else "C")
    if dtype.isnative and arr.flags.c_contiguous:  # maybe misaligned in the body: the job
        return arr  # store pickles it as it is; in-process runs get a copy (binary.owned)
    return arr.astype(dtype.newbyteorder("="), order="C")  # a writable native-order copy


def _load_geometry(upload: Upload, fmt: str, limits: DecodeLimits) -> Any:
    import trimesh

    name = upload.name
    if fmt == "glb":
        from service.gltf import check_glb

        try:
            doc = check_glb(bytes(upload.data), limits.max_bytes)
        except ValueError as exc:
            raise InvalidInputError(f"The part `{name}` is not a valid GLB: {exc}",
                                    field=name) from None
        _check_scene(doc, name, limits)
    if fmt == "gltf":
        raise InvalidInputError(f"The part `{name}` is JSON glTF, whose buffers live in "
                                "other files; send the single-file binary form (.glb).",
                                field=name)
    if fmt in ("ply", "off"):
        _check_header_counts(upload, fmt, limits)
    try:
        loaded = trimesh.load(io.BytesIO(upload.data), file_type=fmt,
                              process=fmt == "stl", force=None)
    except Exception as exc:  # trimesh raises many kinds on malformed files
        raise InvalidInputError(f"The part `{name}` could not be read as {fmt.upper()}: "
                                f"{type(exc).__name__}: {exc}", field=name) from None
    if isinstance(loaded, trimesh.Scene):
        # trimesh's Geometry base declares no `vertices`; every kind a file loads as
        # (Trimesh, PointCloud, Path) has them
        geometries: list[Any] = list(loaded.dump()) if loaded.geometry else []
        if not geometries:
            raise InvalidInputError(f"The {fmt.upper()} part `{name}` holds no geometry.",
                                    field=name)
        meshes = [g for g in geometries if isinstance(g, trimesh.Trimesh)]
        loaded = trimesh.util.concatenate(meshes) if len(meshes) == len(geometries) \
            else trimesh.PointCloud(np.vstack([g.vertices for g in geometries]))
    if not hasattr(loaded, "vertices") or len(loaded.vertices) == 0:
        raise InvalidInputError(f"The {fmt.upper()} part `{name}` holds no vertices.",
                                field=name)
    if len(loaded.vertices) > limits.max_points:
        raise InvalidInputError(f"The {fmt.upper()} part `{name}` holds "
                                f"{len(loaded.vertices)} vertices, more than the limit of "
                                f"{limits.max_points}.", field=name)
    return loaded


def _check_scene(doc: dict[str, Any], name: str, limits: DecodeLimits) -> None:
    """Refuse a GLB whose scene graph is not a forest of at most ``max_nodes`` nodes nested
    at most ``max_depth`` levels (glTF requires disjoint strict trees: no cycles, no node
    with two parents), or whose nodes, by instancing their meshes, would make more than
    ``max_points`` vertices or faces: counted from the accessors' declared counts, before
    a loader expands anything. Without recursion."""
    def refuse(problem: str) -> InvalidInputError:
        return InvalidInputError(f"The GLB part `{name}` {problem}", field=name)

    def index(value: Any, size: int, where: str) -> int:
        if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value < size:
            raise refuse(f"has {where} = {value!r}, not an index below {size}.")
        return value

    def objects(key: str) -> list[dict[str, Any]]:
        items = doc.get(key, [])
        if not isinstance(items, list) or not all(isinstance(x, dict) for x in items):
            raise refuse(f"has `{key}` that is not a list of objects.")
        return items

    nodes, meshes, accessors = objects("nodes"), objects("meshes"), objects("accessors")
    if len(nodes) > limits.max_nodes:
        raise refuse(f"has {len(nodes)} nodes, more than the limit of {limits.max_nodes}.")
    n = len(nodes)
    parent = [-1] * n
    for i, node in enumerate(nodes):
        children = node.get("children", [])
        if not isinstance(children, list):
            raise refuse(f"has nodes[{i}].children that is not a list.")
        for c in children:
            c = index(c, n, f"a child of nodes[{i}]")
            if c == i:
                raise refuse(f"has a cycle in its scene: nodes[{i}] is its own child.")
            if parent[c] >= 0:
                raise refuse(f"has nodes[{c}] as a child of both nodes[{parent[c]}] and "
                             f"nodes[{i}]; glTF nodes form trees (one parent each).")
            parent[c] = i
    # each scene's root list says how often a root is drawn; a root of no scene, once
    listed = [0] * n
    for s_i, scene in enumerate(objects("scenes")):
        roots = scene.get("nodes", [])
        if not isinstance(roots, list):
            raise refuse(f"has scenes[{s_i}].nodes that is not a list.")
        for r in roots:
            listed[index(r, n, f"a node of scenes[{s_i}]")] += 1
    order = [i for i in range(n) if parent[i] < 0]
    depth = [0] * n
    copies = [0] * n
    for i in order:
        copies[i] = max(listed[i], 1)
    seen = 0
    while seen < len(order):  # breadth first from the roots: each node once, in order
        i = order[seen]
        seen += 1
        for c in nodes[i].get("children", []):
            depth[c] = depth[i] + 1
            if depth[c] >= limits.max_depth:
                raise refuse(f"nests its nodes more than {limits.max_depth} levels deep "
                             f"(nodes[{c}]), the limit.")
            copies[c] = copies[i] + listed[c]
            order.append(c)
    if len(order) < n:
        stuck = min(set(range(n)) - set(order))
        raise refuse(f"has a cycle in its scene: nodes[{stuck}] is its own ancestor.")

    def count(acc: Any, where: str) -> int:
        value = accessors[index(acc, len(accessors), where)].get("count", 0)
        return value if isinstance(value, int) else 0

    sizes = []  # (vertices, faces) of each mesh, as declared
    for m, mesh in enumerate(meshes):
        verts = faces = 0
        primitives = mesh.get("primitives", [])
        if not isinstance(primitives, list):
            raise refuse(f"has meshes[{m}].primitives that is not a list.")
        for p, prim in enumerate(primitives):
            where = f"meshes[{m}].primitives[{p}]"
            attributes = prim.get("attributes", {}) if isinstance(prim, dict) else None
            if not isinstance(attributes, dict):
                raise refuse(f"has {where} without an object of attributes.")
            v = count(attributes["POSITION"], f"{where}.attributes.POSITION") \
                if "POSITION" in attributes else 0
            verts += v
            faces += (count(prim["indices"], f"{where}.indices") if "indices" in prim
                      else v) // 3
        sizes.append((verts, faces))
    drawn = [0] * len(meshes)
    for i, node in enumerate(nodes):
        if "mesh" in node:
            m = index(node["mesh"], len(meshes), f"nodes[{i}].mesh")
            instancing = (node.get("extensions") or {}).get("EXT_mesh_gpu_instancing")
            times = 1
            if isinstance(instancing, dict) and isinstance(instancing.get("attributes"), dict):
                times = max([count(a, f"nodes[{i}] instancing")
                             for a in instancing["attributes"].values()], default=1)
            drawn[m] += copies[i] * times
    vertices = sum(max(d, 1) * v for d, (v, _) in zip(drawn, sizes, strict=True))
    faces = sum(max(d, 1) * f for d, (_, f) in zip(drawn, sizes, strict=True))
    if max(vertices, faces) > limits.max_points:
        what = "vertices" if vertices > limits.max_points else "faces"
        raise refuse(f"would make {max(vertices, faces)} {what} once its nodes place their "
                     f"meshes, more than the limit of {limits.max_points}.")


def _check_header_counts(upload: Upload, fmt: str, limits: DecodeLimits) -> None:
    """Refuse a PLY or OFF file whose header declares more elements (vertices, faces) than
    the limit, or than the file has bytes (each element takes one at least), before a
    reader allocates them."""
    head = upload.head(1 << 16)
    if fmt == "ply":
        end = head.find(b"end_header")
        counts = [(m[1].decode("ascii", "replace"), int(m[2])) for m in re.finditer(
            rb"^element[ \t]+(\S+)[ \t]+(\d+)", head[:end if end >= 0 else None], re.M)]
    else:
        lines = [ln.split(b"#")[0].strip() for ln in head.splitlines()[:64]]
        lines = [ln for ln in lines if ln]
        first = lines[0].removeprefix(b"OFF").split() if lines else []
        numbers = first if first else (lines[1].split() if len(lines) > 1 else [])
        counts = [(what, int(x)) for what, x in zip(("vertex", "face"), numbers)
                  if x.isdigit()]
    for what, declared in counts:
        if declared > min(limits.max_points, len(upload.data)):
            why = f"the limit of {limits.max_points}" if declared > limits.max_points \
                else f"the file's {len(upload.data)} bytes could hold"
            raise InvalidInputError(f"The {fmt.upper()} part `{upload.name}` declares "
                                    f"{declared} elements of kind {what!r}, more than "
                                    f"{why}.", field=upload.name)


def place_upload(inputs: dict[str, Any], path: str, value: Any, *,
                 max_depth: int = MAX_DEPTH) -> None:
    """Put an uploaded value at ``name`` or ``name.member`` (``name.a.b``: up to
    ``max_depth`` levels of members) of the inputs."""
    if path.count(".") > max_depth:
        raise too_deep(path)
    target = inputs
    head, _, member = path.partition(".")
    while member:
        target = target.setdefault(head, {})
        if not isinstance(target, dict):
            raise InvalidInputError(f"The part `{path}` sets a member of `{head}`, which the "
                                    "spec already gives as a value that has no members.",
                                    field=path)
        head, _, member = member.partition(".")
    target[head] = value


#: A reference to an output of an earlier job.
REF_PATTERN = re.compile(r"^/jobs/(?P<job>[^/?#]+)/results/(?P<output>[A-Za-z_][A-Za-z0-9_]*)$")


def resolve_refs(value: Any, name: str, fetch: Callable[[str, str, str], Any],
                 own_origin: str, *, max_depth: int = MAX_DEPTH) -> Any:
    """``value`` with every ``{"href": ...}`` object in it (at any depth of objects, up to
    ``max_depth`` levels; deeper is a 422 naming the input) replaced by the output it names,
    as ``fetch(job_id, output, field)`` returns it."""
    if isinstance(value, dict):
        if "href" in value and set(value) <= {"href", "type", "rel", "title"}:
            return fetch(*_parse_ref(value["href"], name, own_origin), name)
        if max_depth <= 0:
            raise too_deep(name)
        return {k: resolve_refs(v, f"{name}.{k}", fetch, own_origin, max_depth=max_depth - 1)
                for k, v in value.items()}
    return value


def _parse_ref(href: Any, name: str, own_origin: str) -> tuple[str, str]:
    if not isinstance(href, str):
        raise InvalidInputError(f"Expected `{name}.href` to be a string, got "
                                f"{type(href).__name__}.", field=name)
    url = urlsplit(href)
    if url.scheme or url.netloc:
        origin = f"{url.scheme}://{url.netloc}".lower()
        if origin != own_origin.lower():
            raise InvalidInputError(
                f"`{name}` refers to {href!r}; inputs by reference may only name results of "
                "this service's own jobs (/jobs/{jobId}/results/{output}): it never fetches "
                "other URLs.", field=name)
    match = REF_PATTERN.match(url.path)
    if not match or url.query or url.fragment:
        raise InvalidInputError(
            f"`{name}` refers to {href!r}; expected /jobs/{{jobId}}/results/{{output}}.",
            field=name)
    return match["job"], match["output"]


# -- outputs -------------------------------------------------------------------------------

def npy_bytes(a: np.ndarray) -> bytes:
    buf = io.BytesIO()
    np.save(buf, np.asarray(a), allow_pickle=False)
    return buf.getvalue()


def turned_up(response: Response, up: str) -> Response:
    """A GLB ``response`` whose scene is turned for data with ``up`` ("y": as it is; "z":
    +z up, the scene under a root node that takes +z to +y, :func:`service.gltf.y_up`).
    Other responses (JSON, ``.npy``, problems) are returned as they are."""
    if up == "y" or response.media_type != MEDIA_GLB or response.status_code != 200:
        return response
    from service.gltf import y_up

    headers = {k: v for k, v in response.headers.items() if k.lower() != "content-length"}
    return Response(y_up(bytes(response.body), up=up), media_type=MEDIA_GLB, headers=headers)


def _accepted(accept: str) -> list[tuple[float, int, str]]:
    out = []
    for i, part in enumerate(accept.split(",")):
        media, *params = [p.strip() for p in part.split(";")]
        q = 1.0
        for p in params:
            key, _, val = p.partition("=")
            if key.strip().lower() == "q":
                try:
                    q = float(val)
                except ValueError:
                    q = 0.0
        if media:
            out.append((q, -i, media.lower()))
    return sorted(out, reverse=True)


def negotiate(accept: str | None, f: str | None) -> str:
    """The result format a request asks for: ``json``, ``glb`` or ``npy``.

    ``?f=`` wins over ``Accept``; among Accept's media types the highest q (the first on a
    tie) that the service writes. Raises ServiceError 406 when none is."""
    if f is not None:
        return f
    if not accept:
        return "json"
    for q, _, media in _accepted(accept):
        if q <= 0:
            continue
        if media in ("*/*", "application/*", MEDIA_JSON) or media.endswith("+json"):
            return "json"
        if media in (MEDIA_GLB, "model/*"):
            return "glb"
        if media in (MEDIA_NPY, "application/npy"):
            return "npy"
    raise ServiceError("not-acceptable", f"The results are available as {MEDIA_JSON}, "
                       f"{MEDIA_GLB} (geometry) or {MEDIA_NPY} (one array); the request "
                       f"accepts {accept!r}.")
