"""A hard limit on a process's resident memory: ``RLIMIT_DATA``, re-aimed as the process runs.

Sampling the resident set size (:meth:`supcoord.bdd.budget.Budget.check`, the command
line's watchdog) cannot stop a single long C operation: one CUDD image computation or one
numpy allocation grows the process while Python waits for it to return.  The kernel can:
with ``RLIMIT_DATA`` set, an allocation that would take the process's private writable
memory past the limit fails at once (``malloc`` returns ``NULL``), which CUDD reports as an
out-of-memory error and numpy and Python as :class:`MemoryError` — exceptions the command
line turns into exit status 3.

The limit counts *virtual* private memory (``VmData``), the resident set counts the pages
that are used: libraries reserve address space they never touch (CUDD's and the
allocator's arenas, thread stacks), so ``VmData`` exceeds the anonymous resident memory by
tens to hundreds of MiB.  A fixed ``RLIMIT_DATA`` equal to the budget would therefore stop
a run well below it.  :class:`MemoryCap` instead sets, about ten times a second, ::

    soft RLIMIT_DATA = VmData now + max(0, budget - RESERVE - VmRSS now)

so the process may still *use* what is left of the budget, whatever it has only
reserved: until the next adjustment its resident memory can grow by at most that much,
and adjustments only need the interpreter between two C operations (the limit holds
during them).  What is reserved and then used without a new allocation escapes the
limit; the one such block known is CUDD's *stash* (``maxMemory / 64``, 16 MiB with
``dd``'s default of 1 GiB), allocated untouched when a manager starts and freed for
reuse when memory runs out, which :data:`RESERVE` leaves room for.  ``RLIMIT_AS`` was not used: it counts every reservation, so it stops at an
address-space size unrelated to the memory used.

Linux only (``/proc/self/status``, ``RLIMIT_DATA`` counting ``mmap`` since Linux 4.7);
elsewhere :class:`MemoryCap` does nothing and the sampled checks remain.
"""

from __future__ import annotations

import threading
from typing import Any

__all__ = ["RESERVE", "MemoryCap", "memory_status"]

#: seconds between two adjustments of the limit
TICK = 0.1
#: bytes of the budget kept back for reserved memory used later without a new
#: allocation: CUDD's stash of one manager (module docstring)
RESERVE = 16 * 2**20


def memory_status() -> dict[str, int]:
    """``VmData``, ``VmRSS``, ``RssAnon`` and ``RssFile`` of this process in bytes (from
    ``/proc/self/status``; empty where there is none)."""
    out: dict[str, int] = {}
    try:
        with open("/proc/self/status", "rb") as f:
            for line in f:
                key, _, value = line.partition(b":")
                if key in (b"VmData", b"VmRSS", b"RssAnon", b"RssFile"):
                    out[key.decode()] = int(value.split()[0]) * 1024
    except (OSError, ValueError, IndexError):
        return {}
    return out


class MemoryCap:
    """Keep this process's resident memory under ``max_bytes`` with ``RLIMIT_DATA``
    (module docstring): a context manager that starts a daemon thread adjusting the limit
    every :data:`TICK` seconds and restores the previous limit on exit.

    Parameters
    ----------
    max_bytes : int
        The budget of resident memory, bytes.
    """

    def __init__(self, max_bytes: int):
        self.max_bytes = int(max_bytes)
        self._previous: tuple[int, int] | None = None
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None
        self.active = False

    def adjust(self) -> None:
        """Aim the soft limit at what is left of the budget now (never below ``VmData``)."""
        if self._previous is None:
            return
        import resource

        status = memory_status()
        if "VmData" not in status or "VmRSS" not in status:
            return
        soft = status["VmData"] + max(0, self.max_bytes - RESERVE - status["VmRSS"])
        hard = self._previous[1]
        if hard != resource.RLIM_INFINITY:
            soft = min(soft, hard)
        resource.setrlimit(resource.RLIMIT_DATA, (soft, hard))

    def _run(self) -> None:
        while not self._stop.wait(TICK):
            try:
                self.adjust()
            except BaseException:  # noqa: BLE001 (an allocation failing here: the next tick retries)
                pass

    def __enter__(self) -> "MemoryCap":
        try:
            import resource

            if not memory_status():
                return self
            self._previous = resource.getrlimit(resource.RLIMIT_DATA)
            self._thread = threading.Thread(target=self._run, name="supcoord-memory-cap", daemon=True)
            self._thread.start()  # before the first adjustment: its stack counts in VmData
            self.adjust()
            self.active = True
        except (ImportError, OSError, ValueError):  # no resource limits here: the sampled checks remain
            self._previous = None
        return self

    def release(self) -> None:
        """Stop adjusting and restore the limit in force before (idempotent)."""
        self._stop.set()
        if self._thread is not None and self._thread is not threading.current_thread():
            self._thread.join()
        self._thread = None
        if self._previous is not None:
            import resource

            try:
                resource.setrlimit(resource.RLIMIT_DATA, self._previous)
            except (OSError, ValueError):
                pass
            self._previous = None
        self.active = False

    def __exit__(self, *exc: Any) -> bool:
        self.release()
        return False
