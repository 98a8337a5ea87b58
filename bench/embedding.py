"""The deterministic embeddings against scikit-learn, side by side in one run.

Prints one table: for each case our time, scikit-learn's on the same data, their ratio
(ours / peer: below 1 is faster) and the trustworthiness (k = 5, the same function for
both) each embedding reaches, so that speed is never bought with quality unseen. Every time
is the median of --repeats runs, ours and the peer's called alternately.

    python bench/embedding.py [--repeats 3] [--quick] [--only isomap]

Cases (sizes divided by 5 with --quick):

- Isomap, 5,000-point swiss roll, 10 neighbours, vs ``sklearn.manifold.Isomap`` (defaults:
  ARPACK);
- LLE, 5,000-point swiss roll, 10 neighbours, vs ``LocallyLinearEmbedding`` (defaults:
  ARPACK, reg 1e-3);
- Laplacian eigenmaps, 5,000-point swiss roll, 10 neighbours, vs ``SpectralEmbedding``
  (nearest-neighbour affinity, ARPACK);
- classical MDS, 1,000 points of ``load_digits``, vs ``ClassicalMDS``;
- metric MDS (SMACOF from classical MDS), the same points, vs ``MDS(init="classical_mds",
  n_init=1)`` (each library's default stopping rule);
- PCA, all 1,797 digits, vs ``PCA``.

A benchmark never asserts.
"""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
# the packages first (tests/algorithms must not shadow algorithms), then bench/ for _common
sys.path[:0] = [str(ROOT), str(ROOT / "bench")]

from _common import print_ratio_table, timed_pair  # noqa: E402
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

warnings.simplefilter("ignore", ConvergenceWarning)
warnings.simplefilter("ignore", FutureWarning)


def _case(name, x, ours, peer, repeats, *, disparity=False):  # noqa: ANN001, ANN202
    t_ours, a, t_peer, b = timed_pair(ours, peer, repeats)
    mine = f"T={trustworthiness(x, a):.4f}"
    if disparity:  # the same embedding up to an orthogonal map and a scale
        mine += f", Procrustes disparity {procrustes(a, b)[2]:.1e}"
    return (name, t_ours, t_peer, mine, f"T={trustworthiness(x, b):.4f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--quick", action="store_true", help="a fifth of the sizes")
    parser.add_argument("--big", type=int, default=0, metavar="N",
                        help="also embed N points by t-SNE once (time, peak memory)")
    parser.add_argument("--only", metavar="WORD",
                        help="only the cases whose name holds WORD (e.g. isomap, tsne)")
    args = parser.parse_args()
    r = args.repeats
    n = 1000 if args.quick else 5000
    m = 200 if args.quick else 1000
    roll = make_swiss_roll(n, random_state=0)[0]
    digits = load_digits().data
    cases = [
        lambda: _case(f"isomap, swiss roll n={n}, k=10", roll,
                      lambda: isomap(roll, n_neighbors=10).embedding,
                      lambda: Isomap(n_neighbors=10).fit_transform(roll), r, disparity=True),
        lambda: _case(f"lle, swiss roll n={n}, k=10", roll,
                      lambda: lle(roll, n_neighbors=10).embedding,
                      lambda: LocallyLinearEmbedding(n_neighbors=10, random_state=0)
                      .fit_transform(roll), r),
        lambda: _case(f"laplacian eigenmaps, swiss roll n={n}, k=10", roll,
                      lambda: laplacian_eigenmaps(roll, n_neighbors=10).embedding,
                      lambda: SpectralEmbedding(n_neighbors=10, random_state=0)
                      .fit_transform(roll), r),
        lambda: _case(f"classical mds, digits n={m}", digits[:m],
                      lambda: mds(digits[:m]).embedding,
                      lambda: ClassicalMDS().fit_transform(digits[:m]), r),
        lambda: _case(f"metric mds (smacof), digits n={m}", digits[:m],
                      lambda: mds(digits[:m], metric=True).embedding,
                      lambda: MDS(init="classical_mds", n_init=1, random_state=0)
                      .fit_transform(digits[:m]), r),
        lambda: _case("pca, digits n=1797", digits,
                      lambda: pca(digits).embedding,
                      lambda: PCA(2).fit_transform(digits), r),
    ]
    names = ["isomap", "lle", "laplacian eigenmaps", "classical mds", "metric mds (smacof)",
             "pca"]
    rows = [case() for name, case in zip(names, cases, strict=True)
            if args.only is None or args.only in name]
    from _embedding_tsne import big_run, case_tsne  # noqa: PLC0415

    if args.only is None or args.only in "t-sne tsne":
        rows += case_tsne(r, args.quick)
    print_ratio_table(rows, r)
    if args.big:
        big_run(args.big)


if __name__ == "__main__":
    main()
