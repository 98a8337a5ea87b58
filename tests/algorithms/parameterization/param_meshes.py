"""Small disk-like meshes generated in code for the parameterization tests."""

from __future__ import annotations

import numpy as np


def grid(nx: int, ny: int, *, jitter: float = 0.0, seed: int = 0) -> tuple[np.ndarray,
                                                                             np.ndarray]:
    """A planar ``nx × ny``-vertex grid, two counter-clockwise triangles per cell, interior
    vertices optionally jittered by up to ``jitter`` of a cell."""
    xs, ys = np.meshgrid(np.arange(nx, dtype=float), np.arange(ny, dtype=float))
    v = np.stack([xs.ravel(), ys.ravel()], axis=1)
    if jitter:
        rng = np.random.default_rng(seed)
        inner = (v[:, 0] > 0) & (v[:, 0] < nx - 1) & (v[:, 1] > 0) & (v[:, 1] < ny - 1)
        v[inner] += rng.uniform(-jitter, jitter, size=(int(inner.sum()), 2))
    idx = np.arange(nx * ny).reshape(ny, nx)
    a, b = idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel()
    c, d = idx[1:, :-1].ravel(), idx[1:, 1:].ravel()
    return v, np.concatenate([np.stack([a, b, d], 1), np.stack([a, d, c], 1)])


def bumpy(nx: int = 14, ny: int = 11, *, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """A jittered grid lifted onto a smooth bump: a curved open disk."""
    v, f = grid(nx, ny, jitter=0.2, seed=seed)
    z = 0.5 * np.sin(0.6 * v[:, 0]) * np.cos(0.45 * v[:, 1])
    return np.column_stack([v, z]), f


def cap(rings: int = 8, sectors: int = 24) -> tuple[np.ndarray, np.ndarray]:
    """A spherical cap (less than a hemisphere) meshed by rings: a curved disk whose
    triangles are well shaped (Delaunay-like)."""
    verts = [[0.0, 0.0, 1.0]]
    faces = []
    for r in range(1, rings + 1):
        t = 1.2 * r / rings
        for s in range(sectors):
            a = 2 * np.pi * (s + 0.5 * (r % 2)) / sectors
            verts.append([np.sin(t) * np.cos(a), np.sin(t) * np.sin(a), np.cos(t)])
    for s in range(sectors):
        faces.append([0, 1 + s, 1 + (s + 1) % sectors])
    for r in range(1, rings):
        o, p = 1 + (r - 1) * sectors, 1 + r * sectors
        for s in range(sectors):
            s1 = (s + 1) % sectors
            if r % 2:   # this ring is turned half a sector against the next
                faces += [[o + s, p + s, p + s1], [o + s, p + s1, o + s1]]
            else:
                faces += [[o + s, p + s, o + s1], [o + s1, p + s, p + s1]]
    return np.array(verts), np.array(faces, dtype=np.int64)
