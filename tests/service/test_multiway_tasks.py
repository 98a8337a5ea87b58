"""A multiway job on the Dask workers runs its pairwise registrations as tasks of its own
(service.jobs.tasks) across a real cluster of two single-threaded worker processes: the
result is the serial in-process one bit for bit, each pair was one task, a dismissal or a
time limit stops the tasks too, a task's error is the job's error, and the fast path keeps
the plain loop."""

from __future__ import annotations

import logging
import time
import warnings
from collections.abc import Iterator
from typing import Any

import numpy as np
import pytest
from distributed import Client, Event, LocalCluster, get_task_stream, get_worker

from algorithms.core.errors import DegenerateInputError
from algorithms.core.parallel import current_mapper, serial_map, task_map
from algorithms.registration import multiway
from service.jobs.runner import TOPIC, Reporter, cancel_event_name, run_job
from service.jobs.status import JobStatus
from service.jobs.tasks import DaskMapper, job_tasks, task_prefix
from tests.algorithms.registration._shapes import blob
from tests.algorithms.registration._views import views


@pytest.fixture(scope="module")
def client() -> Iterator[Client]:
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=None, silence_logs=logging.ERROR) as cluster, \
            Client(cluster) as c:
        yield c


def _submit(client: Client, job_id: str, inputs: dict[str, Any],
            time_limit: float | None = None) -> Any:
    """The job as the engine submits it (service.jobs.engine)."""
    return client.submit(run_job, job_id, "registration.multiway", inputs,
                         time_limit=time_limit, key=f"morphserve-{job_id}", pure=False)


def _running_tasks(client: Client, job_id: str) -> list[str]:
    """The job's tasks whose threads still run on a worker (a cancelled task's thread runs
    on until it returns: Dask cannot stop it)."""
    prefix = task_prefix(job_id)
    active = client.run(lambda dask_worker: list(dask_worker.active_threads.values()))
    return [key for keys in active.values() for key in keys if str(key).startswith(prefix)]


def _no_task_left(client: Client, job_id: str) -> bool:
    for _ in range(300):  # the tasks stop at their next progress call
        if not _running_tasks(client, job_id):
            return True
        time.sleep(0.1)
    return False


def test_the_pairs_run_as_tasks_across_the_workers_and_give_the_serial_result(
        client: Client) -> None:
    sets, _ = views(blob, k=7, n=600, seed=2)
    inputs = {"sets": sets, "correspondences": False}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        serial = multiway(**inputs)
    with get_task_stream(client=client) as stream:
        outcome = _submit(client, "pairs", inputs).result()
    assert outcome.status is JobStatus.SUCCESSFUL, outcome.problem
    for name in ("transforms", "edge_fitness", "edge_kept", "rmse", "fitness"):
        got, want = outcome.outputs[name], getattr(serial, name)
        assert got.dtype == want.dtype and got.tobytes() == want.tobytes(), name
    pairs = 7 * 6 // 2
    tasks = [t for t in stream.data if str(t["key"]).startswith(task_prefix("pairs"))]
    assert len({t["key"] for t in tasks}) == len(tasks) == pairs
    assert len({t["worker"] for t in tasks}) == 2  # both workers ran pairs
    # the job's progress advanced as its tasks ended
    messages = [e["message"] for _, e in client.get_events(TOPIC)
                if e["job"] == "pairs" and e["kind"] == "progress"]
    assert any(m.startswith("pair ") for m in messages)


def test_a_time_limit_stops_the_tasks(client: Client) -> None:
    sets, _ = views(blob, k=10, n=1500, seed=1)  # 45 pairs: seconds of work
    outcome = _submit(client, "late", {"sets": sets, "correspondences": False},
                      time_limit=0.5).result()
    assert outcome.status is JobStatus.FAILED and outcome.timed_out, outcome
    assert _no_task_left(client, "late")


def test_a_dismissal_stops_the_tasks(client: Client) -> None:
    sets, _ = views(blob, k=10, n=1500, seed=1)
    event = Event(cancel_event_name("gone"), client=client)
    event.set()  # dismissed before it started: every task sees it at its first look
    try:
        with get_task_stream(client=client) as stream:
            outcome = _submit(client, "gone", {"sets": sets, "correspondences": False}).result()
        assert outcome.status is JobStatus.DISMISSED, outcome
        assert _no_task_left(client, "gone")
        started = [t for t in stream.data if str(t["key"]).startswith(task_prefix("gone"))]
        assert 0 < len(started) < 45  # tasks ran, and not all: the rest were cancelled
    finally:
        event.clear()


def _fails_on_three(item: int, progress: Any) -> int:
    if item == 3:
        raise DegenerateInputError("Expected a pair to register, got a flat one.",
                                   field=f"sets[{item}]")
    return item


def _map_in_a_job(job_id: str, items: list[int]) -> Any:
    """What a job's algorithm does on a worker: map under the job's mapper."""
    reporter = Reporter(job_id, None, get_worker())
    with job_tasks(reporter):
        assert isinstance(current_mapper(), DaskMapper)
        try:
            return task_map(_fails_on_three, items)
        except DegenerateInputError as exc:
            return type(exc).__name__, exc.field


def test_a_tasks_error_is_the_jobs_error(client: Client) -> None:
    got = client.submit(_map_in_a_job, "err", [0, 1, 2, 3, 4, 5], pure=False).result()
    assert got == ("DegenerateInputError", "sets[3]")
    assert client.submit(_map_in_a_job, "ok", [5, 1, 4], pure=False).result() == [5, 1, 4]


def test_off_a_worker_the_loop_stays_serial() -> None:
    """The fast path's reporter (and an in-process one) has no worker: no tasks."""
    for reporter in (Reporter("fast", None, publish=lambda e: None, cancelled=lambda: False),
                     Reporter("local", None, None)):
        with job_tasks(reporter):
            assert current_mapper() is serial_map
    assert np.array_equal(task_map(lambda x, p: x, [1, 2]), [1, 2])
