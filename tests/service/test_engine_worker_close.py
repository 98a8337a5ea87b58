"""A closing worker lets its heartbeat under way end before it closes its comms (the
engine's ``WarmUp`` plugin, :meth:`~service.jobs.engine.WarmUp.teardown`).

``Worker.close`` closes the worker's pool of comms, the ones in use too: a heartbeat
waiting for the scheduler's answer then failed on its own closed comm and the worker logged
it with a traceback, which a Ctrl-C of ``morphserve serve`` printed about once in 40 on a
loaded 2-core machine (tests/service/test_cli_e2e.py). Here a scheduler and a worker run in
the test's process, the worker's timer stopped: each heartbeat is the test's own."""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Awaitable, Callable
from types import SimpleNamespace
from typing import Any

import pytest
from distributed import Scheduler, Worker
from distributed.core import Status

from service.jobs import engine
from service.jobs.engine import WarmUp

pytestmark = pytest.mark.e2e

Scenario = Callable[[Scheduler, Worker], Awaitable[None]]


class _Errors(logging.Handler):
    def __init__(self) -> None:
        super().__init__(logging.ERROR)
        self.messages: list[str] = []

    def emit(self, record: logging.LogRecord) -> None:
        self.messages.append(self.format(record))


def _errors_of(scenario: Scenario) -> list[str]:
    """Run ``scenario`` on a scheduler and a worker with the plugin, in this process; the
    errors distributed logged meanwhile, tracebacks included."""
    errors = _Errors()
    logger = logging.getLogger("distributed")
    logger.addHandler(errors)

    async def main() -> None:
        async with Scheduler(host="127.0.0.1", port=0, dashboard=False) as scheduler, \
                Worker(scheduler.address, nthreads=1, host="127.0.0.1") as worker:
            await worker.plugin_add(WarmUp(), name="morphserve-warm-up")
            worker.periodic_callbacks["heartbeat"].stop()  # only the scenario's heartbeats
            await scenario(scheduler, worker)

    try:
        asyncio.run(main())
    finally:
        logger.removeHandler(errors)
    return errors.messages


def _heartbeat(worker: Worker) -> Awaitable[Any]:
    """One heartbeat, as the worker's timer runs it."""
    beat = worker.periodic_callbacks["heartbeat"].callback()
    assert beat is not None  # the plugin's wrapper gives the timer its future
    return beat


def test_a_closing_worker_waits_for_its_heartbeats_answer() -> None:
    """The scheduler answers slowly: the heartbeat is under way as the worker closes."""

    async def scenario(scheduler: Scheduler, worker: Worker) -> None:
        answer = scheduler.handlers["heartbeat_worker"]
        asked = asyncio.Event()

        async def slowly(**msg: Any) -> Any:
            asked.set()
            await asyncio.sleep(0.5)
            return answer(**msg)

        scheduler.handlers["heartbeat_worker"] = slowly
        beat = asyncio.ensure_future(_heartbeat(worker))
        await asked.wait()
        await worker.close()
        assert beat.done() and beat.exception() is None
        assert worker.status is Status.closed

    errors = _errors_of(scenario)
    assert errors == [], "\n".join(errors)


def test_a_heartbeat_that_closes_its_worker_does_not_wait_for_itself(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """The scheduler answers that it does not know the worker: the heartbeat closes the
    worker, and that close does not wait for the heartbeat it runs in (which waits for
    the close). The engine's ``asyncio.wait`` is a spy here that waits for nothing and
    notes what it was asked to wait for: without the guard the close asked for its own
    heartbeat (and, really waiting, would stall for :data:`HEARTBEAT_WAIT`)."""
    asked: list[set[Any]] = []

    async def spy(futures: Any, timeout: float | None = None) -> tuple[set[Any], set[Any]]:
        asked.append(set(futures))
        return set(), set(futures)

    monkeypatch.setattr(engine, "asyncio", SimpleNamespace(**{**vars(asyncio), "wait": spy}))

    async def scenario(scheduler: Scheduler, worker: Worker) -> None:
        scheduler.handlers["heartbeat_worker"] = lambda **msg: {"status": "missing"}
        await _heartbeat(worker)
        assert worker.status is Status.closed
        assert asked == []

    errors = _errors_of(scenario)
    assert errors == [], "\n".join(errors)


def test_the_plugin_replaced_or_removed_leaves_the_heartbeat_as_it_was() -> None:
    """A teardown as the plugin is registered again (a service restarted against an
    external scheduler registers it on the workers it finds) or removed, the worker going
    on: its heartbeat runs on, unwrapped."""

    async def scenario(scheduler: Scheduler, worker: Worker) -> None:
        timer = worker.periodic_callbacks["heartbeat"]
        timer.start()
        await worker.plugin_add(WarmUp(), name="morphserve-warm-up")  # again
        assert timer.is_running() and timer.callback != worker.heartbeat
        await _heartbeat(worker)
        await worker.plugin_remove("morphserve-warm-up")
        assert timer.is_running() and timer.callback == worker.heartbeat

    errors = _errors_of(scenario)
    assert errors == [], "\n".join(errors)
