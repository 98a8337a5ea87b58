"""glTF 2.0 binary (GLB) writing, reading and checking: numpy, json and struct only.

What the service sends for ``Accept: model/gltf-binary`` is built here:

- :func:`mesh_glb`: one triangle mesh (``faces``) or point cloud (``faces=None``, primitive
  mode 0 POINTS), with optional ``uv`` (``TEXCOORD_0``), per-vertex ``colors`` (``COLOR_0``)
  and ``normals``;
- :func:`scene_glb`: several meshes or point clouds, one node each, each with its own
  material colour (an aligned source over its target as two coloured point clouds);
- :func:`morph_animation_glb`: frames of one shape as a mesh with morph targets and a LINEAR
  animation of its ``weights`` that plays the frames in order;
- :func:`label_colors`: a deterministic palette for points coloured by label;
  :func:`index_colors`: viridis by point index, for points without labels;
- :func:`checker_png`: a checker texture (PNG, written with zlib) that shows a UV layout;
- :func:`point_hints`: the suggested size of drawn points, for a point cloud's node extras
  (glTF has no point size);
- :func:`y_up`: a scene of z-up data turned +z to +y by a root node.

:func:`check_glb` refuses an uploaded glTF/GLB whose JSON declares more data than the file
holds (buffers, buffer views or accessors beyond the binary chunk, a "huge buffer"),
external references, or truncation, before a loader allocates anything. :func:`read_glb` is
the minimal parser the tests use for round trips.

Conventions of what is written
------------------------------
- Positions are float32 (``POSITION`` with its ``min``/``max``, as the specification
  requires, computed on the float32 values); 2-D coordinates get ``z = 0``.
- Triangle indices are uint16 when every index is at most 65534, else uint32 (the largest
  value of each type is reserved for primitive restart).
- ``TEXCOORD_0`` holds ``(u, 1 - v)``: glTF puts the texture origin at the image's top-left
  corner with ``v`` pointing down, while ``uv`` from a parameterization (and OBJ, libigl,
  Blender's UV editor) has ``v`` pointing up. With the flip an image textured onto the mesh
  appears upright, as trimesh also does when it exports and loads glTF (so trimesh gives the
  original ``uv`` back). :func:`read_glb` returns the stored values, flipped.
- ``COLOR_0``: float RGB/RGBA in [0, 1] is stored as float32; integer colours in [0, 255]
  (uint8 or any integer dtype) as normalized unsigned bytes, RGB widened to RGBA with alpha
  255 (a vertex attribute's elements must be 4-byte aligned, which 3 bytes are not).
- Every buffer view starts at a multiple of 4 bytes; the JSON chunk is padded with spaces
  and the binary chunk with zeros to a multiple of 4; ``asset.generator`` is "morphserve".
- Triangle meshes get a double-sided, non-metallic PBR material; point clouds an unlit one
  (``KHR_materials_unlit``: points have no normals to light), so their colours show as given.

All errors are :class:`~algorithms.core.errors.InvalidInputError` (a :class:`ValueError`)
naming the offending argument in ``field``; nothing here imports the service, so this
module is a plain library.
"""

from __future__ import annotations

import base64
import binascii
import json
import struct
import zlib
from collections.abc import Sequence
from typing import Any

import numpy as np

from algorithms.core.errors import InvalidInputError
from algorithms.core.validation import as_indices, as_points

__all__ = [
    "MEDIA_TYPE",
    "mesh_glb",
    "scene_glb",
    "morph_animation_glb",
    "label_colors",
    "index_colors",
    "point_hints",
    "checker_png",
    "CHECKER_LIGHT",
    "y_up",
    "check_glb",
    "read_glb",
]

#: The media type of a GLB file, as registered with IANA.
MEDIA_TYPE = "model/gltf-binary"

_GLB_MAGIC = 0x46546C67  # b"glTF"
_CHUNK_JSON = 0x4E4F534A  # b"JSON"
_CHUNK_BIN = 0x004E4942  # b"BIN\0"

_BYTE, _UBYTE, _SHORT, _USHORT, _UINT, _FLOAT = 5120, 5121, 5122, 5123, 5125, 5126
_COMPONENT_DTYPE = {_BYTE: "<i1", _UBYTE: "<u1", _SHORT: "<i2", _USHORT: "<u2",
                    _UINT: "<u4", _FLOAT: "<f4"}
_TYPE_SIZE = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT2": 4, "MAT3": 9, "MAT4": 16}
_ARRAY_BUFFER, _ELEMENT_ARRAY_BUFFER = 34962, 34963
_LINEAR, _LINEAR_MIPMAP_LINEAR, _REPEAT = 9729, 9987, 10497
_POINTS, _TRIANGLES = 0, 4

_FLOAT32_MAX = float(np.finfo(np.float32).max)
_UINT16_INDEX_MAX = 65534  # 65535 is the primitive-restart value, not a valid index
_DEFAULT_GREY = (0.8, 0.8, 0.8)

_PART_KEYS = frozenset({"vertices", "faces", "uv", "colors", "normals", "name", "color",
                        "texture", "extras"})


# --------------------------------------------------------------------------------------
# Writing
# --------------------------------------------------------------------------------------

class _Writer:
    """Collects buffer views (each 4-byte aligned) and accessors, then packs the GLB."""

    def __init__(self) -> None:
        self.doc: dict[str, Any] = {
            "asset": {"version": "2.0", "generator": "morphserve"},
            "scene": 0,
            "scenes": [{"nodes": []}],
            "nodes": [],
            "meshes": [],
            "materials": [],
            "bufferViews": [],
            "accessors": [],
            "images": [],
            "samplers": [],
            "textures": [],
        }
        self.blobs: list[Any] = []
        self.size = 0
        self._textures: dict[bytes, int] = {}

    def view(self, arr: np.ndarray, *, target: int | None = None) -> int:
        """Append a C-contiguous little-endian array as one buffer view; its index."""
        raw = np.ascontiguousarray(arr).reshape(-1).view(np.uint8)
        view: dict[str, Any] = {"buffer": 0, "byteOffset": self.size, "byteLength": raw.nbytes}
        if target is not None:
            view["target"] = target
        self.blobs.append(raw)
        self.size += raw.nbytes
        pad = -raw.nbytes % 4
        if pad:
            self.blobs.append(b"\0" * pad)
            self.size += pad
        self.doc["bufferViews"].append(view)
        return len(self.doc["bufferViews"]) - 1

    def accessor(self, arr: np.ndarray, component: int, kind: str, *,
                 target: int | None = None, normalized: bool = False,
                 bounds: bool = False) -> int:
        """One accessor over its own buffer view; ``bounds`` adds ``min``/``max``."""
        acc: dict[str, Any] = {
            "bufferView": self.view(arr, target=target),
            "componentType": component,
            "count": int(arr.shape[0]),
            "type": kind,
        }
        if normalized:
            acc["normalized"] = True
        if bounds:
            # Column-major copy: numpy's strided min(axis=0) over (n, 3) is ~7x slower.
            cols = np.ascontiguousarray(arr.reshape(arr.shape[0], -1).T)
            acc["min"] = [_num(x) for x in cols.min(axis=1)]
            acc["max"] = [_num(x) for x in cols.max(axis=1)]
        self.doc["accessors"].append(acc)
        return len(self.doc["accessors"]) - 1

    def texture(self, png: bytes) -> int:
        """A texture of the PNG ``png`` (one image and texture per distinct PNG, written
        into the binary chunk), repeating, linear and mipmapped; its index."""
        if png in self._textures:
            return self._textures[png]
        view = self.view(np.frombuffer(png, dtype=np.uint8))
        self.doc["images"].append({"bufferView": view, "mimeType": "image/png"})
        if not self.doc["samplers"]:
            self.doc["samplers"].append({"magFilter": _LINEAR,
                                         "minFilter": _LINEAR_MIPMAP_LINEAR,
                                         "wrapS": _REPEAT, "wrapT": _REPEAT})
        self.doc["textures"].append({"sampler": 0, "source": len(self.doc["images"]) - 1})
        index = len(self.doc["textures"]) - 1
        self._textures[png] = index
        return index

    def material(self, color: Sequence[float], *, points: bool, blend: bool,
                 texture: int | None = None) -> int:
        pbr: dict[str, Any] = {"baseColorFactor": [float(c) for c in color],
                               "metallicFactor": 0.0, "roughnessFactor": 1.0}
        if texture is not None:
            pbr["baseColorTexture"] = {"index": texture}
        mat: dict[str, Any] = {"pbrMetallicRoughness": pbr}
        if points:
            mat["extensions"] = {"KHR_materials_unlit": {}}
            used = self.doc.setdefault("extensionsUsed", [])
            if "KHR_materials_unlit" not in used:
                used.append("KHR_materials_unlit")
        else:
            mat["doubleSided"] = True
        if blend:
            mat["alphaMode"] = "BLEND"
        self.doc["materials"].append(mat)
        return len(self.doc["materials"]) - 1

    def node(self, mesh: int, name: str | None, extras: dict[str, Any] | None = None) -> int:
        node: dict[str, Any] = {"mesh": mesh}
        if name is not None:
            node["name"] = name
        if extras:
            node["extras"] = extras
        self.doc["nodes"].append(node)
        index = len(self.doc["nodes"]) - 1
        self.doc["scenes"][0]["nodes"].append(index)
        return index

    def pack(self) -> bytes:
        doc = {k: v for k, v in self.doc.items() if v != []}
        if self.size:
            doc["buffers"] = [{"byteLength": self.size}]
        text = json.dumps(doc, separators=(",", ":"), allow_nan=False).encode("utf-8")
        text += b" " * (-len(text) % 4)
        total = 12 + 8 + len(text) + (8 + self.size if self.size else 0)
        pieces: list[Any] = [struct.pack("<III", _GLB_MAGIC, 2, total),
                             struct.pack("<II", len(text), _CHUNK_JSON), text]
        if self.size:
            pieces.append(struct.pack("<II", self.size, _CHUNK_BIN))
            pieces.extend(self.blobs)
        return b"".join(pieces)


