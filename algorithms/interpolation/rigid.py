r"""Interpolation of a rigid motion or a similarity: the rotation turns along the shortest
arc, the pivot moves on a straight line and the scale changes geometrically."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from algorithms.alignment.rigid import rigid as fit_rigid
from algorithms.alignment.similarity import similarity as fit_similarity
from algorithms.core.errors import InvalidInputError
from algorithms.core.linalg import det, homogeneous
from algorithms.core.params import ArrayInput, ShapeLike, validate_params
from algorithms.core.types import FloatArray, IntArray
from algorithms.interpolation._common import (
    Pair,
    check_pair,
    edge_errors,
    edges_of,
    pivot_of,
    rotation_exp,
    rotation_log,
)
from algorithms.interpolation.affine import Pivot

__all__ = ["RigidInterpolationResult", "rigid", "check_rigid", "split_similarity",
           "SIMILARITY_RTOL"]

#: A given ``transform`` is a similarity when ``‖AᵀA − s² I‖_F <= SIMILARITY_RTOL · s²``.
SIMILARITY_RTOL = 1e-9


@dataclass(frozen=True, eq=False)
class RigidInterpolationResult:
    """Frames of a rigid (or similarity) motion from the source to the target.

    Attributes
    ----------
    frames : (T, n, d) float array
        The shape at each time: ``frames[0]`` is the source when ``times[0] = 0``, the
        last the target when ``times[-1] = 1``.
    times : (T,) float array
        The times of the frames, increasing in [0, 1].
    faces : (m, k) int array
        The source's faces (triangles or tetrahedra), shared by every frame; (0, 3) for a
        point set.
    transform : (d+1, d+1) float array
        The motion ``[[s R, b], [0, 1]]`` at t = 1 (given, or fitted to the target).
    rotation : (d, d) float array
        Its rotation ``R`` (determinant +1).
    scale : float
        Its scale ``s`` (1 for a rigid motion); frame t is scaled by ``s^t``.
    translation : (d,) float array
        Its translation ``b``.
    angle : float
        The rotation angle of ``R`` in radians, in [0, π]: the arc the path turns through.
    max_edge_error : (T,) float array
        Per frame, the largest relative deviation of an edge length from the linear blend
        of its lengths at t = 0 and t = 1 (edges of the faces; for a point set, each
        point and its nearest neighbour); rounding-level for an exact rigid motion.
    rmse : float
        Root-mean-square residual of the fit to the target (0 for a given transform); the
        residual is blended in linearly so that t = 1 lands on the target.
    """

    frames: FloatArray
    times: FloatArray
    faces: IntArray
    transform: FloatArray
    rotation: FloatArray
    scale: float
    translation: FloatArray
    angle: float
    max_edge_error: FloatArray
    rmse: float


def split_similarity(a: FloatArray, scale: bool) -> tuple[FloatArray, float]:
    """``A = s R`` for a given transform, or an error naming ``transform``."""
    d = a.shape[0]
    det_a = float(det(a))
    if not det_a > 0:
        raise InvalidInputError(
            f"Expected `transform` to be a proper {'similarity' if scale else 'rigid motion'} "
            f"(a rotation, det > 0), got a linear part with determinant {det_a:.6g}.",
            field="transform")
    s = det_a ** (1.0 / d)
    gram = a.T @ a
    off = float(np.linalg.norm(gram - s * s * np.eye(d)))
    if off > SIMILARITY_RTOL * s * s:
        raise InvalidInputError(
            f"Expected the linear part of `transform` to be a scaled rotation (AᵀA = s²I), "
            f"got ‖AᵀA − s²I‖ = {off:.3g} for s = {s:.6g}; use interpolation.affine for "
            f"shears and non-uniform scales.", field="transform")
    if not scale and abs(s - 1.0) > SIMILARITY_RTOL:
        raise InvalidInputError(
            f"Expected `transform` to be a rigid motion (scale 1), got scale {s:.12g}; pass "
            f"scale=true to interpolate a similarity.", field="transform")
    return a / s, s


def check_rigid(source: Any, target: Any = None, transform: Any = None, times: Any = None,
                scale: bool = False) -> tuple[
                    Pair, FloatArray, tuple[FloatArray, float, FloatArray, FloatArray, float]]:
    """Check the inputs of :func:`rigid`: the shapes and times (:func:`check_pair`), and a
    rigid motion (a similarity with ``scale``): given and checked (:func:`split_similarity`)
    or fitted to ``target``. Returns the pair, the times and the motion: its rotation,
    scale, translation, the residual of the fit and its RMSE."""
    pair, t = check_pair(source, target, transform, times)
    d = pair.dim
    src = pair.source
    if pair.transform is not None:
        rot, s = split_similarity(pair.transform[:d, :d], scale)
        b = pair.transform[:d, d]
        residual = np.zeros_like(src)
        rmse = 0.0
    else:
        if scale:
            sim = fit_similarity(src, pair.target)
            rot, s, b, rmse = sim.rotation, float(sim.scale), sim.translation, sim.rmse
        else:
            rig = fit_rigid(src, pair.target)
            rot, s, b, rmse = rig.rotation, 1.0, rig.translation, rig.rmse
        residual = pair.target - (s * (src @ rot.T) + b)
    return pair, t, (rot, s, b, residual, rmse)


@validate_params
def rigid(
    source: ShapeLike,
    target: ShapeLike | None = None,
    *,
    transform: ArrayInput | None = None,
    times: ArrayInput | None = None,
    scale: bool = False,
    pivot: Pivot = "centroid",
) -> RigidInterpolationResult:
    r"""Rigid (or similarity) motion interpolation.

    Fits a rigid motion (Kabsch) or similarity (Umeyama) to the target, or takes the one given, and
    moves the shape along it: rotation by slerp (shortest arc), pivot on a straight line, scale
    geometric (s^t).

    The motion :math:`p \mapsto s R p + b` is the ``transform`` given (checked to be one),
    or the least-squares fit to ``target``: Kabsch (:func:`algorithms.alignment.rigid`), or
    Umeyama with ``scale=True`` (:func:`algorithms.alignment.similarity`). With the pivot
    :math:`c`,

    .. math::

        p(t) = s^t \exp(t \log R)\,(p - c) + c + t\,(s R c + b - c) + t\,r_p,

    :math:`r_p = y_p - (s R p + b)` the fit's residual (zero for a given transform), so
    :math:`p(0) = p` and :math:`p(1) = y_p`. The rotation turns about its fixed axis
    through :math:`t` times its angle in :math:`[0, \pi]` (the shortest arc), the pivot
    moves on a straight line, and the scale changes geometrically (:math:`\log s` is
    interpolated linearly), so equal time steps give equal ratios.

    Parameters
    ----------
    source : (n, d) float array or mesh
        The shape at t = 0: a point set or a mesh ``{vertices, faces}`` (triangles, or
        tetrahedra in 3-D); ``d`` = 2 or 3. Fitting a target needs at least ``d`` points,
        not all on one line in 3-D, not all at one point in 2-D.
    target : (n, d) float array or mesh, optional
        The shape at t = 1, point ``i`` for source point ``i``: points, or a mesh with
        exactly the source's faces (the same connectivity). Give this or ``transform``.
    transform : (d+1, d+1) float array, optional
        A homogeneous rigid motion ``[[R, b], [0, 1]]`` (with ``scale=True`` a similarity
        ``[[s R, b], [0, 1]]``) applied to the source instead of ``target``.
    times : (T,) float array, optional
        Strictly increasing times in [0, 1] (no extrapolation), one frame each; 11 evenly
        spaced (0, 0.1, ..., 1) when omitted.
    scale : bool, default False
        Fit and interpolate a uniform scale too, geometrically (:math:`s^t`).
    pivot : {"centroid", "origin"}, default "centroid"
        The point :math:`c` the rotation turns about: ``"centroid"`` the source's centroid,
        which then moves on a straight line; ``"origin"`` the origin.

    Returns
    -------
    RigidInterpolationResult
        ``frames``, ``times``, ``faces``, ``transform``, ``rotation``, ``scale``,
        ``translation``, ``angle``, ``max_edge_error`` and ``rmse``.

    Raises
    ------
    InvalidInputError
        Malformed inputs, neither or both of ``target`` and ``transform``, a target of
        another shape or connectivity (``target`` / ``target.faces``), a ``transform`` that
        is not a proper rigid motion (or similarity), bad ``times``.
    DegenerateInputError
        A source too degenerate to fix a rotation (``source``).

    Notes
    -----
    For a given transform the result is the path of :func:`affine` on the same map (its
    stretch is then :math:`s I`) except for the scale, which :func:`affine` interpolates
    linearly and this function geometrically. The rotation path equals
    ``scipy.spatial.transform.Slerp`` between the identity and :math:`R` (tested). A
    rotation by exactly :math:`\pi` has two shortest arcs; one of them is taken.

    This function moves the whole shape as one rigid body; for a path that turns each
    face by its own rotation use :func:`~algorithms.interpolation.arap` or
    :func:`~algorithms.interpolation.poisson`.

    References
    ----------
    .. [1] K. Shoemake, "Animating rotation with quaternion curves", SIGGRAPH 1985,
       245-254.
    .. [2] S. Umeyama, "Least-squares estimation of transformation parameters between two
       point patterns", IEEE TPAMI 13(4), 376-380, 1991.

    Examples
    --------
    >>> import numpy as np
    >>> sq = np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]])
    >>> res = rigid(sq, sq @ np.array([[0.0, 1.0], [-1.0, 0.0]]) + [5.0, 0.0],
    ...             times=[0.0, 0.5, 1.0])
    >>> round(res.angle, 12), np.round(res.frames[1].mean(axis=0), 12).tolist()
    (1.570796326795, [2.5, 1.0])
    """
    pair, t, (rot, s, b, residual, rmse) = check_rigid(source, target, transform, times, scale)
    d = pair.dim
    src = pair.source
    w = rotation_log(rot)
    c = pivot_of(src, pivot)
    centred = src - c
    shift = s * (rot @ c) + b - c
    frames = np.empty((t.shape[0],) + src.shape)
    for i, ti in enumerate(t):
        frames[i] = (s ** ti) * (centred @ rotation_exp(ti * w, d).T) + (c + ti * shift)
        if ti:
            frames[i] += ti * residual
    return RigidInterpolationResult(
        frames=frames,
        times=t,
        faces=pair.faces,
        transform=homogeneous(s * rot, b),
        rotation=rot,
        scale=float(s),
        translation=np.asarray(b, dtype=np.float64),
        angle=float(np.linalg.norm(w)),
        max_edge_error=edge_errors(frames, t, src, pair.target, edges_of(src, pair.faces)),
        rmse=float(rmse),
    )
