"""Coherent point drift against its peers, for bench/registration.py.

``case_cpd(repeats, quick)`` returns the rows of the registration table:

- rigid CPD (with scale), 3,000 ↔ 3,000 points (quick: 1,000) of a lumpy closed surface, the
  target an independent sampling turned by 30°, scaled by 1.2, shifted and with 0.5% noise;
  against pycpd's ``RigidRegistration`` and probreg's ``registration_cpd`` (rigid), each
  with its own default stopping rule, when they are importable (neither is installed in the
  test environment: issue #4 measured probreg at 8.4 s and pycpd at 39.6 s for this case on
  the reference machine). Figures: rotation error (degrees) and scale error.
- the memory bound: rigid CPD on 20,000 ↔ 20,000 points (quick: 10,000), two iterations,
  with the peak of numpy's allocations (tracemalloc) beside what the M×N posterior alone
  would take; no peer row (pycpd's difference tensor would need 9.6 GB).

A benchmark never asserts.
"""

from __future__ import annotations

import math
import statistics
import time
import tracemalloc
import warnings
from typing import Any

import numpy as np
from _common import angle_deg as _angle  # bench/ is on the path (run by registration.py)
from _common import blob as _blob
from scipy.spatial.transform import Rotation

from algorithms.registration import cpd

__all__ = ["case_cpd"]

ANGLE = 30.0
SCALE = 1.2


def _figure(rot: np.ndarray, scale: float, truth: np.ndarray) -> str:
    return f"{_angle(rot, truth):.4f}°, scale err {abs(scale - SCALE):.1e}"


def _timed(fn: Any, repeats: int) -> tuple[float, Any]:
    times, value = [], None
    for _ in range(repeats):
        t = time.perf_counter()
        value = fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times), value


def case_cpd(repeats: int, quick: bool) -> list[tuple[str, float, float, str, str]]:
    n = 1000 if quick else 3000
    rng = np.random.default_rng(0)
    truth = Rotation.from_rotvec(np.radians(ANGLE) * np.array([1.0, 2.0, 3.0]) / math.sqrt(14))
    truth = truth.as_matrix()
    src = _blob(n, 1)
    dst = SCALE * _blob(n, 2) @ truth.T + [0.3, -0.2, 0.1] + rng.normal(0.0, 0.005, (n, 3))

    def ours() -> Any:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return cpd(src, dst)

    ours_t, res = _timed(ours, repeats)
    mine = _figure(res.rotation, res.scale, truth) + f" ({res.iterations} it)"
    rows: list[tuple[str, float, float, str, str]] = []
    peers = 0
    try:
        from pycpd import RigidRegistration  # noqa: PLC0415 - optional peer
    except ImportError:
        print("note: pycpd is not installed (pip install pycpd); issue #4 measured it at "
              "39.6 s for rigid CPD on 3k points.")
    else:
        peers += 1

        def run_pycpd() -> Any:
            reg = RigidRegistration(X=dst, Y=src)
            _, (s, r, _t) = reg.register()
            return s, r.T, reg.iteration

        peer_t, (s, r, it) = _timed(run_pycpd, repeats)
        rows.append((f"CPD rigid+scale {n:,}↔{n:,} vs pycpd RigidRegistration", ours_t, peer_t,
                     mine, _figure(r, s, truth) + f" ({it} it)"))
    try:
        from probreg import cpd as probreg_cpd  # noqa: PLC0415 - optional peer
    except ImportError:
        print("note: probreg is not installed (pip install probreg); issue #4 measured it at "
              "8.4 s for rigid CPD on 3k points.")
    else:
        peers += 1

        def run_probreg() -> Any:
            tf = probreg_cpd.registration_cpd(src, dst, tf_type_name="rigid")[0]
            return tf.scale, tf.rot                   # scale * rot @ p + t

        peer_t, (s, r) = _timed(run_probreg, repeats)
        rows.append((f"CPD rigid+scale {n:,}↔{n:,} vs probreg registration_cpd", ours_t,
                     peer_t, mine, _figure(r, s, truth)))
    if not peers:
        rows.append((f"CPD rigid+scale {n:,}↔{n:,} (no peer installed)", ours_t, math.nan,
                     mine, "—"))

    big = 10_000 if quick else 20_000
    a = _blob(big, 3)
    b = SCALE * _blob(big, 4) @ truth.T

    def two_iterations() -> Any:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            tracemalloc.start()
            try:
                cpd(a, b, max_iterations=2, tolerance=0)
                return tracemalloc.get_traced_memory()[1]
            finally:
                tracemalloc.stop()

    big_t, peak = _timed(two_iterations, 1)
    full = 8 * big * big
    rows.append((f"CPD rigid {big:,}↔{big:,}, 2 iterations: memory bound (no peer fits)",
                 big_t, math.nan, f"peak {peak / 2**20:.0f} MB",
                 f"the M×N posterior alone: {full / 2**20:.0f} MB"))
    return rows
