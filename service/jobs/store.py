"""The job store: SQLite in WAL mode under the data dir, plus result files.

Durability rules (what "nothing accepted is lost" rests on):

* a job's row and its inputs are committed (``synchronous=FULL``) before the service answers
  ``201``/``200``; inputs above ``inline_input_bytes`` are written to ``inputs/{id}.pkl`` and
  fsynced first, the row names the file;
* outputs that reach the service are stored in the ``results`` table in the same transaction
  that marks the row ``successful``; with an external scheduler the worker also writes
  ``results/{id}.pkl`` atomically (temporary file, fsync, rename) so that work survives a
  restarting API: a result file without its row update is found on start-up and the row
  completed from it;
* rows still ``accepted`` or ``running`` at start-up are submitted again (at-least-once).

One connection, guarded by a lock, is shared by the event loop and the threads it hands
heavy writes to. Writes sent through :meth:`JobStore.write` are group-committed: the writer
thread takes every write waiting when it is free and runs them in one transaction, each in
its own savepoint (one failing leaves the others), so that a burst of jobs costs one fsync
instead of one each; each caller hears back only after the commit that made its write
durable. Pickle is only ever read back from files this service wrote itself.
"""

from __future__ import annotations

import asyncio
import contextlib
import dataclasses
import functools
import json
import os
import pickle
import queue
import sqlite3
import threading
import time
import uuid
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal, TypeVar

import numpy as np

from service.jobs.spool import Spool, load_inputs, remove_stale
from service.jobs.status import ACTIVE, FINISHED, JobStatus, Outcome

__all__ = ["JobRecord", "JobRequest", "Subscriber", "JobStore", "JobStatus", "ACTIVE",
           "FINISHED", "write_atomic", "result_path"]

T = TypeVar("T")

#: Most writes group-committed in one transaction.
MAX_BATCH = 256

#: SQL: the row's job is accepted or running.
_IS_ACTIVE = "status IN (" + ", ".join(f"'{s}'" for s in ACTIVE) + ")"

_SCHEMA = """
CREATE TABLE IF NOT EXISTS jobs (
    seq             INTEGER PRIMARY KEY AUTOINCREMENT,
    id              TEXT NOT NULL UNIQUE,
    process         TEXT NOT NULL,
    status          TEXT NOT NULL,
    message         TEXT NOT NULL DEFAULT '',
    progress        INTEGER NOT NULL DEFAULT 0,
    created         REAL NOT NULL,
    started         REAL,
    finished        REAL,
    updated         REAL NOT NULL,
    request         TEXT NOT NULL DEFAULT '{}',
    inputs          BLOB,
    inputs_file     TEXT,
    problem         TEXT,
    time_limit      REAL,
    idempotency_key TEXT UNIQUE,
    request_hash    TEXT,
    attempts        INTEGER NOT NULL DEFAULT 0,
    owner           TEXT NOT NULL DEFAULT ''
);
CREATE TABLE IF NOT EXISTS results (
    id              TEXT PRIMARY KEY REFERENCES jobs(id) ON DELETE CASCADE,
    outputs         BLOB NOT NULL
);
CREATE INDEX IF NOT EXISTS jobs_status ON jobs(status);
CREATE INDEX IF NOT EXISTS jobs_process ON jobs(process);
"""

#: Run after the schema: indexes on columns that stores made by earlier versions lack until
#: ``_migrate`` adds them.
_INDEXES = """
CREATE INDEX IF NOT EXISTS jobs_owner ON jobs(owner, status);
"""

_COLUMNS = ("id", "process", "status", "message", "progress", "created", "started",
            "finished", "updated", "request", "problem", "time_limit", "idempotency_key",
            "request_hash", "attempts", "inputs_file", "owner")
_SELECT = ", ".join(_COLUMNS)


@dataclass(frozen=True)
class Subscriber:
    """The URLs an execute request's ``subscriber`` names (OGC callbacks), checked by
    :func:`service.callbacks.check_subscriber`; None where the client named none."""

    success_uri: str | None = None
    """POSTed the results document when the job succeeds."""
    in_progress_uri: str | None = None
    """POSTed the statusInfo when the job starts."""
    failed_uri: str | None = None
    """POSTed the statusInfo when the job fails or is dismissed."""

    _MEMBERS = (("successUri", "success_uri"), ("inProgressUri", "in_progress_uri"),
                ("failedUri", "failed_uri"))

    def to_json(self) -> dict[str, str]:
        """The ``subscriber`` object of the request: the members named, by their OGC names."""
        return {member: uri for member, name in self._MEMBERS
                if (uri := getattr(self, name)) is not None}

    @classmethod
    def from_json(cls, doc: Mapping[str, str]) -> Subscriber:
        return cls(**{name: doc[member] for member, name in cls._MEMBERS if member in doc})


