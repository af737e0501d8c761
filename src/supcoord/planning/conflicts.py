"""Targets that cannot be reached together: forbidden pairs and groups for target assignment.

A target-assignment program (PFS's ``forbiddenPairs``, SDSS-V's robostrategy) wants to know,
for a field, which targets it must not give together.  Two levels, each exact about what it
claims:

- **static** (``kind`` ``static-pair``): two robots collide when both stand at their
  targets, so those two targets cannot be observed together; ``static-obstacle``: a robot
  at its target collides with a fixed obstacle; ``static-held``: with a robot held in place
  (offline or fixed) where it stands.  Checked at the target configuration with the
  collision definition of the problem.
- **planned** (``planned-group``), from a collision-free start: a group of robots whose sub-problem (those robots alone,
  from their starts, every other robot removed; held robots and obstacles stay) has no
  single-move plan on the problem's lattice: the local route's certificate
  (:class:`~supcoord.planning.windows.Certificate`).  The groups are looked for among the
  robots in no static conflict: solve, record the certificate's group, remove its robots,
  solve again, at most ``max_groups`` times.  The list is therefore not every such group,
  but every group listed has no plan.

Targets are named by the problem's ``target_ids`` (an optional PROBLEM.json list, one id per
robot) where it has them, else ``r<robot>@<x>,<y>``: the robot and its fibre's target
position in focal-plane mm.
"""

from __future__ import annotations

import csv
import io
from dataclasses import dataclass
from typing import Sequence

import numpy as np

from ..errors import InputError
from ..geometry.layout import _short
from ..geometry.motion import placed_segments
from ..geometry.segments import segment_distance
from ..problems.problem import Problem
from .partial import sub_problem  # noqa: F401  (exported here too)
from .planner import solve

__all__ = ["Conflict", "ConflictReport", "KINDS", "CSV_COLUMNS", "find_conflicts", "static_conflicts",
           "planned_conflicts", "target_names", "sub_problem", "conflicts_csv"]

#: the kinds of a conflict (module docstring)
KINDS = ("static-pair", "static-obstacle", "static-held", "planned-group")
#: the CSV's columns: robots and targets are space-separated lists
CSV_COLUMNS = ("kind", "size", "robots", "targets", "reason")


@dataclass(frozen=True)
class Conflict:
    """Targets that cannot be reached together.

    Attributes
    ----------
    kind : str
        One of :data:`KINDS`.
    robots : tuple of int
        The robots (indices from 0) whose targets conflict; one for ``static-obstacle``
        and ``static-held`` (the obstacle or held robot is named in ``reason``).
    targets : tuple of str
        Their targets' names (:func:`target_names`).
    reason : str
        Why, in words, with the distances in mm.
    """

    kind: str
    robots: tuple[int, ...]
    targets: tuple[str, ...]
    reason: str


@dataclass(frozen=True)
class ConflictReport:
    """The conflicts of a field, and how the search for planned groups ended.

    Attributes
    ----------
    conflicts : list of Conflict
        Static ones first, then the planned groups in the order found.
    searched : str
        ``"complete"`` (the robots left after removing every group have a plan),
        ``"max_groups"`` (stopped after that many groups) or ``"budget"`` (a budget ran out).
    """

    conflicts: list[Conflict]
    searched: str


def target_names(problem: Problem) -> list[str]:
    """Each robot's target name: ``target_ids`` of the problem, else ``r<robot>@<x>,<y>`` (mm).

    >>> from supcoord.problems import parse_problem
    >>> p = parse_problem({"layout": {"kind": "points", "xy": [[0, 0], [30, 0]]},
    ...     "kinematics": {"kind": "rotary", "arm": 10.0, "steps": 4},
    ...     "collision": {"buffer": 1.0}, "start": [0, 0], "target": [1, 2]})
    >>> target_names(p)
    ['r0@0.000,-10.000', 'r1@20.000,0.000']
    """
    ids = problem.extra.get("target_ids")
    if ids is not None:
        if not (isinstance(ids, list) and len(ids) == problem.n and all(isinstance(v, (str, int)) and
                not isinstance(v, bool) and str(v) and not any(ch.isspace() for ch in str(v)) for v in ids)):
            raise InputError(f"target_ids must be a list of {problem.n} strings or integers without spaces, got "
                             f"{_short(ids)}",
                             value=ids, where=problem.where)
        return [str(v) for v in ids]
    out = []
    for p in range(problem.n):
        xy = problem.bases[p] + problem.kin(p).fibre(problem.target[p])
        x, y = (round(float(v), 3) + 0.0 for v in xy)  # + 0.0: no "-0.000"
        out.append(f"r{p}@{x:.3f},{y:.3f}")
    return out


