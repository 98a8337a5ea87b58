"""Registration without correspondences: which point of ``target`` each point of ``source``
matches is unknown, and found together with the transform (iterative closest point)."""

from algorithms.registration.icp import ICPResult, icp

__all__ = [
    "ICPResult",
    "icp",
]
