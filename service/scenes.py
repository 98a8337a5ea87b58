"""The GLB scene of a result: one builder per kind of geometry a process returns.

A catalog entry declares which builder shows its results (``Process.geometry``); nothing
here looks at a process's id, family or output names to guess it. Each builder takes the
result's outputs, the job's validated inputs and a name for the scene's mesh (the
process id) and returns the GLB, or None when this
particular result has nothing to show (a clustering of a graph given without points):

- :func:`animation` — interpolation frames: one mesh with a morph target per frame and a
  LINEAR animation through them;
- :func:`uv_mesh` — a parameterization: the mesh with ``TEXCOORD_0`` (the UVs moved and
  scaled uniformly into the unit square) and a checker texture, beside the flat UV layout
  textured the same way;
- :func:`deformed_mesh` — the ``mesh`` output, and the handles' target positions as points;
- :func:`layout` — the laid-out ``positions``, with the input mesh's faces when there is one,
  coloured by vertex index;
- :func:`clusters` — the input points coloured by cluster ``labels``;
- :func:`embedding` — the embedded points (first three components), coloured by class when
  labels are known, else by index;
- :func:`moved_source` — the moved source, the target and the source where it was, as
  coloured point clouds or meshes (an alignment or registration: ``moved`` or
  ``transform``);
- :func:`moved_sets` — every input set moved by its ``transforms`` row (multiway
  registration).

What a viewer can read besides the geometry (glTF ``extras``; three.js puts them in
``userData``):

- the scene: ``{"kind": <builder name>, "up": "y"}`` (``"up": "z"`` once
  :func:`service.gltf.y_up` has turned the scene under its root node ``"z-up to y-up"``);
- every node: ``"role"``, one of ``"mesh"`` (a result's mesh), ``"uv-layout"``,
  ``"handles"``, ``"points"`` (embedding, clustering), ``"layout"``, ``"frames"``
  (interpolation), ``"moved"``, ``"target"``, ``"source"`` (registration), ``"set"``
  (multiway, with ``"set": i``);
- coloured nodes: ``"colorBy"`` (``"labels"`` or ``"index"``) and, for labels,
  ``"legend"``: ``[{"label": value, "color": [r, g, b]}, ...]`` for up to 64 labels;
- point clouds: ``"pointSize"`` (pixels) and ``"pointSpacing"`` (world units), the
  suggested size of a drawn point (:func:`service.gltf.point_hints`);
- the UV layout: ``"origin"`` and ``"scale"``: its vertex ``k`` is at
  ``origin + scale * (u_k, v_k, 0)``, with ``(u, v)`` the UVs in the unit square.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from algorithms.core.mesh import Handles
from service import gltf

__all__ = ["animation", "uv_mesh", "deformed_mesh", "layout", "clusters", "embedding",
           "moved_source", "moved_sets", "SOURCE_COLOR", "TARGET_COLOR", "ORIGINAL_COLOR",
           "HANDLE_COLOR", "CHECKER"]

Outputs = Mapping[str, Any]
Inputs = Mapping[str, Any]

#: Colours of the two sides of a registration: the moved source and the target.
SOURCE_COLOR = (0.95, 0.45, 0.1)
TARGET_COLOR = (0.15, 0.45, 0.85)
#: The source where it was, before the registration moved it.
ORIGINAL_COLOR = (0.6, 0.6, 0.6)
#: The deformation handles' target positions.
HANDLE_COLOR = (0.85, 0.1, 0.1)
#: The checker texture of parameterizations (16 × 16 squares over the unit square).
CHECKER = gltf.checker_png()

_LEGEND_MAX = 64


def _scene(kind: str) -> dict[str, Any]:
    return {"kind": kind, "up": "y"}


def _json_value(x: Any) -> Any:
    return x.item() if isinstance(x, np.generic) else x


def _colour_by(labels: np.ndarray | None, n: int) -> tuple[np.ndarray, dict[str, Any]]:
    """Per-point colours and the node extras that say how: by ``labels`` (the qualitative
    palette of :func:`service.gltf.label_colors`, with a legend of up to 64 labels), else by
    index (viridis, :func:`service.gltf.index_colors`)."""
    if labels is None:
        return gltf.index_colors(n), {"colorBy": "index"}
    colors = gltf.label_colors(labels)
    extras: dict[str, Any] = {"colorBy": "labels"}
    values, first = np.unique(labels, return_index=True)
    if len(values) <= _LEGEND_MAX:
        extras["legend"] = [{"label": _json_value(v), "color": [float(c) for c in colors[i]]}
                            for v, i in zip(values, first)]
    return colors, extras


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
    return gltf.morph_animation_glb(frames, faces, times=_seconds(outputs.get("times")),
                                    extras={"role": "frames"},
                                    scene_extras=_scene("animation"))


def _layout_place(vertices: np.ndarray) -> tuple[np.ndarray, float]:
    """Where the flat UV layout goes beside a mesh: the origin of its unit square and its
    side, the mesh's largest extent (1 for a mesh of one point), to the right of the mesh
    (+x) by a quarter side, centred on the mesh in y and z."""
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    side = float((hi - lo).max()) or 1.0
    centre = (lo + hi) / 2
    origin = np.array([hi[0] + 0.25 * side, centre[1] - side / 2, centre[2]])
    return origin, side


def uv_mesh(outputs: Outputs, inputs: Inputs, name: str) -> bytes:
    """The ``mesh`` output (else the input mesh) textured by ``uv`` with the checker, and
    beside it the flat UV layout (the same triangles at ``(u, v, 0)``) with the same
    texture, so that any viewer shows the unwrap and its distortion."""
    vertices, faces = _mesh_parts(outputs.get("mesh", inputs.get("mesh")))
    xyz = _xyz(vertices)
    uv = _unit_square(outputs["uv"])
    origin, side = _layout_place(xyz)
    flat = origin + side * np.c_[uv, np.zeros(len(uv))]
    return gltf.scene_glb([
        {"vertices": xyz, "faces": faces, "uv": uv, "texture": CHECKER, "name": name,
         "extras": {"role": "mesh"}},
        {"vertices": flat, "faces": faces, "uv": uv, "texture": CHECKER, "name": "UV layout",
         "extras": {"role": "uv-layout", "origin": [float(x) for x in origin],
                    "scale": side}},
    ], extras=_scene("uv_mesh"))


def deformed_mesh(outputs: Outputs, inputs: Inputs, name: str) -> bytes:
    """The ``mesh`` output, and the handles' target positions as red points when the
    inputs have handles."""
    vertices, faces = _mesh_parts(outputs["mesh"])
    parts: list[dict[str, Any]] = [{"vertices": _xyz(vertices), "faces": faces, "name": name,
                                    "extras": {"role": "mesh"}}]
    handles = inputs.get("handles")
    if isinstance(handles, Handles) and len(handles.positions) \
            and handles.positions.shape[1] <= 3:
        parts.append({"vertices": _xyz(handles.positions), "color": HANDLE_COLOR,
                      "name": "handles", "extras": {
                          "role": "handles", "indices": np.asarray(handles.indices).tolist()}})
    return gltf.scene_glb(parts, extras=_scene("deformed_mesh"))


def layout(outputs: Outputs, inputs: Inputs, name: str) -> bytes:
    """The ``positions`` output, with the input mesh's faces when a mesh was laid out,
    coloured by the input's ``labels`` when it has one per vertex, else by index."""
    mesh = inputs.get("mesh")
    faces = _mesh_parts(mesh)[1] if mesh is not None else None
    positions = _xyz(outputs["positions"])
    colors, extras = _colour_by(_labels_of(len(positions), inputs.get("labels")),
                                len(positions))
    return gltf.scene_glb([{"vertices": positions, "faces": faces, "colors": colors,
                            "name": name, "extras": {"role": "layout", **extras}}],
                          extras=_scene("layout"))


