"""The work of a command with a memory budget, in a child process the command line outlives.

Under :class:`~supcoord.bdd.memory.MemoryCap` an allocation past the budget fails.
Python and numpy raise :class:`MemoryError` and most CUDD operations report the failure,
all of which the command turns into exit status 3; but a few of CUDD's allocation paths
do not expect to fail and end the process (a segmentation fault) instead.  So the command
forks first: the child does the work under the cap and prints its result as usual; the
parent waits, and when the child dies of a signal after using at least
:data:`NEAR_BUDGET` of the budget, the parent reports what the user asked for — exit 3
with ``"status": "unknown"`` — rather than a crash.  A child stopped by a signal that only another process or the
system sends (SIGTERM, SIGHUP, SIGKILL: an operator, a batch scheduler, the kernel's
out-of-memory killer) is reported as such, with the shell's status ``128 + signal``; a
child that dies of any other signal far below its budget is a bug (exit 1, one line).

The fork happens only from the main thread and when standard output and error are real
files (a terminal, a pipe, a file); a caller that captured them (``main([...])`` in a
test or a notebook) runs the work in its own process, under the same cap.
"""

from __future__ import annotations

import os
import signal
import sys
import threading
from typing import Callable

__all__ = ["NEAR_BUDGET", "can_fork", "run_in_child"]

#: share of the budget a child must have used for its death by a signal to count as the
#: budget running out
NEAR_BUDGET = 0.8
#: signals supcoord never raises in its own child: its death by one of them came from outside
FROM_OUTSIDE = (signal.SIGTERM, signal.SIGHUP, signal.SIGKILL)


def can_fork() -> bool:
    """Whether :func:`run_in_child` may fork: POSIX, main thread, real stdout and stderr."""
    if not hasattr(os, "fork") or threading.current_thread() is not threading.main_thread():
        return False
    try:
        return sys.stdout.fileno() == 1 and sys.stderr.fileno() == 2
    except (AttributeError, OSError, ValueError):
        return False


def _die_with_parent() -> None:
    try:
        import ctypes

        ctypes.CDLL(None, use_errno=True).prctl(1, int(signal.SIGKILL), 0, 0, 0)  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        pass


def run_in_child(work: Callable[[], int], max_memory: int,
                 out_of_memory: Callable[[str, dict], int], crashed: Callable[[str], int]) -> int:
    """``work()`` in a forked child; its exit status, or ``out_of_memory(reason, stats)``
    when it died of a signal near ``max_memory`` bytes, ``128 + signal`` after
    ``crashed(message)`` prints why when another process or the system stopped it, or
    ``crashed(message)`` when it died of another signal well below (module docstring)."""
    sys.stdout.flush()
    sys.stderr.flush()
    from ..bdd.memory import memory_status

    inherited = memory_status().get("VmRSS", 0)  # a forked child's ru_maxrss starts at least here
    pid = os.fork()
    if pid == 0:  # the child: the work, then leave without the parent's clean-up
        code = 1
        try:
            _die_with_parent()
            code = work()
        except SystemExit as exc:
            code = exc.code if isinstance(exc.code, int) else 1
        except BaseException:  # a bug: its traceback, as the command would print it unforked
            import traceback

            traceback.print_exc()
        finally:
            for stream in (sys.stdout, sys.stderr):
                try:
                    stream.flush()
                except (OSError, ValueError):
                    pass
            os._exit(code)
    # the parent passes SIGINT and SIGTERM on to the child, which stops cleanly (exit 130); a
    # Ctrl-C at the terminal reaches both, and the child ignores the second interrupt
    previous = {sig: signal.getsignal(sig) for sig in (signal.SIGINT, signal.SIGTERM)}
    for sig in previous:
        signal.signal(sig, lambda signum, frame: os.kill(pid, signum))
    try:
        while True:
            try:
                _, status, usage = os.wait4(pid, 0)
                break
            except InterruptedError:
                continue
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)
    if os.WIFEXITED(status):
        return os.WEXITSTATUS(status)
    sig = os.WTERMSIG(status)
    name = signal.Signals(sig).name if sig in signal.Signals._value2member_map_ else str(sig)
    if sig == signal.SIGINT:
        return 130
    peak = usage.ru_maxrss * 1024
    if peak > inherited and peak >= NEAR_BUDGET * max_memory:
        return out_of_memory(f"memory budget exceeded: the computation ended ({name}) when an allocation "
                             f"failed at the budget of {max_memory / 2**20:.0f} MiB",
                             {"stage": "memory", "peak_rss_bytes": peak, "signal": name})
    if sig in FROM_OUTSIDE:
        crashed(f"the computation was stopped by {name} from outside supcoord (another process or the "
                f"system) at {peak / 2**20:.0f} MiB resident")
        return 128 + sig
    return crashed(f"the computation died of {name} at {peak / 2**20:.0f} MiB resident, "
                   f"well below its memory budget: a bug (please report it)")
