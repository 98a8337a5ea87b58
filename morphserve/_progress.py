"""Progress bars, for ``Job.wait(progress=True)`` and ``client.map(..., progress=True)``.

A bar shows how far it got, the time since it started, the time it still needs (from the
average rate so far) and that rate::

    [############------------------]  40% 00:02<00:03 20.0%/s iteration 12 of 30
    [######------------------------]  41/200 00:05<00:19 8.2 jobs/s 1 failed

Where it is drawn depends on where it goes:

- in a Jupyter notebook, and on a terminal, with ``tqdm`` installed (the ``progress`` extra:
  ``pip install morphserve[progress]``): a ``tqdm.auto`` bar, a widget in a notebook;
- on a terminal otherwise: one line redrawn in place (carriage return), at most ten times a
  second;
- elsewhere (a log file, CI): a full line now and then: the first, one each time another tenth
  is done, one at least every ``log_interval`` seconds when something changed, and the last.
"""

from __future__ import annotations

import importlib
import shutil
import sys
import time
from collections.abc import Callable
from types import TracebackType
from typing import Any, Protocol, TextIO, runtime_checkable

__all__ = ["ProgressBar", "ProgressDisplay", "TqdmBar", "make_progress"]


@runtime_checkable
class ProgressDisplay(Protocol):
    """What shows progress: a :class:`ProgressBar`, a :class:`TqdmBar`, or one's own."""

    def update(self, done: float | None, message: str | None = None) -> None:
        """Show that ``done`` (of the bar's total) is done, with ``message``."""

    def close(self) -> None:
        """End the display; safe to call twice."""


def clock_text(seconds: float) -> str:
    """``mm:ss``, or ``h:mm:ss`` from an hour on."""
    seconds = max(0, int(seconds))
    minutes, secs = divmod(seconds, 60)
    hours, minutes = divmod(minutes, 60)
    return f"{hours}:{minutes:02d}:{secs:02d}" if hours else f"{minutes:02d}:{secs:02d}"


class ProgressBar:
    """Draws ``[####------]  45% 00:09<00:11 5.0%/s message`` on ``stream``.

    Parameters
    ----------
    stream : text stream, optional
        Where to draw; ``sys.stderr`` when None (looked up when drawing, so pytest's capture
        and redirections apply).
    width : int
        Characters between the brackets.
    total : float
        What ``done`` counts up to: 100 for a percentage (the default), the number of jobs of
        a batch.
    unit : str
        ``"%"`` shows ``done`` as a percentage; another unit (``"jobs"``) as ``done/total``,
        and names the rate (``8.2 jobs/s``).
    clock : callable
        Seconds of a monotonic clock (``time.monotonic``); tests pass a fake one.
    min_interval : float
        On a terminal, the least seconds between two redraws (the last state is always drawn).
    log_interval : float
        Off a terminal, the most seconds between two lines while something changes.
    """

    def __init__(self, stream: TextIO | None = None, *, width: int = 30, total: float = 100,
                 unit: str = "%", clock: Callable[[], float] = time.monotonic,
                 min_interval: float = 0.1, log_interval: float = 30.0) -> None:
        if total <= 0:
            raise ValueError(f"Expected `total` above 0, got {total}.")
        self._stream = stream
        self.width = width
        self.total = float(total)
        self.unit = unit
        self._clock = clock
        self.min_interval = min_interval
        self.log_interval = log_interval
        self._start: float | None = None
        self._shown: str | None = None  # the last line drawn or written
        self._shown_at = 0.0
        self._shown_step = -1  # off a terminal: the tenth of the total last written
        self._pending: str | None = None  # a line not drawn yet (throttled)
        self._drawn = 0  # characters of the line now on a terminal, 0 when none

    @property
    def stream(self) -> TextIO:
        return self._stream if self._stream is not None else sys.stderr

    def _is_terminal(self) -> bool:
        try:
            return self.stream.isatty()
        except (AttributeError, ValueError):  # no isatty, or a closed stream
            return False

    def _now(self) -> float:
        """The clock's time; the bar starts at its first reading."""
        now = self._clock()
        if self._start is None:
            self._start = now
        return now

    def render(self, done: float | None, message: str | None = None,
               elapsed: float | None = None) -> str:
        """The bar as text, without line ending. ``elapsed`` defaults to the seconds since
        the first update (0 before it)."""
        done = min(self.total, max(0.0, float(done or 0)))
        if elapsed is None:
            elapsed = 0.0 if self._start is None else self._clock() - self._start
        filled = int(self.width * done / self.total)
        bar = "#" * filled + "-" * (self.width - filled)
        if self.unit == "%":
            count, per = f"{int(done * 100 / self.total):3d}%", "%/s"
        else:
            count, per = f"{done:g}/{self.total:g}", f" {self.unit}/s"
        rate = done / elapsed if elapsed > 0 else 0.0
        left = clock_text((self.total - done) / rate) if rate > 0 else "?"
        if done >= self.total:
            left = "00:00"
        rate_text = f"{rate:.1f}{per}" if rate > 0 else f"?{per}"
        line = f"[{bar}] {count} {clock_text(elapsed)}<{left} {rate_text}"
        return f"{line} {message}" if message else line

    def update(self, done: float | None, message: str | None = None) -> None:
        """Show ``done`` (0 to ``total``; None counts as 0) and ``message``; nothing is drawn
        when the text would not change, or sooner than the bar draws (see the class)."""
        now = self._now()
        start = now if self._start is None else self._start
        line = self.render(done, message, now - start)
        if line == self._shown:
            self._pending = None
            return
        final = float(done or 0) >= self.total
        if self._is_terminal():
            if self._shown is not None and not final and \
                    now - self._shown_at < self.min_interval:
                self._pending = line
                return
            self._draw(line, now)
            return
        step = int(10 * min(self.total, max(0.0, float(done or 0))) / self.total)
        if self._shown is None or final or step > self._shown_step or \
                now - self._shown_at >= self.log_interval:
            self._shown_step = max(step, self._shown_step)
            self._write(line, now)
        else:
            self._pending = line

    def _draw(self, line: str, now: float) -> None:
        columns = shutil.get_terminal_size().columns
        cut = line[: max(columns - 1, 10)]
        self.stream.write("\r" + cut.ljust(self._drawn))
        self.stream.flush()
        self._drawn = len(cut)
        self._shown, self._shown_at, self._pending = line, now, None

    def _write(self, line: str, now: float) -> None:
        self.stream.write(line + "\n")
        self.stream.flush()
        self._shown, self._shown_at, self._pending = line, now, None

    def close(self) -> None:
        """Draw what was held back, and end the line on a terminal; safe to call twice."""
        if self._pending is not None:
            if self._is_terminal():
                self._draw(self._pending, self._clock())
            else:
                self._write(self._pending, self._clock())
        if self._drawn:
            self.stream.write("\n")
            self.stream.flush()
            self._drawn = 0

    def __enter__(self) -> ProgressBar:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()


