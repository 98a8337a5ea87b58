r"""The self-organising map (Kohonen): a grid of nodes pulled onto the data, each point
embedded at the grid position of its best-matching node."""

from __future__ import annotations

import typing
from dataclasses import dataclass
from typing import Annotated, Any, Literal

import numpy as np
import scipy.linalg as la

from algorithms.core.errors import InvalidInputError
from algorithms.core.params import Ge, Gt, Interval, PointsLike, Seed, validate_params
from algorithms.core.progress import Progress, as_progress
from algorithms.core.types import FloatArray, IntArray
from algorithms.core.validation import as_points
from algorithms.embedding._quality import trustworthiness

__all__ = ["check_som", "SOMResult", "som", "check_grid", "Training", "Start", "INITS", "METHODS"]

Training = Literal["online", "batch"]
"""How a SOM is trained: Kohonen's rule one sample at a time, or the batch map."""
Start = Literal["pca", "random"]
"""Where the nodes start: on the plane of the two principal axes, or at random points."""
#: Accepted values of ``init`` and ``method``.
INITS: tuple[str, ...] = typing.get_args(Start)
METHODS: tuple[str, ...] = typing.get_args(Training)


@dataclass(frozen=True, eq=False)
class SOMResult:
    """The trained map and where each point lands on it.

    Attributes
    ----------
    embedding : (n, 2) float array
        The grid position (row, column) of each point's best-matching node.
    codebook : (rows * columns, d) float array
        The position of each node in data space, row-major over the grid.
    bmu : (n,) int array
        The index of each point's best-matching (nearest) node, row-major.
    quantization_error : float
        The mean distance from each point to its best-matching node.
    topographic_error : float
        The fraction of points whose two nearest nodes are not grid neighbours
        (8-neighbourhood, diagonals included, as MiniSom); 0 for a map that folds nowhere.
    trustworthiness : float
        How well the embedding keeps each point's 5 nearest neighbours (1 is perfect;
        ``sklearn.manifold.trustworthiness``; points on one node tie).
    iterations : int
        Training steps: samples presented (online) or epochs (batch).
    """

    embedding: FloatArray
    codebook: FloatArray
    bmu: IntArray
    quantization_error: float
    topographic_error: float
    trustworthiness: float
    iterations: int


def check_som(points: Any, rows: int, columns: int) -> FloatArray:
    """Check the inputs of :func:`som`: at least 2 points and a grid of at least 2 nodes
    (:func:`check_grid`). Returns the points."""
    x = as_points(points, name="points", min_points=2)
    check_grid(rows, columns)
    return x


