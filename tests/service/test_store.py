"""JobStore: the SQLite job table, inputs, results and their durability (no server, no Dask)."""

from __future__ import annotations

import pickle
import sqlite3
import time
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest

from service.jobs.status import ACTIVE, FINISHED, JobStatus, Outcome
from service.jobs.store import (
    JobRecord,
    JobRequest,
    JobStore,
    Subscriber,
    result_path,
    write_atomic,
)


@pytest.fixture
def store(tmp_path: Path) -> Iterator[JobStore]:
    s = JobStore(tmp_path, fsync=False)
    yield s
    s.close()


def _create(store: JobStore, process: str = "alignment.rigid", **kw) -> JobRecord:  # noqa: ANN003
    kw.setdefault("inputs", {"k": 1})
    kw.setdefault("request", JobRequest())
    kw.setdefault("time_limit", None)
    return store.create(process=process, **kw)


def _points(n: int, d: int = 3, seed: int = 0) -> np.ndarray:
    return np.random.default_rng(seed).standard_normal((n, d))


def _same_array(a: np.ndarray, b: np.ndarray) -> bool:
    """Equal dtype, shape and bytes (NaN and -0.0 included)."""
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


# -- creating and reading ------------------------------------------------------------------
def test_create_then_get(store: JobStore) -> None:
    before = time.time()
    request = JobRequest(outputs=("rmse",), response="raw",
                         subscriber=Subscriber(success_uri="http://cb.example/done"))
    job = store.create(process="alignment.rigid", inputs={"k": 1}, request=request,
                       time_limit=12.5, request_hash="abc")
    after = time.time()
    got = store.get(job.id)
    assert got == job
    assert got.process == "alignment.rigid"
    assert got.status == "accepted" and got.active
    assert got.progress == 0 and got.attempts == 0
    assert before <= got.created <= after and before <= got.updated <= after
    assert got.started is None and got.finished is None
    assert got.request == request
    assert got.time_limit == 12.5
    assert got.request_hash == "abc" and got.idempotency_key is None
    assert got.problem is None and got.inputs_file is None


def test_request_is_stored_as_json_as_before(tmp_path: Path, store: JobStore) -> None:
    """The request column holds the JSON object earlier versions wrote, and rows they wrote
    (``'{}'`` included, the column's default) read back as a :class:`JobRequest`."""
    request = JobRequest(outputs=("rmse", "rotation"), response="raw", subscriber=Subscriber(
        success_uri="http://cb.example/ok", failed_uri="http://cb.example/ko"))
    job = _create(store, request=request)
    db = sqlite3.connect(tmp_path / "jobs.sqlite3")
    try:
        (stored,) = db.execute("SELECT request FROM jobs WHERE id = ?", (job.id,)).fetchone()
        assert stored == ('{"outputs": ["rmse", "rotation"], "response": "raw", "subscriber": '
                          '{"successUri": "http://cb.example/ok", '
                          '"failedUri": "http://cb.example/ko"}}')
        old = {"old-full": '{"outputs": null, "response": "document", "subscriber": '
                           '{"inProgressUri": "http://cb.example/p"}}',
               "old-empty": "{}"}
        for job_id, text in old.items():
            db.execute("INSERT INTO jobs (id, process, status, created, updated, request) "
                       "VALUES (?, 'p', 'running', 1, 1, ?)", (job_id, text))
        db.commit()
    finally:
        db.close()
    assert store.get(job.id).request == request
    full, empty = store.get("old-full"), store.get("old-empty")
    assert full.request == JobRequest(subscriber=Subscriber(in_progress_uri="http://cb.example/p"))
    assert empty.request == JobRequest()
    assert full.status is JobStatus.RUNNING and full.active


def test_get_unknown_job_is_none(store: JobStore) -> None:
    assert store.get("no-such-id") is None
    assert store.by_idempotency_key("no-such-key") is None


def test_ids_are_unique(store: JobStore) -> None:
    ids = {_create(store).id for _ in range(20)}
    assert len(ids) == 20


