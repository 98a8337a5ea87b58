r"""Neighbourhood components analysis: the linear map under which a stochastic nearest
neighbour classifier is most often right."""

from __future__ import annotations

import typing
from dataclasses import dataclass
from typing import Annotated, Any, Literal, cast

import numpy as np
import scipy.linalg as la
from scipy.optimize import minimize

from algorithms.classification._common import check_labelled, fix_signs
from algorithms.core.errors import ConvergenceWarning, DegenerateInputError, InvalidInputError, warn
from algorithms.core.params import Ge, LabelsLike, PointsLike, Seed, validate_params
from algorithms.core.progress import Progress, as_progress
from algorithms.core.types import FloatArray, IntArray, IntpArray, KnnQuery, RngLike
from algorithms.core.validation import as_int
from algorithms.embedding import trustworthiness

__all__ = ["NCAResult", "nca", "check_nca", "Init", "INITS", "MAX_POINTS"]

Init = Literal["auto", "pca", "lda", "identity", "random"]
"""NCA's starting map: chosen by the sizes, PCA, LDA, the identity, or random."""
#: Accepted values of ``init``.
INITS: tuple[str, ...] = typing.get_args(Init)
#: Most points (the method holds dense n×n matrices).
MAX_POINTS = 20_000


@dataclass(frozen=True, eq=False)
class NCAResult:
    """The learned linear map, the embedded points, and how the optimisation went.

    Attributes
    ----------
    embedding : (n, k) float array
        The points mapped by ``transform``: ``points @ transform.T``.
    transform : (k, d) float array
        The learned linear map :math:`A`.
    objective : float
        The expected number of points the stochastic neighbour rule classifies correctly,
        :math:`\\sum_i p_i` (at most ``n``).
    accuracy : float
        Leave-one-out accuracy of the 1-nearest-neighbour rule in the embedding.
    query_embedding : (m, k) float array
        ``query @ transform.T``; ``(0, k)`` without a query.
    query_predictions : (m,) list
        The label of each query point's nearest embedded training point; empty without a
        query.
    trustworthiness : float
        How well the embedding keeps each point's 5 nearest neighbours (1 is perfect;
        ``sklearn.manifold.trustworthiness``).
    iterations : int
        Iterations of the optimiser (L-BFGS).
    converged : bool
        False when ``max_iterations`` ran out first (a ``ConvergenceWarning`` is issued).
    """

    embedding: FloatArray
    transform: FloatArray
    objective: float
    accuracy: float
    query_embedding: FloatArray
    query_predictions: list[Any]
    trustworthiness: float
    iterations: int
    converged: bool


def check_nca(points: Any, labels: Any, n_components: Any = None, query: Any = None
              ) -> tuple[FloatArray, np.ndarray, IntArray, int, FloatArray | None]:
    """Check the inputs of :func:`nca`: labelled points (:func:`check_labelled`), at most
    :data:`MAX_POINTS`, and ``n_components`` at most their dimension. Returns the points,
    classes, class indices, the number of components and the query."""
    x, classes, y, q = check_labelled(points, labels, query, max_points=MAX_POINTS)
    d = x.shape[1]
    k = d if n_components is None else as_int(
        n_components, name="n_components", minimum=1, maximum=d,
        reason="the dimension of `points`")
    return x, classes, y, k, q


