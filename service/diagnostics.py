"""Diagnostic processes for end-to-end tests of the job machinery.

Offered only when the setting ``test_processes`` is on (``MORPHSERVE_TEST_PROCESSES=1``):
``diagnostics.sleep`` works for a while and reports progress (cancellation, time limits,
progress reporting), ``diagnostics.nap`` is the same on the fast path (a fast-path job that
outlasts its client's wait), ``diagnostics.crash`` kills the worker process running it (worker loss).
"""

from __future__ import annotations

import os
import time
from dataclasses import dataclass

from pydantic import Field

from algorithms.core.progress import Progress, as_progress
from service.catalog.base import Params
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


def sleep(seconds: float = 1.0, steps: int = 10, *, progress: Progress | None = None
          ) -> SleepResult:
    """Sleep ``seconds`` in ``steps`` slices, reporting progress after each (cancellable).
    The messages name the process id, so that tests can kill the worker mid-job."""
    report = as_progress(progress)
    start = time.monotonic()
    pid = os.getpid()
    for i in range(steps):
        time.sleep(seconds / steps)
        report(i + 1, steps, f"slept {i + 1}/{steps} in pid {pid}")
    return SleepResult(time.monotonic() - start, steps)


def nap(seconds: float = 1.0, steps: int = 10, *, progress: Progress | None = None
        ) -> SleepResult:
    """:func:`sleep`, offered on the fast path (run inside the service, not on a worker)."""
    return sleep(seconds, steps, progress=progress)


@dataclass(frozen=True)
class CrashResult:
    """Attributes
    ----------
    survived : bool
        Never true: the worker dies first.
    """

    survived: bool


def crash(exit_code: int = 137) -> CrashResult:
    """End the worker process at once, as an out-of-memory kill would."""
    os._exit(exit_code)


class SleepParams(Params):
    seconds: float = Field(1.0, ge=0, le=3600, description="How long to sleep.")
    steps: int = Field(10, ge=1, le=100_000, description="Progress steps.")


class CrashParams(Params):
    exit_code: int = Field(137, ge=1, le=255, description="Exit status of the worker.")


diagnostics = Registry()
diagnostics.add(Process(id="diagnostics.sleep", title="Sleep (diagnostic)",
                        description="Sleeps and reports progress; for tests of the job service.",
                        function=sleep, params=SleepParams, result=SleepResult, long=True))
diagnostics.add(Process(id="diagnostics.nap", title="Sleep on the fast path (diagnostic)",
                        description="Sleeps and reports progress in the service's own fast "
                        "path; for tests of the job service.", function=nap,
                        params=SleepParams, result=SleepResult, fast_path=True))
diagnostics.add(Process(id="diagnostics.crash", title="Crash a worker (diagnostic)",
                        description="Kills the worker process that runs it; for tests of "
                        "worker loss.", function=crash, params=CrashParams, result=CrashResult,
                        long=True))
