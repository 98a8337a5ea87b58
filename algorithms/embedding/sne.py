r"""Symmetric stochastic neighbour embedding (SNE): the Gaussian mixture in the embedding
that t-SNE replaces by a Student-t one; exact gradient over all pairs, so small inputs."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Annotated, Any

import numpy as np

from algorithms.core.errors import InvalidInputError
from algorithms.core.params import Ge, Gt, PointsLike, Seed, validate_params
from algorithms.core.progress import Progress, as_progress
from algorithms.core.threads import single_blas_thread
from algorithms.core.types import FloatArray
from algorithms.embedding._quality import fix_signs, trustworthiness
from algorithms.embedding.tsne import (
    _CELLS,
    LearningRate,
    Start,
    _descend,
    affinities,
    check_common,
    initial_embedding,
)

__all__ = ["check_sne", "SNEResult", "sne", "MAX_SNE_POINTS", "check_size"]

#: Most points: every step visits all pairs (O(n²) time; memory in blocks of rows).
MAX_SNE_POINTS = 5_000


@dataclass(frozen=True, eq=False)
class SNEResult:
    """A symmetric SNE embedding and how well it fits.

    Attributes
    ----------
    embedding : (n, k) float array
        One row per point, centred; each column's entry of largest magnitude positive.
    kl_divergence : float
        :math:`\\mathrm{KL}(P \\,\\|\\, Q)` of the final embedding (exact, all pairs).
    trustworthiness : float
        How well the embedding keeps each point's nearest neighbours (1 is perfect).
    iterations : int
        Gradient steps taken, early exaggeration included.
    """

    embedding: FloatArray
    kl_divergence: float
    trustworthiness: float
    iterations: int


def _sne_kl_gradient(p: FloatArray, y: FloatArray, exaggeration: float = 1.0,
                     want_kl: bool = True) -> tuple[float, FloatArray]:
    r"""KL(P‖Q) with Gaussian :math:`q_{ij} \propto e^{-\lVert y_i - y_j\rVert^2}` and its
    gradient :math:`4 \sum_j (\alpha p_{ij} - q_{ij}) (y_i - y_j)`, in blocks of rows."""
    n = y.shape[0]
    att = np.empty_like(y)
    rep = np.empty_like(y)
    z = 0.0
    pd2 = 0.0
    rows = max(1, _CELLS // max(n, 1))
    sq = np.einsum("ij,ij->i", y, y)
    for s in range(0, n, rows):
        r = slice(s, min(n, s + rows))
        yr = y[r]
        d2 = np.maximum(sq[r, None] - 2.0 * (yr @ y.T) + sq[None, :], 0.0)
        w = np.exp(-d2)
        idx = np.arange(r.start, r.stop)
        w[idx - r.start, idx] = 0.0
        z += float(w.sum())
        pr = p[r]
        if want_kl:
            pd2 += float((pr * d2).sum())
        att[r] = yr * pr.sum(axis=1)[:, None] - pr @ y
        rep[r] = yr * w.sum(axis=1)[:, None] - w @ y
    grad = 4.0 * (exaggeration * att - rep / z)
    if not want_kl:
        return float("nan"), grad
    v = p[p > 0]
    kl = float((v * np.log(v)).sum()) + pd2 + np.log(z)   # Σ p log p − Σ p log(w / Z)
    return kl, grad


def check_size(n: int) -> None:
    """Raise when ``n`` points are more than SNE's exact gradient takes."""
    if n > MAX_SNE_POINTS:
        raise InvalidInputError(f"Expected at most {MAX_SNE_POINTS:,} `points` for SNE (an "
                                f"exact O(n²) gradient), got {n:,}; use t-SNE (its fft "
                                f"gradient).", field="points")


def check_sne(points: Any, perplexity: float, learning_rate: float | str = "auto"
              ) -> tuple[FloatArray, float | None]:
    """Check the inputs of :func:`sne`: the data as t-SNE's ``check_common`` takes it, at
    most :data:`MAX_SNE_POINTS` points. Returns the points and the learning rate."""
    x, lr = check_common(points, perplexity=perplexity, learning_rate=learning_rate)
    check_size(x.shape[0])
    return x, lr


