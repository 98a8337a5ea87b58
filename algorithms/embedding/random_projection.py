r"""Random projection: a random linear map that keeps pairwise distances approximately
(Johnson–Lindenstrauss)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Annotated, Any, Literal

import numpy as np
from scipy.spatial.distance import pdist

from algorithms.core.errors import InvalidInputError
from algorithms.core.params import Ge, Interval, PointsLike, Seed, validate_params
from algorithms.core.types import FloatArray
from algorithms.core.validation import as_points
from algorithms.embedding._quality import trustworthiness
from algorithms.embedding.pca import check_linear_components

__all__ = ["check_random_projection", "RandomProjectionResult", "random_projection", "MatrixKind"]

MatrixKind = Literal["gaussian", "sparse"]
"""The entries of the random matrix: Gaussian, or sparse signs (Achlioptas; Li et al.)."""

#: The distortion is measured on the pairs of at most this many points (evenly spaced rows).
_DISTORTION_POINTS = 500


@dataclass(frozen=True, eq=False)
class RandomProjectionResult:
    """Points mapped by a random ``k×D`` matrix.

    Attributes
    ----------
    embedding : (n, k) float array
        :math:`X R^\\mathsf{T}` (not centred), one row per point.
    components : (k, D) float array
        The random matrix :math:`R`; new points map as ``x @ components.T``.
    distortion : float
        The largest relative change of a squared pairwise distance,
        :math:`\\max |\\lVert R(x_i - x_j) \\rVert^2 / \\lVert x_i - x_j \\rVert^2 - 1|`,
        over the pairs of up to 500 evenly spaced points (the ε of Johnson–Lindenstrauss).
    trustworthiness : float
        Trustworthiness of the embedding (1: every embedded neighbourhood is a true one).
    """

    embedding: FloatArray
    components: FloatArray
    distortion: float
    trustworthiness: float


def check_random_projection(points: Any, n_components: Any, kind: str = "gaussian",
                            density: float | None = None) -> tuple[FloatArray, int]:
    """Check the inputs of :func:`random_projection`: ``n_components`` at most the points'
    dimension and number (:func:`check_linear_components`); ``density`` only with
    ``kind="sparse"``. Returns the points and ``n_components``."""
    x = as_points(points, name="points", min_points=1)
    k = check_linear_components(n_components, *x.shape)
    if density is not None and kind != "sparse":
        raise InvalidInputError("Expected `density` only with kind = 'sparse'.",
                                field="density")
    return x, k


@validate_params
def random_projection(
    points: PointsLike,
    *,
    n_components: Annotated[int, Ge(1)] = 2,
    kind: MatrixKind = "gaussian",
    density: Annotated[float, Interval(gt=0, le=1)] | None = None,
    seed: Seed = 0,
    quality_neighbors: Annotated[int, Ge(1)] = 5,
) -> RandomProjectionResult:
    r"""Random projection (Johnson–Lindenstrauss).

    Maps the points by a random k×D matrix, Gaussian or sparse, that keeps squared distances in
    expectation. Reports the matrix, the largest relative distortion of squared distances and
    trustworthiness.

    * ``"gaussian"``: :math:`R_{cj} \sim \mathcal N(0, 1/k)`;
    * ``"sparse"``: :math:`R_{cj} = \pm\sqrt{s/k}` with probability :math:`1/(2s)` each and
      0 otherwise, :math:`s = 1/\text{density}` (default density :math:`1/\sqrt D`).

    Either way :math:`\mathbb E\,\lVert R x \rVert^2 = \lVert x \rVert^2`, and with
    :math:`k = O(\varepsilon^{-2}\log n)` every pairwise distance is kept within a factor
    :math:`1 \pm \varepsilon` with high probability.

    Parameters
    ----------
    points : (n, D) float array
        The data, one row per point.
    n_components : int, default 2
        The dimension ``k`` of the embedding, ``1 <= k <= min(n, D)`` (a projection adds
        no dimensions).
    kind : {"gaussian", "sparse"}, default "gaussian"
        The matrix entries: ``"gaussian"`` independent :math:`\mathcal{N}(0, 1/k)`;
        ``"sparse"`` :math:`\pm\sqrt{(s/k)}` with probability :math:`1/(2s)` each and 0
        otherwise, :math:`s = 1/\text{density}` (Achlioptas; Li, Hastie and Church).
    density : float, optional
        The fraction of non-zero entries with ``kind="sparse"`` (only there), in
        ``(0, 1]``; :math:`1/\sqrt{D}` when omitted.
    seed : int or numpy Generator, default 0
        Draws the matrix; the same seed gives the same matrix.
    quality_neighbors : int, default 5
        The neighbourhood size of the reported trustworthiness (clipped to
        ``(n - 1) // 2`` when larger).

    Returns
    -------
    RandomProjectionResult
        ``embedding``, ``components``, ``distortion``, ``trustworthiness``.

    Raises
    ------
    InvalidInputError
        Bad ``points``; ``n_components`` outside ``[1, min(n, D)]`` (a projection does not
        add dimensions); unknown ``kind``; ``density`` outside ``(0, 1]``.

    Notes
    -----
    Why distances survive: the rows of a random matrix in many dimensions are nearly
    orthogonal and of nearly equal length, so :math:`R` acts almost as a scaled
    orthogonal projection, and the squared length of every difference is kept in
    expectation (exactly) and within :math:`1 \pm \varepsilon` with high probability
    (Johnson–Lindenstrauss). The matrices are scikit-learn's
    (``GaussianRandomProjection``, ``SparseRandomProjection``) in distribution; the random
    streams differ, so the same seed does not give scikit-learn's matrix.

    References
    ----------
    .. [1] W. B. Johnson, J. Lindenstrauss, "Extensions of Lipschitz mappings into a
       Hilbert space", Contemporary Mathematics 26 (1984).
    .. [2] D. Achlioptas, "Database-friendly random projections", PODS (2001).
    .. [3] P. Li, T. J. Hastie, K. W. Church, "Very sparse random projections", KDD (2006).

    Examples
    --------
    >>> import numpy as np
    >>> x = np.random.default_rng(1).normal(size=(50, 100))
    >>> res = random_projection(x, n_components=40, seed=3)
    >>> res.embedding.shape, res.components.shape
    ((50, 40), (40, 100))
    """
    x, k = check_random_projection(points, n_components, kind, density)
    n, dim = x.shape
    rng = np.random.default_rng(seed)
    if kind == "gaussian":
        r = rng.normal(0.0, 1.0 / math.sqrt(k), size=(k, dim))
    else:
        dens = 1.0 / math.sqrt(dim) if density is None else density
        u = rng.random((k, dim))
        sign = np.where(rng.random((k, dim)) < 0.5, -1.0, 1.0)
        r = np.where(u < dens, sign * math.sqrt(1.0 / (dens * k)), 0.0)
    y = x @ r.T
    rows = np.unique(np.linspace(0, n - 1, min(n, _DISTORTION_POINTS)).astype(np.int64))
    dx, dy = pdist(x[rows], "sqeuclidean"), pdist(y[rows], "sqeuclidean")
    keep = dx > 0
    distortion = float(np.abs(dy[keep] / dx[keep] - 1.0).max()) if keep.any() else 0.0
    return RandomProjectionResult(
        embedding=np.ascontiguousarray(y),
        components=r,
        distortion=distortion,
        trustworthiness=trustworthiness(x, y, n_neighbors=quality_neighbors),
    )
