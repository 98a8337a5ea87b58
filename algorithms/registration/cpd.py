"""Coherent point drift (CPD): rigid (with or without scale), affine or nonrigid registration
of two point sets as the fit of a Gaussian mixture by expectation maximisation, in bounded
memory."""

from __future__ import annotations

import contextlib
import math
from collections.abc import Iterator
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import Annotated, Any, Literal, cast, get_args

import numpy as np
from scipy.spatial import cKDTree

from algorithms.core.errors import ConvergenceWarning, InvalidInputError, warn
from algorithms.core.linalg import procrustes
from algorithms.core.params import Ge, Gt, Interval, PointsLike, validate_params
from algorithms.core.progress import Progress, as_progress
from algorithms.core.threads import block_workers, query_workers, single_blas_thread
from algorithms.core.types import FloatArray, KnnQuery
from algorithms.core.validation import as_points, check_min_points, check_span, same_dim

__all__ = ["CPDResult", "cpd", "check_sizes", "MODELS", "CHUNK_BYTES", "EXACT_KERNEL_MAX",
           "LOW_RANK_ABOVE"]

Model = Literal["rigid", "affine", "nonrigid"]
#: The accepted values of ``model``.
MODELS = get_args(Model)

#: The largest block of the M×N kernel held at once, in bytes: the posterior is never
#: materialised; it is summed block by block into ``P1``, ``Pᵀ1`` and ``PX``.
CHUNK_BYTES = 256 * 2**20
#: Nonrigid: the exact M×M kernel ``G`` is used up to this many source points; above it, its
#: leading eigenpairs (the paper's fast version), unless ``low_rank`` says otherwise.
LOW_RANK_ABOVE = 1000
#: Nonrigid: the most source points for which the exact M×M kernel may be asked for (it and
#: the M×M system take 16 M² bytes: 256 MB at 4000 points).
EXACT_KERNEL_MAX = 4000
#: σ² at or below this (in units of the target's squared RMS radius) is an exact fit: stop.
SIGMA2_FLOOR = 1e-14
#: Oversampling and power iterations of the randomised eigen-decomposition of ``G``.
_OVERSAMPLE = 10
_POWER_ITERATIONS = 2
#: Rows of the kernel whose sum is below this are recomputed shifted by their largest
#: exponent, so that no point is lost to underflow (the log-sum-exp trick, only where needed).
_UNDERFLOW = 1e-250
#: Exponents are clipped below at this: exp then never underflows (its slow path in libm costs
#: 3x). A clipped term (≤ 1e-304) is below 1e-54 of the sum of any row kept (≥ _UNDERFLOW):
#: posteriors change by less than 1e-54 in absolute terms; the other rows are recomputed.
_EXP_MIN = -700.0
#: Truncated E-step: terms below exp(-ln M - TRUNCATE) are left out where they cannot change
#: a row's sum by 1e-16 (see _Posterior); blocks of this many target points; dense sums when
#: more than this fraction of all pairs would be met anyway, or fewer source points than this.
_TRUNCATE = 45.0
_TRUNCATED_BLOCK = 32
_DENSE_FRACTION = 0.5
_TRUNCATE_ABOVE = 256
#: The blocks of an E-step are dealt to this many fixed partitions, summed by up to as many
#: threads (numpy's exp and BLAS release the GIL) when the blocks are large enough for that
#: to pay (:func:`~algorithms.core.threads.block_workers`).
_PARTS = 4


@dataclass(frozen=True, eq=False)
class CPDResult:
    """The registration CPD found from ``source`` to ``target``, and how it got there.

    Attributes
    ----------
    transform : (d+1, d+1) float array or None
        The homogeneous matrix ``[[A, t], [0, 1]]`` that maps source points onto the target
        (rigid and affine); null for nonrigid, whose map is not linear (see ``moved``).
    linear : (d, d) float array or None
        The linear part ``A``: ``s R`` (rigid) or any matrix (affine); null for nonrigid.
    rotation : (d, d) float array or None
        The rotation ``R`` (determinant +1) of the rigid model; null otherwise.
    scale : float or None
        The uniform scale ``s`` of the rigid model (1.0 with ``scale=false``); null otherwise.
    translation : (d,) float array or None
        The translation ``t`` applied after the linear part; null for nonrigid.
    moved : (n, d) float array
        The source points moved onto the target by the final map, row for row.
    sigma2 : float
        The final variance σ² of the Gaussian mixture, in squared target units: about the
        mean squared distance of a matched pair per dimension.
    rmse : float
        Root-mean-square distance of the moved source points to their nearest target points.
    iterations : int
        The EM iterations run (M-steps performed).
    converged : bool
        True when the relative change of the negative log-likelihood fell below
        ``tolerance`` or σ² reached rounding level (an exact fit); False when
        ``max_iterations`` ran out or the fit became undetermined (see ``reason``). A
        ``ConvergenceWarning`` accompanies False.
    reason : str
        Why the iterations stopped, in words.
    """

    transform: FloatArray | None
    linear: FloatArray | None
    rotation: FloatArray | None
    scale: float | None
    translation: FloatArray | None
    moved: FloatArray
    sigma2: float
    rmse: float
    iterations: int
    converged: bool
    reason: str


# --- the E-step, in blocks -------------------------------------------------------------------


