"""The spool: a request body written to disk as it arrives, sealed into an inputs file whose
arrays are the body's own bytes (no second copy), and read back bit-exact."""

from __future__ import annotations

import base64
import io
import json
import os
import pickle
import time
from pathlib import Path

import numpy as np
import pytest

from algorithms.core.mesh import Mesh
from service.binary import decode_arrays, lift_base64
from service.jobs.spool import MAGIC, SYNC_EVERY, Spool, load_inputs, remove_stale
from service.jobs.store import JobStore


def _npy(a: np.ndarray) -> bytes:
    buf = io.BytesIO()
    np.save(buf, a)
    return buf.getvalue()


def _body_with(arrays: list[np.ndarray], junk: int = 3) -> tuple[bytearray, list[np.ndarray]]:
    """A body of ``junk`` bytes, then each array's .npy file; and the arrays as views of the
    body (as an upload's .npy parts are), misaligned when ``junk`` is odd."""
    body = bytearray(b"x" * junk)
    offsets = []
    for a in arrays:
        f = _npy(a)
        offsets.append(len(body) + len(f) - a.nbytes)
        body += f
    views = [np.frombuffer(body, dtype=a.dtype, count=a.size, offset=o).reshape(a.shape)
             for a, o in zip(arrays, offsets, strict=True)]
    return body, views


def _spooled(tmp_path: Path, body: bytearray, chunk: int = 65536) -> Spool:
    spool = Spool(tmp_path, fsync=False)
    for i in range(0, len(body), chunk):
        spool.write(bytes(body[i:i + chunk]))
    return spool


def test_views_of_the_body_are_not_written_twice(tmp_path: Path) -> None:
    rng = np.random.default_rng(0)
    a, b = rng.normal(size=(20_000, 3)), rng.integers(0, 9, size=(5000, 3))
    body, (va, vb) = _body_with([a, b])
    assert not va.flags.aligned  # 3 bytes of junk first
    extra = rng.normal(size=(1000, 2))  # not in the body: appended
    inputs = {"source": va, "mesh": Mesh(vertices=extra, faces=vb), "scale": 2.5}
    target = tmp_path / "job.pkl"
    _spooled(tmp_path, body).seal(inputs, body, target)
    size = target.stat().st_size
    assert len(body) + extra.nbytes <= size < len(body) + extra.nbytes + 4096
    assert target.read_bytes()[-len(MAGIC):] == MAGIC
    back = load_inputs(target)
    assert back["scale"] == 2.5
    for got, want in ((back["source"], a), (back["mesh"].vertices, extra),
                      (back["mesh"].faces, b)):
        assert got.dtype == want.dtype and got.tobytes() == want.tobytes()
        assert got.flags.writeable and got.flags.aligned  # misaligned ones are copied
    assert list(tmp_path.glob(".spool-*")) == []


def test_a_plain_pickle_still_loads(tmp_path: Path) -> None:
    path = tmp_path / "old.pkl"
    a = np.arange(10.0)
    path.write_bytes(pickle.dumps({"a": a}, protocol=5))
    assert load_inputs(path)["a"].tobytes() == a.tobytes()


def test_discard_and_a_short_body_leave_nothing(tmp_path: Path) -> None:
    body, (va,) = _body_with([np.arange(3000.0)])
    spool = _spooled(tmp_path, body)
    spool.discard()
    spool.discard()  # twice is harmless
    assert list(tmp_path.iterdir()) == []
    short = _spooled(tmp_path, body[:-100])  # the file holds fewer bytes than the body
    with pytest.raises(RuntimeError, match="spooled"):
        short.seal({"a": va}, body, tmp_path / "job.pkl")
    assert list(tmp_path.iterdir()) == []


