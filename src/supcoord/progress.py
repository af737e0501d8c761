"""Progress of long fixpoints: a live status line, a throttled log, or your own callback.

Every fixpoint of the library calls ``ctx.check_budget(stage, iteration=…, …)`` once
per iteration (:meth:`supcoord.bdd.Context.check_budget`), which passes
``(stage, info)`` to the context's ``progress`` callback; ``info`` always holds
``nodes`` (live BDD nodes in the manager) and ``iteration``, plus what the fixpoint
knows (``method``, ``z_nodes``, ``layer_nodes``, ``members``).  The stages are
``reachable``, ``coreachable``, ``supcon``, ``force`` and the planner's ``layers``.

This module turns those calls into something a person can read:

- :class:`ProgressBar` — one status line (tqdm; a widget-free line in Jupyter too)::

      coreachable #3 | iteration 130 | 30,019 nodes (peak 33,112) | saturation | 0:12

  ``#3`` counts how often the stage started again (a fixpoint called repeatedly, e.g.
  supcon's inner reachability or the planner's windows), ``peak`` is the largest
  node count seen since the bar was made, and the clock is the time since then.
- :class:`ProgressLog` — the same text as lines, at the start and end of each run of
  a stage and at most once per ``interval`` seconds in between (``interval=0``: every
  iteration); for logs, CI and files.
- :func:`progress_bar` — the helper for notebooks and scripts.

Both keep talking during a long single step: a heartbeat thread (:class:`Heartbeat`,
every :data:`HEARTBEAT` seconds) redraws the status line with the time so far, and the
log repeats its last line every ``interval`` seconds, so neither is silent for more than
about 2 s while the interpreter runs.  (A single BDD or numpy operation that holds the
interpreter holds the heartbeat too.)  Phases that know how far along they are report
``done`` and ``total``, shown as ``done/total``.

>>> import io, supcoord as sc
>>> log = sc.ProgressLog(io.StringIO(), interval=0)
>>> log("supcon", {"nodes": 1200, "iteration": 1, "z_nodes": 300})
>>> log("supcon", {"nodes": 1500, "iteration": 2, "z_nodes": 280})
>>> print(log.file.getvalue().replace("0:00", "T"), end="")
[T] supcon | iteration 1 | 1,200 nodes | z_nodes 300
[T] supcon | iteration 2 | 1,500 nodes | z_nodes 280
"""

from __future__ import annotations

import os
import sys
import threading
import time
import warnings
import weakref
from typing import IO, Any, Mapping

__all__ = ["HEARTBEAT", "Heartbeat", "format_progress", "format_elapsed", "ProgressBar", "ProgressLog",
           "progress_bar"]

#: the keys shown in a fixed place; any other key is shown as ``key value`` after them
_PLACED = ("nodes", "iteration", "method", "done", "total")
#: seconds between two heartbeats of a status line or a log (redraws during a long step)
HEARTBEAT = 0.5


class Heartbeat:
    """A daemon thread calling ``beat()`` every ``interval`` seconds until :meth:`stop`.

    Started on demand (:meth:`start` is idempotent), so an object that never reports
    never starts a thread.  ``beat`` runs in the thread: it must take its own locks.
    """

    def __init__(self, beat: Any, interval: float | None = None) -> None:
        # a bound method is held weakly: a bar nobody closes ends its thread when it is dropped
        self._beat = weakref.WeakMethod(beat) if hasattr(beat, "__self__") else (lambda: beat)
        self.interval = HEARTBEAT if interval is None else interval
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None

    def start(self) -> None:
        if self._thread is None and self.interval > 0:
            self._stop.clear()
            self._thread = threading.Thread(target=self._run, name="supcoord-heartbeat", daemon=True)
            self._thread.start()

    def _run(self) -> None:
        while not self._stop.wait(self.interval):
            beat = self._beat()
            if beat is None:
                return
            try:
                beat()
            except Exception:  # noqa: BLE001 - a closed stream must not kill the work it reports on
                return

    def stop(self) -> None:
        self._stop.set()
        if self._thread is not None and self._thread is not threading.current_thread():
            self._thread.join(timeout=5)
        self._thread = None