@pytest.mark.parametrize("dtype", [np.float64, np.int64])
def test_inline_inputs_round_trip_bit_exact(store: JobStore, dtype: type) -> None:
    if dtype is np.float64:
        arr = _points(50)
        arr[0, 0], arr[0, 1], arr[0, 2] = -0.0, 5e-324, np.nextafter(1.0, 2.0)
    else:
        arr = np.arange(-75, 75, dtype=np.int64).reshape(50, 3) * (2**40 + 1)
    inputs = {"source": arr, "target": arr[::-1].copy(), "k": 3, "flag": True, "name": "x"}
    job = _create(store, inputs=inputs)
    assert job.inputs_file is None
    got = store.inputs(job)
    assert set(got) == set(inputs)
    for name in ("source", "target"):
        assert isinstance(got[name], np.ndarray)
        assert _same_array(got[name], inputs[name])
    assert got["k"] == 3 and got["flag"] is True and got["name"] == "x"
    payload = store.payload(job)
    assert isinstance(payload, dict) and _same_array(payload["source"], arr)


def test_large_inputs_go_to_a_file(tmp_path: Path) -> None:
    store = JobStore(tmp_path, fsync=False, inline_input_bytes=1024)
    try:
        small = _create(store, inputs={"source": _points(5)})
        assert small.inputs_file is None
        src, idx = _points(1000), np.arange(3000, dtype=np.int64).reshape(1000, 3)
        job = _create(store, inputs={"source": src, "faces": idx})
        assert job.inputs_file == f"inputs/{job.id}.pkl"
        path = tmp_path / "inputs" / f"{job.id}.pkl"
        assert path.is_file()
        # the row does not hold the blob
        db = sqlite3.connect(tmp_path / "jobs.sqlite3")
        try:
            (blob,) = db.execute("SELECT inputs FROM jobs WHERE id = ?", (job.id,)).fetchone()
        finally:
            db.close()
        assert blob is None
        payload = store.payload(job)
        assert payload == str(path)
        from_file = pickle.loads(Path(payload).read_bytes())
        got = store.inputs(job)
        for d in (from_file, got):
            assert _same_array(d["source"], src) and _same_array(d["faces"], idx)
        # no temporary file is left behind by the atomic write
        assert sorted(p.name for p in (tmp_path / "inputs").iterdir()) == [path.name]
    finally:
        store.close()


# -- transitions ---------------------------------------------------------------------------
def test_running_progress_success(store: JobStore) -> None:
    job = _create(store)
    assert not store.set_progress(job.id, 10, "too early")  # only while running
    assert store.get(job.id).progress == 0
    assert store.mark_running(job.id, started=1234.5)
    rec = store.get(job.id)
    assert rec.status == "running" and rec.started == 1234.5 and rec.attempts == 1
    assert rec.active
    assert store.set_progress(job.id, 40, "step 4/10")
    rec = store.get(job.id)
    assert rec.progress == 40 and rec.message == "step 4/10"
    outputs = {"rotation": np.eye(3), "rmse": 0.25, "n_pairs": np.int64(7)}
    assert store.finish(job.id, "successful", "done", outputs=outputs)
    rec = store.get(job.id)
    assert rec.status == "successful" and not rec.active
    assert rec.progress == 100 and rec.message == "done"
    assert rec.finished is not None and rec.finished >= rec.created
    got = store.result(job.id)
    assert set(got) == set(outputs)
    assert _same_array(got["rotation"], outputs["rotation"])
    assert got["rmse"] == 0.25 and got["n_pairs"] == 7
    # finished jobs stay finished
    assert not store.set_progress(job.id, 10, "late")
    assert not store.mark_running(job.id)
    assert not store.finish(job.id, "failed", "late")
    assert not store.dismiss(job.id)
    assert store.get(job.id).status == "successful"


def test_finish_failed_keeps_problem_and_progress(store: JobStore) -> None:
    job = _create(store)
    store.mark_running(job.id)
    store.set_progress(job.id, 30, "working")
    problem = {"type": "/problems/invalid-input", "status": 422, "detail": "bad",
               "errors": [{"input": "source", "message": "bad"}]}
    assert store.finish(job.id, "failed", "bad", problem=problem)
    rec = store.get(job.id)
    assert rec.status == "failed" and rec.problem == problem and rec.progress == 30
    assert not store.result_file_exists(job.id)


def test_finish_on_accepted_job(store: JobStore) -> None:
    job = _create(store)
    assert store.finish(job.id, "successful", "done", outputs={"x": 1})
    assert store.result(job.id) == {"x": 1}


@pytest.mark.parametrize("outcome", [
    Outcome.successful({"x": np.arange(3.0)}),
    Outcome.failed({"type": "/problems/invalid-input", "status": 422, "detail": "bad source",
                    "errors": []})])
