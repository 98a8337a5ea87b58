"""Coherent point drift against pycpd, for bench/registration.py (through ``compare``).

``case_cpd(quick)`` adds two rows:

- rigid CPD with scale, 3,000 ↔ 3,000 points (quick: 1,000) of a lumpy closed surface, the
  target an independent sampling turned by 30° about a random axis, scaled by 1.2, shifted
  and with 0.5 % noise, against pycpd's ``RigidRegistration``, each with its own default
  stopping rule; pycpd's warm-up runs on 200 points (a call takes tens of seconds at 3,000).
  Figures: rotation error (degrees), scale error and iterations;
- the memory bound: rigid CPD on 20,000 ↔ 20,000 points (quick: 10,000), two iterations,
  ours alone, with the peak of numpy's allocations (tracemalloc) beside what the M×N
  posterior alone would take (pycpd's difference tensor would need 9.6 GB).

A benchmark never asserts.
"""

from __future__ import annotations

import tracemalloc
from typing import Any

import numpy as np
from _common import angle_deg as _angle  # bench/ is on the path (run by registration.py)
from _common import blob as _blob
from _common import compare
from scipy.spatial.transform import Rotation

from algorithms.registration import cpd

__all__ = ["case_cpd"]

ANGLE = 30.0
SCALE = 1.2


def _pair(n: int, seed: int) -> dict[str, Any]:
    rng = np.random.default_rng(seed)
    axis = rng.standard_normal(3)
    truth = Rotation.from_rotvec(np.radians(ANGLE) * axis / np.linalg.norm(axis)).as_matrix()
    src = _blob(n, 2 * seed + 1)
    dst = SCALE * _blob(n, 2 * seed + 2) @ truth.T + [0.3, -0.2, 0.1] + \
        rng.normal(0.0, 0.005, (n, 3))
    return {"src": src, "dst": dst, "rot": truth}


def _error(d: dict[str, Any], res: tuple[np.ndarray, float, int]) -> dict[str, float]:
    rot, scale, it = res
    return {"rot°": _angle(rot, d["rot"]), "|Δs|": abs(scale - SCALE), "it": float(it)}


def case_cpd(quick: bool) -> None:
    n = 1000 if quick else 3000

    def ours(d: dict[str, Any]) -> Any:
        res = cpd(d["src"], d["dst"])
        return res.rotation, res.scale, res.iterations

    threads = "BLAS; kd-tree/parts threads from 2^18 pairs (1 core under the 1-thread policy)"
    try:
        from pycpd import RigidRegistration  # noqa: PLC0415 - optional peer
    except ImportError:
        print("note: pycpd is not installed (pip install pycpd): ours alone")
        compare("registration", f"CPD rigid+scale {n:,}↔{n:,}", lambda s: _pair(n, s), ours,
                None, _error, ours_threads=threads)
    else:
        def run_pycpd(d: dict[str, Any]) -> Any:
            reg = RigidRegistration(X=d["dst"], Y=d["src"])
            _, (s, r, _t) = reg.register()
            return r.T, s, reg.iteration

        small = _pair(200, 99)
        compare("registration", f"CPD rigid+scale {n:,}↔{n:,}", lambda s: _pair(n, s), ours,
                run_pycpd, _error, peer_name="pycpd RigidRegistration", ours_threads=threads,
                peer_threads="numpy/BLAS", warmup=lambda: small, repeats=1)

    from registration import one_core, self_rows  # noqa: PLC0415 - the bench's own helpers

    if self_rows():  # goal: ours at default threads never slower than ours on one core
        compare("registration", f"CPD rigid+scale {n:,}↔{n:,}: ours default threads vs one "
                "core", lambda s: _pair(n, s), ours, one_core(ours), _error,
                peer_name="ours on one core", ours_threads=threads,
                peer_threads="1 core, BLAS 1, E-step and kd-tree workers 1", repeats=1)

    big = 10_000 if quick else 20_000

    def two_iterations(d: dict[str, Any]) -> int:
        tracemalloc.start()
        try:
            cpd(d["src"], d["dst"], max_iterations=2, tolerance=0)
            return tracemalloc.get_traced_memory()[1]
        finally:
            tracemalloc.stop()

    full = 8 * big * big
    compare("registration", f"CPD rigid {big:,}↔{big:,}, 2 iterations: memory bound "
            f"(M×N posterior alone {full / 2**20:.0f} MB; no peer fits)",
            lambda s: _pair(big, s), two_iterations, None,
            lambda d, peak: {"peak MB": peak / 2**20}, ours_threads=threads, repeats=1)
