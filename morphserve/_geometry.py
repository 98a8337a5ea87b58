"""Geometry in and out: the point sets and meshes of trimesh, Open3D and PyVista, and files.

Going out, :func:`prepare_inputs` turns what a user hands :meth:`Client.execute` into what the
service reads, by the form each input takes as the process description declares it (its JSON
Schema: an ``(n, d)`` array of points, a ``{vertices, faces}`` mesh, or either):

- numpy arrays, lists, numbers and dicts go as they are;
- a mesh object (``trimesh.Trimesh``, Open3D ``TriangleMesh``, PyVista ``PolyData`` with
  faces) goes as ``{vertices, faces}`` to an input that takes a mesh, as its vertices to one
  that takes points; a point cloud object (``trimesh.PointCloud``, Open3D ``PointCloud``,
  PyVista ``PolyData`` or ``PointSet`` without faces) as its points;
- a path (``pathlib.Path``, or a string that is not a value the input takes, such as
  ``"rigid"``) names a file: uploaded as it is (the service reads .ply, .obj, .stl, .off, .glb
  and .npy by what the input takes), or, inside a list, read here with trimesh. A path that
  names no file raises :class:`NoSuchFile` before anything is sent.

The objects are recognised by their attributes, not their types, so none of these libraries is
needed unless the user has one: ``faces`` + ``vertices`` (trimesh), ``vertices`` +
``triangles`` (Open3D), ``points`` + a flat ``faces`` array ``[3, i, j, k, 3, ...]`` (PyVista),
``points`` or ``vertices`` alone (point clouds).

Coming back, :func:`output_geometry` finds the mesh or points of a results document, and
:func:`to_open3d` and :func:`to_pyvista` build those libraries' objects from it (trimesh's are
built in :meth:`Results.to_trimesh`).
"""

from __future__ import annotations

import errno
import os
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ._exceptions import MorphserveError

__all__ = ["FILE_SUFFIXES", "Geometry", "NoSuchFile", "as_geometry", "geometry_forms",
           "needs_description", "prepare_inputs", "output_geometry", "to_open3d", "to_pyvista"]

#: Suffixes of the geometry files the service reads.
FILE_SUFFIXES = frozenset({".npy", ".ply", ".obj", ".stl", ".off", ".glb"})


class NoSuchFile(MorphserveError, FileNotFoundError):
    """An input was given as a path (or a string that is no value it takes) naming no file.

    Raised before any request is sent. ``filename`` is the path as given; ``input`` the name
    of the input.
    """

    def __init__(self, message: str, filename: str, input: str | None = None) -> None:  # noqa: A002
        super().__init__(errno.ENOENT, message, filename)
        self.input = input

    def __str__(self) -> str:
        return str(self.strerror)

    def __reduce__(self) -> tuple[Any, ...]:
        return (type(self), (self.strerror, self.filename, self.input))


@dataclass(frozen=True)
class Geometry:
    """A point set or a triangle mesh taken from another library's object."""

    vertices: np.ndarray
    """(n, d) coordinates."""
    faces: np.ndarray | None
    """(m, 3) vertex indices of the triangles; None for a point cloud."""
    what: str
    """What it was made from, for messages: ``"Trimesh"``, ``"PointCloud"`` ..."""

    def as_input(self, forms: frozenset[str], name: str) -> Any:
        """The JSON-ready value for an input taking ``forms`` (``"points"``, ``"mesh"``;
        empty when the input declares neither: then a mesh when there are faces)."""
        if self.faces is not None and ("mesh" in forms or not forms):
            return {"vertices": self.vertices, "faces": self.faces}
        if "points" in forms or not forms:
            return self.vertices
        raise TypeError(f"Expected `{name}` to be a mesh with faces, got a {self.what} of "
                        f"{len(self.vertices)} points and no faces.")


def _array(value: Any, dtype: type) -> np.ndarray:
    return np.asarray(value, dtype=dtype)


