"""What a job's method is given on a worker: the inputs as a local call would have them."""

from __future__ import annotations

import pickle
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from algorithms.core.errors import InvalidInputError
from algorithms.core.mesh import Mesh
from service.jobs import runner
from service.jobs.status import JobStatus, Outcome
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
    out = runner.run_job("job", "recorder", payload, data_dir=str(tmp_path), fsync=False,
                         reporter=runner.Reporter("job", None, None))
    assert out == Outcome.successful({"n": 50.0})
    for name, want in (("points", points), ("faces", faces)):
        got = recorder.given[name]
        assert got.flags.aligned and got.flags.writeable, name
        assert got.dtype == want.dtype and got.tobytes() == want.tobytes()


class _Failing:
    def __init__(self, error: Exception) -> None:
        self.error = error

    def run(self, kwargs: dict[str, Any], progress: Any = None) -> dict[str, Any]:
        raise self.error


@pytest.mark.parametrize(("error", "slug"), [
    (InvalidInputError("Expected `k` to be an integer >= 1, got -3.", field="k"),
     "invalid-input"),
    (ZeroDivisionError("division by zero"), "job-failed")])
def test_a_failing_method_is_a_failed_outcome(monkeypatch: pytest.MonkeyPatch,
                                              error: Exception, slug: str) -> None:
    monkeypatch.setattr(runner, "lookup", lambda process_id, test_processes=False:
                        _Failing(error))
    out = runner.run_job("job", "failing", {}, reporter=runner.Reporter("job", None, None))
    assert out.status is JobStatus.FAILED and out.outputs is None
    assert out.problem is not None and out.problem["type"] == f"/problems/{slug}"
    assert out.message == out.problem["detail"] and str(error) in out.message
    assert not out.timed_out


def test_run_job_takes_its_options_by_keyword() -> None:
    with pytest.raises(TypeError, match="positional"):
        runner.run_job("job", "p", {}, "/data")  # type: ignore[misc]


def test_an_outcome_crosses_dask_without_copying_its_arrays() -> None:
    """Pickled with its arrays out of band, as a task's result is: what arrives is a view
    of the frame, which here is the very array sent."""
    from distributed.protocol import deserialize, serialize

    big = np.random.default_rng(0).standard_normal((500, 3))
    outcome = Outcome.successful({"positions": big, "stress": 0.5})
    header, frames = serialize(outcome)
    back = deserialize(header, frames)
    assert type(back) is Outcome and back.status is JobStatus.SUCCESSFUL
    assert back.outputs is not None and back.outputs["stress"] == 0.5
    assert np.shares_memory(back.outputs["positions"], big)
    failed = Outcome.failed({"type": "/problems/job-failed", "detail": "boom"})
    assert pickle.loads(pickle.dumps(failed, protocol=5)) == failed


def test_outcomes_are_final_and_consistent() -> None:
    assert Outcome("failed", problem={"detail": "x"}).status is JobStatus.FAILED
    dismissed = Outcome.dismissed()
    assert dismissed.problem is not None and dismissed.problem["status"] == 410
    timed_out = Outcome.failed({"type": "/problems/time-limit-exceeded", "detail": "late"})
    assert timed_out.timed_out and timed_out.message == "late"
    assert Outcome.successful({}).message == "done"
    with pytest.raises(ValueError, match="final state"):
        Outcome(JobStatus.RUNNING)
    with pytest.raises(ValueError, match="outputs"):
        Outcome(JobStatus.SUCCESSFUL)
    with pytest.raises(ValueError, match="outputs"):
        Outcome(JobStatus.FAILED, outputs={}, problem={"detail": "x"})
    with pytest.raises(ValueError, match="problem"):
        Outcome(JobStatus.FAILED)
