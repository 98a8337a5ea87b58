r"""Locally linear embedding: reconstruct each point from its neighbours, then keep those
reconstruction weights in few dimensions."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Annotated, Any, Literal, cast

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from algorithms.core.errors import DegenerateInputError, InvalidInputError
from algorithms.core.graphs import (
    NNeighbors,
    Radius,
    check_connected,
    check_n_neighbors,
    check_neighbour_graph,
    nearest_sorted,
)
from algorithms.core.params import Ge, PointsLike, validate_params
from algorithms.core.types import FloatArray
from algorithms.core.validation import as_int
from algorithms.embedding._quality import fix_signs, trustworthiness
from algorithms.embedding.laplacian_eigenmaps import _smallest

__all__ = ["check_lle", "LLEResult", "lle", "barycenter_weights", "Neighbourhood"]

Neighbourhood = Literal["knn", "radius"]
"""Each point's own neighbours in LLE: its ``n_neighbors`` nearest, or all within ``radius``."""


@dataclass(frozen=True, eq=False)
class LLEResult:
    """The bottom non-trivial eigenvectors of :math:`(I - W)^\\mathsf{T}(I - W)`.

    Attributes
    ----------
    embedding : (n, k) float array
        Unit columns, each one's entry of largest magnitude positive.
    eigenvalues : (k,) float array
        The matching eigenvalues of :math:`M = (I - W)^\\mathsf{T}(I - W)`, increasing.
    reconstruction_error : float
        :math:`\\sum_i \\lVert y_i - \\sum_j W_{ij} y_j \\rVert^2`, the sum of
        ``eigenvalues`` (scikit-learn's ``reconstruction_error_``).
    weight_error : float
        :math:`\\sum_i \\lVert x_i - \\sum_j W_{ij} x_j \\rVert^2`: how well the weights
        reconstruct the input points.
    trustworthiness : float
        Trustworthiness of the embedding (1: every embedded neighbourhood is a true one).
    """

    embedding: FloatArray
    eigenvalues: FloatArray
    reconstruction_error: float
    weight_error: float
    trustworthiness: float


def _solve_rows(z: FloatArray, reg: float) -> FloatArray:
    """Sum-to-one weights for a stack of neighbour offsets ``z`` (m, k, D)."""
    c = np.einsum("mkd,mld->mkl", z, z)
    trace = np.trace(c, axis1=1, axis2=2)
    r = np.where(trace > 0, reg * trace, reg)
    kk = c.shape[1]
    c[:, np.arange(kk), np.arange(kk)] += r[:, None]
    try:
        w: FloatArray = np.linalg.solve(c, np.ones((c.shape[0], kk, 1)))[..., 0]
    except np.linalg.LinAlgError:
        raise DegenerateInputError(
            "Expected each point's neighbourhood to determine its reconstruction weights, got "
            "a singular local Gram matrix (more neighbours than dimensions, or coincident "
            "neighbours): use regularization > 0.", field="regularization") from None
    total: FloatArray = w.sum(axis=1, keepdims=True)
    return w / total


def barycenter_weights(x: FloatArray, neighbours: list[np.ndarray] | np.ndarray,
                       reg: float) -> sp.csr_array:
    r"""The sparse ``(n, n)`` matrix of LLE reconstruction weights (rows sum to 1).

    For point :math:`x_i` with neighbours :math:`\eta_1..\eta_m`: the local Gram matrix
    :math:`C_{ab} = (x_i - \eta_a)\cdot(x_i - \eta_b)`, regularised
    :math:`C + r\,\operatorname{tr}(C) I` (``r = reg``; ``r`` itself when the trace is 0),
    and :math:`w = C^{-1}\mathbf 1 / \mathbf 1^\mathsf{T} C^{-1} \mathbf 1`.
    """
    n = x.shape[0]
    if isinstance(neighbours, np.ndarray):  # a full (n, k) table: one batched solve
        nb = neighbours
        w = _solve_rows(x[nb] - x[:, None, :], reg)
        rows = np.repeat(np.arange(n), nb.shape[1])
        return sp.csr_array((w.ravel(), (rows, nb.ravel())), shape=(n, n))
    counts = np.array([len(a) for a in neighbours])
    rows_l, cols_l, vals_l = [], [], []
    for m in np.unique(counts):  # batch the points with the same number of neighbours
        pts = np.flatnonzero(counts == m)
        nb = np.array([neighbours[i] for i in pts], dtype=np.int64).reshape(pts.size, m)
        w = _solve_rows(x[nb] - x[pts, None, :], reg)
        rows_l.append(np.repeat(pts, m))
        cols_l.append(nb.ravel())
        vals_l.append(w.ravel())
    return sp.csr_array((np.concatenate(vals_l), (np.concatenate(rows_l),
                                                  np.concatenate(cols_l))), shape=(n, n))


