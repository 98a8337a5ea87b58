"""t-SNE against openTSNE and scikit-learn (Barnes–Hut), side by side, and a 100,000-point run.

openTSNE's default ``negative_gradient_method="auto"`` is Barnes–Hut (θ = 0.5) below
10,000 points and FFT interpolation from 10,000: its rows below 10,000 points (``--quick``)
compare our FFT repulsion with its Barnes–Hut one, the more accurate of the two there (the
final KLs measured are in ``algorithms.embedding._fft_gradients.NODE_SPACING``'s note).

:func:`case_tsne` adds rows to ``bench/embedding.py``'s table through
``_common.compare`` (ours and the peer alternately, on the data of seeds 0..2, after a
warm-up on 1,000 points), the figures being the trustworthiness (k = 5, the same function
for both) and the KL divergence of each embedding under the *same* P (ours: 3·perplexity
nearest neighbours) with the exact normaliser Z (all pairs, in blocks), so neither
library's own approximation of KL is trusted. Our result holds its trustworthiness,
computed inside our call; each peer's timed call computes it too (the same function).

Data: 10,000 points in 50 dimensions (``--quick``: 2,000, ``--large``: 30,000), 20 Gaussian
clusters of different spreads (``make_blobs``, the seed's draw). Every method runs its
defaults: ours 250 + 500 steps (openTSNE's schedule), openTSNE 250 + 500 (its default
``n_jobs=1``), scikit-learn 1,000 steps (``max_iter``) with its default threads (OpenMP);
under the one-thread policy every pool is held to one thread.

    python bench/_embedding_tsne.py [--quick | --large | --n 100000] [--big 100000]
    python bench/_embedding_tsne.py --memory [--quick | --large | --n 100000]

``--big N`` (0 to skip) also embeds N points of the same kind once and prints the time
and the peak memory (tracemalloc of the call, and the process's peak RSS). openTSNE is
optional (a ``bench`` extra); without it only scikit-learn is compared. ``--memory``
prints instead the peak memory of each side (:func:`memory`: tracemalloc of the call and
the peak RSS of a fresh process per side). A benchmark never
asserts.
"""

from __future__ import annotations

import argparse
import json
import resource
import subprocess
import sys
import time
import tracemalloc
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "bench")]

import numpy as np  # noqa: E402
import scipy.sparse as sp  # noqa: E402
from _common import apply_policy, compare, report  # noqa: E402
from sklearn.datasets import make_blobs  # noqa: E402
from sklearn.manifold import TSNE  # noqa: E402

from algorithms.embedding import trustworthiness, tsne  # noqa: E402
from algorithms.embedding.tsne import affinities  # noqa: E402

try:
    import openTSNE
except ImportError:  # pragma: no cover - optional peer
    openTSNE = None


def data(n: int, seed: int = 0) -> np.ndarray:
    """``n`` points in 50 dimensions: 20 clusters of spreads 1..4."""
    std = np.linspace(1.0, 4.0, 20)
    return make_blobs(n, n_features=50, centers=20, cluster_std=std, center_box=(-20, 20),
                      random_state=seed)[0]


def exact_kl(p: sp.csr_matrix, y: np.ndarray) -> float:
    """KL(P‖Q) with the exact Z over all pairs (blocks of rows), P sparse summing to 1."""
    n = y.shape[0]
    sq = np.einsum("ij,ij->i", y, y)
    z = 0.0
    for s in range(0, n, 1000):
        d2 = np.maximum(sq[s:s + 1000, None] - 2.0 * y[s:s + 1000] @ y.T + sq[None], 0.0)
        z += float((1.0 / (1.0 + d2)).sum()) - min(1000, n - s)   # minus the diagonal
    rows = np.repeat(np.arange(n), np.diff(p.indptr))
    d2e = ((y[rows] - y[p.indices]) ** 2).sum(axis=1)
    v = p.data
    return float((v * np.log(v)).sum() + (v * np.log1p(d2e)).sum() + np.log(z))


def with_trustworthiness(peer: Any) -> Any:
    """``peer(x)`` followed by the trustworthiness (k = 5) of its embedding: our result
    holds it, computed inside our call, so the peer's timed call computes it too (the same
    pipeline on both sides)."""
    def run(x: np.ndarray) -> np.ndarray:
        y = np.asarray(peer(x))
        trustworthiness(x, y, n_neighbors=5)
        return y
    return run


def _figures(d: dict[str, Any], y: np.ndarray) -> dict[str, float]:
    return {"T": trustworthiness(d["x"], y), "KL": exact_kl(d["p"], y)}


def tsne_points(quick: bool, large: bool) -> int:
    """The points of the t-SNE rows: 10,000, ``quick`` 2,000, ``large`` 30,000."""
    return 2000 if quick else 30_000 if large else 10_000


