"""One BLAS thread for loops of memory-bound products.

The iterative layouts multiply an ``n×n`` matrix by a few vectors per iteration: bound by
memory bandwidth, not arithmetic, so more BLAS threads do not help, and when the cores are
shared (several workers, other jobs) OpenBLAS threads spin-waiting for each other made such
loops 10-40× slower in measurements here. The loops run with BLAS limited to one thread
(through ``threadpoolctl``, a dependency of the service).
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterator

from threadpoolctl import threadpool_limits

__all__ = ["single_blas_thread"]


@contextlib.contextmanager
def single_blas_thread() -> Iterator[None]:
    """Limit BLAS to one thread inside the block."""
    with threadpool_limits(limits=1, user_api="blas"):
        yield
