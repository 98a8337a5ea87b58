"""The compiled kd-tree's two-nearest search against scipy's cKDTree and brute force: the
same distances to the bit, the smallest index among equally near points, only points
strictly within the bound, and trees of any depth."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial import cKDTree

from algorithms.core.kdtree import KdTree

ROOT = Path(__file__).resolve().parents[3]


def _brute(data: np.ndarray, x: np.ndarray, bound: float = np.inf):
    """Nearest and second nearest distances strictly within ``bound`` and the nearest's
    index (smallest among equals), squared distances summed over the coordinates in
    order."""
    sq = np.zeros((x.shape[0], data.shape[0]))
    for c in range(data.shape[1]):
        e = x[:, c, None] - data[None, :, c]
        sq += e * e
    sq[sq >= bound * bound] = np.inf
    order = np.lexsort((np.broadcast_to(np.arange(data.shape[0]), sq.shape), sq), axis=1)
    rows = np.arange(x.shape[0])
    s1, s2 = sq[rows, order[:, 0]], sq[rows, order[:, 1]]
    idx = np.where(np.isfinite(s1), order[:, 0], data.shape[0])
    return np.sqrt(s1), np.sqrt(s2), idx


@pytest.mark.parametrize("d", [2, 3, 5])
@pytest.mark.parametrize("bound", [np.inf, 0.3])
def test_agrees_with_ckdtree(d, bound):
    rng = np.random.default_rng(d)
    data = rng.standard_normal((3000, d))
    x = 1.2 * rng.standard_normal((2000, d))
    d1, d2, idx = KdTree(data).query2(x, bound)
    two, which = cKDTree(data).query(x, k=2, distance_upper_bound=bound)
    np.testing.assert_array_equal(d1, two[:, 0])   # the bits
    np.testing.assert_array_equal(d2, two[:, 1])
    np.testing.assert_array_equal(idx, which[:, 0])  # no ties in random data
    if bound < np.inf:
        assert np.isinf(d1).any() and np.isfinite(d1).any()   # the bound cut some


def test_ties_go_to_the_smallest_index():
    # a lattice against itself shifted by half a cell: every point has two nearest
    g = np.arange(9.0)
    data = np.stack(np.meshgrid(g, g, g[:5], indexing="ij"), axis=-1).reshape(-1, 3)
    x = data + [0.5, 0.0, 0.0]
    d1, d2, idx = KdTree(data).query2(x)
    b1, b2, bi = _brute(data, x)
    np.testing.assert_array_equal(idx, bi)
    np.testing.assert_array_equal(d1, b1)
    np.testing.assert_array_equal(d2, b2)
    assert (d1 == d2).mean() > 0.8


def test_only_points_strictly_within_the_bound():
    # on a grid of step 0.5 (exact in binary) the four nearest of a node sit at exactly 0.5
    g = np.arange(5) * 0.5
    data = np.stack(np.meshgrid(g, g, indexing="ij"), axis=-1).reshape(-1, 2)
    tree = KdTree(data)
    d1, d2, idx = tree.query2(data[[12]], bound=0.5)
    assert idx[0] == 12 and d1[0] == 0.0 and d2[0] == np.inf   # the four at 0.5 are out
    d1, d2, idx = tree.query2(data[[12]], bound=0.5 * (1 + 1e-12))
    assert idx[0] == 12 and d1[0] == 0.0 and d2[0] == 0.5      # a hair more: they are in


def test_coincident_points_and_deep_trees():
    # all points at one place: one leaf however many, the smallest index nearest
    same = np.ones((100, 3))
    d1, d2, idx = KdTree(same, leaf=4).query2(np.array([[1.0, 1.0, 2.0]]))
    assert idx[0] == 0 and d1[0] == d2[0] == 1.0
    # coordinates doubling: each split parts one point from the rest, a tree 60 levels deep
    deep = np.c_[2.0 ** np.arange(60), np.zeros(60), np.zeros(60)]
    tree = KdTree(deep, leaf=1)
    assert tree.stack > 50
    x = deep * 1.3 + 0.1
    got = tree.query2(x)
    for a, b in zip(got, _brute(deep, x), strict=True):
        np.testing.assert_array_equal(a, b)


_CACHE_RUN = """
import sys
import numpy as np
from scipy.spatial import cKDTree
from algorithms.core.kdtree import KdTree
for d, frozen in {cases}:
    x = np.random.default_rng(d).random((200, d))
    q = x[::-1].copy()
    q.flags.writeable = not frozen
    d1, d2, idx = KdTree(x).query2(q)
    dist, near = cKDTree(x).query(q, k=2)
    assert np.array_equal(d1, dist[:, 0]) and np.array_equal(d2, dist[:, 1]), d
print("ok")
"""


def test_the_disk_cache_survives_a_second_process(tmp_path):
    """A process that loads the cache index another one wrote and then compiles a new
    signature writes the index back: a compiled function that took another one as an
    argument failed there (``ReferenceError: underlying object has vanished``, once numba
    let go of the function it restored from the index; ``NUMBA_FUNCTION_CACHE_SIZE=0``
    lets go at once, where a Dask worker did after a while)."""
    import subprocess
    import sys

    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path)}
    runs = [("[(3, False)]", {}),
            ("[(3, False), (5, False), (2, True), (3, True)]",
             {"NUMBA_FUNCTION_CACHE_SIZE": "0"})]
    for cases, extra in runs:
        done = subprocess.run([sys.executable, "-c", _CACHE_RUN.format(cases=cases)],
                              env={**env, **extra}, capture_output=True, text=True,
                              cwd=ROOT, timeout=600)
        assert done.returncode == 0 and done.stdout.strip() == "ok", done.stderr[-3000:]
    assert any(tmp_path.rglob("*.nbi")), "nothing was cached: the test tested nothing"


def test_no_compiled_function_takes_another_as_an_argument():
    """The rule the test above guards, over every compiled function of the package that
    has run in this process (the kd-tree's queries and ICP's search, in 2-D, 3-D and
    5-D, run here first): no signature holds a compiled function's type."""
    import importlib
    import pkgutil

    from numba.core import types
    from numba.core.registry import CPUDispatcher

    import algorithms
    from algorithms.registration import icp

    for d in (2, 3, 5):
        x = np.random.default_rng(d).random((300, d))
        KdTree(x).query2(x)
        assert icp(x + 0.01, x, max_iterations=3).transform.shape == (d + 1, d + 1)

    for info in pkgutil.walk_packages(algorithms.__path__, "algorithms."):
        module = importlib.import_module(info.name)
        for name, value in vars(module).items():
            if isinstance(value, CPUDispatcher):
                for signature in value.signatures:
                    assert not any(isinstance(t, types.Dispatcher) for t in signature), \
                        f"{info.name}.{name}{signature}"