def _block_rows(m: int, chunk_bytes: int) -> int:
    """Rows of an ``(rows, m)`` float64 block that fit in ``chunk_bytes``."""
    return max(1, min(chunk_bytes // (8 * max(m, 1)), 1 << 30))


class _Posterior:
    r"""Sums of the posterior :math:`P` (M×N) without storing it.

    For the moved source ``ty`` (M×d) and the target ``x`` (N×d), with
    :math:`a_{mn} = \lVert x_n - t_m \rVert^2 / 2\sigma^2`,

    .. math::

        P_{mn} = \frac{e^{-a_{mn}}}{\sum_k e^{-a_{kn}} + c},

    and :math:`P1`, :math:`P^\mathsf{T}1`, :math:`PX` and :math:`\sum_n \log(\sum_k e^{-a_{kn}}
    + c)` are accumulated over blocks of target points (in the kd-tree's spatial order): at
    most ``rows`` target points × M source points at a time, in one reused buffer of
    ``chunk_bytes``. Squared distances come from :math:`\lVert x\rVert^2 + \lVert t\rVert^2
    - 2 x\cdot t` (one matrix product per block, clipped at 0); :math:`P1` and :math:`PX` from
    one more product of the block with :math:`[X / \mathrm{den},\ 1 / \mathrm{den}]`.

    Once σ is small against the sets, a block of target points meets only the source points
    within ``R = σ √(2 (ln M + TRUNCATE))`` of it (a ball query of a kd-tree of the moved
    source): every term left out is below :math:`e^{-R^2/2\sigma^2}`, so they sum to less
    than :math:`e^{-\mathrm{TRUNCATE}}`, and a row is kept only where that is below 1e-16 of
    its sum (else it is recomputed against every source point): the sums stay exact to
    rounding while the exponentials fall to the pairs that matter.
    """

    def __init__(self, x: FloatArray, m: int, chunk_bytes: int) -> None:
        n = x.shape[0]
        self.m = m
        # _PARTS fixed partitions of the blocks, each with its own buffer and sums (added in
        # a fixed order: the result does not depend on the number of threads).
        self.rows = max(1, min(_block_rows(m, chunk_bytes) // _PARTS, -(-n // _PARTS)))
        self.bufs = [np.empty(self.rows * m) for _ in range(_PARTS)]
        # Blocks for the truncated sums: compact groups of target points, with their balls.
        self.order, self.blocks = _spatial_blocks(x, max(1, min(self.rows, _TRUNCATED_BLOCK)))
        self.x = np.ascontiguousarray(x[self.order])
        self.x2 = np.einsum("ij,ij->i", self.x, self.x)
        self.centres = np.array([self.x[lo:hi].mean(axis=0) for lo, hi in self.blocks])
        self.radii = np.array([np.sqrt(np.max(np.sum((self.x[lo:hi] - c) ** 2, axis=1)))
                               for (lo, hi), c in zip(self.blocks, self.centres)])
        centre = self.x.mean(axis=0)
        self.extent = 2.0 * float(np.sqrt(np.max(np.sum((self.x - centre) ** 2, axis=1))))

    def _mode(self, ty: FloatArray, sigma2: float) -> tuple[Any, Any, int]:
        """``(tree, radii, workers)``: the kd-tree of the moved source and the blocks'
        reach when the truncated sums pay, else ``(None, None, ...)`` (all pairs), and the
        threads that pay for this E-step (:func:`~algorithms.core.threads.block_workers`)."""
        m = ty.shape[0]
        n = self.x.shape[0]
        all_pairs = None, None, block_workers(self.rows * m, n * m, _PARTS)
        reach = math.sqrt(2.0 * sigma2 * (math.log(m) + _TRUNCATE))
        if len(self.blocks) < 2 or m < _TRUNCATE_ABOVE or reach >= self.extent:
            return all_pairs
        tree = cKDTree(ty, leafsize=16, balanced_tree=False)
        radii = self.radii + reach
        reached = int(tree.query_ball_point(self.centres, radii, return_length=True).sum())
        if reached > _DENSE_FRACTION * len(self.blocks) * m:
            return all_pairs
        pairs = reached * (n // len(self.blocks) or 1)
        return tree, radii, block_workers(pairs // len(self.blocks), pairs, _PARTS)

    def _blocks(self, part: int, tree: Any, radii: Any) -> Iterator[tuple[int, int, Any]]:
        """The blocks of partition ``part``, one at a time: ``(lo, hi, None)`` for all source
        points, or ``(lo, hi, idx)`` for the source points ``idx`` near the block."""
        n = self.x.shape[0]
        if tree is None:
            for lo in range(part * self.rows, n, _PARTS * self.rows):
                yield lo, min(lo + self.rows, n), None
            return
        for i in range(part, len(self.blocks), _PARTS):
            lo, hi = self.blocks[i]
            idx = tree.query_ball_point(self.centres[i], radii[i], return_sorted=True)
            yield lo, hi, np.asarray(idx, dtype=np.intp)

    def _plan(self, ty: FloatArray, sigma2: float) -> Iterator[tuple[int, int, Any]]:
        """Every block of this E-step (all partitions)."""
        tree, radii, _ = self._mode(ty, sigma2)
        for part in range(_PARTS):
            yield from self._blocks(part, tree, radii)

    def __call__(self, ty: FloatArray, sigma2: float, log_c: float
                 ) -> tuple[FloatArray, FloatArray, FloatArray, float]:
        n = self.x.shape[0]
        m, d = ty.shape
        inv = 1.0 / sigma2
        ay = np.einsum("ij,ij->i", ty, ty) * (0.5 * inv)
        ax = self.x2 * (0.5 * inv)
        pt1 = np.empty(n)
        ty_scaled = ty * inv
        tree, radii, workers = self._mode(ty, sigma2)

        def run(part: int) -> tuple[FloatArray, float]:
            return self._sums(self._blocks(part, tree, radii), self.bufs[part], ty_scaled,
                              ax, ay, log_c, pt1)

        if workers > 1:
            with ThreadPoolExecutor(workers) as pool:
                parts = list(pool.map(run, range(_PARTS)))
        else:
            parts = [run(part) for part in range(_PARTS)]
        acc = parts[0][0]
        for more, _ in parts[1:]:
            acc += more
        log_den = math.fsum(ld for _, ld in parts)
        out = np.empty(n)
        out[self.order] = pt1
        return acc[:, d].copy(), out, acc[:, :d].copy(), log_den

    def _sums(self, blocks: Iterator[tuple[int, int, Any]], buf: FloatArray,
              ty_scaled: FloatArray, ax: FloatArray, ay: FloatArray, log_c: float,
              pt1: FloatArray) -> tuple[FloatArray, float]:
        """``[PX, P1]`` and the log-denominators summed over ``blocks``; ``pt1`` filled in
        for their rows."""
        x = self.x
        m, d = ty_scaled.shape
        c = math.exp(log_c) if log_c < 700.0 else math.inf
        acc = np.zeros((m, d + 1))                 # [PX, P1]
        log_den = 0.0
        for lo, hi, idx in blocks:
            cols = m if idx is None else idx.size
            blk = buf[: (hi - lo) * cols].reshape(hi - lo, cols)
            if idx is None:
                np.dot(x[lo:hi], ty_scaled.T, out=blk)      # x·t / σ²
                blk -= ay[None, :]
                limit = _UNDERFLOW
            else:
                np.dot(x[lo:hi], ty_scaled[idx].T, out=blk)
                blk -= ay[idx][None, :]
                limit = max(_UNDERFLOW, math.exp(-_TRUNCATE) / 1e-16)
            blk -= ax[lo:hi, None]                          # -a = -(|x|²+|t|²-2x·t)/2σ²
            np.clip(blk, _EXP_MIN, 0.0, out=blk)            # see _EXP_MIN
            np.exp(blk, out=blk)
            s = blk.sum(axis=1)
            with np.errstate(divide="ignore", over="ignore"):
                den = s + c
                ld = np.log(den)
            bad = np.flatnonzero(s < limit)
            if bad.size:
                # Recompute these rows against every source point, shifted by their largest
                # exponent: exact where plain exp underflows (every source point far off at
                # this σ²) or the truncation could matter; a quarter block at a time.
                blk[bad] = 0.0
                step = max(1, self.rows // 4)
                for part in (bad[i:i + step] for i in range(0, bad.size, step)):
                    k, s_bad, den_bad, ld_bad = _exact_rows(x[lo + part], ax[lo + part],
                                                            ty_scaled, ay, log_c)
                    s[part], den[part], ld[part] = s_bad, den_bad, ld_bad
                    w_bad = 1.0 / den_bad
                    rhs = np.empty((part.size, d + 1))
                    rhs[:, :d] = x[lo + part] * w_bad[:, None]
                    rhs[:, d] = w_bad
                    acc += k.T @ rhs
            log_den += float(ld.sum())
            w = 1.0 / den                                   # 0 where den is inf
            pt1[lo:hi] = s * w
            rhs = np.empty((hi - lo, d + 1))
            rhs[:, :d] = x[lo:hi] * w[:, None]
            rhs[:, d] = w
            if idx is None:
                acc += blk.T @ rhs
            elif idx.size:
                acc[idx] += blk.T @ rhs
        return acc, log_den


def _spatial_blocks(x: FloatArray, size: int) -> tuple[Any, list[tuple[int, int]]]:
    """An order of the points and its consecutive blocks of at most ``size`` points, each
    compact: split at the median of the widest coordinate until small enough."""
    order = np.arange(x.shape[0])
    blocks: list[tuple[int, int]] = []
    stack = [(0, x.shape[0])]
    while stack:
        lo, hi = stack.pop()
        if hi - lo <= size:
            blocks.append((lo, hi))
            continue
        part = order[lo:hi]
        pts = x[part]
        axis = int(np.argmax(pts.max(axis=0) - pts.min(axis=0)))
        mid = (hi - lo) // 2
        order[lo:hi] = part[np.argpartition(pts[:, axis], mid)]
        stack.append((lo + mid, hi))
        stack.append((lo, lo + mid))
    blocks.sort()
    return order, blocks


def _exact_rows(x: FloatArray, ax: FloatArray, ty_scaled: FloatArray, ay: FloatArray,
                log_c: float) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Kernel rows of target points ``x`` against every source point, each scaled by
    :math:`e^{a_{min}}` (no underflow): the scaled rows, their sums, the matching
    denominators (:math:`s + c e^{a_{min}}`, possibly inf) and the logs of the true ones."""
    e = x @ ty_scaled.T
    e -= ax[:, None]
    e -= ay[None, :]
    np.minimum(e, 0.0, out=e)
    top = e.max(axis=1)
    e -= top[:, None]
    np.exp(e, out=e)
    s = e.sum(axis=1)
    with np.errstate(over="ignore"):
        c_top = np.exp(log_c - top) if math.isfinite(log_c) else np.zeros_like(top)
    return e, s, s + c_top, np.logaddexp(top + np.log(s), log_c)


# --- the nonrigid kernel ----------------------------------------------------------------------


def _gauss_blocks(y: FloatArray, beta: float, chunk_bytes: int
                  ) -> Iterator[tuple[int, int, FloatArray]]:
    """Yield ``(lo, hi, G[lo:hi])`` for the Gaussian kernel of ``y``, one block at a time."""
    m = y.shape[0]
    y2 = np.einsum("ij,ij->i", y, y) * (0.5 / beta**2)
    ys = y / beta**2
    rows = min(_block_rows(m, chunk_bytes), m)
    buf = np.empty((rows, m))
    for lo in range(0, m, rows):
        hi = min(lo + rows, m)
        blk = buf[: hi - lo]
        np.dot(y[lo:hi], ys.T, out=blk)
        blk -= y2[lo:hi, None]
        blk -= y2[None, :]
        np.clip(blk, _EXP_MIN, 0.0, out=blk)
        np.exp(blk, out=blk)
        yield lo, hi, blk


def _kernel(y: FloatArray, beta: float, chunk_bytes: int) -> FloatArray:
    """The whole M×M Gaussian kernel (small M only)."""
    g = np.empty((y.shape[0], y.shape[0]))
    for lo, hi, blk in _gauss_blocks(y, beta, chunk_bytes):
        g[lo:hi] = blk
    g[np.diag_indices_from(g)] = 1.0
    return 0.5 * (g + g.T)


def _kernel_times(y: FloatArray, beta: float, v: FloatArray, chunk_bytes: int) -> FloatArray:
    """``G v`` without storing ``G``."""
    out = np.empty((y.shape[0], v.shape[1]))
    for lo, hi, blk in _gauss_blocks(y, beta, chunk_bytes):
        out[lo:hi] = blk @ v
    return out


def _low_rank(y: FloatArray, beta: float, k: int, chunk_bytes: int, report: Progress,
              total: int) -> tuple[FloatArray, FloatArray]:
    """The ``k`` leading eigenpairs ``(Q, λ)`` of the Gaussian kernel of ``y`` by randomised
    subspace iteration (Halko, Martinsson and Tropp 2011), ``G`` applied block by block;
    only positive eigenvalues are kept."""
    m = y.shape[0]
    rng = np.random.default_rng(0)                  # fixed: the result is deterministic
    q, _ = np.linalg.qr(_kernel_times(y, beta, rng.standard_normal((m, min(m, k + _OVERSAMPLE))),
                                      chunk_bytes))
    for i in range(_POWER_ITERATIONS):
        report(0, total, f"CPD: low-rank kernel, power iteration {i + 1}")
        q, _ = np.linalg.qr(_kernel_times(y, beta, q, chunk_bytes))
    report(0, total, "CPD: low-rank kernel, projection")
    small = q.T @ _kernel_times(y, beta, q, chunk_bytes)
    lam, vec = np.linalg.eigh(0.5 * (small + small.T))
    order = np.argsort(lam)[::-1][:k]
    lam, vec = lam[order], vec[:, order]
    keep = lam > lam[0] * 1e-14 if lam.size and lam[0] > 0 else np.zeros(lam.size, bool)
    return q @ vec[:, keep], lam[keep]


# --- the M-steps ------------------------------------------------------------------------------


class _Undetermined(Exception):
    """The M-step has no unique solution (say why)."""


def _centred_moments(x: FloatArray, y: FloatArray, p1: FloatArray, pt1: FloatArray,
                     px: FloatArray) -> tuple[float, FloatArray, FloatArray, FloatArray,
                                              FloatArray, float]:
    np_ = float(p1.sum())
    if not np_ > 0:
        raise _Undetermined("every target point is taken as an outlier (Np = 0): w is too "
                            "large for how far apart the sets are")
    mux = (pt1 @ x) / np_
    muy = (p1 @ y) / np_
    yh = y - muy
    a = (px - p1[:, None] * mux).T @ yh            # X̂ᵀ Pᵀ Ŷ
    xh = x - mux
    xpx = float(pt1 @ np.einsum("ij,ij->i", xh, xh))
    return np_, mux, muy, yh, a, xpx


def _rigid_step(x: FloatArray, y: FloatArray, p1: FloatArray, pt1: FloatArray,
                px: FloatArray, with_scale: bool) -> tuple[FloatArray, FloatArray, float, float]:
    np_, mux, muy, yh, a, xpx = _centred_moments(x, y, p1, pt1, px)
    d = x.shape[1]
    fit = procrustes(a)
    rot = fit.rotation
    tr_ar = float(fit.trace)
    ypy = float(p1 @ np.einsum("ij,ij->i", yh, yh))
    if not ypy > 0:
        raise _Undetermined("the matched source points coincide (their weighted spread is 0)")
    if with_scale:
        s = tr_ar / ypy
        if not s > 0:
            raise _Undetermined("the scale estimate is not positive (no correlation left "
                                "between the matched sets)")
        sigma2 = (xpx - s * tr_ar) / (np_ * d)
    else:
        s = 1.0
        sigma2 = (xpx - 2.0 * tr_ar + ypy) / (np_ * d)
    t = mux - s * rot @ muy
    return s * rot, t, s, sigma2


def _affine_step(x: FloatArray, y: FloatArray, p1: FloatArray, pt1: FloatArray,
                 px: FloatArray) -> tuple[FloatArray, FloatArray, float]:
    np_, mux, muy, yh, a, xpx = _centred_moments(x, y, p1, pt1, px)
    d: int = x.shape[1]
    ypy = (yh * p1[:, None]).T @ yh
    ev = np.linalg.eigvalsh(ypy)
    if not ev[0] > 1e-12 * max(ev[-1], 0.0) or not ev[-1] > 0:
        raise _Undetermined("the weighted source points span fewer than d dimensions, so "
                            "the affine map is undetermined")
    # A (Ŷᵀ d(P1) Ŷ)⁻¹; float64 (the stubs of solve say any floating)
    b = cast(FloatArray, np.linalg.solve(ypy, a.T).T)
    sigma2 = (xpx - float(np.sum(a * b))) / (np_ * d)
    return b, mux - b @ muy, sigma2


class _Nonrigid:
    """``T(Y) = Y + G W``: the exact kernel (small M) or its leading eigenpairs."""

    def __init__(self, y: FloatArray, beta: float, alpha: float, rank: int | None,
                 chunk_bytes: int, report: Progress, total: int) -> None:
        self.y, self.alpha = y, alpha
        self.w = np.zeros_like(y)
        if rank is None:
            self.g: FloatArray | None = _kernel(y, beta, chunk_bytes)
            self.q = self.lam = None
        else:
            self.g = None
            self.q, self.lam = _low_rank(y, beta, rank, chunk_bytes, report, total)

    def penalty(self) -> float:
        """``tr(Wᵀ G W)``."""
        if self.g is not None:
            return float(np.sum(self.w * (self.g @ self.w)))
        assert self.q is not None and self.lam is not None
        qw = self.q.T @ self.w
        return float(np.sum(qw * qw * self.lam[:, None]))

    def step(self, x: FloatArray, p1: FloatArray, pt1: FloatArray, px: FloatArray,
             sigma2: float) -> tuple[FloatArray, float]:
        np_ = float(p1.sum())
        if not np_ > 0:
            raise _Undetermined("every target point is taken as an outlier (Np = 0): w is "
                                "too large for how far apart the sets are")
        d = x.shape[1]
        rhs = px - p1[:, None] * self.y
        a = self.alpha * sigma2
        if self.g is not None:
            # (d(P1) G + λσ² I) W = PX - d(P1) Y   (eq. 22 of the paper times d(P1))
            mat = p1[:, None] * self.g
            mat[np.diag_indices_from(mat)] += a
            self.w = cast(FloatArray, np.linalg.solve(mat, rhs))  # float64 (stubs: floating)
            ty = self.y + self.g @ self.w
        else:
            # Woodbury with G ≈ Q Λ Qᵀ: W = (B - d(P1) Q (a Λ⁻¹ + Qᵀ d(P1) Q)⁻¹ Qᵀ B) / a
            assert self.q is not None and self.lam is not None
            q, lam = self.q, self.lam
            inner = q.T @ (p1[:, None] * q)
            inner[np.diag_indices_from(inner)] += a / lam
            self.w = (rhs - p1[:, None] * (q @ np.linalg.solve(inner, q.T @ rhs))) / a
            ty = self.y + q @ (lam[:, None] * (q.T @ self.w))
        sigma2 = (float(pt1 @ np.einsum("ij,ij->i", x, x)) - 2.0 * float(np.sum(px * ty))
                  + float(p1 @ np.einsum("ij,ij->i", ty, ty))) / (np_ * d)
        return ty, sigma2


# --- the function ----------------------------------------------------------------------------


def check_sizes(src: FloatArray, dst: FloatArray, model: str, low_rank: int | None
                ) -> int | None:
    """Check the numbers of points against ``model`` and ``low_rank``; return the number of
    eigenpairs of ``G`` to use (None: the exact kernel, or not nonrigid).

    Raises :class:`InvalidInputError` naming ``source``, ``target`` or ``low_rank``."""
    m_pts, d = src.shape
    need = {"rigid": d, "affine": d + 1, "nonrigid": 2}[model]
    why = {"rigid": f"at least one per dimension in {d}-D",
           "affine": f"d + 1 = {d + 1} for an affine map of {d}-D",
           "nonrigid": "two for a shape"}[model]
    check_min_points(src, need, name="source", reason=why)
    check_min_points(dst, need, name="target", reason=why)
    if model != "nonrigid":
        return None
    if low_rank is None:
        return math.ceil(math.sqrt(m_pts)) if m_pts > LOW_RANK_ABOVE else None
    rank = low_rank  # >= 1: checked by the signature
    if rank < m_pts:
        return rank
    if m_pts > EXACT_KERNEL_MAX:
        raise InvalidInputError(
            f"Expected `low_rank` below the number of source points ({m_pts}): the exact "
            f"kernel is offered up to {EXACT_KERNEL_MAX} source points (it takes 16 M² "
            f"bytes), got {rank}.", field="low_rank")
    return None


@validate_params
def cpd(
    source: PointsLike,
    target: PointsLike,
    *,
    model: Model = "rigid",
    scale: bool = True,
    w: Annotated[float, Interval(ge=0, lt=1)] = 0.0,
    beta: Annotated[float, Gt(0)] = 2.0,
    alpha: Annotated[float, Gt(0)] = 2.0,
    low_rank: Annotated[int, Ge(1)] | None = None,
    normalize: bool = True,
    sigma2: Annotated[float, Gt(0)] | None = None,
    max_iterations: Annotated[int, Ge(1)] = 100,
    tolerance: Annotated[float, Ge(0)] = 1e-5,
    progress: Progress | None = None,
) -> CPDResult:
    r"""Register ``source`` onto ``target`` by coherent point drift; no correspondences.

    The moved source points :math:`T(y_m)` are the centroids of an equally weighted Gaussian
    mixture of variance :math:`\sigma^2`, plus a uniform component of weight ``w`` for
    outliers; the target points :math:`x_n` are its data. EM alternates

    - **E-step:** the posterior of centroid :math:`m` for point :math:`n`,

      .. math::

          P_{mn} = \frac{\exp(-\lVert x_n - T(y_m)\rVert^2 / 2\sigma^2)}
          {\sum_k \exp(-\lVert x_n - T(y_k)\rVert^2 / 2\sigma^2) + c}, \qquad
          c = (2\pi\sigma^2)^{d/2}\,\frac{w}{1-w}\,\frac{M}{N};

    - **M-step:** the map and :math:`\sigma^2` minimising
      :math:`\sum_{mn} P_{mn} \lVert x_n - T(y_m)\rVert^2 / 2\sigma^2 + N_P d/2 \log\sigma^2`
      (:math:`N_P = \sum_{mn} P_{mn}`), in closed form for each ``model``:

      - ``rigid``: :math:`T(y) = sRy + t`, with :math:`R` from the SVD of
        :math:`A = \hat X^\mathsf{T} P^\mathsf{T} \hat Y` (reflection fixed) and
        :math:`s = \operatorname{tr}(A^\mathsf{T} R) / \operatorname{tr}(\hat Y^\mathsf{T}
        d(P1) \hat Y)`, or :math:`s = 1` with ``scale=False``;
      - ``affine``: :math:`T(y) = By + t`, :math:`B = A (\hat Y^\mathsf{T} d(P1)
        \hat Y)^{-1}`;
      - ``nonrigid``: :math:`T(Y) = Y + GW`, :math:`G_{ij} = \exp(-\lVert y_i - y_j\rVert^2
        / 2\beta^2)`, with :math:`(d(P1) G + \lambda\sigma^2 I) W = PX - d(P1) Y` (the
        motion coherence regulariser :math:`\tfrac{\lambda}{2}\operatorname{tr}(W^\mathsf{T}
        GW)`; ``alpha`` is the paper's :math:`\lambda`).

    The iterations stop when the relative change of the negative log-likelihood (plus the
    regulariser) falls below ``tolerance``, when σ² reaches rounding level, or after
    ``max_iterations``.

    Parameters
    ----------
    source : (M, d) float array
        The points to move (the mixture's centroids), ``d ≥ 2``.
    target : (N, d) float array
        The points to register onto, same ``d``; ``N`` need not equal ``M`` and no
        correspondence with ``source`` is needed.
    model : {"rigid", "affine", "nonrigid"}, default "rigid"
        The family of maps: ``"rigid"`` a rotation and a translation (and, with ``scale``,
        a uniform scale); ``"affine"`` any linear map and a translation; ``"nonrigid"`` a
        smooth displacement of every source point (Gaussian kernel, motion coherence).
    scale : bool, default True
        Rigid only: estimate the uniform scale ``s`` too (a similarity); False keeps
        ``s = 1``.
    w : float in [0, 1), default 0.0
        The weight of the uniform outlier component, ``0 <= w < 1``: raise it for noise and
        for points of one set missing from the other.
    beta : float > 0, default 2.0
        Nonrigid: the width :math:`\beta` of the Gaussian kernel ``G``; larger is smoother.
        In the units of the normalised sets (unit RMS radius) when ``normalize``, else in
        the points' units.
    alpha : float > 0, default 2.0
        Nonrigid: the regularisation weight :math:`\lambda` of the paper (pycpd's
        ``alpha``); larger keeps the motion closer to a translation.
    low_rank : int >= 1, optional
        Nonrigid: the number ``K`` of leading eigenpairs of ``G`` to use (the paper's fast
        version). Default: the exact kernel up to 1000 source points, else
        ``K = ceil(sqrt(M))`` (the authors' code's default). A value ``≥ M``
        asks for the exact kernel, allowed up to 4000 source points (it takes
        :math:`16M^2` bytes).
    normalize : bool, default True
        Nonrigid: centre each set on its mean and divide it by its RMS radius before
        registering (as the authors' code), so ``beta`` and ``alpha`` need not follow the
        data's units (``sigma2`` stays in squared target units); ``moved`` is returned in
        target units. False: ``beta`` is
        in the points' own units (as pycpd). Rigid and affine results do not depend on it
        (they are computed on centred sets under one common scale, which they commute
        with).
    sigma2 : float > 0, optional
        The initial variance σ² of the mixture, in squared target units. Default: the
        paper's :math:`\sum_{mn}\lVert x_n - y_m\rVert^2 / dMN`, the mean squared
        distance of all pairs per dimension.
    max_iterations : int >= 1, default 100
        The most EM iterations.
    tolerance : float >= 0, default 1e-5
        Stop when the negative log-likelihood changes by less than this fraction in an
        iteration (the relative rule and default of Myronenko and Song's reference code;
        pycpd's ``tolerance``, default 0.001, bounds the absolute change of its objective
        instead, so the two stop at different iterations on the same input).
    progress : callable, optional
        ``progress(done, total, message)`` after every iteration (and during the low-rank
        set-up); it may raise :class:`~algorithms.core.errors.Cancelled` to stop the work.

    Returns
    -------
    CPDResult
        The map (``transform``, ``linear``, ``rotation``, ``scale``, ``translation``: rigid
        and affine), the ``moved`` source points (every model), the final ``sigma2``,
        ``rmse`` to the nearest target points, ``iterations``, ``converged`` and ``reason``.

    Raises
    ------
    InvalidInputError
        Malformed points (not (n, d), ``d < 2``, NaN/Inf), different dimensions, fewer points
        than the model needs (``d`` for rigid, ``d + 1`` for affine, 2 for nonrigid), ``w``
        outside [0, 1), a non-positive ``beta``, ``alpha`` or ``sigma2``, an exact kernel
        asked for more than 4000 source points, an unknown ``model``.
    DegenerateInputError
        Rigid: a set spans fewer than ``d - 1`` dimensions (the rotation is undetermined);
        affine: fewer than ``d`` (the affine map is).
    Cancelled
        Raised by ``progress``.

    Warns
    -----
    ConvergenceWarning
        When ``converged`` is False.

    Notes
    -----
    **Memory.** The M×N posterior is never stored. Each E-step visits the target in blocks
    of ``r = ⌊CHUNK_BYTES / 8M⌋`` points (256 MB by default: 1677 points against 20,000
    source points) and accumulates :math:`P1`, :math:`P^\mathsf{T}1`, :math:`PX` and the
    log-likelihood from one reused ``r × M`` buffer (plus a quarter of it for the rows
    recomputed, below), so the working memory is at most ``1.25 CHUNK_BYTES`` plus
    :math:`O((M + N) d)`: 20,000 × 20,000 points take about 330 MB, whatever the size, where
    the full matrix would take 3.2 GB and pycpd's float64 difference tensor 9.6 GB.
    Nonrigid adds the kernel: exact :math:`16M^2` bytes up to 1000 points (16 MB), else
    :math:`K` eigenvectors (:math:`8MK` bytes: 23 MB for M = 20,000), found by randomised
    subspace iteration with ``G`` applied in blocks of the same size (four passes over ``G``,
    never stored); each M-step then costs :math:`O(MK^2)` by the Woodbury identity instead
    of an :math:`O(M^3)` solve.

    **Cost.** While σ is large, :math:`MN` exponentials per iteration (the dominating cost)
    and :math:`O(MNd)` for two block products. Once σ is small against the sets, the target
    is visited in compact groups of 32 points (median splits) and each group meets only the
    source points within :math:`\sigma\sqrt{2(\ln M + 45)}` of it (a kd-tree ball query):
    what is left out is below :math:`e^{-45}`, under 1e-16 of every row kept; rows where it
    could matter, and rows whose sum underflows, are recomputed against every source point
    shifted by their largest exponent, so the posterior stays exact to rounding (never set
    to zero, as a plain implementation does once σ² is small). Squared distances are
    :math:`\lVert x\rVert^2 + \lVert t\rVert^2 - 2x\cdot t`, clipped at 0, on centred and
    scaled coordinates; exponents are clipped at -700 (libm's underflow path is slow).

    **Conventions.** ``source`` moves onto ``target`` (the paper's :math:`Y` and :math:`X`).
    The iterations start with the centroids of the two sets aligned (each set is centred, as
    in the authors' code; pycpd starts from the raw positions). The negative
    log-likelihood, up to a constant, is
    :math:`-\sum_n \log(\sum_m e^{-a_{mn}} + c) + \tfrac{Nd}{2}\log\sigma^2`, computed in
    each E-step; the stopping rule compares two successive values, as the authors' code.
    CPD is a local method: rotations beyond about 60-70° may end in a wrong minimum.

    References
    ----------
    .. [1] A. Myronenko and X. Song, "Point set registration: coherent point drift", IEEE
       TPAMI 32(12), 2262-2275, 2010. arXiv:0905.2635.
    .. [2] N. Halko, P.-G. Martinsson and J. A. Tropp, "Finding structure with randomness",
       SIAM Review 53(2), 217-288, 2011 (the eigenpairs of ``G``).

    Examples
    --------
    >>> import numpy as np
    >>> from algorithms.registration import cpd
    >>> src = np.array([[0.0, 0.0], [4.0, 0.0], [0.0, 2.0], [1.0, 1.0], [3.0, 2.5]])
    >>> c, s = np.cos(0.3), np.sin(0.3)
    >>> dst = 1.5 * src[::-1] @ np.array([[c, -s], [s, c]]).T + [0.3, -0.2]
    >>> res = cpd(src, dst)
    >>> res.converged, round(res.scale, 9)
    (True, 1.5)
    >>> bool(np.allclose(res.rotation, [[c, -s], [s, c]]))
    True
    """
    report = as_progress(progress)
    src = as_points(source, name="source", min_dim=2)
    dst = as_points(target, name="target", min_dim=2)
    same_dim(src, dst, names=("source", "target"))
    m_pts, d = src.shape
    n_pts = dst.shape[0]
    rank = check_sizes(src, dst, model, low_rank)
    if model == "rigid":
        check_span(src, "source", d - 1, "the rotation is undetermined")
        check_span(dst, "target", d - 1, "the rotation is undetermined")
    elif model == "affine":
        check_span(src, "source", d, "the affine map is undetermined")

    # Centre each set; scale both by the target's RMS radius (rigid, affine, nonrigid
    # without normalize: the maps commute with it) or each by its own (nonrigid normalize).
    mu_x, mu_y = dst.mean(axis=0), src.mean(axis=0)
    x, y = dst - mu_x, src - mu_y
    rx = math.sqrt(float(np.einsum("ij,ij->", x, x)) / n_pts)
    ry = math.sqrt(float(np.einsum("ij,ij->", y, y)) / m_pts)
    sx = rx or ry or 1.0
    sy = (ry or sx) if (model == "nonrigid" and normalize) else sx
    x, y = x / sx, y / sy
    if model == "nonrigid" and not normalize:
        beta = beta / sx            # the same kernel in scaled units
        alpha = alpha * sx * sx     # λσ² unchanged

    if sigma2 is None:
        # Σ_mn |x_n - y_m|² = M Σ|x|² + N Σ|y|² - 2 (Σx)·(Σy), without the M×N pairs
        sq = (m_pts * float(np.einsum("ij,ij->", x, x))
              + n_pts * float(np.einsum("ij,ij->", y, y))
              - 2.0 * float(x.sum(axis=0) @ y.sum(axis=0))) / (d * m_pts * n_pts)
        s2 = max(sq, SIGMA2_FLOOR)
    else:
        s2 = sigma2 / (sx * sx)
    log_w = -math.inf if w == 0.0 else math.log(w / (1.0 - w)) + math.log(m_pts / n_pts)

    posterior = _Posterior(x, m_pts, CHUNK_BYTES)
    nonrigid = (_Nonrigid(y, beta, alpha, rank, CHUNK_BYTES, report, max_iterations)
                if model == "nonrigid" else None)
    linear, shift, s_est = np.eye(d), np.zeros(d), 1.0
    ty = y
    previous = math.nan
    converged, reason = False, f"max_iterations = {max_iterations} reached before the " \
        "tolerance was met"
    k = 0
    # The thread policy (algorithms.core.threads): one BLAS thread for the E-step, whose
    # partitions run on threads of their own, and for the thin products of the rigid and
    # affine M-steps; the nonrigid M-step's M × M solve keeps BLAS's threads.
    with contextlib.nullcontext() if model == "nonrigid" else single_blas_thread():
        for k in range(1, max_iterations + 1):
            log_c = 0.5 * d * math.log(2.0 * math.pi * s2) + log_w
            with single_blas_thread():
                p1, pt1, px, log_den = posterior(ty, s2, log_c)
            objective = -log_den + 0.5 * n_pts * d * math.log(s2)
            if nonrigid is not None:
                objective += 0.5 * nonrigid.alpha * nonrigid.penalty()
            change = abs(objective - previous) / abs(objective) if objective != 0 else 0.0
            previous = objective
            try:
                if model == "rigid":
                    linear, shift, s_est, new_s2 = _rigid_step(x, y, p1, pt1, px, scale)
                    ty = y @ linear.T + shift
                elif model == "affine":
                    linear, shift, new_s2 = _affine_step(x, y, p1, pt1, px)
                    ty = y @ linear.T + shift
                else:
                    assert nonrigid is not None
                    ty, new_s2 = nonrigid.step(x, p1, pt1, px, s2)
            except (_Undetermined, np.linalg.LinAlgError) as err:
                k -= 1
                reason = f"the M-step of iteration {k + 1} is undetermined: {err}"
                break
            report(k, max_iterations, f"CPD iteration {k}: sigma² {new_s2 * sx * sx:.6g}")
            if not new_s2 > SIGMA2_FLOOR:
                s2 = SIGMA2_FLOOR
                converged, reason = True, "sigma² at rounding level (exact fit)"
                break
            s2 = new_s2
            if change < tolerance:
                converged = True
                reason = (f"relative change of the negative log-likelihood {change:.3g} below "
                          f"tolerance {tolerance:g}")
                break

    moved = ty * sx + mu_x
    tree = cKDTree(dst)
    dist, _ = cast(KnnQuery, tree.query(moved, workers=query_workers(m_pts)))
    rmse = math.sqrt(float(dist @ dist) / m_pts)
    if not converged:
        warn(f"CPD did not converge: {reason}.", ConvergenceWarning)
    if model == "nonrigid":
        return CPDResult(None, None, None, None, None, moved, s2 * sx * sx, rmse, k,
                         converged, reason)
    # x = mu_x + sx (L (y - mu_y) / sx + t)  =  L y + (mu_x - L mu_y + sx t)
    translation = mu_x - linear @ mu_y + sx * shift
    transform = np.eye(d + 1)
    transform[:d, :d] = linear
    transform[:d, d] = translation
    rotation = linear / s_est if model == "rigid" else None
    return CPDResult(transform, linear.copy(), rotation,
                     float(s_est) if model == "rigid" else None, translation.copy(),
                     moved, s2 * sx * sx, rmse, k, converged, reason)
