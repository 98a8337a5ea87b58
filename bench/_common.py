"""What the bench scripts share: timing, the plain-text tables they print, the test mesh and
the timing of the sparse Cholesky backends.

Each script puts the repository root and this folder on ``sys.path`` and imports from here::

    sys.path[:0] = [str(ROOT), str(ROOT / "bench")]
    from _common import timed, print_table  # noqa: E402

A benchmark never asserts; nothing here does either.
"""

from __future__ import annotations

import statistics
import time
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from algorithms.core.laplacian import cotangent_laplacian
from algorithms.core.linsolve import Factor, available_backends

__all__ = ["timed", "timed_pair", "wavy_grid", "backend_timings", "table_lines",
           "print_table", "print_ratio_table"]


def timed(fn: Callable[[], Any], repeats: int) -> tuple[float, Any]:
    """Median wall time of ``repeats`` calls, and the last call's value."""
    times, value = [], None
    for _ in range(repeats):
        t = time.perf_counter()
        value = fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times), value


def timed_pair(ours: Callable[[], Any], peer: Callable[[], Any], repeats: int
               ) -> tuple[float, Any, float, Any]:
    """Median wall times of ``ours`` and ``peer``, called alternately (so that a busy machine
    slows both alike), and the last values."""
    t_ours, t_peer, a, b = [], [], None, None
    for _ in range(repeats):
        t = time.perf_counter()
        a = ours()
        t_ours.append(time.perf_counter() - t)
        t = time.perf_counter()
        b = peer()
        t_peer.append(time.perf_counter() - t)
    return statistics.median(t_ours), a, statistics.median(t_peer), b


def wavy_grid(nx: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """A jittered wavy grid: ``nx × nx`` vertices over the unit square lifted by
    ``0.1 sin(6x) cos(5y)``, moved in the plane by up to 0.3 of a cell (many obtuse
    triangles, some negative cotangent weights), two triangles a cell.

    Returns ``(vertices, faces)``: ``(nx², 3)`` floats and ``(2 (nx - 1)², 3)`` int64.
    """
    rng = np.random.default_rng(seed)
    x, y = np.meshgrid(np.linspace(0, 1, nx), np.linspace(0, 1, nx))
    v = np.c_[x.ravel(), y.ravel(), 0.1 * np.sin(6 * x.ravel()) * np.cos(5 * y.ravel())]
    v[:, :2] += rng.uniform(-0.3, 0.3, (nx * nx, 2)) / nx
    idx = np.arange(nx * nx).reshape(nx, nx)
    a, b = idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel()
    c, d = idx[1:, :-1].ravel(), idx[1:, 1:].ravel()
    return v, np.r_[np.c_[a, b, d], np.c_[a, d, c]].astype(np.int64)


def backend_timings(v: np.ndarray, f: np.ndarray, pinned: np.ndarray, repeats: int
                    ) -> tuple[Any, list[tuple[str, Factor, float, float, float]]]:
    """Every installed sparse Cholesky backend on the free block of a cotangent Laplacian.

    The block ``a`` is the cotangent Laplacian of ``(v, f)`` without the rows and columns
    of the ``pinned`` vertices; the right-hand sides are 3 standard normal columns (seed 1).

    Returns ``a`` and, for each backend of
    :func:`~algorithms.core.linsolve.available_backends`, ``(backend asked for, the Factor,
    median seconds to factor, median seconds of one solve, relative residual
    ‖a x - b‖∞ / ‖b‖∞)``.
    """
    lap = cotangent_laplacian(v, f)
    free = np.setdiff1d(np.arange(len(v)), pinned)
    a = lap[free][:, free].tocsc()
    b = np.random.default_rng(1).standard_normal((a.shape[0], 3))
    out = []
    for backend in available_backends():
        fac_t, fac = timed(lambda backend=backend: Factor(a, backend=backend), repeats)
        sol_t, x = timed(lambda fac=fac: fac.solve(b), repeats)
        res = float(np.abs(a @ x - b).max() / np.abs(b).max())
        out.append((backend, fac, fac_t, sol_t, res))
    return a, out


def table_lines(header: Sequence[str], rows: Sequence[Sequence[str]],
                left: tuple[int, ...] = (0,)) -> list[str]:
    """The lines of a plain-text table: the header, a rule of dashes, then the rows.

    Every column is as wide as its widest cell, the columns listed in ``left`` aligned left
    and the others right, two spaces between columns.
    """
    table = [header, *rows]
    widths = [max(len(row[i]) for row in table) for i in range(len(header))]
    lines = []
    for i, row in enumerate(table):
        lines.append("  ".join(cell.ljust(w) if j in left else cell.rjust(w)
                               for j, (cell, w) in enumerate(zip(row, widths, strict=True))))
        if i == 0:
            lines.append("  ".join("-" * w for w in widths))
    return lines


def print_table(title: str, header: tuple[str, ...], rows: list[tuple[str, ...]],
                left: tuple[int, ...] = (0,)) -> None:
    """Print ``title``, the table of :func:`table_lines` and an empty line."""
    print(title)
    for line in table_lines(header, rows, left):
        print(line)
    print()


def print_ratio_table(rows: list[tuple[str, float, float, str, str]], repeats: int) -> None:
    """Print the one table of a family against its peers.

    ``rows`` hold ``(case, our seconds, the peer's seconds, our figure, the peer's
    figure)``; the table adds the ratio (ours / peer) under a line naming the number of
    runs each time is the median of.
    """
    header = ("case", "ours (s)", "peer (s)", "ratio", "ours", "peer")
    table = [(name, f"{ours:.3f}", f"{peer:.3f}", f"{ours / peer:.2f}", mine, theirs)
             for name, ours, peer, mine, theirs in rows]
    print(f"median of {repeats} runs; ratio = ours / peer (below 1: we are faster)")
    for line in table_lines(header, table, left=(0, 4, 5)):
        print(line)


def blob(n: int, seed: int) -> np.ndarray:
    """``n`` points on an asymmetric lumpy closed surface about 2 across: the registration
    benches' shape (no symmetry, so every rotation is recoverable)."""
    rng = np.random.default_rng(seed)
    u = rng.standard_normal((n, 3))
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    x, y, z = u.T
    r = 1.0 + 0.3 * x + 0.15 * y * z + 0.2 * x * y + 0.1 * z ** 3 + 0.12 * y
    return u * r[:, None] * [1.3, 1.0, 0.8]


def angle_deg(r_est: np.ndarray, r_true: np.ndarray) -> float:
    """The angle of the rotation between two rotation matrices, in degrees."""
    c = (np.trace(r_est @ r_true.T) - 1.0) / 2.0
    return float(np.degrees(np.arccos(np.clip(c, -1.0, 1.0))))