def _num(x: Any) -> float | int:
    """A numpy scalar as a JSON number (float32 widens to float64 exactly)."""
    value: float | int = x.item() if isinstance(x, np.generic) else x
    return value


def _err(message: str, field: str) -> InvalidInputError:
    return InvalidInputError(message, field=field)


def _positions(x: Any, field: str) -> np.ndarray:
    """(n, 2|3) finite coordinates -> (n, 3) float32, z = 0 for 2-D input."""
    pts = as_points(x, name=field, min_points=1)
    d = pts.shape[1]
    if d not in (2, 3):
        raise _err(f"Expected `{field}` to be an (n, 3) or (n, 2) array of finite numbers, "
                   f"got shape ({pts.shape[0]}, {d}).", field)
    _check_float32_range(pts, field)
    out = np.zeros((pts.shape[0], 3), dtype="<f4")
    out[:, :d] = pts
    return out


def _check_float32_range(arr: np.ndarray, field: str) -> None:
    if arr.size and max(arr.max(), -arr.min()) > _FLOAT32_MAX:
        flat = int(np.argmax(np.abs(arr).reshape(-1)))
        row = np.unravel_index(flat, arr.shape)[0]
        raise _err(f"Expected `{field}` to hold values of magnitude at most {_FLOAT32_MAX:.6g} "
                   f"(glTF stores float32), got {arr.reshape(-1)[flat]!r} at row {row}.", field)


def _faces(f: Any, n: int, field: str) -> tuple[np.ndarray, int]:
    """(m, 3) vertex indices -> (m * 3,) uint16 or uint32 and its component type."""
    idx = as_indices(f, n, name=field, what="vertex indices")
    if idx.ndim != 2 or idx.shape[1] != 3 or idx.shape[0] < 1:
        raise _err(f"Expected `{field}` to be an (m, 3) array of vertex indices with m >= 1, "
                   f"got shape {tuple(idx.shape)}.", field)
    if n - 1 <= _UINT16_INDEX_MAX:
        return idx.astype("<u2").reshape(-1), _USHORT
    return idx.astype("<u4").reshape(-1), _UINT


def _rows(arr: np.ndarray, n: int, field: str, what: str) -> None:
    if arr.shape[0] != n:
        raise _err(f"Expected `{field}` to have one row per vertex ({n}), got {arr.shape[0]} "
                   f"{what}.", field)


def _uv(uv: Any, n: int, field: str) -> np.ndarray:
    arr = as_points(uv, name=field, dim=2, min_points=0)
    _rows(arr, n, field, "rows")
    _check_float32_range(arr, field)
    out = np.empty((n, 2), dtype="<f4")
    out[:, 0] = arr[:, 0]
    out[:, 1] = 1.0 - arr[:, 1]
    return out


def _colors(c: Any, n: int, field: str) -> tuple[np.ndarray, int, bool]:
    """Per-vertex colours -> (array, component type, has translucency)."""
    expected = ("an (n, 3) or (n, 4) array of RGB(A) colours, floats in [0, 1] or integers "
                "in [0, 255]")
    try:
        arr = np.asarray(c)
    except (ValueError, TypeError):
        raise _err(f"Expected `{field}` to be {expected}, got a ragged sequence.", field) from None
    if arr.dtype.kind not in "iuf":
        raise _err(f"Expected `{field}` to be {expected}, got dtype {arr.dtype}.", field)
    if arr.ndim != 2 or arr.shape[1] not in (3, 4):
        raise _err(f"Expected `{field}` to be {expected}, got shape {tuple(arr.shape)}.", field)
    _rows(arr, n, field, "colours")
    if arr.dtype.kind == "f":
        if n and not np.isfinite(arr).all():
            row = int(np.argmax(~np.isfinite(arr).all(axis=1)))
            raise _err(f"Expected `{field}` to hold finite numbers, got {arr[row].tolist()} at "
                       f"row {row}.", field)
        if n and (arr.min() < 0 or arr.max() > 1):
            row = int(np.argmax(((arr < 0) | (arr > 1)).any(axis=1)))
            raise _err(f"Expected `{field}` to be {expected}; float colours must lie in "
                       f"[0, 1], got {arr[row].tolist()} at row {row}.", field)
        out = np.ascontiguousarray(arr, dtype="<f4")
        blend = arr.shape[1] == 4 and bool(n) and bool(out[:, 3].min() < 1)
        return out, _FLOAT, blend
    if n and (arr.min() < 0 or arr.max() > 255):
        row = int(np.argmax(((arr < 0) | (arr > 255)).any(axis=1)))
        raise _err(f"Expected `{field}` to be {expected}; integer colours must lie in "
                   f"[0, 255], got {arr[row].tolist()} at row {row}.", field)
    out = np.empty((n, 4), dtype=np.uint8)
    out[:, : arr.shape[1]] = arr
    if arr.shape[1] == 3:
        out[:, 3] = 255
    blend = bool(n) and bool(out[:, 3].min() < 255)
    return out, _UBYTE, blend


