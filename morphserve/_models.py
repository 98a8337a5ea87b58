"""What the SDK hands back: small frozen dataclasses and a read-only mapping of results.

Each model is built from the JSON document of the HTTP contract by its ``from_json``
classmethod, which raises :class:`~morphserve.ProtocolError` when a required member is
missing, so a server drifting from the contract fails loudly rather than with a KeyError.
"""

from __future__ import annotations

import io
import json
import os
import sys
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass, field
from datetime import datetime
from pathlib import Path
from typing import Any

import numpy as np
import pybase64  # SIMD base64: 30x binascii's speed on large arrays

from ._exceptions import ProtocolError
from ._geometry import as_geometry, output_geometry, to_open3d, to_pyvista

__all__ = [
    "JOB_STATES",
    "JobStatus",
    "ProcessDescription",
    "ProcessSummary",
    "Results",
    "to_json_value",
]

JOB_STATES = ("accepted", "running", "successful", "failed", "dismissed")
"""Every job status, in the order a job goes through them."""
_FINAL_STATES = frozenset({"successful", "failed", "dismissed"})


def _member(document: Mapping[str, Any], name: str, what: str) -> Any:
    try:
        return document[name]
    except (KeyError, TypeError):
        raise ProtocolError(f"Expected {what} to hold `{name}`, got {document!r:.200}.") from None


def _timestamp(value: Any, name: str) -> datetime | None:
    if value is None:
        return None
    try:
        return datetime.fromisoformat(value)
    except (TypeError, ValueError):
        raise ProtocolError(f"Expected `{name}` to be an ISO-8601 time, got {value!r}.") from None


@dataclass(frozen=True)
class ProcessSummary:
    """One process of the catalog, as ``GET /processes`` lists it."""

    id: str
    title: str
    description: str
    version: str | None
    job_control_options: tuple[str, ...]

    @classmethod
    def _fields_from_json(cls, document: Mapping[str, Any]) -> dict[str, Any]:
        return {
            "id": _member(document, "id", "a process"),
            "title": document.get("title") or "",
            "description": document.get("description") or "",
            "version": document.get("version"),
            "job_control_options": tuple(document.get("jobControlOptions") or ()),
        }

    @classmethod
    def from_json(cls, document: Mapping[str, Any]) -> ProcessSummary:
        """Build from one entry of the ``processes`` list."""
        return cls(**cls._fields_from_json(document))


@dataclass(frozen=True)
class ProcessDescription(ProcessSummary):
    """A process with its inputs and outputs, as ``GET /processes/{id}`` describes it.

    ``inputs`` maps each input name to its description (``title``, ``description``, ``schema``
    holding a JSON Schema with any ``default``, ``minOccurs``, ``maxOccurs``); ``outputs`` maps
    each output name to its ``title``, ``description`` and ``schema``. ``raw`` is the whole
    document.
    """

    inputs: dict[str, dict[str, Any]]
    outputs: dict[str, dict[str, Any]]
    raw: dict[str, Any] = field(repr=False, compare=False)

    @classmethod
    def from_json(cls, document: Mapping[str, Any]) -> ProcessDescription:
        """Build from the process description document."""
        return cls(
            **cls._fields_from_json(document),
            inputs=dict(document.get("inputs") or {}),
            outputs=dict(document.get("outputs") or {}),
            raw=dict(document),
        )


@dataclass(frozen=True)
class JobStatus:
    """Where a job stands, as ``GET /jobs/{id}`` answers (the statusInfo document).

    ``status`` is one of ``accepted``, ``running``, ``successful``, ``failed``,
    ``dismissed``; ``progress`` is 0 to 100 (None when the service did not say); times are
    timezone-aware when the service sends an offset, as it does.
    """

    job_id: str
    process_id: str | None
    status: str
    progress: int | None = None
    message: str | None = None
    created: datetime | None = None
    started: datetime | None = None
    finished: datetime | None = None
    updated: datetime | None = None
    raw: dict[str, Any] = field(default_factory=dict, repr=False, compare=False)

    @property
    def done(self) -> bool:
        """True once the job has ended: successful, failed or dismissed."""
        return self.status in _FINAL_STATES

    @classmethod
    def from_json(cls, document: Mapping[str, Any]) -> JobStatus:
        """Build from a statusInfo document."""
        progress = document.get("progress")
        return cls(
            job_id=str(_member(document, "jobID", "a job status")),
            process_id=document.get("processID"),
            status=str(_member(document, "status", "a job status")),
            progress=None if progress is None else int(progress),
            message=document.get("message") or None,
            created=_timestamp(document.get("created"), "created"),
            started=_timestamp(document.get("started"), "started"),
            finished=_timestamp(document.get("finished"), "finished"),
            updated=_timestamp(document.get("updated"), "updated"),
            raw=dict(document),
        )


