"""Generalised Procrustes analysis: several point sets whose rows correspond, brought into
one frame by a rotation (and scale) each and their mean shape."""

from __future__ import annotations

import math
from typing import Annotated, Literal, get_args

import numpy as np

from algorithms.core.errors import ConvergenceWarning, DegenerateInputError, warn
from algorithms.core.linalg import homogeneous, procrustes
from algorithms.core.params import ArrayInput, Ge, validate_params
from algorithms.core.progress import Progress, as_progress
from algorithms.core.types import FloatArray
from algorithms.registration._point_sets import (
    MultiwayResult,
    PointSetsLike,
    check_sets,
    check_transforms,
)

__all__ = ["generalized_procrustes", "MODELS", "Model"]

Model = Literal["rigid", "similarity"]
#: The accepted values of ``model``.
MODELS = get_args(Model)

#: An objective at or below this fraction of the data's squared size is an exact fit.
ROUNDING_RTOL = 1e-24


@validate_params
def generalized_procrustes(
    sets: PointSetsLike,
    *,
    model: Model = "rigid",
    init: ArrayInput | None = None,
    max_iterations: Annotated[int, Ge(1)] = 100,
    tolerance: Annotated[float, Ge(0)] = 1e-9,
    progress: Progress | None = None,
) -> MultiwayResult:
    r"""Register ``k >= 2`` point sets whose rows correspond (row ``j`` of every set is the
    same point); one transform per set into set 0's frame, and their mean shape.

    Generalised Procrustes analysis (Gower 1975). With the sets centred, :math:`\tilde X_i`,
    it solves

    .. math::

        \min_{R_i,\ s_i,\ M}\ \sum_{i=1}^{k} \lVert s_i \tilde X_i R_i^\mathsf{T} - M
        \rVert_F^2, \qquad \det R_i = 1,\quad
        \textstyle\sum_i s_i^2 \lVert \tilde X_i \rVert_F^2 = \sum_i \lVert \tilde X_i
        \rVert_F^2

    (:math:`s_i = 1` and no constraint for ``model="rigid"``) by block-coordinate descent
    from :math:`M = \tilde X_0`: each pass rotates every set onto the current mean
    (:func:`~algorithms.core.linalg.procrustes` of :math:`M^\mathsf{T} \tilde X_i`, the
    reflection fixed), then, for similarity, sets the scales to ten Berge's (1977) optimum
    for those rotations, :math:`s_i = \phi_i \sqrt{\sum_j \lVert \tilde X_j \rVert^2} /
    \lVert \tilde X_i \rVert` with :math:`\phi` the top eigenvector of the sets'
    correlation matrix :math:`\Phi_{ij} = \langle Z_i, Z_j \rangle / (\lVert Z_i \rVert
    \lVert Z_j \rVert)`, :math:`Z_i = \tilde X_i R_i^\mathsf{T}`, then takes the mean. The
    objective never increases; the iterations stop when it falls by less than
    ``tolerance`` (relatively). The gauge is then fixed to set 0: every working transform
    is composed with the inverse of set 0's, and the mean shape moved into set 0's frame.

    Parameters
    ----------
    sets : sequence of (n, d) float arrays
        At least two point sets of the same length ``n`` and dimension ``d >= 1``, row
        ``j`` of each the same point.
    model : {"rigid", "similarity"}, default "rigid"
        ``"rigid"``: a rotation and a translation per set; ``"similarity"``: also a
        uniform scale (relative to set 0's).
    init : (k, d+1, d+1) float array, optional
        A start transform per set into a common frame (rigid or similarity, as ``model``);
        only their relative transforms matter: the first mean is that of the sets as they
        move them. Omitted: the first mean is set 0.
    max_iterations : int, default 100
        Most passes (rotations, scales, mean), ``>= 1``.
    tolerance : float, default 1e-9
        Stop when the objective decreases by less than this fraction of its value in a
        pass, ``>= 0``.
    progress : callable, optional
        ``progress(done, total, message)`` after every pass; it may raise
        :class:`~algorithms.core.errors.Cancelled`, which propagates.

    Returns
    -------
    MultiwayResult
        ``transforms``, ``rotations``, ``scales``, ``translations``, ``mean_shape`` and
        ``rmse`` (to the mean shape); ``fitness`` all 1.0 and no ``edges``;
        ``iterations``, ``converged`` and ``reason``.

    Raises
    ------
    InvalidInputError
        Fewer than 2 sets (``field="sets"``); a malformed or non-finite set, another
        dimension or length than ``sets[0]``'s (``field="sets[i]"``); a malformed
        ``init``; an option out of range.
    DegenerateInputError
        A set too flat to determine its rotation (coincident points; collinear in 3-D)
        or, for similarity, its scale, or one opposed to the consensus (no positive scale
        fits it) (``field="sets[i]"``).

    Warns
    -----
    ConvergenceWarning
        Whenever ``converged`` is False.

    Notes
    -----
    **The scale constraint.** Without one, all scales would shrink to zero. ten Berge's
    constraint (above) and Dryden & Mardia's unit size of the mean give the same
    transforms up to one common scale, which the gauge removes: the scale of the
    consensus minimising :math:`\sum_i \lVert s_i Z_i - M \rVert^2` with
    :math:`\lVert M \rVert` fixed is :math:`s_i \propto \langle \hat Z_i, u \rangle /
    \lVert Z_i \rVert` with :math:`u` the top eigenvector of :math:`\sum_i \hat Z_i \hat
    Z_i^\mathsf{T}`, the same :math:`\phi_i / \lVert Z_i \rVert` as ten Berge's. For two
    sets the relative scale is the ratio of their sizes, :math:`\lVert \tilde X_0 \rVert
    / \lVert \tilde X_1 \rVert`, symmetric in the sets, unlike the one-sided Umeyama scale
    that :func:`scipy.spatial.procrustes` applies; the rotations agree.

    **The gauge.** Only the relative transforms are determined; fixing set 0 as the
    reference makes ``transforms[0]`` the identity and expresses ``mean_shape`` and
    ``rmse`` in set 0's units.

    **Cost.** :math:`O(k n d^2)` per pass.

    References
    ----------
    .. [1] J. C. Gower, "Generalized Procrustes analysis", Psychometrika 40(1), 33-51,
       1975.
    .. [2] J. M. F. ten Berge, "Orthogonal Procrustes rotation for two or more matrices",
       Psychometrika 42(2), 267-276, 1977.
    .. [3] I. L. Dryden and K. V. Mardia, *Statistical Shape Analysis*, 2nd ed., Wiley,
       2016, chapter 7.

    Examples
    --------
    >>> import numpy as np
    >>> from algorithms.registration import generalized_procrustes
    >>> x = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 1.0]])
    >>> turned = x @ np.array([[0.0, -1.0], [1.0, 0.0]]).T + [5.0, 0.0]   # 90°, shifted
    >>> res = generalized_procrustes([x, turned, x + 1.0])
    >>> res.converged, [float(r) for r in np.round(res.rmse, 12)]
    (True, [0.0, 0.0, 0.0])
    >>> np.round(res.transforms[1], 12) + 0.0
    array([[ 0.,  1.,  0.],
           [-1.,  0.,  5.],
           [ 0.,  0.,  1.]])
    """
    report = as_progress(progress)
    pts = check_sets(sets, correspondences=True, model=model)
    k, d = len(pts), pts[0].shape[1]
    start = None if init is None else check_transforms(init, k, d, model)
    result = _procrustes(pts, model, start, max_iterations, tolerance, report)
    if not result.converged:
        warn(f"Generalised Procrustes did not converge: {result.reason}.",
             ConvergenceWarning)
    return result


