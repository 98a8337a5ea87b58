"""A job's states, and how one run of a job ends.

:class:`JobStatus` is the one list of the states of OGC API – Processes (``statusInfo``'s
``status``); as a :class:`~enum.StrEnum` its members *are* those strings, in the store's rows,
in JSON and in f-strings alike. :class:`Outcome` is what :func:`~service.jobs.runner.run_job`
returns (on a Dask worker, or on the service's fast path) and what the engine records in the
store and hands to the routes and the callbacks.

Workers import this module: it needs no web stack.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum
from typing import Any

from service.problems import dismissed_problem, problem_body

__all__ = ["JobStatus", "ACTIVE", "FINISHED", "Outcome"]


class JobStatus(StrEnum):
    """Where a job stands. ``accepted`` -> ``running`` -> ``successful`` or ``failed``;
    ``dismissed`` from either of the first two. The finished states are final."""

    ACCEPTED = "accepted"
    RUNNING = "running"
    SUCCESSFUL = "successful"
    FAILED = "failed"
    DISMISSED = "dismissed"

    @property
    def active(self) -> bool:
        """Accepted or running: the job may still change."""
        return self in ACTIVE


#: The states a job may leave (what a restart must finish).
ACTIVE: tuple[JobStatus, ...] = (JobStatus.ACCEPTED, JobStatus.RUNNING)
#: The final states.
FINISHED: tuple[JobStatus, ...] = (JobStatus.SUCCESSFUL, JobStatus.FAILED, JobStatus.DISMISSED)


@dataclass(frozen=True)
class Outcome:
    """How one run of a job ended.

    It crosses Dask as the task's result: pickled (protocol 5), the arrays among its outputs
    travel out of band, not copied. Build it with :meth:`successful`, :meth:`failed` or
    :meth:`dismissed`.
    """

    status: JobStatus
    """``successful``, ``failed`` or ``dismissed`` (never an active state)."""
    outputs: dict[str, Any] | None = None
    """The method's outputs by name, as it returned them; only when successful."""
    problem: dict[str, Any] | None = None
    """The problem+json body (without ``instance``) of a failed or dismissed run."""

    def __post_init__(self) -> None:
        object.__setattr__(self, "status", JobStatus(self.status))  # "failed" is FAILED
        if self.status.active:
            raise ValueError(f"an outcome is a final state, not {self.status!r}")
        if (self.status is JobStatus.SUCCESSFUL) != (self.outputs is not None):
            raise ValueError("a successful outcome, and only that, has outputs")
        if (self.status is JobStatus.SUCCESSFUL) != (self.problem is None):
            raise ValueError("a failed or dismissed outcome, and only that, has a problem")

    @classmethod
    def successful(cls, outputs: dict[str, Any]) -> Outcome:
        return cls(JobStatus.SUCCESSFUL, outputs=outputs)

    @classmethod
    def failed(cls, problem: dict[str, Any]) -> Outcome:
        return cls(JobStatus.FAILED, problem=problem)

    @classmethod
    def dismissed(cls) -> Outcome:
        return cls(JobStatus.DISMISSED, problem=dismissed_problem())

    @classmethod
    def time_limit_exceeded(cls, limit: float) -> Outcome:
        """The outcome of a job stopped for running longer than ``limit`` seconds."""
        return cls.failed(problem_body(
            "time-limit-exceeded", f"The job was stopped: time limit of {limit:g} s exceeded."))

    @property
    def message(self) -> str:
        """The job's message once it ended so: ``done``, or the problem's detail."""
        if self.problem is None:
            return "done"
        return str(self.problem["detail"])

    @property
    def timed_out(self) -> bool:
        """Stopped for running past its time limit."""
        return self.problem is not None and str(self.problem.get("type", "")).endswith(
            "time-limit-exceeded")
