"""The job store on a full disk (no server, no Dask): a 30 MB tmpfs filled until it refuses a
byte. Writes are refused with ``StorageFull`` (an ``OSError`` of errno ENOSPC, answered 507),
reads go on, and the outcome of a job that ends meanwhile is held in memory, read from
there and written once room returns. The server's side: ``test_e2e_disk_full.py``."""

from __future__ import annotations

import asyncio
import errno
import pickle
import sqlite3
import threading
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from service.jobs.status import JobStatus
from service.jobs.store import HOLD_RETRY, JobRequest, JobStore, StorageFull
from tests.small_disk import fill, free_bytes, small_disk


@pytest.fixture
def disk(tmp_path: Path) -> Iterator[Path]:
    with small_disk(tmp_path / "disk") as where:
        yield where


def _create(store: JobStore, **kw: Any) -> Any:
    kw.setdefault("inputs", {"k": 1})
    return store.create(process="p", request=JobRequest(), time_limit=None, **kw)


def _row(data_dir: Path, job_id: str) -> tuple[str, bytes | None]:
    """The job's status and stored outputs, as a fresh connection reads them from disk."""
    db = sqlite3.connect(f"file:{data_dir / 'jobs.sqlite3'}?mode=ro", uri=True)
    try:
        (status,), = db.execute("SELECT status FROM jobs WHERE id = ?", (job_id,))
        out = db.execute("SELECT outputs FROM results WHERE id = ?", (job_id,)).fetchall()
        return status, out[0][0] if out else None
    finally:
        db.close()


def test_the_reserve_is_a_share_of_a_small_volume(disk: Path) -> None:
    store = JobStore(disk, fsync=False)
    try:
        total = 30 * 2**20
        assert store.reserve_bytes == int(total * 0.05)  # under RESERVE_BYTES (64 MiB)
        space = store.space()
        assert space.ok and space.held == 0
        assert 0 < total - space.free_bytes < 2**20  # an empty store takes little room
    finally:
        store.close()


def test_a_full_disk_refuses_new_jobs_and_keeps_reads(disk: Path) -> None:
    store = JobStore(disk, fsync=True)
    try:
        done = _create(store)
        store.finish(done.id, JobStatus.SUCCESSFUL, "done", outputs={"x": np.arange(3.0)})
        fill(disk)
        assert free_bytes(disk) == 0
        space = store.space()
        assert space.free_bytes == 0 and not space.ok

        async def submit() -> None:
            await store.write(store.create, process="p", inputs={"k": 2},
                              request=JobRequest(), time_limit=None)

        with pytest.raises(StorageFull, match="The data dir is full: 0 bytes free") as caught:
            asyncio.run(submit())
        assert caught.value.errno == errno.ENOSPC and caught.value.free_bytes == 0
        with pytest.raises(StorageFull):
            store.spool()  # a large body is refused before a byte of it is received
        assert store.get(done.id).status is JobStatus.SUCCESSFUL
        assert store.result(done.id)["x"].tolist() == [0.0, 1.0, 2.0]
        assert store.page()[1] == 1
    finally:
        store.close()


