"""Diagnostic processes for end-to-end tests of the job machinery.

Offered only when the setting ``test_processes`` is on (``MORPHSERVE_TEST_PROCESSES=1``):
``diagnostics.sleep`` works for a while and reports progress (cancellation, time limits,
progress reporting), ``diagnostics.nap`` is the same on the fast path (a fast-path job that
outlasts its client's wait), ``diagnostics.crash`` kills the worker process running it
(worker loss).
"""

from __future__ import annotations

import os
import time
from dataclasses import dataclass
from typing import Annotated

from algorithms.core.params import Ge, Le, validate_params
from algorithms.core.progress import Progress, as_progress
from service.catalog.registry import Process, Registry

__all__ = ["diagnostics"]


@dataclass(frozen=True)
class SleepResult:
    """Attributes
    ----------
    slept : float
        Seconds actually slept.
    steps : int
        Progress steps reported.
    """

    slept: float
    steps: int


@validate_params
def sleep(seconds: Annotated[float, Ge(0)] = 1.0, steps: Annotated[int, Ge(1)] = 10, *,
          progress: Progress | None = None) -> SleepResult:
    """Sleep ``seconds`` in ``steps`` slices, reporting progress after each (cancellable).
    The messages name the process id, so that tests can kill the worker mid-job.

    Parameters
    ----------
    seconds : float, default 1.0
        How long to sleep.
    steps : int, default 10
        Progress steps: slices of the sleep, each reported when done.
    """
    report = as_progress(progress)
    start = time.monotonic()
    pid = os.getpid()
    for i in range(steps):
        time.sleep(seconds / steps)
        report(i + 1, steps, f"slept {i + 1}/{steps} in pid {pid}")
    return SleepResult(time.monotonic() - start, steps)


@validate_params
def nap(seconds: Annotated[float, Ge(0)] = 1.0, steps: Annotated[int, Ge(1)] = 10, *,
        progress: Progress | None = None) -> SleepResult:
    """:func:`sleep`, offered on the fast path (run inside the service, not on a worker).

    Parameters
    ----------
    seconds : float, default 1.0
        How long to sleep.
    steps : int, default 10
        Progress steps: slices of the sleep, each reported when done.
    """
    return sleep(seconds, steps, progress=progress)


@dataclass(frozen=True)
class CrashResult:
    """Attributes
    ----------
    survived : bool
        Never true: the worker dies first.
    """

    survived: bool


@validate_params
def crash(exit_code: Annotated[int, Ge(1), Le(255)] = 137) -> CrashResult:
    """End the worker process at once, as an out-of-memory kill would.

    Parameters
    ----------
    exit_code : int, default 137
        Exit status of the worker (137 is a kill by SIGKILL).
    """
    os._exit(exit_code)


#: What a shared test service still refuses: an hour's sleep, more steps than progress rows.
_CAPS = {"seconds": Le(3600), "steps": Le(100_000)}

diagnostics = Registry()
diagnostics.add(Process(id="diagnostics.sleep", title="Sleep (diagnostic)",
                        description="Sleeps and reports progress; for tests of the job service.",
                        function=sleep, limits=_CAPS, long=True))
diagnostics.add(Process(id="diagnostics.nap", title="Sleep on the fast path (diagnostic)",
                        description="Sleeps and reports progress in the service's own fast "
                        "path; for tests of the job service.", function=nap, limits=_CAPS,
                        fast_path=True))
diagnostics.add(Process(id="diagnostics.crash", title="Crash a worker (diagnostic)",
                        description="Kills the worker process that runs it; for tests of "
                        "worker loss.", function=crash, long=True))
