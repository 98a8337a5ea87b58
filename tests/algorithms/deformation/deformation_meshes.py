"""Small meshes generated in code for the deformation tests (nothing downloaded)."""

from __future__ import annotations

import numpy as np
import trimesh


def grid(nx: int, ny: int, *, jitter: float = 0.0, seed: int = 0) -> tuple[np.ndarray,
                                                                             np.ndarray]:
    """A planar ``nx × ny``-vertex grid on ``[0, nx-1] × [0, ny-1]``, two triangles per
    cell (counter-clockwise), interior vertices optionally jittered."""
    xs, ys = np.meshgrid(np.arange(nx, dtype=float), np.arange(ny, dtype=float))
    v = np.stack([xs.ravel(), ys.ravel()], axis=1)
    if jitter:
        rng = np.random.default_rng(seed)
        inner = (v[:, 0] > 0) & (v[:, 0] < nx - 1) & (v[:, 1] > 0) & (v[:, 1] < ny - 1)
        v[inner] += rng.uniform(-jitter, jitter, size=(int(inner.sum()), 2))
    idx = np.arange(nx * ny).reshape(ny, nx)
    a, b = idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel()
    c, d = idx[1:, :-1].ravel(), idx[1:, 1:].ravel()
    f = np.concatenate([np.stack([a, b, d], 1), np.stack([a, d, c], 1)])
    return v, f


def bumpy_sheet(nx: int = 9, ny: int = 7, *, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """A jittered grid lifted onto a smooth bump: a curved, open 3-D surface."""
    v, f = grid(nx, ny, jitter=0.2, seed=seed)
    z = 0.4 * np.sin(0.7 * v[:, 0]) * np.cos(0.5 * v[:, 1])
    return np.column_stack([v, z]), f


def tube(sections: int = 12, rings: int = 15, *, radius: float = 0.5,
         length: float = 5.0) -> tuple[np.ndarray, np.ndarray]:
    """An open cylinder along z (a bar to bend): ``rings`` circles of ``sections``
    vertices, ring ``k`` at ``z = k * length / (rings - 1)``."""
    t = 2 * np.pi * np.arange(sections) / sections
    z = np.linspace(0.0, length, rings)
    v = np.array([[radius * np.cos(a), radius * np.sin(a), h] for h in z for a in t])
    f = []
    for k in range(rings - 1):
        for s in range(sections):
            i, j = k * sections + s, k * sections + (s + 1) % sections
            f += [[i, j, j + sections], [i, j + sections, i + sections]]
    return v, np.array(f, dtype=np.int64)


def blob(subdivisions: int = 3) -> tuple[np.ndarray, np.ndarray]:
    """A closed, curved, irregular surface: an icosphere stretched and dented."""
    m = trimesh.creation.icosphere(subdivisions=subdivisions)
    v = np.asarray(m.vertices, dtype=float) * [1.0, 0.8, 1.6]
    v[:, 0] += 0.25 * np.sin(3 * v[:, 2])
    return v, np.asarray(m.faces, dtype=np.int64)


def random_rotation(rng: np.random.Generator, d: int = 3) -> np.ndarray:
    q, r = np.linalg.qr(rng.standard_normal((d, d)))
    q = q * np.sign(np.diag(r))
    if np.linalg.det(q) < 0:
        q[:, 0] = -q[:, 0]
    return q
