"""Alignment with known correspondences: row ``i`` of ``source`` pairs with row ``i`` of
``target``; each method finds the transform of its model that maps one onto the other."""

from algorithms.alignment.rigid import RigidResult, rigid

__all__ = ["RigidResult", "rigid"]
