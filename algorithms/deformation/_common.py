"""What every deformation method shares: reading the mesh and the handles, the pinned set
(handles plus the vertices no face uses), the check that every component holds a handle,
and the handle residual."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from algorithms.core.errors import DegenerateInputError, InvalidInputError
from algorithms.core.mesh import (
    Handles,
    Mesh,
    as_handles,
    components,
    pattern_components,
    read_mesh,
)
from algorithms.core.types import FloatArray, IntArray
from algorithms.core.validation import as_indices, as_points

__all__ = [
    "read_handles",
    "read_handle_indices",
    "read_positions",
    "Pins",
    "pins_of",
    "check_spread",
    "check_handles",
    "handle_residual",
    "affine_rank",
]


def read_handles(handles: Any, mesh: Mesh, *, name: str = "handles") -> Handles:
    """Checked :class:`Handles` from ``Handles``, a mapping ``{"indices", "positions"}`` or
    an ``(indices, positions)`` pair."""
    if isinstance(handles, (tuple, list)) and len(handles) == 2:
        handles = {"indices": handles[0], "positions": handles[1]}
    return as_handles(handles, mesh, name=name)


def read_handle_indices(indices: Any, mesh: Mesh, *, name: str = "handle_indices") -> IntArray:
    """Distinct vertex indices of ``mesh``, a non-empty flat list."""
    idx = as_indices(indices, mesh.n_vertices, name=name, what="vertex indices")
    if idx.ndim != 1:
        raise InvalidInputError(
            f"Expected `{name}` to be a flat list of vertex indices, got shape "
            f"{tuple(idx.shape)}.", field=name)
    if idx.shape[0] == 0:
        raise InvalidInputError(f"Expected `{name}` to hold at least 1 index, got 0.",
                                field=name)
    uniq, counts = np.unique(idx, return_counts=True)
    if (counts > 1).any():
        v = int(uniq[np.argmax(counts > 1)])
        where = np.flatnonzero(idx == v)[:2].tolist()
        raise InvalidInputError(
            f"Expected `{name}` to be unique, got {v} twice (positions {where[0]} and "
            f"{where[1]}).", field=name)
    return idx


def read_positions(positions: Any, count: int, dim: int, *, name: str) -> FloatArray:
    """``(count, dim)`` finite target positions."""
    pos = as_points(positions, name=name, dim=dim)
    if pos.shape[0] != count:
        raise InvalidInputError(
            f"Expected `{name}` to hold one row per handle ({count}), got {pos.shape[0]}.",
            field=name)
    return pos


def _component_labels(mesh: Mesh, adjacency: Any = None) -> tuple[int, IntArray, np.ndarray]:
    if adjacency is not None:
        count, labels = pattern_components(adjacency)
    else:
        f = mesh.faces
        # every face's three sides, repeats and all (no need to deduplicate for connectivity)
        count, labels = components(mesh.n_vertices, f[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2))
    used = np.zeros(mesh.n_vertices, dtype=bool)
    used[mesh.faces.ravel()] = True
    return count, labels, used


@dataclass(frozen=True, eq=False)
class Pins:
    """The vertices a solve holds fixed: the handles first, then the vertices no face
    references (they stay where they are: they take no part in any energy)."""

    indices: IntArray
    n_handles: int
    labels: IntArray
    """The connected component of every vertex."""

    @property
    def unused(self) -> IntArray:
        return self.indices[self.n_handles:]

    def values(self, handle_positions: FloatArray, rest: FloatArray) -> FloatArray:
        """Pinned positions: the handle targets, then the rest positions of unused vertices."""
        return np.concatenate([handle_positions, rest[self.unused]], axis=0)


def pins_of(mesh: Mesh, handle_indices: IntArray, *, name: str = "handles",
            adjacency: Any = None) -> Pins:
    """The pinned set of a mesh, after checking that every component holds a handle.

    ``adjacency``, a sparse ``(n, n)`` matrix with the mesh's edges as its pattern (its
    Laplacian, say), gives the components without building an edge list.

    Raises
    ------
    DegenerateInputError
        A connected component of the mesh (through its faces) without any handle: its
        position would be undetermined (``field=name``).
    """
    count, labels, used = _component_labels(mesh, adjacency)
    has = np.zeros(count, dtype=bool)
    has[labels[handle_indices]] = True
    real = np.zeros(count, dtype=bool)
    real[labels[used]] = True
    missing = np.flatnonzero(real & ~has)
    if missing.size:
        c = int(missing[0])
        members = np.flatnonzero(labels == c)
        more = (f"; {missing.size} of the mesh's {int(real.sum())} components have none"
                if missing.size > 1 else "")
        what = (f"a component of {members.size} vertices (vertex {int(members[0])} among "
                f"them)" if members.size > 1 else f"a component of 1 vertex "
                f"(vertex {int(members[0])})")
        raise DegenerateInputError(
            f"Expected every connected component to hold at least one of `{name}`, got "
            f"{what} without one{more}.", field=name)
    unused = np.flatnonzero(~used)
    unused = unused[~np.isin(unused, handle_indices)]
    idx = np.concatenate([np.asarray(handle_indices, dtype=np.int64), unused])
    return Pins(idx, int(len(handle_indices)), labels)


def affine_rank(points: FloatArray, *, rtol: float = 1e-9) -> int:
    """The dimension of the affine hull of ``points`` (0 for one point or coincident ones)."""
    if points.shape[0] < 2:
        return 0
    centred = points - points.mean(axis=0)
    s = np.linalg.svd(centred, compute_uv=False)
    scale = max(float(np.abs(points).max()), float(s[0]))
    return int(np.count_nonzero(s > rtol * scale)) if scale > 0 else 0


def check_spread(pins: Pins, points: FloatArray, minimum: int, *, name: str,
                 what: str, why: str) -> None:
    """Every component's handles (``points``, one row per handle) must span an affine
    hull of dimension ``minimum`` at least."""
    hl = pins.labels[pins.indices[: pins.n_handles]]
    order = np.argsort(hl, kind="stable")
    groups = np.split(order, np.flatnonzero(np.diff(hl[order])) + 1)
    for g in groups:
        if affine_rank(points[g]) < minimum:
            v = int(pins.indices[g[0]])
            raise DegenerateInputError(
                f"Expected `{name}` to hold {what} in every connected component ({why}), got "
                f"{g.size} handle{'s' if g.size != 1 else ''} without that in the component of "
                f"vertex {v}.", field=name)


def check_handles(mesh: Any, handles: Any, *, name: str = "handles") -> Handles:
    """Check ``handles`` against ``mesh``: indices in range and distinct, positions of the
    mesh's dimension, and at least one handle in every connected component of the mesh.

    What every deformation method checks first; the service calls it while validating a
    request, so that these errors come back before a job is queued.

    Returns
    -------
    Handles

    Raises
    ------
    InvalidInputError
        Malformed handles (field ``{name}``, ``{name}.indices`` or ``{name}.positions``).
    DegenerateInputError
        A connected component without a handle (field ``name``).
    """
    m = mesh if isinstance(mesh, Mesh) else read_mesh(mesh)
    h = read_handles(handles, m, name=name)
    pins_of(m, h.indices, name=name)
    return h


def handle_residual(vertices: FloatArray, handles: Handles) -> float:
    """The largest distance of a handle vertex from its target."""
    diff = vertices[handles.indices] - handles.positions
    return float(np.sqrt(np.einsum("ij,ij->i", diff, diff).max())) if diff.size else 0.0
