"""Catalog entries of the alignment family (known correspondences: row i of source ↔ row i
of target; ``alignment.pca`` needs none)."""

from __future__ import annotations

from typing import Literal

from pydantic import Field, model_validator

from algorithms.alignment import (
    AffineResult,
    HomographyResult,
    PCAResult,
    PrincipalScalingResult,
    RigidResult,
    SimilarityResult,
    affine,
    homography,
    pca,
    principal_scaling,
    rigid,
    similarity,
)
from service.catalog.base import Params
from service.catalog.inputs import Points, Weights
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

_WEIGHTS = "Optional non-negative weight per pair."
_SYMMETRIC = ("Also count the inverse residuals (target mapped back onto source) in the "
              "objective and in rmse.")
_REFLECTION = ("Allow det(R) = −1 when a reflection fits better. Off: always a proper "
               "rotation.")


def check_pairs(source, target, weights) -> None:  # noqa: ANN001 - arrays
    from algorithms.core.validation import as_weights, same_shape

    same_shape(source, target, names=("source", "target"))
    if weights is not None:
        as_weights(weights, source.shape[0], name="weights")


class _PairedParams(Params):
    source: Points = Field(description="Points to move: an (n, d) array.")
    target: Points = Field(description="Where each source row should land: (n, d), row i "
                           "corresponds to source row i.")
    weights: Weights | None = Field(None, description=_WEIGHTS)

    @model_validator(mode="after")
    def _paired(self) -> _PairedParams:
        check_pairs(self.source, self.target, self.weights)
        return self


class RigidParams(_PairedParams):
    source: Points = Field(description="Points to move: an (n, d) array, d ≥ 2, n ≥ d.",
                           examples=[_SQUARE])
    target: Points = Field(description="Where each source row should land: (n, d), row i "
                           "corresponds to source row i.", examples=[_MOVED])
    allow_reflection: bool = Field(False, description=_REFLECTION)


class SimilarityParams(_PairedParams):
    source: Points = Field(description="Points to move: an (n, d) array, d ≥ 2, n ≥ d.",
                           examples=[_SQUARE])
    target: Points = Field(description="Where each source row should land: (n, d), row i "
                           "corresponds to source row i.", examples=[_GROWN])
    allow_reflection: bool = Field(False, description=_REFLECTION)
    symmetric: bool = Field(False, description=_SYMMETRIC)


class AffineParams(_PairedParams):
    source: Points = Field(description="Points to move: an (n, d) array with at least d + 1 "
                           "affinely independent rows.", examples=[_SQUARE])
    target: Points = Field(description="Where each source row should land: (n, d), row i "
                           "corresponds to source row i.", examples=[_SHEARED])
    symmetric: bool = Field(False, description=_SYMMETRIC + " Iterative (Newton's method "
                            "from the closed form).")


class PrincipalScalingParams(_PairedParams):
    source: Points = Field(description="Points to move: an (n, d) array, d ≥ 2, n ≥ d. The "
                           "map is least-squares optimal only when Σ wᵢ x̃ᵢx̃ᵢᵀ = I "
                           "(whitened source).", examples=[_WHITE])
    target: Points = Field(description="Where each source row should land: (n, d), row i "
                           "corresponds to source row i.", examples=[_STRETCHED])
    weights: Weights | None = Field(None, description=_WEIGHTS + " Used unnormalised: M = "
                                    "Σ wᵢ ỹᵢ x̃ᵢᵀ.")
    symmetric: bool = Field(False, description="Also count the inverse residuals in rmse "
                            "(M is a formula, not a fit: the map does not change).")
    allow_reflection: bool = Field(False, description=_REFLECTION)


class HomographyParams(_PairedParams):
    source: Points = Field(description="Points to move: an (n, d) array with n ≥ d + 2 "
                           "points in general position.", examples=[_UNIT])
    target: Points = Field(description="Where each source row should land: (n, d), row i "
                           "corresponds to source row i.", examples=[_PERSPECTIVE])
    weights: Weights | None = Field(None, description=_WEIGHTS + " They scale the pair's DLT "
                                    "rows (algebraic error).")
    symmetric: bool = Field(False, description="Also count the backward transfer error in "
                            "rmse (the DLT estimate does not change).")