def _normals(nrm: Any, n: int, field: str) -> np.ndarray:
    arr = as_points(nrm, name=field, dim=3, min_points=0)
    _rows(arr, n, field, "normals")
    length = np.sqrt(np.einsum("ij,ij->i", arr, arr))
    if n and not length.min() > 0:
        row = int(np.argmin(length))
        raise _err(f"Expected `{field}` to hold non-zero vectors, got {arr[row].tolist()} at "
                   f"row {row}.", field)
    return np.ascontiguousarray(arr / length[:, None], dtype="<f4")


def _color_factor(color: Any, field: str) -> list[float]:
    try:
        arr = np.asarray(color, dtype=np.float64)
    except (ValueError, TypeError):
        arr = np.empty(0)
    if arr.shape not in ((3,), (4,)) or not np.isfinite(arr).all() or arr.min() < 0 \
            or arr.max() > 1:
        raise _err(f"Expected `{field}` to be an RGB or RGBA colour of 3 or 4 floats in [0, 1], "
                   f"got {color!r}.", field)
    return [float(x) for x in arr] + ([1.0] if arr.shape == (3,) else [])


def _name(name: Any, field: str) -> str | None:
    if name is not None and not isinstance(name, str):
        raise _err(f"Expected `{field}` to be a string, got {type(name).__name__}.", field)
    return name


def _add_part(w: _Writer, part: dict[str, Any], prefix: str,
              default_color: Sequence[float]) -> None:
    """One mesh (one primitive), its material and its node."""
    unknown = sorted(set(part) - _PART_KEYS)
    if unknown:
        raise _err(f"Expected `{prefix.rstrip('.') or 'part'}` to have only the keys "
                   f"{sorted(_PART_KEYS)}, got also {unknown}.", prefix.rstrip(".") or "part")
    if part.get("vertices") is None:
        raise _err(f"Expected `{prefix}vertices`, the points or mesh vertices; got none.",
                   f"{prefix}vertices")
    pos = _positions(part["vertices"], f"{prefix}vertices")
    n = pos.shape[0]
    name = _name(part.get("name"), f"{prefix}name")
    points = part.get("faces") is None
    attributes = {"POSITION": w.accessor(pos, _FLOAT, "VEC3", target=_ARRAY_BUFFER,
                                         bounds=True)}
    if part.get("normals") is not None:
        attributes["NORMAL"] = w.accessor(_normals(part["normals"], n, f"{prefix}normals"),
                                          _FLOAT, "VEC3", target=_ARRAY_BUFFER)
    if part.get("uv") is not None:
        attributes["TEXCOORD_0"] = w.accessor(_uv(part["uv"], n, f"{prefix}uv"), _FLOAT,
                                              "VEC2", target=_ARRAY_BUFFER)
    texture = None
    if part.get("texture") is not None:
        if points or part.get("uv") is None:
            raise _err(f"Expected `{prefix}texture` only on a triangle mesh with `uv` (the "
                       "texture is looked up at each vertex's uv).", f"{prefix}texture")
        texture = w.texture(_png(part["texture"], f"{prefix}texture"))
    blend = False
    if part.get("colors") is not None:
        col, comp, blend = _colors(part["colors"], n, f"{prefix}colors")
        attributes["COLOR_0"] = w.accessor(col, comp, f"VEC{col.shape[1]}",
                                           target=_ARRAY_BUFFER, normalized=comp == _UBYTE)
    if part.get("color") is not None:
        factor = _color_factor(part["color"], f"{prefix}color")
    elif part.get("colors") is not None or texture is not None:
        factor = [1.0, 1.0, 1.0, 1.0]  # the factor multiplies them: white shows them as given
    else:
        factor = [float(c) for c in default_color] + [1.0]
    blend = blend or factor[3] < 1
    primitive: dict[str, Any] = {"attributes": attributes,
                                 "mode": _POINTS if points else _TRIANGLES}
    if not points:
        idx, comp = _faces(part["faces"], n, f"{prefix}faces")
        primitive["indices"] = w.accessor(idx, comp, "SCALAR", target=_ELEMENT_ARRAY_BUFFER)
    primitive["material"] = w.material(factor, points=points, blend=blend, texture=texture)
    mesh: dict[str, Any] = {"primitives": [primitive]}
    if name is not None:
        mesh["name"] = name
    w.doc["meshes"].append(mesh)
    extras = _extras(part.get("extras"), f"{prefix}extras")
    if points:
        extras = {**point_hints(pos), **extras}
    w.node(len(w.doc["meshes"]) - 1, name, extras)


def point_hints(positions: Any) -> dict[str, float | int]:
    """How large to draw points, for the node's ``extras`` (glTF has no point size; many
    viewers draw one pixel).

    Returns ``{"pointSize": px, "pointSpacing": s}``: a size on screen in pixels (6 up to
    1000 points, 4 up to 10 000, 3 up to 100 000, else 2), and about the distance between
    neighbouring points were they spread evenly over their bounding box,
    ``s = (V / n)^(1/k)`` with ``V`` the product of the ``k`` non-zero extents of the box
    (``k`` = 2 for a flat embedding), a size in world units for viewers that scale points
    with distance (three.js ``PointsMaterial`` with ``sizeAttenuation``). ``s`` is 1 when
    every point is the same.

    Examples
    --------
    >>> point_hints(np.c_[np.arange(11.0), np.zeros(11)])
    {'pointSize': 6, 'pointSpacing': 0.9090909090909091}
    """
    pts = np.asarray(positions, dtype=np.float64)
    n = len(pts)
    size = 6 if n <= 1000 else 4 if n <= 10_000 else 3 if n <= 100_000 else 2
    extent = pts.max(axis=0) - pts.min(axis=0) if n else np.zeros(1)
    span = extent[extent > 1e-12 * max(float(extent.max(initial=0.0)), 1e-300)]
    spacing = float(np.prod(span) / n) ** (1.0 / len(span)) if len(span) and n else 1.0
    return {"pointSize": size, "pointSpacing": spacing}


def _extras(extras: Any, field: str) -> dict[str, Any]:
    """A node's ``extras``: a JSON object (checked to serialise), or none."""
    if extras is None:
        return {}
    if not isinstance(extras, dict):
        raise _err(f"Expected `{field}` to be a dict (the node's glTF extras), got "
                   f"{type(extras).__name__}.", field)
    try:
        json.dumps(extras, allow_nan=False)
    except (TypeError, ValueError) as exc:
        raise _err(f"Expected `{field}` to hold JSON values only: {exc}.", field) from None
    return dict(extras)


_PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def _png(data: Any, field: str) -> bytes:
    if not isinstance(data, (bytes, bytearray)) or not bytes(data[:8]) == _PNG_SIGNATURE:
        raise _err(f"Expected `{field}` to be the bytes of a PNG image.", field)
    return bytes(data)