def static_conflicts(problem: Problem) -> list[Conflict]:
    """The ``static-*`` conflicts at the target configuration (module docstring)."""
    names = target_names(problem)
    held = set(problem.held)
    out = []
    for a, b, d in sorted(problem.collisions(problem.target)):
        need = problem.buffers[a] + problem.buffers[b]
        if a in held and b in held:
            continue
        if a in held or b in held:
            p, h = (b, a) if a in held else (a, b)
            out.append(Conflict("static-held", (p,), (names[p],),
                                f"robot {p} at its target is {d:.3f} mm from robot {h}, held in place, less than "
                                f"{need:.3f} mm"))
            continue
        out.append(Conflict("static-pair", (a, b), (names[a], names[b]),
                            f"robots {a} and {b} at their targets are {d:.3f} mm apart, less than {need:.3f} mm"))
    if len(problem.obstacles):
        for p in range(problem.n):
            if p in held:
                continue
            seg = placed_segments(problem.kin(p), problem.bases[p], problem.target[p].astype(float))
            d = segment_distance(seg[0], seg[1], problem.obstacles[:, 0], problem.obstacles[:, 1])
            gap = d - problem.buffers[p] - problem.obstacle_buffers
            o = int(np.argmin(gap))
            if gap[o] < 0:
                out.append(Conflict("static-obstacle", (p,), (names[p],),
                                    f"robot {p} at its target is {d[o]:.3f} mm from obstacle {o}, less than "
                                    f"{problem.buffers[p] + problem.obstacle_buffers[o]:.3f} mm"))
    return out


def planned_conflicts(problem: Problem, exclude: Sequence[int] = (), max_groups: int = 8,
                      budget=None) -> ConflictReport:
    """The ``planned-group`` conflicts among the robots not in ``exclude`` (module docstring)."""
    from ..errors import BudgetExceeded

    names = target_names(problem)
    left = [p for p in range(problem.n) if p not in set(exclude)]
    out: list[Conflict] = []
    while left:
        if len(out) >= max_groups:
            return ConflictReport(out, "max_groups")
        sub = sub_problem(problem, left)
        try:
            plan = solve(sub, simultaneous=None, finer=None, improve=0, budget=budget, when_incomplete="infeasible")
        except BudgetExceeded:
            return ConflictReport(out, "budget")
        if plan.status == "complete":
            return ConflictReport(out, "complete")
        if plan.status != "infeasible" or not plan.stats.get("certificate"):
            return ConflictReport(out, "budget")
        group = tuple(sorted(left[i] for i in plan.stats["certificate"]))
        out.append(Conflict("planned-group", group, tuple(names[p] for p in group),
                            f"robots {', '.join(map(str, group))} alone (every other robot removed) have no "
                            f"single-move plan from their starts to these targets on the problem's lattice"))
        left = [p for p in left if p not in group]
    return ConflictReport(out, "complete")


def find_conflicts(problem: Problem, max_groups: int = 8, budget=None) -> ConflictReport:
    """Static conflicts, then planned groups among the robots in none (module docstring).

    Parameters
    ----------
    problem : Problem
        The field: a problem whose target may collide
        (:func:`~supcoord.problems.problem.parse_problem` with ``check_collisions=False``).
    max_groups : int, default 8
        Most planned groups looked for (0: static conflicts only).
    budget : Budget, optional
        The budget of each solve (a budget that runs out ends the search for groups).

    Returns
    -------
    ConflictReport
        The conflicts and how the search for groups ended.

    Raises
    ------
    InputError
        ``max_groups`` negative, ``target_ids`` of the wrong shape, or (``max_groups`` > 0)
        a start whose robots collide.

    Examples
    --------
    >>> from supcoord.problems import parse_problem
    >>> p = parse_problem({"layout": {"kind": "points", "xy": [[0, 0], [20, 0]]},
    ...     "kinematics": {"kind": "rotary", "arm": 12.0, "steps": 4},
    ...     "collision": {"buffer": 1.0}, "start": [2, 0], "target": [0, 2]},
    ...     check_collisions=False)
    >>> r = find_conflicts(p)
    >>> [(c.kind, c.robots) for c in r.conflicts], r.searched
    ([('static-pair', (0, 1))], 'complete')

    References
    ----------
    ``docs/formats.md`` (``supcoord conflicts``); the certificate: ``docs/architecture.md``.
    """
    if isinstance(max_groups, bool) or not isinstance(max_groups, int) or max_groups < 0:
        raise InputError(f"max_groups must be an integer >= 0, got {max_groups!r}", value=max_groups,
                         where="max_groups")
    hits = problem.collisions(problem.start) if max_groups else []
    if hits:
        raise InputError(f"start configuration collides: positioners {hits[0][0]} and {hits[0][1]} (planned groups "
                         f"need a collision-free start; max_groups or --max-groups 0: static conflicts only)",
                         value=list(hits[0][:2]), where=problem.where)
    static = static_conflicts(problem)
    busy = {p for c in static for p in c.robots}
    for a, b, _ in problem.collisions(problem.target):  # a held robot's partner is busy too
        busy |= {a, b} - set(problem.held)
    if max_groups == 0:
        return ConflictReport(static, "max_groups")
    planned = planned_conflicts(problem, sorted(busy), max_groups, budget)
    return ConflictReport(static + planned.conflicts, planned.searched)


def conflicts_csv(conflicts: Sequence[Conflict]) -> str:
    """The CSV text: a header of :data:`CSV_COLUMNS`, one row per conflict."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(CSV_COLUMNS)
    for c in conflicts:
        w.writerow([c.kind, len(c.robots), " ".join(map(str, c.robots)), " ".join(c.targets), c.reason])
    return buf.getvalue()
