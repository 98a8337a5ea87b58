"""Warnings of the library name the line that called it."""

from __future__ import annotations

import warnings

import numpy as np
from scipy.spatial.transform import Rotation

from algorithms.core.errors import ConvergenceWarning, warn
from algorithms.registration import icp, multiway


def test_warning_names_the_caller_through_wrappers() -> None:
    """ICP warns from inside its body, behind the validating wrapper, and behind multiway's
    dispatch to generalised Procrustes: each warning names this file's calling line."""
    x = np.random.default_rng(0).normal(size=(50, 3))
    y = x @ np.diag([1.0, -1.0, 1.0]) + 0.3
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        icp(x, y, max_iterations=1); line = _line()  # noqa: E702
    assert [w.category for w in seen] == [ConvergenceWarning]
    assert (seen[0].filename, seen[0].lineno) == (__file__, line)
    rng = np.random.default_rng(1)
    sets = [x] + [(x + rng.normal(scale=0.05, size=x.shape)) @ Rotation.random(random_state=i)
                  .as_matrix().T for i in range(3)]
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        multiway(sets, max_iterations=1, tolerance=0.0); line = _line()  # noqa: E702
    assert seen and all((w.filename, w.lineno) == (__file__, line) for w in seen)


def test_warn_outside_the_library_is_its_caller() -> None:
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        warn("from a test", UserWarning); line = _line()  # noqa: E702
    assert (seen[0].filename, seen[0].lineno, seen[0].category) == (__file__, line, UserWarning)


def _line() -> int:
    import sys

    return sys._getframe(1).f_lineno
