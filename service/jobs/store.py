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

A full disk (PostgreSQL's behaviour is the model: writes are refused, reads go on):

* a write that finds no room (``ENOSPC``, SQLite's ``SQLITE_FULL``) raises
  :class:`StorageFull`, answered ``507``; the transaction is rolled back and the inputs
  file it wrote removed;
* new jobs are refused while the data dir has less free space than
  :attr:`JobStore.reserve_bytes`, kept for the outcomes and deletions of the jobs already
  accepted;
* the outcome of a job that ends while its write finds no room is *held* in memory: the job
  reads as ended (its results too), and the writer thread writes the outcome as soon as
  there is room again (every :data:`HOLD_RETRY` seconds). A crash before that runs the job
  again at start-up, as for any job whose end was not recorded. Progress reports that find
  no room are dropped (the next report says it again).

The data dir belongs to one service at a time (an exclusive lock on ``jobs.lock``): at
start-up no request can be receiving a body, so every spool file left in ``inputs/`` is a
crash's leftover and is removed.
"""

from __future__ import annotations

import asyncio
import contextlib
import dataclasses
import errno
import fcntl
import functools
import inspect
import json
import logging
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
           "FINISHED", "write_atomic", "result_path", "StorageFull", "Space", "RESERVE_BYTES",
           "HOLD_RETRY"]

T = TypeVar("T")

log = logging.getLogger("morphserve.store")

#: Most writes group-committed in one transaction.
MAX_BATCH = 256
#: Free space kept in the data dir for the jobs already accepted: at most this, and at most
#: :data:`RESERVE_SHARE` of the filesystem (a small volume is not reserved whole).
RESERVE_BYTES = 64 * 2**20
RESERVE_SHARE = 0.05
#: Seconds between two attempts to write the outcomes held while the disk was full.
HOLD_RETRY = 1.0
#: What a write through :meth:`JobStore.write` does when it finds no room: ``hold`` (a job's
#: outcome, kept in memory until it can be written), ``drop`` (start and progress reports);
#: any other write raises :class:`StorageFull`.
_WHEN_FULL = {"finish": "hold", "mark_running": "drop", "set_progress": "drop"}

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


class StorageFull(OSError):
    """The data dir has no room for a write, or less free space than the store keeps for
    the jobs it has accepted (:attr:`JobStore.reserve_bytes`); an ``OSError`` with
    ``errno.ENOSPC``. Answered ``507 insufficient-storage``."""

    def __init__(self, free_bytes: int, reserve_bytes: int, needed: int = 0) -> None:
        more = f", and this request needs about {needed} more" if needed else ""
        super().__init__(errno.ENOSPC, (
            f"The data dir is full: {free_bytes} bytes free, {reserve_bytes} kept for the jobs "
            f"already accepted{more}. Nothing new is stored until space is freed; reading "
            "jobs and results still works."))
        self.free_bytes = free_bytes
        self.reserve_bytes = reserve_bytes


def _is_full(exc: BaseException) -> bool:
    """``exc`` says the filesystem had no room (or the user's quota was used up)."""
    if isinstance(exc, OSError):
        return exc.errno in (errno.ENOSPC, errno.EDQUOT)
    return (isinstance(exc, sqlite3.OperationalError)
            and getattr(exc, "sqlite_errorcode", None) == sqlite3.SQLITE_FULL)


@dataclass(frozen=True)
class Space:
    """The data dir's room, as the store sees it (:meth:`JobStore.space`)."""

    free_bytes: int
    """Bytes free on the data dir's filesystem (for an unprivileged user)."""
    reserve_bytes: int
    """Bytes kept for the jobs already accepted: below this, new jobs are refused."""
    held: int
    """Outcomes of ended jobs held in memory, not yet written."""

    @property
    def ok(self) -> bool:
        """New jobs are accepted, and every outcome is written."""
        return self.free_bytes >= self.reserve_bytes and not self.held


@dataclass(frozen=True)
class _Held:
    """The outcome of a job, as :meth:`JobStore.finish` takes it, kept in memory while the
    disk is full."""

    job_id: str
    status: JobStatus
    message: str
    problem: Mapping[str, Any] | None
    outputs: Mapping[str, Any] | None
    started: float | None
    now: float


@dataclass(frozen=True)
class _Write:
    """A write waiting for the writer thread, and what it does when the disk is full."""

    call: functools.partial[Any]
    loop: asyncio.AbstractEventLoop
    future: asyncio.Future[Any]
    when_full: str | None


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
    try:
        with open(tmp, "wb") as f:
            if isinstance(data, (bytes, bytearray, memoryview)):
                f.write(data)
            else:  # protocol 5 writes a large array's buffer straight to the file
                pickle.dump(data, f, protocol=5)
            if fsync:
                f.flush()
                os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:  # e.g. no room left: no half-written file stays behind
        tmp.unlink(missing_ok=True)
        raise
    if fsync:
        dir_fd = os.open(path.parent, os.O_RDONLY)
        try:
            os.fsync(dir_fd)
        finally:
            os.close(dir_fd)


def result_path(data_dir: Path, job_id: str) -> Path:
    """Where the worker writes the outputs of ``job_id``."""
    return Path(data_dir) / "results" / f"{job_id}.pkl"


def _lock(path: Path) -> Any:
    """``path`` opened and locked exclusively, for as long as it stays open: one service
    per data dir (a second one's start-up would take the first one's live uploads for a
    crash's leftovers, and both would run the unfinished jobs)."""
    f = open(path, "a+b")  # noqa: SIM115 - open for the store's lifetime
    try:
        fcntl.flock(f.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        f.close()
        raise RuntimeError(f"Another morphserve service uses the data dir {path.parent}; "
                           "give each service a data dir of its own.") from None
    return f


class JobStore:
    """Jobs, their inputs and their results under ``data_dir``.

    ``reserve_bytes``: the free space kept for the jobs already accepted (new ones are
    refused below it); default :data:`RESERVE_BYTES`, or :data:`RESERVE_SHARE` of the data
    dir's filesystem where that is less."""

    def __init__(self, data_dir: Path, *, fsync: bool = True, inline_input_bytes: int = 2**20,
                 reserve_bytes: int | None = None) -> None:
        self.data_dir = Path(data_dir)
        self.fsync = fsync
        self.inline_input_bytes = inline_input_bytes
        for sub in ("results", "inputs"):
            (self.data_dir / sub).mkdir(parents=True, exist_ok=True)
        self._lockfile = _lock(self.data_dir / "jobs.lock")
        # nothing can be arriving: every body spooled before is a crash's leftover; a worker
        # of an external scheduler may be writing a result even now, though
        remove_stale(self.data_dir / "inputs")
        remove_stale(self.data_dir / "results", older_than=3600.0)
        if reserve_bytes is None:
            st = os.statvfs(self.data_dir)
            reserve_bytes = min(RESERVE_BYTES, int(st.f_blocks * st.f_frsize * RESERVE_SHARE))
        self.reserve_bytes = reserve_bytes
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
        self._undo: list[Callable[[], None]] = []
        """What undoes the open transaction's effects outside SQLite (files written, held
        outcomes dropped), run if it is rolled back."""
        self._held: dict[str, _Held] = {}
        """Outcomes of ended jobs the disk had no room for (written by the writer thread)."""
        self._held_lock = threading.Lock()
        self._retry_at = 0.0
        self._queue: queue.SimpleQueue[_Write | None] = queue.SimpleQueue()
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
        if self._held:
            self._write_held()
        if self._held:
            log.warning("%d job outcomes were never written (the data dir is full): those "
                        "jobs run again at the next start", len(self._held))
        with self._lock:
            self._db.close()
        with self._rlock:
            self._rdb.close()
        self._lockfile.close()

    # -- room ------------------------------------------------------------------------------
    def free_bytes(self) -> int:
        """Bytes free on the data dir's filesystem (as an unprivileged user may use them)."""
        st = os.statvfs(self.data_dir)
        return int(st.f_bavail * st.f_frsize)

    def space(self) -> Space:
        """The data dir's free space, the reserve and the outcomes held in memory."""
        return Space(self.free_bytes(), self.reserve_bytes, len(self._held))

    def _check_room(self, needed: int = 0) -> None:
        """Raise :class:`StorageFull` unless ``needed`` bytes more leave the reserve free."""
        free = self.free_bytes()
        if free - needed < self.reserve_bytes:
            raise StorageFull(free, self.reserve_bytes, needed)

    # -- the writer thread -----------------------------------------------------------------
    def write(self, method: Callable[..., T], /, *args: Any, **kwargs: Any
              ) -> asyncio.Future[T]:
        """Run a writing ``method`` of this store on its writer thread; await the result,
        which arrives once the write is committed.

        Writes happen in submission order, off the event loop (a commit waits for its fsync
        without holding the GIL, so the loop serves other requests meanwhile), and those
        waiting together share one commit (see the module's notes). A write that finds the
        disk full raises :class:`StorageFull`, but for a job's outcome (:meth:`finish`),
        held in memory until there is room, and its start and progress, dropped."""
        loop = asyncio.get_running_loop()
        future: asyncio.Future[T] = loop.create_future()
        mine = getattr(method, "__self__", None) is self
        when_full = _WHEN_FULL.get(getattr(method, "__name__", "")) if mine else None
        if when_full == "hold":  # the end is now, not when the outcome can be written
            kwargs.setdefault("now", time.time())
        self._queue.put(_Write(functools.partial(method, *args, **kwargs), loop, future,
                               when_full))
        return future

    def _write_loop(self) -> None:
        while True:
            if self._held and time.monotonic() >= self._retry_at:
                self._write_held()
            try:
                first = self._queue.get(
                    timeout=max(0.0, self._retry_at - time.monotonic()) if self._held
                    else None)
            except queue.Empty:  # time to try the held outcomes again
                continue
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
            outcomes = self._run_batch([w.call for w in batch])
            for w, outcome in zip(batch, outcomes, strict=True):
                if not outcome[0] and _is_full(outcome[1]):
                    outcome = self._when_full(w, outcome[1])
                try:
                    w.loop.call_soon_threadsafe(_settle, w.future, outcome)
                except RuntimeError:  # the loop is closed: nobody is waiting any more
                    pass
            if stop:
                return

    def _when_full(self, w: _Write, exc: BaseException) -> tuple[bool, Any]:
        """The answer to a write that found the disk full (see :meth:`write`)."""
        if w.when_full == "hold":
            self._hold(w.call)
            return True, True
        if w.when_full == "drop":
            return True, False
        if isinstance(exc, StorageFull):
            return False, exc
        full = StorageFull(self.free_bytes(), self.reserve_bytes)
        full.__cause__ = exc
        return False, full

    def _hold(self, call: functools.partial[Any]) -> None:
        """Keep the outcome of :meth:`finish` ``call`` in memory until it can be written."""
        a = inspect.signature(self.finish).bind(*call.args, **call.keywords).arguments
        held = _Held(a["job_id"], JobStatus(a["status"]), a["message"], a.get("problem"),
                     a.get("outputs"), a.get("started"), a["now"])
        with self._held_lock:
            self._held[held.job_id] = held
        self._retry_at = time.monotonic() + HOLD_RETRY
        log.warning("job %s ended %s but the data dir is full (%d bytes free): its outcome "
                    "is held in memory and written when there is room", held.job_id,
                    held.status, self.free_bytes())

    def _write_held(self) -> None:
        """Write the held outcomes, oldest first (those that find no room stay held)."""
        self._retry_at = time.monotonic() + HOLD_RETRY
        with self._held_lock:
            pending = list(self._held.values())
        for held in pending:
            try:
                self.finish(held.job_id, held.status, held.message, held.problem,
                            held.outputs, started=held.started, now=held.now)
            except Exception as exc:
                if _is_full(exc):
                    continue  # still no room: the next attempt is HOLD_RETRY seconds away
                log.error("job %s: its held outcome could not be written (%s: %s); the job "
                          "runs again at the next start", held.job_id, type(exc).__name__,
                          exc)
            else:
                log.info("job %s: held outcome written", held.job_id)
            with self._held_lock:
                self._held.pop(held.job_id, None)

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
                self._rollback(0)
                return [(False, exc)] * len(calls)
            finally:
                self._undo.clear()
        return outcomes

    def _rollback(self, mark: int) -> None:
        """Roll the open transaction back (SQLite may have done so already, as after a
        failed commit) and undo what it did since ``mark`` outside SQLite."""
        if self._db.in_transaction:
            with contextlib.suppress(sqlite3.Error):
                self._db.execute("ROLLBACK")
        self._undo_since(mark)

    def _undo_since(self, mark: int) -> None:
        for undo in reversed(self._undo[mark:]):
            undo()
        del self._undo[mark:]

    def _on_rollback(self, undo: Callable[[], None]) -> None:
        """Run ``undo`` if the open transaction is rolled back; outside a transaction the
        write is committed already and there is nothing to undo."""
        if self._db.in_transaction:
            self._undo.append(undo)

    @contextlib.contextmanager
    def _atomic(self) -> Iterator[None]:
        """All or nothing: a transaction of its own, or a savepoint inside the current one.
        What :meth:`_on_rollback` registered meanwhile is undone if it is rolled back."""
        with self._lock:
            mark = len(self._undo)
            if self._db.in_transaction:
                self._db.execute("SAVEPOINT atomic")
                try:
                    yield
                except BaseException:
                    self._db.execute("ROLLBACK TO atomic")
                    self._db.execute("RELEASE atomic")
                    self._undo_since(mark)
                    raise
                self._db.execute("RELEASE atomic")
            else:
                self._db.execute("BEGIN IMMEDIATE")
                try:
                    yield
                    self._db.execute("COMMIT")  # a full disk fails here
                except BaseException:
                    self._rollback(mark)
                    raise
                finally:
                    del self._undo[mark:]

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
        size = _array_bytes(inputs)
        large = size > self.inline_input_bytes
        try:
            self._check_room(size)
        except StorageFull:
            if spool is not None:
                spool.discard()
            raise
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
                if inputs_file:
                    self._on_rollback(functools.partial(
                        (self.data_dir / inputs_file).unlink, missing_ok=True))
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
            with self._held_lock:  # a held outcome goes with its row (back if it stays)
                held = self._held.pop(job_id, None)
            if held is not None:
                self._on_rollback(functools.partial(self._held.__setitem__, job_id, held))
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
        jobs = [_record(r) for r in self._read(f"SELECT {_SELECT} FROM jobs {where}", args)]
        return [self._with_held(j) for j in jobs] if self._held else jobs

    def _with_held(self, job: JobRecord) -> JobRecord:
        """``job`` as it reads with its held outcome (see the module's notes), as
        :meth:`finish` would write it; an ended job (dismissed meanwhile) stays as it is."""
        with self._held_lock:
            held = self._held.get(job.id)
        if held is None or not job.active:
            return job
        done = held.status is JobStatus.SUCCESSFUL
        return dataclasses.replace(
            job, status=held.status, message=held.message,
            problem=dict(held.problem) if held.problem else None,
            progress=100 if done else job.progress, started=job.started or held.started,
            finished=held.now, updated=held.now)

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
        """A new :class:`Spool` for a request body, in the inputs directory; raises
        :class:`StorageFull` first when the data dir is at its reserve."""
        self._check_room()
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
        with self._held_lock:
            held = self._held.get(job_id)
        if held is not None and held.outputs is not None:
            return dict(held.outputs)
        rows = self._read("SELECT outputs FROM results WHERE id = ?", (job_id,))
        blob = rows[0][0] if rows else result_path(self.data_dir, job_id).read_bytes()
        outputs: dict[str, Any] = pickle.loads(blob)
        return outputs