def _from_json_value(value: Any) -> Any:
    """A JSON list as a numpy array when it is a regular grid of numbers, a typed binary
    array as its numpy array (shape and dtype kept, empty ones too), objects member by
    member; anything else unchanged."""
    if isinstance(value, dict):
        if value.keys() == {"dtype", "shape", "data"}:
            return np.frombuffer(pybase64.b64decode(value["data"]), dtype=value["dtype"]
                                 ).reshape(value["shape"]).astype(
                                     np.dtype(value["dtype"]).newbyteorder("="))
        return {k: _from_json_value(v) for k, v in value.items()}
    if not isinstance(value, list):
        return value
    try:
        array = np.asarray(value)
    except ValueError:  # ragged: lists of lists of different lengths
        return value
    if array.dtype.kind not in "biuf":  # strings, nulls, objects, ints beyond int64
        return value
    return array


class Results(Mapping[str, Any]):
    """The outputs of a successful job: a read-only mapping of output name to value.

    JSON arrays come back as numpy arrays (lists of ints stay int, of bools stay bool); ragged
    lists, lists of strings and objects stay as JSON gave them; numbers, booleans and strings
    are plain Python. ``raw`` is the results document as JSON values.
    """

    __slots__ = ("_raw", "_values", "_download")

    def __init__(self, document: Mapping[str, Any],
                 download: Callable[[str, str | None], bytes] | None = None) -> None:
        self._raw = dict(document)
        self._values = {name: _from_json_value(value) for name, value in self._raw.items()}
        self._download = download

    def to_json(self) -> dict[str, Any]:
        """The results as plain JSON values: arrays as nested lists (``raw`` keeps what the
        service sent, typed binary arrays included)."""
        plain: dict[str, Any] = _plain(self._values)
        return plain

    def save(self, path: str | os.PathLike[str], output: str | None = None) -> Path:
        """Write the results to a file, in the format its suffix names.

        - ``.glb``: the result's geometry as glTF binary, made by the service (a moved source
          over its target, a deformed or UV-mapped mesh, an embedding coloured by label, an
          interpolation as a morph-target animation); opens in Blender or a browser viewer.
        - ``.ply``, ``.obj``, ``.stl``, ``.off``: the mesh or points of the results (the
          output named ``output``, by default as :meth:`to_trimesh` picks it), written by
          trimesh; .stl and .off need a mesh, .ply and .obj also take points.
        - ``.npy``: one array output (``output`` names it unless the results hold just one).
        - ``.json``: the results document.

        Returns the path written. Raises ``ValueError`` for another suffix and
        :class:`NotAcceptable` when the results have no such representation.
        """
        target = Path(path)
        suffix = target.suffix.lower()
        if suffix == ".json":
            target.write_text(json.dumps(self.to_json()) + "\n")
            return target
        if suffix == ".npy":
            if output is None:
                arrays = [k for k, v in self._values.items() if isinstance(v, np.ndarray)]
                if len(arrays) != 1:
                    raise ValueError(f"Name the output to save as .npy: one of {arrays}.")
                output = arrays[0]
            buf = io.BytesIO()
            np.save(buf, np.asarray(self[output]), allow_pickle=False)
            target.write_bytes(buf.getvalue())
            return target
        if suffix in MESH_SUFFIXES:
            geometry = self.to_trimesh(output)
            if suffix in (".stl", ".off") and not hasattr(geometry, "faces"):
                raise ValueError(f"A {suffix} file holds a mesh; these results give points "
                                 "(save them as .ply or .obj).")
            target.write_bytes(_exported(geometry, suffix))
            return target
        if suffix != ".glb":
            raise ValueError(f"Expected a path ending in .glb, .ply, .obj, .stl, .off, .npy "
                             f"or .json, got {str(path)!r}.")
        if self._download is None:
            raise TypeError("These results were not fetched by a synchronous Client; use "
                            "`await job.save(path)` with an AsyncClient.")
        target.write_bytes(self._download("glb", output))
        return target

    def to_trimesh(self, name: str | None = None) -> Any:
        """An output as a ``trimesh`` object: a mesh output (``{vertices, faces}``) as
        ``trimesh.Trimesh`` (with ``uv`` as its texture coordinates when the results have
        them), an (n, 2|3) array as ``trimesh.PointCloud`` (2-D coordinates in z = 0).
        ``name`` defaults to the first of ``mesh``, ``moved``, ``positions``,
        ``mean_shape``, ``embedding``, ``uv`` the results hold."""
        import trimesh

        geometry, name = output_geometry(self._values, name)
        if geometry.faces is None:
            # trimesh does not annotate this constructor
            return trimesh.PointCloud(geometry.vertices)  # type: ignore[no-untyped-call]
        mesh = trimesh.Trimesh(geometry.vertices, geometry.faces, process=False)
        uv = self._values.get("uv")
        if name == "mesh" and isinstance(uv, np.ndarray) and len(uv) == len(geometry.vertices):
            # trimesh does not annotate this constructor
            mesh.visual = trimesh.visual.TextureVisuals(uv=uv)  # type: ignore[no-untyped-call]
        return mesh

    def to_open3d(self, name: str | None = None) -> Any:
        """An output as an Open3D ``TriangleMesh`` (a mesh output) or ``PointCloud`` (an
        (n, 2|3) array); ``name`` as in :meth:`to_trimesh`. Raises ImportError naming the
        package when Open3D is not installed (``pip install open3d``)."""
        return to_open3d(output_geometry(self._values, name)[0])

    def to_pyvista(self, name: str | None = None) -> Any:
        """An output as a PyVista ``PolyData`` (triangles, or points alone); ``name`` as in
        :meth:`to_trimesh`. Raises ImportError naming the package when PyVista (and its VTK)
        cannot be imported (``pip install pyvista``)."""
        return to_pyvista(output_geometry(self._values, name)[0])

    @property
    def raw(self) -> dict[str, Any]:
        """The results document as the service sent it (JSON values)."""
        return self._raw

    def __getitem__(self, name: str) -> Any:
        try:
            return self._values[name]
        except KeyError:
            known = ", ".join(self._values) or "none"
            raise KeyError(f"No output {name!r}; the outputs are: {known}.") from None

    def __iter__(self) -> Iterator[str]:
        return iter(self._values)

    def __len__(self) -> int:
        return len(self._values)

    def __repr__(self) -> str:
        parts = []
        for name, value in self._values.items():
            if isinstance(value, np.ndarray):
                parts.append(f"{name}=<{value.dtype} array {value.shape}>")
            else:
                parts.append(f"{name}={value!r:.40}")
        return f"Results({', '.join(parts)})"


