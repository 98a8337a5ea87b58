"""The deterministic embeddings against scikit-learn, side by side in one run.

Every row goes through ``_common.compare``: ours and scikit-learn alternately after a
warm-up, on the data of seeds 0..2, the median and range of the times, the threads
allowed, and the trustworthiness (k = 5, the same function for both) each embedding reaches
on every seed, so that speed is never bought with quality unseen.

The same work on both sides: each of our embeddings reports its trustworthiness (k = 5),
computed inside the call, so the peer's timed call computes it too, on its embedding, with
the same function (``algorithms.embedding.trustworthiness``; scikit-learn's own sorts the
full ``n × n`` distance matrix, 3.2 GB at 20,000 points). The row's note says so.

    python bench/embedding.py [--quick | --large] [--only isomap] [--big N] [--n N]

Cases (sizes divided by 5 with --quick; with --large the swiss roll has 20,000 points and
t-SNE 30,000; the swiss roll's size set by ``--n``; the swiss roll and
the digits subset drawn per seed):

- Isomap, 5,000-point swiss roll, 10 neighbours, vs ``sklearn.manifold.Isomap`` (defaults:
  ARPACK);
- LLE, 5,000-point swiss roll, 10 neighbours, vs ``LocallyLinearEmbedding`` (defaults:
  ARPACK, reg 1e-3);
- Laplacian eigenmaps, 5,000-point swiss roll, 10 neighbours, vs ``SpectralEmbedding``
  (nearest-neighbour affinity, ARPACK);
- classical MDS, 1,000 points of ``load_digits``, vs ``ClassicalMDS``;
- metric MDS (SMACOF from classical MDS), the same points, vs ``MDS(init="classical_mds",
  n_init=1)`` (each library's default stopping rule);
- PCA, 1,500 digits, vs ``PCA``;
- t-SNE against openTSNE and scikit-learn (``_embedding_tsne``).

A benchmark never asserts.
"""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
# the packages first (tests/algorithms must not shadow algorithms), then bench/ for _common
sys.path[:0] = [str(ROOT), str(ROOT / "bench")]

import numpy as np  # noqa: E402
from _common import apply_policy, compare, report  # noqa: E402
from _embedding_tsne import with_trustworthiness  # noqa: E402
from scipy.spatial import procrustes  # noqa: E402
from sklearn.datasets import load_digits, make_swiss_roll  # noqa: E402
from sklearn.decomposition import PCA  # noqa: E402
from sklearn.manifold import (  # noqa: E402
    MDS,
    ClassicalMDS,
    Isomap,
    LocallyLinearEmbedding,
    SpectralEmbedding,
)

from algorithms.core import ConvergenceWarning  # noqa: E402
from algorithms.embedding import (  # noqa: E402
    isomap,
    laplacian_eigenmaps,
    lle,
    mds,
    pca,
    trustworthiness,
)
from algorithms.embedding.isomap import MAX_ISOMAP_POINTS  # noqa: E402

warnings.simplefilter("ignore", ConvergenceWarning)
warnings.simplefilter("ignore", FutureWarning)


FAMILY = "embedding"


def _case(name: str, data: Any, ours: Any, peer: Any, peer_name: str, *,
          disparity: bool = False) -> None:
    def quality(x: np.ndarray, y: np.ndarray) -> dict[str, float]:
        return {"T": trustworthiness(x, y)}

    def agree(_x: np.ndarray, a: np.ndarray, b: np.ndarray) -> dict[str, float]:
        # the same embedding up to an orthogonal map and a scale
        return {"Procrustes disparity": procrustes(a, b)[2]}

    compare(FAMILY, name, data, ours, with_trustworthiness(peer), quality,
            peer_name=peer_name, agreement=agree if disparity else None,
            peer_threads="+ trustworthiness (k = 5), as ours")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="a fifth of the sizes")
    parser.add_argument("--large", action="store_true",
                        help="swiss roll 20,000 points, t-SNE 30,000")
    parser.add_argument("--big", type=int, default=0, metavar="N",
                        help="also embed N points by t-SNE once (time, peak memory)")
    parser.add_argument("--only", metavar="WORD",
                        help="only the cases whose name holds WORD (e.g. isomap, tsne)")
    parser.add_argument("--n", type=int, default=0, metavar="N",
                        help="points of the swiss roll (default 5,000; 1,000 with --quick, "
                        "20,000 with --large)")
    args = parser.parse_args()
    apply_policy()
    n = args.n or (1000 if args.quick else 20_000 if args.large else 5000)
    m = 200 if args.quick else 1000
    digits = load_digits().data

    def roll(seed: int) -> np.ndarray:
        return make_swiss_roll(n, random_state=seed)[0]

    def subset(size: int) -> Any:
        return lambda seed: digits[np.random.default_rng(seed).permutation(len(digits))[:size]]

    cases = {
        "isomap": lambda: _case(
            f"isomap, swiss roll n={n}, k=10", roll,
            lambda x: isomap(x, n_neighbors=10).embedding,
            lambda x: Isomap(n_neighbors=10).fit_transform(x), "sklearn Isomap",
            disparity=True),
        "lle": lambda: _case(
            f"lle, swiss roll n={n}, k=10", roll,
            lambda x: lle(x, n_neighbors=10).embedding,
            lambda x: LocallyLinearEmbedding(n_neighbors=10, random_state=0).fit_transform(x),
            "sklearn LocallyLinearEmbedding"),
        "laplacian eigenmaps": lambda: _case(
            f"laplacian eigenmaps, swiss roll n={n}, k=10", roll,
            lambda x: laplacian_eigenmaps(x, n_neighbors=10).embedding,
            lambda x: SpectralEmbedding(n_neighbors=10, random_state=0).fit_transform(x),
            "sklearn SpectralEmbedding"),
        "classical mds": lambda: _case(
            f"classical mds, digits n={m}", subset(m), lambda x: mds(x).embedding,
            lambda x: ClassicalMDS().fit_transform(x), "sklearn ClassicalMDS"),
        "metric mds (smacof)": lambda: _case(
            f"metric mds (smacof), digits n={m}", subset(m),
            lambda x: mds(x, metric=True).embedding,
            lambda x: MDS(init="classical_mds", n_init=1, random_state=0).fit_transform(x),
            'sklearn MDS(init="classical_mds", n_init=1)'),
        "pca": lambda: _case("pca, digits n=1500", subset(1500), lambda x: pca(x).embedding,
                             lambda x: PCA(2).fit_transform(x), "sklearn PCA"),
    }
    for name, case in cases.items():
        if args.only is not None and args.only not in name:
            continue
        if name == "isomap" and n > MAX_ISOMAP_POINTS:
            print(f"isomap skipped: n={n:,} is over MAX_ISOMAP_POINTS = {MAX_ISOMAP_POINTS:,}")
            continue
        case()
    from _embedding_tsne import big_run, case_tsne, tsne_points  # noqa: PLC0415

    if args.only is None or args.only in "t-sne tsne":
        case_tsne(tsne_points(args.quick, args.large))
    report(FAMILY)
    if args.big:
        big_run(args.big)


if __name__ == "__main__":
    main()
