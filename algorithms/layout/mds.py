r"""Classical multidimensional scaling, from a full or a partial distance matrix."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Annotated, cast

import numpy as np
import scipy.linalg as la
from scipy.sparse.linalg import eigsh
from scipy.spatial.distance import cdist

from algorithms.core.errors import ConvergenceWarning, warn
from algorithms.core.params import ArrayInput, Ge, GraphLike, validate_params
from algorithms.core.threads import single_blas_thread
from algorithms.core.types import FloatArray, IntArray
from algorithms.core.validation import as_int
from algorithms.layout._inputs import check_n_components, resolve_distances

__all__ = ["MDSResult", "mds", "classical_coordinates", "complete_squared_distances",
           "raw_stress"]

#: Below this many points the truncations and the final eigenproblem use a full dense
#: eigendecomposition; above, a warm-started subspace iteration and Lanczos (ARPACK).
_DENSE_EIGH_BELOW = 400


@dataclass(frozen=True, eq=False)
class MDSResult:
    """Coordinates whose pairwise distances best reproduce the given ones (classical MDS).

    Attributes
    ----------
    positions : (n, k) float array
        One row per point, centred at the origin; column ``c`` is the ``c``-th principal
        coordinate (decreasing eigenvalue), each column's largest entry in absolute value
        positive (scikit-learn's sign convention).
    eigenvalues : (k,) float array
        The ``k`` largest eigenvalues of the double-centred squared distances
        :math:`-\\tfrac12 J D^{(2)} J`, in decreasing order; a non-positive one means the
        distances do not span ``k`` dimensions (its column is zero).
    stress : float
        The raw stress over the known pairs, :math:`\\sum_{i<j} (\\lVert x_i - x_j \\rVert -
        d_{ij})^2`.
    normalized_stress : float
        :math:`\\sqrt{\\text{stress} / \\sum_{i<j} d_{ij}^2}` over the known pairs: 0 for a
        perfect fit.
    missing_pairs : int
        How many pairs ``i < j`` had no known distance and were completed.
    completion_iterations : int
        Iterations of the completion after its one-shot start (0 when nothing was missing).
    converged : bool
        False when the completion stopped at ``max_iterations`` before ``tolerance`` (a
        :class:`ConvergenceWarning` is issued); True when nothing was missing.
    """

    positions: FloatArray
    eigenvalues: FloatArray
    stress: float
    normalized_stress: float
    missing_pairs: int
    completion_iterations: int
    converged: bool


@validate_params
def mds(
    distances: ArrayInput | None = None,
    *,
    distance_pairs: ArrayInput | None = None,
    n_points: Annotated[int, Ge(2)] | None = None,
    graph: GraphLike | None = None,
    n_components: Annotated[int, Ge(1)] = 2,
    rank: Annotated[int, Ge(1)] | None = None,
    max_iterations: Annotated[int, Ge(0)] = 500,
    tolerance: Annotated[float, Ge(0)] = 1e-7,
) -> MDSResult:
    r"""Classical multidimensional scaling (with completion of missing distances).

    Coordinates from the top eigenvectors of the double-centred squared distances −½JD⁽²⁾J. Missing
    distances are completed first: rank-(k+2) truncation of the squared distances (Drineas et al.'s
    one-shot estimate), refined by alternating projections. Reports the stress over the known pairs.

    With the squared distances :math:`D^{(2)} = D \odot D` and the centring matrix
    :math:`J = I - \tfrac1n \mathbf 1 \mathbf 1^\mathsf{T}`, points :math:`X` with those
    distances satisfy :math:`X X^\mathsf{T} = -\tfrac12 J D^{(2)} J`. Its ``k`` largest
    eigenpairs :math:`(\lambda_c, e_c)` give :math:`X = [\sqrt{\lambda_1} e_1, \dots,
    \sqrt{\lambda_k} e_k]`, the best rank-``k`` fit of the centred Gram matrix.

    **Completion** (Drineas, Javed, Magdon-Ismail, Pandurangan, Virrankoski and Savvides
    2006). Squared Euclidean distances of points in :math:`\mathbb R^k` form a matrix of
    rank at most :math:`k + 2`. Missing entries are set to zero and the known
    off-diagonal ones divided by the fraction ``p`` of known pairs (an unbiased estimate
    of the full matrix), and the result is truncated to rank ``r = rank`` (default
    ``k + 2``): that is the paper's one-shot estimate. It is then refined by alternating
    projections: the missing entries are replaced by the current estimate, the known ones
    (and the zero diagonal) restored, and the matrix truncated to rank ``r`` again, until
    the missing entries change by less than ``tolerance`` (relative) or
    ``max_iterations`` is reached; ``max_iterations=0`` keeps the one-shot estimate.
    Completed squared distances are clipped at zero.

    The truncation keeps the eigenpairs a squared-distance matrix has: its largest
    (positive) eigenvalue and its ``r - 1`` most negative ones (Schoenberg: a Euclidean
    squared-distance matrix is negative semidefinite on the vectors summing to zero, so it
    has exactly one positive eigenvalue).

    Parameters
    ----------
    distances : (n, n) array_like, optional
        Pairwise distances, non-negative, the diagonal zero; NaN (``null`` in JSON) marks
        a missing entry. Symmetric where ``d_ij`` and ``d_ji`` are both known (to a
        relative 1e-5, as scikit-learn's MDS checks; an asymmetric matrix is refused);
        where one is known it stands for both. Exactly one of ``distances``,
        ``distance_pairs`` and ``graph``.
    distance_pairs : (m, 3) array_like, optional
        Instead of ``distances``: the known distances as rows ``(i, j, d)``, points ``i``
        and ``j`` (0-based) ``d`` apart; every other pair is missing. A pair listed twice
        (either order) must give one distance.
    n_points : int, optional
        With ``distance_pairs``: the number of points (default: the largest index + 1).
    graph : Graph or mapping, optional
        Instead of ``distances``: a connected graph whose shortest-path lengths are the
        distances (``graph.weights`` are edge lengths, default 1).
    n_components : int, default 2
        The dimension ``k`` of the layout, at most the number of points.
    rank : int, optional
        The rank of the completed squared-distance matrix, from ``n_components`` to the
        number of points; default ``n_components + 2``. Only used when entries are
        missing.
    max_iterations : int, default 500
        Refinement iterations of the completion after its one-shot estimate; 0 keeps the
        one-shot estimate of Drineas et al.
    tolerance : float, default 1e-7
        The completion stops when the missing squared distances change by less than this,
        relative to their size.

    Returns
    -------
    MDSResult
        ``positions``, ``eigenvalues``, ``stress``, ``normalized_stress``,
        ``missing_pairs``, ``completion_iterations``, ``converged``.

    Raises
    ------
    InvalidInputError
        Not exactly one of ``distances``, ``distance_pairs``, ``graph``; a matrix that is
        not square, a negative, infinite or (in ``distance_pairs``) NaN distance, a
        non-zero diagonal; indices out of range; ``n_components`` not in ``[1, n]``;
        ``rank`` not in ``[n_components, n]``; more than 4,000 points.
    DegenerateInputError
        A point with no known distance, or known distances that split the points into
        unrelated groups; a disconnected graph.

    Notes
    -----
    **The truncation: rank k + 2, with the inertia of a distance matrix.** A truncation
    by SVD to "the ``k`` largest singular values", then symmetrised,
    :math:`\tilde D = \tfrac12 (D_k + D_k^\mathsf{T})`, is wrong in two ways. The rank
    must be ``k + 2``, not ``k``: an exact ``k``-dimensional squared-distance matrix has
    rank ``k + 2``, and truncating it to rank ``k`` changes even the known entries. And
    the ``r`` eigenpairs kept must be those a squared-distance matrix has (the largest
    and the ``r - 1`` most negative), not the ``r`` of largest magnitude that the SVD
    keeps: with the latter the refinement stalled far from the answer in about half of
    the trials here (2-D points, 30-60 % of pairs known), with the inertia kept it
    converged. The input is symmetrised first, so every truncation is symmetric (an
    eigendecomposition) and needs no symmetrisation after it. The one-shot estimate alone
    is poor unless most pairs are known (normalized stress 0.1-0.4 with half of the pairs
    missing); the refinement is not in the paper.

    **When completion fails.** The rank condition constrains the missing entries only when
    ``n`` is well above ``r`` and every point keeps several known distances: with 2-D
    points it recovered them (to 1e-6) in every trial with 50 or 150 points and half or
    30 % of the pairs known, but in only 5-40 % of the trials with 5 to 20 points (10-50 %
    missing), where the refinement settles on a low-rank completion that is no planar
    layout. The reported ``stress`` over the known pairs shows it;
    :func:`~algorithms.layout.stress` then minimises that stress directly (from a wrong
    start it too may stop in a local minimum).

    Classical MDS minimises the *strain* :math:`\lVert X X^\mathsf{T} + \tfrac12 J D^{(2)}
    J \rVert_F`, not the stress; :func:`~algorithms.layout.stress` minimises the stress and
    starts from this layout.

    Cost: :math:`O(n^2)` memory; the eigenproblem is a Lanczos iteration on the dense
    matrix above 400 points (a full ``eigh`` below); each completion iteration costs two
    products of the ``n×n`` matrix with ``2r + 4`` vectors (a warm-started subspace
    iteration with Rayleigh-Ritz; a full eigendecomposition for small ``n``), run with one
    BLAS thread (memory-bound products).

    References
    ----------
    .. [1] W. S. Torgerson, "Multidimensional scaling: I. Theory and method",
       Psychometrika 17 (1952).
    .. [2] P. Drineas, A. Javed, M. Magdon-Ismail, G. Pandurangan, R. Virrankoski,
       A. Savvides, "Distance matrix reconstruction from incomplete distance information
       for sensor network localization", IEEE SECON (2006).

    Examples
    --------
    >>> import numpy as np
    >>> from algorithms.layout import mds
    >>> d = [[0, 3, 4], [3, 0, 5], [4, 5, 0]]          # a 3-4-5 right triangle
    >>> res = mds(d)
    >>> x = res.positions
    >>> np.round([np.linalg.norm(x[0] - x[1]), np.linalg.norm(x[0] - x[2]),
    ...           np.linalg.norm(x[1] - x[2])], 10).tolist()
    [3.0, 4.0, 5.0]
    """
    d, name = resolve_distances(distances, distance_pairs, n_points, graph)
    n = d.shape[0]
    k = check_n_components(n_components, n)
    r = k + 2 if rank is None else as_int(rank, name="rank", minimum=k, maximum=n,
                                          reason="from n_components to the number of points")
    r = min(r, n)

    with single_blas_thread():
        squared, used, converged = complete_squared_distances(d, r, max_iterations, tolerance)
    missing = int(np.count_nonzero(np.isnan(np.triu(d, 1))))
    if not converged:
        warn(f"The distance completion stopped after {used} iterations before "
             f"reaching tolerance {tolerance:g}.", ConvergenceWarning)
    x, eigenvalues = classical_coordinates(squared, k)
    stress_value, total = raw_stress(x, d)
    return MDSResult(
        positions=x,
        eigenvalues=eigenvalues,
        stress=stress_value,
        normalized_stress=math.sqrt(stress_value / total) if total > 0 else 0.0,
        missing_pairs=missing,
        completion_iterations=used,
        converged=converged,
    )


def raw_stress(x: FloatArray, d: FloatArray) -> tuple[float, float]:
    """``sum over known pairs i<j of (|x_i - x_j| - d_ij)^2`` and ``sum of d_ij^2`` (NaN in
    ``d`` marks unknown pairs)."""
    known = ~np.isnan(d)
    diff = np.where(known, cdist(x, x) - np.where(known, d, 0.0), 0.0)
    dd = np.where(known, d, 0.0)
    return 0.5 * float(np.vdot(diff, diff)), 0.5 * float(np.vdot(dd, dd))


def classical_coordinates(squared: FloatArray, k: int) -> tuple[FloatArray, FloatArray]:
    """Classical MDS of a full symmetric matrix of squared distances.

    Returns the ``(n, k)`` coordinates (scikit-learn's sign convention: each column's entry
    of largest magnitude positive) and the ``k`` largest eigenvalues, decreasing.
    """
    n = squared.shape[0]
    row = squared.mean(axis=1)
    b = squared - row[:, None]
    b -= row[None, :]
    b += row.mean()
    b *= -0.5
    b = 0.5 * (b + b.T)
    if n <= _DENSE_EIGH_BELOW or k >= n // 2:
        w, u = la.eigh(b, subset_by_index=[n - k, n - 1])
    else:
        v0 = np.ones(n) / math.sqrt(n) + np.cos(np.arange(n))  # deterministic start
        w, u = eigsh(b, k=k, which="LA", v0=v0, tol=0.0)
    order = np.argsort(w)[::-1]
    w, u = w[order], u[:, order]
    biggest = np.argmax(np.abs(u), axis=0)
    signs = np.sign(u[biggest, np.arange(k)])
    signs[signs == 0] = 1.0
    u = u * signs
    x = u * np.sqrt(np.maximum(w, 0.0))
    return np.ascontiguousarray(x), w


def _edm_pick(w: FloatArray, r: int) -> IntArray:
    """Indices of the largest eigenvalue and the ``r - 1`` most negative ones."""
    order = np.argsort(w)
    return np.concatenate([order[-1:], order[: r - 1]])


def _truncate(f: FloatArray, r: int, basis: FloatArray | None, steps: int
              ) -> tuple[FloatArray, FloatArray]:
    """The rank-``r`` approximation of the symmetric ``f`` with the inertia of a squared
    distance matrix (its largest eigenpair and its ``r - 1`` most negative ones), and a
    basis to warm-start the next call.

    Small matrices take a full eigendecomposition; larger ones ``steps`` block power
    (subspace) iterations on ``2r + 4`` vectors from ``basis``, then Rayleigh-Ritz.
    """
    n = f.shape[0]
    width = 2 * r + 4
    if n <= 4 * width:
        w, u = la.eigh(f, check_finite=False)
        top = _edm_pick(w, r)
        ur = u[:, top]
        return (ur * w[top]) @ ur.T, u[:, :0]
    q = basis
    if q is None or q.shape[1] == 0:
        q = np.random.default_rng(0).standard_normal((n, width))
    for _ in range(steps):  # Q of float64 is float64 (the stubs say any floating)
        q = cast(FloatArray,
                 la.qr(f @ q, mode="economic", overwrite_a=True, check_finite=False)[0])
    t = q.T @ (f @ q)
    w, v = la.eigh(0.5 * (t + t.T), check_finite=False)  # Rayleigh-Ritz
    q = q @ v
    top = _edm_pick(w, r)
    ur = q[:, top]
    return (ur * w[top]) @ ur.T, q


def complete_squared_distances(d: FloatArray, rank: int, max_iterations: int,
                               tolerance: float) -> tuple[FloatArray, int, bool]:
    """Complete a symmetric distance matrix with NaN for unknown entries.

    Returns the full matrix of squared distances (known entries exact, completed ones
    clipped at zero), the refinement iterations used and whether they converged. See
    :func:`mds` for the method.
    """
    known = ~np.isnan(d)
    observed = np.where(known, d, 0.0)
    observed *= observed
    if known.all():
        return observed, 0, True
    n = d.shape[0]
    holes = np.flatnonzero(~known)
    p = (np.count_nonzero(known) - n) / (n * (n - 1))
    estimate, basis = _truncate(observed / p, rank, None, steps=8)  # Drineas et al.
    values = estimate.ravel()[holes]
    used, converged = 0, max_iterations == 0
    tiny = np.finfo(float).tiny
    for it in range(1, max_iterations + 1):
        filled = observed.copy()
        filled.ravel()[holes] = values
        estimate, basis = _truncate(filled, rank, basis, steps=1)
        new = estimate.ravel()[holes]
        change = float(np.linalg.norm(new - values))
        values, used = new, it
        if change <= tolerance * max(float(np.linalg.norm(new)), tiny):
            converged = True
            break
    out = observed.copy()
    out.ravel()[holes] = np.maximum(values, 0.0)
    out = 0.5 * (out + out.T)
    np.fill_diagonal(out, 0.0)
    return out, used, converged