def _polydata_faces(flat: np.ndarray, what: str) -> np.ndarray | None:
    """The (m, 3) triangles of PyVista's padded face array ``[3, i, j, k, 3, ...]``."""
    flat = np.asarray(flat, dtype=np.int64).ravel()
    if flat.size == 0:
        return None
    if flat.size % 4 == 0 and np.all(flat[::4] == 3):
        triangles: np.ndarray = flat.reshape(-1, 4)[:, 1:]
        return triangles
    at = 0
    while at < flat.size:  # find the first face that is not a triangle, for the message
        if flat[at] != 3:
            raise ValueError(f"This {what} has a face of {flat[at]} vertices; the service "
                             "takes triangles: call .triangulate() on it first.")
        at += 4
    raise ValueError(f"This {what}'s face array is not of the form [3, i, j, k, 3, ...].")


def as_geometry(value: Any) -> Geometry | None:
    """``value`` as a :class:`Geometry` if it is a mesh or point cloud object of trimesh,
    Open3D or PyVista (or anything with their attributes); None for anything else (arrays,
    lists, dicts, numbers, strings)."""
    if value is None or isinstance(value, (np.ndarray, Mapping, list, tuple, str, bytes,
                                           int, float, complex, os.PathLike, np.generic)):
        return None
    what = type(value).__name__
    if hasattr(value, "points") and hasattr(value, "faces"):  # PyVista PolyData
        return Geometry(_array(value.points, np.float64),
                        _polydata_faces(np.asarray(value.faces), what), what)
    if hasattr(value, "vertices") and hasattr(value, "faces"):  # trimesh.Trimesh
        faces = _array(value.faces, np.int64)
        return Geometry(_array(value.vertices, np.float64),
                        faces if faces.size else None, what)
    if hasattr(value, "vertices") and hasattr(value, "triangles"):  # Open3D TriangleMesh
        faces = _array(value.triangles, np.int64).reshape(-1, 3)
        return Geometry(_array(value.vertices, np.float64),
                        faces if len(faces) else None, what)
    if hasattr(value, "points"):  # Open3D PointCloud, PyVista PointSet
        return Geometry(_array(value.points, np.float64), None, what)
    if hasattr(value, "vertices"):  # trimesh.PointCloud
        return Geometry(_array(value.vertices, np.float64), None, what)
    return None


# -- what an input takes, by its JSON Schema ---------------------------------------------


def _alternatives(schema: Any) -> Iterator[Mapping[str, Any]]:
    if not isinstance(schema, Mapping):
        return
    union = schema.get("oneOf") or schema.get("anyOf")
    if isinstance(union, list):
        for alternative in union:
            yield from _alternatives(alternative)
    else:
        yield schema


def _types(schema: Mapping[str, Any]) -> set[str]:
    kind = schema.get("type")
    return set(kind) if isinstance(kind, list) else {kind} if isinstance(kind, str) else set()


def geometry_forms(schema: Any) -> frozenset[str]:
    """Which geometry an input of this schema takes: ``"mesh"`` (an object of vertices and
    faces), ``"points"`` (an array of rows of numbers), both, or neither."""
    forms = set()
    for alternative in _alternatives(schema):
        types = _types(alternative)
        properties = alternative.get("properties")
        if "object" in types and isinstance(properties, Mapping) and \
                {"vertices", "faces"} <= set(properties):
            forms.add("mesh")
        items = alternative.get("items")
        if "array" in types and isinstance(items, Mapping) and "array" in _types(items):
            inner = items.get("items")
            if isinstance(inner, Mapping) and _types(inner) & {"number", "integer"}:
                forms.add("points")
    return frozenset(forms)


def _item_schema(schema: Any) -> Any:
    """The schema of the members of a list input whose members are geometry (a list of point
    sets), else None."""
    for alternative in _alternatives(schema):
        items = alternative.get("items")
        if "array" in _types(alternative) and geometry_forms(items):
            return items
    return None