class PCAParams(Params):
    source: Points = Field(description="Points to move: an (n, d) array, d ≥ 2, n ≥ 2.",
                           examples=[_SKEWED])
    target: Points = Field(description="Points to align to: an (m, d) array, same d, any "
                           "m ≥ 2; no correspondence with source needed.",
                           examples=[_SKEWED_MOVED])
    mode: Literal["unoriented", "oriented"] = Field(
        "unoriented",
        description="unoriented: try every proper sign choice of the principal axes and keep "
        "the one `choose` prefers; oriented: point each axis towards the set's skew (third "
        "moment), pair by variance order.",
    )
    choose: Literal["residual", "rotation"] = Field(
        "residual",
        description="With mode=unoriented: residual keeps the sign choice of least Chamfer "
        "distance (kd-tree), rotation the one of smallest rotation angle (largest trace).",
    )
    scale: Literal["anisotropic", "isotropic", "none"] = Field(
        "anisotropic",
        description="anisotropic: stretch each principal axis by the ratio of standard "
        "deviations; isotropic: one factor, the ratio of RMS radii; none: rotate only.",
    )
    allow_reflection: bool = Field(False, description=_REFLECTION)
    symmetric: bool = Field(False, description="Also count the inverse nearest-point "
                            "residuals (target mapped back onto source) in rmse.")

    @model_validator(mode="after")
    def _same_dim(self) -> PCAParams:
        from algorithms.core.validation import same_dim

        same_dim(self.source, self.target, names=("source", "target"))
        return self


_UMEYAMA = ("Umeyama, S. (1991). Least-squares estimation of transformation parameters "
            "between two point patterns. IEEE TPAMI 13(4), 376–380.")

registry.add(Process(
    id="alignment.rigid",
    title="Rigid alignment (Kabsch / Umeyama without scale)",
    description="The rotation R (det +1 unless reflections are allowed) and translation t "
    "minimising Σ wᵢ‖R xᵢ + t − yᵢ‖² for paired points in any dimension d ≥ 2.",
    function=rigid,
    params=RigidParams,
    result=RigidResult,
    reference=_UMEYAMA,
    fast_path=True,
    keywords=("procrustes", "kabsch", "rotation", "correspondences"),
))

registry.add(Process(
    id="alignment.similarity",
    title="Similarity alignment (Umeyama)",
    description="The rotation R (det +1 unless reflections are allowed), uniform scale s and "
    "translation t minimising Σ wᵢ‖s R xᵢ + t − yᵢ‖² for paired points, d ≥ 2; "
    "s = tr(DΣ)/σx² with Umeyama's reflection-corrected trace.",
    function=similarity,
    params=SimilarityParams,
    result=SimilarityResult,
    reference=_UMEYAMA,
    fast_path=True,
    keywords=("procrustes", "umeyama", "scale", "rotation", "correspondences"),
))

registry.add(Process(
    id="alignment.affine",
    title="Affine alignment (linear least squares)",
    description="The matrix A and translation b minimising Σ wᵢ‖A xᵢ + b − yᵢ‖² for paired "
    "points in any dimension: A = Ỹ X̃⁺ by least squares, b through the centroids.",
    function=affine,
    params=AffineParams,
    result=AffineResult,
    reference="Schaefer, S., McPhail, T., Warren, J. (2006). Image deformation using moving "
    "least squares. ACM TOG 25(3), 533–540.",
    fast_path=True,
    keywords=("least squares", "affine", "regression", "correspondences"),
))

registry.add(Process(
    id="alignment.principal_scaling",
    title="Principal scaling alignment (M = Ỹ X̃ᵀ, as the seed states it)",
    description="Scale along perpendicular axes, then rotate: y = UΣVᵀx + t with "
    "UΣVᵀ = Σ wᵢ ỹᵢ x̃ᵢᵀ. Equals the least-squares affine map exactly when the source is "
    "whitened (Σ wᵢ x̃ᵢ x̃ᵢᵀ = I); otherwise a worse fit.",
    function=principal_scaling,
    params=PrincipalScalingParams,
    result=PrincipalScalingResult,
    reference=_UMEYAMA,
    fast_path=True,
    keywords=("svd", "scaling", "cross-covariance", "correspondences"),
))

registry.add(Process(
    id="alignment.homography",
    title="Projective alignment (normalised DLT)",
    description="The (d+1)×(d+1) projective matrix P (P[d, d] = 1 when possible) with "
    "y ≈ dehomogenize(P [x; 1]), by the direct linear transformation on Hartley-normalised "
    "points, in any dimension; at least d + 2 pairs in general position.",
    function=homography,
    params=HomographyParams,
    result=HomographyResult,
    reference="Hartley, R., Zisserman, A. (2004). Multiple View Geometry in Computer Vision, "
    "2nd ed., §4.1–4.4. Cambridge University Press.",
    fast_path=True,
    keywords=("homography", "projective", "dlt", "perspective", "correspondences"),
))

registry.add(Process(
    id="alignment.pca",
    title="Principal-axis alignment (no correspondences)",
    description="Lays the principal axes of the source onto those of the target (sets of any "
    "sizes): A = E′ S K Eᵀ with signs S from skewness (oriented) or the best of the proper "
    "sign choices (unoriented), scale K none, isotropic or anisotropic √(D′D⁻¹).",
    function=pca,
    params=PCAParams,
    result=PCAResult,
    reference="Ju, T. CSE 554 Lecture 7: Alignment. Washington University in St. Louis.",
    fast_path=True,
    keywords=("pca", "principal axes", "moments", "initial alignment"),
))