def test_create_finished_is_one_transaction(store: JobStore, outcome: Outcome) -> None:
    """A job that ran before its row: row, inputs and outcome in one commit, and the record
    it returns is the one read back."""
    statements: list[str] = []
    store._db.set_trace_callback(statements.append)
    started = time.time()
    job = store.create_finished(outcome, started=started, process="alignment.rigid",
                                inputs={"source": _points(5)}, request=JobRequest(),
                                time_limit=None,
                                job_id="fixed-id", created=started - 0.5)
    store._db.set_trace_callback(None)
    words = [st.split()[0].upper() for st in statements]
    assert words.count("BEGIN") == 1 and words.count("COMMIT") == 1, statements
    assert words[0] == "BEGIN" and words[-1] == "COMMIT", statements
    assert job.id == "fixed-id" and job.created == started - 0.5 and job.started == started
    assert store.get(job.id) == job
    assert job.status is outcome.status and not job.active
    assert job.finished is not None and job.finished >= started
    if job.status == "successful":
        assert job.progress == 100 and job.message == "done"
        assert _same_array(store.result(job.id)["x"], np.arange(3.0))
    else:
        assert job.problem == outcome.problem and job.message == "bad source"
    assert _same_array(store.inputs(job)["source"], _points(5))


def test_finish_on_dismissed_job_does_nothing(store: JobStore) -> None:
    job = _create(store)
    store.mark_running(job.id)
    assert store.dismiss(job.id)
    rec = store.get(job.id)
    assert rec.status == "dismissed" and rec.finished is not None and not rec.active
    assert not store.finish(job.id, "successful", "done", outputs={"x": 1})
    assert store.get(job.id).status == "dismissed"
    with pytest.raises(FileNotFoundError):  # no results row, no results file
        store.result(job.id)
    assert not store.mark_running(job.id)
    assert not store.set_progress(job.id, 50, "x")


def test_finish_unknown_job(store: JobStore) -> None:
    assert not store.finish("nope", "successful", "done", outputs={"x": 1})
    assert not store.mark_running("nope")
    assert not store.dismiss("nope")
    assert not store.requeue("nope")


@pytest.mark.parametrize("start", ["accepted", "running"])
def test_dismiss_active_jobs_only(store: JobStore, start: str) -> None:
    job = _create(store)
    if start == "running":
        store.mark_running(job.id)
    assert store.dismiss(job.id)
    assert store.get(job.id).status == "dismissed"
    assert not store.dismiss(job.id)  # dismissed is final


@pytest.mark.parametrize("final", ["successful", "failed"])
def test_dismiss_refuses_finished_jobs(store: JobStore, final: str) -> None:
    job = _create(store)
    store.finish(job.id, final, final)
    assert not store.dismiss(job.id)
    assert store.get(job.id).status == final


def test_requeue(store: JobStore) -> None:
    job = _create(store)
    store.mark_running(job.id)
    store.set_progress(job.id, 70, "far")
    assert store.requeue(job.id)
    rec = store.get(job.id)
    assert rec.status == "accepted" and rec.progress == 0 and rec.attempts == 1
    assert "restart" in rec.message
    assert store.mark_running(job.id)
    assert store.get(job.id).attempts == 2
    store.finish(job.id, "successful", "done", outputs={})
    assert not store.requeue(job.id)
    assert store.get(job.id).status == "successful"


# -- deleting ------------------------------------------------------------------------------
def test_delete_removes_row_results_and_files(tmp_path: Path) -> None:
    store = JobStore(tmp_path, fsync=False, inline_input_bytes=64)
    try:
        job = _create(store, inputs={"source": _points(100)})
        inputs_file = tmp_path / job.inputs_file
        store.finish(job.id, "successful", "done", outputs={"x": np.ones(3)})
        write_atomic(result_path(tmp_path, job.id), pickle.dumps({"x": np.ones(3)}), fsync=False)
        other = _create(store, inputs={"source": _points(100, seed=1)})
        store.finish(other.id, "successful", "done", outputs={"y": 2})
        assert inputs_file.exists() and store.result_file_exists(job.id)

        store.delete(job.id)
        assert store.get(job.id) is None
        assert not inputs_file.exists()
        assert not store.result_file_exists(job.id)
        with pytest.raises(FileNotFoundError):
            store.result(job.id)
        db = sqlite3.connect(tmp_path / "jobs.sqlite3")
        try:
            assert db.execute("SELECT COUNT(*) FROM results WHERE id = ?",
                              (job.id,)).fetchone() == (0,)
        finally:
            db.close()
        # the other job is untouched
        assert store.result(other.id) == {"y": 2}
        assert (tmp_path / other.inputs_file).exists()
        store.delete(job.id)  # deleting twice is harmless
        store.delete("never-existed")
    finally:
        store.close()


