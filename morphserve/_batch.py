"""Many jobs at once: ``client.map(process, [inputs, ...])`` and ``as_completed(jobs)``.

A batch keeps up to ``max_in_flight`` jobs on the service at a time, so its workers never wait
for the client, and draws one progress bar for the lot. Each input gives one
:class:`BatchItem`, in the order of the inputs, holding the job's results or the error it met:
one bad input does not stop the others.

Every job of a batch is sent with an ``Idempotency-Key`` (the user's, or ``batch_id`` with the
process and the position in the batch), so sending a request again, after a lost connection,
a full queue, or in a batch run again with the same ``batch_id``, gives back the job already
made instead of starting another.

The work of one item is a flow (see :mod:`morphserve._client`): the synchronous client runs
the flows of a batch on threads, the asynchronous one as tasks.
"""

from __future__ import annotations

import uuid
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Generic, TypeVar

from ._exceptions import QueueFull, ServiceUnavailable, TransportError
from ._models import Results

if TYPE_CHECKING:
    from ._client import _Flow, _Protocol, _Submitted

__all__ = ["BatchItem", "batch_inputs", "batch_keys", "item_flow", "MAX_ATTEMPTS"]

J = TypeVar("J")

#: Attempts at sending one request of a batch when the queue is full, the service is
#: starting, or the connection broke (the same Idempotency-Key each time).
MAX_ATTEMPTS = 5
_MAX_BACKOFF = 5.0
#: Seconds each request of a batch asks the service to wait for its job (``Prefer:
#: wait=N``), so that most jobs answer with their results in one request; a job that runs
#: longer is then polled.
BATCH_WAIT = 30.0


@dataclass(frozen=True)
class BatchItem(Generic[J]):
    """One input of a batch and what became of it: its results, or the error it met.

    ``job`` is the :class:`Job` (or :class:`AsyncJob`) started, None when none could be
    (the input was refused, or the service could not be reached); ``key`` is the
    Idempotency-Key it was sent with.
    """

    index: int
    """Its position in the batch."""
    key: str
    job: J | None
    results: Results | None = None
    error: Exception | None = field(default=None)

    @property
    def ok(self) -> bool:
        """True when the job succeeded."""
        return self.error is None

    def result(self) -> Results:
        """The results; raises the error when the job did not succeed."""
        if self.error is not None:
            raise self.error
        assert self.results is not None
        return self.results

    def exception(self) -> Exception | None:
        """The error the item met (``InvalidInput``, ``JobFailed`` ...), None on success."""
        return self.error

    def __repr__(self) -> str:
        what = "ok" if self.error is None else f"{type(self.error).__name__}: {self.error}"
        job = getattr(self.job, "id", None)
        return f"<BatchItem {self.index} job={job} {what:.80}>"


def batch_keys(process_id: str, count: int, batch_id: str | None,
               keys: Sequence[str] | None) -> tuple[str, list[str]]:
    """The batch id and the Idempotency-Key of each of ``count`` items: ``keys`` when given,
    else ``{batch_id}:{process_id}:{index}`` (a fresh random batch id when None)."""
    if keys is not None:
        if batch_id is not None:
            raise TypeError("Give `batch_id` or `keys`, not both.")
        keys = list(keys)
        if len(keys) != count:
            raise ValueError(f"Expected one key per input ({count}), got {len(keys)}.")
        if len(set(keys)) != count:
            raise ValueError("Expected distinct keys, got repeated ones.")
        return "", keys
    if batch_id is None:
        batch_id = uuid.uuid4().hex
    return batch_id, [f"{batch_id}:{process_id}:{index}" for index in range(count)]


def batch_inputs(process_id: str, inputs: Iterable[Mapping[str, Any]],
                 common: Mapping[str, Any], batch_id: str | None, keys: Sequence[str] | None,
                 max_in_flight: int) -> tuple[list[dict[str, Any]], list[str]]:
    """Each item's inputs over the inputs common to all, and each item's Idempotency-Key
    (see :func:`batch_keys`). Raises TypeError for an item that is not a mapping of input
    names, ValueError for ``max_in_flight`` below 1."""
    if isinstance(max_in_flight, bool) or not isinstance(max_in_flight, int) or \
            max_in_flight < 1:
        raise ValueError(f"Expected `max_in_flight` to be an integer >= 1, got "
                         f"{max_in_flight!r}.")
    merged = []
    for index, item in enumerate(inputs):
        if not isinstance(item, Mapping):
            raise TypeError(f"Expected each item of `inputs` to be a dict of named inputs, "
                            f"got {type(item).__name__} at index {index}.")
        merged.append({**common, **item})
    return merged, batch_keys(process_id, len(merged), batch_id, keys)[1]


def _backoff(attempt: int, error: Exception) -> float:
    if isinstance(error, QueueFull) and error.retry_after is not None:
        return min(error.retry_after, _MAX_BACKOFF * 2)
    return min(0.25 * 2.0 ** attempt, _MAX_BACKOFF)


def item_flow(protocol: _Protocol, process_id: str, inputs: Mapping[str, Any], key: str, *,
              outputs: Iterable[str] | Mapping[str, Any] | None, time_limit: float | None,
              timeout: float | None, poll_interval: float
              ) -> _Flow[tuple[_Submitted | None, Exception | None]]:
    """Start one job of a batch and see it to its end: the job as submitted (its results
    filled in when it succeeded) and the error it met, if any. Errors are returned, not
    raised; a full queue or a lost connection is retried with the same key."""
    from ._client import _Sleep, _Submitted

    wait = BATCH_WAIT if timeout is None else min(BATCH_WAIT, timeout)
    submitted: _Submitted | None = None
    for attempt in range(MAX_ATTEMPTS):
        try:
            submitted = yield from protocol.execute(
                process_id, inputs, wait=wait, outputs=outputs, idempotency_key=key,
                time_limit=time_limit)
            break
        except (QueueFull, ServiceUnavailable, TransportError) as error:
            if attempt == MAX_ATTEMPTS - 1:
                return None, error
            yield _Sleep(_backoff(attempt, error))
        except Exception as error:  # refused (InvalidInput, NoSuchFile ...): this item only
            return None, error
    assert submitted is not None
    if submitted.results is not None:
        return submitted, None
    try:
        remaining = None if timeout is None else max(0.0, timeout - wait)
        status = yield from protocol.wait(submitted.job_id, timeout=remaining,
                                          progress=False, poll_interval=poll_interval)
        results = yield from protocol.fetch_results(submitted.job_id)
    except Exception as error:  # JobFailed, JobDismissed, WaitTimeout, TransportError
        return submitted, error
    return _Submitted(submitted.job_id, submitted.process_id, status, results), None
