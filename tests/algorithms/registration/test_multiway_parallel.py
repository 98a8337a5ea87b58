"""Multiway registration without correspondences hands its pairwise registrations to the
installed mapper (algorithms.core.parallel): with a mapper that runs them on a thread pool
the result is the serial one bit for bit, every pair went through the mapper, and the
mapper holds for its own context only."""

from __future__ import annotations

import contextvars
import importlib
import threading
import warnings
from collections.abc import Callable, Sequence
from concurrent.futures import ThreadPoolExecutor
from typing import Any

import numpy as np
import pytest

from algorithms.core.errors import Cancelled
from algorithms.core.parallel import current_mapper, serial_map, task_map, use_mapper
from algorithms.registration import multiway
from tests.algorithms.registration._shapes import angle_deg, blob
from tests.algorithms.registration._views import assert_same_fields, views

# the module (the package re-exports the function under the same name)
pose_graph_module = importlib.import_module("algorithms.registration.pose_graph")
POOL_PREFIX = "mapped-call"


class _ThreadMapper:
    """Runs the calls on a pool of 2 threads, in order of the items; records each map."""

    def __init__(self) -> None:
        self.maps: list[int] = []
        self.calls: list[Any] = []

    def __call__(self, fn: Callable[[Any, Any], Any], items: Sequence[Any],
                 progress: Any) -> list[Any]:
        self.maps.append(len(items))

        def one(item: Any) -> Any:
            self.calls.append(item)  # list.append: safe from the pool's threads
            return fn(item, progress)

        with ThreadPoolExecutor(2, thread_name_prefix=POOL_PREFIX) as pool:
            return list(pool.map(one, items))


@pytest.mark.parametrize("k", [6, 12])  # all pairs (15); beyond 10 sets, 2 neighbours (21)
def test_a_mapper_runs_every_pair_and_the_result_is_the_serial_one(
        k: int, monkeypatch: pytest.MonkeyPatch) -> None:
    sets, poses = views(blob, k=k, n=400, seed=3)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        serial = multiway(sets, correspondences=False)
        threads: list[str] = []
        icp = pose_graph_module.icp

        def recording_icp(*args: Any, **kwargs: Any) -> Any:
            threads.append(threading.current_thread().name)
            return icp(*args, **kwargs)

        monkeypatch.setattr(pose_graph_module, "icp", recording_icp)
        mapper = _ThreadMapper()
        with use_mapper(mapper):
            mapped = multiway(sets, correspondences=False)
    assert_same_fields(mapped, serial)
    pairs = len(serial.edges)
    assert pairs == (k * (k - 1) // 2 if k <= 10 else 2 * k - 3)
    assert mapper.maps == [pairs] and len(mapper.calls) == pairs
    # every ICP run (4 stages a pair) ran in the mapper's threads: none was left to a loop
    assert len(threads) >= 4 * pairs
    assert all(name.startswith(POOL_PREFIX) for name in threads)
    # and the poses are right, not only the same (the true poses, to the noise)
    for t, true in zip(mapped.transforms, poses, strict=True):
        assert angle_deg(t[:3, :3], true[:3, :3]) < 2.0  # sparse views: ~1° of noise


def test_procrustes_has_no_pairs_to_map() -> None:
    rng = np.random.default_rng(0)
    x = rng.standard_normal((30, 3))
    mapper = _ThreadMapper()
    with use_mapper(mapper):
        multiway([x, x + 1.0, x - 2.0])
    assert mapper.maps == []


def test_an_error_of_a_mapped_call_propagates() -> None:
    """A progress callback that stops the run (a dismissal) from inside a mapped call."""
    sets, _ = views(blob, k=4, n=300, seed=1)
    seen = []

    def progress(done: float, total: float, message: str = "") -> None:
        seen.append(threading.current_thread().name)
        if len(seen) > 5:
            raise Cancelled("stop")

    with use_mapper(_ThreadMapper()), pytest.raises(Cancelled, match="stop"), \
            warnings.catch_warnings():
        warnings.simplefilter("ignore")
        multiway(sets, correspondences=False, progress=progress)
    assert seen[-1].startswith(POOL_PREFIX)


def test_the_mapper_holds_in_its_own_context_only() -> None:
    assert current_mapper() is serial_map
    mine = _ThreadMapper()
    seen: dict[str, Any] = {}
    inside = threading.Event()
    leave = threading.Event()

    def other_job() -> None:  # a second job in another thread of the same process
        seen["other, while installed"] = current_mapper()
        theirs = _ThreadMapper()
        with use_mapper(theirs):
            inside.set()
            leave.wait(10)
            seen["other, its own"] = current_mapper() is theirs
            seen["other, maps"] = task_map(lambda x, p: x + 1, [1, 2])

    with use_mapper(mine):
        thread = threading.Thread(target=other_job)
        thread.start()
        inside.wait(10)
        seen["mine, while the other's installed"] = current_mapper()
        leave.set()
        thread.join(10)
        seen["fresh context"] = contextvars.Context().run(current_mapper)
        assert task_map(lambda x, p: 2 * x, [1, 2, 3]) == [2, 4, 6]
        with use_mapper(serial_map):  # blocks nest
            assert current_mapper() is serial_map
        assert current_mapper() is mine
    assert current_mapper() is serial_map
    assert seen["other, while installed"] is serial_map
    assert seen["other, its own"] is True and seen["other, maps"] == [2, 3]
    assert seen["mine, while the other's installed"] is mine
    assert seen["fresh context"] is serial_map
    assert mine.maps == [3]  # the other thread's map did not go through mine


def test_the_mapper_is_restored_after_an_error() -> None:
    with pytest.raises(RuntimeError), use_mapper(_ThreadMapper()):
        raise RuntimeError
    assert current_mapper() is serial_map