# -- listing and counting ------------------------------------------------------------------
@pytest.fixture
def populated(store: JobStore) -> tuple[JobStore, list[JobRecord]]:
    """Eight jobs, oldest first: statuses cycle through all five, two processes."""
    jobs = []
    plan = [("alignment.rigid", "accepted"), ("assignment.nearest", "running"),
            ("alignment.rigid", "successful"), ("assignment.nearest", "failed"),
            ("alignment.rigid", "dismissed"), ("alignment.rigid", "running"),
            ("assignment.nearest", "accepted"), ("assignment.nearest", "successful")]
    for process, status in plan:
        job = _create(store, process=process)
        if status == "running":
            store.mark_running(job.id)
        elif status in ("successful", "failed"):
            store.finish(job.id, status, status, outputs={} if status == "successful" else None)
        elif status == "dismissed":
            store.dismiss(job.id)
        jobs.append(store.get(job.id))
        assert jobs[-1].status == status
    return store, jobs


def test_page_newest_first_with_total(populated) -> None:  # noqa: ANN001
    store, jobs = populated
    page, total = store.page(limit=100)
    assert total == 8
    assert [j.id for j in page] == [j.id for j in reversed(jobs)]
    assert page == list(reversed(jobs))  # full records


def test_page_limit_offset(populated) -> None:  # noqa: ANN001
    store, jobs = populated
    newest_first = [j.id for j in reversed(jobs)]
    page, total = store.page(limit=3, offset=0)
    assert total == 8 and [j.id for j in page] == newest_first[:3]
    page, total = store.page(limit=3, offset=3)
    assert total == 8 and [j.id for j in page] == newest_first[3:6]
    page, total = store.page(limit=3, offset=6)
    assert total == 8 and [j.id for j in page] == newest_first[6:]
    page, total = store.page(limit=3, offset=100)
    assert total == 8 and page == []
    assert len(store.page()[0]) == 8  # default limit 10


def test_page_filters(populated) -> None:  # noqa: ANN001
    store, jobs = populated

    def expect(statuses=(), processes=()):  # noqa: ANN001, ANN202
        return [j.id for j in reversed(jobs)
                if (not statuses or j.status in statuses)
                and (not processes or j.process in processes)]

    for statuses, processes in [
        (("running",), ()),
        (("accepted", "running"), ()),
        ((), ("assignment.nearest",)),
        (("successful",), ("alignment.rigid",)),
        (("successful", "failed"), ("alignment.rigid", "assignment.nearest")),
        (("dismissed",), ("assignment.nearest",)),
        ((), ("no.such",)),
    ]:
        page, total = store.page(statuses=statuses, processes=processes, limit=100)
        assert [j.id for j in page] == expect(statuses, processes), (statuses, processes)
        assert total == len(expect(statuses, processes))
    # the total counts every match, not only the page
    page, total = store.page(statuses=["accepted", "running"], limit=1)
    assert len(page) == 1 and total == 4
    # generators are accepted as filters
    page, total = store.page(statuses=(s for s in ["failed"]), limit=5)
    assert total == 1 and page[0].status == "failed"


def test_counts(populated) -> None:  # noqa: ANN001
    store, _ = populated
    assert store.count_active() == 4
    assert store.count_by_status() == {"accepted": 2, "running": 2, "successful": 2,
                                       "failed": 1, "dismissed": 1}


def test_counts_of_empty_store(store: JobStore) -> None:
    assert store.count_active() == 0
    assert store.count_by_status() == {}
    assert store.page() == ([], 0)
    assert store.unfinished() == []


def test_unfinished_oldest_first(populated) -> None:  # noqa: ANN001
    store, jobs = populated
    expected = [j.id for j in jobs if j.status in ACTIVE]
    assert [j.id for j in store.unfinished()] == expected
    assert {j.status for j in store.unfinished()} == {"accepted", "running"}
    assert set(ACTIVE) | set(FINISHED) == {"accepted", "running", "successful", "failed",
                                           "dismissed"}


def test_statuses_are_their_wire_strings() -> None:
    assert set(ACTIVE) | set(FINISHED) == set(JobStatus) and not set(ACTIVE) & set(FINISHED)
    assert [str(s) for s in JobStatus] == ["accepted", "running", "successful", "failed",
                                           "dismissed"]
    assert all(s.active == (s in ACTIVE) for s in JobStatus)
    assert JobStatus("failed") is JobStatus.FAILED and f"{JobStatus.RUNNING}" == "running"


