r"""As-rigid-as-possible shape interpolation (Alexa, Cohen-Or & Levin 2000): every face's
affine map is interpolated by its polar decomposition, and the vertices follow in the
least-squares sense."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Annotated

import numpy as np

from algorithms.core.params import ArrayInput, Ge, ShapeLike, validate_params
from algorithms.core.progress import Progress
from algorithms.core.types import FloatArray, IntArray
from algorithms.interpolation._common import (
    check_anchored,
    edge_errors,
    edges_of,
)
from algorithms.interpolation._faces import FacePath, face_dets

__all__ = ["ArapInterpolationResult", "arap"]


@dataclass(frozen=True, eq=False)
class ArapInterpolationResult:
    """Frames of the as-rigid-as-possible path between two meshes with the same faces.

    Attributes
    ----------
    frames : (T, n, d) float array
        The vertices at each time: ``frames[0]`` is the source when ``times[0] = 0``, the
        last the target when ``times[-1] = 1`` (up to the solver's rounding).
    times : (T,) float array
        The times of the frames, increasing in [0, 1].
    faces : (m, k) int array
        The faces (triangles or tetrahedra) shared by every frame.
    min_det : (T,) float array
        Per frame, the smallest ratio of a face's signed area (volume for tetrahedra) to
        its source area; for triangles in 3-D the unsigned area ratio. Negative means a
        face turned over.
    max_edge_error : (T,) float array
        Per frame, the largest relative deviation of an edge length from the linear blend
        of its lengths at t = 0 and t = 1.
    max_angle : float
        The largest rotation angle of a face's map, in radians (at most π: each face turns
        along its own shortest arc).
    """

    frames: FloatArray
    times: FloatArray
    faces: IntArray
    min_det: FloatArray
    max_edge_error: FloatArray
    max_angle: float


@validate_params
def arap(
    source: ShapeLike,
    target: ShapeLike | None = None,
    *,
    transform: ArrayInput | None = None,
    times: ArrayInput | None = None,
    anchor: Annotated[int, Ge(0)] = 0,
    progress: Progress | None = None,
) -> ArapInterpolationResult:
    r"""As-rigid-as-possible shape interpolation.

    Per face, A_f = R_f S_f interpolated as slerp(R_f) lerp(I, S_f); the vertices of each frame
    solve min Σ_f ‖B_f(x) − A_f(t)‖² with one vertex on its straight path (one factored sparse
    system, one solve per frame).

    Each face's affine map :math:`A_f` from source to target (see the module docstring of
    :mod:`algorithms.interpolation._faces`: the face's edges, plus the normal as third
    axis for triangles in 3-D) is split by the polar decomposition :math:`A_f = R_f S_f`
    and interpolated as :math:`A_f(t) = \operatorname{slerp}(I, R_f; t)\,((1 - t) I + t
    S_f)`, the rotation along its shortest arc. The vertices at time :math:`t` minimise

    .. math::

        \sum_f \lVert B_f(X) - A_f(t) \rVert_F^2,

    :math:`B_f(X)` the map face :math:`f` takes under positions :math:`X` (its edges'
    least-squares fit), with one vertex held on its straight path
    :math:`(1 - t)\,p_a + t\,q_a`. The normal equations are one sparse system, factored
    once; each frame is one solve with a new right-hand side.

    Parameters
    ----------
    source : Mesh or {"vertices", "faces"}
        The mesh at t = 0: ``(n, d)`` vertices and ``(m, 3)`` triangles (``d`` = 2 or 3)
        or, in 3-D, ``(m, 4)`` tetrahedra; no zero-area (zero-volume) faces. A point set
        is refused: the method interpolates per face.
    target : (n, d) float array or mesh, optional
        The mesh at t = 1 with exactly the source's faces (the same connectivity), or its
        vertices alone. Give this or ``transform``.
    transform : (d+1, d+1) float array, optional
        A homogeneous affine matrix ``[[A, b], [0, 1]]`` applied to the source instead of
        ``target``.
    times : (T,) float array, optional
        Strictly increasing times in [0, 1] (no extrapolation), one frame each; 11 evenly
        spaced (0, 0.1, ..., 1) when omitted.
    anchor : int, default 0
        The vertex that moves on a straight line from its source to its target position
        (it fixes the free translation); every other connected component holds its
        lowest-numbered vertex on its line.
    progress : callable, optional
        ``progress(done, total, message)``, called after each frame.

    Returns
    -------
    ArapInterpolationResult
        ``frames``, ``times``, ``faces``, ``min_det``, ``max_edge_error`` and
        ``max_angle``.

    Raises
    ------
    InvalidInputError
        Malformed inputs (the field names them); a point set as ``source``; neither or
        both of ``target`` and ``transform``; a target with other faces (``target.faces``)
        or of another shape; ``anchor`` out of range; bad ``times``.
    DegenerateInputError
        A zero-area source face (``source.faces``).

    Notes
    -----
    **Objective.** Alexa et al. sum the squared Frobenius distances unweighted, one term
    per triangle, :math:`\min \sum_f \lVert B_f(X) - A_f(t)\rVert^2` subject to shared
    vertices; so does this function (use :func:`~algorithms.interpolation.poisson` for the
    area-weighted objective, the cotangent Laplacian). The free translation is fixed by
    one vertex on its straight path as in the paper; holding that vertex on the path of
    the global affine map instead would only move each frame by a translation.

    **Reflections.** A face whose map mirrors (:math:`\det A_f < 0`, a face turned over in
    the target) gets the factors of :func:`~algorithms.interpolation.affine`'s
    ``reflection="flip"``: a rotation and a stretch with one negative eigenvalue, which
    passes through zero once; ``min_det`` shows where faces flatten.

    **Limits.** Each face takes its own shortest arc, so a part that turns by more than
    half a turn relative to the rest tears where neighbouring faces choose opposite
    directions; :func:`~algorithms.interpolation.poisson` makes the angles continuous
    across faces first.

    References
    ----------
    .. [1] M. Alexa, D. Cohen-Or and D. Levin, "As-rigid-as-possible shape interpolation",
       SIGGRAPH 2000, 157-164.
    .. [2] R. W. Sumner and J. Popović, "Deformation transfer for triangle meshes", ACM TOG
       23(3), 2004 (the normal as fourth vertex of a triangle in space).

    Examples
    --------
    >>> import numpy as np
    >>> v = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    >>> f = np.array([[0, 1, 2], [0, 2, 3]])
    >>> turned = v @ np.array([[0.0, 1.0], [-1.0, 0.0]])   # a quarter turn
    >>> res = arap({"vertices": v, "faces": f}, {"vertices": turned, "faces": f},
    ...            times=[0.0, 0.5, 1.0])
    >>> bool(res.max_edge_error.max() < 1e-12), round(res.max_angle, 12)
    (True, 1.570796326795)
    """
    pair, t = check_anchored(source, target, transform, times, anchor)
    rotations, stretch = FacePath.decompose(pair)
    path = FacePath(pair, np.ones(pair.faces.shape[0]), rotations, stretch, anchor=anchor,
                    solves=t.shape[0])
    frames = path.run(t, progress, "interpolation.arap")
    return ArapInterpolationResult(
        frames=frames,
        times=t,
        faces=pair.faces,
        min_det=face_dets(pair.source, frames, pair.faces),
        max_edge_error=edge_errors(frames, t, pair.source, pair.target,
                                   edges_of(pair.source, pair.faces)),
        max_angle=float(np.linalg.norm(rotations, axis=1).max()),
    )