def format_elapsed(seconds: float) -> str:
    """``m:ss`` (``h:mm:ss`` past an hour), as tqdm shows time.

    >>> format_elapsed(75.4), format_elapsed(3725)
    ('1:15', '1:02:05')
    """
    s = int(seconds)
    h, rest = divmod(s, 3600)
    m, s = divmod(rest, 60)
    return f"{h}:{m:02d}:{s:02d}" if h else f"{m}:{s:02d}"


def _number(value: Any) -> str:
    if isinstance(value, bool) or not isinstance(value, int):
        return str(value)
    return f"{value:,}"


def format_progress(stage: str, info: Mapping[str, Any], *, run: int = 1, peak: int | None = None) -> str:
    """One line describing a progress report: stage, run, iteration, nodes, the rest.

    ``iteration`` is called ``layer`` in the ``force`` stage (each iteration adds one
    forcibility layer).

    >>> format_progress("force", {"nodes": 19137, "iteration": 4, "layer_nodes": 601}, peak=20000)
    'force | layer 4 | 19,137 nodes (peak 20,000) | layer_nodes 601'
    >>> format_progress("layers", {"nodes": 47133, "iteration": 0, "members": 4}, run=312)
    'layers #312 | iteration 0 | 47,133 nodes | members 4'
    >>> format_progress("figure", {"done": 3, "total": 40, "frames": "plan.gif"})
    'figure | 3/40 | frames plan.gif'
    """
    parts = [stage if run <= 1 else f"{stage} #{run}"]
    if "done" in info:
        parts.append(f"{_number(info['done'])}/{_number(info['total'])}" if "total" in info else _number(info["done"]))
    if "iteration" in info:
        parts.append(f"{'layer' if stage == 'force' else 'iteration'} {_number(info['iteration'])}")
    if "nodes" in info:
        nodes = f"{_number(info['nodes'])} nodes"
        if peak is not None and isinstance(info["nodes"], int) and peak > info["nodes"]:
            nodes += f" (peak {_number(peak)})"
        parts.append(nodes)
    if "method" in info:
        parts.append(str(info["method"]))
    parts += [f"{k} {_number(v)}" for k, v in info.items() if k not in _PLACED]
    return " | ".join(parts)


class _Tracker:
    """Stage, run number (restarts of a stage) and peak nodes across calls."""

    def __init__(self, started: float | None = None) -> None:
        self.started = time.perf_counter() if started is None else started
        self.stage: str | None = None
        self.runs: dict[str, int] = {}
        self.last_iteration: Any = None
        self.peak = 0

    def update(self, stage: str, info: Mapping[str, Any]) -> tuple[bool, bool]:
        """Record a report; ``(new stage, new run of the stage)``."""
        nodes = info.get("nodes")
        if isinstance(nodes, int):
            self.peak = max(self.peak, nodes)
        iteration = info.get("iteration")
        new_stage = stage != self.stage
        restarted = new_stage or (
            isinstance(iteration, int) and isinstance(self.last_iteration, int) and iteration <= self.last_iteration
        )
        if restarted:
            self.runs[stage] = self.runs.get(stage, 0) + 1
        self.stage, self.last_iteration = stage, iteration
        return new_stage, restarted

    def text(self, stage: str, info: Mapping[str, Any]) -> str:
        return format_progress(stage, info, run=self.runs.get(stage, 1), peak=self.peak or None)

    def elapsed(self) -> str:
        return format_elapsed(time.perf_counter() - self.started)


def _screen(file: IO[str]) -> tuple[int, int]:
    """``(columns, lines)`` of the terminal, with 100 × 24 where it reports none: the
    pseudo-terminals of ``script`` and some CI runners say 0 × 0, and tqdm then prints
    nothing at all (a bar at row 0 of 0 rows is "hidden")."""
    try:
        size = os.get_terminal_size(file.fileno())
        columns, lines = size.columns, size.lines
    except (AttributeError, OSError, ValueError):
        columns = lines = 0
    if columns <= 0:
        try:
            columns = int(os.environ.get("COLUMNS", "0"))
        except ValueError:
            columns = 0
    return (columns if columns > 0 else 100), (lines if lines > 0 else 24)