# -- idempotency keys ----------------------------------------------------------------------
def test_idempotency_key_is_unique(store: JobStore) -> None:
    job = _create(store, idempotency_key="key-1", request_hash="h1")
    assert store.by_idempotency_key("key-1") == job
    with pytest.raises(sqlite3.IntegrityError):
        _create(store, idempotency_key="key-1", request_hash="h2")
    assert store.page()[1] == 1  # nothing half-created
    other = _create(store, idempotency_key="key-2")
    assert store.by_idempotency_key("key-2").id == other.id
    # jobs without a key do not collide with each other
    _create(store)
    _create(store)
    assert store.page()[1] == 4


# -- results written by a worker -----------------------------------------------------------
def test_result_from_worker_file(tmp_path: Path, store: JobStore) -> None:
    job = _create(store)
    assert not store.result_file_exists(job.id)
    outputs = {"transform": _points(4, 4), "pairs": np.arange(8, dtype=np.int64).reshape(4, 2),
               "rmse": 0.5}
    path = result_path(tmp_path, job.id)
    assert path == tmp_path / "results" / f"{job.id}.pkl"
    write_atomic(path, pickle.dumps(outputs, protocol=5))
    assert store.result_file_exists(job.id)
    assert [p.name for p in path.parent.iterdir()] == [path.name]  # no temporary left
    got = store.result(job.id)  # no results row yet: read from the file
    assert _same_array(got["transform"], outputs["transform"])
    assert _same_array(got["pairs"], outputs["pairs"])
    assert got["rmse"] == 0.5
    # once the row is completed, the results table wins
    store.finish(job.id, "successful", "done", outputs={"rmse": 1.5})
    assert store.result(job.id) == {"rmse": 1.5}


def test_write_atomic_replaces(tmp_path: Path) -> None:
    path = tmp_path / "f.bin"
    write_atomic(path, b"old")
    write_atomic(path, b"new contents", fsync=False)
    assert path.read_bytes() == b"new contents"
    assert [p.name for p in tmp_path.iterdir()] == ["f.bin"]


# -- durability ----------------------------------------------------------------------------
def test_store_survives_reopening(tmp_path: Path) -> None:
    store = JobStore(tmp_path, inline_input_bytes=256)  # fsync on, as in production
    big = _points(200)
    done = store.create(process="alignment.rigid", inputs={"source": big},
                        request=JobRequest(outputs=("rotation",)),
                        time_limit=5.0, idempotency_key="k")
    store.mark_running(done.id)
    store.finish(done.id, "successful", "done", outputs={"rotation": np.eye(3)})
    waiting = store.create(process="assignment.nearest", inputs={"k": 2}, request=JobRequest(),
                           time_limit=None)
    running = store.create(process="assignment.nearest", inputs={"k": 3}, request=JobRequest(),
                           time_limit=None)
    store.mark_running(running.id)
    store.set_progress(running.id, 60, "halfway")
    worker_done = store.create(process="alignment.rigid", inputs={}, request=JobRequest(),
                               time_limit=None)
    write_atomic(result_path(tmp_path, worker_done.id), pickle.dumps({"rmse": 2.0}))
    before = {j.id: j for j in store.page(limit=100)[0]}
    store.close()

    again = JobStore(tmp_path, inline_input_bytes=256)
    try:
        after = {j.id: j for j in again.page(limit=100)[0]}
        assert after == before
        assert _same_array(again.result(done.id)["rotation"], np.eye(3))
        assert _same_array(again.inputs(again.get(done.id))["source"], big)
        assert again.inputs(again.get(waiting.id)) == {"k": 2}
        assert again.by_idempotency_key("k").id == done.id
        assert [j.id for j in again.unfinished()] == [waiting.id, running.id, worker_done.id]
        assert again.get(running.id).progress == 60
        assert again.result_file_exists(worker_done.id)
        assert again.result(worker_done.id) == {"rmse": 2.0}
        # new jobs still go after the old ones
        newest = _create(again)
        assert again.page(limit=1)[0][0].id == newest.id
        with pytest.raises(sqlite3.IntegrityError):
            _create(again, idempotency_key="k")
    finally:
        again.close()


