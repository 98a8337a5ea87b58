"""Registration without correspondences: which point of ``target`` each point of ``source``
matches is unknown, and found together with the transform — locally (iterative closest
point, coherent point drift), globally (RANSAC over features), or for several sets at once
(multiway: generalised Procrustes when the rows of the sets correspond, a pose graph when
they do not)."""

from algorithms.registration._normals import given_normals
from algorithms.registration.cpd import CPDResult, cpd
from algorithms.registration.features import fpfh, match_features
from algorithms.registration.icp import ICPResult, icp
from algorithms.registration.multiway import MultiwayResult, multiway
from algorithms.registration.pose_graph import pose_graph
from algorithms.registration.procrustes import generalized_procrustes
from algorithms.registration.ransac import RANSACResult, ransac

__all__ = [
    "ICPResult",
    "icp",
    "CPDResult",
    "cpd",
    "fpfh",
    "match_features",
    "given_normals",
    "RANSACResult",
    "ransac",
    "MultiwayResult",
    "multiway",
    "generalized_procrustes",
    "pose_graph",
]
