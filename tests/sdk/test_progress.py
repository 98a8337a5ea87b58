"""The progress display (morphserve._progress): elapsed time, rate and time left, drawn in
place on a terminal, as sparse lines elsewhere, with tqdm when it is installed.

Every test runs on a fake clock and a fake stream: what is drawn depends on nothing else.
"""

from __future__ import annotations

import io
import sys
import types
from typing import Any

import pytest

from morphserve import ProgressBar, ProgressDisplay
from morphserve._progress import TqdmBar, clock_text, make_progress
from tests.sdk.test_client import FakeClock, FakeTerminal


def test_clock_text() -> None:
    assert clock_text(0) == "00:00"
    assert clock_text(59.9) == "00:59"
    assert clock_text(61) == "01:01"
    assert clock_text(3600 + 61) == "1:01:01"
    assert clock_text(-3) == "00:00"


def test_render_of_a_count_names_the_rate_and_time_left() -> None:
    bar = ProgressBar(io.StringIO(), total=200, unit="jobs")
    # 50 of 200 jobs in 20 s: 2.5 jobs/s, so the other 150 take 60 s
    assert bar.render(50, "2 failed", elapsed=20) == \
        "[#######-----------------------] 50/200 00:20<01:00 2.5 jobs/s 2 failed"
    assert bar.render(0, elapsed=5) == "[------------------------------] 0/200 00:05<? ? jobs/s"
    assert bar.render(200, elapsed=3725) == \
        "[##############################] 200/200 1:02:05<00:00 0.1 jobs/s"


def test_off_a_terminal_a_line_per_tenth() -> None:
    stream = io.StringIO()
    bar = ProgressBar(stream, total=200, unit="jobs", clock=FakeClock(1.0))
    for done in range(0, 201):  # job n done at n s
        bar.update(done)
    bar.close()
    lines = stream.getvalue().splitlines()
    # the first line, then one each time another tenth (20 jobs) is done
    assert [line.split()[1] for line in lines] == [f"{n}/200" for n in range(0, 201, 20)]
    # 100 jobs in 100 s: 1 job/s, and the 100 left take 100 s more
    assert lines[5] == "[###############---------------] 100/200 01:40<01:40 1.0 jobs/s"
    assert lines[-1] == "[" + "#" * 30 + "] 200/200 03:20<00:00 1.0 jobs/s"


def test_off_a_terminal_slow_progress_writes_every_log_interval() -> None:
    stream = io.StringIO()
    bar = ProgressBar(stream, clock=FakeClock(10.0), log_interval=30)
    for percent in (1, 2, 3, 4, 5):  # at 0, 10, 20, 30, 40 s: all in the first tenth
        bar.update(percent)
    assert [line.split()[1] for line in stream.getvalue().splitlines()] == ["1%", "4%"]
    bar.close()  # what was held back is written at the end
    assert [line.split()[1] for line in stream.getvalue().splitlines()] == ["1%", "4%", "5%"]
    bar.close()
    assert len(stream.getvalue().splitlines()) == 3


def test_off_a_terminal_the_last_state_is_written_when_closing() -> None:
    stream = io.StringIO()
    with ProgressBar(stream, clock=FakeClock(1.0)) as bar:
        bar.update(50, "running")
        bar.update(52, "failed: out of memory")  # same tenth: held back
        assert stream.getvalue().count("\n") == 1
    assert stream.getvalue().splitlines()[-1].endswith("failed: out of memory")


def test_on_a_terminal_redraws_at_most_every_min_interval() -> None:
    stream = FakeTerminal()
    bar = ProgressBar(stream, width=10, clock=FakeClock(0.04), min_interval=0.1)
    for percent in (10, 20, 30, 40, 50):  # at 0, 0.04, 0.08, 0.12, 0.16 s
        bar.update(percent)
    drawn = stream.getvalue()
    assert drawn.count("\r") == 2  # 10 % at 0 s and 40 % at 0.12 s
    assert "\r[####------]  40% 00:00<00:00 333.3%/s" in drawn
    bar.close()  # 50 % as it was at 0.16 s, held back until now; then the line ends
    drawn = stream.getvalue()
    assert drawn.count("\r") == 3
    assert drawn.endswith("\r[#####-----]  50% 00:00<00:00 312.5%/s\n")