#: Suffixes :meth:`Results.save` writes through trimesh.
MESH_SUFFIXES = (".ply", ".obj", ".stl", ".off")


def _exported(geometry: Any, suffix: str) -> bytes:
    """``geometry`` (a trimesh object) as the bytes of a file of this suffix."""
    data = geometry.export(file_type=suffix.lstrip("."))
    return data.encode() if isinstance(data, str) else bytes(data)


def _plain(value: Any) -> Any:
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, np.generic):
        return value.item()
    return value


#: Arrays of at least this many numbers (and empty ones, which keep their shape so) travel
#: as typed binary arrays: bit-exact, and decoded in milliseconds where JSON lists of a
#: million points take over 100 ms.
BINARY_ABOVE = 1024


def binary_array(a: np.ndarray) -> dict[str, Any]:
    """The service's typed binary array object for ``a``: dtype, shape, base64 bytes."""
    a = np.ascontiguousarray(a)
    if a.dtype.byteorder == ">" or (a.dtype.byteorder == "=" and sys.byteorder == "big"):
        a = a.astype(a.dtype.newbyteorder("<"))
    return {"dtype": a.dtype.newbyteorder("<").str, "shape": list(a.shape),
            "data": pybase64.b64encode_as_string(a.data)}


#: Arrays of at least this many bytes (an input, or a member of a mesh-like input) are
#: uploaded as ``.npy`` parts of a multipart request instead: the body is a quarter
#: smaller than with base64, nothing is encoded or decoded, and the service keeps the
#: arrays as views of the body (bench/transport.py).
NPY_ABOVE = 1 << 20