def _labels_of(n: int, *sources: Any) -> np.ndarray | None:
    """The first of ``sources`` that holds one label per point (of ``n``), or None."""
    for source in sources:
        if source is not None and np.ndim(source) == 1 and len(source) == n:
            return np.asarray(source)
    return None


def matched_classes(clusters: np.ndarray, classes: np.ndarray) -> np.ndarray:
    """Each point's cluster named after the class it matches: clusters and classes paired
    one to one so that the most points agree (the assignment that maximises the trace of
    their contingency table). A cluster left without a class takes a name of its own: the
    next integers after the classes' largest (integer classes), else ``"cluster k"``. Points
    whose cluster is their class then share its colour; the misclustered stand out."""
    from scipy.optimize import linear_sum_assignment

    ids, cluster_of = np.unique(clusters, return_inverse=True)
    names, class_of = np.unique(classes, return_inverse=True)
    table = np.zeros((len(ids), len(names)), dtype=np.int64)
    np.add.at(table, (cluster_of, class_of), 1)
    rows, cols = linear_sum_assignment(table, maximize=True)
    match = dict(zip(rows.tolist(), cols.tolist()))
    integral = np.issubdtype(names.dtype, np.integer)
    spare = iter(range(int(names.max()) + 1, int(names.max()) + 1 + len(ids))) if integral \
        else None
    out = [names[match[r]].item() if r in match
           else (next(spare) if spare is not None else f"cluster {ids[r]}")
           for r in range(len(ids))]
    return np.asarray(out)[cluster_of]


