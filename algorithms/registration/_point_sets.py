"""What the two multiway registrations share: their result, :class:`MultiwayResult`, and the
checks of their inputs (the list of point sets, the start transforms), which the service
runs too, before a job is queued.

Private to the registration family: :mod:`algorithms.registration.multiway` re-exports
them.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Annotated, Any

import numpy as np
from numpy.typing import ArrayLike

from algorithms.core.errors import InvalidInputError
from algorithms.core.params import Kind
from algorithms.core.types import BoolArray, FloatArray, IntArray
from algorithms.core.validation import as_points, check_span
from algorithms.registration.icp import check_init

__all__ = ["PointSetsLike", "MultiwayResult", "check_sets", "check_transforms", "check_rigid"]

PointSetsLike = Annotated[Sequence[ArrayLike], Kind.ARRAY]
"""A list of ``(n_i, d)`` point arrays (or one ``(k, n, d)`` array), checked by
:func:`check_sets`."""


@dataclass(frozen=True, eq=False)
class MultiwayResult:
    """One transform per set into the frame of set 0, and how well the sets agree there.

    Attributes
    ----------
    transforms : (k, d+1, d+1) float array
        ``transforms[i]`` maps the points of set ``i`` into the frame of set 0 (the
        reference: ``transforms[0]`` is the identity), homogeneous ``[[s R, t], [0, 1]]``.
    rotations : (k, d, d) float array
        The rotation ``R`` of each transform (determinant +1).
    scales : (k,) float array
        The scale ``s`` of each transform: all 1.0 for the rigid model; relative to set 0
        for similarity.
    translations : (k, d) float array
        The translation ``t`` of each transform, applied after ``s R``.
    mean_shape : (n, d) float array or None
        Generalised Procrustes only: the mean shape (consensus), row ``j`` the mean of the
        sets' row ``j`` after their transforms, in the frame (and units) of set 0. Null for
        the pose graph.
    rmse : (k,) float array
        Per set, in set 0's units. Procrustes: the root-mean-square distance of the moved
        set's rows to the mean shape's. Pose graph: the RMS distance from the set's moved
        points to the nearest moved point of the sets it kept an edge with, over the points
        that have one within ``max_correspondence_distance`` (0.0 when none has).
    fitness : (k,) float array
        Pose graph: per set, the fraction of its points with a point of a set it kept an
        edge with within ``max_correspondence_distance`` (Open3D's fitness, over the
        graph). Procrustes: all 1.0 (every row has its partner).
    edges : (m, 2) int array
        Pose graph: the pairs ``(i, j)`` registered by ICP (set ``i`` onto set ``j``), kept
        or not. Procrustes: empty (no pairwise registration).
    edge_fitness : (m,) float array
        Pose graph: the ICP fitness of each edge (share of set ``i``'s points with a
        partner in set ``j`` within ``max_correspondence_distance``). Procrustes: empty.
    edge_kept : (m,) bool array
        Pose graph: whether the edge is in the final graph; dropped for low fitness
        (below ``min_fitness``) or pruned by the line process (a loop closure whose
        confidence fell below ``edge_prune_threshold``). Procrustes: empty.
    iterations : int
        Procrustes: passes of the rotation/scale/mean updates. Pose graph: accepted
        Levenberg-Marquardt steps of both optimisation rounds.
    converged : bool
        True when the relative decrease of the objective fell below ``tolerance`` (or the
        fit is exact); False when ``max_iterations`` ran out. A ``ConvergenceWarning``
        accompanies False.
    reason : str
        Why the iterations stopped, in words.
    """

    transforms: FloatArray
    rotations: FloatArray
    scales: FloatArray
    translations: FloatArray
    mean_shape: FloatArray | None
    rmse: FloatArray
    fitness: FloatArray
    edges: IntArray
    edge_fitness: FloatArray
    edge_kept: BoolArray
    iterations: int
    converged: bool
    reason: str


def check_sets(sets: Any, *, correspondences: bool, model: str = "rigid",
               metric: str = "symmetric", max_points: int | None = None
               ) -> list[FloatArray]:
    """Check the list of point sets of a multiway registration and return them as float arrays.

    At least two sets, each an ``(n_i, d)`` array of finite numbers with the same ``d``;
    with ``correspondences`` all of the same length ``n`` (row ``j`` of each is the same
    point) and spread enough to determine their rotation (and scale); without, 3-D and
    enough points for the pairwise ICP. Errors name the set: ``field="sets[2]"``.
    """
    if isinstance(sets, np.ndarray) and sets.ndim == 3:
        sets = list(sets)
    if isinstance(sets, (str, bytes)) or not isinstance(sets, (Sequence, np.ndarray)):
        raise InvalidInputError(f"Expected `sets` to be a list of (n, d) point arrays, got "
                                f"{type(sets).__name__}.", field="sets")
    if len(sets) < 2:
        raise InvalidInputError(f"Expected `sets` to hold at least 2 point sets, got "
                                f"{len(sets)}.", field="sets")
    out = [as_points(s, name=f"sets[{i}]", max_points=max_points) for i, s in enumerate(sets)]
    n, d = out[0].shape
    for i, s in enumerate(out[1:], start=1):
        if s.shape[1] != d:
            raise InvalidInputError(
                f"Expected `sets[{i}]` to have the dimension of `sets[0]` ({d}), got shape "
                f"({s.shape[0]}, {s.shape[1]}).", field=f"sets[{i}]")
        if correspondences and s.shape[0] != n:
            raise InvalidInputError(
                f"Expected `sets[{i}]` to hold as many points as `sets[0]` ({n}, paired row "
                f"by row since correspondences=true), got {s.shape[0]}; give "
                "correspondences=false for sets without known correspondences.",
                field=f"sets[{i}]")
    if correspondences:
        need = max(d - 1, 1 if model == "similarity" else 0)
        why = "its rotation is undetermined" if need == d - 1 and d > 1 else \
            "its scale is undetermined"
        for i, s in enumerate(out):
            check_span(s, f"sets[{i}]", need, why)
        return out
    if d != 3:
        raise InvalidInputError(
            f"Expected 3-D point sets for correspondences=false (the pose graph is on "
            f"SE(3)), got d = {d}; give correspondences=true (generalised Procrustes, any "
            "d) for sets whose rows correspond.", field="sets")
    check_rigid(model)
    fewest = 3 if metric == "point_to_point" else 6
    for i, s in enumerate(out):
        if s.shape[0] < fewest:
            raise InvalidInputError(
                f"Expected `sets[{i}]` to hold at least {fewest} points (pairwise {metric} "
                f"ICP), got {s.shape[0]}.", field=f"sets[{i}]")
        check_span(s, f"sets[{i}]", 2, "the rotation of its pairwise ICP is undetermined")
    return out


def check_rigid(model: str) -> None:
    """The pose graph is on SE(3): only ``model="rigid"``; ``field="model"``."""
    if model != "rigid":
        raise InvalidInputError(
            f"Expected model='rigid' with correspondences=false (the pose graph is on "
            f"SE(3)), got {model!r}.", field="model")


def check_transforms(init: Any, k: int, d: int, model: str) -> FloatArray:
    """Check ``init``: ``k`` homogeneous ``(d+1, d+1)`` matrices of the model (rotations
    for rigid, positive multiples of rotations for similarity); ``field="init"``."""
    try:
        arr = np.asarray(init, dtype=np.float64)
    except (TypeError, ValueError):
        raise InvalidInputError(f"Expected `init` to be a ({k}, {d + 1}, {d + 1}) array of "
                                "homogeneous matrices, got one numpy cannot read.",
                                field="init") from None
    if arr.shape != (k, d + 1, d + 1):
        raise InvalidInputError(
            f"Expected `init` to be a ({k}, {d + 1}, {d + 1}) array: one homogeneous matrix "
            f"per set, got shape {tuple(arr.shape)}.", field="init")
    out = np.empty_like(arr)
    for i in range(k):
        try:
            out[i] = check_init(arr[i], d, model)
        except InvalidInputError as err:
            raise InvalidInputError(f"init[{i}]: {err.message}", field="init") from None
    return out