def test_large_bodies_are_pushed_to_disk_as_they_come(tmp_path: Path) -> None:
    a = np.random.default_rng(1).normal(size=(3 * SYNC_EVERY // 8 // 3, 3))
    body, (va,) = _body_with([a], junk=0)
    spool = Spool(tmp_path, fsync=True)
    for i in range(0, len(body), 1 << 20):
        spool.write(bytes(body[i:i + (1 << 20)]))
    spool.seal({"a": va}, body, tmp_path / "job.pkl")
    assert load_inputs(tmp_path / "job.pkl")["a"].tobytes() == a.tobytes()


def test_remove_stale_with_an_age_spares_bodies_still_arriving(tmp_path: Path) -> None:
    old, new = tmp_path / ".spool-old.tmp", tmp_path / ".spool-new.tmp"
    other = tmp_path / "job.pkl"
    for p in (old, new, other):
        p.write_bytes(b"x")
    hours_ago = time.time() - 7200
    os.utime(old, (hours_ago, hours_ago))
    os.utime(other, (hours_ago, hours_ago))
    assert remove_stale(tmp_path, older_than=3600) == 1
    assert sorted(p.name for p in tmp_path.iterdir()) == [".spool-new.tmp", "job.pkl"]


def test_start_up_removes_every_upload_a_crash_cut_off(tmp_path: Path) -> None:
    """A body spooled a moment before a crash (mtime: now) is gone once the store starts,
    and so is an inputs file cut off mid-write; inputs files of jobs stay, and so does a
    result a worker of an external scheduler may still be writing."""
    inputs, results = tmp_path / "inputs", tmp_path / "results"
    inputs.mkdir()
    results.mkdir()
    cut = Spool(inputs, fsync=False)  # a real spool file, as an upload leaves it
    cut.write(b"x" * 100_000)
    cut._stop()
    os.close(cut._fd)  # the process "dies": nothing discards it
    half = inputs / ".1234.pkl.0123abcd.tmp"  # write_atomic's temporary, cut off
    half.write_bytes(b"half")
    kept = inputs / "1234.pkl"
    kept.write_bytes(b"inputs")
    writing = results / ".5678.pkl.89abcdef.tmp"  # a live worker's, just begun
    writing.write_bytes(b"r")
    stale = results / ".9999.pkl.00000000.tmp"
    stale.write_bytes(b"r")
    hours_ago = time.time() - 7200
    os.utime(stale, (hours_ago, hours_ago))
    assert cut.path.exists() and cut.path.stat().st_size == 100_000

    store = JobStore(tmp_path, fsync=False)
    try:
        assert sorted(p.name for p in inputs.iterdir()) == ["1234.pkl"]
        assert sorted(p.name for p in results.iterdir()) == [writing.name]
    finally:
        store.close()


def test_one_service_per_data_dir(tmp_path: Path) -> None:
    """A second store on a data dir in use refuses to start (it would take the first one's
    uploads for leftovers); once the first is closed, it starts."""
    first = JobStore(tmp_path, fsync=False)
    live = first.spool()
    live.write(b"body still arriving")
    try:
        with pytest.raises(RuntimeError, match="Another morphserve service uses the data dir"):
            JobStore(tmp_path, fsync=False)
        assert live.path.exists()  # the refused store removed nothing
    finally:
        live.discard()
        first.close()
    JobStore(tmp_path, fsync=False).close()


def _json_body(arrays: dict[str, np.ndarray]) -> bytearray:
    return bytearray(json.dumps({"inputs": {name: {
        "dtype": a.dtype.str, "shape": list(a.shape),
        "data": base64.b64encode(a.tobytes()).decode()} for name, a in arrays.items()}},
        indent=1).encode())


def test_arrays_decoded_from_base64_in_the_body_keep_their_text(tmp_path: Path) -> None:
    """Arrays that came as typed binary arrays (base64 in a JSON body) are sealed as the
    place of their text in the file: the body is not followed by a second copy of them;
    a view of part of one is rebuilt from the same text."""
    rng = np.random.default_rng(4)
    a, b = rng.normal(size=(30_000, 3)), rng.integers(-5, 5, size=(7000, 3), dtype=np.int32)
    body = _json_body({"source": a, "faces": b})
    skeleton, lifted = lift_base64(body)
    assert lifted is not None and len(lifted.spans) == 2
    doc = json.loads(skeleton)["inputs"]
    va, vb = (decode_arrays(doc[k], k, lifted) for k in ("source", "faces"))
    extra = rng.normal(size=(100, 2))  # not in the body: appended
    inputs = {"source": va, "mesh": Mesh(vertices=extra, faces=vb), "tail": va[10_000:]}
    target = tmp_path / "job.pkl"
    _spooled(tmp_path, body).seal(inputs, body, target, lifted.decoded)
    assert len(body) + extra.nbytes <= target.stat().st_size < len(body) + extra.nbytes + 4096
    back = load_inputs(target)
    for got, want in ((back["source"], a), (back["mesh"].faces, b), (back["tail"], a[10_000:]),
                      (back["mesh"].vertices, extra)):
        assert got.dtype == want.dtype and got.shape == want.shape
        assert got.tobytes() == want.tobytes()
        assert got.flags.writeable and got.flags.aligned


def test_a_body_mostly_not_kept_is_not_kept(tmp_path: Path) -> None:
    """A body whose arrays were parsed from text (JSON lists here) would sit in the inputs
    file beside them as dead weight: the file is emptied first and holds the inputs only."""
    a = np.random.default_rng(5).normal(size=(20_000, 3))
    body = bytearray(json.dumps({"inputs": {"source": a.tolist()}}).encode())
    parsed = np.array(json.loads(body)["inputs"]["source"])
    target = tmp_path / "job.pkl"
    _spooled(tmp_path, body).seal({"source": parsed}, body, target)
    assert len(body) > 2 * a.nbytes
    assert a.nbytes <= target.stat().st_size < a.nbytes + 4096
    assert load_inputs(target)["source"].tobytes() == a.tobytes()


def test_chunks_are_written_whole_and_in_order_however_the_system_splits_them(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Chunks queued faster than they are written go out together by one writev, which may
    write less than it was given: what is left is written next, in order."""
    import service.jobs.spool as spool_module

    real = os.writev
    calls: list[int] = []

    def stingy(fd: int, buffers: list[memoryview]) -> int:  # at most 1000 bytes a call
        calls.append(len(buffers))
        budget, out = 1000, []
        for buf in buffers:
            out.append(buf[:budget])
            budget -= len(out[-1])
            if not budget:
                break
        return real(fd, out)

    monkeypatch.setattr(spool_module.os, "writev", stingy)
    rng = np.random.default_rng(6)
    a = rng.normal(size=(4000,))
    body, (va,) = _body_with([a])
    spool = Spool(tmp_path, fsync=False)
    for i in range(0, len(body), 333):
        spool.write(bytes(body[i:i + 333]))
    target = tmp_path / "job.pkl"
    spool.seal({"a": va}, body, target)
    assert max(calls) > 1  # several chunks in one call
    assert target.read_bytes()[:len(body)] == bytes(body)
    assert load_inputs(target)["a"].tobytes() == a.tobytes()