class ProgressBar:
    """A ``progress`` callback drawing one live status line with tqdm.

    ``auto=True`` uses ``tqdm.auto`` (a Jupyter widget where ipywidgets is installed,
    else a text line that the notebook redraws in place).  ``leave=True`` keeps the
    last line when closed.  Use it as a context manager, or call :meth:`close`.

    >>> import io, supcoord as sc
    >>> out = io.StringIO()
    >>> with sc.ProgressBar(file=out, auto=False) as bar:
    ...     ctx = sc.Context(progress=bar)
    ...     G = sc.from_explicit(ctx, sc.Generator(2, [sc.Event("a", True)], [(0, "a", 1)], 0, [1]))
    ...     _ = sc.reachable(G)
    >>> "reachable | iteration 1" in out.getvalue()
    True
    """

    def __init__(self, file: IO[str] | None = None, *, auto: bool = True, leave: bool = True,
                 mininterval: float = 0.1, started: float | None = None):
        self.file = file
        self.auto = auto
        self.leave = leave
        self.mininterval = mininterval
        self._tracker = _Tracker(started)
        self._bar: Any = None
        self._shown = 0.0
        self._text = ""
        self._body = ""
        self._width: int | None = None
        self._lock = threading.RLock()
        self._heartbeat = Heartbeat(self._beat)

    def _make(self) -> Any:
        if self.auto:
            with warnings.catch_warnings():  # tqdm.auto warns when ipywidgets is missing
                warnings.simplefilter("ignore")
                from tqdm.auto import tqdm
        else:
            from tqdm import tqdm
        file = self.file if self.file is not None else sys.stderr
        if tqdm.__module__.startswith("tqdm.notebook"):  # a Jupyter widget: it sizes itself
            self._width = None
            return tqdm(total=None, bar_format="{desc}", leave=self.leave, mininterval=self.mininterval)
        columns, lines = _screen(file)
        self._width = columns - 1
        return tqdm(total=None, bar_format="{desc}", file=file, leave=self.leave, ncols=columns, nrows=lines,
                    mininterval=self.mininterval, dynamic_ncols=False)

    def _show(self) -> None:
        text = self._text if self._width is None else self._text[: max(self._width, 20)]
        self._bar.set_description_str(text, refresh=True)

    def __call__(self, stage: str, info: Mapping[str, Any]) -> None:
        with self._lock:
            new_stage, _ = self._tracker.update(stage, info)
            self._body = self._tracker.text(stage, info)
            self._text = f"{self._body} | {self._tracker.elapsed()}"
            if self._bar is None:
                self._bar = self._make()
            now = time.perf_counter()
            if new_stage or now - self._shown >= self.mininterval:
                self._show()
                self._shown = now
        self._heartbeat.start()

    def _beat(self) -> None:
        """The heartbeat: the last report again, with the time so far."""
        with self._lock:
            if self._bar is not None and time.perf_counter() - self._shown >= self._heartbeat.interval:
                self._text = f"{self._body} | {self._tracker.elapsed()}"
                self._show()
                self._shown = time.perf_counter()

    def write(self, line: str) -> None:
        """Print ``line`` above the status line (which is redrawn below it)."""
        with self._lock:
            if self._bar is None:
                print(line, file=self.file if self.file is not None else sys.stderr)
            else:
                self._bar.write(line, file=self.file if self.file is not None else sys.stderr)

    def close(self) -> None:
        self._heartbeat.stop()
        with self._lock:
            if self._bar is not None:
                if self.leave:
                    self._show()
                self._bar.close()
                self._bar = None

    def __enter__(self) -> "ProgressBar":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()