def _takes_string(schema: Any, value: str) -> bool:
    """Whether an input of this schema takes ``value`` as it is (a choice such as
    ``"rigid"``, or free text)."""
    for alternative in _alternatives(schema):
        if "enum" in alternative:
            if value in alternative["enum"]:
                return True
        elif "const" in alternative:
            if value == alternative["const"]:
                return True
        elif "string" in _types(alternative):
            return True
    return False


def _describe_forms(forms: frozenset[str]) -> str:
    if forms == {"points", "mesh"}:
        return "points, a mesh or a geometry file"
    if forms == {"mesh"}:
        return "a mesh or a mesh file"
    if forms == {"points"}:
        return "points or a geometry file"
    return "a value or a file"


def needs_description(inputs: Mapping[str, Any]) -> bool:
    """Whether preparing ``inputs`` needs the process description: a string (a value, or a
    file?), a mesh object (sent as a mesh, or as its points?), or a list holding either."""
    def needs(value: Any) -> bool:
        if isinstance(value, str):
            return True
        geometry = as_geometry(value)
        return geometry is not None and geometry.faces is not None

    for value in inputs.values():
        if needs(value):
            return True
        if isinstance(value, (list, tuple)) and any(
                needs(v) or isinstance(v, os.PathLike) for v in value):
            return True
    return False


def _choices(schema: Any) -> list[str]:
    """The strings an input of this schema takes as they are (its choices)."""
    return [str(v) for alternative in _alternatives(schema)
            for v in alternative.get("enum") or () if isinstance(v, str)]


def _missing(name: str, path: str, forms: frozenset[str],
             choices: list[str] | None = None) -> NoSuchFile:
    what = _describe_forms(forms)
    if choices:
        what += ", or one of " + ", ".join(repr(c) for c in choices)
    return NoSuchFile(f"Expected `{name}` to be {what}; got {path!r}, which names no file "
                      f"(looked in {os.getcwd()}).", path, name)


def _read_file(path: Path, name: str) -> Geometry | np.ndarray:
    """A geometry file read here (for a list member, which cannot be an upload of its own):
    .npy as its array, the others through trimesh."""
    if path.suffix.lower() == ".npy":
        array: np.ndarray = np.load(path, allow_pickle=False)
        return array
    import trimesh

    loaded: Any = trimesh.load(str(path), process=False)
    if isinstance(loaded, trimesh.Scene):  # .glb: its meshes as one
        loaded = loaded.to_geometry() if hasattr(loaded, "to_geometry") else \
            loaded.dump(concatenate=True)
    geometry = as_geometry(loaded)
    if geometry is None:
        raise ValueError(f"The file {str(path)!r} given for `{name}` holds no points or mesh.")
    return geometry


def _prepare_member(value: Any, schema: Any, name: str) -> Any:
    forms = geometry_forms(schema)
    if isinstance(value, (str, os.PathLike)):
        path = Path(value)
        if not path.is_file():
            raise _missing(name, str(value), forms)
        value = _read_file(path, name)
    geometry = value if isinstance(value, Geometry) else as_geometry(value)
    return value if geometry is None else geometry.as_input(forms, name)


def prepare_inputs(inputs: Mapping[str, Any], schemas: Mapping[str, Any] | None
                   ) -> tuple[dict[str, Any], dict[str, Path]]:
    """The inputs to send as values (geometry objects turned into arrays or meshes) and the
    files to upload, by input name.

    ``schemas`` maps input names to their JSON Schemas (from the process description); None
    when it was not needed (see :func:`needs_description`) or an input is not described (the
    service then names the unknown input).

    Raises :class:`NoSuchFile` for a path naming no file, ``TypeError`` for a point cloud
    given to an input that takes only meshes.
    """
    values: dict[str, Any] = {}
    files: dict[str, Path] = {}
    for name, value in inputs.items():
        schema = (schemas or {}).get(name)
        forms = geometry_forms(schema)
        if isinstance(value, os.PathLike):
            path = Path(value)
            if not path.is_file():
                raise _missing(name, os.fspath(value), forms)
            files[name] = path
        elif isinstance(value, str):
            # a file if it can be one: the input takes geometry, or the name says so
            filelike = bool(forms) or Path(value).suffix.lower() in FILE_SUFFIXES
            if schema is not None and _takes_string(schema, value):
                values[name] = value
            elif filelike and Path(value).is_file():
                files[name] = Path(value)
            elif filelike:
                raise _missing(name, value, forms, _choices(schema))
            else:  # a wrong choice, or an input the process lacks: the service says which
                values[name] = value
        elif isinstance(value, (list, tuple)) and _item_schema(schema) is not None:
            item = _item_schema(schema)
            values[name] = [_prepare_member(v, item, f"{name}[{i}]") for i, v in
                            enumerate(value)]
        else:
            geometry = as_geometry(value)
            values[name] = value if geometry is None else geometry.as_input(forms, name)
    return values, files