def check_lle(points: Any, n_components: Any, neighbors: str = "knn",
              n_neighbors: Any = None, radius: Any = None) -> tuple[FloatArray, int]:
    """Check the inputs of :func:`lle`: at least 3 points, neighbour-graph parameters
    that fit them, ``n_components`` at most their number minus 2 (the eigenvectors after
    the trivial one, and fewer than all) and at most their dimension (as scikit-learn's
    ``LocallyLinearEmbedding``: the weights reconstruct each point in ``D`` dimensions).
    Returns the points and ``n_components``."""
    x = check_neighbour_graph(points, neighbors, n_neighbors, radius, min_points=3)
    n, d = x.shape
    reason = "the dimension of `points`" if d < n - 2 else "the number of `points` minus two"
    k = as_int(n_components, name="n_components", minimum=1, maximum=min(d, n - 2),
               reason=reason)
    return x, k


@validate_params
def lle(
    points: PointsLike,
    *,
    n_components: Annotated[int, Ge(1)] = 2,
    neighbors: Neighbourhood = "knn",
    n_neighbors: NNeighbors = 5,
    radius: Radius | None = None,
    regularization: Annotated[float, Ge(0)] = 1e-3,
    quality_neighbors: Annotated[int, Ge(1)] = 5,
) -> LLEResult:
    r"""Locally linear embedding.

    Sum-to-one weights reconstructing each point from its neighbours (regularised), then the bottom
    non-trivial eigenvectors of (I − W)ᵀ(I − W). Reports eigenvalues, the reconstruction error in
    the embedding and of the weights, and trustworthiness.

    1. Neighbours of each point: its ``n_neighbors`` nearest (``"knn"``, each point's own
       list, not symmetrised) or all within ``radius``; no edge weights are chosen.
    2. Reconstruction weights :math:`W` (:func:`barycenter_weights`): each row minimises
       :math:`\lVert x_i - \sum_j W_{ij} x_j \rVert^2` subject to :math:`\sum_j W_{ij} = 1`.
    3. The embedding: the eigenvectors of the ``k`` smallest eigenvalues of
       :math:`M = (I - W)^\mathsf{T}(I - W)` after the trivial constant one, i.e. the unit
       :math:`Y` minimising :math:`\sum_i \lVert y_i - \sum_j W_{ij} y_j \rVert^2`.

    Parameters
    ----------
    points : (n, D) float array
        The data, one row per point; at least 3 points.
    n_components : int, default 2
        The dimension ``k`` of the embedding, ``1 <= k <= min(D, n - 2)`` (scikit-learn's
        bound ``k <= D`` too).
    neighbors : {"knn", "radius"}, default "knn"
        The points each point is reconstructed from: ``"knn"`` its own ``n_neighbors``
        nearest (not symmetrised), ``"radius"`` all within ``radius``.
    n_neighbors : int, default 5
        Neighbours per point with ``neighbors="knn"`` (the point itself not counted, as
        scikit-learn's ``n_neighbors``), at most ``n - 1``. Equidistant candidates are
        taken by lower index (scikit-learn's choice among them varies with its search
        and thread count: see :func:`algorithms.core.graphs.nearest_sorted`).
    radius : float, optional
        The radius with ``neighbors="radius"``, required there; every point needs at
        least one neighbour within it.
    regularization : float, default 1e-3
        ``r``: the local Gram matrix :math:`C` gets :math:`r \operatorname{tr}(C)` on its
        diagonal. Needed when ``n_neighbors > D`` (then :math:`C` is singular); 0 turns it
        off.
    quality_neighbors : int, default 5
        The neighbourhood size of the reported trustworthiness (clipped to
        ``(n - 1) // 2`` when larger).

    Returns
    -------
    LLEResult
        ``embedding``, ``eigenvalues``, ``reconstruction_error``, ``weight_error``,
        ``trustworthiness``.

    Raises
    ------
    InvalidInputError
        Bad ``points``; ``n_neighbors`` outside ``[1, n - 1]`` (fewer points than
        neighbours); ``n_components`` outside ``[1, min(D, n - 2)]``; ``neighbors="all"`` or
        unknown; ``radius`` missing or not positive; negative ``regularization``.
    DegenerateInputError
        A singular local Gram matrix with ``regularization=0``; a point without neighbours
        within ``radius``; a disconnected neighbourhood graph (the message says into how
        many components: each adds a zero eigenvalue).

    Notes
    -----
    **The weights.** The closed form :math:`w_a = \sum_b C^{-1}_{ab} / \sum_{bc}
    C^{-1}_{bc}` is the solution of :math:`C w = \mathbf 1` normalised to sum to 1;
    it is computed by a solve (no inverse). The weights sum to 1, as in the paper, not
    to the number of neighbours: a scale of the weights would scale :math:`W` and break
    :math:`(I - W)\mathbf 1 = 0`.

    **The matrix of the last step.** With :math:`L = I - W`, the embedding minimises
    :math:`\lVert L Y \rVert^2 = \operatorname{tr}(Y^\mathsf{T} L^\mathsf{T} L Y)`, so
    its matrix is :math:`M = L^\mathsf{T} L` (a squared operator, like a bilaplacian),
    not the symmetric part :math:`(L + L^\mathsf{T}) / 2` a graph-Laplacian reading of
    :math:`W` would suggest (:math:`W` is not symmetric). Only :math:`L^\mathsf{T} L`
    keeps the constant vector as an exact null vector: :math:`L \mathbf 1 = 0` because
    the rows of :math:`W` sum to 1, so :math:`L^\mathsf{T} L \mathbf 1 = 0`, whereas
    :math:`(L + L^\mathsf{T}) \mathbf 1 = (I - W^\mathsf{T}) \mathbf 1` vanishes only if
    the columns of :math:`W` sum to 1 too. This follows the paper and scikit-learn.

    The regularisation is scikit-learn's (always applied, scaled by the trace, so the
    results agree: with the same neighbours the embedding equals
    ``sklearn.manifold.LocallyLinearEmbedding(method="standard", eigen_solver="dense")``'s
    up to an orthogonal transform).

    Disconnected graphs are an error naming the component count; scikit-learn returns an
    embedding that only separates the components.

    Cost: a kd-tree, one batched ``k×k`` solve per point, then a dense ``eigh`` up to
    1,000 points, shift-invert Lanczos on the sparse :math:`M` above.

    References
    ----------
    .. [1] S. T. Roweis, L. K. Saul, "Nonlinear dimensionality reduction by locally linear
       embedding", Science 290 (2000).

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0, 1, 30)
    >>> line = np.c_[t, 2 * t, np.zeros(30)]
    >>> y = lle(line, n_components=1, n_neighbors=2).embedding[:, 0]
    >>> bool(np.all(np.diff(y) > 0) or np.all(np.diff(y) < 0))
    True
    """
    x, k = check_lle(points, n_components, neighbors, n_neighbors, radius)
    n = x.shape[0]
    reg = regularization
    tree = cKDTree(x)
    if neighbors == "knn":
        m = check_n_neighbors(n, n_neighbors)
        # the m + 1 nearest, ties by index, without the first (the point itself, or a
        # coincident point of lower index): scikit-learn's barycenter_kneighbors_graph
        _, idx = nearest_sorted(x, m + 1, tree=tree)
        nbrs: Any = np.ascontiguousarray(idx[:, 1:])
    else:
        if radius is None:
            raise InvalidInputError("Expected `radius` with neighbors='radius', got none.",
                                    field="radius")
        r = radius
        # x is 2-D: an object array of one list per point (the stubs also allow a list)
        lists = cast(NDArray[np.object_], tree.query_ball_point(x, r))
        nbrs = [np.array([j for j in lst if j != i], dtype=np.int64)
                for i, lst in enumerate(lists)]
        lonely = [i for i, a in enumerate(nbrs) if a.size == 0]
        if lonely:
            raise DegenerateInputError(
                f"Expected every point to have a neighbour within `radius` = {r:g}, got "
                f"{len(lonely)} without (the first at row {lonely[0]}).", field="radius")
    w = barycenter_weights(x, nbrs, reg)
    pattern = w.copy()
    pattern.data = np.ones_like(pattern.data)
    check_connected(((pattern + pattern.T) > 0).astype(np.float64), neighbors=neighbors,
                    method="locally linear embedding")
    i_w = (sp.eye_array(n, format="csr") - w).tocsr()
    mat = (i_w.T @ i_w).tocsr()
    vals, vecs = _smallest(mat, k + 1, float(mat.diagonal().max()))
    vals = np.maximum(vals[1:], 0.0)
    y = fix_signs(vecs[:, 1:])
    resid = x - w @ x
    return LLEResult(
        embedding=np.ascontiguousarray(y),
        eigenvalues=vals,
        reconstruction_error=float(vals.sum()),
        weight_error=float(np.einsum("ij,ij->", resid, resid)),
        trustworthiness=trustworthiness(x, y, n_neighbors=quality_neighbors),
    )