def mesh_glb(vertices: Any, faces: Any = None, *, uv: Any = None, colors: Any = None,
             normals: Any = None, name: str | None = None, texture: bytes | None = None,
             extras: dict[str, Any] | None = None) -> bytes:
    """One triangle mesh or point cloud as a GLB file.

    Parameters
    ----------
    vertices : (n, 3) or (n, 2) float array
        Vertex positions, finite and within float32 range; 2-D points get ``z = 0``.
    faces : (m, 3) int array, optional
        Triangles (vertex indices in ``[0, n)``, ``m >= 1``). ``None`` writes a point cloud
        (primitive mode 0, POINTS, with an unlit material).
    uv : (n, 2) float array, optional
        Texture coordinates, written to ``TEXCOORD_0`` as ``(u, 1 - v)`` (glTF's ``v`` axis
        points down; see the module's notes).
    colors : (n, 3) or (n, 4) array, optional
        Per-vertex colours in ``COLOR_0``: floats in [0, 1] (stored as float32) or integers
        in [0, 255] (stored as normalized unsigned bytes, RGB widened to RGBA). Any alpha
        below 1 makes the material blended.
    normals : (n, 3) float array, optional
        Per-vertex normals, normalized here (``NORMAL`` must hold unit vectors); a zero
        vector is an error.
    name : str, optional
        Name of the mesh and its node.
    texture : bytes, optional
        A PNG image (:func:`checker_png`) the material shows, looked up at ``uv``
        (``baseColorTexture``); needs ``faces`` and ``uv``.
    extras : dict, optional
        The node's glTF ``extras`` (JSON values). A point cloud's also get
        :func:`point_hints` (``pointSize``, ``pointSpacing``) unless given here.

    Returns
    -------
    bytes
        The GLB file (``model/gltf-binary``): one scene, one node, one mesh, one primitive.
        Its material colour is grey, or white when ``colors`` or ``texture`` give the
        colours (the factor multiplies them).

    Raises
    ------
    InvalidInputError
        A wrong shape or dtype, NaN/Inf, a value beyond float32, a face index out of range,
        a colour out of range or a zero normal; ``field`` names the argument.

    See Also
    --------
    scene_glb : several meshes or point clouds in one file.
    read_glb : parse the result back.

    Examples
    --------
    >>> glb = mesh_glb([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]], uv=[[0, 0], [1, 0], [0, 1]])
    >>> glb[:4], len(glb) % 4
    (b'glTF', 0)
    >>> read_glb(glb)["json"]["meshes"][0]["primitives"][0]["mode"]
    4
    """
    w = _Writer()
    part = {"vertices": vertices, "faces": faces, "uv": uv, "colors": colors,
            "normals": normals, "name": name, "texture": texture, "extras": extras}
    _add_part(w, part, "", _DEFAULT_GREY)
    return w.pack()


def scene_glb(parts: list[dict[str, Any]], *, extras: dict[str, Any] | None = None) -> bytes:
    """Several meshes and point clouds as separate nodes of one scene, in one GLB file.

    Parameters
    ----------
    parts : list of dict
        One dict per mesh or point cloud, with the keys of :func:`mesh_glb` (``vertices``
        required; ``faces``, ``uv``, ``colors``, ``normals``, ``name`` optional) and
        ``color``: the part's material colour, RGB or RGBA floats in [0, 1] (it multiplies
        ``colors`` where both are given), ``texture`` (as in :func:`mesh_glb`), and
        ``extras``: the node's glTF extras. Without ``color`` part ``i`` gets
        ``label_colors([i])``: blue, orange, green, red, ... (white when ``colors`` or a
        ``texture`` colour it).
    extras : dict, optional
        The scene's glTF ``extras`` (JSON values).

    Returns
    -------
    bytes
        The GLB file: one scene whose node ``i`` holds mesh ``i`` with material ``i``, each
        named by its part's ``name``.

    Raises
    ------
    InvalidInputError
        No part, a part that is not a dict or has an unknown key, or any error of
        :func:`mesh_glb`; ``field`` is e.g. ``"parts[1].vertices"``.

    Examples
    --------
    An aligned source over its target, as two coloured point clouds:

    >>> rng = np.random.default_rng(0)
    >>> target = rng.normal(size=(100, 3))
    >>> glb = scene_glb([{"vertices": target, "name": "target"},
    ...                  {"vertices": target + 0.01, "name": "aligned source"}])
    >>> [n["name"] for n in read_glb(glb)["json"]["nodes"]]
    ['target', 'aligned source']
    """
    if isinstance(parts, dict) or not isinstance(parts, Sequence) or len(parts) == 0:
        raise _err("Expected `parts` to be a non-empty list of dicts (one per mesh or point "
                   f"cloud), got {type(parts).__name__}"
                   f"{' of length 0' if isinstance(parts, Sequence) else ''}.", "parts")
    palette = label_colors(np.arange(len(parts)))
    w = _Writer()
    for i, part in enumerate(parts):
        if not isinstance(part, dict):
            raise _err(f"Expected `parts[{i}]` to be a dict with `vertices` and optional "
                       f"`faces`, `uv`, `colors`, `normals`, `name`, `color`; got "
                       f"{type(part).__name__}.", f"parts[{i}]")
        _add_part(w, part, f"parts[{i}].", palette[i])
    if extras is not None:
        w.doc["scenes"][0]["extras"] = _extras(extras, "extras")
    return w.pack()