# -- results back as geometry objects ----------------------------------------------------

#: Outputs that hold the geometry of a result, in the order they are preferred.
GEOMETRY_OUTPUTS = ("mesh", "moved", "positions", "mean_shape", "embedding", "uv")


def output_geometry(values: Mapping[str, Any], name: str | None) -> tuple[Geometry, str]:
    """The mesh or points of the results ``values`` (output name to value) and the output
    they came from: ``name``, or by default the first of :data:`GEOMETRY_OUTPUTS` there.
    Coordinates are made 3-D (a 2-D layout or UV map lies in z = 0)."""
    if name is None:
        name = next((n for n in GEOMETRY_OUTPUTS if n in values), None)
        if name is None:
            raise ValueError(f"These results hold no mesh or points (their outputs: "
                             f"{', '.join(values) or 'none'}); name the output to convert.")
    try:
        value = values[name]
    except KeyError:
        raise KeyError(f"No output {name!r}; the outputs are: {', '.join(values)}.") from None
    if isinstance(value, Mapping) and "vertices" in value:
        vertices = _as_3d(np.asarray(value["vertices"], dtype=np.float64), name)
        faces = value.get("faces")
        return Geometry(vertices, None if faces is None else
                        np.asarray(faces, dtype=np.int64), "mesh"), name
    return Geometry(_as_3d(np.asarray(value, dtype=np.float64), name), None, "points"), name


def _as_3d(points: np.ndarray, name: str) -> np.ndarray:
    if points.ndim != 2 or points.shape[1] not in (2, 3):
        raise ValueError(f"The output {name!r} is not a mesh or (n, 2|3) points "
                         f"(its shape is {points.shape}).")
    if points.shape[1] == 3:
        return points
    return np.hstack([points, np.zeros((len(points), 1))])


def _import(module: str, package: str) -> Any:
    import importlib

    try:
        return importlib.import_module(module)
    except ImportError as exc:  # not installed, or installed without its native parts
        raise ImportError(f"This needs {package}, which could not be imported ({exc}); "
                          f"install it with `pip install {package}`.") from exc


def to_open3d(geometry: Geometry) -> Any:
    """An Open3D ``TriangleMesh`` (with faces) or ``PointCloud``."""
    o3d = _import("open3d", "open3d")
    vertices = o3d.utility.Vector3dVector(np.ascontiguousarray(geometry.vertices))
    if geometry.faces is None:
        return o3d.geometry.PointCloud(vertices)
    triangles = o3d.utility.Vector3iVector(
        np.ascontiguousarray(geometry.faces, dtype=np.int32))
    return o3d.geometry.TriangleMesh(vertices, triangles)


def to_pyvista(geometry: Geometry) -> Any:
    """A PyVista ``PolyData``: triangles in its padded face layout, or vertices alone."""
    pv = _import("pyvista", "pyvista")
    if geometry.faces is None:
        return pv.PolyData(geometry.vertices)
    faces = np.hstack([np.full((len(geometry.faces), 1), 3, dtype=np.int64),
                       geometry.faces]).ravel()
    return pv.PolyData(geometry.vertices, faces)