class TqdmBar:
    """A ``tqdm.auto`` bar behind the :class:`ProgressDisplay` interface: a widget in a
    notebook, tqdm's own line on a terminal. ``total`` and ``unit`` as for
    :class:`ProgressBar`; ``tqdm`` is the module (``tqdm.auto``) to draw with."""

    def __init__(self, tqdm: Any, *, total: float = 100, unit: str = "%",
                 desc: str | None = None) -> None:
        count = "{percentage:3.0f}%" if unit == "%" else "{n_fmt}/{total_fmt}"
        # tqdm puts ", " before a postfix, and takes the description as it is
        fmt = "{desc}" + count + "|{bar}| {elapsed}<{remaining} {rate_fmt}{postfix}"
        self._bar = tqdm.tqdm(total=total, unit=unit if unit == "%" else f" {unit}",
                              desc=f"{desc}: " if desc else None, bar_format=fmt, leave=True)
        self._done = 0.0
        self._closed = False

    def update(self, done: float | None, message: str | None = None) -> None:
        """Move the bar to ``done`` and show ``message`` after it."""
        done = float(done or 0)
        if message is not None:
            self._bar.set_postfix_str(message, refresh=False)
        if done > self._done:
            step = done - self._done
            self._bar.update(int(step) if step.is_integer() else step)  # "3/200", not "3.0"
            self._done = done
        else:
            self._bar.refresh()

    def close(self) -> None:
        """Close the tqdm bar; safe to call twice."""
        if not self._closed:
            self._closed = True
            self._bar.close()


def _tqdm() -> Any:
    """``tqdm.auto`` when tqdm is installed, else None."""
    try:
        return importlib.import_module("tqdm.auto")
    except ImportError:
        return None


def _interactive() -> bool:
    """Whether stderr is a terminal or a Jupyter kernel's output (where a widget shows)."""
    stream = sys.stderr
    if type(stream).__module__.split(".")[0] == "ipykernel":
        return True
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):
        return False


def make_progress(progress: bool | ProgressDisplay | None, *, total: float = 100,
                  unit: str = "%", desc: str | None = None) -> ProgressDisplay | None:
    """The display ``progress`` asks for: itself when it is one, None for False, and for True
    a ``tqdm.auto`` bar in a notebook or on a terminal when tqdm is installed, else a
    :class:`ProgressBar` on stderr."""
    if progress is None or progress is False:
        return None
    if progress is not True:
        if not isinstance(progress, ProgressDisplay):
            raise TypeError(f"Expected `progress` to be True, False or a progress bar, got "
                            f"{type(progress).__name__}.")
        return progress
    tqdm = _tqdm() if _interactive() else None
    if tqdm is not None:
        return TqdmBar(tqdm, total=total, unit=unit, desc=desc)
    return ProgressBar(total=total, unit=unit)