def case_tsne(n: int) -> None:
    """Rows against openTSNE (when importable) and scikit-learn, on ``n`` × 50."""

    def sample(seed: int, size: int = n) -> dict[str, Any]:
        x = data(size, seed)
        return {"x": x, "p": affinities(x, 30.0, dense=False)}

    small = sample(99, 1000)

    def ours(d: dict[str, Any]) -> np.ndarray:
        return tsne(d["x"]).embedding

    def on_x(peer: Any) -> Any:
        timed = with_trustworthiness(peer)
        return lambda d: timed(d["x"])

    if openTSNE is not None:
        compare("embedding", f"t-SNE (defaults), n={n}×50", sample, ours,
                on_x(lambda x: openTSNE.TSNE(random_state=0).fit(x)), _figures,
                peer_name="openTSNE TSNE (defaults: "
                f"{'Barnes-Hut' if n < 10_000 else 'fft'}, n_jobs=1)", warmup=lambda: small,
                repeats=1, peer_threads="n_jobs=1 (its default); + trustworthiness (k = 5), "
                "as ours")
    compare("embedding", f"t-SNE (defaults), n={n}×50", sample, ours,
            on_x(lambda x: TSNE(init="pca", random_state=0).fit_transform(x)), _figures,
            peer_name="sklearn TSNE (barnes_hut)", warmup=lambda: small, repeats=1,
            peer_threads="+ trustworthiness (k = 5), as ours")


def big_run(n: int) -> None:
    """Embed ``n`` points once; print the time, trustworthiness and peak memory."""
    x = data(n)
    tracemalloc.start()
    t = time.perf_counter()
    res = tsne(x)
    elapsed = time.perf_counter() - t
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024  # KiB on Linux
    print(f"t-SNE (defaults), n={n:,}×50: {elapsed:.1f} s, {res.iterations} iterations, "
          f"KL {res.kl_divergence:.4f} (interpolated Z), T={res.trustworthiness:.4f}, "
          f"peak traced memory {peak / 2**20:.0f} MiB, process peak RSS {rss:.0f} MiB")


def _peak_of(side: str, n: int) -> None:
    """In this (fresh) process: make the data, then run one side on it under tracemalloc;
    print one line of JSON: the traced peak of the call and the process's peak RSS before
    and after it."""
    x = data(n)
    rss0 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    tracemalloc.start()
    t = time.perf_counter()
    if side == "ours":
        tsne(x)
    else:
        openTSNE.TSNE(random_state=0).fit(x)
    elapsed = time.perf_counter() - t
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(json.dumps({"side": side, "n": n, "seconds": elapsed, "traced_peak_mib": peak / 2**20,
                      "rss_before_mib": rss0, "rss_peak_mib": rss}), flush=True)


def memory(n: int) -> None:
    """Peak memory of each side on ``n`` points, each in a fresh process (ours, openTSNE,
    ours, openTSNE: the RSS of a process is its own high-water mark): tracemalloc's peak
    of the call (numpy's and Python's allocations, openTSNE's C++ ones not seen) and the
    peak RSS (everything, imports and the data included; the RSS before the call given
    too). Under tracemalloc the calls run slower: these are not timings."""
    for side in ("ours", "openTSNE"):
        done = subprocess.run([sys.executable, __file__, "--peak-of", side, "--n", str(n)],
                              check=True, capture_output=True, text=True)
        r = json.loads(done.stdout.strip().splitlines()[-1])
        print(f"t-SNE n={n:,}x50 {side:8s}: traced peak {r['traced_peak_mib']:7.0f} MiB, "
              f"peak RSS {r['rss_peak_mib']:7.0f} MiB (before the call "
              f"{r['rss_before_mib']:.0f} MiB), {r['seconds']:.1f} s under tracemalloc",
              flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="2,000 points, not 10,000")
    parser.add_argument("--large", action="store_true", help="30,000 points, not 10,000")
    parser.add_argument("--n", type=int, default=0, help="points of the rows (overrides "
                        "--quick and --large; e.g. 100000)")
    parser.add_argument("--big", type=int, default=100_000, help="points of the big run "
                        "(0: skip)")
    parser.add_argument("--memory", action="store_true", help="only the peak memory of "
                        "each side on the rows' points, each in a fresh process")
    parser.add_argument("--peak-of", choices=("ours", "openTSNE"), help=argparse.SUPPRESS)
    args = parser.parse_args()
    apply_policy()
    n = args.n or tsne_points(args.quick, args.large)
    if args.peak_of:
        _peak_of(args.peak_of, n)
        return
    if args.memory:
        memory(n)
        return
    case_tsne(n)
    report("t-SNE")
    if args.big:
        big_run(args.big)


if __name__ == "__main__":
    main()
