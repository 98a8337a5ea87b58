"""Catalog entries of the alignment family (known correspondences: row i of source ↔ row i
of target; ``alignment.pca`` needs none)."""

from __future__ import annotations

from typing import Any

from algorithms.alignment import (
    affine,
    homography,
    pca,
    principal_scaling,
    rigid,
    similarity,
)
from algorithms.core.validation import as_weights, same_dim, same_shape
from service import scenes
from service.catalog.registry import Process, registry

_SQUARE = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]
_MOVED = [[1, 2, 3], [1, 3, 3], [0, 2, 3], [1, 2, 4]]          # 90° about z, then (1, 2, 3)
_GROWN = [[1, 2, 3], [1, 4, 3], [-1, 2, 3], [1, 2, 5]]         # the same, scaled by 2
_SHEARED = [[1, 0, 0], [3, 0, 0], [2, 1, 0], [1, 0, 3]]        # A = [[2,1,0],[0,1,0],[0,0,3]]
_WHITE = [[0.5, 0.5], [-0.5, 0.5], [-0.5, -0.5], [0.5, -0.5]]  # sum of x xᵀ = I
_STRETCHED = [[2.5, 1.25], [-0.5, 1.25], [-0.5, 0.75], [2.5, 0.75]]  # diag(3, 0.5), (1, 1)
_UNIT = [[0, 0], [1, 0], [1, 1], [0, 1]]
_PERSPECTIVE = [[0, 0], [0.5, 0], [0.5, 0.5], [0, 1]]           # (x, y) / (x + 1)
_SKEWED = [[-1, 0], [-1, 0], [2, 0], [0, 0.5], [0, 0.5], [0, -1]]
_SKEWED_MOVED = [[4, 2], [-0.5, 2], [-0.5, 2], [1, 8], [1, -1], [1, -1]]  # 3·(90°), (1, 2)


def _paired(p: Any) -> None:
    """Row i of source pairs with row i of target; weights, when given, one per pair."""
    same_shape(p.source, p.target, names=("source", "target"))
    if p.weights is not None:
        as_weights(p.weights, p.source.shape[0], name="weights")


def _same_dim(p: Any) -> None:
    """The two sets share their dimension (their sizes may differ)."""
    same_dim(p.source, p.target, names=("source", "target"))



registry.add(Process(
    id="alignment.rigid",
    geometry=scenes.moved_source,
    title="Rigid alignment (Kabsch / Umeyama without scale)",
    description="The rotation R (det +1 unless reflections are allowed) and translation t "
    "minimising Σ wᵢ‖R xᵢ + t − yᵢ‖² for paired points in any dimension d ≥ 2.",
    function=rigid,
    examples={"source": _SQUARE, "target": _MOVED},
    check=_paired,
    fast_path=True,
    keywords=("procrustes", "kabsch", "rotation", "correspondences"),
))

registry.add(Process(
    id="alignment.similarity",
    geometry=scenes.moved_source,
    title="Similarity alignment (Umeyama)",
    description="The rotation R (det +1 unless reflections are allowed), uniform scale s and "
    "translation t minimising Σ wᵢ‖s R xᵢ + t − yᵢ‖² for paired points, d ≥ 2; "
    "s = tr(DΣ)/σx² with Umeyama's reflection-corrected trace.",
    function=similarity,
    examples={"source": _SQUARE, "target": _GROWN},
    check=_paired,
    fast_path=True,
    keywords=("procrustes", "umeyama", "scale", "rotation", "correspondences"),
))

registry.add(Process(
    id="alignment.affine",
    geometry=scenes.moved_source,
    title="Affine alignment (linear least squares)",
    description="The matrix A and translation b minimising Σ wᵢ‖A xᵢ + b − yᵢ‖² for paired "
    "points in any dimension: A = Ỹ X̃⁺ by least squares, b through the centroids.",
    function=affine,
    examples={"source": _SQUARE, "target": _SHEARED},
    check=_paired,
    fast_path=True,
    keywords=("least squares", "affine", "regression", "correspondences"),
))

registry.add(Process(
    id="alignment.principal_scaling",
    geometry=scenes.moved_source,
    title="Principal scaling alignment (the cross-covariance map M = Ỹ X̃ᵀ)",
    description="Scale along perpendicular axes, then rotate: y = UΣVᵀx + t with "
    "UΣVᵀ = Σ wᵢ ỹᵢ x̃ᵢᵀ. Equals the least-squares affine map exactly when the source is "
    "whitened (Σ wᵢ x̃ᵢ x̃ᵢᵀ = I); otherwise a worse fit.",
    function=principal_scaling,
    examples={"source": _WHITE, "target": _STRETCHED},
    check=_paired,
    fast_path=True,
    keywords=("svd", "scaling", "cross-covariance", "correspondences"),
))

registry.add(Process(
    id="alignment.homography",
    geometry=scenes.moved_source,
    title="Projective alignment (normalised DLT)",
    description="The (d+1)×(d+1) projective matrix P (P[d, d] = 1 when possible) with "
    "y ≈ dehomogenize(P [x; 1]), by the direct linear transformation on Hartley-normalised "
    "points, in any dimension; at least d + 2 pairs in general position.",
    function=homography,
    examples={"source": _UNIT, "target": _PERSPECTIVE},
    check=_paired,
    fast_path=True,
    keywords=("homography", "projective", "dlt", "perspective", "correspondences"),
))

registry.add(Process(
    id="alignment.pca",
    geometry=scenes.moved_source,
    title="Principal-axis alignment (no correspondences)",
    description="Lays the principal axes of the source onto those of the target (sets of any "
    "sizes): A = E′ S K Eᵀ with signs S from skewness (oriented) or the best of the proper "
    "sign choices (unoriented), scale K none, isotropic or anisotropic √(D′D⁻¹).",
    function=pca,
    examples={"source": _SKEWED, "target": _SKEWED_MOVED},
    check=_same_dim,
    fast_path=True,
    keywords=("pca", "principal axes", "moments", "initial alignment"),
))
