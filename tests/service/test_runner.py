"""What a job's method is given on a worker: the inputs as a local call would have them."""

from __future__ import annotations

import pickle
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from algorithms.core.mesh import Mesh
from service.jobs import runner
from service.jobs.store import write_atomic


class _Recorder:
    """Stands for a process: records the arrays its method is given."""

    def __init__(self) -> None:
        self.given: dict[str, np.ndarray] = {}

    def run(self, kwargs: dict[str, Any], progress: Any = None) -> dict[str, Any]:
        self.given = {"points": kwargs["points"], "faces": kwargs["mesh"].faces}
        return {"n": float(len(kwargs["points"]))}


def _misaligned_readonly(a: np.ndarray, offset: int = 3) -> np.ndarray:
    raw = bytes(offset) + a.tobytes()  # bytes: read-only, the array 3 bytes in
    return np.frombuffer(raw, dtype=a.dtype, count=a.size, offset=offset).reshape(a.shape)


@pytest.mark.parametrize("via", ["inline", "file"])
def test_inputs_reach_the_method_aligned_and_writable(tmp_path: Path, via: str,
                                                      monkeypatch: pytest.MonkeyPatch) -> None:
    """Inline inputs come out of the task's frame as views at any byte offset, a plain
    pickle's arrays as read-only views of its bytes: BLAS takes other paths (other last
    bits) for misaligned operands, and a method may work in place on its input."""
    recorder = _Recorder()
    monkeypatch.setattr(runner, "lookup", lambda process_id, test_processes=False: recorder)
    rng = np.random.default_rng(0)
    points, faces = rng.normal(size=(50, 3)), np.array([[0, 1, 2], [1, 2, 3]])
    inputs = {"points": _misaligned_readonly(points),
              "mesh": Mesh(vertices=points, faces=_misaligned_readonly(faces))}
    assert not inputs["points"].flags.aligned and not inputs["points"].flags.writeable
    payload: Any = inputs
    if via == "file":
        path = tmp_path / "job.pkl"
        write_atomic(path, pickle.dumps(inputs, protocol=5), fsync=False)
        payload = str(path)
    out = runner.run_job("job", "recorder", payload, str(tmp_path), fsync=False,
                         reporter=runner.Reporter("job", None, None))
    assert out == {"status": "successful", "outputs": {"n": 50.0}}
    for name, want in (("points", points), ("faces", faces)):
        got = recorder.given[name]
        assert got.flags.aligned and got.flags.writeable, name
        assert got.dtype == want.dtype and got.tobytes() == want.tobytes()