def test_on_a_terminal_the_end_is_always_drawn() -> None:
    stream = FakeTerminal()
    bar = ProgressBar(stream, width=10, clock=FakeClock(0.01), min_interval=0.1)
    bar.update(10)
    bar.update(100, "done")  # 0.01 s later, yet drawn: it is the end
    assert stream.getvalue().endswith("100% 00:00<00:00 10000.0%/s done")


def test_a_total_must_be_positive() -> None:
    with pytest.raises(ValueError, match="Expected `total` above 0, got 0"):
        ProgressBar(total=0)


class FakeTqdm:
    """What morphserve calls of ``tqdm.auto.tqdm``, recorded."""

    made: list[FakeTqdm] = []

    def __init__(self, **options: Any) -> None:
        self.options = options
        self.n = 0.0
        self.postfix: list[str] = []
        self.refreshes = 0
        self.closed = 0
        FakeTqdm.made.append(self)

    def update(self, n: float) -> None:
        self.n += n

    def set_postfix_str(self, text: str, refresh: bool = True) -> None:
        self.postfix.append(text)

    def refresh(self) -> None:
        self.refreshes += 1

    def close(self) -> None:
        self.closed += 1


@pytest.fixture
def fake_tqdm(monkeypatch: pytest.MonkeyPatch) -> type[FakeTqdm]:
    auto = types.ModuleType("tqdm.auto")
    auto.tqdm = FakeTqdm  # type: ignore[attr-defined]
    package = types.ModuleType("tqdm")
    package.auto = auto  # type: ignore[attr-defined]
    monkeypatch.setitem(sys.modules, "tqdm", package)
    monkeypatch.setitem(sys.modules, "tqdm.auto", auto)
    FakeTqdm.made = []
    return FakeTqdm


def test_tqdm_bar_moves_by_the_difference(fake_tqdm: type[FakeTqdm]) -> None:
    bar = TqdmBar(sys.modules["tqdm.auto"], total=200, unit="jobs", desc="registration.icp")
    (made,) = fake_tqdm.made
    assert made.options["total"] == 200 and made.options["desc"] == "registration.icp: "
    assert made.options["bar_format"].endswith("{rate_fmt}{postfix}")  # tqdm adds ", "
    assert "{remaining}" in made.options["bar_format"]  # the time left
    assert "{rate_fmt}" in made.options["bar_format"] and "{elapsed}" in made.options["bar_format"]
    bar.update(3)
    bar.update(3, "1 failed")  # no move: redrawn for the message
    bar.update(10)
    assert made.n == 10 and made.postfix == ["1 failed"] and made.refreshes == 1
    bar.close()
    bar.close()
    assert made.closed == 1


def test_progress_true_uses_tqdm_on_a_terminal(
    fake_tqdm: type[FakeTqdm], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(sys, "stderr", FakeTerminal())
    display = make_progress(True, total=5, unit="jobs")
    assert isinstance(display, TqdmBar) and isinstance(display, ProgressDisplay)
    assert fake_tqdm.made[0].options["total"] == 5


def test_progress_true_uses_tqdm_in_a_notebook(
    fake_tqdm: type[FakeTqdm], monkeypatch: pytest.MonkeyPatch
) -> None:
    kernel_stream = type("OutStream", (io.StringIO,), {"__module__": "ipykernel.iostream"})
    monkeypatch.setattr(sys, "stderr", kernel_stream())  # not a tty, yet a widget shows
    assert isinstance(make_progress(True), TqdmBar)


def test_progress_true_off_a_terminal_writes_lines_even_with_tqdm(
    fake_tqdm: type[FakeTqdm], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(sys, "stderr", io.StringIO())  # a log file: tqdm's \r would clutter it
    display = make_progress(True)
    assert isinstance(display, ProgressBar) and fake_tqdm.made == []


def test_progress_true_without_tqdm_draws_its_own_bar(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "tqdm.auto", None)  # import tqdm.auto: ImportError
    monkeypatch.setattr(sys, "stderr", FakeTerminal())
    display = make_progress(True, total=3, unit="jobs")
    assert isinstance(display, ProgressBar) and display.total == 3 and display.unit == "jobs"


def test_make_progress_passes_a_display_through_and_refuses_others() -> None:
    bar = ProgressBar(io.StringIO())
    assert make_progress(bar) is bar
    assert make_progress(False) is None and make_progress(None) is None
    with pytest.raises(TypeError, match="Expected `progress` to be True, False or a progress "
                                        "bar, got str"):
        make_progress("yes")  # type: ignore[arg-type]
