"""The embedded Dask scheduler, in a process of its own.

In the service's process the scheduler shared the event loop with the API: every job's
graph, its transitions and the workers' reports were handled between two HTTP requests,
and under load (16 clients) the loop was the bottleneck, with the workers idle most of the
time. Here :class:`SchedulerProcess` runs it in a child process (``spawn``, like Dask's own
worker processes), so that the loop serves requests and the scheduler's work runs on
another core. It is the ``scheduler`` of the engine's :class:`~distributed.LocalCluster`
(:func:`embedded_scheduler`): the nannies stay in the service's process, the workers in
their own, and the cluster talks to the scheduler at its address as it would in process.

The child takes the service's Dask configuration as it is when the scheduler starts (the
engine's quiet monitoring, its allowed failures, no HTTP routes), the cluster's
:class:`~distributed.security.Security` (the in-memory certificate: only the service and
its workers may talk to it) and dies with the service: a thread waits on the parent's
sentinel, so a service killed with ``kill -9`` leaves no scheduler behind.
"""

from __future__ import annotations

import asyncio
import multiprocessing
import multiprocessing.connection
import os
import threading
from typing import Any

import dask
from distributed import LocalCluster, Scheduler, SchedulerPlugin
from distributed.deploy.spec import ProcessInterface

__all__ = ["SchedulerProcess", "embedded_scheduler", "send_promptly", "SEND_INTERVAL",
           "START_TIMEOUT"]

#: Seconds a Dask comm waits after one message before it sends the next (the batching
#: interval of distributed's ``BatchedSend``). Dask's own are 10 ms from a client to the
#: scheduler, 5 ms from the scheduler to a worker and 2 ms from a worker to the scheduler:
#: good for graphs of thousands of small tasks, but a job here is one task, and its
#: submission usually came less than 10 ms after the previous job's release, so it waited
#: out the client's interval (about 5 ms of the p50 of a 1,000-point alignment through
#: Dask, 27 → 22 ms side by side). At 1 ms a burst of jobs is still sent in a few batches.
SEND_INTERVAL = 0.001

#: Seconds the scheduler's process may take to start and report its address.
START_TIMEOUT = 60.0


def send_promptly(comm: Any) -> None:
    """Set the batching interval of a Dask ``BatchedSend`` to at most :data:`SEND_INTERVAL`
    (``interval`` is distributed's own attribute: tests/service/test_engine_scheduler.py checks
    that it is still there and still a float)."""
    if comm is not None and isinstance(getattr(comm, "interval", None), float):
        comm.interval = min(comm.interval, SEND_INTERVAL)


class Prompt(SchedulerPlugin):
    """Has the scheduler send to its workers promptly (:data:`SEND_INTERVAL`)."""

    def add_worker(self, scheduler: Any, worker: str) -> None:
        send_promptly(scheduler.stream_comms.get(worker))

    def add_client(self, scheduler: Any, client: str) -> None:
        # the stream to the client is made just after this call: set once it is there
        def prompt() -> None:
            send_promptly(scheduler.client_comms.get(client))

        scheduler.loop.add_callback(prompt)


class SchedulerProcess(ProcessInterface):
    """A :class:`distributed.Scheduler` with ``options`` in a child process: what a
    :class:`~distributed.SpecCluster` takes as its scheduler (``address``, ``start``,
    ``close``)."""

    def __init__(self, **options: Any) -> None:
        self.options = options
        self.process: Any = None
        super().__init__()

    async def start(self) -> None:
        ctx = multiprocessing.get_context("spawn")
        receive, send = ctx.Pipe(duplex=False)
        self.process = ctx.Process(target=_serve, args=(send, dask.config.config, self.options),
                                   name="morphserve-scheduler", daemon=True)
        self.process.start()
        send.close()
        loop = asyncio.get_running_loop()
        address = await loop.run_in_executor(None, _receive, receive)
        if address is None:
            self.process.kill()
            raise RuntimeError(f"the Dask scheduler's process did not start within "
                               f"{START_TIMEOUT:g} s (exit code {self.process.exitcode})")
        self.address = address
        await super().start()

    async def close(self) -> None:
        process = self.process
        if process is not None and process.is_alive():
            process.terminate()
            loop = asyncio.get_running_loop()
            await loop.run_in_executor(None, process.join, 10)
            if process.is_alive():
                process.kill()
        await super().close()


def _receive(conn: Any) -> str | None:
    """The address the child sends, or None if it exits or is silent too long."""
    try:
        if conn.poll(START_TIMEOUT):
            return str(conn.recv())
    except (EOFError, OSError):
        pass
    finally:
        conn.close()
    return None


def _serve(conn: Any, config: dict[str, Any], options: dict[str, Any]) -> None:
    """The child: run the scheduler until it is closed or the service goes."""
    import logging
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)  # the service closes it on Ctrl-C
    logging.getLogger("distributed").setLevel(logging.ERROR)  # as the cluster's silence_logs
    dask.config.update(dask.config.config, config, priority="new")
    parent = multiprocessing.parent_process()
    if parent is not None:
        def orphaned() -> None:
            multiprocessing.connection.wait([parent.sentinel])
            os._exit(0)

        threading.Thread(target=orphaned, name="morphserve-orphaned", daemon=True).start()
    asyncio.run(_run(conn, options))


async def _run(conn: Any, options: dict[str, Any]) -> None:
    scheduler = await Scheduler(**options)
    if not options.get("dashboard") and scheduler.http_server is not None:
        scheduler.http_server.stop()  # Dask always starts one
    scheduler.add_plugin(Prompt(), name="morphserve-prompt")
    conn.send(scheduler.address)
    conn.close()
    await scheduler.finished()


def embedded_scheduler(cluster: LocalCluster) -> LocalCluster:
    """``cluster`` (a :class:`~distributed.LocalCluster` made with ``asynchronous=True``,
    not yet awaited) with its scheduler in a :class:`SchedulerProcess`, on the options
    the cluster would have given it in process."""
    options = dict(cluster.scheduler_spec["options"])
    if not options.get("dashboard_address"):  # its HTTP server, stopped at once: any port
        options["dashboard_address"] = f"{options.get('host') or '127.0.0.1'}:0"
    cluster.scheduler_spec = {"cls": SchedulerProcess, "options": options}
    return cluster
