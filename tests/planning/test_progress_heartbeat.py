"""Long work never goes silent: the status line and the log keep reporting during a long
single step (a heartbeat), on stderr only; ``--json`` keeps stdout one JSON object and
``-q`` silences progress.  Gaps are measured on the timestamps of the lines as they were
written, not on how fast anything ran."""

from __future__ import annotations

import io
import json
import time
from pathlib import Path

import pytest

import supcoord.planning.planner as planner
from supcoord.cli.main import main
from supcoord.progress import ProgressLog

EXAMPLE = Path(__file__).resolve().parents[2] / "docs" / "examples" / "three_rotary.json"
#: the longest silence allowed (seconds)
MAX_GAP = 2.0
#: how long the patched validation step takes, one step without any report of its own
LONG_STEP = 3.0


class Recorder(io.StringIO):
    """A stderr that notes when each write happened."""

    def __init__(self, tty: bool) -> None:
        super().__init__()
        self.tty = tty
        self.times: list[float] = []

    def write(self, text: str) -> int:
        if text.strip():
            self.times.append(time.perf_counter())
        return super().write(text)

    def isatty(self) -> bool:
        return self.tty


@pytest.fixture
def slow_validation(monkeypatch):
    validate = planner.validate_plan

    def slow(*args, **kwargs):
        time.sleep(LONG_STEP)  # a long step that reports nothing itself (and releases the GIL, as I/O does)
        return validate(*args, **kwargs)

    monkeypatch.setattr(planner, "validate_plan", slow)


@pytest.mark.parametrize("flags,tty", [(["-v"], False), ([], True)], ids=["log", "status line"])
def test_a_long_step_is_never_silent_and_json_stays_on_stdout(slow_validation, monkeypatch, capsys, flags, tty):
    err = Recorder(tty)
    monkeypatch.setattr("sys.stderr", err)
    started = time.perf_counter()
    assert main(["solve", str(EXAMPLE), "--json", *flags]) == 0
    ended = time.perf_counter()
    out = capsys.readouterr().out
    assert json.loads(out)["status"] == "complete" and out.count("\n") == 1  # one JSON object, nothing else
    stamps = [started, *err.times, ended]  # the silence before the end counts too
    gaps = [b - a for a, b in zip(stamps, stamps[1:])]
    assert ended - started >= LONG_STEP and len(err.times) >= 3
    assert max(gaps) <= MAX_GAP, gaps
    assert "validate" in err.getvalue()


def test_quiet_prints_no_progress(slow_validation, monkeypatch, capsys):
    err = Recorder(True)
    monkeypatch.setattr("sys.stderr", err)
    assert main(["solve", str(EXAMPLE), "--json", "-q"]) == 0
    assert err.getvalue() == "" and json.loads(capsys.readouterr().out)["status"] == "complete"


def test_the_log_repeats_its_last_report_while_nothing_reports():
    lines: list[tuple[float, str]] = []
    log = ProgressLog(interval=0.3, write=lambda text: lines.append((time.perf_counter(), text)))
    log("figure", {"done": 3, "total": 40})
    time.sleep(1.0)
    log.close()
    assert len(lines) >= 3 and all("figure | 3/40" in text for _, text in lines)
    stamps = [t for t, _ in lines]
    assert max(b - a for a, b in zip(stamps, stamps[1:])) <= MAX_GAP


def test_the_notebook_bar_keeps_redrawing_during_a_long_step():
    # what `supcoord.progress_bar()` draws in a notebook or script, without a terminal
    from supcoord.progress import ProgressBar

    out = Recorder(False)
    with ProgressBar(file=out, auto=False) as bar:
        bar("validate", {"steps": 12})
        started = time.perf_counter()
        time.sleep(2.5)  # one long step, no report
        ended = time.perf_counter()
    stamps = [started, *[t for t in out.times if started <= t <= ended], ended]
    assert max(b - a for a, b in zip(stamps, stamps[1:])) <= MAX_GAP
    assert "validate | steps 12 | 0:02" in out.getvalue()  # the clock moved on the redrawn line
