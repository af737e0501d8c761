"""A start that collides: reading such a problem, and the repair phase of its plan (PLAN.json ``repair``).

After a fault, or from kaiju's "decollide" input, robots may start in collision with each
other.  A plan from such a start begins with a **repair phase** (``docs/formats.md``,
PLAN.json ``repair``): configurations ``c_0 = start, …, c_k`` in which

- only the robots listed in ``repair.moved`` move, each of them a member of a pair that
  collides at the start, and none of them held (offline or fixed);
- along every step (all joints turning linearly in angle), a pair that collides at the
  step's beginning never comes closer than it is there (by more than 1e-6 mm), and a pair
  (or a robot and a fixed obstacle) that does not collide there does not collide anywhere
  on the step;
- ``c_k`` is collision-free.

From ``c_k`` on, the plan is an ordinary plan to the target.  The validator checks exactly
this (:mod:`.validate_repair`); the planner's repair is :func:`supcoord.planning.repair.repair_start`.
A start robot colliding with a fixed obstacle, or breaking a joint rule, is still refused:
only collisions between robots are repaired.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..errors import FormatError
from ..geometry.kinematics import _is_int
from ..geometry.layout import _short
from .json_input import read_json
from .problem import MAX_PROBLEM_BYTES, Problem, _check_fixed, _check_free, parse_problem

__all__ = ["Repair", "read_repair", "start_collisions", "load_problem_any_start", "parse_problem_any_start"]


@dataclass(frozen=True)
class Repair:
    """PLAN.json's ``repair``: the repair phase of a plan from a colliding start.

    Attributes
    ----------
    moved : tuple of int
        The robots that move in the repair phase (indices from 0), sorted.
    steps : int
        The number of steps of the repair phase: configurations ``0 … steps``.
    minimum : bool
        True when ``len(moved)`` equals ``lower_bound``, so no repair moves fewer robots.
    lower_bound : int
        A proven lower bound of the robots any repair moves: the minimum vertex cover of
        the graph of colliding pairs where it was computed exactly, else the size of a
        maximal matching of it (every matched pair needs one robot of its own to move).
    """

    moved: tuple[int, ...]
    steps: int
    minimum: bool
    lower_bound: int

    def to_json(self) -> dict[str, Any]:
        """The PLAN.json object ``{"moved": [...], "steps": k, "minimum": bool, "lower_bound": m}``."""
        return {"moved": [int(p) for p in self.moved], "steps": int(self.steps), "minimum": bool(self.minimum),
                "lower_bound": int(self.lower_bound)}


def read_repair(value: Any, n: int, where: str | None) -> Repair | None:
    """PLAN.json's ``repair`` (absent or null: None); a :class:`FormatError` naming the field.

    >>> read_repair({"moved": [2, 0], "steps": 3, "minimum": True, "lower_bound": 2}, 5, None).moved
    (0, 2)
    """
    if value is None:
        return None
    if not isinstance(value, dict) or set(value) - {"moved", "steps", "minimum", "lower_bound"}:
        raise FormatError(f"repair must be an object {{\"moved\": [...], \"steps\": k, \"minimum\": bool, "
                          f"\"lower_bound\": m}}, got {_short(value)}", value=value, where=where)
    moved, steps = value.get("moved"), value.get("steps")
    if not isinstance(moved, list) or not all(_is_int(p) and 0 <= p < n for p in moved) or len(set(moved)) != len(moved):
        raise FormatError(f"repair.moved must list distinct robot indices in [0, {n - 1}], got {_short(moved)}",
                          value=moved, where=where)
    if not _is_int(steps) or steps < 0:
        raise FormatError(f"repair.steps must be a number of steps >= 0, got {_short(steps)}", value=steps,
                          where=where)
    minimum, bound = value.get("minimum", False), value.get("lower_bound", 0)
    if not isinstance(minimum, bool) or not _is_int(bound) or bound < 0:
        raise FormatError(f"repair.minimum must be true or false and repair.lower_bound an integer >= 0, got "
                          f"{_short(minimum)} and {_short(bound)}", value=[minimum, bound], where=where)
    return Repair(tuple(sorted(int(p) for p in moved)), int(steps), minimum, int(bound))


def start_collisions(problem: Problem) -> list[tuple[int, int]]:
    """The pairs ``(a, b)``, ``a < b``, of robots that collide at the start."""
    return sorted((min(a, b), max(a, b)) for a, b, _ in problem.collisions(problem.start))


def parse_problem_any_start(data: Any, where: str | None = None) -> Problem:
    """:func:`~.problem.parse_problem`, except that robots may collide with each other at the start.

    The target must still be collision-free, and no robot may touch a fixed obstacle or break
    a joint rule at the start (one line naming them, as :func:`~.problem.parse_problem` says).

    >>> p = parse_problem_any_start({"layout": {"kind": "points", "xy": [[0, 0], [20, 0]]},
    ...     "kinematics": {"kind": "rotary", "arm": 12.0, "steps": 4},
    ...     "collision": {"buffer": 1.0}, "start": [0, 2], "target": [2, 0]})
    >>> start_collisions(p)
    [(0, 1)]
    """
    problem = parse_problem(data, where, check_collisions=False)
    _check_free(problem, "target", problem.target, where)
    _check_fixed(problem, "start", problem.start, where)
    return problem


def load_problem_any_start(path: str | Path) -> Problem:
    """Read PROBLEM.json whose start may collide (:func:`parse_problem_any_start`)."""
    return parse_problem_any_start(read_json(path, "problem", MAX_PROBLEM_BYTES), str(path))
