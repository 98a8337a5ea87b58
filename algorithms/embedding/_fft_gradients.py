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
there would be in :math:`y_i \sum_j K_2 - \sum_j K_2 y_j`). A uniform grid of nodes
spaced :math:`h = 1/3` (openTSNE's spacing: 3 nodes in a box of side 1; at least 200 nodes
per dimension, a smaller embedding gets a power-of-two fraction of :math:`h`) covers the
bounding box of the points:

1. each point's charge is spread onto the :math:`p^d` nodes nearest it, :math:`p = 4` per
   dimension, with the Lagrange polynomials of its position (the transpose of
   interpolation);
2. the kernel between grid nodes is a Toeplitz matrix: the node potentials are a discrete
   convolution, done by FFT on a zero-padded (circulant) grid;
3. the potentials are interpolated back to the points with the same Lagrange weights.

Why the nearest nodes, not those of the point's box. FIt-SNE and openTSNE cut the grid into
boxes of :math:`p` nodes and interpolate each point from its own box's nodes, so a point
near a box's edge sits outside its nodes' span, where Lagrange interpolation degrades: the
error factor :math:`\prod_k (t - t_k)` reaches :math:`6.6\,h^4` there (nodes at
:math:`t_k = 0, h, 2h, 3h`, the point at :math:`-h/2`) but at most :math:`0.56\,h^4` for a
point in the middle interval, where the nearest nodes put every point (except within two
spacings of the grid's ends, where the stencil stops at the last node). The same four
nodes per dimension and the same grid cost, 2.5-3× less error in the repulsion at a given
spacing: enough to widen the spacing from :math:`1/4` (the box stencils with 4 nodes) to
:math:`1/3` with both a smaller grid and a better final KL (the figures are at
:data:`NODE_SPACING`).

The spread charge of a point interacts with itself on the grid:
:math:`\sum_{a,b} w_{ia} K_1(x_a - x_b) w_{ib}` over its stencil's nodes :math:`x_a`, not
exactly :math:`K_1(0) = 1` where the interpolation is not exact. :math:`Z` removes that
term itself, point by point (a :math:`p^d \times p^d` matrix, the same for every point),
rather than :math:`n`: on sparse embeddings (points a few units apart) this cuts the
relative error of :math:`Z` from :math:`10^{-3}`–:math:`10^{-2}` to about
:math:`10^{-4}`. The repulsion needs no such term: :math:`G` is odd, so
:math:`w_i^\mathsf{T} G\, w_i = 0`.

Only the ``d`` components of :math:`G` are transformed back: :math:`\sum_i \phi_{K_1}(y_i)`
is the inner product of the grid charges with their convolution by :math:`K_1`, which
Parseval's identity gives from the charges' transform already at hand,
:math:`Z + s = m^{-d} \sum_f \hat K_1(f)\, \lvert \hat c(f) \rvert^2` (``m`` the padded
grid side; the zero padding makes the circular convolution the linear one on the
nodes; ``s`` the self-interactions below). So one forward and ``d`` inverse transforms per
evaluation, where four separate convolutions would need four of each. The number of nodes
is rounded up to a 5-smooth
integer (the FFT lengths, twice the nodes, are then pocketfft's fastest), and in two
dimensions the column transforms skip the empty half of the padded grid (forward) and
the rows never read (inverse). Each kernel is even or odd along each axis, so its
transform is kept as one real quarter of the spectrum (:func:`_kernels`, by type-I DCTs
and DSTs), and the inverse transforms go by bands of columns: an evaluation holds about
three grids of the charges' transform, no more (a 2,000-point run's grid of about 300
nodes a side: under 1 MB of kernels kept, where up to four grids of 6 MB each would be
cached). A loop
of evaluations holds an :class:`FFTRepulsion`, which keeps the last grid's kernels.

Cost :math:`O(n p^d + N^d \log N)` per evaluation, :math:`N` the grid nodes per dimension.
Everything is numpy (``bincount`` to spread, ``take`` to gather, ``scipy.fft``),
with no per-point Python loop; the result is deterministic.
"""

from __future__ import annotations

import functools
from collections.abc import Callable

import numpy as np
import scipy.fft as sfft

from algorithms.core.types import FloatArray, IntArray

__all__ = ["FFTRepulsion", "repulsion_fft"]

#: Interpolation nodes per point and dimension: the ``p`` grid nodes nearest the point
#: (cubic Lagrange interpolation for 4).
N_INTERPOLATION = 4
#: Node spacing of the grid (openTSNE's: 3 nodes in a box of side 1), and its fewest nodes
#: per dimension (a smaller embedding gets a spacing of a power-of-two fraction of it).
#: Measured on 2,000 points in 20 clusters in 50-D (median of 3 seeds run twice, the same
#: P and start, one thread; times relative to the box stencils in the same run): the box
#: stencils these replaced (4 nodes per box of side 1, spacing 1/4) end at KL 0.825; the
#: nearest nodes at spacing 1/4 at 0.809 (time 1.10×), at 0.3 at 0.811 (0.87×), at 1/3 at
#: 0.812 (0.76×; 0.82× with the self-interaction term of Z); the exact repulsion at 0.807
#: and openTSNE's default there (Barnes-Hut below 10,000 points) at 0.815. 10,000 points
#: (2 seeds): 2.171 -> 2.163, time 0.91×; 30,000 (1 seed): 3.183 -> 3.178, 0.97×. The
#: final embedding of the more accurate repulsion is about 10 % wider (its grid with it).
NODE_SPACING = 1.0 / 3.0
MIN_NODES = 200
#: Cells of the spectrum handled at once after the forward transform (the temporaries).
_BAND_CELLS = 1 << 15
#: Fewest columns of a band (the transforms of narrower ones cost more than they save).
_BAND_MIN = 32


@functools.lru_cache(maxsize=1)
def _smooth_numbers(limit: int = 1 << 16) -> np.ndarray:
    """The 5-smooth integers (no prime factor above 5) up to ``limit``, ascending."""
    out = []
    a = 1
    while a <= limit:
        b = a
        while b <= limit:
            c = b
            while c <= limit:
                out.append(c)
                c *= 5
            b *= 3
        a *= 2
    return np.array(sorted(out), dtype=np.int64)


def _smooth_ceil(needed: int) -> int:
    """The smallest 5-smooth integer ``>= needed`` (then every FFT length, twice the
    nodes, is 5-smooth too: pocketfft's fastest)."""
    smooth = _smooth_numbers()
    if needed > smooth[-1]:
        return int(needed)
    return int(smooth[np.searchsorted(smooth, needed)])


def _grid(span: float) -> tuple[float, int]:
    """Node spacing and node count per dimension for an embedding of extent ``span``:
    spacing ``NODE_SPACING`` (at least ``MIN_NODES`` nodes; a smaller embedding gets a
    power-of-two fraction of it), node 0 at the lowest point, the last node at or beyond
    the highest. The count is rounded up to a 5-smooth number, so the grid (and with it the
    kernels' cached transforms) changes only now and then."""
    h = NODE_SPACING
    if span < MIN_NODES * NODE_SPACING:
        h *= 2.0 ** np.ceil(np.log2(max(span, 1e-12) / (MIN_NODES * NODE_SPACING)))
    return h, _smooth_ceil(max(int(span / h) + 2, N_INTERPOLATION))


def _stencils(t: FloatArray, p: int, nodes: int) -> tuple[IntArray, FloatArray]:
    """The first of the ``p`` consecutive nodes each position uses, and their Lagrange
    weights; ``t`` in node spacings from node 0 (``0 <= t <= nodes - 1``). The nodes are
    the ``p`` nearest ones, the position in their middle interval (even ``p``) or within
    half a spacing of the middle node (odd ``p``), except within ``p / 2`` spacings of
    either end of the grid, where the stencil stops at the end node."""
    first = np.clip(np.floor(t - (p - 2) / 2), 0, nodes - p)
    return first.astype(np.intp), _lagrange(t - first, p)


def _lagrange(s: FloatArray, p: int) -> FloatArray:
    """Lagrange basis values at ``s`` for the ``p`` nodes ``0, 1, …, p - 1``; shape
    ``(n, p)``."""
    diff = s[None, :] - np.arange(p, dtype=np.float64)[:, None]       # (p, n)
    out = np.empty((p, s.shape[0]))
    for k in range(p):
        others = [j for j in range(p) if j != k]
        scale = 1.0 / float(np.prod([k - j for j in others]))
        acc = np.multiply(diff[others[0]], scale, out=out[k])
        for j in others[1:]:
            acc *= diff[j]
    return out.T


def _kernels(d: int, nodes_1d: int, spacing: float) -> tuple[np.ndarray, np.ndarray]:
    r"""The kernels' transforms on the circulant grid of node offsets (side
    ``m = 2 N``, ``N = nodes_1d``; zero at the offset ``N``), at the frequencies
    :math:`0 \le u, v \le N` only (a quarter of the spectrum, the rest by symmetry,
    :func:`_spectrum_band`), both float32 (single precision, as the transforms):

    - ``g``: :math:`\operatorname{Im} \hat G_0(u, v)` for the first component
      :math:`G_0(\delta) = K_1(\delta)^2 \delta_0`. It is odd in its own axis and even
      in the other, so its transform is imaginary, odd in ``u`` and even in ``v``; the
      second component is its transpose, :math:`\hat G_1(u, v) = \hat G_0(v, u)`.
    - ``w``: the weights :math:`\hat K_1(f)\, c(f) / m^d` that give :math:`Z` from the
      power :math:`\lvert \hat c(f) \rvert^2` of the charges' transform by Parseval,
      :math:`c(f)` counting each column of ``rfftn``'s half spectrum with its mirror
      (:math:`K_1` even: its transform is real and even).

    So the transforms are real ones of the quarter grid (type-I DCT for an even axis,
    type-I DST for an odd one): a quarter of the memory of one complex grid, and no
    complex grid at all while they are made. In 1-D ``g`` and ``w`` have ``N + 1``
    entries (``rfft``'s half spectrum)."""
    a = np.arange(nodes_1d + 1)
    off = (a * spacing).astype(np.float32)           # offsets 0 … N (N: the padding's)
    sq = off * off
    scale = np.full(nodes_1d + 1, 2.0)
    scale[0] = scale[-1] = 1.0                       # the columns without a mirror
    scale = (scale / float(2 * nodes_1d) ** d).astype(np.float32)
    if d == 1:
        k1 = 1.0 / (1.0 + sq)
        k1[nodes_1d] = 0.0
        odd = k1 * k1 * off
        g = np.zeros(nodes_1d + 1, dtype=np.float32)
        g[1:nodes_1d] = -sfft.dst(odd[1:nodes_1d], type=1)
        w = sfft.dct(k1, type=1) * scale
    else:
        k1 = sq[:, None] + sq[None, :]
        k1 += 1.0
        np.reciprocal(k1, out=k1)
        k1[nodes_1d, :] = k1[:, nodes_1d] = 0.0
        w = sfft.dct(sfft.dct(k1, type=1, axis=0), type=1, axis=1)
        w *= scale                                   # by column
        odd = k1[1:nodes_1d]                         # K1² δ_0, rows 1 … N - 1 (0 elsewhere)
        odd *= odd
        odd *= off[1:nodes_1d, None]
        g = np.zeros((nodes_1d + 1, nodes_1d + 1), dtype=np.float32)
        g[1:nodes_1d] = -sfft.dst(sfft.dct(odd, type=1, axis=1), type=1, axis=0)
    g.setflags(write=False)
    w.setflags(write=False)
    return g, w


def _spectrum_band(quarter: np.ndarray, cols: slice, sign: float, transpose: bool
                   ) -> np.ndarray:
    """Columns ``cols`` of a 2-D kernel's ``rfftn`` half spectrum (all ``m`` rows) from
    its quarter (:func:`_kernels`): rows ``u > N`` mirror rows ``m - u`` times ``sign``
    (−1: odd in ``u``); with ``transpose`` the spectrum is the quarter's transpose
    (the second component of ``G``, even in ``u``)."""
    nodes_1d = quarter.shape[0] - 1
    part = quarter[cols].T if transpose else quarter[:, cols]         # (N + 1, w)
    band = np.empty((2 * nodes_1d, part.shape[1]), dtype=np.float32)
    band[:nodes_1d + 1] = part
    np.multiply(part[nodes_1d - 1:0:-1], sign, out=band[nodes_1d + 1:])
    return band


class FFTRepulsion:
    """:func:`repulsion_fft` with the kernels' transforms of the last grid kept: the grid
    grows with the embedding and changes only now and then (2,000 points, 750 steps: 62
    grids, each used for a run of steps, never again after the next), so one grid is
    kept, and only for the life of this object (one t-SNE run): the cache is not a
    module's, holding memory after the run."""

    def __init__(self) -> None:
        self._key: tuple[int, int, float] | None = None
        self._kernels: tuple[np.ndarray, np.ndarray] | None = None

    def kernels(self, d: int, nodes_1d: int, spacing: float
                ) -> tuple[np.ndarray, np.ndarray]:
        """:func:`_kernels` of this grid, from the cache if it is the last one's."""
        key = (d, nodes_1d, spacing)
        if self._key != key or self._kernels is None:
            self._kernels = None                     # the old grid freed before the new
            self._kernels, self._key = _kernels(d, nodes_1d, spacing), key
        return self._kernels

    def __call__(self, y: FloatArray) -> tuple[FloatArray, float]:
        """:func:`repulsion_fft` of ``y``."""
        return _repulsion(y, self.kernels)


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

    A loop of evaluations (an optimisation) should hold an :class:`FFTRepulsion`, which
    keeps the kernels of the last grid.
    """
    return _repulsion(y, _kernels)


def _repulsion(y: FloatArray, kernels: Callable[[int, int, float],
                                                tuple[np.ndarray, np.ndarray]]
               ) -> tuple[FloatArray, float]:
    """:func:`repulsion_fft` with the grid's kernels from ``kernels``."""
    n, d = y.shape
    p = N_INTERPOLATION
    lo = y.min(axis=0)
    span = float((y.max(axis=0) - lo).max())
    spacing, nodes_1d = _grid(span)
    m = 2 * nodes_1d
    g_im, z_weights = kernels(d, nodes_1d, spacing)

    # per dimension: the first node of each point's stencil and its Lagrange weights; one
    # flat index into the N^d nodes spreads the charges and reads the potentials (the zero
    # padding to m per axis is the transforms')
    lks, firsts = [], []
    for k in range(d):
        first, lk = _stencils((y[:, k] - lo[k]) * (1.0 / spacing), p, nodes_1d)
        lks.append(lk)                                               # (n, p)
        firsts.append(first)
    if d == 1:
        weights = lks[0]
        flat = firsts[0][:, None] + np.arange(p)
    else:
        weights = np.repeat(lks[0], p, axis=1)
        weights *= np.tile(lks[1], (1, p))                           # (n, p²): [a p + b]
        offsets = (np.arange(p)[:, None] * nodes_1d + np.arange(p)[None, :]).ravel()
        flat = (firsts[0] * nodes_1d + firsts[1])[:, None] + offsets
    charges = np.bincount(flat.ravel(), weights=weights.ravel(), minlength=nodes_1d ** d
                          ).astype(np.float32).reshape((nodes_1d,) * d)
    # remove each point's interaction with itself as the grid sees it: w_i^T K1 w_i over
    # its stencil's nodes (1 where the interpolation is exact)
    offs = np.indices((p,) * d).reshape(d, -1).T * spacing                  # (p^d, d)
    k_st = 1.0 / (1.0 + ((offs[:, None, :] - offs[None, :, :]) ** 2).sum(-1))
    z = -float(np.einsum("ia,ia->", weights @ k_st, weights))
    rep = np.empty((n, d))
    if d == 1:
        c_hat = sfft.rfft(charges, n=m)
        z += float(np.dot(z_weights, np.square(np.abs(c_hat), dtype=np.float64)))
        line = sfft.irfft(1j * g_im * c_hat, n=m)[:nodes_1d]
        rep[:, 0] = np.einsum("ij,ij->i", line.take(flat), weights, dtype=np.float64)
        return rep, z
    # pruned: the column transforms skip the empty rows
    rows_hat = sfft.rfft(charges, n=m, axis=1)
    del charges
    c_hat = sfft.fft(rows_hat, n=m, axis=0)                             # (m, N + 1)
    del rows_hat
    # Z by Parseval, then each component's inverse transform (the columns first, keeping
    # only the rows that are read), in bands of columns of the spectrum: the
    # temporaries are bands, not grids
    step = max(_BAND_MIN, _BAND_CELLS // m)
    for s in range(0, nodes_1d + 1, step):
        cs = c_hat[:, s:s + step]
        power = np.square(cs.real, dtype=np.float64)    # summed in double precision
        power += np.square(cs.imag, dtype=np.float64)
        band = _spectrum_band(z_weights, slice(s, s + step), 1.0, False)
        z += float(np.dot(band.ravel(), power.ravel()))
    for k in range(2):
        half = np.empty((nodes_1d, nodes_1d + 1), dtype=np.complex64)
        for s in range(0, nodes_1d + 1, step):
            cols = slice(s, s + step)
            prod = c_hat[:, cols] * _spectrum_band(g_im, cols, -1.0 if k == 0 else 1.0,
                                                   k == 1)
            prod *= 1j                                  # the transform of G: imaginary
            half[:, cols] = sfft.ifft(prod, axis=0, overwrite_x=True)[:nodes_1d]
        pots = sfft.irfft(half, n=m, axis=1)[:, :nodes_1d].ravel()     # (N × N)
        del half
        rep[:, k] = np.einsum("ij,ij->i", pots.take(flat), weights, dtype=np.float64)
        del pots
    return rep, z
