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

    Any input, or member of an input, may instead be a reference to an output of an earlier
    job of the same API key: ``{"href": "/jobs/{jobId}/results/{output}"}`` (or the same path
    under this service's own URL). Other URLs are refused: the service never fetches from
    the network on a client's behalf.

Outputs
    JSON results documents (arrays as nested lists or, when the client prefers
    ``arrays=binary``, typed binary arrays, whose shape survives even when empty); a single
    array as ``.npy`` (``application/x-npy``); and geometry as glTF binary
    (``model/gltf-binary``, the scene its catalog entry declares: :mod:`service.scenes`).
"""

from __future__ import annotations

import io
import re
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import PurePosixPath
from typing import Any
from urllib.parse import urlsplit

import numpy as np

from algorithms.core.errors import InvalidInputError
from service.errors import ServiceError

__all__ = ["Upload", "parse_multipart", "decode_upload", "place_upload", "resolve_refs",
           "REF_PATTERN", "npy_bytes", "MEDIA_GLB", "MEDIA_NPY",
           "MEDIA_JSON", "negotiate"]

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


def decode_upload(upload: Upload, *, takes: str, max_glb_bytes: int) -> Any:
    """The value of one uploaded part: an array (``.npy``), or from a geometry file what the
    input ``takes``: ``"points"`` its vertices, ``"mesh"`` ``{"vertices", "faces"}`` (a point
    cloud is refused), ``"either"`` the mesh when the file has faces, else its vertices.
    Errors name the part."""
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
    geometry = _load_geometry(upload, fmt, max_glb_bytes)
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


def _load_geometry(upload: Upload, fmt: str, max_glb_bytes: int) -> Any:
    import trimesh

    name = upload.name
    if fmt == "glb":
        from service.gltf import check_glb

        try:
            check_glb(bytes(upload.data), max_glb_bytes)
        except ValueError as exc:
            raise InvalidInputError(f"The part `{name}` is not a valid GLB: {exc}",
                                    field=name) from None
    if fmt == "gltf":
        raise InvalidInputError(f"The part `{name}` is JSON glTF, whose buffers live in "
                                "other files; send the single-file binary form (.glb).",
                                field=name)
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
    return loaded


def place_upload(inputs: dict[str, Any], path: str, value: Any) -> None:
    """Put an uploaded value at ``name`` or ``name.member`` of the inputs."""
    head, _, member = path.partition(".")
    if not member:
        inputs[head] = value
        return
    target = inputs.setdefault(head, {})
    if not isinstance(target, dict):
        raise InvalidInputError(f"The part `{path}` sets a member of `{head}`, which the spec "
                                "already gives as a value that has no members.", field=path)
    place_upload(target, member, value)


#: A reference to an output of an earlier job.
REF_PATTERN = re.compile(r"^/jobs/(?P<job>[^/?#]+)/results/(?P<output>[A-Za-z_][A-Za-z0-9_]*)$")


def resolve_refs(value: Any, name: str, fetch: Callable[[str, str, str], Any],
                 own_origin: str) -> Any:
    """``value`` with every ``{"href": ...}`` object in it (at any depth of objects) replaced
    by the output it names, as ``fetch(job_id, output, field)`` returns it."""
    if isinstance(value, dict):
        if "href" in value and set(value) <= {"href", "type", "rel", "title"}:
            return fetch(*_parse_ref(value["href"], name, own_origin), name)
        return {k: resolve_refs(v, f"{name}.{k}", fetch, own_origin) for k, v in value.items()}
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
