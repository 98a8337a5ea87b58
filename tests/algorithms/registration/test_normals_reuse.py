"""reuse_normals: inside the block the normals of the same points are estimated once, the
answers are those of a fresh estimate to the bit, and a pose graph estimates each set's
normals once (in-process) or once per pair (its pairs elsewhere), with the transforms of
the graph that estimates them for every ICP stage."""

from __future__ import annotations

import contextlib
import importlib
import warnings
from collections.abc import Callable, Sequence
from concurrent.futures import ThreadPoolExecutor
from typing import Any

import numpy as np
import pytest

from algorithms.core.parallel import use_mapper
from algorithms.registration import _normals as normals_module
from algorithms.registration import multiway
from algorithms.registration._normals import estimate_normals, reuse_normals
from tests.algorithms.registration._shapes import blob
from tests.algorithms.registration._views import views

pose_graph_module = importlib.import_module("algorithms.registration.pose_graph")


def _counting(monkeypatch: pytest.MonkeyPatch) -> list[int]:
    """Count the estimates actually made (by point count) from now on."""
    made: list[int] = []
    estimate = normals_module._estimate

    def counted(points: Any, *args: Any) -> Any:
        made.append(len(points))
        return estimate(points, *args)

    monkeypatch.setattr(normals_module, "_estimate", counted)
    return made


def test_the_same_points_are_estimated_once_and_alike(monkeypatch: pytest.MonkeyPatch) -> None:
    pts = np.random.default_rng(0).normal(size=(300, 3))
    fresh_n, fresh_p = estimate_normals(pts, None, 10, 1)
    made = _counting(monkeypatch)
    with reuse_normals():
        n1, p1 = estimate_normals(pts, None, 10, 1)
        n2, p2 = estimate_normals(pts.copy(), None, 10, 1)   # equal bytes, another array
        n3, _ = estimate_normals(pts, None, 8, 1)             # another k: its own estimate
        moved = pts.copy()
        moved[7, 2] = np.nextafter(moved[7, 2], np.inf)       # one bit differs
        estimate_normals(moved, None, 10, 1)
        with reuse_normals():                                  # nested: the outer's
            n4, _ = estimate_normals(pts, None, 10, 1)
    assert made == [300, 300, 300]
    assert n2 is n1 and p2 is p1 and n4 is n1
    np.testing.assert_array_equal(n1, fresh_n)
    np.testing.assert_array_equal(p1, fresh_p)
    assert not np.array_equal(n3, n1)
    assert not n1.flags.writeable and not p1.flags.writeable   # shared: nobody may edit
    with pytest.raises(ValueError):
        n1[0, 0] = 0.0
    estimate_normals(pts, None, 10, 1)                         # after the block: fresh
    assert made == [300, 300, 300, 300]


class _PoolMapper:
    """The pairs on 2 threads of a pool, which do not see the caller's context (as pairs
    on other machines would not)."""

    def __call__(self, fn: Callable[[Any, Any], Any], items: Sequence[Any],
                 progress: Any) -> list[Any]:
        with ThreadPoolExecutor(2) as pool:
            return list(pool.map(lambda item: fn(item, progress), items))


@pytest.mark.parametrize("metric", ["symmetric", "point_to_plane"])
def test_a_pose_graph_estimates_each_set_once_with_the_same_answer(
        metric: str, monkeypatch: pytest.MonkeyPatch) -> None:
    k = 12   # beyond 10 sets: each with its next 2, 21 pairs
    sets, _ = views(blob, k=k, n=500, seed=1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        made = _counting(monkeypatch)
        reused = multiway(sets, correspondences=False, metric=metric)
        serial_estimates = len(made)
        with use_mapper(_PoolMapper()):
            pooled = multiway(sets, correspondences=False, metric=metric)
        pooled_estimates = len(made) - serial_estimates
        # the graph as before the reuse: every ICP stage estimates its normals afresh
        monkeypatch.setattr(pose_graph_module, "reuse_normals", contextlib.nullcontext)
        before = len(made)
        fresh = multiway(sets, correspondences=False, metric=metric)
        fresh_estimates = len(made) - before
    pairs = len(fresh.edges)
    assert pairs == 21
    plane_stages = sum(1 for _, m in pose_graph_module.STAGES if m is None)
    per_icp = 2 if metric == "symmetric" else 1        # symmetric: source and target
    assert fresh_estimates == pairs * plane_stages * per_icp
    # in-process: each set once (as source or target, the same points); on the pool's
    # threads: once per pair and role
    touched = {int(i) for e in fresh.edges for i in (e if per_icp == 2 else e[1:])}
    assert serial_estimates == len(touched)
    assert pooled_estimates == pairs * per_icp
    for got in (reused, pooled):
        np.testing.assert_array_equal(got.transforms, fresh.transforms)
        np.testing.assert_array_equal(got.rmse, fresh.rmse)
        np.testing.assert_array_equal(got.edge_fitness, fresh.edge_fitness)