def test_writes_that_find_no_room_raise_storage_full_and_leave_no_file(
        disk: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Past the reserve's check (switched off here), the write itself fails: SQLite's
    SQLITE_FULL, or ENOSPC from the inputs file or the spool; each is a StorageFull, and no
    file of the refused job stays."""
    store = JobStore(disk, fsync=True, inline_input_bytes=1024, reserve_bytes=0)
    try:
        kept = _create(store)
        fill(disk)
        monkeypatch.setattr(store, "_check_room", lambda needed=0: None)

        async def create(**kw: Any) -> Any:
            return await store.write(store.create, process="p", request=JobRequest(),
                                     time_limit=None, **kw)

        with pytest.raises(StorageFull) as caught:  # the row: SQLite finds no room
            asyncio.run(create(inputs={"k": 2}))
        assert isinstance(caught.value.__cause__, sqlite3.OperationalError)
        assert caught.value.__cause__.sqlite_errorcode == sqlite3.SQLITE_FULL
        with pytest.raises(StorageFull) as caught:  # an inputs file: ENOSPC
            asyncio.run(create(inputs={"a": np.ones(100_000)}))
        assert isinstance(caught.value.__cause__, OSError)
        assert caught.value.__cause__.errno == errno.ENOSPC

        body = bytearray(b"y" * 300_000)

        async def spooled() -> Any:
            spool = store.spool()
            spool.write(bytes(body))
            view = np.frombuffer(body, dtype=np.uint8)
            return await create(inputs={"a": view}, spool=spool, body=body)

        with pytest.raises(StorageFull):  # the spool's writes: ENOSPC, raised when sealed
            asyncio.run(spooled())
        assert sorted(p.name for p in (disk / "inputs").iterdir()) == []
        assert [j.id for j in store.page()[0]] == [kept.id]
    finally:
        store.close()


async def _one_batch(store: JobStore, writes: Callable[[], list[asyncio.Future[Any]]],
                     before: Callable[[], None] = lambda: None) -> list[Any]:
    """The outcomes of the ``writes`` queued while the writer thread is held, so that they
    are group-committed in one transaction; ``before`` runs just before they are queued."""
    started, release = threading.Event(), threading.Event()

    def gate() -> None:
        started.set()
        release.wait(30)

    gated = store.write(gate)
    assert await asyncio.to_thread(started.wait, 30)
    before()
    queued = writes()
    release.set()
    await gated
    return await asyncio.gather(*queued, return_exceptions=True)


def _big_create(store: JobStore, i: int, **kw: Any) -> asyncio.Future[Any]:
    return store.write(store.create, process="p", request=JobRequest(), time_limit=None,
                       inputs={"a": np.full(50, i, float)}, **kw)


def test_a_failed_commit_removes_the_inputs_files_of_its_batch(tmp_path: Path) -> None:
    """Jobs group-committed together whose COMMIT fails (as on a full disk): none is stored,
    and none of their inputs files stays behind."""
    store = JobStore(tmp_path, fsync=False, inline_input_bytes=64)
    real = store._db

    class CommitFails:
        def __getattr__(self, name: str) -> Any:
            return getattr(real, name)

        def execute(self, sql: str, *args: Any) -> Any:
            if sql == "COMMIT":
                raise sqlite3.OperationalError("database or disk is full")
            return real.execute(sql, *args)

    def failing() -> None:
        store._db = CommitFails()  # type: ignore[assignment]

    try:
        outcomes = asyncio.run(_one_batch(
            store, lambda: [_big_create(store, i) for i in range(5)], failing))
        store._db = real
        assert [type(o) for o in outcomes] == [sqlite3.OperationalError] * 5
        assert list((tmp_path / "inputs").iterdir()) == []
        assert store.page()[1] == 0
        assert not real.in_transaction
        _create(store)  # the connection is usable again
    finally:
        store._db = real
        store.close()


def test_a_job_refused_in_a_batch_leaves_no_file_and_the_others_are_stored(
        tmp_path: Path) -> None:
    store = JobStore(tmp_path, fsync=False, inline_input_bytes=64)
    try:
        outcomes = asyncio.run(_one_batch(store, lambda: [
            _big_create(store, 0, idempotency_key="k"), _big_create(store, 1),
            _big_create(store, 2, idempotency_key="k")]))  # the key raced in: refused
        assert isinstance(outcomes[2], sqlite3.IntegrityError)
        stored = {f"{o.id}.pkl" for o in outcomes[:2]}
        assert {p.name for p in (tmp_path / "inputs").iterdir()} == stored
        assert store.page()[1] == 2
    finally:
        store.close()


def test_an_outcome_that_finds_no_room_is_held_then_written(disk: Path) -> None:
    store = JobStore(disk, fsync=True)
    try:
        job = _create(store)
        assert store.mark_running(job.id)
        filler = fill(disk)
        outputs = {"rotation": np.eye(3)}

        async def finish() -> Any:
            await store.write(store.mark_running, job.id)  # dropped: no error
            await store.write(store.set_progress, job.id, 50, "half")  # dropped
            return await store.write(store.finish, job.id, JobStatus.SUCCESSFUL, "done",
                                     None, outputs, started=1.0)

        assert asyncio.run(finish()) is True  # held: the engine goes on
        # the job reads as ended, its results too; on disk it is still running
        held = store.get(job.id)
        assert held.status is JobStatus.SUCCESSFUL and held.progress == 100
        assert held.message == "done" and held.finished is not None and not held.active
        assert store.result(job.id)["rotation"].tolist() == np.eye(3).tolist()
        assert _row(disk, job.id) == ("running", None)
        assert store.space().held == 1 and not store.space().ok

        filler.unlink()  # room again: the writer thread writes it within HOLD_RETRY
        deadline = time.monotonic() + 20 * HOLD_RETRY
        while store.space().held and time.monotonic() < deadline:
            time.sleep(HOLD_RETRY / 10)
        assert store.space().held == 0 and store.space().ok
        status, blob = _row(disk, job.id)
        assert status == "successful" and blob is not None
        assert pickle.loads(blob)["rotation"].tolist() == np.eye(3).tolist()
        again = store.get(job.id)
        assert again.status is JobStatus.SUCCESSFUL and again.finished == held.finished
    finally:
        store.close()


def test_a_held_job_deleted_before_room_returns_is_gone(disk: Path) -> None:
    """DELETE of a job whose outcome is held: refused while there is no room (the job still
    reads as ended), done once there is; the held outcome goes with the row."""
    store = JobStore(disk, fsync=True)
    try:
        job = _create(store)
        store.mark_running(job.id)
        filler = fill(disk)

        async def finish_then_delete() -> None:
            await store.write(store.finish, job.id, JobStatus.FAILED, "boom",
                              {"type": "/problems/job-failed"}, None)
            assert store.get(job.id).status is JobStatus.FAILED
            with pytest.raises(StorageFull):  # no room for the deletion either
                await store.write(store.delete, job.id)
            assert store.get(job.id).status is JobStatus.FAILED  # still held, still read
            filler.unlink()
            await store.write(store.delete, job.id)

        asyncio.run(finish_then_delete())
        assert store.get(job.id) is None and store.space().held == 0
    finally:
        store.close()
