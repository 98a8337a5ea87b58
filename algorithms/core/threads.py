"""One BLAS thread for loops of memory-bound products.

Iterative methods that multiply a large matrix by a few vectors per iteration (the layouts'
SMACOF and distance completion) are bound by memory bandwidth, not arithmetic, so more BLAS
threads do not help, and when the cores are shared (several workers, other jobs) OpenBLAS
threads spin-waiting for each other made such loops 10-40× slower in measurements here. Such
loops run with BLAS limited to one thread (through ``threadpoolctl``, a dependency of the
package).
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterator

from threadpoolctl import threadpool_limits

__all__ = ["single_blas_thread"]


@contextlib.contextmanager
def single_blas_thread() -> Iterator[None]:
    """Limit BLAS to one thread inside the block (the previous limits come back after it).

    Examples
    --------
    >>> import numpy as np
    >>> with single_blas_thread():
    ...     y = np.ones((200, 200)) @ np.ones(200)
    """
    with threadpool_limits(limits=1, user_api="blas"):
        yield