def _npy_worthy(value: Any) -> bool:
    return isinstance(value, np.ndarray) and value.nbytes >= NPY_ABOVE and \
        value.dtype.kind in "iuf" and value.dtype.itemsize <= 8 and 1 <= value.ndim <= 4


def npy_bytes(a: np.ndarray) -> bytes:
    """``a`` as the bytes of an ``.npy`` file (C order)."""
    buf = io.BytesIO()
    np.save(buf, np.ascontiguousarray(a), allow_pickle=False)
    return buf.getvalue()


def split_npy_parts(inputs: Mapping[str, Any]) -> tuple[dict[str, Any], dict[str, np.ndarray]]:
    """``inputs`` without their large arrays (:data:`NPY_ABOVE`), and those arrays by part
    name: ``name`` for an input, ``name.member`` for a member of a mapping or of a
    ``trimesh`` object (``mesh.vertices``)."""
    rest: dict[str, Any] = {}
    parts: dict[str, np.ndarray] = {}
    for name, value in inputs.items():
        if _npy_worthy(value):
            parts[name] = value
            continue
        geometry = as_geometry(value)  # prepare_inputs has turned these to arrays already
        if geometry is not None:
            value = geometry.as_input(frozenset(), name)
        if isinstance(value, Mapping) and any(_npy_worthy(v) for v in value.values()):
            parts.update({f"{name}.{k}": v for k, v in value.items() if _npy_worthy(v)})
            value = {k: v for k, v in value.items() if not _npy_worthy(v)}
            if not value:
                continue
        rest[name] = value
    return rest, parts


def to_json_value(value: Any, name: str = "input") -> Any:
    """An input value as plain JSON: numpy arrays become lists (large or empty ones typed
    binary arrays, see :func:`binary_array`), numpy scalars numbers.

    The service validates: NaN and infinity are sent (as the ``NaN``/``Infinity`` tokens
    Python's json writes, which the service reads) so that its :class:`InvalidInput` names the
    input and row, as do arrays of strings. Raises TypeError, naming the input, only for a
    value JSON cannot hold at all.
    """
    if isinstance(value, np.ndarray):
        if value.dtype.kind not in "biufUS":
            raise TypeError(
                f"Expected `{name}` to be an array of numbers, got dtype {value.dtype}."
            )
        if value.dtype.kind in "iuf" and value.dtype.itemsize <= 8 and \
                (value.size >= BINARY_ABOVE or value.size == 0) and 1 <= value.ndim <= 4:
            return binary_array(value)
        return value.tolist()
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, Mapping):
        return {str(k): to_json_value(v, f"{name}.{k}") for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [to_json_value(v, f"{name}[{i}]") for i, v in enumerate(value)]
    if value is None or isinstance(value, (str, int, float, bool)):
        return value
    geometry = as_geometry(value)  # a mesh or point cloud object (trimesh, Open3D, PyVista)
    if geometry is not None:
        return to_json_value(geometry.as_input(frozenset(), name), name)
    if hasattr(value, "__array__"):
        return to_json_value(np.asarray(value), name)
    raise TypeError(
        f"Expected `{name}` to be a numpy array, number, string, list or dict, "
        f"got {type(value).__name__}."
    )


def dumps(document: Any) -> bytes:
    """Compact UTF-8 JSON of an already converted document (NaN/Infinity as Python writes
    them: the service answers with an error naming where they are)."""
    return json.dumps(document, separators=(",", ":"), allow_nan=True).encode()
