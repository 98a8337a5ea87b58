"""Make ``patch.ply``, the tour's mesh: a disk cut from the airplane mesh in pyvista's wheel.

Run ``.venv/bin/python examples/meshes/make_patch.py`` (it needs pyvista's wheel installed, as
``make test`` installs it, but never imports pyvista). One wing of the airplane (of its two
second-largest connected pieces, the one whose centre lies further along x) is grown into a
patch from the vertex nearest to its centre: faces are taken in the order of their centres'
distance to that vertex, each one kept only if the patch stays a topological disk (one
boundary loop, Euler characteristic 1, every edge on at most two faces). The result is
written as binary PLY with the vertices in the order they were first used.
"""

from __future__ import annotations

import sys
from collections import Counter
from pathlib import Path

import numpy as np
import trimesh

HERE = Path(__file__).resolve().parent
FACES = 350
"""Faces in the patch."""


def _airplane() -> Path:
    import importlib.util

    spec = importlib.util.find_spec("pyvista")  # where the wheel is, without importing it
    if spec is None or spec.origin is None:
        sys.exit("pyvista's wheel is not installed (make test installs it)")
    return Path(spec.origin).parent / "examples" / "airplane.ply"


def _is_disk(faces: list[tuple[int, int, int]]) -> bool:
    edges = Counter(tuple(sorted(e)) for f in faces
                    for e in ((f[0], f[1]), (f[1], f[2]), (f[2], f[0])))
    if max(edges.values()) > 2:
        return False
    vertices = {v for f in faces for v in f}
    if len(vertices) - len(edges) + len(faces) != 1:
        return False
    boundary = [e for e, n in edges.items() if n == 1]
    degree = Counter(v for e in boundary for v in e)
    if any(d != 2 for d in degree.values()):
        return False
    # one loop: walk it from any boundary vertex
    nxt: dict[int, list[int]] = {}
    for a, b in boundary:
        nxt.setdefault(a, []).append(b)
        nxt.setdefault(b, []).append(a)
    start = boundary[0][0]
    seen, previous, here = {start}, start, nxt[start][0]
    while here != start:
        seen.add(here)
        previous, here = here, next(v for v in nxt[here] if v != previous)
    return len(seen) == len(degree)


def wing(mesh: trimesh.Trimesh) -> np.ndarray:
    """The faces of the wing the module's docstring names."""
    pieces = trimesh.graph.connected_components(mesh.face_adjacency, min_len=1)
    sizes = sorted({len(p) for p in pieces})
    wings = [p for p in pieces if len(p) == sizes[-2]]
    return max(wings, key=lambda p: mesh.triangles_center[p][:, 0].mean())


def patch(mesh: trimesh.Trimesh, piece: np.ndarray, n_faces: int) -> trimesh.Trimesh:
    """A disk of ``n_faces`` faces of ``mesh`` from the faces ``piece``, grown as the
    module's docstring says."""
    centres = mesh.triangles_center[piece]
    seed = mesh.vertices[mesh.faces[piece]].reshape(-1, 3)
    seed = seed[np.argmin(np.linalg.norm(seed - centres.mean(axis=0), axis=1))]
    order = piece[np.argsort(np.linalg.norm(centres - seed, axis=1), kind="stable")]
    kept: list[tuple[int, int, int]] = []
    pending = [tuple(int(v) for v in mesh.faces[f]) for f in order]
    while len(kept) < n_faces and pending:
        for i, face in enumerate(pending):
            touching = not kept or len(set(face) & {v for f in kept for v in f}) >= 2
            if touching and _is_disk([*kept, face]):
                kept.append(face)
                del pending[i]
                break
        else:
            break
    used = list(dict.fromkeys(v for f in kept for v in f))
    index = {v: i for i, v in enumerate(used)}
    faces = np.array([[index[v] for v in f] for f in kept])
    return trimesh.Trimesh(mesh.vertices[used], faces, process=False)


def main() -> int:
    source = trimesh.load(_airplane(), process=False)
    disk = patch(source, wing(source), FACES)
    out = HERE / "patch.ply"
    disk.export(out, encoding="binary")
    print(f"{out}: {len(disk.vertices)} vertices, {len(disk.faces)} faces, "
          f"{out.stat().st_size} bytes")
    return 0


if __name__ == "__main__":
    sys.exit(main())
