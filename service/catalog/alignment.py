"""Catalog entries of the alignment family (known correspondences: row i of source ↔ row i
of target; ``alignment.pca`` needs none)."""

from __future__ import annotations

from functools import partial

from algorithms.alignment import affine, homography, pca, principal_scaling, rigid, similarity
from algorithms.core.pairs import check_pairs
from algorithms.core.validation import check_point_sets
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

# closed forms on paired points: row i of source pairs with row i of target
_paired = partial(Process, geometry=scenes.moved_source, check=check_pairs, fast_path=True)

registry.add(_paired(rigid, examples={"source": _SQUARE, "target": _MOVED},
                     keywords=("procrustes", "kabsch", "rotation", "correspondences")))
registry.add(_paired(similarity, examples={"source": _SQUARE, "target": _GROWN},
                     keywords=("procrustes", "umeyama", "scale", "rotation", "correspondences")))
registry.add(_paired(affine, examples={"source": _SQUARE, "target": _SHEARED},
                     keywords=("least squares", "affine", "regression", "correspondences")))
registry.add(_paired(principal_scaling, examples={"source": _WHITE, "target": _STRETCHED},
                     keywords=("svd", "scaling", "cross-covariance", "correspondences")))
registry.add(_paired(homography, examples={"source": _UNIT, "target": _PERSPECTIVE},
                     keywords=("homography", "projective", "dlt", "perspective",
                               "correspondences")))
registry.add(_paired(pca, examples={"source": _SKEWED, "target": _SKEWED_MOVED},
                     check=check_point_sets,
                     keywords=("pca", "principal axes", "moments", "initial alignment")))
