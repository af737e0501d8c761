"""Where a synthesis spends its effort: seconds per fixpoint stage and CUDD's counters.

:class:`EffortMeter` times the stages of one computation (``with meter.stage("reach"):``,
seconds added up per name) and reads the BDD manager's counters at its start and end;
:meth:`EffortMeter.result` gives an :class:`Effort`.  CUDD's computed-table lookups
count the recursive steps of every BDD operation (the work, the same on every
machine, unlike seconds); hits are the lookups answered from the table.

References
----------
- F. Somenzi, CUDD: CU Decision Diagram Package, release 3.0 (``Cudd_ReadCacheLookUps``,
  ``Cudd_ReadCacheHits``, ``Cudd_ReadPeakLiveNodeCount``).
"""

from __future__ import annotations

import time
from contextlib import contextmanager
from dataclasses import asdict, dataclass, field
from typing import Any, Iterator

from ..bdd.context import Context

__all__ = ["Effort", "EffortMeter", "add_closure_work"]


@dataclass
class Effort:
    """The effort of one synthesis.

    Attributes
    ----------
    stage_seconds : dict[str, float]
        Wall-clock seconds per stage (s), in the order the stages first ran.
    peak_live_nodes : int
        The BDD manager's peak of live nodes (nodes; over the manager's life, so it
        includes building the models in it).
    live_nodes : int
        Live nodes at the end (nodes).
    cudd_lookups, cudd_hits, cudd_insertions : int or None
        Computed-table lookups, hits and insertions of the manager during the
        computation (counts; ``None`` without CUDD).
    closure_lookups : int
        Computed-table lookups spent computing local closures in their scratch manager
        (count; :mod:`.closures`), not part of ``cudd_lookups``.
    closures_built, closures_abandoned : int
        Write groups closed, and groups whose closure was abandoned (it outgrew its node
        cap or its work bound) and kept their plain steps (counts).
    """

    stage_seconds: dict[str, float] = field(default_factory=dict)
    peak_live_nodes: int = 0
    live_nodes: int = 0
    cudd_lookups: int | None = None
    cudd_hits: int | None = None
    cudd_insertions: int | None = None
    closure_lookups: int = 0
    closures_built: int = 0
    closures_abandoned: int = 0

    @property
    def work(self) -> int | None:
        """All computed-table lookups, the manager's and the closures' (count)."""
        return None if self.cudd_lookups is None else self.cudd_lookups + self.closure_lookups

    def as_dict(self) -> dict[str, Any]:
        out = asdict(self)
        out["stage_seconds"] = {k: round(v, 6) for k, v in self.stage_seconds.items()}
        return out


_COUNTERS = {"cudd_lookups": "cache_lookups", "cudd_hits": "cache_hits", "cudd_insertions": "cache_insertions"}
_ACTIVE: list[EffortMeter] = []


def add_closure_work(lookups: int, built: int, abandoned: int) -> None:
    """Report a closure computation to the active meters (:mod:`.closures` calls it)."""
    for m in _ACTIVE:
        m.closure = [a + b for a, b in zip(m.closure, (lookups, built, abandoned))]


class EffortMeter:
    """``with EffortMeter(ctx) as meter:`` times named stages (:meth:`stage`), collects
    the closures computed meanwhile and reads ``ctx``'s counters on entry and at
    :meth:`result`."""

    def __init__(self, ctx: Context) -> None:
        self.ctx = ctx
        self.seconds: dict[str, float] = {}
        self.closure = [0, 0, 0]
        self._start: dict[str, Any] = {}

    def __enter__(self) -> EffortMeter:
        self._start = self._counters()
        _ACTIVE.append(self)
        return self

    def __exit__(self, *exc: object) -> None:
        _ACTIVE.remove(self)

    def _counters(self) -> dict[str, Any]:
        return self.ctx.statistics()

    @contextmanager
    def stage(self, name: str) -> Iterator[None]:
        t = time.perf_counter()
        try:
            yield
        finally:
            self.seconds[name] = self.seconds.get(name, 0.0) + time.perf_counter() - t

    def result(self) -> Effort:
        end = self._counters()
        counts = {}
        for ours, theirs in _COUNTERS.items():
            if theirs in end and theirs in self._start:
                counts[ours] = int(end[theirs] - self._start[theirs])
        peak = max(self.ctx.peak_nodes(), int(end.get("peak_live_nodes", 0)))
        live = int(end.get("n_nodes", 0))
        return Effort(dict(self.seconds), peak, live, **counts, closure_lookups=self.closure[0],
                      closures_built=self.closure[1], closures_abandoned=self.closure[2])
