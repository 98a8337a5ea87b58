"""Helpers of the multiway registration tests: homogeneous matrices, moving points, and
partial noisy views of one shape seen from several poses."""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np
from scipy.spatial.transform import Rotation

__all__ = ["homogeneous", "apply", "views", "assert_same_fields"]


def homogeneous(linear: np.ndarray, shift) -> np.ndarray:  # noqa: ANN001
    d = linear.shape[0]
    out = np.eye(d + 1)
    out[:d, :d] = linear
    out[:d, d] = shift
    return out


def apply(t: np.ndarray, pts: np.ndarray) -> np.ndarray:
    d = pts.shape[1]
    return pts @ t[:d, :d].T + t[:d, d]


def views(shape, k: int = 5, n: int = 1500, seed: int = 0, noise: float = 0.01,  # noqa: ANN001
          degrees: float = 10.0, shift: float = 0.1, keep: float = 0.7
          ) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """``k`` partial noisy views of one shape: view ``i`` keeps the ``keep`` fraction of
    points seen from direction ``2πi/k`` in the xy-plane, adds Gaussian noise and is seen
    from the pose ``T_i`` (a random turn up to ``degrees`` and shift up to ``shift``;
    ``T_0 = I``), i.e. holds ``T_i⁻¹ x``. Returns the views and the true poses."""
    rng = np.random.default_rng(seed)
    base = shape(n, seed)
    base = base - base.mean(axis=0)
    sets, poses = [], []
    for i in range(k):
        phi = 2 * np.pi * i / k
        proj = base @ [np.cos(phi), np.sin(phi), 0.0]
        pts = base[proj >= np.quantile(proj, 1 - keep)]
        pts = pts + noise * rng.standard_normal(pts.shape)
        pose = np.eye(4)
        if i:
            axis = rng.uniform(-1, 1, 3)
            pose[:3, :3] = Rotation.from_rotvec(
                np.radians(degrees) * axis / np.linalg.norm(axis)).as_matrix()
            pose[:3, 3] = rng.uniform(-shift, shift, 3)
        sets.append(apply(np.linalg.inv(pose), pts))
        poses.append(pose)
    return sets, poses



def assert_same_fields(a: Any, b: Any) -> None:
    """Two results (dataclasses) equal field by field, arrays bit for bit."""
    for f in dataclasses.fields(a):
        x, y = getattr(a, f.name), getattr(b, f.name)
        if isinstance(x, np.ndarray):
            assert x.dtype == y.dtype and x.tobytes() == y.tobytes(), f.name
        else:
            assert x == y, f.name
