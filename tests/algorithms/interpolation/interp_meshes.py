"""Small meshes and bends generated in code for the interpolation tests (nothing
downloaded)."""

from __future__ import annotations

import numpy as np


def bar(length: float = 10.0, width: float = 1.0, nx: int = 21, ny: int = 3
        ) -> tuple[np.ndarray, np.ndarray]:
    """A planar bar ``[0, length] × [-width/2, width/2]`` of ``nx × ny`` vertices, two
    triangles per cell (counter-clockwise)."""
    xs, ys = np.meshgrid(np.linspace(0.0, length, nx), np.linspace(-width / 2, width / 2, ny))
    v = np.stack([xs.ravel(), ys.ravel()], axis=1)
    idx = np.arange(nx * ny).reshape(ny, nx)
    a, b = idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel()
    c, d = idx[1:, :-1].ravel(), idx[1:, 1:].ravel()
    f = np.concatenate([np.stack([a, b, d], 1), np.stack([a, d, c], 1)])
    return v, f.astype(np.int64)


def bend2(v: np.ndarray, angle: float, length: float = 10.0) -> np.ndarray:
    """Bend a planar bar along x into a circular arc turning through ``angle`` (its centre
    line keeps its length; the sides stretch and shrink with the offset)."""
    if angle == 0:
        return v.copy()
    r = length / angle
    phi = v[:, 0] / r
    return np.stack([(r - v[:, 1]) * np.sin(phi), r - (r - v[:, 1]) * np.cos(phi)], axis=1)


def strip3(length: float = 10.0, width: float = 1.0, nx: int = 21, ny: int = 3
           ) -> tuple[np.ndarray, np.ndarray]:
    """The bar as a surface in the plane z = 0."""
    v, f = bar(length, width, nx, ny)
    return np.column_stack([v, np.zeros(len(v))]), f


def roll3(v: np.ndarray, angle: float, length: float = 10.0) -> np.ndarray:
    """Roll a 3-D bar along x about an axis parallel to y (the z = 0 sheet bends without
    stretching: an isometry of the strip; thickness in z stretches and shrinks)."""
    if angle == 0:
        return v.copy()
    r = length / angle
    phi = v[:, 0] / r
    return np.stack([(r - v[:, 2]) * np.sin(phi), v[:, 1], r - (r - v[:, 2]) * np.cos(phi)],
                    axis=1)


def tet_bar(length: float = 10.0, nx: int = 11, ny: int = 2, nz: int = 2, size: float = 1.0
            ) -> tuple[np.ndarray, np.ndarray]:
    """A box bar ``[0, length] × [0, size] × [-size/2, size/2]`` cut into tetrahedra (six
    per cube, all around the main diagonal, positively oriented)."""
    xs = np.linspace(0.0, length, nx)
    ys = np.linspace(0.0, size, ny)
    zs = np.linspace(-size / 2, size / 2, nz)
    grid = np.stack(np.meshgrid(xs, ys, zs, indexing="ij"), axis=-1).reshape(-1, 3)
    idx = np.arange(nx * ny * nz).reshape(nx, ny, nz)
    cubes = []
    for i in range(nx - 1):
        for j in range(ny - 1):
            for k in range(nz - 1):
                c = [idx[i + a, j + b, k + e] for e in (0, 1) for b in (0, 1) for a in (0, 1)]
                cubes.append(c)
    tets = []
    # corners c[0..7] as bits (x, y, z); six tets around the diagonal 0 - 7
    paths = [(1, 3), (1, 5), (2, 3), (2, 6), (4, 5), (4, 6)]
    for c in cubes:
        for a, b in paths:
            t = [c[0], c[a], c[b], c[7]]
            p = grid[t]
            if np.linalg.det(p[1:] - p[0]) < 0:
                t[1], t[2] = t[2], t[1]
            tets.append(t)
    return grid, np.array(tets, dtype=np.int64)


def random_rotation(rng: np.random.Generator, d: int = 3) -> np.ndarray:
    q, r = np.linalg.qr(rng.standard_normal((d, d)))
    q = q * np.sign(np.diag(r))
    if np.linalg.det(q) < 0:
        q[:, 0] = -q[:, 0]
    return q


def rot2(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s], [s, c]])


def linear_blend_error(source: np.ndarray, target: np.ndarray, faces: np.ndarray,
                       times: np.ndarray) -> float:
    """The largest relative edge-length deviation of the linear blend of positions."""
    from algorithms.interpolation._common import edge_errors, edges_of

    frames = np.array([(1 - t) * source + t * target for t in times])
    return float(edge_errors(frames, times, source, target, edges_of(source, faces)).max())