def morph_animation_glb(frames: Any, faces: Any = None, times: Any = None, *,
                        duration: float = 2.0, name: str | None = None,
                        extras: dict[str, Any] | None = None,
                        scene_extras: dict[str, Any] | None = None) -> bytes:
    r"""Frames of one shape as a mesh with morph targets and a LINEAR weights animation.

    The mesh's base positions are ``frames[0]``; morph target ``k - 1`` holds
    ``frames[k] - frames[0]`` for ``k = 1 .. T-1``. The animation's keyframe ``k`` at
    ``times[k]`` has weight 1 on target ``k - 1`` and 0 on the others (all 0 at ``k = 0``),
    so the shape shown at time ``times[k]`` is exactly ``frames[k]`` (to float32), and in
    between LINEAR interpolation of the weights blends the two neighbouring frames:

    .. math::
        x(t) = (1 - s)\, f_k + s\, f_{k+1}, \qquad
        s = \frac{t - t_k}{t_{k+1} - t_k}, \quad t_k \le t \le t_{k+1}.

    Parameters
    ----------
    frames : (T, n, 3) or (T, n, 2) float array
        The shapes, same vertex count and order in every frame, ``T >= 1``; 2-D frames get
        ``z = 0``. With ``T = 1`` the file holds a static mesh (no targets, no animation).
    faces : (m, 3) int array, optional
        Triangles shared by all frames; ``None`` writes a point cloud.
    times : (T,) float array, optional
        Keyframe times in seconds, finite, ``>= 0`` and strictly increasing (also after the
        cast to float32). Default: ``T`` evenly spaced times from 0 to ``duration``.
    duration : float, default 2.0
        Length of the default timeline in seconds (ignored when ``times`` is given).
    name : str, optional
        Name of the mesh, its node and the animation.
    extras : dict, optional
        The node's glTF ``extras``, as in :func:`mesh_glb` (points get :func:`point_hints`).
    scene_extras : dict, optional
        The scene's glTF ``extras``.

    Returns
    -------
    bytes
        The GLB file. ``mesh.weights`` is all zeros (the base, ``frames[0]``, when no
        animation plays) and ``mesh.extras.targetNames`` names target ``k - 1``
        ``"frame k"``. Every morph target ``POSITION`` accessor carries ``min``/``max``.

    Raises
    ------
    InvalidInputError
        A wrong shape, NaN/Inf, values beyond float32, bad ``faces``, ``times`` not
        strictly increasing or negative, or a non-positive ``duration``.

    Notes
    -----
    A file holds ``T`` copies of the positions (base plus ``T - 1`` targets) and ``T (T-1)``
    animation weights; a viewer blends all targets on every frame, so keep ``T`` in the
    tens. Normals are not written: viewers compute flat normals of the morphed triangles.

    Examples
    --------
    >>> square = np.array([[0., 0], [1, 0], [1, 1], [0, 1]])
    >>> frames = np.stack([square * s for s in (1.0, 1.5, 2.0)])
    >>> doc = read_glb(morph_animation_glb(frames, [[0, 1, 2], [0, 2, 3]]))["json"]
    >>> doc["meshes"][0]["extras"]["targetNames"], doc["accessors"][-2]["max"]
    (['frame 1', 'frame 2'], [2.0])
    """
    try:
        arr = np.asarray(frames)
    except (ValueError, TypeError):
        arr = None
    if arr is None or arr.dtype.kind not in "iuf" or arr.ndim != 3 or arr.shape[0] < 1 \
            or arr.shape[1] < 1 or arr.shape[2] not in (2, 3):
        got = ("a ragged sequence" if arr is None
               else f"dtype {arr.dtype}" if arr.dtype.kind not in "iuf"
               else f"shape {tuple(arr.shape)}")
        raise _err("Expected `frames` to be a (T, n, 3) or (T, n, 2) array of finite numbers "
                   f"with T >= 1 and n >= 1, got {got}.", "frames")
    T, n, d = arr.shape
    # Checks the values (finite, float32 range) frame-major: `frames` row r is frame r // n.
    flat = as_points(arr.reshape(T * n, d), name="frames", min_points=1)
    _check_float32_range(flat, "frames")
    f64 = flat.reshape(T, n, d)
    if times is None:
        if isinstance(duration, bool) or not isinstance(duration, (int, float)) \
                or not np.isfinite(duration) or duration <= 0:
            raise _err(f"Expected `duration` to be a positive number of seconds, got "
                       f"{duration!r}.", "duration")
        t32 = np.linspace(0.0, float(duration), T).astype("<f4")
    else:
        t32 = _times(times, T)
    name = _name(name, "name")

    w = _Writer()
    base = np.zeros((n, 3), dtype="<f4")
    base[:, :d] = f64[0]
    attributes = {"POSITION": w.accessor(base, _FLOAT, "VEC3", target=_ARRAY_BUFFER,
                                         bounds=True)}
    points = faces is None
    primitive: dict[str, Any] = {"attributes": attributes,
                                 "mode": _POINTS if points else _TRIANGLES}
    if not points:
        idx, comp = _faces(faces, n, "faces")
        primitive["indices"] = w.accessor(idx, comp, "SCALAR", target=_ELEMENT_ARRAY_BUFFER)
    primitive["material"] = w.material([*_DEFAULT_GREY, 1.0], points=points, blend=False)
    mesh: dict[str, Any] = {"primitives": [primitive]}
    if name is not None:
        mesh["name"] = name
    if T > 1:
        # One (n, 3) block per target, each its own buffer view (the writer keeps them).
        deltas = np.zeros((T - 1, n, 3), dtype="<f4")
        np.subtract(f64[1:], f64[0], out=deltas[:, :, :d], casting="same_kind")
        targets = [{"POSITION": w.accessor(deltas[k], _FLOAT, "VEC3", target=_ARRAY_BUFFER,
                                           bounds=True)} for k in range(T - 1)]
        primitive["targets"] = targets
        mesh["weights"] = [0.0] * (T - 1)
        mesh["extras"] = {"targetNames": [f"frame {k}" for k in range(1, T)]}
    w.doc["meshes"].append(mesh)
    node_extras = _extras(extras, "extras")
    if points:
        node_extras = {**point_hints(f64[0]), **node_extras}
    node = w.node(0, name, node_extras)
    if T > 1:
        weights = np.zeros((T, T - 1), dtype="<f4")
        weights[np.arange(1, T), np.arange(T - 1)] = 1.0
        t_acc = w.accessor(t32, _FLOAT, "SCALAR", bounds=True)
        w_acc = w.accessor(weights.reshape(-1), _FLOAT, "SCALAR")
        animation: dict[str, Any] = {
            "samplers": [{"input": t_acc, "output": w_acc, "interpolation": "LINEAR"}],
            "channels": [{"sampler": 0, "target": {"node": node, "path": "weights"}}],
        }
        if name is not None:
            animation["name"] = name
        w.doc["animations"] = [animation]
    if scene_extras is not None:
        w.doc["scenes"][0]["extras"] = _extras(scene_extras, "scene_extras")
    return w.pack()


def _times(times: Any, T: int) -> np.ndarray:
    try:
        shape = np.shape(times)
    except (ValueError, TypeError):
        shape = None
    if shape != (T,):
        raise _err(f"Expected `times` to be a 1-D array of {T} times in seconds (one per "
                   f"frame), got {'a ragged sequence' if shape is None else f'shape {shape}'}.",
                   "times")
    arr = as_points(np.asarray(times).reshape(T, 1), name="times", dim=1, min_points=0)
    t = arr[:, 0]
    if T and t.min() < 0:
        raise _err(f"Expected `times` to be >= 0 seconds, got {t.min()!r} at position "
                   f"{int(np.argmin(t))}.", "times")
    _check_float32_range(arr, "times")
    t32 = t.astype("<f4")
    steps = np.diff(t32)
    if steps.size and not steps.min() > 0:
        k = int(np.argmax(~(steps > 0)))
        raise _err("Expected `times` to be strictly increasing (also as float32), got "
                   f"{t[k]!r} then {t[k + 1]!r} at positions {k} and {k + 1}.", "times")
    return t32


# Tableau 10 (matplotlib's "tab10"), then golden-ratio hues.
_TAB10 = np.array([
    [0x1F, 0x77, 0xB4], [0xFF, 0x7F, 0x0E], [0x2C, 0xA0, 0x2C], [0xD6, 0x27, 0x28],
    [0x94, 0x67, 0xBD], [0x8C, 0x56, 0x4B], [0xE3, 0x77, 0xC2], [0x7F, 0x7F, 0x7F],
    [0xBC, 0xBD, 0x22], [0x17, 0xBE, 0xCF]], dtype=np.float64) / 255.0
_NOISE_GREY = (0.85, 0.85, 0.85)
_GOLDEN = 0.6180339887498949


def _palette(codes: np.ndarray) -> np.ndarray:
    """(k,) non-negative label values -> (k, 3) colours: tab10, then golden-ratio hues."""
    codes = np.asarray(codes, dtype=np.float64)
    h = np.mod(codes * _GOLDEN, 1.0) * 6.0
    s = np.where(np.mod(np.floor(codes / 10), 2) == 0, 0.65, 0.45)
    v = np.where(np.mod(np.floor(codes / 20), 2) == 0, 0.85, 0.65)
    i = np.floor(h).astype(np.int64) % 6
    f = h - np.floor(h)
    p, q, t = v * (1 - s), v * (1 - s * f), v * (1 - s * (1 - f))
    out = np.stack([np.choose(i, [v, q, p, p, t, v]), np.choose(i, [t, v, v, q, p, p]),
                    np.choose(i, [p, p, t, v, v, q])], axis=1)
    small = codes < 10
    out[small] = _TAB10[codes[small].astype(np.int64)]
    return out


