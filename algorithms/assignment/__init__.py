"""Assignment: correspondences between two point sets (who pairs with whom)."""

from algorithms.assignment.nearest import DIRECTIONS, NearestResult, nearest

__all__ = ["DIRECTIONS", "NearestResult", "nearest"]
