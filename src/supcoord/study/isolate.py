"""One case in a process of its own, with a time limit and a memory limit.

:func:`execute` is what a Dask worker (or the serial runner) calls for each case.  It
starts ``python -m supcoord.study.child`` (:mod:`.child`) in a new session, waits for it
with ``wait4`` — which also returns the child's resource usage: its CPU seconds and
``ru_maxrss`` (the peak resident memory recorded when the child reports none itself: on
Linux it starts at the runner's resident size) — and kills the whole session at the time limit plus a
grace period (the library stops cleanly at the limit between two fixpoint iterations;
the kill is for code that cannot be interrupted, such as one long BDD operation).

The **row** it returns (one row of the results database, :mod:`.store`) holds the case's
measurement (:mod:`.case_run`) and how it ran: ``status`` is

- ``ok``: an answer (``verdict`` says which);
- ``timeout``: the library stopped at the time limit, or the process was killed after it;
- ``out-of-memory``: an allocation failed under the memory limit (or the node budget it
  implies ran out; or the process died of a signal after using 80 % of its limit);
- ``error``: the case's parameters were refused by the library (``message`` says why);
- ``crashed``: the process died (a signal, such as a segmentation fault) or raised an
  unexpected exception; ``message`` holds what it reported (the last lines of its error
  output, or the exception).
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from datetime import UTC, datetime
from typing import Any

from .machine import cpu_model, load, machine

__all__ = ["FAILED", "STATUSES", "execute", "grace_seconds"]

STATUSES = ("ok", "timeout", "out-of-memory", "error", "crashed", "lost", "skipped")
#: the statuses counted as failures in progress lines and summaries
FAILED = ("timeout", "out-of-memory", "error", "crashed", "lost")
#: share of its memory limit a case must have used for its death by a signal to count as
#: running out of memory (supcoord.cli.guard.NEAR_BUDGET)
NEAR_LIMIT = 0.8
#: error output of CUDD / the C++ runtime when memory runs out
_OOM_TEXT = ("bad_alloc", "MemoryError", "out of memory", "Cannot allocate memory")


def grace_seconds(time_limit: float) -> float:
    """How long past its time limit a case may run before it is killed: 10 % of the
    limit, at least 2 s and at most 60 s (one fixpoint iteration may overrun the limit)."""
    return min(60.0, max(2.0, 0.1 * time_limit))


def _tail(path: str, lines: int = 3) -> str:
    try:
        with open(path, encoding="utf-8", errors="replace") as f:
            text = f.read()[-4000:]
    except OSError:
        return ""
    return " | ".join(line.strip() for line in text.strip().splitlines()[-lines:] if line.strip())


def execute(task: dict[str, Any], should_stop: Callable[[], bool] | None = None) -> dict[str, Any]:
    """Run ``task`` (``kind``, ``params``, ``time_limit``, ``memory_limit_mb``, ``key``) in a
    child process; the row of the results database (module docstring).  ``should_stop``
    is polled about once a second: when it returns true the child is killed and the row
    has status ``None`` (an interrupted case, not recorded)."""
    started = datetime.now(UTC).isoformat(timespec="seconds")
    row: dict[str, Any] = {"key": task.get("key"), "machine": machine(), "cpu": cpu_model(), "load": load(),
                           "started": started, "worker": task.get("worker")}
    limit = float(task["time_limit"])
    with tempfile.TemporaryDirectory(prefix="supcoord-case-") as tmp:
        task_path, result_path = os.path.join(tmp, "task.json"), os.path.join(tmp, "result.json")
        err_path = os.path.join(tmp, "stderr.txt")
        with open(task_path, "w", encoding="utf-8") as f:
            json.dump(task, f)
        env = {**os.environ, "SUPCOORD_STUDY_PARENT": str(os.getpid()), "OMP_NUM_THREADS": "1",
               "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1", "MPLBACKEND": "Agg"}
        inherited = _high_water()  # a child's ru_maxrss starts at this process's peak (Linux, at exec)
        t0 = time.perf_counter()
        with open(os.path.join(tmp, "stdout.txt"), "wb") as out, open(err_path, "wb") as err:
            proc = subprocess.Popen([sys.executable, "-m", "supcoord.study.child", task_path, result_path],
                                    stdin=subprocess.DEVNULL, stdout=out, stderr=err, env=env, start_new_session=True)
        killed, stopped, status, usage = _wait(proc, t0 + limit + grace_seconds(limit), should_stop)
        _kill(proc)  # what the case started in its session and left running ends with it
        wall = time.perf_counter() - t0
        result: dict[str, Any] = {}
        if os.path.exists(result_path):
            with open(result_path, encoding="utf-8") as f:
                result = json.load(f)
        stderr = _tail(err_path)
    if stopped:
        return {**row, "status": None}
    row.update(wall_seconds=wall, cpu_seconds=usage.ru_utime + usage.ru_stime, peak_rss_mb=usage.ru_maxrss / 1024)
    row.update({k: v for k, v in result.items() if k != "extra" and not (k == "peak_rss_mb" and v is None)})
    row["extra"] = result.get("extra") or {}
    if killed:
        row.update(status="timeout", message=f"killed {wall:.0f} s after its start: past the time limit of "
                                             f"{limit:g} s and {grace_seconds(limit):g} s of grace")
    elif not result:
        row.update(status="crashed", message=_death(status, stderr))
        memory = task.get("memory_limit_mb")
        peak = usage.ru_maxrss * 1024
        near = memory is not None and peak > inherited and peak >= NEAR_LIMIT * memory * 2**20
        if any(t in stderr for t in _OOM_TEXT) or (near and os.WIFSIGNALED(status)):
            row["status"] = "out-of-memory"  # (a few CUDD paths die of SIGSEGV when an allocation fails)
    elif row.get("status") == "crashed" and stderr:
        row["extra"]["stderr"] = stderr
    row.setdefault("message", "")
    return row


def _high_water() -> int:
    """This process's peak resident bytes (``VmHWM``; 0 where unknown).  The kernel carries
    it into the ``ru_maxrss`` of a child it starts, so only a child's ``ru_maxrss`` above it
    is the child's own peak."""
    try:
        with open("/proc/self/status", "rb") as f:
            for line in f:
                if line.startswith(b"VmHWM:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    return 0


def _death(status: int, stderr: str) -> str:
    if os.WIFSIGNALED(status):
        sig = os.WTERMSIG(status)
        name = signal.Signals(sig).name if sig in signal.Signals._value2member_map_ else str(sig)
        what = f"killed by signal {name}"
        if sig == signal.SIGKILL:
            what += " (not by the study: the kernel's out-of-memory killer or another process)"
    else:
        what = f"exited with status {os.WEXITSTATUS(status)} without a result"
    return f"{what}: {stderr}"[:500] if stderr else what


def _wait(proc: subprocess.Popen, deadline: float, should_stop: Callable[[], bool] | None):
    """Wait for ``proc`` with ``wait4``; kill its session at ``deadline`` or when asked to
    stop.  ``(killed at the deadline, stopped, wait status, resource usage)``."""
    killed = stopped = False
    pause, last_check = 0.01, time.perf_counter()
    try:
        while True:
            pid, status, usage = os.wait4(proc.pid, os.WNOHANG)
            if pid:
                proc.returncode = status  # reaped here: keep Popen from waiting again
                return killed, stopped, status, usage
            now = time.perf_counter()
            if should_stop is not None and now - last_check > 1.0:
                last_check = now
                if should_stop():
                    stopped = True
                    _kill(proc)
            if now > deadline and not killed:
                killed = True
                _kill(proc)
            time.sleep(pause)
            pause = min(0.2, pause * 1.5)
    except BaseException:  # KeyboardInterrupt in the serial runner: never leave the case running
        _kill(proc)
        os.wait4(proc.pid, 0)
        proc.returncode = -9
        raise


def _kill(proc: subprocess.Popen) -> None:
    try:
        os.killpg(proc.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass
