"""Resource limits of the fixpoints: live BDD nodes, wall-clock seconds and resident memory.

Every fixpoint calls :meth:`supcoord.bdd.Context.check_budget` once per iteration (the
cheap ones through a throttled check); it reports progress and :meth:`Budget.check`
raises :class:`~supcoord.errors.BudgetExceeded` (with the stage and statistics so far)
once a limit is passed.  Long loops outside the fixpoints (table building, descent,
validation) call :meth:`Budget.check` themselves.

The memory limit is on the process's *resident set size* (RSS), what the kernel's
out-of-memory killer looks at: BDD nodes are only part of it (numpy tables, caches,
Python objects are the rest), so a node budget alone cannot keep a run inside the
machine.
"""

from __future__ import annotations

import math
import os
import resource
import sys
import time
from dataclasses import dataclass, field
from typing import Any, Callable, Mapping

from ..errors import BudgetExceeded, InputError

__all__ = ["Budget", "ProgressCallback", "current_rss", "MAX_TIMEOUT"]

#: ``progress(stage, {"nodes": live nodes, **info})``, called at every budget check
ProgressCallback = Callable[[str, Mapping[str, Any]], None]
#: longest time budget accepted (seconds, a year): beyond it the timers overflow
MAX_TIMEOUT = 365 * 24 * 3600.0

_PAGE = os.sysconf("SC_PAGE_SIZE") if hasattr(os, "sysconf") else 4096


def current_rss() -> int:
    """Resident set size of this process in bytes: ``/proc/self/statm`` where it exists,
    else the peak from ``getrusage`` (an upper bound of the current one)."""
    try:
        with open("/proc/self/statm", "rb") as f:
            return int(f.read().split()[1]) * _PAGE
    except (OSError, ValueError, IndexError):
        peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
        return int(peak if sys.platform == "darwin" else peak * 1024)


def _limit(value: Any, name: str, *, integer: bool) -> Any:
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float)) or (integer and not float(value).is_integer()):
        kind = "an integer" if integer else "a number"
        raise InputError(f"Budget.{name} must be {kind} or None, got {value!r}", value=value, where=name)
    if not (value > 0 and math.isfinite(value)):
        raise InputError(f"Budget.{name} must be positive and finite, got {value!r}", value=value, where=name)
    if name == "timeout" and value > MAX_TIMEOUT:
        raise InputError(f"Budget.timeout must be at most {MAX_TIMEOUT:.0f} s, got {value!r}", value=value, where=name)
    return int(value) if integer else float(value)


@dataclass
class Budget:
    """Resource limits: live BDD nodes (``max_nodes``), wall-clock seconds (``timeout``) and
    resident memory in bytes (``max_memory``); ``None`` is no limit.  Values are checked:
    a wrong type or a value that is not positive and finite raises :class:`InputError`."""

    max_nodes: int | None = None
    timeout: float | None = None
    started: float = field(default_factory=time.perf_counter)
    max_memory: int | None = None

    def __post_init__(self) -> None:
        self.max_nodes = _limit(self.max_nodes, "max_nodes", integer=True)
        self.timeout = _limit(self.timeout, "timeout", integer=False)
        self.max_memory = _limit(self.max_memory, "max_memory", integer=True)

    def elapsed(self) -> float:
        return time.perf_counter() - self.started

    def check(self, stage: str, nodes: int = 0, info: Mapping[str, Any] | None = None) -> None:
        """Raise :class:`BudgetExceeded` if ``nodes`` live nodes, the time so far or the
        resident memory pass a limit."""
        info = info or {}
        if self.max_nodes is not None and nodes > self.max_nodes:
            raise BudgetExceeded(
                f"node budget exceeded in {stage}: {nodes} live nodes > {self.max_nodes}",
                stats={"stage": stage, "bdd_nodes": nodes, "seconds": self.elapsed(), **info},
                value=self.max_nodes,
            )
        if self.timeout is not None and self.elapsed() > self.timeout:
            raise BudgetExceeded(
                f"time budget exceeded in {stage}: {self.elapsed():.1f} s > {self.timeout} s",
                stats={"stage": stage, "bdd_nodes": nodes, "seconds": self.elapsed(), **info},
                value=self.timeout,
            )
        if self.max_memory is not None:
            rss = current_rss()
            if rss > self.max_memory:
                raise BudgetExceeded(
                    f"memory budget exceeded in {stage}: {rss / 2**20:.0f} MiB resident > "
                    f"{self.max_memory / 2**20:.0f} MiB",
                    stats={"stage": stage, "bdd_nodes": nodes, "seconds": self.elapsed(), "rss_bytes": rss, **info},
                    value=self.max_memory,
                )
