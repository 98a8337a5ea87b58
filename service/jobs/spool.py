"""Large request bodies written to the data dir while they arrive, and the inputs files that
refer to them.

Accepting a job means its inputs are on disk (fsynced) before the answer. For a 48 MB upload
the disk write alone takes about as long as receiving the body; done one after the other
they doubled the time to accept. A :class:`Spool` writes the chunks of a body to a temporary
file in ``inputs/`` as they arrive, on a thread of its own that takes every chunk waiting at
once and writes them with one ``writev`` (the GIL is taken once for them all, so the thread
keeps up with the event loop), and pushes the data to the device every :data:`SYNC_EVERY`
bytes, so that the final fsync waits only for the tail.

Once the body is parsed and validated, :meth:`Spool.seal` turns the file into the job's
inputs file: the inputs are pickled (protocol 5) with their array buffers out of band; a
buffer that is a view of the body (an ``.npy`` part) is recorded as its place in the file,
one decoded from base64 text in the body (a typed binary array) as the place of that text,
and any other is appended. The file then ends with the pickle stream, a table of the
buffers (``[offset, length]``, or ``[offset, length, start, size]`` for bytes
``[start, start + size)`` of the base64 text at ``offset``) and a fixed footer;
:func:`load_inputs` reads both this layout and a plain pickle. A body of which less than
half would be kept so is not kept at all. Nothing of a body that fails validation stays
behind (:meth:`Spool.discard`), and the store removes at start-up every spool file a crash
left (:func:`remove_stale`).
"""

from __future__ import annotations

import json
import os
import pickle
import queue
import struct
import threading
import time
import uuid
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
import pybase64

__all__ = ["Spool", "load_inputs", "remove_stale", "SYNC_EVERY"]

#: Bytes written between two pushes of the spool file to the device.
SYNC_EVERY = 8 * 2**20
#: The last bytes of an inputs file with out-of-band buffers.
MAGIC = b"MSINPUT1"
_FOOTER = struct.Struct("<QQ8s")  # pickle length, table length, MAGIC
#: Appended buffers start at multiples of this (aligned arrays when loaded).
_ALIGN = 64
_PREFIX = ".spool-"
#: Most chunks written by one writev (IOV_MAX on Linux and macOS).
_IOV_MAX = 1024