class ProgressLog:
    """A ``progress`` callback printing lines: the first and the last report of a stage
    (until another stage reports), and in between at most one every ``interval``
    seconds (0: every report).

    ``write`` (default: print to ``file``) receives each finished line, so the log can
    go to :mod:`logging` instead: ``ProgressLog(write=logger.info)``.
    """

    def __init__(self, file: IO[str] | None = None, *, interval: float = 2.0, write: Any = None,
                 started: float | None = None):
        self.file = file
        self.interval = interval
        self._write = write
        self._tracker = _Tracker(started)
        self._shown = float("-inf")
        self._pending: str | None = None  # the last report of the current run, if not shown
        self._body: str | None = None  # the last report, without its time
        self._lock = threading.RLock()
        self._heartbeat = Heartbeat(self._beat, min(HEARTBEAT, interval) if interval > 0 else 0)

    def _emit(self, text: str) -> None:
        if self._write is not None:
            self._write(text)
        else:
            print(text, file=self.file if self.file is not None else sys.stderr, flush=True)

    def __call__(self, stage: str, info: Mapping[str, Any]) -> None:
        with self._lock:
            new_stage, _ = self._tracker.update(stage, info)
            self._body = self._tracker.text(stage, info)
            text = f"[{self._tracker.elapsed()}] {self._body}"
            now = time.perf_counter()
            if new_stage and self._pending is not None:
                self._emit(self._pending)  # how the previous stage ended
                self._pending = None
            if new_stage or now - self._shown >= self.interval:
                self._emit(text)
                self._shown, self._pending = now, None
            else:
                self._pending = text
        self._heartbeat.start()

    def _beat(self) -> None:
        """The heartbeat: past ``interval`` seconds of silence, the last report again, with
        the time so far."""
        with self._lock:
            # now if a later beat could come too late (a beat may itself be late by up to one
            # interval on a busy machine): never more than ``interval`` silent
            if self._body is not None and time.perf_counter() - self._shown + 2 * self._heartbeat.interval > self.interval:
                self._emit(f"[{self._tracker.elapsed()}] {self._body}")
                self._shown, self._pending = time.perf_counter(), None

    def close(self) -> None:
        self._heartbeat.stop()
        with self._lock:
            if self._pending is not None:
                self._emit(self._pending)
                self._pending = None

    def __enter__(self) -> "ProgressLog":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()


def progress_bar(*, leave: bool = True, file: IO[str] | None = None) -> ProgressBar:
    """A progress callback for notebooks and scripts: pass it as ``progress=`` to
    :class:`supcoord.Context` (or to ``solve(…, progress=…)``) and close it after.

    >>> import supcoord as sc
    >>> with sc.progress_bar() as bar:      # in Jupyter: a line under the cell, redrawn live
    ...     ctx = sc.Context(progress=bar)
    ...     G, E = sc.literal_models(sc.random_instance(20, 12, seed=0), ctx)
    ...     result = sc.supcon(G, E)
    >>> result.stats["marked"]
    1
    """
    return ProgressBar(file=file, auto=True, leave=leave)


def summary_repr(name: str, fields: Mapping[str, Any]) -> str:
    """The short ``repr`` of a result: ``Name(key=value, …)``, each value cut to 60 characters,
    so a notebook shows a line, whatever the size of the object.

    >>> summary_repr("Plan", {"status": "complete", "positioners": 500, "makespan": 22})
    "Plan(status='complete', positioners=500, makespan=22)"
    """
    parts = []
    for k, v in fields.items():
        text = repr(v)
        parts.append(f"{k}={text if len(text) <= 60 else text[:57] + '...'}")
    return f"{name}({', '.join(parts)})"


def summary_html(name: str, fields: Mapping[str, Any]) -> str:
    """The ``_repr_html_`` of a result: its name over a two-column table of ``fields``."""
    from html import escape

    rows = "".join(f"<tr><th style='text-align:left'>{escape(str(k))}</th><td style='text-align:left'>"
                   f"{escape(_number(v) if len(str(v)) <= 200 else str(v)[:197] + '...')}</td></tr>"
                   for k, v in fields.items())
    return f"<table><caption style='text-align:left'><b>{escape(name)}</b></caption>{rows}</table>"
