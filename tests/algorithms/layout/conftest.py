"""Meshes and point sets for the layout tests, generated in code."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pytest
from scipy.spatial import Delaunay


def grid(n: int) -> tuple[np.ndarray, np.ndarray]:
    """An n×n vertex grid on the unit square, two counter-clockwise triangles per cell."""
    x, y = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n))
    v = np.c_[x.ravel(), y.ravel()]
    i, j = np.meshgrid(np.arange(n - 1), np.arange(n - 1), indexing="ij")
    a = (i * n + j).ravel()
    b, c, d = a + 1, a + n, a + n + 1
    f = np.concatenate([np.c_[a, b, d], np.c_[a, d, c]])
    return v, f


def ccw(v: np.ndarray, f: np.ndarray) -> np.ndarray:
    """Faces reordered counter-clockwise in the plane of the first two coordinates."""
    p0, p1, p2 = v[f[:, 0], :2], v[f[:, 1], :2], v[f[:, 2], :2]
    a, b = p1 - p0, p2 - p0
    neg = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0] < 0
    f = f.copy()
    f[neg] = f[neg][:, [0, 2, 1]]
    return f


def disk(rings: int = 6) -> tuple[np.ndarray, np.ndarray]:
    """A Delaunay triangulation of concentric rings of points in the unit disk."""
    pts = [np.zeros((1, 2))]
    for r in range(1, rings + 1):
        t = np.arange(6 * r) / (6 * r) * 2 * np.pi + 0.3 * r
        pts.append(r / rings * np.c_[np.cos(t), np.sin(t)])
    v = np.concatenate(pts)
    return v, ccw(v, Delaunay(v).simplices.astype(np.int64))


def squashed_disk(rings: int = 6) -> tuple[np.ndarray, np.ndarray]:
    """The disk triangulated, then squashed 20:1 and bent: triangles with angles near 180°
    (far from Delaunay: many negative cotangent weights)."""
    v, f = disk(rings)
    w = v.copy()
    w[:, 1] *= 0.05
    w[:, 0] += 0.3 * np.sin(3 * v[:, 1])
    return w, f


def spiky_grid(seed: int, n: int = 8, height: float = 2.0) -> tuple[np.ndarray, np.ndarray]:
    """A grid lifted to random heights up to ``height``: a 3-D disk-like surface with very
    obtuse triangles."""
    v, f = grid(n)
    z = np.random.default_rng(seed).random(len(v)) * height
    return np.c_[v, z], f


def cap(subdivisions: int = 2) -> tuple[np.ndarray, np.ndarray]:
    """The upper part (z > -0.2) of an icosphere: a curved disk in 3-D."""
    import trimesh

    s = trimesh.creation.icosphere(subdivisions=subdivisions)
    keep = (s.vertices[s.faces][:, :, 2] > -0.2).all(axis=1)
    f = s.faces[keep]
    used = np.unique(f)
    remap = np.full(len(s.vertices), -1)
    remap[used] = np.arange(len(used))
    return np.asarray(s.vertices[used], dtype=float), remap[f].astype(np.int64)


@pytest.fixture
def meshes() -> dict[str, Callable[..., tuple[np.ndarray, np.ndarray]]]:
    return {"grid": grid, "disk": disk, "squashed_disk": squashed_disk,
            "spiky_grid": spiky_grid, "cap": cap}