class Spool:
    """A request body on its way to disk (see the module's notes).

    :meth:`write` each chunk from the event loop (it only queues it); then either
    :meth:`seal` into an inputs file or :meth:`discard`."""

    def __init__(self, directory: Path, *, fsync: bool = True) -> None:
        self.path = Path(directory) / f"{_PREFIX}{uuid.uuid4().hex}.tmp"
        self.fsync = fsync
        self._fd = os.open(self.path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
        self._size = 0
        self._queue: queue.SimpleQueue[bytes | None] = queue.SimpleQueue()
        self._error: BaseException | None = None
        self._thread = threading.Thread(target=self._drain, name="morphserve-spool",
                                        daemon=True)
        self._thread.start()

    def write(self, chunk: bytes) -> None:
        """Queue ``chunk`` (the next bytes of the body) for the file; never blocks."""
        if chunk:
            self._queue.put(chunk)

    def _drain(self) -> None:
        unsynced = 0
        done = False
        while not done:
            # every chunk waiting is written by one writev: this thread takes the GIL once
            # for them all (one write call per chunk waited up to the interpreter's switch
            # interval each time, and fell tens of milliseconds behind the body)
            chunks: list[bytes] = []
            item = self._queue.get()
            while item is not None:  # None (from _stop) ends the body: no chunk follows it
                chunks.append(item)
                if len(chunks) == _IOV_MAX:
                    break
                try:
                    item = self._queue.get_nowait()
                except queue.Empty:
                    break
            else:
                done = True
            if self._error is not None or not chunks:
                continue
            try:
                size = sum(map(len, chunks))
                _writev_all(self._fd, chunks)
                self._size += size
                unsynced += size
                if self.fsync and unsynced >= SYNC_EVERY:
                    os.fdatasync(self._fd)  # on this thread: the loop keeps receiving
                    unsynced = 0
            except BaseException as exc:  # noqa: BLE001 - raised by seal()
                self._error = exc

    def _stop(self) -> None:
        if self._thread.is_alive():
            self._queue.put(None)
            self._thread.join()

    def discard(self) -> None:
        """Drop the file (a body that failed, or inputs stored another way)."""
        self._stop()
        if self._fd >= 0:
            os.close(self._fd)
            self._fd = -1
        self.path.unlink(missing_ok=True)

    def seal(self, inputs: dict[str, Any], body: Any, target: Path,
             encoded: Sequence[tuple[bytearray, int, int]] = ()) -> None:
        """Make the file ``target``, the inputs file of ``inputs``, whose arrays may be views
        of ``body`` (the bytes that were written) or of bytes decoded from base64 text in it
        (``encoded``: the decoded bytes, and the offset and length of their text); durable
        when this returns.

        When less than half of the body is kept that way (a body of JSON lists, or of a
        geometry file whose arrays were parsed from text), the file is emptied first and
        holds only the inputs: the rest of the body would be dead weight on disk."""
        try:
            self._stop()
            if self._error is not None:
                raise self._error
            base, size = _address(memoryview(body)), len(body)
            if size != self._size:
                raise RuntimeError(f"spooled {self._size} bytes of a {size}-byte body")
            texts = [(_address(memoryview(raw)), len(raw), at, n) for raw, at, n in encoded]
            buffers: list[pickle.PickleBuffer] = []
            stream = pickle.dumps(inputs, protocol=5, buffer_callback=buffers.append)
            table: list[list[int] | None] = []
            for buffer in buffers:
                raw = buffer.raw()
                at, n = _address(raw), raw.nbytes
                if n and base <= at and at + n <= base + size:
                    table.append([at - base, n])  # already in the file
                    continue
                table.append(next(([text, length, at - start, n]  # decoded from the file
                                   for start, count, text, length in texts
                                   if n and start <= at and at + n <= start + count), None))
            kept = {entry[0]: entry[1] for entry in table if entry is not None}
            if 2 * sum(kept.values()) < size:
                os.ftruncate(self._fd, 0)
                os.lseek(self._fd, 0, os.SEEK_SET)
                self._size = 0
                table = [None] * len(buffers)
            for i, buffer in enumerate(buffers):
                if table[i] is None:  # appended, aligned
                    raw = buffer.raw()
                    pad = -self._size % _ALIGN
                    table[i] = [self._size + pad, raw.nbytes]
                    _writev_all(self._fd, [bytes(pad), raw])
                    self._size += pad + raw.nbytes
            index = json.dumps(table).encode()
            _writev_all(self._fd, [stream, index,
                                   _FOOTER.pack(len(stream), len(index), MAGIC)])
            if self.fsync:
                os.fsync(self._fd)
            os.close(self._fd)
            self._fd = -1
            os.replace(self.path, target)
            if self.fsync:
                dir_fd = os.open(target.parent, os.O_RDONLY)
                try:
                    os.fsync(dir_fd)
                finally:
                    os.close(dir_fd)
        except BaseException:
            self.discard()
            raise


def _address(view: memoryview) -> int:
    return int(np.frombuffer(view.cast("B"), dtype=np.uint8).ctypes.data) if view.nbytes else 0


def _writev_all(fd: int, chunks: list[Any]) -> None:
    """Write all of ``chunks`` (buffers) to ``fd``, in order, however the system splits
    them."""
    views = [memoryview(c).cast("B") for c in chunks]
    while views:
        written = os.writev(fd, views)
        while views and written >= views[0].nbytes:
            written -= views.pop(0).nbytes
        if views:
            views[0] = views[0][written:]


def load_inputs(path: Path | str) -> Any:
    """The inputs stored in ``path``: an inputs file sealed from a :class:`Spool` (arrays
    are views of the file's bytes, copied where misaligned, or decoded from its base64
    text), or a plain pickle."""
    path = Path(path)
    data = bytearray(path.stat().st_size)
    with open(path, "rb", buffering=0) as f:
        view = memoryview(data)
        while view:
            got = f.readinto(view)
            if not got:
                raise EOFError(f"{path} ended early")
            view = view[got:]
    if len(data) < _FOOTER.size or data[-len(MAGIC):] != MAGIC:
        return pickle.loads(data)
    n_stream, n_index, _ = _FOOTER.unpack_from(data, len(data) - _FOOTER.size)
    end = len(data) - _FOOTER.size
    whole = memoryview(data)
    table = json.loads(bytes(whole[end - n_index:end]))
    stream = whole[end - n_index - n_stream:end - n_index]
    decoded: dict[tuple[int, int], memoryview] = {}
    buffers: list[Any] = []
    for entry in table:
        at, n = entry[:2]
        if len(entry) == 4:  # base64 text in the file: its bytes [start, start + n)
            if (at, n) not in decoded:
                decoded[at, n] = memoryview(
                    pybase64.b64decode_as_bytearray(whole[at:at + n], validate=True))
            source, (at, n) = decoded[entry[0], entry[1]], entry[2:]
        else:
            source = whole
        if (_address(source) + at) % 16 == 0:
            buffers.append(source[at:at + n])
        else:
            buffers.append(bytearray(source[at:at + n]))
    return pickle.loads(stream, buffers=buffers)


def remove_stale(directory: Path, older_than: float = 0.0) -> int:
    """Remove the temporary files a crash left in ``directory`` (spooled bodies, inputs or
    results files cut off while being written: ``.*.tmp``) untouched for at least
    ``older_than`` seconds; 0: all of them, as at start-up, when no request of the service
    can be writing one. Returns how many were removed."""
    removed = 0
    now = time.time()
    for path in Path(directory).glob(".*.tmp"):
        try:
            if older_than <= 0 or now - path.stat().st_mtime >= older_than:
                path.unlink()
                removed += 1
        except FileNotFoundError:
            pass
    return removed
