"""What the bench scripts share: the harness every row against a peer goes through
(:func:`compare`), the plain-text tables they print, the test shapes and the timing of the
sparse Cholesky backends.

Each script puts the repository root and this folder on ``sys.path`` and imports from here::

    sys.path[:0] = [str(ROOT), str(ROOT / "bench")]
    from _common import apply_policy, compare, report  # noqa: E402

and in its ``main``: ``apply_policy()``, one :func:`compare` per row, then ``report(title)``.
``bench/run.py`` runs each script once per thread policy (``BENCH_THREADS=1`` with the
thread variables at 1, and the libraries' defaults) and gathers the rows of every script
into one table and one JSON file.

The rules :func:`compare` keeps: one untimed warm-up call of each side; the two sides
called alternately (the side that goes first alternating too), on the data of at least 3
seeds, the data made outside the timed region; the median and range of the times, the
ratio of the medians with the range of the pair-by-pair ratios; CPU seconds per wall second
of each side (the threads it really used); each side's accuracy on every seed; the thread
policy, cores and pools allowed; the load average before and after.

A benchmark never asserts; nothing here does either.
"""

from __future__ import annotations

import contextlib
import json
import os
import statistics
import sys
import time
import warnings
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

# BENCH_NO_CHOLMOD=1: the permissive default install, as if cvxopt and cholespy (the GPL
# cholmod extra) were not installed (every import of them fails), as
# tests/algorithms/core/test_linsolve.py does. Read here, before anything imports
# algorithms: every bench imports _common first.
if os.environ.get("BENCH_NO_CHOLMOD") == "1":
    sys.modules["cvxopt"] = None  # type: ignore[assignment]
    sys.modules["cholespy"] = None  # type: ignore[assignment]

import numpy as np  # noqa: E402
from threadpoolctl import threadpool_info, threadpool_limits  # noqa: E402

from algorithms.core.laplacian import cotangent_laplacian  # noqa: E402
from algorithms.core.linsolve import Factor, available_backends  # noqa: E402

__all__ = ["timed", "timed_pair", "wavy_grid", "backend_timings", "table_lines",
           "print_table", "print_ratio_table", "compare", "report", "workers", "apply_policy",
           "single_thread", "threads_allowed", "MODE", "SEEDS", "ROWS", "ROW_HEADER",
           "row_cells", "LEFT"]


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


# ---------------------------------------------------------------------------------------
# The harness: every row of every bench goes through :func:`compare`.
# ---------------------------------------------------------------------------------------

#: The thread policy of this process, set by ``bench/run.py`` (``BENCH_THREADS``): ``"1"``
#: pins the process to one core and holds every BLAS/OpenMP pool to one thread (the
#: environment variables are set before the process starts, so every OpenMP runtime reads
#: them) and Open3D's TBB pool too (``set_max_threads``: TBB ignores ``OMP_NUM_THREADS``);
#: ``"default"`` leaves each library as it runs untouched.
MODE = os.environ.get("BENCH_THREADS", "default")
#: Seeds of the data of every row (``BENCH_SEEDS``: how many, at least 3).
SEEDS = tuple(range(max(3, int(os.environ.get("BENCH_SEEDS", "3")))))
#: The rows measured so far in this process (see :func:`compare`).
ROWS: list[dict[str, Any]] = []
#: Only the rows whose "case vs peer" holds one of these ``|``-separated words
#: (``BENCH_CASES``; empty: every row).
CASES = tuple(w for w in os.environ.get("BENCH_CASES", "").split("|") if w)
#: Calls shorter than this are repeated within a seed (more pairs, less noise).
SHORT = 0.2


def single_thread() -> bool:
    """Whether this process runs the one-thread policy."""
    return MODE == "1"


def apply_policy() -> None:
    """Pin this process to one core under the one-thread policy (a no-op otherwise).

    ``bench/run.py`` sets ``OMP_NUM_THREADS`` and the BLAS variables before the process
    starts; a bench run by hand with ``BENCH_THREADS=1`` gets the same pinning here, and
    :func:`compare` also holds the pools to one thread through ``threadpoolctl``.
    """
    if single_thread() and hasattr(os, "sched_setaffinity"):
        cpus = sorted(os.sched_getaffinity(0))
        os.sched_setaffinity(0, {cpus[0]})


def workers() -> int:
    """The kd-tree ``workers`` a peer loop written in the bench passes: 1 under the one-thread
    policy, -1 (every core) by default."""
    return 1 if single_thread() else -1


