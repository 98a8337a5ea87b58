"""The package's thread policy: our own threads for the parallel work, one BLAS thread.

The iterative methods here parallelise at a coarse grain themselves (kd-tree queries with
``workers``, CPD's partitions of the E-step) and, between those, multiply thin matrices:
``(n, 3) @ (3, 3)`` transforms, ``(n, 3)ᵀ (n, 3)`` moments, matrix-vector products of
SMACOF and t-SNE. Such products are bound by memory bandwidth, not arithmetic, so BLAS
threads do not speed them up; they wake, spin and contend with the kd-tree's workers and
with each other. Measured on 2 cores: one ``(100000, 3) @ (3, 3)`` product took 34 ms of
CPU with 2 OpenBLAS threads against 3 ms with one, ICP ran 1.4-1.7× slower at default
settings than with BLAS held to one thread, CPD 1.9×, and the layouts' loops 10-40× on busy
cores. The policy, applied in every such loop (ICP, CPD, RANSAC, multiway, the layouts and
the embeddings):

1. the loop runs inside :func:`single_blas_thread` (BLAS on one thread);
2. kd-tree queries use :func:`query_workers`: every core available to the process from
   :data:`SERIAL_BELOW` query points, one thread below (starting threads costs more there);
   work split into blocks over threads of our own (CPD's E-step) uses :func:`block_workers`:
   threads only for large totals made of large blocks (small numpy calls hold the GIL).
   ICP splits its nearest-point search over :func:`usable_cores` threads of its own from
   a few thousand points (``icp.PART_MIN`` a thread), each taking a contiguous part of the
   source whole (the test that keeps a partner, the query of the rest on one worker; from
   ``icp.SPREAD_FROM`` points, several parts per thread, taken in turn):
   SciPy's own ``workers`` start threads on every call and did not pay below tens of
   thousands of points (10,000 points a side: no gain; split by parts, 1.3-1.4x faster);
3. dense factorisations and solves of large matrices (CPD's nonrigid ``M × M`` solve, the
   eigensolvers) stay outside the block, where BLAS threads do pay.

Results never depend on the number of threads that the kd-tree uses; a BLAS product on one
thread sums in one fixed order, so results inside the block are the same on every machine.
"""

from __future__ import annotations

import contextlib
import functools
import os
import threading
from collections.abc import Iterator
from typing import Any

import scipy.linalg  # noqa: F401 - loads SciPy's own OpenBLAS before the controller looks
import threadpoolctl
from threadpoolctl import ThreadpoolController

__all__ = ["single_blas_thread", "query_workers", "block_workers", "usable_cores",
           "SERIAL_BELOW", "THREADED_WORK", "THREADED_BLOCK"]

#: Queries of fewer points than this run on one thread (starting threads costs more).
SERIAL_BELOW = 8192
#: Work split over threads of our own (CPD's E-step) only above this many elements in all
#: (starting a pool costs more below) ...
THREADED_WORK = 1 << 18
#: ... and only when each numpy call of a thread handles at least this many elements: below,
#: a call's interpreter overhead, which holds the GIL, outweighs the part that releases it,
#: and threads convoy on the GIL. Measured on 2 cores: rigid CPD on 3,000 points (most
#: E-steps truncated to blocks of 32 × ~100 pairs) took 4.5 s wall (6.1 s CPU) with 2
#: threads against 2.5 s with one.
THREADED_BLOCK = 1 << 16

_lock = threading.Lock()
_depth = 0
_limiter: Any = None     # threadpoolctl's limiter of the outermost block, restored at its end


@functools.cache
def _controller() -> ThreadpoolController:
    # Inspecting the loaded libraries costs about a millisecond: once per process, not per
    # block (0.02 ms). Libraries loaded later are not seen; NumPy's and SciPy's are loaded.
    return ThreadpoolController()


@contextlib.contextmanager
def single_blas_thread() -> Iterator[None]:
    """Limit BLAS to one thread inside the block; the previous limits come back after it.

    Blocks may nest and may be entered by several threads at once (jobs in the threads of
    one worker): the limit is set when the first block starts and the previous limits are
    restored when the last one ends, whatever the order in which they end (OpenBLAS's
    limit is one for the whole process). BLAS calls of other threads in the meantime also
    run on one thread.

    Examples
    --------
    >>> import numpy as np
    >>> with single_blas_thread():
    ...     y = np.ones((200, 200)) @ np.ones(200)
    """
    global _depth, _limiter
    with _lock:
        if _depth == 0:
            _limiter = _controller().limit(limits=1, user_api="blas")
            _release()
        _depth += 1
    try:
        yield
    finally:
        with _lock:
            _depth -= 1
            if _depth == 0:
                _limiter.restore_original_limits()
                _limiter = None
                _release()


def _release() -> None:
    """Let any thread set OpenBLAS's limits next. Recent threadpoolctl (3.8) lets only one
    thread, the first to set them, change the shared pool's limits until it leaves its
    ``with`` block; the limits set here are not such a block, and the thread that restores
    them may not be the one that set them. (A thread inside a ``threadpool_limits`` block of
    its own keeps control, and its limits win: the calls here then change nothing.)"""
    clear = getattr(getattr(threadpoolctl, "OpenBLASController", None),
                    "clear_controlling_thread", None)
    if clear is not None:
        clear()


def usable_cores() -> int:
    """The number of cores this process may run on (its CPU affinity where the system
    reports it, e.g. under ``taskset`` or a container's cpuset; else every core)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def query_workers(n: int) -> int:
    """The ``workers`` for a kd-tree query of ``n`` points: one below
    :data:`SERIAL_BELOW`, else :func:`usable_cores`. The answers never depend on it."""
    return 1 if n < SERIAL_BELOW else usable_cores()


def block_workers(block: int, total: int, parts: int) -> int:
    """The threads for ``total`` elements of work in blocks of about ``block`` elements,
    dealt to ``parts`` fixed partitions: one below :data:`THREADED_WORK` in all or
    :data:`THREADED_BLOCK` a block, else ``min(parts, usable_cores())``. The partitions are
    fixed, so the answers never depend on it."""
    if total < THREADED_WORK or block < THREADED_BLOCK:
        return 1
    return min(parts, usable_cores())
