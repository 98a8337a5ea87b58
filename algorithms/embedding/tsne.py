r"""t-distributed stochastic neighbour embedding (t-SNE): perplexity-calibrated Gaussian
affinities in the input, Cauchy affinities in the embedding, the Kullback–Leibler divergence
between them minimised by gradient descent with momentum, gains and early exaggeration.
The repulsive forces are exact (all pairs, small ``n``) or FFT-interpolated (FIt-SNE), so
that 100,000 points run in minutes."""

from __future__ import annotations

import typing
from collections.abc import Callable
from dataclasses import dataclass
from typing import Annotated, Any, Literal

import numpy as np
import scipy.sparse as sp

from algorithms.core.errors import InvalidInputError
from algorithms.core.params import Ge, Gt, PointsLike, Seed, validate_params
from algorithms.core.progress import Progress, as_progress
from algorithms.core.threads import single_blas_thread
from algorithms.core.types import FloatArray, IntArray
from algorithms.core.validation import as_points
from algorithms.embedding._fft_gradients import FFTRepulsion
from algorithms.embedding._quality import _nearest_neighbors, fix_signs, trustworthiness

__all__ = ["TSNEResult", "tsne", "check_tsne", "Method", "Start", "LearningRate", "METHODS",
           "INITS", "MAX_EXACT_POINTS", "AUTO_EXACT_BELOW", "check_perplexity", "resolve_method"]

Method = Literal["auto", "exact", "fft"]
"""How t-SNE computes its gradient: all pairs, or the repulsion by FFT interpolation."""
Start = Literal["pca", "random"]
"""Where t-SNE and SNE start: scaled PCA scores, or small Gaussian draws."""
LearningRate = Annotated[float, Gt(0)] | Literal["auto"]
"""A step size > 0, or "auto": one that follows the number of points and the exaggeration."""
#: Accepted values of ``method`` and ``init``.
METHODS: tuple[str, ...] = typing.get_args(Method)
INITS: tuple[str, ...] = typing.get_args(Start)
#: Most points for ``method="exact"`` (all pairs each iteration: O(n²) time).
MAX_EXACT_POINTS = 5_000
#: ``method="auto"`` is exact below this many points (and for ``n_components > 2``).
AUTO_EXACT_BELOW = 500
#: Rows of the all-pairs kernel computed at once (memory: about ``_CELLS`` floats a block).
_CELLS = 2_000_000
#: Entropy tolerance (nats) and most steps of the per-point binary search on β.
_ENTROPY_TOL = 1e-8
_SEARCH_STEPS = 200
#: openTSNE's largest step per point and iteration (``max_step_norm``).
_MAX_STEP = 5.0
#: Pairs of P per chunk of the attraction (its temporaries: a few such float arrays).
_PAIR_CHUNK = 131_072
#: Rows of the perplexity calibration at once (its temporaries: a few such blocks).
_CALIBRATE_ROWS = 1024


@dataclass(frozen=True, eq=False)
class TSNEResult:
    """A t-SNE embedding and how well it fits.

    Attributes
    ----------
    embedding : (n, k) float array
        One row per point, centred; each column's entry of largest magnitude positive.
    kl_divergence : float
        :math:`\\mathrm{KL}(P \\,\\|\\, Q)` of the final embedding (exact ``Z`` for
        ``method="exact"``, the interpolated ``Z`` for ``"fft"``), without exaggeration.
    trustworthiness : float
        How well the embedding keeps each point's nearest neighbours (1 is perfect).
    iterations : int
        Gradient steps taken, early exaggeration included.
    method : str
        The gradient used: ``"exact"`` or ``"fft"`` (what ``"auto"`` chose).
    """

    embedding: FloatArray
    kl_divergence: float
    trustworthiness: float
    iterations: int
    method: str