def threads_allowed() -> dict[str, Any]:
    """What this process lets each side use: its cores (affinity), the thread variables of
    the environment, every thread pool ``threadpoolctl`` sees (BLAS, OpenMP once loaded) and
    Open3D's own limit (it runs on TBB, which ignores ``OMP_NUM_THREADS``) once it is
    imported."""
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    env = {k: os.environ[k] for k in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS",
                                      "MKL_NUM_THREADS") if k in os.environ}
    pools = sorted({f"{p['internal_api']}:{p['num_threads']}"
                    for p in threadpool_info()})
    o3d = sys.modules.get("open3d")
    if o3d is not None:
        pools.append(f"open3d-tbb:{o3d.utility.get_max_threads()}")
    return {"mode": MODE, "cores": cores, "env": env, "pools": pools}


def _hold_open3d() -> None:
    """Open3D's TBB pool to one thread under the one-thread policy, once it is imported."""
    o3d = sys.modules.get("open3d")
    if single_thread() and o3d is not None:
        o3d.utility.set_max_threads(1)


def _threads_label(t: dict[str, Any]) -> str:
    pools = ",".join(p.split(":")[0] + "=" + p.split(":")[1] for p in t["pools"])
    return f"{t['cores']} core{'s' if t['cores'] != 1 else ''} ({pools})"


def _summary(values: Sequence[float]) -> dict[str, float]:
    return {"median": float(statistics.median(values)), "min": float(min(values)),
            "max": float(max(values))}


def compare(family: str, case: str, data: Callable[[int], Any],
            ours: Callable[[Any], Any], peer: Callable[[Any], Any] | None = None,
            accuracy: Callable[[Any, Any], dict[str, float]] | None = None, *,
            peer_name: str = "", ours_threads: str = "", peer_threads: str = "",
            seeds: Sequence[int] = SEEDS, warmup: bool | Callable[[], Any] = True,
            repeats: int | None = None,
            agreement: Callable[[Any, Any, Any], dict[str, float]] | None = None
            ) -> dict[str, Any] | None:
    """Time ``ours`` against ``peer`` interleaved, and measure both one's accuracy per seed.

    For each seed ``s``, ``d = data(s)`` is made outside the timed region, then ``ours(d)``
    and ``peer(d)`` are timed alternately, the side that goes first alternating from one
    pair to the next, so that a busy machine slows both alike. One untimed call of each side
    on the first seed's data comes first (imports, first-call costs, caches; ``warmup`` may
    instead give smaller data for it, or be false). A call that
    took under ``SHORT`` seconds in the warm-up is repeated 5 times per seed, else once
    (``repeats`` overrides). ``accuracy(d, result)`` is applied to each side's first result
    on every seed (a mapping of figure names to numbers), so neither side's accuracy comes
    from one seed or from its last repeat only; ``agreement(d, ours_result, peer_result)``,
    when given, compares the two sides' first results on every seed (e.g. the largest
    difference of their outputs).

    Returns the row (also appended to :data:`ROWS`): the case, the peer's name, the times
    of each side (median, min, max, and every time), the ratio ours / peer (of the medians,
    with the range of the pair-by-pair ratios), each side's accuracy per seed, the thread
    policy and the pools each side was allowed (with the bench's own notes, e.g. a kd-tree's
    ``workers``), and the load average before and after. ``peer=None`` times ours alone.
    A row that :data:`CASES` leaves out is not run (``None``).
    """
    if CASES and not any(w in f"{case} vs {peer_name}" for w in CASES):
        return None
    limits = threadpool_limits(1) if single_thread() else contextlib.nullcontext()
    load_before = os.getloadavg()
    sides: list[tuple[str, Callable[[Any], Any]]] = [("ours", ours)]
    if peer is not None:
        sides.append(("peer", peer))
    times: dict[str, list[float]] = {name: [] for name, _ in sides}
    cpu: dict[str, list[float]] = {name: [] for name, _ in sides}
    acc: dict[str, dict[str, list[float]]] = {name: {} for name, _ in sides}
    agree: dict[str, list[float]] = {}
    pairs: list[float] = []
    with limits, warnings.catch_warnings():
        warnings.simplefilter("ignore")
        first = data(seeds[0])
        per_seed = repeats or 1
        if warmup:
            slow = 0.0
            w = warmup() if callable(warmup) else first
            _hold_open3d()
            for _, fn in sides:
                t = time.perf_counter()
                fn(w)
                slow = max(slow, time.perf_counter() - t)
            if repeats is None and slow < SHORT:
                per_seed = 5
        _hold_open3d()
        k = 0
        for s in seeds:
            d = first if s == seeds[0] else data(s)
            for r in range(per_seed):
                order = sides if k % 2 == 0 else sides[::-1]
                pair: dict[str, float] = {}
                got: dict[str, Any] = {}
                for name, fn in order:
                    c, t = time.process_time(), time.perf_counter()
                    value = fn(d)
                    pair[name] = time.perf_counter() - t
                    times[name].append(pair[name])
                    cpu[name].append(time.process_time() - c)
                    got[name] = value
                    if r == 0 and accuracy is not None:
                        for key, x in accuracy(d, value).items():
                            acc[name].setdefault(key, []).append(float(x))
                if peer is not None:
                    pairs.append(pair["ours"] / pair["peer"])
                    if r == 0 and agreement is not None:
                        for key, x in agreement(d, got["ours"], got["peer"]).items():
                            agree.setdefault(key, []).append(float(x))
                k += 1
        threads = threads_allowed()
    row: dict[str, Any] = {
        "family": family, "case": case, "peer": peer_name, "mode": MODE,
        "seeds": list(seeds), "repeats_per_seed": per_seed,
        "ours": {**_summary(times["ours"]), "times": times["ours"],
                 "cpu_per_wall": sum(cpu["ours"]) / sum(times["ours"]),
                 "accuracy": acc["ours"]},
        "agreement": agree,
        "threads": {**threads, "ours": ours_threads, "peer": peer_threads},
        "load": {"before": list(load_before), "after": list(os.getloadavg())},
    }
    if peer is not None:
        row["peer_times"] = {**_summary(times["peer"]), "times": times["peer"],
                             "cpu_per_wall": sum(cpu["peer"]) / sum(times["peer"]),
                             "accuracy": acc["peer"]}
        row["ratio"] = {"median": row["ours"]["median"] / row["peer_times"]["median"],
                        "min": min(pairs), "max": max(pairs)}
    ROWS.append(row)
    print(f"  {family}: {case} [{_threads_label(threads)}] ours {_fmt_time(row['ours'])}"
          + (f", peer {_fmt_time(row['peer_times'])}, ratio {_fmt_ratio(row['ratio'])}"
             if peer is not None else ""), flush=True)
    return row