def label_colors(labels: Any) -> np.ndarray:
    """A deterministic RGB colour per label, for points coloured by cluster or class.

    Parameters
    ----------
    labels : (n,) array_like
        Integer labels (integral floats and bools count as integers), or any other
        sortable labels (strings, non-integral floats).

    Returns
    -------
    (n, 3) float64 array
        Colours in [0, 1]. An integer label ``k >= 0`` always gets the same colour, whatever
        the other labels: Tableau 10 (matplotlib's ``tab10``) for ``k < 10``, then hues
        stepped by the golden ratio (alternating saturation and value every ten labels).
        Negative labels (noise, as DBSCAN's -1) are light grey. Other labels are numbered
        by their rank among the sorted distinct labels, then coloured the same way.

    Raises
    ------
    InvalidInputError
        ``labels`` not 1-D, or a NaN label.

    Examples
    --------
    >>> label_colors([0, 1, -1]).round(3)
    array([[0.122, 0.467, 0.706],
           [1.   , 0.498, 0.055],
           [0.85 , 0.85 , 0.85 ]])
    >>> bool((label_colors(["b", "a"]) == label_colors([1, 0])).all())
    True
    """
    arr = np.asarray(labels)
    if arr.ndim != 1:
        raise _err(f"Expected `labels` to be a 1-D array (one label per point), got shape "
                   f"{tuple(arr.shape)}.", "labels")
    if arr.dtype.kind == "b":
        arr = arr.astype(np.int64)
    if arr.dtype.kind == "f":
        if np.isnan(arr).any():
            raise _err(f"Expected `labels` to hold no NaN, got one at position "
                       f"{int(np.argmax(np.isnan(arr)))}.", "labels")
        if np.isfinite(arr).all() and (arr == np.round(arr)).all() \
                and (arr.size == 0 or np.abs(arr).max() < 2.0**53):
            arr = arr.astype(np.int64)
    if arr.dtype.kind in "iu" and (arr.size == 0 or arr.max() < max(4 * arr.size, 1024)):
        # Small label values: colour each value once, then index (no sort of n labels).
        codes = np.maximum(arr.astype(np.int64), -1)
        table = np.vstack([_NOISE_GREY, _palette(np.arange(int(codes.max(initial=0)) + 1))])
        colors: np.ndarray = table[codes + 1]
        return colors
    if arr.dtype.kind in "iu":  # large label values: colour each distinct one
        values, inverse = np.unique(arr, return_inverse=True)
        table = np.empty((values.shape[0], 3))
        neg = values < 0
        table[neg] = _NOISE_GREY
        table[~neg] = _palette(values[~neg].astype(np.uint64).astype(np.float64))
        return table[inverse.reshape(-1)]
    try:
        values, codes = np.unique(arr, return_inverse=True)
    except TypeError:
        raise _err("Expected `labels` to be integers or sortable values of one type "
                   "(strings or numbers).", "labels") from None
    return _palette(np.arange(values.shape[0]))[codes.reshape(-1)]


# matplotlib's viridis at 0, 1/9, ..., 1 (its ten-colour sampling; the map is CC0)
_VIRIDIS = np.array([
    [0x44, 0x01, 0x54], [0x48, 0x28, 0x78], [0x3E, 0x49, 0x89], [0x31, 0x68, 0x8E],
    [0x26, 0x82, 0x8E], [0x1F, 0x9E, 0x89], [0x35, 0xB7, 0x79], [0x6E, 0xCE, 0x58],
    [0xB5, 0xDE, 0x2B], [0xFD, 0xE7, 0x25]], dtype=np.float64) / 255.0


def index_colors(n: int) -> np.ndarray:
    """A sequential colour per point by its index: viridis from dark purple (point 0) to
    yellow (point ``n - 1``), for points that have no labels (neighbours in the input order
    get neighbouring colours, so an embedding shows where the sequence goes).

    Parameters
    ----------
    n : int
        Number of points, ``n >= 0``.

    Returns
    -------
    (n, 3) float64 array
        Colours in [0, 1]: viridis at ``i / (n - 1)``, linearly interpolated between its
        ten-colour sampling (within 0.02 of the full map); point 0 alone is the first colour.

    Examples
    --------
    >>> (index_colors(2) * 255).round().astype(int).tolist()
    [[68, 1, 84], [253, 231, 37]]
    """
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 0:
        raise _err(f"Expected `n` to be an integer >= 0, got {n!r}.", "n")
    t = np.linspace(0.0, 1.0, int(n)) if n > 1 else np.zeros(int(n))
    x = t * (len(_VIRIDIS) - 1)
    out = np.stack([np.interp(x, np.arange(len(_VIRIDIS)), _VIRIDIS[:, c]) for c in range(3)],
                   axis=1)
    return out


def _png_rgb(image: np.ndarray) -> bytes:
    """An (h, w, 3) uint8 image as a PNG file: 8-bit RGB, one IDAT chunk, no filtering."""
    h, w, _ = image.shape

    def chunk(kind: bytes, body: bytes) -> bytes:
        return struct.pack(">I", len(body)) + kind + body + struct.pack(
            ">I", zlib.crc32(kind + body) & 0xFFFFFFFF)

    rows = np.zeros((h, 1 + 3 * w), dtype=np.uint8)  # filter byte 0 (None) on each row
    rows[:, 1:] = image.reshape(h, 3 * w)
    return (_PNG_SIGNATURE + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(rows.tobytes(), 9)) + chunk(b"IEND", b""))


#: The checker's light squares; the dark ones are tinted by their place in the square.
CHECKER_LIGHT = (235, 235, 235)


def checker_png(size: int = 512, cells: int = 16) -> bytes:
    """A checker texture over the unit square of UV space, as a PNG file.

    The square ``[0, 1]²`` holds ``cells × cells`` squares: the square of ``(u, v)`` is
    ``(floor(u cells), floor(v cells)) = (i, j)``; it is light grey (:data:`CHECKER_LIGHT`)
    when ``i + j`` is even, else dark and tinted so that the layout's orientation shows:
    red ``64 + 160 i / (cells - 1)``, green 90, blue ``64 + 160 j / (cells - 1)`` (reddish
    towards +u, bluish towards +v). Pixel row ``r`` holds ``v = 1 - (r + 1/2) / size``, as
    glTF textures hold ``(u, 1 - v)`` (see the module's notes), so the image appears
    upright on a mesh textured by :func:`mesh_glb`.

    Parameters
    ----------
    size : int, default 512
        Width and height in pixels, a power of two (mipmapped everywhere, WebGL 1 too).
    cells : int, default 16
        Squares along each side, at least 2, dividing ``size``.

    Returns
    -------
    bytes
        The PNG file (8-bit RGB).

    Examples
    --------
    >>> checker_png(8, 2)[:8]
    b'\\x89PNG\\r\\n\\x1a\\n'
    """
    if size < 2 or size & (size - 1) or cells < 2 or size % cells:
        raise _err(f"Expected `size` a power of two and `cells` >= 2 dividing it, got size "
                   f"{size!r}, cells {cells!r}.", "size")
    centre = (np.arange(size) + 0.5) / size
    i = np.floor(centre * cells).astype(np.int64)  # columns: u
    j = np.floor((1.0 - centre) * cells).astype(np.int64)  # rows: v = 1 - t
    image = np.empty((size, size, 3), dtype=np.uint8)
    image[:, :, 0] = (64 + 160 * i[None, :] / (cells - 1)).round()
    image[:, :, 1] = 90
    image[:, :, 2] = (64 + 160 * j[:, None] / (cells - 1)).round()
    light = (i[None, :] + j[:, None]) % 2 == 0
    image[light] = CHECKER_LIGHT
    return _png_rgb(image)


#: Rotation of -90° about +x, as a glTF quaternion (x, y, z, w): takes +z to +y.
_Z_UP_TO_Y_UP = [-float(np.sqrt(0.5)), 0.0, 0.0, float(np.sqrt(0.5))]