@validate_params
def nca(
    points: PointsLike,
    labels: LabelsLike,
    *,
    n_components: Annotated[int, Ge(1)] | None = None,
    init: Init = "auto",
    max_iterations: Annotated[int, Ge(1)] = 50,
    tolerance: Annotated[float, Ge(0)] = 1e-5,
    query: PointsLike | None = None,
    seed: Seed = 0,
    progress: Progress | None = None,
) -> NCAResult:
    r"""Neighbourhood components analysis.

    The linear map maximising the expected number of points whose stochastic nearest neighbour
    (softmax over squared distances) has their class, by L-BFGS as scikit-learn. Reports the map,
    the embedding, leave-one-out 1-NN accuracy, query predictions and trustworthiness. Progress per
    iteration, cancellable.

    With :math:`z_i = A x_i`, each point picks a neighbour at random with probability

    .. math:: p_{ij} = \frac{e^{-\lVert z_i - z_j \rVert^2}}
              {\sum_{l \ne i} e^{-\lVert z_i - z_l \rVert^2}}, \qquad p_{ii} = 0,

    and NCA maximises the expected number of points that pick one of their own class,
    :math:`f(A) = \sum_i \sum_{j \in C_i} p_{ij}`, with gradient

    .. math:: \frac{\partial f}{\partial A} = 2A \sum_i \Big(p_i \sum_k p_{ik}
              x_{ik} x_{ik}^\mathsf{T} - \sum_{j \in C_i} p_{ij} x_{ij} x_{ij}^\mathsf{T}\Big),
              \quad x_{ij} = x_i - x_j,

    by L-BFGS (scipy), as scikit-learn's ``NeighborhoodComponentsAnalysis`` does (same
    defaults, same initialisations, the same objective). Each gradient costs
    :math:`O(n^2 (d + k))` with dense ``n×n`` matrices.

    Parameters
    ----------
    points : (n, d) float array
        The training points, one row per point; at least 3 and at most 20,000 points (the
        method holds dense ``n×n`` matrices).
    labels : (n,) int or str array
        The class of each point (integers or strings); at least 2 classes.
    n_components : int, optional
        The output dimension ``k``, ``1 <= k <= d``; ``d`` when omitted.
    init : {"auto", "pca", "lda", "identity", "random"}, default "auto"
        The starting map: ``"pca"`` the ``k`` principal axes, ``"lda"`` the discriminant
        directions (needs ``k <= min(d, c - 1)`` for ``c`` classes; when the classes
        differ only along directions in which they are flat, PCA starts instead),
        ``"identity"`` the first ``k`` coordinates, ``"random"`` a standard normal
        ``k×d`` matrix drawn with ``seed``; ``"auto"`` is LDA when ``k <= min(d, c - 1)``,
        else PCA when ``k < d``, else the identity (scikit-learn's rule).
    max_iterations : int, default 50
        Most L-BFGS iterations (``converged`` is False when they run out).
    tolerance : float, default 1e-5
        L-BFGS stops when the relative decrease of the objective, or the largest gradient
        entry, falls below this (scipy's ``tol``, as scikit-learn passes it).
    query : (m, d) float array, optional
        Points to embed and classify (1-nearest neighbour in the embedding); none when
        omitted (the query outputs are then empty).
    seed : int or numpy Generator, default 0
        Draws the start of ``init="random"`` (unused otherwise); the same seed gives the
        same map.
    progress : callable, optional
        ``progress(iteration, max_iterations, message)`` after each iteration; may raise
        :class:`~algorithms.core.errors.Cancelled`.

    Returns
    -------
    NCAResult
        ``embedding``, ``transform``, ``objective``, ``accuracy``, ``query_embedding``,
        ``query_predictions``, ``trustworthiness``, ``iterations``, ``converged``.

    Raises
    ------
    InvalidInputError
        Bad ``points``; more than ``MAX_POINTS`` points; ``labels`` not one per point or
        fewer than 2 classes; ``n_components`` above ``d``; ``query`` of another
        dimension; an unknown ``init``.
    Cancelled
        Raised by ``progress``.

    Notes
    -----
    NCA is stochastic neighbour embedding's idea applied to classes: a linear map making
    the pairwise distances of same-class points small, with each row of the distance
    matrix turned into probabilities — the softmax rows :math:`p_{i\cdot}` above sum to
    one. The objective of Goldberger et al. is the sum of same-class probabilities, not
    of distances: large distances get probability near zero rather than a large penalty,
    so a class may stay spread over several groups.

    References
    ----------
    .. [1] J. Goldberger, S. Roweis, G. Hinton, R. Salakhutdinov, "Neighbourhood
       components analysis", NIPS 2004.

    Examples
    --------
    >>> pts = [[0, 0], [0, 3], [0.2, 0.1], [0.2, 3.1], [0.4, -0.1], [0.4, 2.9]]
    >>> res = nca(pts, [0, 1, 0, 1, 0, 1], n_components=1)
    >>> res.accuracy, res.transform.shape
    (1.0, (1, 2))
    """
    report = as_progress(progress)
    x, classes, y, k, q = check_nca(points, labels, n_components, query)
    n, d = x.shape
    c = classes.shape[0]
    iters, tol = max_iterations, tolerance

    a0 = _initial(x, y, k, c, init, seed)
    same = y[:, None] == y[None, :]
    state = {"it": 0, "f": np.nan}

    def fun(flat: FloatArray) -> tuple[float, FloatArray]:
        a = flat.reshape(k, d)
        z = x @ a.T
        sq = np.einsum("ij,ij->i", z, z)
        dist = np.maximum(sq[:, None] - 2.0 * z @ z.T + sq[None, :], 0.0)
        np.fill_diagonal(dist, np.inf)
        dist -= dist.min(axis=1, keepdims=True)   # softmax without overflow
        p = np.exp(-dist)
        p /= p.sum(axis=1, keepdims=True)
        pm = np.where(same, p, 0.0)
        pi = pm.sum(axis=1)
        f = float(pi.sum())
        wgt = pm - p * pi[:, None]
        wgt = wgt + wgt.T
        np.fill_diagonal(wgt, -wgt.sum(axis=0))
        grad = 2.0 * (z.T @ wgt) @ x
        state["f"] = f
        return -f, -grad.ravel()

    def callback(xk: FloatArray) -> None:  # `xk`: the name in scipy's callback protocol
        state["it"] += 1
        report(state["it"], iters, f"objective {state['f']:.6g} of {n}")

    res = minimize(fun, a0.ravel(), jac=True, method="L-BFGS-B", callback=callback, tol=tol,
                   options={"maxiter": iters})
    a = res.x.reshape(k, d)
    # deterministic signs: each output coordinate's largest projection positive
    emb = x @ a.T
    big = np.argmax(np.abs(emb), axis=0)
    sign = np.where(emb[big, np.arange(k)] < 0, -1.0, 1.0)
    a = a * sign[:, None]
    emb = emb * sign
    converged = res.status == 0  # 1: iteration limit
    if not converged:
        warn(f"NCA stopped after {int(res.nit)} iterations before the objective "
             f"changed by less than {tol:g}.", ConvergenceWarning)
    objective = -float(res.fun)
    nearest = _nearest(emb, emb, exclude_self=True)
    if q is not None:
        q_emb = q @ a.T
        q_pred = classes[y[_nearest(q_emb, emb, exclude_self=False)]].tolist()
    else:
        q_emb = np.zeros((0, k))
        q_pred = []
    return NCAResult(
        embedding=np.ascontiguousarray(emb),
        transform=np.ascontiguousarray(a),
        objective=objective,
        accuracy=float(np.mean(y[nearest] == y)),
        query_embedding=np.ascontiguousarray(q_emb),
        query_predictions=q_pred,
        trustworthiness=trustworthiness(x, emb),
        iterations=int(res.nit),
        converged=converged,
    )


