"""Alignment with known correspondences: row ``i`` of ``source`` pairs with row ``i`` of
``target``; each method finds the transform of its model that maps one onto the other.
``pca`` is the exception: it needs no correspondences and the sets may differ in size."""

from algorithms.alignment.affine import AffineResult, affine
from algorithms.alignment.homography import HomographyResult, homography
from algorithms.alignment.pca import PCAResult, pca
from algorithms.alignment.principal_scaling import PrincipalScalingResult, principal_scaling
from algorithms.alignment.rigid import RigidResult, rigid
from algorithms.alignment.similarity import SimilarityResult, similarity

__all__ = [
    "AffineResult",
    "affine",
    "HomographyResult",
    "homography",
    "PCAResult",
    "pca",
    "PrincipalScalingResult",
    "principal_scaling",
    "RigidResult",
    "rigid",
    "SimilarityResult",
    "similarity",
]