@validate_params
def som(
    points: PointsLike,
    *,
    rows: Annotated[int, Ge(1)] = 10,
    columns: Annotated[int, Ge(1)] = 10,
    method: Training = "online",
    max_iterations: Annotated[int, Ge(1)] | None = None,
    learning_rate: Annotated[float, Interval(gt=0, le=1)] = 0.5,
    sigma: Annotated[float, Gt(0)] | None = None,
    init: Start = "pca",
    seed: Seed = 0,
    progress: Progress | None = None,
) -> SOMResult:
    r"""Self-organising map.

    A rows × columns grid of nodes pulled onto the data (Kohonen's online rule or the batch map);
    each point is embedded at its best-matching node's grid position. Reports the codebook,
    quantization and topographic errors and trustworthiness. Progress per 1 % of the steps,
    cancellable.

    Each node :math:`j` has a grid position :math:`g_j` and a data-space position
    :math:`w_j`. Online training (Kohonen) presents one point :math:`x` at step :math:`t`,
    finds its best-matching node :math:`b = \arg\min_j \lVert x - w_j \rVert` and pulls
    every node towards it, grid neighbours of :math:`b` the most:

    .. math:: w_j \leftarrow w_j + \eta(t)\, h_{bj}(t)\, (x - w_j), \qquad
              h_{bj}(t) = e^{-\lVert g_b - g_j \rVert^2 / 2\sigma(t)^2},

    with :math:`\eta(t) = \eta_0 / (1 + 2t/T)` and :math:`\sigma(t) = \sigma_0 / (1 +
    2t/T)` (MiniSom's default decay). Batch training replaces each epoch of such steps by
    their fixed point, :math:`w_j = \sum_i h_{b_i j} x_i / \sum_i h_{b_i j}`, with
    :math:`\sigma` decaying from :math:`\sigma_0` to 1 over the epochs.

    Parameters
    ----------
    points : (n, d) float array
        The points to map, one row per point; at least 2 points.
    rows, columns : int, default 10
        The number of grid rows and columns; at least 1 each and 2 nodes in all.
    method : {"online", "batch"}, default "online"
        ``"online"``: Kohonen's rule, one randomly drawn point per step (a stochastic
        gradient step); ``"batch"``: each epoch moves every node to the fixed point of
        an epoch of such steps, the neighbourhood-weighted mean of the points.
    max_iterations : int, optional
        Training steps: samples presented with ``"online"`` (``max(1000, 10 n)`` up to
        100,000 when omitted) or epochs with ``"batch"`` (30 when omitted).
    learning_rate : float, default 0.5
        :math:`\eta_0`, the starting step of online training, in ``(0, 1]`` (unused by
        ``"batch"``).
    sigma : float, optional
        :math:`\sigma_0`, the neighbourhood's starting width in grid units; half the
        larger grid side (at least 1) when omitted.
    init : {"pca", "random"}, default "pca"
        Starting nodes: ``"pca"`` spread over the plane of the two principal axes (one
        standard deviation per half side), ``"random"`` at random data points drawn with
        ``seed``.
    seed : int or numpy Generator, default 0
        Draws the order of the samples (online) and the random start; the same seed gives
        the same map.
    progress : callable, optional
        ``progress(done, total, message)`` every 1 % of the steps (online) or each epoch
        (batch); may raise :class:`~algorithms.core.errors.Cancelled`.

    Returns
    -------
    SOMResult
        ``embedding``, ``codebook``, ``bmu``, ``quantization_error``,
        ``topographic_error``, ``trustworthiness``, ``iterations``.

    Raises
    ------
    InvalidInputError
        Bad ``points`` (fewer than 2); a grid of fewer than 2 nodes; ``learning_rate``
        outside ``(0, 1]``; a non-positive ``sigma``; an unknown option.
    Cancelled
        Raised by ``progress``.

    Notes
    -----
    The SOM is less an embedding than an alignment: a low-dimensional quadrilateral grid
    is aligned to high-dimensional data whose correspondence to the grid is unknown, so
    every step re-assigns nearest nodes, and a gradient step moves the nearest node
    together with its grid neighbours. That is the online rule above; the embedding is
    then read off the grid.

    References
    ----------
    .. [1] T. Kohonen, "Self-organized formation of topologically correct feature maps",
       Biological Cybernetics 43, 1982.
    .. [2] T. Kohonen, *Self-Organizing Maps*, 3rd ed., Springer 2001 (batch map, §3.14).
    .. [3] G. Vettigli, MiniSom, https://github.com/JustGlowing/minisom.

    Examples
    --------
    >>> pts = [[0.0, 0.0], [0.1, 0.0], [5.0, 5.0], [5.1, 5.0]]
    >>> res = som(pts, rows=1, columns=2, method="batch")
    >>> res.bmu.tolist()
    [0, 0, 1, 1]
    """
    report = as_progress(progress)
    x = check_som(points, rows, columns)
    n, d = x.shape
    r, c = rows, columns
    eta0 = learning_rate
    s0 = max(1.0, max(r, c) / 2.0) if sigma is None else sigma
    if max_iterations is None:
        steps = min(100_000, max(1000, 10 * n)) if method == "online" else 30
    else:
        steps = max_iterations
    rng = np.random.default_rng(seed)
    grid = np.stack(np.meshgrid(np.arange(r, dtype=np.float64),
                                np.arange(c, dtype=np.float64), indexing="ij"), -1).reshape(-1, 2)
    w = _initial(x, grid, r, c, init, rng)
    grid_sq = ((grid[:, None, :] - grid[None, :, :]) ** 2).sum(-1)     # (m, m)

    if method == "online":
        order = rng.integers(n, size=steps)
        every = max(1, steps // 100)
        for t in range(steps):
            xi = x[order[t]]
            diff = xi - w
            best = int(np.argmin(np.einsum("ij,ij->i", diff, diff)))
            decay = 1.0 + 2.0 * t / steps
            s = s0 / decay
            h = np.exp(-grid_sq[best] / (2.0 * s * s)) * (eta0 / decay)
            w += h[:, None] * diff
            if (t + 1) % every == 0 or t + 1 == steps:
                report(t + 1, steps, f"{t + 1} samples")
    else:
        for t in range(steps):
            s = s0 * (1.0 / s0) ** (t / max(steps - 1, 1))
            nearest = _bmu(x, w)[0]
            h = np.exp(-grid_sq[nearest] / (2.0 * s * s))            # (n, m)
            mass = h.sum(axis=0)
            new = h.T @ x
            hit = mass > 1e-300
            w[hit] = new[hit] / mass[hit, None]
            report(t + 1, steps, f"epoch {t + 1}, σ {s:.3g}")
    b, first, second = _bmu(x, w)
    emb = grid[b]
    gap = np.abs(grid[first] - grid[second]).max(axis=1)
    return SOMResult(
        embedding=np.ascontiguousarray(emb),
        codebook=np.ascontiguousarray(w),
        bmu=b.astype(np.int64),
        quantization_error=float(np.mean(np.linalg.norm(x - w[b], axis=1))),
        topographic_error=float(np.mean(gap > 1)),
        trustworthiness=trustworthiness(x, emb),
        iterations=steps,
    )


def check_grid(rows: int, columns: int) -> None:
    """Raise unless a ``rows × columns`` grid has at least 2 nodes (one node maps every
    point to one place)."""
    if rows * columns < 2:
        raise InvalidInputError(f"Expected a grid of at least 2 nodes, got rows={rows} and "
                                f"columns={columns}.", field="rows")


def _initial(x: FloatArray, grid: FloatArray, r: int, c: int, init: str,
             rng: np.random.Generator) -> FloatArray:
    m: int = grid.shape[0]
    if init == "random":
        return x[rng.integers(x.shape[0], size=m)].copy()
    mean: FloatArray = x.mean(axis=0)
    _, s, vt = la.svd(x - mean, full_matrices=False, check_finite=False)
    sd = s / np.sqrt(max(x.shape[0] - 1, 1))
    axes = np.zeros((2, x.shape[1]))
    for i in range(min(2, vt.shape[0])):
        v = vt[i]
        v = v * (1.0 if v[np.argmax(np.abs(v))] >= 0 else -1.0)  # deterministic sign
        axes[i] = sd[i] * v
    u = (grid[:, 0] / max(r - 1, 1)) * 2.0 - 1.0 if r > 1 else np.zeros(m)
    v = (grid[:, 1] / max(c - 1, 1)) * 2.0 - 1.0 if c > 1 else np.zeros(m)
    # the longer grid side follows the first principal axis
    first, second = (u, v) if r >= c else (v, u)
    start: FloatArray = mean + first[:, None] * axes[0] + second[:, None] * axes[1]
    return start


def _bmu(x: FloatArray, w: FloatArray) -> tuple[IntArray, IntArray, IntArray]:
    """Each point's nearest node, and its two nearest (for the topographic error)."""
    d = (np.einsum("ij,ij->i", x, x)[:, None] - 2.0 * x @ w.T
         + np.einsum("ij,ij->i", w, w)[None, :])
    if w.shape[0] >= 2:
        two = np.argpartition(d, 1, axis=1)[:, :2]
        pick = np.take_along_axis(d, two, axis=1)
        swap = pick[:, 1] < pick[:, 0]
        two[swap] = two[swap][:, ::-1]
        first, second = two[:, 0], two[:, 1]
    else:
        first = second = np.zeros(x.shape[0], dtype=np.int64)
    b = np.argmin(d, axis=1)
    return b, first, second
