"""How long the service takes to accept a job with two 1,000,000-point inputs, by transport.

    python bench/transport.py [--repeats 5] [--points 1000000]

One live service (embedded cluster); each request is ``POST
/processes/alignment.rigid/execution`` with ``Prefer: respond-async``, timed from the first
byte sent to the ``201 Created`` (the job's row and inputs committed), for three encodings of
the same two (n, 3) float64 arrays:

- JSON lists (what a plain client sends);
- typed binary arrays inside JSON (``{"dtype", "shape", "data": base64}``);
- ``multipart/form-data`` with two ``.npy`` parts;
- and, for comparison, the SDK's ``Client.execute`` given the arrays (it sends them as
  ``.npy`` parts), its own encoding included.

The body is encoded once before timing (a client's own cost is not the service's), and the
client is httpx on a kept-alive connection, handed the body in 1 MiB pieces (with its
Content-Length), as the SDK does. The last column hands httpx the body as one bytes object
instead: httpcore then writes it by ``send()`` after ``send()``, copying all that is left
each time, which costs the client more than the service takes (a 61 MB body: ~150 ms of
the client's CPU). Every accepted job is then awaited and its rotation compared with the
truth, so that speed never hides a wrong answer. Goal (#8): multipart and base64 accepted in
≤ 200 ms on this machine. Prints medians of ``--repeats``; a benchmark never asserts.
"""

from __future__ import annotations

import argparse
import base64
import io
import json
import statistics
import sys
import tempfile
import time
from collections.abc import Iterator
from pathlib import Path

import httpx
import numpy as np
from scipy.spatial.transform import Rotation

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "bench")]
sys.path.append(str(ROOT / "tests"))
from _common import print_table  # noqa: E402
from live import LiveServer, wait_for_status  # noqa: E402

PATH = "/processes/alignment.rigid/execution"
BOUNDARY = "morphserve-bench-boundary"
PIECE = 1 << 20


def pieces(body: bytes) -> Iterator[memoryview]:
    view = memoryview(body)
    for start in range(0, len(view), PIECE):
        yield view[start:start + PIECE]


def _binary(a: np.ndarray) -> dict:
    return {"dtype": a.dtype.str, "shape": list(a.shape),
            "data": base64.b64encode(a.tobytes()).decode("ascii")}


def _npy(a: np.ndarray) -> bytes:
    buf = io.BytesIO()
    np.save(buf, a)
    return buf.getvalue()


def bodies(source: np.ndarray, target: np.ndarray) -> dict[str, tuple[bytes, str]]:
    """Each encoding: (body, Content-Type)."""
    lists = json.dumps({"inputs": {"source": source.tolist(), "target": target.tolist()}})
    b64 = json.dumps({"inputs": {"source": _binary(source), "target": _binary(target)}})
    parts = b""
    for name, arr in (("source", source), ("target", target)):
        parts += (f"--{BOUNDARY}\r\nContent-Disposition: form-data; name=\"{name}\"; "
                  f"filename=\"{name}.npy\"\r\nContent-Type: application/x-npy\r\n\r\n"
                  ).encode() + _npy(arr) + b"\r\n"
    parts += f"--{BOUNDARY}--\r\n".encode()
    return {
        "JSON lists": (lists.encode(), "application/json"),
        "typed binary (base64)": (b64.encode(), "application/json"),
        "multipart .npy": (parts, f"multipart/form-data; boundary={BOUNDARY}"),
    }


def _sdk_row(url: str, source: np.ndarray, target: np.ndarray, rotation: np.ndarray,
             repeats: int) -> tuple[str, ...]:
    """The SDK's ``Client.execute`` with the arrays themselves (it sends arrays of 1 MiB
    and more as .npy parts): its own encoding counts here, unlike in the other rows."""
    from morphserve import Client

    times, errors = [], []
    with Client(url) as client:
        for _ in range(repeats):
            t0 = time.perf_counter()
            job = client.execute("alignment.rigid", source=source, target=target)
            times.append(time.perf_counter() - t0)
            job.wait(timeout=600)
            got = job.results()["rotation"]
            errors.append(float(np.abs(np.asarray(got) - rotation).max()))
    return ("SDK Client.execute (encoding included)", "",
            f"{statistics.median(times) * 1000:.0f}",
            f"{min(times) * 1000:.0f}–{max(times) * 1000:.0f}", "", f"{max(errors):.1e}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--points", type=int, default=1_000_000)
    args = ap.parse_args()

    rng = np.random.default_rng(0)
    source = rng.normal(size=(args.points, 3))
    rotation = Rotation.from_euler("xyz", [10, 20, 30], degrees=True).as_matrix()
    target = source @ rotation.T + [1.0, 2.0, 3.0]
    encoded = bodies(source, target)

    with tempfile.TemporaryDirectory() as tmp:
        srv = LiveServer(Path(tmp) / "data", {  # JSON lists of 2M points: 125 MB
            "MORPHSERVE_MAX_REQUEST_BYTES": str(512 * 2**20)}).start()
        try:
            rows = []
            with httpx.Client(base_url=srv.url, timeout=600) as http:
                for label, (body, ctype) in encoded.items():
                    times: dict[bool, list[float]] = {True: [], False: []}
                    errors = []
                    for _ in range(args.repeats):
                        for piecewise in (True, False):
                            t0 = time.perf_counter()
                            r = http.post(PATH, content=pieces(body) if piecewise else body,
                                          headers={"Content-Type": ctype,
                                                   "Content-Length": str(len(body)),
                                                   "Prefer": "respond-async"})
                            times[piecewise].append(time.perf_counter() - t0)
                            if r.status_code != 201:
                                raise SystemExit(f"{label}: {r.status_code} {r.text[:500]}")
                            info = wait_for_status(http, r.json()["jobID"], timeout=600)
                            res = http.get(f"/jobs/{info['jobID']}/results/rotation").json()
                            errors.append(float(np.abs(np.asarray(res) - rotation).max()))
                    ms = {k: [t * 1000 for t in v] for k, v in times.items()}
                    rows.append((label, f"{len(body) / 2**20:.1f}",
                                 f"{statistics.median(ms[True]):.0f}",
                                 f"{min(ms[True]):.0f}–{max(ms[True]):.0f}",
                                 f"{statistics.median(ms[False]):.0f}", f"{max(errors):.1e}"))
            rows.append(_sdk_row(srv.url, source, target, rotation, args.repeats))
        finally:
            srv.stop()
    print_table(f"accepting a job of two {args.points:,}-point inputs (alignment.rigid, "
                f"Prefer: respond-async), median of {args.repeats}",
                ("transport", "body MiB", "accept ms", "range ms", "one piece ms",
                 "max |R - R_true|"), rows)


if __name__ == "__main__":
    main()
