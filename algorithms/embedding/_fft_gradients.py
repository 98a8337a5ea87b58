r"""The repulsive forces of t-SNE by FFT-accelerated interpolation (Linderman et al. 2019,
FIt-SNE; openTSNE's ``negative_gradient_method="fft"``), in 1 and 2 dimensions.

The repulsive part of the t-SNE gradient needs, for every point :math:`i`, sums over all
other points of the Cauchy kernel :math:`K_1(y_i, y_j) = (1 + \lVert y_i - y_j\rVert^2)^{-1}`
and of its square :math:`K_2 = K_1^2`:

.. math::

   Z = \sum_{i \ne j} K_1(y_i, y_j), \qquad
   r_i = \sum_{j} K_2(y_i, y_j) (y_i - y_j) = y_i \sum_j K_2(y_i, y_j) - \sum_j K_2(y_i, y_j) y_j.

Both are sums :math:`\phi(y_i) = \sum_j K(y_i, y_j)\, q_j` of a smooth kernel against
charges :math:`q_j = 1`, for the kernels :math:`K_1` and :math:`G(\delta) = K_2(\delta)\,
\delta` (one scalar and ``d`` vector components: no cancellation between large terms, as
there would be in :math:`y_i \sum_j K_2 - \sum_j K_2 y_j`). The bounding box of the points
is cut into boxes of side 1 (at least 50 per dimension; a smaller embedding gets boxes
of a power-of-two fraction of 1), each with :math:`p = 4` equispaced interpolation nodes
per dimension, so that all nodes form one uniform grid:

1. each point's charges are spread onto the :math:`p^d` nodes of its box with the
   Lagrange polynomials of its position (the transpose of interpolation);
2. the kernel between grid nodes is a Toeplitz matrix: the node potentials are a discrete
   convolution, done by FFT on a zero-padded (circulant) grid;
3. the potentials are interpolated back to the points with the same Lagrange weights.

Cost :math:`O(n p^d + N^d \log N)` per evaluation, :math:`N` the grid nodes per dimension.
Everything is numpy (``bincount`` to spread, fancy indexing to gather, ``scipy.fft``),
with no per-point Python loop; the result is deterministic.
"""

from __future__ import annotations

import functools

import numpy as np
import scipy.fft as sfft

from algorithms.core.types import FloatArray

__all__ = ["repulsion_fft"]

#: Interpolation nodes per box and dimension. FIt-SNE and openTSNE use 3; with this
#: module's kernels 3 nodes leave a median error of 3.5 % in the repulsion of a digits
#: embedding and a 3-4 % higher final KL, 4 nodes 1 % and about 1 % (5: 0.3 %, 1.7× the grid).
N_INTERPOLATION = 4
#: Fewest boxes per dimension, and the box side (openTSNE's defaults).
MIN_BOXES = 50
BOX_SIDE = 1.0


def _lagrange(t: FloatArray, p: int) -> FloatArray:
    """Lagrange basis values at ``t`` (positions in box units, in [0, 1]) for the ``p``
    nodes at ``(k + 1/2) / p``; shape ``(n, p)``."""
    nodes = (np.arange(p) + 0.5) / p
    out = np.ones((t.shape[0], p))
    for k in range(p):
        for m in range(p):
            if m != k:
                out[:, k] *= (t - nodes[m]) / (nodes[k] - nodes[m])
    return out


def _kernels_hat(d: int, m: int, nodes_1d: int, spacing: float) -> np.ndarray:
    """FFT of the kernels K1 and K1² δ on the circulant grid of node offsets, zero on the
    padding; single precision (the convolutions run 2-3× faster and the interpolation's
    own error is far larger). Cached: the grids change only now and then."""
    return _kernels_hat_cached(d, m, nodes_1d, spacing)


