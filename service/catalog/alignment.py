"""Catalog entries of the alignment family (known correspondences: row i of source ↔ row i
of target)."""

from __future__ import annotations

from pydantic import Field, model_validator

from algorithms.alignment import RigidResult, rigid
from service.catalog.base import Params
from service.catalog.inputs import Points, Weights
from service.catalog.registry import Process, registry

_SQUARE = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]
_MOVED = [[1, 2, 3], [1, 3, 3], [0, 2, 3], [1, 2, 4]]


class RigidParams(Params):
    source: Points = Field(description="Points to move: an (n, d) array, d ≥ 2, n ≥ d.",
                           examples=[_SQUARE])
    target: Points = Field(description="Where each source row should land: (n, d), row i "
                           "corresponds to source row i.", examples=[_MOVED])
    weights: Weights | None = Field(None, description="Optional non-negative weight per pair.")
    allow_reflection: bool = Field(False, description="Allow det(R) = −1 when a reflection "
                                   "fits better. Off: always a proper rotation.")

    @model_validator(mode="after")
    def _paired(self) -> RigidParams:
        check_pairs(self.source, self.target, self.weights)
        return self


def check_pairs(source, target, weights) -> None:  # noqa: ANN001 - arrays
    from algorithms.core.validation import as_weights, same_shape

    same_shape(source, target, names=("source", "target"))
    if weights is not None:
        as_weights(weights, source.shape[0], name="weights")


registry.add(Process(
    id="alignment.rigid",
    title="Rigid alignment (Kabsch / Umeyama without scale)",
    description="The rotation R (det +1 unless reflections are allowed) and translation t "
    "minimising Σ wᵢ‖R xᵢ + t − yᵢ‖² for paired points in any dimension d ≥ 2.",
    function=rigid,
    params=RigidParams,
    result=RigidResult,
    reference="Umeyama, S. (1991). Least-squares estimation of transformation parameters "
    "between two point patterns. IEEE TPAMI 13(4), 376–380.",
    fast_path=True,
    keywords=("procrustes", "kabsch", "rotation", "correspondences"),
))