def y_up(glb: bytes, *, up: str = "z") -> bytes:
    """The GLB ``glb`` with its scene turned so that the data's ``up`` axis points up.

    glTF's up axis is +y; scans and CAD data usually have +z up. For ``up="z"`` the
    scene's nodes become the children of one new root node, named ``"z-up to y-up"``,
    whose rotation (-90° about +x) takes +z to +y (and +y to -z): the positions
    themselves are unchanged, so every accessor, animation and node index stays valid.
    The scene's ``extras.up`` becomes ``"z"``. ``up="y"`` returns ``glb`` as it is.

    Parameters
    ----------
    glb : bytes
        A GLB file as written here (JSON chunk first).
    up : {"y", "z"}, default "z"
        The axis of the data that points up.

    Returns
    -------
    bytes
        The GLB file.

    Examples
    --------
    >>> doc = read_glb(y_up(mesh_glb(np.eye(3))))["json"]
    >>> doc["nodes"][-1]["name"], doc["scenes"][0]["nodes"]
    ('z-up to y-up', [1])
    """
    if up not in ("y", "z"):
        raise _err(f"Expected `up` to be 'y' or 'z', got {up!r}.", "up")
    if up == "y":
        return glb
    json_len = struct.unpack_from("<I", glb, 12)[0]
    doc = json.loads(bytes(glb[20:20 + json_len]))
    scene = doc["scenes"][doc.get("scene", 0)]
    doc.setdefault("nodes", []).append({"name": "z-up to y-up", "rotation": _Z_UP_TO_Y_UP,
                                        "children": scene.get("nodes", [])})
    scene["nodes"] = [len(doc["nodes"]) - 1]
    scene["extras"] = {**scene.get("extras", {}), "up": "z"}
    text = json.dumps(doc, separators=(",", ":"), allow_nan=False).encode("utf-8")
    text += b" " * (-len(text) % 4)
    rest = bytes(glb[20 + json_len:])
    return b"".join([struct.pack("<III", _GLB_MAGIC, 2, 12 + 8 + len(text) + len(rest)),
                     struct.pack("<II", len(text), _CHUNK_JSON), text, rest])


# --------------------------------------------------------------------------------------
# Reading and checking
# --------------------------------------------------------------------------------------

def _fail(field: str | None, problem: str) -> InvalidInputError:
    what = f"`{field}`" if field else "the glTF file"
    return InvalidInputError(f"Expected {what} to be a well-formed glTF 2.0 file (GLB or "
                             f"glTF JSON) that holds all the data it declares: {problem}",
                             field=field)


def _split_glb(data: memoryview, field: str | None) -> tuple[dict[str, Any], memoryview | None]:
    """The JSON document and the BIN chunk of a GLB (checked to lie inside ``data``)."""
    n = len(data)
    if n < 20:
        raise _fail(field, f"it is truncated ({n} bytes, less than a GLB header and a chunk "
                           "header).")
    magic, version, length = struct.unpack_from("<III", data, 0)
    if version != 2:
        raise _fail(field, f"its GLB header says version {version}, not 2.")
    if length != n:
        what = "it is truncated" if length > n else "it has bytes after its end"
        raise _fail(field, f"{what}: the header declares {length} bytes, the file holds {n}.")
    json_chunk: memoryview | None = None
    bin_chunk: memoryview | None = None
    pos = 12
    while pos < n:
        if pos + 8 > n:
            raise _fail(field, f"it is truncated inside a chunk header at byte {pos}.")
        size, kind = struct.unpack_from("<II", data, pos)
        if pos + 8 + size > n:
            raise _fail(field, f"a chunk at byte {pos} declares {size} bytes, beyond the "
                               f"end of the file ({n} bytes).")
        body = data[pos + 8: pos + 8 + size]
        if json_chunk is None:
            if kind != _CHUNK_JSON:
                raise _fail(field, "its first chunk is not JSON.")
            json_chunk = body
        elif kind == _CHUNK_BIN and bin_chunk is None:
            bin_chunk = body
        pos += 8 + size  # chunk lengths include their padding (multiples of 4)
    if json_chunk is None:  # unreachable: n >= 20 means one chunk header was read
        raise _fail(field, "it has no JSON chunk.")
    return _parse_json(json_chunk, field), bin_chunk


def _parse_json(raw: memoryview | bytes, field: str | None) -> dict[str, Any]:
    try:
        text = bytes(raw).rstrip(b" \t\r\n\0").decode("utf-8")
        doc = json.loads(text)
    except (UnicodeDecodeError, ValueError, RecursionError) as exc:
        raise _fail(field, f"its JSON does not parse ({type(exc).__name__}: "
                           f"{str(exc)[:120]}).") from None
    if not isinstance(doc, dict):
        raise _fail(field, "its JSON is not an object.")
    asset = doc.get("asset")
    version = asset.get("version") if isinstance(asset, dict) else None
    if not isinstance(version, str) or not version.startswith("2."):
        raise _fail(field, f"its asset.version is {version!r}, not '2.0'.")
    return doc


def _items(doc: dict[str, Any], key: str, field: str | None) -> list[dict[str, Any]]:
    items = doc.get(key, [])
    if not isinstance(items, list) or not all(isinstance(x, dict) for x in items):
        raise _fail(field, f"`{key}` is not a list of objects.")
    return items


def _int(obj: dict[str, Any], key: str, where: str, field: str | None, *, default: int | None
         = None, minimum: int = 0, maximum: int | None = None) -> int:
    value = obj.get(key, default)
    if isinstance(value, float) and value.is_integer():
        value = int(value)
    if not isinstance(value, int) or isinstance(value, bool) or value < minimum or (
            maximum is not None and value > maximum):
        bound = f" in [{minimum}, {maximum}]" if maximum is not None else f" >= {minimum}"
        raise _fail(field, f"{where}.{key} is {value!r}, not an integer{bound}.")
    return value


def _data_uri_size(uri: str, where: str, field: str | None) -> int:
    """The decoded size of a base64 data URI, without decoding it."""
    head, sep, payload = uri.partition(",")
    if not sep or not head.endswith(";base64"):
        raise _fail(field, f"{where}.uri is a data URI that is not base64.")
    payload = payload.strip()
    return len(payload) * 3 // 4 - payload[-2:].count("=")


def _check_doc(doc: dict[str, Any], bin_chunk: memoryview | None, max_bytes: int,
               field: str | None) -> None:
    buffers = _items(doc, "buffers", field)
    sizes = []
    for i, buf in enumerate(buffers):
        where = f"buffers[{i}]"
        length = _int(buf, "byteLength", where, field, minimum=1)
        uri = buf.get("uri")
        if uri is None:
            have = len(bin_chunk) if (i == 0 and bin_chunk is not None) else 0
            if length > have:
                raise _fail(field, f"{where} declares {length} bytes but the binary chunk "
                                   f"holds {have}.")
        elif isinstance(uri, str) and uri.startswith("data:"):
            have = _data_uri_size(uri, where, field)
            if length > have:
                raise _fail(field, f"{where} declares {length} bytes but its data URI holds "
                                   f"{have}.")
        else:
            raise _fail(field, f"{where} refers to an external file ({str(uri)[:80]!r}); "
                               "only data embedded in the file is accepted.")
        sizes.append(length)
    views = _items(doc, "bufferViews", field)
    view_sizes = []
    for i, view in enumerate(views):
        where = f"bufferViews[{i}]"
        b = _int(view, "buffer", where, field, maximum=len(sizes) - 1)
        offset = _int(view, "byteOffset", where, field, default=0)
        length = _int(view, "byteLength", where, field, minimum=1)
        if "byteStride" in view:
            _int(view, "byteStride", where, field, minimum=4, maximum=252)
        if offset + length > sizes[b]:
            raise _fail(field, f"{where} spans bytes {offset}..{offset + length} of "
                               f"buffers[{b}], which has {sizes[b]}.")
        view_sizes.append(length)

    def span(obj: dict[str, Any], where: str, count: int, elem: int, stride: int) -> None:
        v = _int(obj, "bufferView", where, field, maximum=len(view_sizes) - 1)
        offset = _int(obj, "byteOffset", where, field, default=0)
        end = offset + stride * (count - 1) + elem
        if end > view_sizes[v]:
            raise _fail(field, f"{where} needs bytes {offset}..{end} of bufferViews[{v}], "
                               f"which has {view_sizes[v]}.")

    total = 0
    for i, acc in enumerate(_items(doc, "accessors", field)):
        where = f"accessors[{i}]"
        comp = acc.get("componentType")
        kind = acc.get("type")
        if comp not in _COMPONENT_DTYPE or kind not in _TYPE_SIZE:
            raise _fail(field, f"{where} has componentType {comp!r} and type {kind!r}.")
        count = _int(acc, "count", where, field, minimum=1)
        elem = np.dtype(_COMPONENT_DTYPE[comp]).itemsize * _TYPE_SIZE[kind]
        total += count * elem
        if total > max_bytes:
            raise _fail(field, f"its accessors declare more than {max_bytes} bytes of data "
                               f"(the limit), {where} alone {count * elem}.")
        if "bufferView" in acc:
            v = _int(acc, "bufferView", where, field, maximum=len(view_sizes) - 1)
            stride = views[v].get("byteStride", elem)
            span(acc, where, count, elem, stride)
        sparse = acc.get("sparse")
        if sparse is not None:
            if not isinstance(sparse, dict) or not isinstance(sparse.get("indices"), dict) \
                    or not isinstance(sparse.get("values"), dict):
                raise _fail(field, f"{where}.sparse is not an object with indices and values.")
            scount = _int(sparse, "count", f"{where}.sparse", field, minimum=1, maximum=count)
            icomp = sparse["indices"].get("componentType")
            if icomp not in (_UBYTE, _USHORT, _UINT):
                raise _fail(field, f"{where}.sparse.indices has componentType {icomp!r}.")
            isize = np.dtype(_COMPONENT_DTYPE[icomp]).itemsize
            span(sparse["indices"], f"{where}.sparse.indices", scount, isize, isize)
            span(sparse["values"], f"{where}.sparse.values", scount, elem, elem)
    for i, image in enumerate(_items(doc, "images", field)):
        uri = image.get("uri")
        if uri is not None and not (isinstance(uri, str) and uri.startswith("data:")):
            raise _fail(field, f"images[{i}] refers to an external file ({str(uri)[:80]!r}); "
                               "only data embedded in the file is accepted.")
        if "bufferView" in image:
            _int(image, "bufferView", f"images[{i}]", field, maximum=len(view_sizes) - 1)


