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

Only the ``d`` components of :math:`G` are transformed back: :math:`\sum_i \phi_{K_1}(y_i)`
is the inner product of the grid charges with their convolution by :math:`K_1`, which
Parseval's identity gives from the charges' transform already at hand,
:math:`Z + n = m^{-d} \sum_f \hat K_1(f)\, \lvert \hat c(f) \rvert^2` (``m`` the padded
grid side; the zero padding makes the circular convolution the linear one on the
nodes). So one forward and ``d`` inverse transforms per evaluation, where four separate
convolutions would need four of each. The number of boxes is rounded up to a 5-smooth
integer (the FFT lengths, twice the nodes, are then pocketfft's fastest), and in two
dimensions the column transforms skip the empty half of the padded grid (forward) and
the rows never read (inverse). Each kernel is even or odd along each axis, so its
transform is kept as one real quarter of the spectrum (:func:`_kernels`, by type-I DCTs
and DSTs), and the inverse transforms go by bands of columns: an evaluation holds about
three grids of the charges' transform, no more (a 2,000-point run's grid of 384 nodes a
side: 1.2 MB of kernels kept, where up to four grids of 9.5 MB each were cached). A loop
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

from algorithms.core.types import FloatArray

__all__ = ["FFTRepulsion", "repulsion_fft"]

#: Interpolation nodes per box and dimension. FIt-SNE and openTSNE use 3. On a final
#: 2,000-point embedding (20 clusters in 50-D) the repulsion's median relative error is
#: 1.4 % with 3 nodes (openTSNE's own FFT: 1.0 %), 0.4 % with 4, 0.1 % with 5 (1.6× the
#: grid). The final KL of that case (median of 3 seeds, the same P and start) follows the
#: repulsion's accuracy: 0.845 with 3 nodes, 0.827 with 4, 0.813 with 5, 0.807 with the
#: exact repulsion (an exact Z alone changes nothing: 0.843 with 3 nodes); openTSNE's own
#: 3-node FFT inside our descent 0.826, openTSNE's default there (Barnes–Hut below 10,000
#: points) 0.815.
N_INTERPOLATION = 4
#: Fewest boxes per dimension, and the box side (openTSNE's defaults).
MIN_BOXES = 50
BOX_SIDE = 1.0
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


def _box_count(needed: int) -> int:
    """The smallest 5-smooth integer ``>= needed`` (then every FFT length, twice the
    nodes, is 5-smooth too: pocketfft's fastest)."""
    smooth = _smooth_numbers()
    if needed > smooth[-1]:
        return int(needed)
    return int(smooth[np.searchsorted(smooth, needed)])


def _grid(span: float) -> tuple[float, int]:
    """Box side and box count for an embedding of extent ``span``: boxes of side 1 (at
    least ``MIN_BOXES`` of them); a smaller embedding gets boxes of a power-of-two
    fraction of 1. The count is rounded up to a 5-smooth number, so the grid (and with it
    the kernels' cached transforms) changes only now and then."""
    side = BOX_SIDE
    if span < MIN_BOXES * BOX_SIDE:
        side *= 2.0 ** np.ceil(np.log2(max(span, 1e-12) / (MIN_BOXES * BOX_SIDE)))
    return side, _box_count(int(span / side) + 1)


def _lagrange(t: FloatArray, p: int) -> FloatArray:
    """Lagrange basis values at ``t`` (positions in box units, in [0, 1]) for the ``p``
    nodes at ``(k + 1/2) / p``; shape ``(n, p)``."""
    nodes = (np.arange(p) + 0.5) / p
    diff = t[None, :] - nodes[:, None]                               # (p, n)
    out = np.empty((p, t.shape[0]))
    for k in range(p):
        others = [j for j in range(p) if j != k]
        scale = 1.0 / float(np.prod(nodes[k] - nodes[others]))
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
    side, boxes = _grid(span)
    nodes_1d = boxes * p
    m = 2 * nodes_1d
    g_im, z_weights = kernels(d, nodes_1d, side / p)

    # per dimension: Lagrange weights and the first node of each point's box; one flat
    # index into the N^d nodes spreads the charges and reads the potentials (the zero
    # padding to m per axis is the transforms')
    lks, firsts = [], []
    for k in range(d):
        u = (y[:, k] - lo[k]) * (1.0 / side)
        b = np.minimum(u.astype(np.intp), boxes - 1)
        lks.append(_lagrange(u - b, p))                              # (n, p)
        firsts.append(b * p)
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
    z = -float(n)                                   # remove K1(y_i, y_i) = 1
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