@validate_params
def sne(
    points: PointsLike,
    *,
    n_components: Annotated[int, Ge(1)] = 2,
    perplexity: Annotated[float, Gt(0)] = 30.0,
    init: Start = "pca",
    learning_rate: LearningRate = "auto",
    max_iterations: Annotated[int, Ge(1)] = 750,
    early_exaggeration: Annotated[float, Ge(1)] = 4.0,
    exaggeration_iterations: Annotated[int, Ge(0)] = 250,
    min_grad_norm: Annotated[float, Ge(0)] = 1e-7,
    seed: Seed = 0,
    quality_neighbors: Annotated[int, Ge(1)] = 5,
    progress: Progress | None = None,
) -> SNEResult:
    r"""Symmetric SNE (stochastic neighbour embedding).

    t-SNE's input affinities with a Gaussian kernel in the embedding too (the light tails crowd
    clusters together: t-SNE's motivation); exact all-pairs gradient, at most 5,000 points. Reports
    KL, trustworthiness and iterations. Progress every iteration, cancellable.

    The input affinities are t-SNE's (perplexity-calibrated Gaussians over all pairs,
    symmetrised, :math:`p_{ij} = (p_{j|i} + p_{i|j}) / 2n`); the embedding's are Gaussian
    too,

    .. math:: q_{ij} = \frac{e^{-\lVert y_i - y_j\rVert^2}}
                            {\sum_{k \ne l} e^{-\lVert y_k - y_l\rVert^2}}, \qquad
              \frac{\partial\, \mathrm{KL}(P\|Q)}{\partial y_i}
              = 4 \sum_j (p_{ij} - q_{ij})(y_i - y_j),

    minimised by the same descent as :func:`~algorithms.embedding.tsne.tsne` (momentum,
    gains, early exaggeration).

    Parameters
    ----------
    points : (n, D) float array
        The data, one row per point; at least 2 and at most 5,000 points.
    n_components : int, default 2
        The embedding's dimension ``k``.
    perplexity : float, default 30
        The effective number of neighbours of each point's Gaussian (its entropy is
        :math:`\log(\text{perplexity})`, found by binary search), ``0 < perplexity < n``.
    init : {"pca", "random"}, default "pca"
        The start: ``"pca"`` the PCA scores scaled to a first-column standard deviation
        of 1e-4, ``"random"`` Gaussian draws of that size from ``seed``.
    learning_rate : float or "auto", default "auto"
        The step, ``> 0``. ``"auto"``: :math:`\max(n / 4\alpha, 50)`, :math:`\alpha` the
        exaggeration in force (as t-SNE).
    max_iterations : int, default 750
        Gradient steps in all, the exaggeration phase included.
    early_exaggeration : float, default 4
        The factor :math:`\alpha \ge 1` on :math:`P` for the first
        ``exaggeration_iterations`` steps (4, the value of the t-SNE paper; the Gaussian
        kernel cannot hold clusters apart under t-SNE's 12).
    exaggeration_iterations : int, default 250
        The number of steps with :math:`P` multiplied by ``early_exaggeration``;
        counted in ``max_iterations``.
    min_grad_norm : float, default 1e-7
        After the exaggeration phase, stop once the gradient's norm falls below this.
    seed : int or numpy Generator, default 0
        Draws the random start (and the extra columns of a PCA start when ``k`` exceeds
        the data's dimension); the same seed gives the same embedding.
    quality_neighbors : int, default 5
        The neighbourhood size of the reported trustworthiness (clipped to
        ``(n - 1) // 2`` when larger).
    progress : callable, optional
        ``progress(done, total, message)`` every iteration; may raise ``Cancelled``.

    Returns
    -------
    SNEResult
        ``embedding``, ``kl_divergence``, ``trustworthiness``, ``iterations``.

    Raises
    ------
    InvalidInputError
        Bad ``points``; more than 5,000 points (the gradient is exact, :math:`O(n^2)` a
        step; use :func:`~algorithms.embedding.tsne`); ``perplexity`` not in ``(0, n)``;
        a bad option.
    Cancelled
        Raised by ``progress``.

    Notes
    -----
    SNE models the embedding by a mixture of Gaussians, t-SNE by a mixture of Student-t
    distributions; read as interpolation weights, t-SNE's are inverse squared distances
    :math:`1/(1 + d^2)`, SNE's the Gaussian :math:`e^{-d^2}`. Both are here so the
    difference can be seen: on clustered data SNE's light-tailed kernel crowds the
    clusters together (lower trustworthiness than t-SNE at the same perplexity). The
    gradient is again a difference of graph Laplacians, :math:`4 (L_P - L_Q) Y`, the
    second rebuilt from :math:`Y` every step. This is the symmetric variant (one joint
    :math:`P` and :math:`Q`), not the original asymmetric SNE of Hinton and Roweis.

    References
    ----------
    .. [1] G. Hinton, S. Roweis, "Stochastic neighbor embedding", NIPS 15 (2002).
    .. [2] L. van der Maaten, G. Hinton, "Visualizing data using t-SNE", JMLR 9 (2008).

    Examples
    --------
    >>> import numpy as np
    >>> rng = np.random.default_rng(0)
    >>> x = np.r_[rng.normal(0, 1, (30, 5)), rng.normal(20, 1, (30, 5))]
    >>> res = sne(x, perplexity=10, max_iterations=300)
    >>> res.embedding.shape, res.trustworthiness > 0.8
    ((60, 2), True)
    """
    report = as_progress(progress)
    x, lr = check_sne(points, perplexity, learning_rate)
    k, perp, iters = n_components, perplexity, max_iterations
    rng = np.random.default_rng(seed)
    y = initial_embedding(x, k, init, rng)
    report(0, iters, "affinities")
    p = affinities(x, perp, dense=True)

    def gradient(yy: FloatArray, alpha: float, want: bool) -> tuple[float, FloatArray]:
        return _sne_kl_gradient(p, yy, alpha, want)

    with single_blas_thread():
        y, done = _descend(y, gradient, max_iterations=iters, exaggeration=early_exaggeration,
                           exaggeration_iterations=exaggeration_iterations, learning_rate=lr,
                           min_grad_norm=min_grad_norm, report=report, what="SNE")
        kl, _ = gradient(y, 1.0, True)
    y = fix_signs(y)
    return SNEResult(
        embedding=np.ascontiguousarray(y),
        kl_divergence=float(kl),
        trustworthiness=trustworthiness(x, y, n_neighbors=quality_neighbors),
        iterations=done,
    )
