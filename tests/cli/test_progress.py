"""wearjoint.progress: plain lines every LOG_INTERVAL_S seconds in a redirected log (a fake non-terminal
stream and a clock set by the test), a tqdm bar on a terminal, nothing when disabled."""
import io

import pytest

from wearjoint import progress
from wearjoint.progress import Progress, clock_text


class Clock:
    def __init__(self):
        self.t = 1000.0

    def __call__(self):
        return self.t


class FakeTerminal(io.StringIO):
    def isatty(self):
        return True


@pytest.fixture
def clock(monkeypatch):
    c = Clock()
    monkeypatch.setattr(progress, "_now", c)
    return c


def test_a_redirected_log_gets_a_plain_line_every_interval(clock):
    log = io.StringIO()                          # a file: isatty() is False
    bar = Progress(4000, "wear-study", unit="rev", stream=log, interval_s=15.0)
    for second in range(1, 61):                  # 60 s of updates, one a second, 10 rev/s
        clock.t += 1.0
        bar.update(10.0 * second)
    lines = log.getvalue().splitlines()
    assert len(lines) == 4                       # at 15, 30, 45 and 60 s, no more
    assert lines[0] == "wear-study:   3.8% (150/4000 rev), elapsed 0:00:15, ETA 0:06:25"
    assert lines[-1] == "wear-study:  15.0% (600/4000 rev), elapsed 0:01:00, ETA 0:05:40"
    bar.close()
    assert log.getvalue().splitlines()[-1].startswith("wear-study:  15.0% (600/4000 rev)")   # closed early


def test_the_eta_counts_from_the_end_of_compilation_and_a_finished_run_says_so(clock):
    log = io.StringIO()
    bar = Progress(100.0, "simulate", compiling=True, stream=log, interval_s=10.0)
    clock.t += 40.0                              # compiling, nothing done
    bar.update(0.0)
    assert log.getvalue().splitlines() == ["simulate (compiling):   0.0% (0/100 s), elapsed 0:00:40, ETA ?"]
    bar.compiled()
    clock.t += 10.0
    bar.update(25.0)                             # 25 s simulated in 10 s of wall time: 30 s left
    assert log.getvalue().splitlines()[-1] == "simulate:  25.0% (25/100 s), elapsed 0:00:50, ETA 0:00:30"
    clock.t += 30.0
    bar.update(100.0)
    bar.close()
    assert log.getvalue().splitlines()[-1] == "simulate: 100.0% (100 s) in 0:01:20"


def test_a_callers_eta_replaces_the_rates(clock):
    """A run whose pace is not its amount done (cycle jumping's growing jumps) gives its own ETA, marked ~."""
    log = io.StringIO()
    bar = Progress(400_000, "wear-study (cycle jumping)", unit="rev", stream=log, interval_s=15.0, caller_eta=True)
    clock.t += 20.0
    bar.update(4.0, eta_s=125.0)
    assert log.getvalue().splitlines() == [
        "wear-study (cycle jumping):   0.0% (4/4e+05 rev), elapsed 0:00:20, ETA ~0:02:05"]
    term = FakeTerminal()
    shown = Progress(400_000, "wear-study", unit="rev", stream=term, delay_s=0.0, caller_eta=True)
    shown.update(4.0, eta_s=125.0)
    assert "ETA ~0:02:05" in str(shown._bar)     # what the bar draws at its next refresh
    shown.close()


def test_a_short_run_writes_nothing_and_a_disabled_one_never(clock):
    log = io.StringIO()
    bar = Progress(10.0, "simulate", stream=log)
    clock.t += progress.LOG_INTERVAL_S - 0.5
    bar.update(10.0)
    bar.close()
    off = Progress(10.0, "simulate", enabled=False, stream=log)
    clock.t += 100.0
    off.update(5.0)
    off.close()
    assert log.getvalue() == ""


def test_a_terminal_gets_the_tqdm_bar_not_the_lines(clock):
    term = FakeTerminal()
    bar = Progress(10.0, "simulate", stream=term, delay_s=0.0)
    assert bar._bar is not None and bar._log is None
    clock.t += 100.0
    bar.update(5.0)
    bar.close()
    assert "simulate" in term.getvalue() and "ETA" not in term.getvalue()


def test_clock_text():
    assert clock_text(3725.4) == "1:02:05" and clock_text(float("nan")) == "?" and clock_text(-3) == "0:00:00"