def _fmt_time(s: dict[str, float]) -> str:
    return f"{s['median']:.3g} [{s['min']:.3g}–{s['max']:.3g}]"


def _fmt_ratio(r: dict[str, float]) -> str:
    return f"{r['median']:.2f} [{r['min']:.2f}–{r['max']:.2f}]"


def _fmt_acc(acc: dict[str, list[float]]) -> str:
    parts = []
    for key, vals in acc.items():
        if not vals:
            continue
        med = statistics.median(vals)
        if min(vals) == max(vals):
            parts.append(f"{key} {med:.4g}")
        else:
            parts.append(f"{key} {med:.4g} [{min(vals):.3g}–{max(vals):.3g}]")
    return ", ".join(parts) or "—"


def row_cells(row: dict[str, Any]) -> tuple[str, ...]:
    """A row of :func:`compare` as the cells of :data:`ROW_HEADER`."""
    peer = row.get("peer_times")
    threads = "1 thread" if row["mode"] == "1" else "default"
    threads += f": {_threads_label(row['threads'])}"
    cpu = f"{row['ours']['cpu_per_wall']:.2f}"
    if peer:
        cpu += f" / {peer['cpu_per_wall']:.2f}"
    return (row["family"], row["case"], row["peer"] or "—", threads, _fmt_time(row["ours"]),
            _fmt_time(peer) if peer else "—", _fmt_ratio(row["ratio"]) if peer else "—", cpu,
            _fmt_acc(row["ours"]["accuracy"]), _fmt_acc(peer["accuracy"]) if peer else "—",
            _fmt_acc(row.get("agreement", {})),
            f"{row['load']['before'][0]:.1f}→{row['load']['after'][0]:.1f}")


#: The columns of the one table (``bench/run.py`` and :func:`report`).
ROW_HEADER = ("family", "case", "peer", "threads allowed", "ours s: median [range]",
              "peer s: median [range]", "ours/peer", "cpu/wall ours / peer",
              "ours: accuracy, median [range] over seeds", "peer: accuracy",
              "ours vs peer", "load 1 min")
#: The columns :func:`table_lines` aligns left.
LEFT = (0, 1, 2, 3, 8, 9, 10)


def report(title: str) -> None:
    """Print this process's rows as one table, and write them to the JSON file named by
    ``BENCH_JSON`` when it is set (``bench/run.py`` gathers them)."""
    print(f"\n{title}: median [range] of the timed runs (seeds {list(SEEDS)}, ours and the "
          "peer alternately after a warm-up); ratio = ours / peer (below 1: we are faster), "
          "the range that of the pair-by-pair ratios")
    for line in table_lines(ROW_HEADER, [row_cells(r) for r in ROWS],
                            left=LEFT):
        print(line)
    out = os.environ.get("BENCH_JSON")
    if out:
        Path(out).write_text(json.dumps(ROWS, indent=1))