# -- input affinities ------------------------------------------------------------------------
def _calibrate(d2: FloatArray, perplexity: float) -> tuple[FloatArray, FloatArray]:
    r"""Conditional affinities :math:`p_{j|i} \propto e^{-\beta_i d_{ij}^2}` over each row's
    neighbours, :math:`\beta_i` found by bisection so that the row's entropy is
    :math:`\log(\text{perplexity})` (nats); all rows at once.

    Returns ``(p, beta)``: ``(n, k)`` rows summing to 1, and ``(n,)``. In blocks of
    ``_CALIBRATE_ROWS`` rows (the temporaries' memory; every row on its own, so the same
    bits).
    """
    n = d2.shape[0]
    if n > _CALIBRATE_ROWS:
        p = np.empty(d2.shape)
        beta = np.empty(n)
        for s in range(0, n, _CALIBRATE_ROWS):
            p[s:s + _CALIBRATE_ROWS], beta[s:s + _CALIBRATE_ROWS] = _calibrate(
                d2[s:s + _CALIBRATE_ROWS], perplexity)
        return p, beta
    target = np.log(perplexity)
    d = d2 - d2.min(axis=1, keepdims=True)          # shift: the nearest has weight 1
    scale = d2.mean(axis=1)                         # a start on the data's own scale
    beta = np.where(scale > 0, 1.0 / np.maximum(scale, 1e-300), 1.0)
    lo = np.zeros(n)
    hi = np.full(n, np.inf)
    p = np.empty_like(d)
    active = np.arange(n)
    for _ in range(_SEARCH_STEPS):
        if active.size == 0:
            break
        da = d[active]
        e = np.exp(-beta[active, None] * da)
        s = e.sum(axis=1)
        pa = e / s[:, None]
        h = np.log(s) + beta[active] * (pa * da).sum(axis=1)
        p[active] = pa
        gap = h - target
        done = np.abs(gap) <= _ENTROPY_TOL
        high = gap > 0                                # entropy too high: β too small
        b = beta[active]
        lo[active] = np.where(high, b, lo[active])
        hi[active] = np.where(high, hi[active], b)
        lo_a, hi_a = lo[active], hi[active]
        beta[active] = np.where(np.isinf(hi_a), b * 2.0, (lo_a + hi_a) / 2.0)
        beta[active[done]] = b[done]
        active = active[~done]
    return p, beta


def _row_entropy(p: FloatArray) -> FloatArray:
    """Shannon entropy (nats) of each row."""
    with np.errstate(divide="ignore", invalid="ignore"):
        plogp: FloatArray = np.where(p > 0, p * np.log(p), 0.0).sum(axis=1)
        return -plogp


def _sparse_affinities(x: FloatArray, perplexity: float
                       ) -> tuple[sp.csr_matrix, FloatArray, IntArray]:
    """The sparse joint affinities of :func:`affinities` and the sorted neighbour lists
    they were computed over: squared distances and indices, both ``(n, k)``."""
    n = x.shape[0]
    k = max(1, min(n - 1, int(3 * perplexity)))
    d2, nbr = _nearest_neighbors(x, k)
    if n < 2**31:
        nbr = nbr.astype(np.int32)                  # kept for the trustworthiness: half
    cond, _ = _calibrate(d2, perplexity)
    # straight to CSR (k distinct neighbours a row): no COO triplets and their conversion
    pc = sp.csr_matrix((cond.ravel(), nbr.ravel(), np.arange(0, n * k + 1, k)), shape=(n, n))
    del cond
    p = (pc + pc.T).tocsr()
    del pc
    p.data *= 1.0 / (2.0 * n)                       # in place (as scipy's `/ (2n)` does it)
    p.sum_duplicates()
    p.sort_indices()
    return p, d2, nbr


def _aligned(x: FloatArray) -> FloatArray:
    """``x`` as a C-contiguous float64 array aligned for its dtype: ``x`` itself when it is
    one, else a copy.

    The results depend on it: numpy sends ``x @ x.T`` to BLAS ``syrk`` only when both
    operands are the same aligned buffer, and otherwise copies each operand on its own
    and calls ``gemm``, whose last bits differ (OpenBLAS, SkylakeX kernels); the descent
    amplifies a last-bit difference in ``P`` into a different embedding. Inputs that
    arrive inside a pickle or a network frame (a Dask worker's) are views at any byte
    offset, so without this the service's answer differed from a local call's.
    """
    return np.require(x, dtype=np.float64, requirements=("C_CONTIGUOUS", "ALIGNED"))


@typing.overload
def affinities(x: FloatArray, perplexity: float, *, dense: Literal[True]) -> FloatArray: ...
@typing.overload
def affinities(x: FloatArray, perplexity: float, *, dense: Literal[False]) -> sp.csr_matrix: ...
@typing.overload
def affinities(x: FloatArray, perplexity: float, *, dense: bool
               ) -> FloatArray | sp.csr_matrix: ...
def affinities(x: FloatArray, perplexity: float, *, dense: bool) -> FloatArray | sp.csr_matrix:
    r"""The symmetric joint affinities :math:`p_{ij} = (p_{j|i} + p_{i|j}) / 2n`.

    ``dense=True``: over all pairs (an ``(n, n)`` array, as scikit-learn's exact t-SNE);
    else over each point's :math:`k = \min(n - 1, \lfloor 3\,\text{perplexity}\rfloor)`
    (at least 1) nearest neighbours (exact: :func:`_nearest_neighbors`), a sparse CSR
    matrix summing to 1.
    """
    x = _aligned(x)                                 # x @ x.T: always syrk (see _aligned)
    n: int = x.shape[0]
    if dense:
        sq = np.einsum("ij,ij->i", x, x)
        d2 = np.maximum(sq[:, None] - 2.0 * (x @ x.T) + sq[None, :], 0.0)
        off = ~np.eye(n, dtype=bool)
        cond, _ = _calibrate(d2[off].reshape(n, n - 1), perplexity)
        full = np.zeros((n, n))
        full[off] = cond.ravel()
        return (full + full.T) / (2.0 * n)
    return _sparse_affinities(x, perplexity)[0]