@dataclass(frozen=True)
class JobRequest:
    """What the client asked for besides the inputs; stored with the job, as the JSON
    object ``{"outputs": [...] | null, "response": ..., "subscriber": {...} | null}``."""

    outputs: tuple[str, ...] | None = None
    """The outputs to send, in the process's order; None (or empty): all of them."""
    response: Literal["document", "raw"] = "document"
    """``raw``: a single output is sent as its bare value, not in a results document."""
    subscriber: Subscriber | None = None
    """Whom to call back when the job starts and ends; None: nobody."""

    def to_json(self) -> dict[str, Any]:
        return {"outputs": None if self.outputs is None else list(self.outputs),
                "response": self.response,
                "subscriber": self.subscriber.to_json() if self.subscriber else None}

    @classmethod
    def from_json(cls, doc: Mapping[str, Any]) -> JobRequest:
        """Read a stored request; a member missing (rows of ``'{}'``) takes its default."""
        outputs, subscriber = doc.get("outputs"), doc.get("subscriber")
        return cls(outputs=None if outputs is None else tuple(outputs),
                   response=doc.get("response") or "document",
                   subscriber=Subscriber.from_json(subscriber) if subscriber else None)


@dataclass(frozen=True)
class JobRecord:
    """One row of the job table (without the inputs blob)."""

    id: str
    process: str
    status: JobStatus
    message: str
    progress: int
    created: float
    started: float | None
    finished: float | None
    updated: float
    request: JobRequest
    """What the client asked for besides the inputs: outputs, response mode, subscriber."""
    problem: dict[str, Any] | None
    time_limit: float | None
    idempotency_key: str | None
    request_hash: str | None
    attempts: int
    inputs_file: str | None
    owner: str = ""
    """The API key's name that created the job; "" when the service runs without keys."""

    def __post_init__(self) -> None:
        if not isinstance(self.status, JobStatus):  # "running" is RUNNING
            object.__setattr__(self, "status", JobStatus(self.status))

    @classmethod
    def accepted(cls, *, process: str, request: JobRequest, time_limit: float | None,
                 idempotency_key: str | None = None, request_hash: str | None = None,
                 owner: str = "", job_id: str | None = None, created: float | None = None,
                 inputs_file: str | None = None) -> JobRecord:
        """A job just accepted, not yet run: its record as :meth:`JobStore.create` writes
        it. ``job_id`` and ``created`` are new ones unless given."""
        now = created or time.time()
        return cls(id=job_id or str(uuid.uuid4()), process=process,
                   status=JobStatus.ACCEPTED, message="", progress=0, created=now,
                   started=None, finished=None, updated=now, request=request, problem=None,
                   time_limit=time_limit, idempotency_key=idempotency_key,
                   request_hash=request_hash, attempts=0, inputs_file=inputs_file, owner=owner)

    @property
    def active(self) -> bool:
        return self.status in ACTIVE


def _settle(future: asyncio.Future[Any], outcome: tuple[bool, Any]) -> None:
    if future.done():  # the awaiting request went away
        return
    ok, value = outcome
    if ok:
        future.set_result(value)
    else:
        future.set_exception(value)


def _scoped(owner: str, key: str | None) -> str | None:
    """The stored form of an Idempotency-Key: prefixed by its owner, so that one key's
    clients can neither collide with nor find another's jobs through it."""
    if key is None or not owner:
        return key
    return f"{owner}\x1f{key}"


def _record(row: tuple[Any, ...]) -> JobRecord:
    d = dict(zip(_COLUMNS, row, strict=True))
    key, owner = d["idempotency_key"], d["owner"]
    if key is not None and owner and key.startswith(owner + "\x1f"):
        d["idempotency_key"] = key[len(owner) + 1:]
    d["request"] = JobRequest.from_json(json.loads(d["request"]))
    d["problem"] = json.loads(d["problem"]) if d["problem"] else None
    return JobRecord(**d)


def _array_bytes(inputs: Mapping[str, Any]) -> int:
    """The bytes of the numpy arrays among the inputs (a lower bound of their pickle)."""
    total = 0
    for value in inputs.values():
        if isinstance(value, np.ndarray):
            total += value.nbytes
        elif dataclasses.is_dataclass(value) and not isinstance(value, type):
            total += sum(getattr(value, f.name).nbytes for f in dataclasses.fields(value)
                         if isinstance(getattr(value, f.name), np.ndarray))
    return total


