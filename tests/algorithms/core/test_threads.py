"""The thread policy: one BLAS thread inside the block, the previous limits after it, also
when blocks nest or end in another order on other threads; the loops that apply it."""

from __future__ import annotations

import threading
import warnings

import numpy as np
import pytest
from threadpoolctl import ThreadpoolController, threadpool_info

from algorithms.core.threads import (  # _release: threadpoolctl 3.8 keeps control per thread
    SERIAL_BELOW,
    THREADED_BLOCK,
    THREADED_WORK,
    _release,
    block_workers,
    query_workers,
    single_blas_thread,
    usable_cores,
)
from algorithms.registration import cpd, icp


def _blas() -> list[dict]:
    return [lib for lib in threadpool_info() if lib["user_api"] == "blas"]


#: The BLAS libraries whose thread count can be set (NumPy's and SciPy's OpenBLAS; a
#: single-threaded build, such as cvxopt's when the tests import it, stays at 1 whatever
#: the limit): set by the fixture below
_SETTABLE: set[str] = set()


def blas_threads() -> set[int]:
    """The thread counts of the BLAS libraries loaded whose count can be set."""
    return {lib["num_threads"] for lib in _blas() if lib["filepath"] in _SETTABLE}


@pytest.fixture
def two_blas_threads():
    """BLAS set to 2 threads around the test, so that a limit of 1 can be told apart (set
    without holding threadpoolctl's control, as a worker process is when a job starts)."""
    limiter = ThreadpoolController().limit(limits=2, user_api="blas")
    _release()
    _SETTABLE.clear()
    _SETTABLE.update(lib["filepath"] for lib in _blas() if lib["num_threads"] == 2)
    assert any("numpy" in path for path in _SETTABLE)  # NumPy's own BLAS at least
    assert blas_threads() == {2}
    yield
    limiter.restore_original_limits()
    _release()


def test_one_thread_inside_and_the_previous_limit_after(two_blas_threads):
    with single_blas_thread():
        assert blas_threads() == {1}
    assert blas_threads() == {2}


def test_nested_blocks_restore_at_the_outermost_end(two_blas_threads):
    with single_blas_thread():
        with single_blas_thread():
            assert blas_threads() == {1}
        assert blas_threads() == {1}       # the outer block still runs
    assert blas_threads() == {2}


def test_the_previous_limit_is_restored_even_after_an_error(two_blas_threads):
    with pytest.raises(RuntimeError, match="inside"), single_blas_thread():
        raise RuntimeError("inside")
    assert blas_threads() == {2}


def test_blocks_on_two_threads_ending_out_of_order(two_blas_threads):
    # A enters, B enters, A leaves (B still inside: one thread), B leaves: restored. With
    # nested threadpoolctl limits, A's exit would restore 2 under B, B's exit 1 for good.
    a_in, b_in, a_out, b_check = (threading.Event() for _ in range(4))
    seen: dict[str, set[int]] = {}

    def a() -> None:
        with single_blas_thread():
            a_in.set()
            b_in.wait()
        a_out.set()

    def b() -> None:
        a_in.wait()
        with single_blas_thread():
            b_in.set()
            a_out.wait()
            seen["b after a left"] = blas_threads()
        b_check.set()

    threads = [threading.Thread(target=a), threading.Thread(target=b)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert b_check.is_set()
    assert seen["b after a left"] == {1}
    assert blas_threads() == {2}


def test_block_workers():
    # threads only for large totals of large blocks, never more than the partitions
    assert block_workers(THREADED_BLOCK, THREADED_WORK - 1, 4) == 1
    assert block_workers(THREADED_BLOCK - 1, 100 * THREADED_WORK, 4) == 1
    assert block_workers(THREADED_BLOCK, THREADED_WORK, 4) == min(4, usable_cores())
    assert block_workers(THREADED_BLOCK, THREADED_WORK, 1) == 1


def test_query_workers():
    assert query_workers(1) == 1
    assert query_workers(SERIAL_BELOW - 1) == 1
    assert query_workers(SERIAL_BELOW) == usable_cores() >= 1


def _blob(n: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    u = rng.standard_normal((n, 3))
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    return u * (1.0 + 0.3 * u[:, :1] + 0.2 * u[:, 1:2] * u[:, 2:]) * [1.3, 1.0, 0.8]


def test_icp_iterates_on_one_blas_thread_and_restores(two_blas_threads):
    # the progress callback runs inside the iterations: it sees the limit in force there
    src = _blob(SERIAL_BELOW, 0)        # large enough for the kd-tree's workers
    dst = src @ np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]).T * 0.02 \
        + src * 0.98 + [0.01, 0.0, 0.0]
    seen: list[set[int]] = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        icp(src, dst, max_iterations=3, progress=lambda *_: seen.append(blas_threads()))
    assert seen and all(s == {1} for s in seen)
    assert blas_threads() == {2}


def test_cpd_rigid_iterates_on_one_blas_thread_and_restores(two_blas_threads):
    src = _blob(300, 1)
    seen: list[set[int]] = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cpd(src, src + [0.05, 0.0, 0.0], max_iterations=3,
            progress=lambda *_: seen.append(blas_threads()))
    assert seen and all(s == {1} for s in seen)
    assert blas_threads() == {2}
