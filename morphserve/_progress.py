"""A one-line terminal progress bar, for ``Job.wait(progress=True)``.

On a terminal the line is redrawn in place::

    [############------------------]  40% iteration 12 of 30

Elsewhere (a log file, CI) one such line is written per change instead, so the log shows the
steps without carriage returns. Either way the bar ends with a newline when closed.
"""

from __future__ import annotations

import shutil
import sys
from types import TracebackType
from typing import TextIO

__all__ = ["ProgressBar"]


class ProgressBar:
    """Draws ``[####------] 45% message`` on ``stream`` (default: ``sys.stderr``).

    Parameters
    ----------
    stream : text stream, optional
        Where to draw; ``sys.stderr`` when None (looked up when drawing, so pytest's capture
        and redirections apply).
    width : int
        Characters between the brackets.
    """

    def __init__(self, stream: TextIO | None = None, *, width: int = 30) -> None:
        self._stream = stream
        self.width = width
        self._last: tuple[int, str] | None = None
        self._drawn = 0  # characters of the line now on a terminal, 0 when none

    @property
    def stream(self) -> TextIO:
        return self._stream if self._stream is not None else sys.stderr

    def _is_terminal(self) -> bool:
        try:
            return self.stream.isatty()
        except (AttributeError, ValueError):  # no isatty, or a closed stream
            return False

    def render(self, percent: float | None, message: str | None = None) -> str:
        """The bar as text, without line ending."""
        percent = min(100.0, max(0.0, float(percent or 0)))
        filled = int(self.width * percent / 100)
        bar = "#" * filled + "-" * (self.width - filled)
        line = f"[{bar}] {int(percent):3d}%"
        return f"{line} {message}" if message else line

    def update(self, percent: float | None, message: str | None = None) -> None:
        """Show ``percent`` (0 to 100; None counts as 0) and ``message``; no-op if unchanged."""
        line = self.render(percent, message)
        key = (int(percent or 0), message or "")
        if key == self._last:
            return
        self._last = key
        stream = self.stream
        if self._is_terminal():
            columns = shutil.get_terminal_size().columns
            line = line[: max(columns - 1, 10)]
            stream.write("\r" + line.ljust(self._drawn))
            self._drawn = len(line)
        else:
            stream.write(line + "\n")
        stream.flush()

    def close(self) -> None:
        """End the line on a terminal; safe to call twice."""
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
