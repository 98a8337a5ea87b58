"""The GLB scene of a result: one builder per kind of geometry a process returns.

A catalog entry declares which builder shows its results (``Process.geometry``); nothing
here looks at a process's id, family or output names to guess it. Each builder takes the
result's outputs, the job's validated inputs and a name for the scene's mesh (the
process id) and returns the GLB, or None when this
particular result has nothing to show (a clustering of a graph given without points):

- :func:`animation` — interpolation frames: one mesh with a morph target per frame and a
  LINEAR animation through them;
- :func:`uv_mesh` — a parameterization: the mesh with ``TEXCOORD_0`` (the UVs moved and
  scaled uniformly into the unit square);
- :func:`deformed_mesh` — the ``mesh`` output;
- :func:`layout` — the laid-out ``positions``, with the input mesh's faces when there is one;
- :func:`clusters` — the input points coloured by cluster ``labels``;
- :func:`embedding` — the embedded points (first three components), coloured by class when
  labels are known;
- :func:`moved_source` — the moved source and the target as two coloured point clouds or
  meshes (an alignment or registration: ``moved`` or ``transform``);
- :func:`moved_sets` — every input set moved by its ``transforms`` row (multiway
  registration).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from service import gltf

__all__ = ["animation", "uv_mesh", "deformed_mesh", "layout", "clusters", "embedding",
           "moved_source", "moved_sets", "SOURCE_COLOR", "TARGET_COLOR"]

Outputs = Mapping[str, Any]
Inputs = Mapping[str, Any]

#: Colours of the two sides of a registration: the moved source and the target.
SOURCE_COLOR = (0.95, 0.45, 0.1)
TARGET_COLOR = (0.15, 0.45, 0.85)


def _xyz(points: Any) -> np.ndarray:
    """Points as 3-D positions: 1-D and 2-D padded with zeros, more dimensions cut to the
    first three (an embedding's leading components)."""
    p = np.asarray(points, dtype=np.float64)
    if p.ndim == 1:
        p = p[:, None]
    if p.shape[1] >= 3:
        return p[:, :3]
    return np.hstack([p, np.zeros((len(p), 3 - p.shape[1]))])


def _apply(transform: Any, points: np.ndarray) -> np.ndarray:
    """A homogeneous (d+1)×(d+1) transform (projective included) applied to (n, d) points."""
    t = np.asarray(transform, dtype=np.float64)
    d = points.shape[1]
    h = points @ t[:d, :d].T + t[:d, d]
    w = points @ t[d, :d] + t[d, d]
    return h / w[:, None] if not np.allclose(t[d, :d], 0) or t[d, d] != 1 else h


def _mesh_parts(value: Any) -> tuple[np.ndarray, np.ndarray | None]:
    """Vertices and faces of a mesh input or output (a Mesh, a dict) or of points."""
    if hasattr(value, "vertices"):
        return np.asarray(value.vertices), np.asarray(value.faces)
    if isinstance(value, dict) and "vertices" in value:
        return np.asarray(value["vertices"]), np.asarray(value.get("faces"))
    return np.asarray(value), None


def _seconds(times: Any, duration: float = 2.0) -> np.ndarray | None:
    """Keyframe times of the animation: the frames' parameters stretched over ``duration``
    seconds when they increase, else evenly spaced (None)."""
    if times is None:
        return None
    t = np.asarray(times, dtype=np.float64).ravel()
    if len(t) < 2 or not np.all(np.diff(t) > 0):
        return None
    seconds: np.ndarray = (t - t[0]) * (duration / (t[-1] - t[0]))
    return seconds


def _unit_square(uv: Any) -> np.ndarray:
    """UVs moved and scaled uniformly into [0, 1]² (texture space), aspect kept."""
    uv = np.asarray(uv, dtype=np.float64)
    lo = uv.min(axis=0)
    span = float((uv.max(axis=0) - lo).max()) or 1.0
    unit: np.ndarray = (uv - lo) / span
    return unit


def animation(outputs: Outputs, inputs: Inputs, name: str) -> bytes:
    """``frames`` as a morph animation over the ``faces`` output (or the input mesh's);
    tetrahedra show their boundary triangles, point sets their points."""
    from algorithms.interpolation import surface_triangles

    faces = outputs.get("faces")
    if faces is None:
        _, faces = _mesh_parts(inputs.get("mesh", inputs.get("source")))
    frames = np.asarray(outputs["frames"], dtype=np.float64)
    faces = surface_triangles(frames[0], faces) if faces is not None and len(faces) else None
    # 2-D frames go as they are: the writer sets z = 0
    return gltf.morph_animation_glb(frames, faces, times=_seconds(outputs.get("times")))


def uv_mesh(outputs: Outputs, inputs: Inputs, name: str) -> bytes:
    """The ``mesh`` output (else the input mesh) textured by ``uv``."""
    vertices, faces = _mesh_parts(outputs.get("mesh", inputs.get("mesh")))
    return gltf.mesh_glb(_xyz(vertices), faces, uv=_unit_square(outputs["uv"]),
                         name=name)


def deformed_mesh(outputs: Outputs, inputs: Inputs, name: str) -> bytes:
    """The ``mesh`` output."""
    vertices, faces = _mesh_parts(outputs["mesh"])
    return gltf.mesh_glb(_xyz(vertices), faces, name=name)


def layout(outputs: Outputs, inputs: Inputs, name: str) -> bytes:
    """The ``positions`` output, with the input mesh's faces when a mesh was laid out."""
    mesh = inputs.get("mesh")
    faces = _mesh_parts(mesh)[1] if mesh is not None else None
    return gltf.mesh_glb(_xyz(outputs["positions"]), faces, name=name)


def clusters(outputs: Outputs, inputs: Inputs, name: str) -> bytes | None:
    """The input ``points`` coloured by ``labels``; None for a graph given without points."""
    if inputs.get("points") is None:
        return None
    return gltf.mesh_glb(_xyz(inputs["points"]), None,
                         colors=gltf.label_colors(outputs["labels"]), name=name)


def embedding(outputs: Outputs, inputs: Inputs, name: str) -> bytes:
    """The ``embedding`` output, coloured by the input's ``labels`` (or the result's own
    ``labels`` or ``predictions``) when one label per point is known."""
    emb = np.asarray(outputs["embedding"])
    labels = None
    for source in (inputs.get("labels"), outputs.get("labels"), outputs.get("predictions")):
        if source is not None and np.ndim(source) == 1 and len(source) == len(emb):
            labels = np.asarray(source)
            break
    colors = gltf.label_colors(labels) if labels is not None else None
    return gltf.mesh_glb(_xyz(emb), None, colors=colors, name=name)


def moved_source(outputs: Outputs, inputs: Inputs, name: str) -> bytes | None:
    """The ``source`` moved by the result (its ``moved`` output, else its ``transform``)
    beside the ``target``; None for sets of more than three dimensions."""
    src_v, src_f = _mesh_parts(inputs["source"])
    dst_v, dst_f = _mesh_parts(inputs["target"])
    if src_v.ndim != 2 or dst_v.ndim != 2 or src_v.shape[1] > 3 or dst_v.shape[1] > 3:
        return None
    if outputs.get("moved") is not None:
        moved = np.asarray(outputs["moved"], dtype=np.float64)
    else:
        moved = _apply(outputs["transform"], src_v.astype(np.float64))
    return gltf.scene_glb([
        {"vertices": _xyz(moved), "faces": src_f, "color": SOURCE_COLOR,
         "name": "source (moved)"},
        {"vertices": _xyz(dst_v), "faces": dst_f, "color": TARGET_COLOR, "name": "target"},
    ])


def moved_sets(outputs: Outputs, inputs: Inputs, name: str) -> bytes:
    """Every input set moved by its row of ``transforms``, one node each."""
    sets = [np.asarray(s, dtype=np.float64) for s in inputs["sets"]]
    return gltf.scene_glb([{"vertices": _xyz(_apply(t, s)), "name": f"set {i}"}
                           for i, (t, s) in enumerate(zip(outputs["transforms"], sets))])