def clusters(outputs: Outputs, inputs: Inputs, name: str) -> bytes | None:
    """The input ``points`` coloured by their cluster (``labels``); with class ``labels``
    among the inputs, each cluster takes the colour of the class it matches best
    (:func:`matched_classes`). None for a graph given without points."""
    if inputs.get("points") is None:
        return None
    points = _xyz(inputs["points"])
    found = np.asarray(outputs["labels"])
    classes = _labels_of(len(points), inputs.get("labels"))
    colors, extras = _colour_by(found if classes is None else matched_classes(found, classes),
                                len(points))
    return gltf.scene_glb([{"vertices": points, "colors": colors, "name": name,
                            "extras": {"role": "points", **extras}}],
                          extras=_scene("clusters"))


def embedding(outputs: Outputs, inputs: Inputs, name: str) -> bytes:
    """The ``embedding`` output, coloured by the input's ``labels`` (or the result's own
    ``labels`` or ``predictions``) when one label per point is known, else by index."""
    emb = _xyz(outputs["embedding"])
    labels = _labels_of(len(emb), inputs.get("labels"), outputs.get("labels"),
                        outputs.get("predictions"))
    colors, extras = _colour_by(labels, len(emb))
    return gltf.scene_glb([{"vertices": emb, "colors": colors, "name": name,
                            "extras": {"role": "points", **extras}}],
                          extras=_scene("embedding"))


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
         "name": "source (moved)", "extras": {"role": "moved"}},
        {"vertices": _xyz(dst_v), "faces": dst_f, "color": TARGET_COLOR, "name": "target",
         "extras": {"role": "target"}},
        {"vertices": _xyz(src_v), "faces": src_f, "color": ORIGINAL_COLOR, "name": "source",
         "extras": {"role": "source"}},
    ], extras=_scene("moved_source"))


def moved_sets(outputs: Outputs, inputs: Inputs, name: str) -> bytes:
    """Every input set moved by its row of ``transforms``, one node each."""
    sets = [np.asarray(s, dtype=np.float64) for s in inputs["sets"]]
    return gltf.scene_glb([{"vertices": _xyz(_apply(t, s)), "name": f"set {i}",
                            "extras": {"role": "set", "set": i}}
                           for i, (t, s) in enumerate(zip(outputs["transforms"], sets))],
                          extras=_scene("moved_sets"))