def write_atomic(path: Path, data: Any, *, fsync: bool = True) -> None:
    """Write ``data`` (bytes, or any object, pickled as it is written) to ``path`` so that
    readers see the old file or the whole new one."""
    tmp = path.with_name(f".{path.name}.{uuid.uuid4().hex}.tmp")
    with open(tmp, "wb") as f:
        if isinstance(data, (bytes, bytearray, memoryview)):
            f.write(data)
        else:  # protocol 5 writes a large array's buffer straight to the file
            pickle.dump(data, f, protocol=5)
        if fsync:
            f.flush()
            os.fsync(f.fileno())
    os.replace(tmp, path)
    if fsync:
        dir_fd = os.open(path.parent, os.O_RDONLY)
        try:
            os.fsync(dir_fd)
        finally:
            os.close(dir_fd)


def result_path(data_dir: Path, job_id: str) -> Path:
    """Where the worker writes the outputs of ``job_id``."""
    return Path(data_dir) / "results" / f"{job_id}.pkl"


class JobStore:
    """Jobs, their inputs and their results under ``data_dir``."""

    def __init__(self, data_dir: Path, *, fsync: bool = True, inline_input_bytes: int = 2**20
                 ) -> None:
        self.data_dir = Path(data_dir)
        self.fsync = fsync
        self.inline_input_bytes = inline_input_bytes
        for sub in ("results", "inputs"):
            (self.data_dir / sub).mkdir(parents=True, exist_ok=True)
        remove_stale(self.data_dir / "inputs")
        path = self.data_dir / "jobs.sqlite3"
        # One connection writes, another reads: in WAL mode readers never wait for a commit's
        # fsync, and the event loop only ever reads.
        self._lock = threading.RLock()  # a batch's transaction holds it around its writes
        self._db = sqlite3.connect(path, isolation_level=None, check_same_thread=False)
        self._db.execute("PRAGMA journal_mode=WAL")
        self._db.execute(f"PRAGMA synchronous={'FULL' if fsync else 'NORMAL'}")
        self._db.execute("PRAGMA busy_timeout=5000")
        self._db.executescript(_SCHEMA)
        self._migrate()
        self._db.executescript(_INDEXES)
        self._rlock = threading.Lock()
        self._rdb = sqlite3.connect(path, isolation_level=None, check_same_thread=False)
        self._rdb.execute("PRAGMA busy_timeout=5000")
        self._queue: queue.SimpleQueue[Any] = queue.SimpleQueue()
        self._writer = threading.Thread(target=self._write_loop, name="morphserve-store",
                                        daemon=True)
        self._writer.start()

    def _migrate(self) -> None:
        """Bring a store written by an earlier version up to the current schema."""
        columns = {row[1] for row in self._db.execute("PRAGMA table_info(jobs)")}
        if "owner" not in columns:
            self._db.execute("ALTER TABLE jobs ADD COLUMN owner TEXT NOT NULL DEFAULT ''")

    def close(self) -> None:
        self._queue.put(None)
        self._writer.join()
        with self._lock:
            self._db.close()
        with self._rlock:
            self._rdb.close()

    def write(self, method: Callable[..., T], /, *args: Any, **kwargs: Any
              ) -> asyncio.Future[T]:
        """Run a writing ``method`` of this store on its writer thread; await the result,
        which arrives once the write is committed.

        Writes happen in submission order, off the event loop (a commit waits for its fsync
        without holding the GIL, so the loop serves other requests meanwhile), and those
        waiting together share one commit (see the module's notes)."""
        loop = asyncio.get_running_loop()
        future: asyncio.Future[T] = loop.create_future()
        self._queue.put((functools.partial(method, *args, **kwargs), loop, future))
        return future

    def _write_loop(self) -> None:
        while True:
            first = self._queue.get()
            if first is None:
                return
            batch = [first]
            stop = False
            while len(batch) < MAX_BATCH:
                try:
                    item = self._queue.get_nowait()
                except queue.Empty:
                    break
                if item is None:
                    stop = True
                    break
                batch.append(item)
            outcomes = self._run_batch([call for call, _, _ in batch])
            for (_, loop, future), outcome in zip(batch, outcomes, strict=True):
                try:
                    loop.call_soon_threadsafe(_settle, future, outcome)
                except RuntimeError:  # the loop is closed: nobody is waiting any more
                    pass
            if stop:
                return

    def _run_batch(self, calls: list[Callable[[], Any]]) -> list[tuple[bool, Any]]:
        """Run the calls in one transaction, each in a savepoint; (ok, value or error)."""
        if len(calls) == 1:
            try:
                return [(True, calls[0]())]
            except BaseException as exc:  # noqa: BLE001 - handed to the awaiting caller
                return [(False, exc)]
        outcomes: list[tuple[bool, Any]] = []
        with self._lock:
            try:
                self._db.execute("BEGIN IMMEDIATE")
                for call in calls:
                    try:
                        with self._atomic():
                            outcomes.append((True, call()))
                    except BaseException as exc:  # noqa: BLE001
                        outcomes.append((False, exc))
                self._db.execute("COMMIT")
            except BaseException as exc:  # noqa: BLE001 - the commit failed: nothing is durable
                if self._db.in_transaction:
                    self._db.execute("ROLLBACK")
                return [(False, exc)] * len(calls)
        return outcomes

    @contextlib.contextmanager
    def _atomic(self) -> Iterator[None]:
        """All or nothing: a transaction of its own, or a savepoint inside the current one."""
        with self._lock:
            if self._db.in_transaction:
                self._db.execute("SAVEPOINT atomic")
                try:
                    yield
                except BaseException:
                    self._db.execute("ROLLBACK TO atomic")
                    self._db.execute("RELEASE atomic")
                    raise
                self._db.execute("RELEASE atomic")
            else:
                self._db.execute("BEGIN IMMEDIATE")
                try:
                    yield
                except BaseException:
                    self._db.execute("ROLLBACK")
                    raise
                self._db.execute("COMMIT")

    # -- writing -----------------------------------------------------------------------------
    def create(self, *, process: str, inputs: Mapping[str, Any], request: JobRequest,
               time_limit: float | None, idempotency_key: str | None = None,
               request_hash: str | None = None, owner: str = "", job_id: str | None = None,
               created: float | None = None, spool: Spool | None = None,
               body: Any = None, encoded: Sequence[tuple[bytearray, int, int]] = ()
               ) -> JobRecord:
        """Record a new accepted job with its inputs; durable when this returns.

        ``idempotency_key`` is unique per ``owner``: two keys' clients may use the same.
        ``job_id`` and ``created`` are new ones unless given (a job run before its row was
        written, :meth:`create_finished`). ``spool``: the request ``body`` already on its
        way to disk, which large inputs (views of it, or ``encoded``: bytes decoded from
        base64 text in it) are sealed into; always consumed."""
        job_id = job_id or str(uuid.uuid4())
        inputs_file = None
        blob: bytes | None = None
        large = _array_bytes(inputs) > self.inline_input_bytes
        if spool is not None and not large:
            spool.discard()
        if large and spool is not None:  # the body is (mostly) on disk already
            inputs_file = f"inputs/{job_id}.pkl"
            spool.seal(dict(inputs), body, self.data_dir / inputs_file, encoded)
        elif large:  # pickled straight into the file: no copy of large arrays as one blob
            inputs_file = f"inputs/{job_id}.pkl"
            write_atomic(self.data_dir / inputs_file, dict(inputs), fsync=self.fsync)
        else:
            blob = pickle.dumps(dict(inputs), protocol=5)
            if len(blob) > self.inline_input_bytes:
                inputs_file = f"inputs/{job_id}.pkl"
                write_atomic(self.data_dir / inputs_file, blob, fsync=self.fsync)
                blob = None
        job = JobRecord.accepted(process=process, request=request, time_limit=time_limit,
                                 idempotency_key=idempotency_key, request_hash=request_hash,
                                 owner=owner, job_id=job_id, created=created,
                                 inputs_file=inputs_file)
        try:
            with self._lock:
                self._db.execute(
                    "INSERT INTO jobs (id, process, status, created, updated, request, inputs, "
                    "inputs_file, time_limit, idempotency_key, request_hash, owner) "
                    "VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)",
                    (job.id, job.process, job.status, job.created, job.updated,
                     json.dumps(job.request.to_json()), blob, job.inputs_file, job.time_limit,
                     _scoped(job.owner, job.idempotency_key), job.request_hash, job.owner))
        except BaseException:  # e.g. the idempotency key raced in: leave no orphan file
            if inputs_file:
                (self.data_dir / inputs_file).unlink(missing_ok=True)
            raise
        return job

    def create_finished(self, outcome: Outcome, *, started: float, **create: Any) -> JobRecord:
        """Record a job that already ran (a fast-path job the client waited for): its row,
        inputs and outcome in one transaction, so one commit (one fsync) instead of the two
        of :meth:`create` and :meth:`finish`. Nothing was accepted before this returns: the
        client hears of the job only after the commit. ``create`` are :meth:`create`'s
        arguments, ``outcome`` is the runner's (successful with outputs, or failed)."""
        status, problem, message = outcome.status, outcome.problem, outcome.message
        with self._atomic():  # a savepoint when group-committed: not readable till the commit
            job = self.create(**create)
            now = time.time()
            self.finish(job.id, status, message, problem, outcome.outputs,
                        started=started, now=now)
        return dataclasses.replace(
            job, status=status, message=message, problem=dict(problem) if problem else None,
            progress=100 if status is JobStatus.SUCCESSFUL else 0, started=started,
            finished=now, updated=now)

    def _update(self, job_id: str, where: str = "", **values: Any) -> bool:
        values.setdefault("updated", time.time())
        cols = ", ".join(f"{k} = ?" for k in values)
        args = [json.dumps(v) if k in ("problem", "request") and v is not None else v
                for k, v in values.items()]
        with self._lock:
            cur = self._db.execute(f"UPDATE jobs SET {cols} WHERE id = ? {where}",
                                   (*args, job_id))
        return cur.rowcount > 0

    def mark_running(self, job_id: str, started: float | None = None) -> bool:
        """accepted -> running (no effect on a finished or dismissed job)."""
        with self._lock:
            cur = self._db.execute(
                "UPDATE jobs SET status = ?, started = ?, updated = ?, "
                "message = 'running', attempts = attempts + 1 "
                f"WHERE id = ? AND {_IS_ACTIVE}",
                (JobStatus.RUNNING, started or time.time(), time.time(), job_id))
        return cur.rowcount > 0

    def set_progress(self, job_id: str, progress: int, message: str) -> bool:
        return self._update(job_id, f"AND status = '{JobStatus.RUNNING}'",
                            progress=int(progress), message=message)

    def finish(self, job_id: str, status: JobStatus, message: str,
               problem: Mapping[str, Any] | None = None,
               outputs: Mapping[str, Any] | None = None,
               started: float | None = None, now: float | None = None) -> bool:
        """running/accepted -> successful/failed, with the outputs in the same transaction.
        A dismissed job stays dismissed. ``started`` fills in a start time never recorded
        (fast-path jobs are not marked running: they take milliseconds); ``now`` is the
        end's time (default: now)."""
        now = now or time.time()
        status = JobStatus(status)
        blob = pickle.dumps(dict(outputs), protocol=5) if outputs is not None else None
        with self._atomic():
            cur = self._db.execute(
                "UPDATE jobs SET status = ?, message = ?, finished = ?, updated = ?, "
                "problem = ?, progress = CASE WHEN ? THEN 100 ELSE progress "
                "END, started = COALESCE(started, ?) "
                f"WHERE id = ? AND {_IS_ACTIVE}",
                (status, message, now, now, json.dumps(dict(problem)) if problem else None,
                 status is JobStatus.SUCCESSFUL, started, job_id))
            if cur.rowcount and blob is not None:
                self._db.execute("INSERT OR REPLACE INTO results (id, outputs) VALUES (?, ?)",
                                 (job_id, blob))
        return cur.rowcount > 0

    def requeue(self, job_id: str) -> bool:
        """Back to accepted, for a resubmission after a restart."""
        return self._update(job_id, f"AND {_IS_ACTIVE}", status=JobStatus.ACCEPTED,
                            message="resubmitted after a restart", progress=0)

    def dismiss(self, job_id: str) -> bool:
        now = time.time()
        return self._update(job_id, f"AND {_IS_ACTIVE}", status=JobStatus.DISMISSED,
                            message="dismissed by the client", finished=now, updated=now)

    def delete(self, job_id: str) -> None:
        rec = self.get(job_id)
        with self._atomic():
            self._db.execute("DELETE FROM results WHERE id = ?", (job_id,))
            self._db.execute("DELETE FROM jobs WHERE id = ?", (job_id,))
        if rec is not None and rec.inputs_file:
            (self.data_dir / rec.inputs_file).unlink(missing_ok=True)
        result_path(self.data_dir, job_id).unlink(missing_ok=True)

    # -- reading -----------------------------------------------------------------------------
    def _read(self, sql: str, args: Iterable[Any] = ()) -> list[tuple[Any, ...]]:
        """All rows of one query on the reader connection, its cursor closed at once: a
        cursor left open would pin the connection's WAL snapshot and hide later commits."""
        with self._rlock:
            cur = self._rdb.execute(sql, tuple(args))
            try:
                return cur.fetchall()
            finally:
                cur.close()

    def _jobs(self, where: str, args: Iterable[Any] = ()) -> list[JobRecord]:
        return [_record(r) for r in self._read(f"SELECT {_SELECT} FROM jobs {where}", args)]

    def get(self, job_id: str) -> JobRecord | None:
        found = self._jobs("WHERE id = ?", (job_id,))
        return found[0] if found else None

    def by_idempotency_key(self, key: str, owner: str = "") -> JobRecord | None:
        found = self._jobs("WHERE idempotency_key = ?", (_scoped(owner, key),))
        return found[0] if found else None

    def page(self, *, statuses: Iterable[JobStatus | str] = (), processes: Iterable[str] = (),
             limit: int = 10, offset: int = 0, owner: str | None = None
             ) -> tuple[list[JobRecord], int]:
        """A page of jobs, newest first, and the number of jobs matching the filter
        (``owner`` None: every owner's)."""
        where: list[str] = []
        args: list[Any] = []
        if owner is not None:
            where.append("owner = ?")
            args.append(owner)
        for col, vals in (("status", list(statuses)), ("process", list(processes))):
            if vals:
                where.append(f"{col} IN ({', '.join('?' * len(vals))})")
                args += vals
        clause = f"WHERE {' AND '.join(where)}" if where else ""
        total = self._read(f"SELECT COUNT(*) FROM jobs {clause}", args)[0][0]
        jobs = self._jobs(f"{clause} ORDER BY seq DESC LIMIT ? OFFSET ?", (*args, limit, offset))
        return jobs, total

    def count_active(self, owner: str | None = None) -> int:
        """Jobs accepted or running, of one ``owner`` or (None) of all."""
        if owner is None:
            return int(self._read(f"SELECT COUNT(*) FROM jobs WHERE {_IS_ACTIVE}")[0][0])
        return int(self._read(f"SELECT COUNT(*) FROM jobs WHERE owner = ? AND {_IS_ACTIVE}",
                              (owner,))[0][0])

    def count_by_status(self) -> dict[JobStatus, int]:
        return {JobStatus(s): n for s, n in self._read(
            "SELECT status, COUNT(*) FROM jobs GROUP BY status")}

    def count_by_process(self) -> dict[tuple[str, JobStatus], int]:
        """``{(process, status): jobs}`` over the whole store."""
        return {(p, JobStatus(s)): n for p, s, n in self._read(
            "SELECT process, status, COUNT(*) FROM jobs GROUP BY process, status")}

    def unfinished(self) -> list[JobRecord]:
        """Jobs accepted or running, oldest first (what a restart must finish)."""
        return self._jobs(f"WHERE {_IS_ACTIVE} ORDER BY seq")

    def inputs(self, job: JobRecord) -> dict[str, Any]:
        """The job's validated inputs, as the algorithm's keyword arguments."""
        inputs: dict[str, Any]
        if job.inputs_file:
            inputs = load_inputs(self.data_dir / job.inputs_file)
        else:
            ((blob,),) = self._read("SELECT inputs FROM jobs WHERE id = ?", (job.id,))
            inputs = pickle.loads(blob)
        return inputs

    def spool(self) -> Spool:
        """A new :class:`Spool` for a request body, in the inputs directory."""
        return Spool(self.data_dir / "inputs", fsync=self.fsync)

    def payload(self, job: JobRecord) -> dict[str, Any] | str:
        """What travels to the worker: small inputs themselves, large ones by file path."""
        if job.inputs_file:
            return str(self.data_dir / job.inputs_file)
        return self.inputs(job)

    def result_file_exists(self, job_id: str) -> bool:
        """A worker wrote this job's outputs to the data dir (external scheduler)."""
        return result_path(self.data_dir, job_id).exists()

    def result(self, job_id: str) -> dict[str, Any]:
        """The outputs of a successful job."""
        rows = self._read("SELECT outputs FROM results WHERE id = ?", (job_id,))
        blob = rows[0][0] if rows else result_path(self.data_dir, job_id).read_bytes()
        outputs: dict[str, Any] = pickle.loads(blob)
        return outputs

