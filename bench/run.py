"""Every bench against its peer, under both thread policies, in one table and one JSON file.

Each bench script runs twice in its own process (the most robust way to hold every
library's threads: the variables are read when a library loads):

- ``1 thread``: ``BENCH_THREADS=1``, ``OMP_NUM_THREADS``, ``OPENBLAS_NUM_THREADS`` and
  ``MKL_NUM_THREADS`` at 1 (scikit-learn's OpenMP reads the first), the process pinned to
  one core (so a kd-tree's ``workers=-1`` inside our functions gets one core too, and
  Open3D's TBB pool sizes itself from it), the BLAS/OpenMP pools held to 1 by
  ``threadpoolctl`` and Open3D's by ``open3d.utility.set_max_threads(1)`` as well;
- ``default``: every library as it runs by default on this machine.

Every row is timed by :func:`_common.compare` (interleaved, warm-up, seeds). The benches
with no peer (``linsolve``: the solver backends against each other; ``service_overhead``:
the service's own costs) and ``multiway`` (2 Dask workers against 1) run once at default
threads and their tables follow. The rows are
printed as one table, written to ``build/bench/results.txt`` and, with every time and
every seed's accuracy, to ``build/bench/results.json`` (``build/`` is not committed).

    python bench/run.py [--quick | --large] [--only registration,assignment]
                        [--modes 1,default] [--seeds 3] [--cases 'ICP p2p 100,000|openTSNE']

``make bench`` runs it (``make bench BENCH_ARGS=--quick`` for the small sizes).
``BENCH_NO_CHOLMOD=1`` runs every bench as the permissive default install would (cvxopt and
cholespy, the GPL ``cholmod`` extra, made unimportable): the libigl rows then show the
default's speed, and the rows without it what CHOLMOD adds.

``--quick`` (or ``BENCH_QUICK=1``) runs every bench at its small sizes (a few minutes); the
full run takes up to about 40 minutes on two cores. ``--large`` runs the benches of
:data:`LARGE` at their large sizes instead (ICP at 1,000,000 points a side, the meshes at
200,704 vertices, the swiss roll at 20,000 points, t-SNE at 30,000) and skips the others;
its rows go in the same table. Not run here: ``load``, ``transport``, ``sdk_map`` (service
load tests, minutes each) and ``workbench`` (needs a browser). A benchmark never asserts.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "bench")]

from _common import LEFT, ROW_HEADER, row_cells, table_lines  # noqa: E402

#: The benches with a peer, in the order of the table.
BENCHES = ("registration", "fpfh_open3d", "assignment", "solvers", "deformation",
           "parameterization", "layout", "embedding")
MODES = {"1": {"BENCH_THREADS": "1", "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1",
               "MKL_NUM_THREADS": "1"},
         "default": {"BENCH_THREADS": "default"}}
POLICY_VARS = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")
#: The benches with large sizes (``--large``: the script's own flag).
LARGE = ("registration", "solvers", "deformation", "parameterization", "embedding")
#: Benches with no peer and their own tables (ours against ours: the solver backends, the
#: service's overhead), run once at default threads; their output is kept as printed.
#: Arguments: (full run, quick run).
OWN_TABLES = {
    "linsolve": ([], ["--sizes", "5k"]),
    "service_overhead": ([], ["--requests", "50", "--clients", "4", "--per-client", "10"]),
    # 2 Dask workers against 1: meaningless on one pinned core, so at default threads only
    "multiway": ([], ["--quick"]),
}


def run_own(bench: str, quick: bool) -> str:
    """Run a bench with its own table; its printed output (or why it failed)."""
    cmd = [sys.executable, str(ROOT / "bench" / f"{bench}.py"),
           *OWN_TABLES[bench][1 if quick else 0]]
    print(f"== {bench} (its own table, default threads)", flush=True)
    done = subprocess.run(cmd, cwd=ROOT, check=False, capture_output=True, text=True)
    print(done.stdout, end="", flush=True)
    if done.returncode:
        return f"{done.stdout}\nFAILED (exit {done.returncode}):\n{done.stderr[-2000:]}"
    return done.stdout


def run_one(bench: str, mode: str, size: str, seeds: int, out: Path, cases: str
            ) -> list[dict]:
    env = {k: v for k, v in os.environ.items() if k not in POLICY_VARS}
    env |= MODES[mode] | {"BENCH_JSON": str(out), "BENCH_SEEDS": str(seeds),
                          "BENCH_CASES": cases}
    cmd = [sys.executable, str(ROOT / "bench" / f"{bench}.py")] + \
        ([f"--{size}"] if size != "full" else [])
    print(f"== {bench} ({'1 thread' if mode == '1' else 'default threads'})", flush=True)
    t = time.perf_counter()
    done = subprocess.run(cmd, env=env, cwd=ROOT, check=False)
    print(f"   {time.perf_counter() - t:.0f} s, exit {done.returncode}", flush=True)
    if done.returncode or not out.exists():
        return [{"family": bench, "case": f"FAILED (exit {done.returncode})", "mode": mode}]
    rows: list[dict] = json.loads(out.read_text())
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true",
                        default=os.environ.get("BENCH_QUICK", "") not in ("", "0"))
    parser.add_argument("--large", action="store_true",
                        help="the large sizes of the benches that have them")
    parser.add_argument("--only", default="", help="comma-separated benches (default: all)")
    parser.add_argument("--modes", default="1,default")
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--cases", default="", help="only the rows whose 'case vs peer' "
                        "holds one of these |-separated words (e.g. 'ICP p2p 100,000')")
    parser.add_argument("--out", default=str(ROOT / "build" / "bench"))
    args = parser.parse_args()
    only = args.only.split(",") if args.only else []
    if args.quick and args.large:
        parser.error("--quick and --large exclude each other")
    size = "quick" if args.quick else "large" if args.large else "full"
    benches = [b for b in BENCHES if (not only or b in only) and (not args.large or b in LARGE)]
    own = [b for b in OWN_TABLES if (not only or b in only) and not args.cases
           and not args.large]
    modes = args.modes.split(",")
    rows: list[dict] = []
    start = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        for bench in benches:
            for mode in modes:
                rows += run_one(bench, mode, size, args.seeds,
                                Path(tmp) / f"{bench}-{mode}.json", args.cases)
    own_text = {b: run_own(b, args.quick) for b in own}
    # both policies of a case side by side
    order: dict[tuple[str, str, str], int] = {}
    for i, r in enumerate(rows):
        order.setdefault((r["family"], r["case"], r.get("peer", "")), i)
    rows.sort(key=lambda r: (order[(r["family"], r["case"], r.get("peer", ""))],
                             r["mode"] != "1"))
    cells = [row_cells(r) if "ours" in r else (r["family"], r["case"], "", r["mode"])
             + ("",) * (len(ROW_HEADER) - 4) for r in rows]
    when = time.strftime("%Y-%m-%d %H:%M", time.gmtime())
    lines = [f"bench {size} run, {when} UTC, {os.cpu_count()} cores, "
             f"{time.perf_counter() - start:.0f} s; every time "
             f"is the median [range] of the timed runs over seeds 0..{args.seeds - 1}, ours "
             "and the peer alternately after a warm-up; ratio = ours / peer (below 1: we are "
             "faster), its range that of the pair-by-pair ratios; cpu/wall = CPU seconds per "
             "wall second of each side's calls (the threads it really used); load = 1-minute "
             "load average before→after the row",
             *table_lines(ROW_HEADER, cells, left=LEFT)]
    for bench, out_text in own_text.items():
        lines += ["", f"--- {bench} (no peer: its own table, default threads) ---",
                  out_text.rstrip()]
    text = "\n".join(lines)
    print("\n" + text)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "results.txt").write_text(text + "\n")
    (out / "results.json").write_text(json.dumps(
        {"quick": args.quick, "size": size, "seeds": args.seeds, "cores": os.cpu_count(),
         "rows": rows, "own_tables": own_text},
        indent=1))
    print(f"\nwritten: {out / 'results.txt'}, {out / 'results.json'}")


if __name__ == "__main__":
    main()
