"""Type aliases shared by the algorithms."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

__all__ = ["FloatArray", "IntArray", "IntpArray", "BoolArray", "RngLike", "KnnQuery"]

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
IntpArray = NDArray[np.intp]  # indices as numpy and scipy return them (argsort, kd-tree queries)
BoolArray = NDArray[np.bool_]
RngLike = np.random.Generator | int | None

#: What ``cKDTree.query`` returns for a 2-D ``x`` or a list of ``k``: (distances, indices).
#: Its stubs also allow the scalars of a single point queried with an int ``k``, hence
#: ``cast(KnnQuery, tree.query(...))`` where the query is known to be 2-D.
KnnQuery = tuple[FloatArray, IntpArray]
