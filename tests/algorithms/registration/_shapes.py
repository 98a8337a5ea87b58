"""Generated test shapes for the registration tests: asymmetric, so that a rotation is
determined by the shape alone (no symmetry leaves part of it free)."""

from __future__ import annotations

import numpy as np
import trimesh
from scipy.spatial.transform import Rotation

__all__ = ["blob", "bent_bar", "rotation_about", "random_rotation", "move", "angle_deg"]


def blob(n: int, seed: int = 0) -> np.ndarray:
    """``n`` points on a lumpy closed surface: a sphere whose radius varies with
    low-order terms that share no symmetry axis (an asymmetric potato, about 2 across)."""
    rng = np.random.default_rng(seed)
    u = rng.standard_normal((n, 3))
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    x, y, z = u.T
    r = 1.0 + 0.3 * x + 0.15 * y * z + 0.2 * x * y + 0.1 * z ** 3 + 0.12 * y
    return u * r[:, None] * [1.3, 1.0, 0.8]


def bent_bar(n: int, seed: int = 0, bend: float = 0.8) -> np.ndarray:
    """``n`` points on the surface of a 4 × 1 × 0.6 box bent into an arc of ``bend`` radians
    about the z axis, with one end thicker (so the bend and the ends tell it apart)."""
    box = trimesh.creation.box(extents=[4.0, 1.0, 0.6])
    rng = np.random.default_rng(seed)
    pts, _ = trimesh.sample.sample_surface(box, n, seed=int(rng.integers(2**31)))
    x, y, z = pts.T
    taper = 1.0 + 0.15 * (x + 2.0)                     # thicker at x = +2
    y, z = y * taper, z * (0.7 + 0.3 * taper)
    radius = 4.0 / bend
    phi = x / radius
    return np.c_[(radius + y) * np.sin(phi), (radius + y) * np.cos(phi) - radius, z]


def rotation_about(axis, degrees: float) -> np.ndarray:  # noqa: ANN001
    axis = np.asarray(axis, float)
    return Rotation.from_rotvec(np.radians(degrees) * axis / np.linalg.norm(axis)).as_matrix()


def random_rotation(rng: np.random.Generator, d: int = 3) -> np.ndarray:
    """A Haar-random rotation (det +1)."""
    q, r = np.linalg.qr(rng.standard_normal((d, d)))
    q = q * np.sign(np.diag(r))
    if np.linalg.det(q) < 0:
        q[:, 0] = -q[:, 0]
    return q


def move(points: np.ndarray, linear: np.ndarray, shift, rng=None) -> np.ndarray:  # noqa: ANN001
    """``linear @ p + shift`` for every point, rows shuffled when ``rng`` is given."""
    out = points @ np.asarray(linear).T + shift
    return out if rng is None else out[rng.permutation(len(out))]


def angle_deg(r_est: np.ndarray, r_true: np.ndarray) -> float:
    """The angle of ``r_est r_trueᵀ`` in degrees."""
    c = (np.trace(r_est @ r_true.T) - 1.0) / 2.0
    return float(np.degrees(np.arccos(np.clip(c, -1.0, 1.0))))