def _kernels_hat_fresh(d: int, m: int, nodes_1d: int, spacing: float) -> np.ndarray:
    off = np.arange(m)
    off = np.where(off < nodes_1d, off, off - m).astype(np.float64)
    inside = np.abs(off) < nodes_1d
    off *= spacing
    if d == 1:
        grids, mask = [off], inside
    else:
        grids = [np.broadcast_to(off[:, None], (m, m)), np.broadcast_to(off[None, :], (m, m))]
        mask = inside[:, None] & inside[None, :]
    k1 = np.where(mask, 1.0 / (1.0 + sum(g * g for g in grids)), 0.0)
    k2 = k1 * k1
    kernels = np.stack([k1] + [k2 * g for g in grids]).astype(np.float32)
    out = sfft.rfftn(kernels, s=(m,) * d, axes=tuple(range(1, d + 1)))
    out.setflags(write=False)
    return out


_kernels_hat_cached = functools.lru_cache(maxsize=3)(_kernels_hat_fresh)


def repulsion_fft(y: FloatArray) -> tuple[FloatArray, float]:
    """Repulsive sums of t-SNE by FFT interpolation.

    Parameters
    ----------
    y : (n, d) float array, d in {1, 2}
        The embedding.

    Returns
    -------
    rep : (n, d) float array
        :math:`r_i = \\sum_j K_2(y_i, y_j)(y_i - y_j)` (not yet divided by ``Z``).
    z : float
        :math:`Z = \\sum_{i \\ne j} K_1(y_i, y_j)`.
    """
    n, d = y.shape
    p = N_INTERPOLATION
    lo = y.min(axis=0)
    span = float((y.max(axis=0) - lo).max())
    # boxes of side 1 (at least MIN_BOXES of them); a smaller embedding gets boxes of a
    # power-of-two fraction of 1, and the count is rounded up to a multiple of 8, so the
    # grid, and with it the kernels' transforms (cached), changes only now and then
    side = BOX_SIDE
    if span < MIN_BOXES * BOX_SIDE:
        side *= 2.0 ** np.ceil(np.log2(max(span, 1e-12) / (MIN_BOXES * BOX_SIDE)))
    boxes = -(-(int(span / side) + 1) // 8) * 8
    nodes_1d = boxes * p
    spacing = side / p

    # per dimension: box index, Lagrange weights, node index along that dimension
    weights = np.ones((n, 1))
    flat = np.zeros((n, 1), dtype=np.int64)
    for k in range(d):
        u = (y[:, k] - lo[k]) / side
        b = np.minimum(u.astype(np.int64), boxes - 1)
        lk = _lagrange(u - b, p)                                   # (n, p)
        ik = b[:, None] * p + np.arange(p)[None, :]                # (n, p)
        weights = (weights[:, :, None] * lk[:, None, :]).reshape(n, -1)
        flat = (flat[:, :, None] * nodes_1d + ik[:, None, :]).reshape(n, -1)
    idx = flat.ravel()
    size = nodes_1d ** d

    # one charge (1 per point) spread onto the grid
    charges = np.bincount(idx, weights=weights.ravel(), minlength=size)
    charges = charges.reshape((nodes_1d,) * d)

    m = sfft.next_fast_len(2 * nodes_1d - 1, real=True)
    k_hat = _kernels_hat(d, m, nodes_1d, spacing)
    c32 = charges.astype(np.float32)
    if d == 1:
        pots = sfft.irfft(k_hat * sfft.rfft(c32, n=m)[None], n=m, axis=-1)[:, :nodes_1d]
    else:
        # pruned 2-D transforms: only the nodes_1d rows that hold charges (forward) and
        # the nodes_1d rows that are read (inverse) go through the row transforms
        c_hat = sfft.fft(sfft.rfft(c32, n=m, axis=1), n=m, axis=0)
        prod = k_hat * c_hat[None]
        rows = sfft.ifft(prod, axis=1)[:, :nodes_1d]
        pots = sfft.irfft(rows, n=m, axis=2)[:, :, :nodes_1d]
    pots = pots.reshape(d + 1, size).astype(np.float64)

    # back to the points: (d + 1, n)
    phi = np.einsum("cnj,nj->cn", pots[:, flat], weights)
    z = float(phi[0].sum() - n)                      # remove K1(y_i, y_i) = 1
    rep = np.ascontiguousarray(phi[1:].T)
    return rep, z
