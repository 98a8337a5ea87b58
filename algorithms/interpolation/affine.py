r"""Interpolation of an affine map by its polar decomposition (Shoemake & Duff 1992): the
rotation turns along the shortest arc, the symmetric stretch and the translation move
linearly."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Literal, get_args

import numpy as np

from algorithms.alignment.affine import affine as fit_affine
from algorithms.core.errors import DegenerateInputError
from algorithms.core.linalg import batched_polar, det, homogeneous
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

__all__ = ["AffineInterpolationResult", "affine", "check_affine", "Reflection", "Pivot",
           "REFLECTIONS", "PIVOTS"]

Reflection = Literal["refuse", "flip"]
"""What to do with a map that mirrors (``det A < 0``)."""
Pivot = Literal["centroid", "origin"]
"""The point the linear part acts about."""
REFLECTIONS, PIVOTS = get_args(Reflection), get_args(Pivot)


@dataclass(frozen=True, eq=False)
class AffineInterpolationResult:
    """Frames of the path from the source to its image under an affine map.

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
        The affine map ``[[A, b], [0, 1]]`` at t = 1 (given, or fitted to the target).
    rotation : (d, d) float array
        The rotation ``R`` of the polar decomposition ``A = R S`` (determinant +1).
    stretch : (d, d) float array
        The symmetric factor ``S``; positive definite unless ``reflection``.
    angle : float
        The rotation angle of ``R`` in radians, in [0, π]: the arc the path turns through.
    det : (T,) float array
        The determinant of the interpolated linear part at each frame (its volume ratio);
        positive for every frame unless ``reflection``.
    max_edge_error : (T,) float array
        Per frame, the largest relative deviation of an edge length from the linear blend
        of its lengths at t = 0 and t = 1 (edges of the faces; for a point set, each
        point and its nearest neighbour).
    rmse : float
        Root-mean-square residual of the affine fit to the target (0 for a given
        transform); the residual is blended in linearly so that t = 1 lands on the target.
    reflection : bool
        True when ``det A < 0`` and ``reflection="flip"`` let the path pass through a
        singular map.
    """

    frames: FloatArray
    times: FloatArray
    faces: IntArray
    transform: FloatArray
    rotation: FloatArray
    stretch: FloatArray
    angle: float
    det: FloatArray
    max_edge_error: FloatArray
    rmse: float
    reflection: bool


def check_affine(source: Any, target: Any = None, transform: Any = None, times: Any = None,
                 reflection: str = "refuse"
                 ) -> tuple[Pair, FloatArray,
                            tuple[FloatArray, FloatArray, FloatArray, float, float]]:
    """Check the inputs of :func:`affine`: the shapes and times (:func:`check_pair`), and a
    map (given, or fitted to ``target``) that keeps orientation unless
    ``reflection="flip"``. Returns the pair, the times and the map: its linear part, its
    translation, the residual of the fit, its RMSE and the determinant of the linear part."""
    pair, t = check_pair(source, target, transform, times)
    d = pair.dim
    src = pair.source
    if pair.transform is not None:
        a, b = pair.transform[:d, :d], pair.transform[:d, d]
        residual = np.zeros_like(src)
        rmse = 0.0
        field = "transform"
    else:
        fit = fit_affine(src, pair.target)
        a, b, rmse = fit.linear, fit.translation, float(fit.rmse)
        residual = pair.target - (src @ a.T + b)
        field = "target"
    det_a = float(det(a))
    if det_a < 0 and reflection == "refuse":
        raise DegenerateInputError(
            f"Expected the map to `{field}` to keep orientation (det A > 0), got a reflection "
            f"(det A = {det_a:.6g}): no path of invertible maps reaches a mirror image; pass "
            f"reflection='flip' to pass through a flattened shape once.", field=field)
    return pair, t, (a, b, residual, rmse, det_a)


@validate_params
def affine(
    source: ShapeLike,
    target: ShapeLike | None = None,
    *,
    transform: ArrayInput | None = None,
    times: ArrayInput | None = None,
    reflection: Reflection = "refuse",
    pivot: Pivot = "centroid",
) -> AffineInterpolationResult:
    r"""Affine interpolation by polar decomposition.

    A = R S (polar decomposition); R turns along the shortest arc (slerp), S and the translation
    move linearly, so det A(t) > 0 all along the path. The map is given or fitted to the target (its
    residual blended in, so t = 1 is the target).

    The map :math:`p \mapsto A p + b` is the ``transform`` given, or the least-squares fit
    to ``target`` (:func:`algorithms.alignment.affine`). With the polar decomposition
    :math:`A = R S` (:math:`R` a rotation, :math:`S` symmetric) and the pivot :math:`c`,

    .. math::

        A(t) = \operatorname{slerp}(I, R; t)\,\bigl((1 - t) I + t S\bigr), \qquad
        p(t) = A(t)\,(p - c) + c + t\,(A c + b - c) + t\,r_p,

    where :math:`\operatorname{slerp}(I, R; t) = \exp(t \log R)` turns about the fixed
    axis of :math:`R` through :math:`t` times its angle in :math:`[0, \pi]` (the shortest
    arc) and :math:`r_p = y_p - (A p + b)` is the fit's residual at point :math:`p` (zero
    for a given transform). So :math:`p(0) = p` and :math:`p(1) = A p + b + r_p`: the
    target itself.

    Parameters
    ----------
    source : (n, d) float array or mesh
        The shape at t = 0: a point set or a mesh ``{vertices, faces}`` (triangles, or
        tetrahedra in 3-D); ``d`` = 2 or 3.
    target : (n, d) float array or mesh, optional
        The shape at t = 1, point ``i`` for source point ``i``: points, or a mesh with
        exactly the source's faces (the same connectivity); the fitted map needs at least
        ``d + 1`` affinely independent source points. Give this or ``transform``.
    transform : (d+1, d+1) float array, optional
        A homogeneous affine matrix ``[[A, b], [0, 1]]`` applied to the source instead of
        ``target``.
    times : (T,) float array, optional
        Strictly increasing times in [0, 1] (no extrapolation), one frame each; 11 evenly
        spaced (0, 0.1, ..., 1) when omitted.
    reflection : {"refuse", "flip"}, default "refuse"
        For a map that mirrors (:math:`\det A < 0`), which no path of invertible maps
        reaches: ``"refuse"`` raises an error; ``"flip"`` takes a rotation and a stretch
        with one negative eigenvalue, so the path flattens the shape once on the way.
    pivot : {"centroid", "origin"}, default "centroid"
        The point :math:`c` the linear part acts about: ``"centroid"`` the source's
        centroid, which then moves on a straight line; ``"origin"`` the origin, so that the
        translation is interpolated as :math:`t b`.

    Returns
    -------
    AffineInterpolationResult
        ``frames``, ``times``, ``faces``, ``transform``, ``rotation``, ``stretch``,
        ``angle``, ``det``, ``max_edge_error``, ``rmse`` and ``reflection``.

    Raises
    ------
    InvalidInputError
        Malformed inputs (the field names them), neither or both of ``target`` and
        ``transform``, a target of another shape or connectivity (``target`` /
        ``target.faces``), bad ``times``.
    DegenerateInputError
        ``det A < 0`` with ``reflection="refuse"`` (field ``transform`` or ``target``);
        a source too flat to fit an affine map (``source``).

    Notes
    -----
    **Why polar.** Of the factorizations of :math:`A` one could interpolate (eigen-,
    singular value and polar decomposition) the polar one looks best (Shoemake & Duff): the
    rotation and the stretch are interpolated separately, so a pure rotation stays rigid
    along the path and :math:`\det A(t) = \det((1 - t) I + t S) = \prod_i (1 - t +
    t\lambda_i) > 0` for :math:`t \in [0, 1]` whenever :math:`S` is positive definite: the
    volume never collapses.

    **Reflections.** No continuous path of invertible maps joins the identity
    (:math:`\det = 1`) to a mirror (:math:`\det < 0`): the determinant must cross zero.
    By default such a map is refused. ``reflection="flip"`` keeps a rotation in the
    factors: :math:`A = Q P` with :math:`\det Q = -1` is rewritten :math:`R = Q D`,
    :math:`S = D P`, :math:`D = \operatorname{diag}(1, \dots, 1, -1)` along the singular
    vector of the smallest singular value, so :math:`R` is a rotation and :math:`S` has one
    negative eigenvalue :math:`-\sigma_d`; the path then flattens the shape along that
    direction exactly once, at :math:`t = 1 / (1 + \sigma_d)` (``det`` reports it).
    Negating both factors instead (:math:`R = -Q`, :math:`S = -P`) is simpler but gives a
    rotation in odd dimensions only, and its path flattens every direction at once, so it
    is not offered.

    **Pivot.** Interpolating the translation as :math:`t b` about the origin makes a shape
    far from the origin swing around it. The default pivot is the source's centroid;
    ``pivot="origin"`` gives the path about the origin.

    **Peer.** The rotation path equals ``scipy.spatial.transform.Slerp`` between the
    identity and :math:`R` (tested).

    References
    ----------
    .. [1] K. Shoemake and T. Duff, "Matrix animation and polar decomposition", Graphics
       Interface 1992, 258-264.
    .. [2] M. Alexa, D. Cohen-Or and D. Levin, "As-rigid-as-possible shape interpolation",
       SIGGRAPH 2000, 157-164 (§3, the single-triangle case).

    Examples
    --------
    >>> import numpy as np
    >>> sq = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    >>> quarter = [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]
    >>> res = affine(sq, transform=quarter, times=[0.0, 0.5, 1.0], pivot="origin")
    >>> np.round(res.frames[1, 1], 12) + 0.0   # (1, 0) turned by 45 degrees
    array([0.70710678, 0.70710678])
    >>> round(res.angle, 12), res.det.round(12).tolist()
    (1.570796326795, [1.0, 1.0, 1.0])
    """
    pair, t, (a, b, residual, rmse, det_a) = check_affine(source, target, transform, times,
                                                          reflection)
    d = pair.dim
    src = pair.source
    rot, stretch = batched_polar(a, proper=True)
    w = rotation_log(rot)
    c = pivot_of(src, pivot)
    centred = src - c
    shift = a @ c + b - c
    eye = np.eye(d)
    frames = np.empty((t.shape[0],) + src.shape)
    dets = np.empty(t.shape[0])
    for i, ti in enumerate(t):
        s_t = (1.0 - ti) * eye + ti * stretch
        a_t = rotation_exp(ti * w, d) @ s_t
        frames[i] = centred @ a_t.T + (c + ti * shift)
        if ti:
            frames[i] += ti * residual
        dets[i] = det(s_t)
    return AffineInterpolationResult(
        frames=frames,
        times=t,
        faces=pair.faces,
        transform=homogeneous(a, b),
        rotation=rot,
        stretch=stretch,
        angle=float(np.linalg.norm(w)),
        det=dets,
        max_edge_error=edge_errors(frames, t, src, pair.target, edges_of(src, pair.faces)),
        rmse=rmse,
        reflection=bool(det_a < 0),
    )