def _load(data: Any, max_bytes: int, field: str | None
          ) -> tuple[dict[str, Any], memoryview | None]:
    try:
        mem = memoryview(data).cast("B")
    except TypeError:
        raise _fail(field, f"got {type(data).__name__}, not bytes.") from None
    if len(mem) > max_bytes:
        raise _fail(field, f"it is {len(mem)} bytes, more than the limit of {max_bytes}.")
    if len(mem) == 0:
        raise _fail(field, "it is empty.")
    if bytes(mem[:4]) == b"glTF":
        doc, bin_chunk = _split_glb(mem, field)
    else:
        doc, bin_chunk = _parse_json(mem, field), None
    _check_doc(doc, bin_chunk, max_bytes, field)
    return doc, bin_chunk


def check_glb(data: bytes, max_bytes: int, *, field: str | None = None) -> dict[str, Any]:
    """Refuse a glTF/GLB that is truncated, too large, or declares data it does not hold.

    Call this on an upload before a loader (trimesh) sees it: a loader trusts the sizes in
    the JSON and may allocate them before finding the data missing.

    Parameters
    ----------
    data : bytes-like
        A GLB file, or a glTF JSON file with its buffers in data URIs.
    max_bytes : int
        Largest accepted file, and largest total of data its accessors may describe (a
        well-formed file's accessors describe at most the bytes it holds).
    field : str, optional
        The input's name, used in messages and as the error's ``field``.

    Returns
    -------
    dict
        The parsed glTF JSON document.

    Raises
    ------
    InvalidInputError
        The file is larger than ``max_bytes``; the GLB header's length differs from the
        file's; a chunk runs past the end; the JSON does not parse or is not glTF 2.0; a
        buffer declares more bytes than the binary chunk (or its data URI) holds; a buffer
        view lies outside its buffer; an accessor (or its sparse part) lies outside its
        buffer view; the accessors together describe more than ``max_bytes``; a buffer or
        image refers to an external file (uploads carry no other files).

    Examples
    --------
    >>> glb = mesh_glb(np.eye(3))
    >>> check_glb(glb, 1 << 20)["asset"]["generator"]
    'morphserve'
    >>> check_glb(glb[:-4], 1 << 20)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    algorithms.core.errors.InvalidInputError: Expected the glTF file to be a well-formed ...
    """
    doc, _ = _load(data, max_bytes, field)
    return doc


def read_glb(data: bytes) -> dict[str, Any]:
    """Parse a GLB (or glTF JSON with data URIs): its JSON and every accessor as numpy.

    The file is first checked by :func:`check_glb` with a limit of four times its size.

    Parameters
    ----------
    data : bytes-like
        The file.

    Returns
    -------
    dict
        ``"json"``: the glTF JSON document; ``"accessors"``: one array per accessor, as
        stored (``TEXCOORD_0`` flipped, normalized integers not scaled, sparse values
        applied), shape ``(count,)`` for SCALAR and ``(count, k)`` otherwise (matrices
        flattened column by column, without their column padding).

    Raises
    ------
    InvalidInputError
        Whatever :func:`check_glb` refuses.

    Examples
    --------
    >>> out = read_glb(mesh_glb([[0, 0], [1, 0], [0, 1]], [[0, 1, 2]]))
    >>> out["accessors"][0]
    array([[0., 0., 0.],
           [1., 0., 0.],
           [0., 1., 0.]], dtype=float32)
    >>> out["accessors"][1]
    array([0, 1, 2], dtype=uint16)
    """
    mem = memoryview(data).cast("B")
    doc, bin_chunk = _load(mem, max(4 * len(mem), 1 << 16), None)
    buffers = []
    for i, buf in enumerate(doc.get("buffers", [])):
        uri = buf.get("uri")
        if uri is None:
            buffers.append(bin_chunk if i == 0 else memoryview(b""))
        else:
            try:
                buffers.append(memoryview(base64.b64decode(uri.partition(",")[2])))
            except (binascii.Error, ValueError):
                raise _fail(None, f"buffers[{i}].uri is not valid base64.") from None
    views = doc.get("bufferViews", [])

    def raw(obj: dict[str, Any], count: int, dtype: np.dtype, k: int, stride: int | None
            ) -> np.ndarray:
        view = views[obj["bufferView"]]
        start = view.get("byteOffset", 0)
        body = buffers[view["buffer"]][start: start + view["byteLength"]]
        step = stride or dtype.itemsize * k
        out = np.ndarray((count, k), dtype=dtype, buffer=body, offset=obj.get("byteOffset", 0),
                         strides=(step, dtype.itemsize))
        return out.copy()

    accessors = []
    for acc in doc.get("accessors", []):
        dtype = np.dtype(_COMPONENT_DTYPE[acc["componentType"]])
        k = _TYPE_SIZE[acc["type"]]
        count = acc["count"]
        if "bufferView" in acc:
            stride = views[acc["bufferView"]].get("byteStride")
            arr = raw(acc, count, dtype, k, stride)
        else:
            arr = np.zeros((count, k), dtype=dtype)
        sparse = acc.get("sparse")
        if sparse is not None:
            sidx = raw(sparse["indices"], sparse["count"],
                       np.dtype(_COMPONENT_DTYPE[sparse["indices"]["componentType"]]), 1, None)
            arr[sidx[:, 0]] = raw(sparse["values"], sparse["count"], dtype, k, None)
        accessors.append(arr[:, 0] if acc["type"] == "SCALAR" else arr)
    return {"json": doc, "accessors": accessors}
