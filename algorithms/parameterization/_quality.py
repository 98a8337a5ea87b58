r"""The quality figures every parameterization reports, and the per-face Jacobians they
(and the local/global methods) are built on.

For face :math:`t` let :math:`J_t` be the 2×2 Jacobian of the piecewise-linear map from the
triangle (in an isometric 2-D frame of its own plane) to its image in the UV plane. Write
:math:`J = \begin{pmatrix} a & b \\ c & d \end{pmatrix}`,
:math:`Q = \tfrac12\lVert(a + d, c - b)\rVert` (its similarity part) and
:math:`R = \tfrac12\lVert(a - d, c + b)\rVert` (its anti-similarity part): the signed singular
values are :math:`\sigma_1 = Q + R`, :math:`\sigma_2 = Q - R`, :math:`\det J = Q^2 - R^2`,
and :math:`J` is a similarity iff :math:`R = 0`.

* ``flipped_faces``: faces whose UV orientation is opposite to that of the map as a whole
  (:func:`algorithms.layout.laplacian.face_orientation`), ``degenerate_faces``: faces
  collapsed to (near) zero UV area.
* ``angle_distortion``: the area-weighted mean of :math:`\sigma_1 / |\sigma_2| - 1` over the
  faces that are not degenerate (0 for a conformal map; the quasi-conformal distortion
  minus one).
* ``area_distortion``: the area-weighted mean of :math:`|\log(|\det J_t| / s)|` over the
  same faces, :math:`s` the ratio of the total UV area to the total surface area (0 for a map
  that scales every area alike; global scale does not count).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TypedDict

import numpy as np

from algorithms.core.mesh import corner_edges, cross_norm
from algorithms.core.types import FloatArray, IntArray
from algorithms.layout.laplacian import face_orientation

__all__ = ["Quality", "quality", "face_frames", "jacobians", "similarity_parts"]


class QualityFields(TypedDict):
    flipped_faces: int
    degenerate_faces: int
    angle_distortion: float
    area_distortion: float


@dataclass(frozen=True)
class Quality:
    flipped_faces: int
    degenerate_faces: int
    angle_distortion: float
    area_distortion: float

    def fields(self) -> QualityFields:
        """The four figures by name, as every parameterization result carries them."""
        return QualityFields(flipped_faces=self.flipped_faces,
                             degenerate_faces=self.degenerate_faces,
                             angle_distortion=self.angle_distortion,
                             area_distortion=self.area_distortion)


def face_frames(vertices: FloatArray, faces: IntArray) -> FloatArray:
    """Each face's corners in an isometric 2-D frame of its plane, ``(m, 3, 2)``: corner 0
    at the origin, corner 1 on the positive x axis, corner 2 above it (counter-clockwise)."""
    e1, e2 = corner_edges(vertices, faces)
    l1 = np.sqrt(sum(a * a for a in e1))
    x2 = sum(a * b for a, b in zip(e1, e2)) / l1
    y2 = cross_norm(e1, e2) / l1
    out = np.zeros((faces.shape[0], 3, 2))
    out[:, 1, 0] = l1
    out[:, 2, 0] = x2
    out[:, 2, 1] = y2
    return out


def jacobians(frames: FloatArray, faces: IntArray, uv: FloatArray) -> FloatArray:
    """The per-face Jacobians ``(m, 2, 2)`` of the map taking ``frames`` to ``uv``."""
    l1, x2, y2 = frames[:, 1, 0], frames[:, 2, 0], frames[:, 2, 1]
    # J = [u1 - u0, u2 - u0] [[l1, x2], [0, y2]]^-1, one coordinate at a time (1-D gathers)
    out = np.empty((faces.shape[0], 2, 2))
    for a in range(2):
        x = uv[:, a]
        u0 = x[faces[:, 0]]
        d1, d2 = x[faces[:, 1]] - u0, x[faces[:, 2]] - u0
        out[:, a, 0] = d1 / l1
        out[:, a, 1] = (d2 - out[:, a, 0] * x2) / y2
    return out


def similarity_parts(J: FloatArray) -> tuple[FloatArray, FloatArray]:
    """``Q`` and ``R`` of the module docstring, each ``(m,)``."""
    a, b, c, d = J[:, 0, 0], J[:, 0, 1], J[:, 1, 0], J[:, 1, 1]
    return 0.5 * np.hypot(a + d, c - b), 0.5 * np.hypot(a - d, c + b)


def quality(vertices: FloatArray, faces: IntArray, uv: FloatArray,
            frames: FloatArray | None = None) -> Quality:
    """Flips, degenerate faces, angle and area distortion of the map ``vertices -> uv``."""
    flipped, degenerate = face_orientation(uv, faces)
    fr = face_frames(vertices, faces) if frames is None else frames
    J = jacobians(fr, faces, uv)
    q, r = similarity_parts(J)
    area = 0.5 * fr[:, 1, 0] * fr[:, 2, 1]
    s1, s2 = q + r, np.abs(q - r)
    det = s1 * s2
    ok = s2 > 1e-12 * np.maximum(s1, np.finfo(float).tiny)
    w = area[ok]
    if w.sum() <= 0:
        return Quality(flipped, degenerate, float("inf"), float("inf"))
    scale = float((det * area).sum() / area.sum())  # |det J| * area: a face's UV area
    angle = float(np.average(s1[ok] / s2[ok] - 1.0, weights=w))
    areal = float(np.average(np.abs(np.log(det[ok] / scale)), weights=w))
    return Quality(flipped, degenerate, angle, areal)

