"""The statistics of one ``solve``, typed, and the one place their JSON is made.

A run fills a :class:`SolveStats` as it goes (the route's model, the descent, the windows,
the certificate, the schedule, the validation); :meth:`SolveStats.to_json` makes the
``stats`` object of PLAN.json from it.  PLAN.json lists the statistics in the order the run
reached them, so a statistics object remembers the order in which its fields were first
set (:class:`Recorded`); a field never set is not written.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

__all__ = ["Recorded", "DescentShort", "Refined", "WindowStats", "MonolithicStats", "SolveStats"]


class Recorded:
    """A dataclass whose fields set after ``__init__`` are written to JSON in the order they
    were first set (later assignments change the value, not the place)."""

    def __post_init__(self) -> None:
        object.__setattr__(self, "_set_order", [])

    def __setattr__(self, name: str, value: Any) -> None:
        order = self.__dict__.get("_set_order")
        if order is not None and name not in order:
            order.append(name)
        object.__setattr__(self, name, value)

    def set_fields(self) -> list[str]:
        """The names of the fields set so far, in the order they were first set."""
        return list(self.__dict__.get("_set_order", []))

    def to_json(self) -> dict[str, Any]:
        """The fields set so far, in the order they were first set; nested statistics
        (:class:`Recorded`) inline, other typed values as JSON."""
        out: dict[str, Any] = {}
        for name in self.set_fields():
            value = getattr(self, name)
            if isinstance(value, Recorded):
                out.update(value.to_json())
            else:
                out[name] = _json(value)
        return out


def _json(value: Any) -> Any:
    if hasattr(value, "to_json"):
        return value.to_json()
    return value


@dataclass
class DescentShort:
    """How many robots the greedy descent leaves short of their goal in each direction."""

    forward: int
    reverse: int

    def to_json(self) -> dict[str, int]:
        return {"forward": self.forward, "reverse": self.reverse}


@dataclass
class Refined:
    """What the finer lattice gave after a single-move certificate: ``status`` ``"not
    searched"``, ``"unknown"`` (its budget ran out: ``why``), ``"complete"`` (the plan came
    from there: ``original`` lattice, the coarse ``certificate`` and its ``seconds``), or
    ``"infeasible"`` (its own ``certificate``)."""

    status: str
    lattice: tuple[int, ...] | None = None
    why: str | None = None
    original: tuple[int, ...] | None = None
    certificate: list[int] | None = None
    seconds: float | None = None

    def to_json(self) -> dict[str, Any]:
        out: dict[str, Any] = {}
        if self.lattice is not None:
            out["lattice"] = list(self.lattice)
        out["status"] = self.status
        if self.why is not None:
            out["why"] = self.why
        if self.status == "complete":
            out.update({"from": list(self.original or ()), "certificate": self.certificate, "seconds": self.seconds})
        elif self.status not in ("not searched", "unknown"):
            out["certificate"] = self.certificate
        return out


@dataclass
class WindowStats(Recorded):
    """The local route's work (:func:`.windows.solve_local`): conflict components, windows
    and their sizes (members), descents and their moves, robots at target, peak BDD nodes of
    the windows' own managers."""

    components: int = 0
    largest_component: int = 0
    windows: int = 0
    largest_window: int = 0
    window_sizes: dict[str, int] = field(default_factory=dict)
    relaxed_checks: int = 0
    windows_abandoned: int = 0
    descent_steps: int = 0
    descent_moves: int = 0
    at_target: int = 0
    windows_few_displaced: int = 0
    window_peak_nodes: int = 0

    def begin(self, components: int, largest_component: int, at_target: int) -> None:
        """The start of a run: its conflict components, the robots at target, every counter
        at zero (all of them written from here on, in this order)."""
        self.components = components
        self.largest_component = largest_component
        self.windows = 0
        self.largest_window = 0
        self.window_sizes = {}
        self.relaxed_checks = 0
        self.windows_abandoned = 0
        self.descent_steps = 0
        self.descent_moves = 0
        self.at_target = at_target

    def count_window(self, members: int) -> None:
        """One more window of ``members`` positioners."""
        self.windows += 1
        self.largest_window = max(self.largest_window, members)

    def count_solved(self, members: int) -> None:
        """One more window of ``members`` positioners that reached its goal."""
        key = str(members)
        self.window_sizes[key] = self.window_sizes.get(key, 0) + 1


@dataclass
class MonolithicStats(Recorded):
    """The monolithic route's one window: its size, the length of a shortest single-move plan
    (None: none), and the supervisor's reachable states (with ``supcon``)."""

    windows: int = 1
    largest_window: int = 0
    single_moves: int | None = None
    supervisor_states: int | None = None


@dataclass
class SolveStats(Recorded):
    """Everything one ``solve`` reports in ``Plan.stats`` (PLAN.json's ``stats``).

    ``route`` is the route that ran (``"local"``, ``"monolithic"``); ``search`` the route's own
    statistics (written inline); ``certificate`` the positioners of a single-move
    certificate and ``certificate_model`` the motion model it holds for; ``plan_model``
    ``"simultaneous"`` when the plan came from the simultaneous search; ``refined`` what the
    finer lattice gave.  Times in seconds, BDD sizes in nodes, clearance in millimetres."""

    route: str = ""
    order: str = ""
    positioners: int = 0
    descent_short: DescentShort | None = None
    direction: str | None = None
    search: WindowStats | MonolithicStats | None = None
    bdd_nodes: int = 0
    certificate: list[int] | None = None
    certificate_model: str | None = None
    plan_model: str | None = None
    schedule: str | None = None
    single_moves: int | None = None
    makespan_scheduled: int | None = None
    improve_seconds: float | None = None
    improved_groups: int | None = None
    improve_replans: int | None = None
    seconds: float = 0.0
    min_clearance: float | None = None
    validate_seconds: float | None = None
    timing: dict[str, Any] | None = None
    refined: Refined | None = None

    def window_peak_nodes(self) -> int:
        """The peak BDD nodes of the local route's own window managers (0: none)."""
        return self.search.window_peak_nodes if isinstance(self.search, WindowStats) else 0