# -- gradients -------------------------------------------------------------------------------
def _exact_terms(p: FloatArray, y: FloatArray, want_kl: bool = True
                 ) -> tuple[FloatArray, FloatArray, float, float]:
    """Attractive sum ``Σ_j p_ij w_ij (y_i − y_j)``, repulsive sum ``Σ_j w_ij² (y_i − y_j)``,
    ``Z`` and ``Σ p_ij log w_ij`` (when ``want_kl``) over all pairs, in blocks of rows."""
    n = y.shape[0]
    att = np.empty_like(y)
    rep = np.empty_like(y)
    z = 0.0
    plogw = 0.0
    rows = max(1, _CELLS // max(n, 1))
    sq = np.einsum("ij,ij->i", y, y)
    for s in range(0, n, rows):
        r = slice(s, min(n, s + rows))
        yr = y[r]
        d2 = np.maximum(sq[r, None] - 2.0 * (yr @ y.T) + sq[None, :], 0.0)
        w = 1.0 / (1.0 + d2)
        idx = np.arange(r.start, r.stop)
        w[idx - r.start, idx] = 0.0
        z += float(w.sum())
        pr = p[r]
        pw = pr * w
        att[r] = yr * pw.sum(axis=1)[:, None] - pw @ y
        w2 = w * w
        rep[r] = yr * w2.sum(axis=1)[:, None] - w2 @ y
        if want_kl:                   # log w = −log(1 + d²)
            plogw -= float((pr * np.log1p(d2)).sum())
    return att, rep, z, plogw


def _exact_kl_gradient(p: FloatArray, y: FloatArray, exaggeration: float = 1.0,
                       want_kl: bool = True, plogp: float | None = None
                       ) -> tuple[float, FloatArray]:
    r"""KL(P‖Q) (NaN unless ``want_kl``) and its gradient
    :math:`4 \sum_j (\alpha p_{ij} - q_{ij}) w_{ij} (y_i - y_j)` over all pairs (dense
    ``p``); ``α`` the exaggeration; ``plogp`` is :math:`\sum p \log p` if known."""
    att, rep, z, plogw = _exact_terms(p, y, want_kl)
    grad = 4.0 * (exaggeration * att - rep / z)
    if not want_kl:
        return float("nan"), grad
    return (_plogp(p) if plogp is None else plogp) - plogw + float(np.log(z)), grad


def _plogp(p: FloatArray | sp.csr_matrix) -> float:
    v = p.data if isinstance(p, sp.csr_matrix) else p[p > 0]
    return float((v * np.log(v)).sum())


class _SparseAttraction:
    r"""Attractive forces :math:`\sum_j p_{ij} w_{ij} (y_i - y_j)` over the stored pairs of a
    symmetric CSR ``P``.

    Row by row of ``P`` (each unordered pair visited from both ends): every stored
    :math:`p_{ij}` gathers :math:`y_j`, and each row's forces are summed in place by
    ``add.reduceat`` over its contiguous run, so the only random access is that gather
    from the (cache-resident) embedding. A 2-D point is one complex number (one gather
    per pair, not two; numpy's loops over ``(m, 2)`` arrays are several times slower than
    over 1-D ones). The rows go in chunks of about ``_PAIR_CHUNK`` pairs whose temporaries
    stay in the cache. Visiting each pair once (the upper triangle) and scattering its
    force to both ends with ``ufunc.at`` does half the arithmetic but took 1.3× as long
    (100,000 points, 14.6 M stored pairs: 110 against 83 ms a step), a sorted second
    pass for the lower ends 1.7× (its gather leaves the cache). The order of the sums is
    fixed: the same input gives the same bits.

    Every row of ``P`` holds a pair (a point's own neighbours). Memory: the column
    indices (int32) and the values (float32) of ``P``, 8 bytes per stored pair;
    :math:`\sum p_{ij} \log p_{ij}` is taken once, in double precision, from the values
    given.
    """

    def __init__(self, p: sp.csr_matrix) -> None:
        n = p.shape[0]
        self.plogp = _plogp(p)
        self.indptr = p.indptr.astype(np.intp)
        self.indices = p.indices.astype(np.int32)
        self.p32 = p.data.astype(np.float32)
        self.counts = np.diff(self.indptr)
        # chunks of whole rows, about _PAIR_CHUNK pairs each (one row may exceed it)
        cuts = np.searchsorted(self.indptr, np.arange(_PAIR_CHUNK, self.indptr[-1], _PAIR_CHUNK))
        self.chunks = np.unique(np.r_[0, cuts, n])

    def __call__(self, y: FloatArray, want_kl: bool) -> tuple[FloatArray, float]:
        n, d = y.shape
        # in 2-D a point is one complex number: one gather per pair (not two); in 1-D the
        # imaginary parts stay 0. Single precision (complex64): half the memory traffic, a
        # third less time; the forces' relative error is about 1e-5, against 5e-3 for the
        # FFT repulsion they are balanced with
        z = (y[:, 0] + 1j * y[:, 1] if d == 2 else y[:, 0]).astype(np.complex64)
        att = np.empty(n, dtype=np.complex64)
        plogw = 0.0
        for s, e in zip(self.chunks[:-1].tolist(), self.chunks[1:].tolist()):
            lo, hi = self.indptr[s], self.indptr[e]
            diff = np.repeat(z[s:e], self.counts[s:e])
            diff -= z.take(self.indices[lo:hi])
            d2 = np.abs(diff)
            d2 *= d2                                    # |y_i - y_j|²
            pij = self.p32[lo:hi]
            if want_kl:                                 # log w = -log(1 + d²), in double
                plogw -= float(np.dot(pij.astype(np.float64), np.log1p(d2.astype(np.float64))))
            d2 += 1.0
            diff *= np.divide(pij, d2, out=d2)          # p_ij w_ij (y_i - y_j)
            att[s:e] = np.add.reduceat(diff, self.indptr[s:e] - lo)
        out = np.empty((n, d))
        out[:, 0] = att.real
        if d == 2:
            out[:, 1] = att.imag
        return out, plogw


# -- the optimiser ---------------------------------------------------------------------------
Gradient = Callable[[FloatArray, float, bool], tuple[float, FloatArray]]


def _descend(y: FloatArray, gradient: Gradient, *, max_iterations: int,
             exaggeration: float, exaggeration_iterations: int, learning_rate: float | None,
             min_grad_norm: float, report: Progress, what: str, style: str = "sklearn"
             ) -> tuple[FloatArray, int]:
    r"""Gradient descent with momentum and delta-bar-delta gains, each point's step
    capped at 5 (openTSNE's ``max_step_norm``), the embedding re-centred every step.

    ``style="sklearn"`` (scikit-learn's): momentum 0.5 during the exaggeration, then
    0.8; gains +0.2 where the update and the gradient have opposite signs, else ×0.8, at
    least 0.01; the update and gains start afresh after the exaggeration phase (a second
    descent). ``style="opentsne"`` (openTSNE's defaults): momentum 0.8 throughout; gains
    +0.2 where the signs differ (a zero update counting as different), else
    ×0.8 + 0.01; the gains carry on from one phase to the next, the update (momentum)
    starts afresh, as in earlier openTSNE releases, whose two ``optimize`` calls each
    began from a zero update (later ones carry it over, which on small regular data ends
    in worse minima: see :func:`tsne`'s Notes).

    ``learning_rate=None`` is openTSNE's "auto" in this gradient's units (4× openTSNE's):
    :math:`\max(n / 4\alpha, 50)`, ``α`` the exaggeration in force.

    ``gradient(y, α, want_kl)`` returns ``(KL, grad)`` (the KL only when asked: every 50
    steps, for the progress message). Every iteration reports progress, which may raise
    ``Cancelled``. Stops early when the gradient's norm falls below ``min_grad_norm``
    after the exaggeration phase."""
    opentsne = style == "opentsne"
    y = np.array(y, dtype=np.float64, copy=True)
    update = np.zeros_like(y)
    gains = np.ones_like(y)
    step = np.empty_like(y)
    it = 0
    kl = float("nan")
    for it in range(1, max_iterations + 1):
        early = it <= exaggeration_iterations
        alpha = exaggeration if early else 1.0
        mom = 0.5 if early and not opentsne else 0.8
        lr = max(y.shape[0] / (4.0 * alpha), 50.0) if learning_rate is None else learning_rate
        if it == exaggeration_iterations + 1:
            # a second descent: the momentum built under exaggeration would fling the
            # points once it is switched off (on scikit-learn's 10 x 10 uniform grid the
            # fft path then ended at KL 0.10-0.29 after 500 steps, against 0.066)
            update[:] = 0.0
            if not opentsne:
                gains[:] = 1.0
        kl, grad = gradient(y, alpha, it % 50 == 0)
        if opentsne:
            flip = np.sign(update) != np.sign(grad)
            gains = np.where(flip, gains + 0.2, gains * 0.8 + 0.01)
        else:
            gains = np.where(update * grad < 0.0, gains + 0.2, gains * 0.8)
            np.maximum(gains, 0.01, out=gains)
        np.multiply(gains, grad, out=step)
        step *= lr
        update *= mom
        update -= step
        norms = np.sqrt(np.einsum("ij,ij->i", update, update))
        big = norms > _MAX_STEP
        if big.any():
            update[big] *= (_MAX_STEP / norms[big])[:, None]
        y += update
        y -= y.mean(axis=0)
        msg = f"{what} iteration {it}" + ("" if it % 50 else f", KL {kl:.4f}")
        report(it, max_iterations, msg)
        if not early and float(np.linalg.norm(grad)) < min_grad_norm:
            break
    return y, it


def initial_embedding(x: FloatArray, k: int, init: str, rng: np.random.Generator
                      ) -> FloatArray:
    """PCA scores (first column's standard deviation 1e-4, signs fixed; as openTSNE and
    scikit-learn) or ``N(0, 1e-4²)`` draws; columns beyond the data's rank are random."""
    n, dim = x.shape
    if init == "random":
        return rng.normal(0.0, 1e-4, size=(n, k))
    xc = x - x.mean(axis=0)
    with single_blas_thread():
        if dim <= n:
            _, vecs = np.linalg.eigh(xc.T @ xc)
            axes = vecs[:, ::-1][:, :min(k, dim)]
        else:
            _, _, vt = np.linalg.svd(xc, full_matrices=False)
            axes = vt[:min(k, dim)].T
        y = fix_signs(xc @ axes)
    sd = float(np.std(y[:, 0]))
    y = y / sd * 1e-4 if sd > 0 else np.zeros_like(y)
    if y.shape[1] < k:
        y = np.c_[y, rng.normal(0.0, 1e-4, size=(n, k - y.shape[1]))]
    return y


def check_start(init: Any, n: int, k: int) -> FloatArray:
    """A start embedding given as an array: ``(n, k)`` finite numbers, copied."""
    y = as_points(init, name="init")
    if y.shape != (n, k):
        raise InvalidInputError(
            f"Expected `init` to be 'pca', 'random' or an array of one row per point and "
            f"n_components columns, shape ({n}, {k}), got shape ({y.shape[0]}, "
            f"{y.shape[1]}).", field="init")
    return np.array(y, dtype=np.float64, order="C")


def check_perplexity(perplexity: float, n: int) -> None:
    """Raise unless ``perplexity`` is below the number of points ``n`` (a point's Gaussian
    cannot spread over more neighbours than there are)."""
    if perplexity >= n:
        raise InvalidInputError(f"Expected `perplexity` to be below the number of `points` "
                                f"({n}), got {perplexity:g}.", field="perplexity")


def resolve_method(method: str, n: int, n_components: int) -> Literal["exact", "fft"]:
    """The gradient t-SNE uses for ``n`` points in ``n_components`` dimensions: ``method``,
    or for ``"auto"`` exact below :data:`AUTO_EXACT_BELOW` points or above 2 dimensions,
    else fft. Raises when the exact gradient gets more than :data:`MAX_EXACT_POINTS`
    points or the fft one more than 2 dimensions."""
    exact = method == "exact" or (method == "auto" and (n < AUTO_EXACT_BELOW
                                                         or n_components > 2))
    if exact and n > MAX_EXACT_POINTS:
        if method == "exact":
            raise InvalidInputError(f"Expected at most {MAX_EXACT_POINTS:,} `points` for "
                                    f"method = 'exact' (O(n²) per step), got {n:,}; use "
                                    f"method = 'fft' (n_components <= 2).", field="method")
        raise InvalidInputError(f"Expected `n_components` <= 2 for {n:,} `points` (more "
                                f"dimensions need the exact gradient, O(n²) per step, at "
                                f"most {MAX_EXACT_POINTS:,} points), got {n_components}.",
                                field="n_components")
    if not exact and n_components > 2:
        raise InvalidInputError(f"Expected `n_components` <= 2 for method = 'fft', got "
                                f"{n_components}; use method = 'exact'.", field="n_components")
    return "exact" if exact else "fft"


def check_common(points: Any, *, perplexity: float, learning_rate: float | str
                 ) -> tuple[FloatArray, float | None]:
    """The checks of the data shared by t-SNE and SNE: the points (C-contiguous and
    aligned, as :func:`as_points` gives them: see :func:`_aligned`), the perplexity below
    their number; and the learning rate, None for ``"auto"`` (chosen per phase in
    :func:`_descend`)."""
    x = as_points(points, name="points", min_points=2)
    check_perplexity(perplexity, x.shape[0])
    lr = None if isinstance(learning_rate, str) else learning_rate
    return x, lr


def check_tsne(points: Any, perplexity: float, method: str = "auto", n_components: int = 2,
               learning_rate: float | str = "auto"
               ) -> tuple[FloatArray, float | None, Literal["exact", "fft"]]:
    """Check the inputs of :func:`tsne`: the data as :func:`check_common` takes it, and a
    gradient method that takes its size and ``n_components`` (:func:`resolve_method`).
    Returns the points, the learning rate (None for ``"auto"``) and the method."""
    x, lr = check_common(points, perplexity=perplexity, learning_rate=learning_rate)
    return x, lr, resolve_method(method, x.shape[0], n_components)


@validate_params
def tsne(
    points: PointsLike,
    *,
    n_components: Annotated[int, Ge(1)] = 2,
    perplexity: Annotated[float, Gt(0)] = 30.0,
    method: Method = "auto",
    init: Start | PointsLike = "pca",
    learning_rate: LearningRate = "auto",
    max_iterations: Annotated[int, Ge(1)] = 750,
    early_exaggeration: Annotated[float, Ge(1)] = 12.0,
    exaggeration_iterations: Annotated[int, Ge(0)] = 250,
    min_grad_norm: Annotated[float, Ge(0)] = 1e-7,
    seed: Seed = 0,
    quality_neighbors: Annotated[int, Ge(1)] = 5,
    progress: Progress | None = None,
) -> TSNEResult:
    r"""t-SNE (t-distributed stochastic neighbour embedding).

    Perplexity-calibrated Gaussian affinities (binary search per point), Cauchy affinities in the
    embedding, KL(P‖Q) minimised by gradient descent with momentum, gains and early exaggeration;
    exact all-pairs gradient for small inputs, FFT-interpolated repulsion (FIt-SNE) for up to
    100,000s of points. Reports KL, trustworthiness and iterations. Progress every iteration,
    cancellable.

    Input affinities: for each point a Gaussian over its neighbours, its precision
    :math:`\beta_i` found by binary search so that the perplexity :math:`2^{H(P_i)}`
    equals ``perplexity``, then symmetrised,

    .. math:: p_{j|i} = \frac{e^{-\beta_i \lVert x_i - x_j\rVert^2}}
                             {\sum_{k \ne i} e^{-\beta_i \lVert x_i - x_k\rVert^2}},
              \qquad p_{ij} = \frac{p_{j|i} + p_{i|j}}{2n}.

    Embedding affinities: the Cauchy (Student-t, one degree of freedom) kernel
    :math:`w_{ij} = (1 + \lVert y_i - y_j\rVert^2)^{-1}`, :math:`q_{ij} = w_{ij} / Z`,
    :math:`Z = \sum_{k \ne l} w_{kl}`. The embedding minimises

    .. math:: C = \mathrm{KL}(P \,\|\, Q) = \sum_{i \ne j} p_{ij} \log \frac{p_{ij}}{q_{ij}},
              \qquad \frac{\partial C}{\partial y_i} = 4 \sum_j (p_{ij} - q_{ij})\, w_{ij}\,
              (y_i - y_j),

    by gradient descent with momentum (scikit-learn's 0.5 then 0.8 for ``"exact"``,
    openTSNE's 0.8 for ``"fft"``), per-coordinate gains and, for the first
    ``exaggeration_iterations`` steps, :math:`P` multiplied by ``early_exaggeration``.

    Parameters
    ----------
    points : (n, D) float array
        The data, one row per point; at least 2 points.
    n_components : int, default 2
        The embedding's dimension ``k``. ``method="fft"`` needs ``k <= 2``; larger ``k``
        is exact only (at most 5,000 points).
    perplexity : float, default 30
        The effective number of neighbours of each point's Gaussian (its entropy is
        :math:`\log(\text{perplexity})`, found by binary search), ``0 < perplexity < n``.
    method : {"auto", "exact", "fft"}, default "auto"
        ``"exact"``: all pairs each iteration, affinities over all pairs (as scikit-learn's
        ``method="exact"``; at most 5,000 points). ``"fft"``: affinities over the
        :math:`\min(n - 1, 3\,\text{perplexity})` nearest neighbours (rounded down), the
        repulsion by FFT-accelerated interpolation (FIt-SNE; openTSNE's default;
        ``n_components <= 2``). ``"auto"``: exact below 500 points or for
        ``n_components > 2``, else fft.
    init : {"pca", "random"} or (n, k) float array, default "pca"
        The start: ``"pca"`` the PCA scores scaled to a first-column standard deviation
        of 1e-4 (openTSNE, scikit-learn), ``"random"`` Gaussian draws of that size from
        ``seed``, or the start positions themselves, one row per point and
        ``n_components`` columns, used as given (as scikit-learn and openTSNE do: e.g. a
        previous embedding to continue from). An embedding started from an array keeps
        its orientation: its column signs are not normalised.
    learning_rate : float or "auto", default "auto"
        The step, ``> 0``. ``"auto"``: :math:`\max(n / 4\alpha, 50)` with :math:`\alpha`
        the exaggeration in force — scikit-learn's :math:`\max(n / 4 \cdot 12, 50)` during
        the exaggeration, then openTSNE's :math:`n / \alpha` (openTSNE's gradient lacks
        the factor 4) with :math:`\alpha = 1`, 12× larger, which converges in fewer steps.
    max_iterations : int, default 750
        Gradient steps in all, the exaggeration phase included (openTSNE's 250 + 500;
        scikit-learn's ``max_iter`` is 1000 with its smaller step).
    early_exaggeration : float, default 12
        The factor :math:`\alpha \ge 1` on :math:`P` during the first
        ``exaggeration_iterations`` steps (it pulls clusters together early on).
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
        ``progress(done, total, message)`` every iteration (the KL every 50); may raise
        :class:`~algorithms.core.errors.Cancelled`.

    Returns
    -------
    TSNEResult
        ``embedding``, ``kl_divergence``, ``trustworthiness``, ``iterations``, ``method``.

    Raises
    ------
    InvalidInputError
        Bad ``points`` (fewer than 2, NaN); ``perplexity`` not in ``(0, n)``; the exact
        gradient (``method="exact"``, or ``"auto"`` with ``n_components > 2``) for more
        than 5,000 points; ``method="fft"`` with ``n_components > 2``; a non-positive
        learning rate; an unknown option; an ``init`` array not of shape
        ``(n, n_components)`` or not finite.
    Cancelled
        Raised by ``progress``.

    Notes
    -----
    Choices that follow the peers: squared Euclidean input distances; the binary search
    on :math:`\beta_i` runs until the entropy is within 1e-8 nats of
    :math:`\log(\text{perplexity})` (scikit-learn stops at 1e-5); one degree of freedom
    in every dimension (openTSNE; scikit-learn uses :math:`k - 1` for :math:`k > 2`).
    The descent follows scikit-learn's exact t-SNE for ``method="exact"`` (momentum 0.5
    then 0.8; after the exaggeration phase the gains and update restart, a second
    descent) and openTSNE's defaults for ``"fft"`` (momentum 0.8 throughout, gains
    carried over, gains ×0.8 + 0.01 / +0.2), except that the update restarts after the
    exaggeration phase: carried over, the momentum built under exaggeration left the
    fft path in clearly worse minima on small regular data (scikit-learn's
    ``test_uniform_grid``, a 10 × 10 grid, perplexity 50, 500 steps: KL 0.10 to 0.29 for
    seeds 0-2, against 0.066 for the exact path; restarted, 0.066 for every seed; the
    FFT repulsion itself was not the cause: with the exact path's descent it reached
    0.066 too). Each point's step is capped at 5
    (openTSNE's ``max_step_norm``) and the embedding is re-centred every step. The final
    columns are sign-fixed (entry of largest magnitude positive), which changes neither
    KL nor trustworthiness.

    ``method="fft"``: the nearest neighbours are exact, recall 1 (openTSNE's are
    approximate, Annoy); above 8 input dimensions they come from blocks of the distance
    matrix by one BLAS product each and ``argpartition`` (a kd-tree visits nearly every
    point in 50 dimensions; this is several times faster), else from a kd-tree. From
    5,000 points the rows go group by group of a k-means partition of the points, and a
    group's columns are only the groups that may hold a neighbour by the triangle
    inequality (its gap to them below an upper bound on its rows' :math:`k`-th
    distance, from the nearest groups): still exact, and on clustered data most of the
    :math:`n \times n` distances are never computed (30,000 points in 20 clusters,
    50-D: 5× faster); on data without clusters nothing is pruned. The FFT
    repulsion (:mod:`algorithms.embedding._fft_gradients`) interpolates each point from
    the 4 × 4 nearest nodes of a grid of spacing at most 1/3 (openTSNE: the 3 × 3 nodes of
    the point's box of side 1; 2,000 points in 20 clusters: final KL 0.812, against 0.825
    with 4 nodes per box, 0.807 with the exact repulsion and 0.815 for openTSNE's
    default), and convolves the kernel :math:`w^2 (y_i - y_j)` on the node grid by FFT
    (single precision); :math:`Z` comes from the same transform of the charges by
    Parseval's identity, less each point's interaction with itself on the grid (relative
    error about 1e-5 on those final embeddings); the repulsion's median relative error is
    about 0.4 %. The attractive
    forces go row by row of :math:`P` (each pair from both ends, every row summed in
    place: no scatter) in single precision (their relative error about
    1e-5, against 5e-3 for the repulsion). All sums run in a fixed order: the same ``seed``
    gives the same bits. Everything runs in one thread (BLAS limited to one).

    Three readings of t-SNE. As a mixture model: SNE's Gaussian mixture in the embedding
    replaced by a Student-t one, whose heavy tails let moderately distant points sit far
    apart (SNE crowds them together: :func:`~algorithms.embedding.sne`). As
    interpolation: a constant function 1 carried by inverse-distance-weighting
    interpolation, whose weights are the normalised :math:`q_{ij}`; the normaliser must
    then be the sum over *all* ordered pairs, :math:`Z = \sum_{k \ne l} w_{kl}` (a
    normaliser over the pairs of :math:`i` alone would be SNE's per-point conditional
    :math:`q_{j|i}`, not the joint :math:`q_{ij}` the gradient above assumes), and the
    gradient's :math:`q_{ij}` uses that same :math:`Z`. As an adaptive Laplacian: with
    weights :math:`w_{ij} = 1/(1 + d_{ij}^2)` (an inverse squared distance, the 1 keeping
    it finite at :math:`d = 0`), the gradient is :math:`4 (L_{P \circ W} - L_{Q \circ
    W})\, Y` — the difference of two graph Laplacians, the second rebuilt from :math:`Y`
    every step; that is how the exact path computes it, in blocks of rows.

    Cost: exact :math:`O(n^2)` per step; fft :math:`O(n k_P + N^2 \log N)` per step with
    :math:`k_P \approx 3\,\text{perplexity}` stored pairs per point and :math:`N` the grid
    nodes per side (about 3× the embedding's extent, at least 100), plus the neighbour
    search once (:math:`O(n^2 D)` above 8 dimensions at worst, in blocks; about
    :math:`O(n\, m D)` on data in clusters of :math:`m` points).

    References
    ----------
    .. [1] L. van der Maaten, G. Hinton, "Visualizing data using t-SNE", JMLR 9 (2008).
    .. [2] G. C. Linderman, M. Rachh, J. G. Hoskins, S. Steinerberger, Y. Kluger, "Fast
       interpolation-based t-SNE for improved visualization of single-cell RNA-seq
       data", Nature Methods 16 (2019).
    .. [3] P. G. Poličar, M. Stražar, B. Zupan, "openTSNE: a modular Python library for
       t-SNE dimensionality reduction and embedding", J. Stat. Softw. 109 (2024).

    Examples
    --------
    >>> import numpy as np
    >>> rng = np.random.default_rng(0)
    >>> x = np.r_[rng.normal(0, 1, (30, 5)), rng.normal(20, 1, (30, 5))]
    >>> res = tsne(x, perplexity=10, max_iterations=300)
    >>> res.method, res.embedding.shape, res.trustworthiness > 0.9
    ('exact', (60, 2), True)
    """
    report = as_progress(progress)
    x, lr, method = check_tsne(points, perplexity, method, n_components, learning_rate)
    k, perp, iters = n_components, perplexity, max_iterations
    rng = np.random.default_rng(seed)
    given = not isinstance(init, str)
    if isinstance(init, str):  # "pca" or "random": checked by the signature
        y = initial_embedding(x, k, init, rng)
    else:
        y = check_start(init, x.shape[0], k)
    report(0, iters, "affinities")
    if method == "exact":
        p = affinities(x, perp, dense=True)

        plogp = _plogp(p)

        def gradient(yy: FloatArray, alpha: float, want: bool) -> tuple[float, FloatArray]:
            return _exact_kl_gradient(p, yy, alpha, want, plogp)
    else:
        p_sparse, input_d2, input_nbr = _sparse_affinities(x, perp)
        attraction = _SparseAttraction(p_sparse)
        del p_sparse                                # the attraction holds its own (smaller) copy
        repulsion_fft = FFTRepulsion()              # the last grid's kernels, for this run

        def gradient(yy: FloatArray, alpha: float, want: bool) -> tuple[float, FloatArray]:
            att, plogw = attraction(yy, want)
            rep, z = repulsion_fft(yy)
            return attraction.plogp - plogw + np.log(z), 4.0 * (alpha * att - rep / z)

    with single_blas_thread():
        y, done = _descend(y, gradient, max_iterations=iters, exaggeration=early_exaggeration,
                           exaggeration_iterations=exaggeration_iterations, learning_rate=lr,
                           min_grad_norm=min_grad_norm, report=report, what="t-SNE",
                           style="sklearn" if method == "exact" else "opentsne")
        kl, _ = gradient(y, 1.0, True)
    # P (or the attraction's pairs) freed before the trustworthiness: the peak memory
    del gradient
    if method == "exact":
        del p
    else:
        del attraction, repulsion_fft
    y = y if given else fix_signs(y)
    lists = None if method == "exact" else (input_d2, input_nbr)
    return TSNEResult(
        embedding=np.ascontiguousarray(y),
        kl_divergence=float(kl),
        trustworthiness=trustworthiness(x, y, n_neighbors=quality_neighbors,
                                        input_neighbours=lists),
        iterations=done,
        method=method,
    )