def _procrustes(pts: list[FloatArray], model: str, start: FloatArray | None,
                max_iterations: int, tolerance: float, report: Progress) -> MultiwayResult:
    k = len(pts)
    n, d = pts[0].shape
    centres = np.stack([p.mean(axis=0) for p in pts])                  # (k, d)
    x = np.stack(pts) - centres[:, None, :]                             # (k, n, d)
    sq = np.einsum("knd,knd->k", x, x)                                  # ‖X̃_i‖²
    total = float(sq.sum())
    scales = np.ones(k)
    if start is None:
        mean = x[0].copy()
    else:  # the mean of the sets as the start moves them (the linear parts suffice)
        mean = np.einsum("kij,knj->ni", start[:, :d, :d], x) / k
    objective = math.inf
    converged, reason, it = False, "", 0
    for it in range(1, max_iterations + 1):
        rot = procrustes(np.einsum("nd,kne->kde", mean, x)).rotation      # (k, d, d)
        z = np.einsum("kij,knj->kni", rot, x)                           # Z_i = X̃_i R_iᵀ
        if model == "similarity":
            scales = _ten_berge(z, sq, total)
        y = z * scales[:, None, None]
        mean = y.mean(axis=0)
        diff = y - mean
        new = float(np.einsum("knd,knd->", diff, diff))
        report(it, max_iterations, f"Procrustes pass {it}: objective {new:.6g}")
        if new <= ROUNDING_RTOL * total:
            converged, reason = True, "objective at rounding level (exact fit)"
            break
        if math.isfinite(objective) and objective - new <= tolerance * objective:
            change = (objective - new) / objective
            converged, reason = True, (f"relative objective change {change:.3g} below "
                                       f"tolerance {tolerance:g}")
            break
        objective = new
    else:
        reason = f"max_iterations = {max_iterations} reached before the tolerance was met"
    # Gauge: compose every working map W_i(x) = s_i R_i (x - c_i) with W_0⁻¹.
    rel_scale = scales / scales[0]
    rotations = np.einsum("ji,kjl->kil", rot[0], rot)                   # R_0ᵀ R_i
    linear = rotations * rel_scale[:, None, None]
    translations = centres[0] - np.einsum("kij,kj->ki", linear, centres)
    rotations[0] = np.eye(d)
    translations[0] = 0.0
    linear[0] = np.eye(d)
    mean_shape = mean @ rot[0] / scales[0] + centres[0]
    rmse = np.sqrt(np.einsum("knd,knd->k", diff, diff) / n) / scales[0]
    return MultiwayResult(
        transforms=homogeneous(linear, translations),
        rotations=rotations,
        scales=rel_scale if model == "similarity" else np.ones(k),
        translations=translations,
        mean_shape=mean_shape,
        rmse=rmse,
        fitness=np.ones(k),
        edges=np.zeros((0, 2), dtype=np.int64),
        edge_fitness=np.zeros(0),
        edge_kept=np.zeros(0, dtype=bool),
        iterations=it,
        converged=converged,
        reason=reason,
    )


def _ten_berge(z: FloatArray, sq: FloatArray, total: float) -> FloatArray:
    """The optimal scales for rotated sets ``z`` under ``Σ s_i² ‖X_i‖² = Σ ‖X_i‖²``."""
    norms = np.sqrt(sq)
    gram = np.einsum("knd,lnd->kl", z, z) / np.outer(norms, norms)
    _, vecs = np.linalg.eigh(gram)
    phi = vecs[:, -1] * (1.0 if vecs[:, -1].sum() >= 0 else -1.0)
    if not (phi > 0).all():
        i = int(np.argmin(phi))
        raise DegenerateInputError(
            f"Expected every set to correlate positively with the consensus, got `sets[{i}]` "
            "opposed to it: no positive scale fits it (its shape does not match the "
            "others').", field=f"sets[{i}]")
    return phi * math.sqrt(total) / norms