def test_wal_mode(tmp_path: Path, store: JobStore) -> None:
    _create(store)
    (mode,) = store._db.execute("PRAGMA journal_mode").fetchone()
    assert mode.lower() == "wal"
    db = sqlite3.connect(tmp_path / "jobs.sqlite3")  # persistent: any new connection sees it
    try:
        assert db.execute("PRAGMA journal_mode").fetchone()[0].lower() == "wal"
    finally:
        db.close()


def test_synchronous_follows_fsync(tmp_path: Path) -> None:
    full = JobStore(tmp_path / "a", fsync=True)
    normal = JobStore(tmp_path / "b", fsync=False)
    try:
        assert full._db.execute("PRAGMA synchronous").fetchone()[0] == 2  # FULL
        assert normal._db.execute("PRAGMA synchronous").fetchone()[0] == 1  # NORMAL
    finally:
        full.close()
        normal.close()


def test_failed_create_leaves_no_inputs_file(tmp_path: Path) -> None:
    store = JobStore(tmp_path, fsync=False, inline_input_bytes=64)
    try:
        first = _create(store, inputs={"source": _points(100)}, idempotency_key="k")
        with pytest.raises(sqlite3.IntegrityError):
            _create(store, inputs={"source": _points(100)}, idempotency_key="k")
        assert sorted(p.name for p in (tmp_path / "inputs").iterdir()) == [f"{first.id}.pkl"]
    finally:
        store.close()


# -- owners (API keys) -----------------------------------------------------------------------


def test_jobs_are_listed_and_counted_per_owner(store: JobStore) -> None:
    a = store.create(process="p", inputs={}, request=JobRequest(), time_limit=None,
                     owner="alice")
    b = store.create(process="p", inputs={}, request=JobRequest(), time_limit=None,
                     owner="bob")
    assert store.get(a.id).owner == "alice" and store.get(b.id).owner == "bob"
    assert [j.id for j in store.page(owner="alice")[0]] == [a.id]
    assert store.page(owner="carol") == ([], 0)
    assert store.page()[1] == 2  # None: everyone's
    assert store.count_active("alice") == 1 and store.count_active() == 2
    store.finish(a.id, "successful", "done", outputs={})
    assert store.count_active("alice") == 0 and store.count_active("bob") == 1


def test_idempotency_keys_are_scoped_by_owner(store: JobStore) -> None:
    a = store.create(process="p", inputs={}, request=JobRequest(), time_limit=None,
                     idempotency_key="k", owner="alice")
    b = store.create(process="p", inputs={}, request=JobRequest(), time_limit=None,
                     idempotency_key="k", owner="bob")  # no IntegrityError: another owner
    assert store.by_idempotency_key("k", "alice").id == a.id
    assert store.by_idempotency_key("k", "bob").id == b.id
    assert store.by_idempotency_key("k", "carol") is None
    assert store.by_idempotency_key("k") is None  # the open service's "" owner
    assert store.get(a.id).idempotency_key == "k"  # reported as the client sent it
    with pytest.raises(sqlite3.IntegrityError):
        store.create(process="p", inputs={}, request=JobRequest(), time_limit=None,
                     idempotency_key="k", owner="alice")


def test_a_store_from_before_owners_is_migrated(tmp_path: Path) -> None:
    db = sqlite3.connect(tmp_path / "jobs.sqlite3")
    db.executescript("""
        CREATE TABLE jobs (seq INTEGER PRIMARY KEY AUTOINCREMENT, id TEXT NOT NULL UNIQUE,
            process TEXT NOT NULL, status TEXT NOT NULL, message TEXT NOT NULL DEFAULT '',
            progress INTEGER NOT NULL DEFAULT 0, created REAL NOT NULL, started REAL,
            finished REAL, updated REAL NOT NULL, request TEXT NOT NULL DEFAULT '{}',
            inputs BLOB, inputs_file TEXT, problem TEXT, time_limit REAL,
            idempotency_key TEXT UNIQUE, request_hash TEXT,
            attempts INTEGER NOT NULL DEFAULT 0);
        INSERT INTO jobs (id, process, status, created, updated, inputs)
            VALUES ('old', 'p', 'accepted', 1, 1, NULL);
    """)
    db.close()
    s = JobStore(tmp_path, fsync=False)
    try:
        assert s.get("old").owner == "" and s.unfinished()[0].id == "old"
        new = s.create(process="p", inputs={}, request=JobRequest(), time_limit=None,
                       owner="alice")
        assert s.get(new.id).owner == "alice"
    finally:
        s.close()