def _initial(x: FloatArray, y: IntArray, k: int, c: int, init: str, seed: RngLike
             ) -> FloatArray:
    n, d = x.shape
    if init == "auto":
        init = "lda" if k <= min(d, c - 1) else ("pca" if k < d else "identity")
    if init == "identity":
        return np.eye(k, d)
    if init == "random":
        return np.random.default_rng(seed).standard_normal((k, d))
    if init == "pca":
        _, _, vt = la.svd(x - x.mean(axis=0), full_matrices=False, check_finite=False)
        out = np.zeros((k, d))
        out[:min(k, vt.shape[0])] = vt[:k]
        return fix_signs(out.T).T
    from algorithms.classification.lda import lda  # "lda"

    if k > min(d, c - 1):
        raise InvalidInputError(
            f"Expected `n_components` to be at most min(classes - 1, dimension) = "
            f"{min(d, c - 1)} with init='lda', got {k}.", field="n_components")
    try:
        return lda(x, y, n_components=k).scalings.T
    except DegenerateInputError:  # the classes differ only where they are flat
        return _initial(x, y, k, c, "pca" if k < d else "identity", seed)


def _nearest(a: FloatArray, b: FloatArray, *, exclude_self: bool) -> IntpArray:
    from scipy.spatial import cKDTree

    tree = cKDTree(b)
    if exclude_self:
        _, idx = cast(KnnQuery, tree.query(a, k=2))
        own = idx[:, 0] == np.arange(a.shape[0])
        return np.where(own, idx[:, 1], idx[:, 0])
    _, idx = cast(KnnQuery, tree.query(a, k=1))
    return np.asarray(idx)
