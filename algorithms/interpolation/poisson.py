r"""Poisson shape interpolation (Xu, Zhang, Tong, Guo & Shum 2005): per-face gradients are
interpolated (rotations continuous across the mesh, stretches linearly) and the vertices
recovered by one Poisson solve per frame with a prefactored cotangent Laplacian."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Annotated

import numpy as np

from algorithms.core.laplacian import cotangent_laplacian
from algorithms.core.params import ArrayInput, Ge, ShapeLike, validate_params
from algorithms.core.progress import Progress
from algorithms.core.types import FloatArray, IntArray
from algorithms.interpolation._common import (
    check_anchored,
    edge_errors,
    edges_of,
)
from algorithms.interpolation._faces import (
    FacePath,
    face_adjacency,
    face_dets,
    face_measures,
    unwrap_rotations,
)

__all__ = ["PoissonInterpolationResult", "poisson"]


@dataclass(frozen=True, eq=False)
class PoissonInterpolationResult:
    """Frames of the Poisson interpolation between two meshes with the same faces.

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
        The largest rotation angle of a face after the angles were made continuous across
        the mesh, in radians (may exceed π: a bar coiled by more than half a turn).
    """

    frames: FloatArray
    times: FloatArray
    faces: IntArray
    min_det: FloatArray
    max_edge_error: FloatArray
    max_angle: float


@validate_params
def poisson(
    source: ShapeLike,
    target: ShapeLike | None = None,
    *,
    transform: ArrayInput | None = None,
    times: ArrayInput | None = None,
    anchor: Annotated[int, Ge(0)] = 0,
    progress: Progress | None = None,
) -> PoissonInterpolationResult:
    r"""Poisson shape interpolation.

    Per-face gradients interpolated (rotations made continuous across the mesh then slerped,
    stretches lerped) and each frame recovered by a Poisson solve L x = div(gradients) with the
    prefactored cotangent Laplacian.

    Each face's map :math:`A_f = R_f S_f` (polar decomposition; the face's edges, plus the
    normal as third axis for triangles in 3-D) is interpolated as
    :math:`A_f(t) = \exp(t \log R_f)\,((1 - t) I + t S_f)`; row :math:`r` of
    :math:`A_f(t)` is the wanted gradient of coordinate :math:`r` over the face. The
    coordinates at time :math:`t` solve the Poisson equation

    .. math::

        L\, X(t) = G^\mathsf{T} M\, [A_f(t)^\mathsf{T}]_f ,

    :math:`L` the cotangent Laplacian (:func:`~algorithms.core.laplacian.cotangent_laplacian`;
    for tetrahedra the same FEM stiffness assembled from the gradients), :math:`M` the face
    areas (volumes) and :math:`G^\mathsf{T} M` the divergence: the area-weighted
    least-squares fit of the gradients. One vertex moves on its straight path (the
    Dirichlet condition); :math:`L` is factored once and each frame is one solve.

    The rotation vectors :math:`\log R_f` are made continuous across the mesh before
    interpolating (:func:`~algorithms.interpolation._faces.unwrap_rotations`): from the
    face that turns least, each face takes the multiple of a whole turn that puts it
    nearest the neighbour it was reached from, so a part turned by more than half a turn
    does not tear.

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
    PoissonInterpolationResult
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
    **Gradients, not Laplacian coordinates.** Poisson interpolation is sometimes described
    as interpolating the Laplacian coordinates linearly, :math:`\Delta p^{(t)} =
    \operatorname{lerp}(\Delta p^{(0)}, \Delta p^{(1)})`, and solving :math:`L x = \Delta
    p^{(t)}`. But the Laplacian and the interpolation are both linear and commute: with pins
    on their straight paths the solution is then exactly the linear blend of the vertex
    positions, which shrinks a bending bar. Xu et al. interpolate the *gradient field* with
    its rotations (slerp) and stretches (lerp) and only then take the divergence; that is
    what is implemented, and it is what keeps the bar's length (tested against the linear
    blend).

    **Reflections.** A face turned over in the target gets the factors of
    :func:`~algorithms.interpolation.affine`'s ``reflection="flip"`` (a rotation and a
    stretch with one negative eigenvalue); ``min_det`` shows where faces flatten.

    References
    ----------
    .. [1] D. Xu, H. Zhang, Q. Wang and H. Bao, "Poisson shape interpolation", ACM
       Symposium on Solid and Physical Modeling 2005, 267-274.
    .. [2] M. Alexa, D. Cohen-Or and D. Levin, "As-rigid-as-possible shape interpolation",
       SIGGRAPH 2000, 157-164.

    Examples
    --------
    >>> import numpy as np
    >>> v = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    >>> f = np.array([[0, 1, 2], [0, 2, 3]])
    >>> res = poisson({"vertices": v, "faces": f}, transform=[[2, 0, 0], [0, 2, 0], [0, 0, 1]],
    ...               times=[0.0, 0.5, 1.0])
    >>> np.round(res.frames[1], 12) + 0.0     # uniformly 1.5 times larger, vertex 0 fixed
    array([[0. , 0. ],
           [1.5, 0. ],
           [1.5, 1.5],
           [0. , 1.5]])
    """
    pair, t = check_anchored(source, target, transform, times, anchor)
    rotations, stretch = FacePath.decompose(pair)
    rotations = unwrap_rotations(rotations, face_adjacency(pair.faces))
    measures = face_measures(pair.source, pair.faces)
    system = (cotangent_laplacian(pair.source, pair.faces) if pair.faces.shape[1] == 3
              else None)
    path = FacePath(pair, measures, rotations, stretch, anchor=anchor, system=system,
                    solves=t.shape[0])
    frames = path.run(t, progress, "interpolation.poisson")
    return PoissonInterpolationResult(
        frames=frames,
        times=t,
        faces=pair.faces,
        min_det=face_dets(pair.source, frames, pair.faces),
        max_edge_error=edge_errors(frames, t, pair.source, pair.target,
                                   edges_of(pair.source, pair.faces)),
        max_angle=float(np.linalg.norm(rotations, axis=1).max()),
    )
