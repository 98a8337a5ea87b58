"""Registration without correspondences: which point of ``target`` each point of ``source``
matches is unknown, and found together with the transform — locally (iterative closest
point, coherent point drift), globally (RANSAC over features), or for several sets at once
(multiway)."""

from algorithms.registration.cpd import CPDResult, cpd
from algorithms.registration.features import fpfh, match_features
from algorithms.registration.icp import ICPResult, icp
from algorithms.registration.multiway import MultiwayResult, multiway
from algorithms.registration.ransac import RANSACResult, ransac

__all__ = [
    "ICPResult",
    "icp",
    "CPDResult",
    "cpd",
    "fpfh",
    "match_features",
    "RANSACResult",
    "ransac",
    "MultiwayResult",
    "multiway",
]
