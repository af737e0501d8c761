"""Plans from a colliding start: repair it first with the fewest robots moved, then plan as usual.

The rule a repair phase obeys is :mod:`supcoord.problems.repair_phase`'s (only robots of
colliding pairs move; a colliding pair never comes closer, no new collision; its end is
collision-free).  Every colliding pair needs one of its robots to move, so the robots moved
form a **vertex cover** of the graph of colliding pairs, and the minimum vertex cover is a
lower bound of any repair.  Per connected component of that graph:

- up to :data:`EXACT_ROBOTS` robots: the covers are enumerated by size (held robots, which
  never move, excluded), the first size with a cover is the exact minimum, and the covers
  are tried smallest first;
- larger: a maximal matching ``M`` (greedy, in index order) is a lower bound (each of its
  pairs needs a robot of its own), its end points a cover of at most ``2·|M|`` robots,
  pruned of robots whose pairs are all covered by others: the cover moved is at most twice
  the minimum.

A cover is realised one robot at a time, the others standing: robot ``p`` searches its own
lattice breadth-first (single-joint moves, fewest first) for a position free of every robot
except the cover's robots still to move, taking only moves that obey the rule against the
standing robots (the exact least distance of the turn, :func:`supcoord.geometry.sweep.rotation_clearance`).
This search is not exhaustive (robots of the cover never move together), so when no cover
of a component is realised the colliding start is refused as before (:class:`RepairNotFound`,
an :class:`~supcoord.errors.InputError` that says so): not a proof that no repair exists.  ``Repair.minimum`` is
True when the robots moved are as many as the proven lower bound.
"""

from __future__ import annotations

import dataclasses
import itertools
import time
from collections import deque
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import InputError, ModelError
from ..geometry.motion import placed_segments
from ..geometry.segments import segment_distance
from ..geometry.sweep import rotation_clearance
from ..problems.plan import Move, Plan, event_name, lower_bound
from ..problems.problem import Problem
from ..problems.repair_phase import Repair, start_collisions
from ..problems.trajectory import check_speed, continuous_angles, joint_names, wrapped_angles
from ..problems.validate import validate_plan
from . import planner

__all__ = ["EXACT_ROBOTS", "MAX_COVERS", "RepairResult", "RepairNotFound", "repair_start", "repair_trajectories",
           "solve_any_start"]

#: largest component of the colliding-pair graph whose minimum vertex cover is enumerated
EXACT_ROBOTS = 16
#: most covers of one component tried before the repair gives up
MAX_COVERS = 64
#: how far (mm) below its starting distance the planner lets a colliding pair's exact least
#: distance fall on a repair move: rounding only (the validator allows 1e-6 mm)
_ROUNDING = 1e-9


class RepairNotFound(InputError):
    """No cover of a component was realised by moving its robots one at a time (not a proof
    that none exists): the colliding start stays the user's to fix, as before repairs."""


@dataclass(frozen=True)
class RepairResult:
    """A repaired start: the configurations ``start … c_k`` (``(N, J)`` ints), the single
    moves between them (one per step) and PLAN.json's ``repair``."""

    configurations: list[np.ndarray]
    moves: list[Move]
    repair: Repair


def repair_start(problem: Problem) -> RepairResult:
    """Repair a colliding start with the fewest robots moved (module docstring).

    Parameters
    ----------
    problem : Problem
        A problem whose robots may collide at the start
        (:func:`~supcoord.problems.repair_phase.parse_problem_any_start`); lengths in mm.

    Returns
    -------
    RepairResult
        The repair phase, one single-joint move per step; no step when the start is free.

    Raises
    ------
    InputError
        Two held (offline or fixed) robots collide with each other at the start.
    RepairNotFound
        No cover of some component was realised (the search is not exhaustive); an
        :class:`~supcoord.errors.InputError`.

    Examples
    --------
    >>> from supcoord.problems.repair_phase import parse_problem_any_start
    >>> p = parse_problem_any_start({"layout": {"kind": "points", "xy": [[0, 0], [20, 0], [40, 0]]},
    ...     "kinematics": {"kind": "rotary", "arm": 12.0, "steps": 8},
    ...     "collision": {"buffer": 1.0}, "start": [0, 4, 0], "target": [4, 4, 4]})
    >>> r = repair_start(p)
    >>> r.repair.moved, r.repair.minimum, len(r.configurations) == r.repair.steps + 1
    ((0,), True, True)

    References
    ----------
    M. R. Garey, D. S. Johnson, *Computers and Intractability*, 1979 (vertex cover);
    the factor-2 bound of a maximal matching's end points, e.g. V. V. Vazirani,
    *Approximation Algorithms*, Springer 2001, §1.1.
    """
    pairs = start_collisions(problem)
    held = set(problem.held)
    both = [(a, b) for a, b in pairs if a in held and b in held]
    if both:
        raise InputError(f"start: held (offline or fixed) robots {both[0][0]} and {both[0][1]} collide with each "
                         f"other; neither may move", value=list(both[0]), where=problem.where)
    search = _Search(problem)
    moved: list[int] = []
    bound = 0
    for edges in _components(pairs):
        covers, low = _covers(edges, held)
        bound += low
        moved += search.realise(covers, edges)
    repair = Repair(tuple(sorted(moved)), len(search.moves), len(moved) == bound, bound)
    return RepairResult(search.configurations, search.moves, repair)


def _components(pairs: list[tuple[int, int]]) -> list[list[tuple[int, int]]]:
    """The edges of each connected component of the graph ``pairs``, smallest robot first."""
    parent: dict[int, int] = {}

    def root(x: int) -> int:
        while parent.setdefault(x, x) != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    for a, b in pairs:
        parent[root(a)] = root(b)
    groups: dict[int, list[tuple[int, int]]] = {}
    for a, b in pairs:
        groups.setdefault(root(a), []).append((a, b))
    return sorted(groups.values(), key=lambda e: min(min(p) for p in e))


def _covers(edges: list[tuple[int, int]], held: set[int]) -> tuple[Any, int]:
    """The covers to try (smallest first) and a proven lower bound of their size: exact up to
    :data:`EXACT_ROBOTS` robots, else a maximal matching's (module docstring)."""
    robots = sorted({p for e in edges for p in e})
    free = [p for p in robots if p not in held]
    forced = {b if a in held else a for a, b in edges if a in held or b in held}
    if len(robots) <= EXACT_ROBOTS:
        return _exact_covers(edges, free, forced)
    return _matching_cover(edges, held, forced)


def _exact_covers(edges: list[tuple[int, int]], free: list[int], forced: set[int]) -> tuple[Any, int]:
    """Every cover of robots ``free`` holding ``forced``, by size; the least size (exact)."""
    bit = {p: 1 << i for i, p in enumerate(free)}
    masks = [(bit.get(a, 0) | bit.get(b, 0)) for a, b in edges]
    need = sum(bit[p] for p in forced)
    found = [c for s in range(len(forced), len(free) + 1) for c in itertools.combinations(free, s)
             if _covered(c, bit, masks, need)]
    return iter(found), (len(found[0]) if found else 0)


def _matching_cover(edges: list[tuple[int, int]], held: set[int], forced: set[int]) -> tuple[Any, int]:
    """The end points of a greedy maximal matching (with ``forced``), pruned; the matching's size."""
    matching: list[tuple[int, int]] = []
    used: set[int] = set()
    for a, b in edges:
        if a not in used and b not in used:
            matching.append((a, b))
            used |= {a, b}
    cover = {p for e in matching for p in e if p not in held} | forced
    for p in sorted(cover - forced, key=lambda p: -sum(p in e for e in edges)):
        if all((a in cover and a != p) or (b in cover and b != p) for a, b in edges if p in (a, b)):
            cover.discard(p)
    return iter([tuple(sorted(cover))]), len(matching)


def _covered(cover: tuple[int, ...], bit: dict[int, int], masks: list[int], need: int) -> bool:
    """Does ``cover`` (with every robot of ``need``) meet every edge's mask?"""
    m = sum(bit[p] for p in cover)
    return (m & need) == need and all(m & e for e in masks)


class _Search:
    """Moves robots one at a time from the start, keeping the configurations and moves made."""

    def __init__(self, problem: Problem):
        self.problem = problem
        self.current = np.array(problem.start, dtype=np.int64)
        self.configurations = [self.current.copy()]
        self.moves: list[Move] = []
        self.near: dict[int, list[int]] = {}
        for a, b in problem.pairs:
            self.near.setdefault(int(a), []).append(int(b))
            self.near.setdefault(int(b), []).append(int(a))

    def realise(self, covers: Any, edges: list[tuple[int, int]]) -> list[int]:
        """Move the robots of the first cover that works; the robots moved."""
        for tried, cover in enumerate(covers):
            if tried >= MAX_COVERS:
                break
            mark = (self.current.copy(), len(self.configurations), len(self.moves))
            order = sorted(cover, key=lambda p: (-sum(p in e for e in edges), p))
            if all(self._free(p, set(order[i + 1:])) for i, p in enumerate(order)):
                return list(cover)
            self.current, self.configurations, self.moves = mark[0], self.configurations[:mark[1]], self.moves[:mark[2]]
        robots = sorted({p for e in edges for p in e})
        raise RepairNotFound(f"start configuration collides and was not repaired: the collisions among robots "
                             f"{robots} stay whichever robots of a vertex cover move, one at a time (a search that "
                             f"is not exhaustive)", value=robots, where=self.problem.where)

    def _free(self, p: int, pending: set[int]) -> bool:
        """Breadth-first over robot ``p``'s positions to one free of every robot outside
        ``pending``; the moves are applied when found."""
        kin = self.problem.kin(p)
        start = tuple(int(v) for v in self.current[p])
        back: dict[tuple, tuple | None] = {start: None}
        queue = deque([start])
        while queue:
            q = queue.popleft()
            if self._clear(p, np.array(q), pending):
                self._apply(p, q, back)
                return True
            for joint, delta in kin.moves():
                nxt = kin.step(np.array(q), joint, delta)
                if nxt is None or tuple(int(v) for v in nxt) in back or not self._allowed(p, np.array(q), joint, delta):
                    continue
                back[tuple(int(v) for v in nxt)] = (q, joint, delta)
                queue.append(tuple(int(v) for v in nxt))
        return False

    def _apply(self, p: int, q: tuple, back: dict) -> None:
        path = []
        while back[q] is not None:
            prev, joint, delta = back[q]
            path.append((p, joint, delta))
            q = prev
        for move in reversed(path):
            self.current[p] = self.problem.kin(p).step(self.current[p], move[1], move[2])
            self.moves.append(move)
            self.configurations.append(self.current.copy())

    def _distances(self, p: int, q: np.ndarray, others: list[int]) -> np.ndarray:
        """Distances (mm) from robot ``p`` at ``q`` to the robots ``others`` where they stand."""
        problem = self.problem
        seg = placed_segments(problem.kin(p), problem.bases[p], q.astype(float))
        segs = np.array([placed_segments(problem.kin(o), problem.bases[o], self.current[o].astype(float))
                         for o in others]).reshape(-1, 2, 2)
        return segment_distance(seg[0], seg[1], segs[:, 0], segs[:, 1])

    def _clear(self, p: int, q: np.ndarray, pending: set[int]) -> bool:
        others = [o for o in self.near.get(p, []) if o not in pending]
        if not others:
            return True
        bsum = self.problem.buffers[p] + self.problem.buffers[others]
        return bool(np.all(self._distances(p, q, others) >= bsum))

    def _allowed(self, p: int, q: np.ndarray, joint: int, delta: int) -> bool:
        """Does the move obey the rule against the standing robots, and robot ``p``'s own constraints?"""
        problem = self.problem
        d = np.zeros((1, problem.kinematics.n_joints), dtype=np.int64)
        d[0, joint] = delta
        if problem.own_motion_blocked(p, q[None, :], d)[0]:
            return False
        others = self.near.get(p, [])
        if not others:
            return True
        kin = problem.kin(p)
        centre, angle = kin.rotation(q.astype(float)[None, :], joint, delta)
        seg = placed_segments(kin, problem.bases[p], q.astype(float))
        segs = np.array([placed_segments(problem.kin(o), problem.bases[o], self.current[o].astype(float))
                         for o in others]).reshape(-1, 2, 2)
        least = rotation_clearance(np.broadcast_to(seg, segs.shape), centre[0] + problem.bases[p], angle[0], segs)
        now = self._distances(p, q, others)
        bsum = problem.buffers[p] + problem.buffers[others]
        return bool(np.all(np.where(now < bsum, least >= now - _ROUNDING, least >= bsum)))


def solve_any_start(problem: Problem, route: Any = "local", **options: Any) -> Plan:
    """:func:`~.planner.solve` from any start: a colliding start is repaired first (:func:`repair_start`).

    Parameters
    ----------
    problem : Problem
        The problem; its robots may collide with each other at the start.
    route : Local, Monolithic or str, default "local"
        As for :func:`~.planner.solve`.
    **options
        :func:`~.planner.solve`'s keyword options; with ``speed``, the trajectories of a plan
        from a colliding start are those of :func:`repair_trajectories`.

    Returns
    -------
    Plan
        :func:`~.planner.solve`'s plan when the start is free.  Else a ``complete`` plan
        whose first ``repair.steps`` steps are the repair phase (``plan.repair``,
        validated with it), or the verdict of the repaired problem with
        ``stats["repair"]``.

    Raises
    ------
    InputError
        Held robots colliding with each other; no repair found (:class:`RepairNotFound`); and :func:`~.planner.solve`'s errors.
    BudgetExceeded
        The budget ran out while solving the repaired problem.

    Examples
    --------
    >>> from supcoord.problems.repair_phase import parse_problem_any_start
    >>> p = parse_problem_any_start({"layout": {"kind": "points", "xy": [[0, 0], [20, 0]]},
    ...     "kinematics": {"kind": "rotary", "arm": 12.0, "steps": 8},
    ...     "collision": {"buffer": 1.0}, "start": [0, 4], "target": [4, 0]})
    >>> plan = solve_any_start(p)
    >>> plan.status, plan.repair.moved, plan.repair.minimum
    ('complete', (0,), True)
    """
    if not start_collisions(problem):
        return planner.solve(problem, route=route, **options)
    t0 = time.perf_counter()
    fixed = repair_start(problem)
    rest = planner.solve(dataclasses.replace(problem, start=fixed.configurations[-1]), route=route, **options)
    rest.stats = dict(rest.stats, repair=fixed.repair.to_json(), repair_seconds=time.perf_counter() - t0)
    if rest.lattice is not None and rest.configurations:  # planned on a finer lattice: the repair's positions are not on it
        return Plan("unknown", [], None, lower_bound(problem), [], "the repaired start needs a finer lattice, "
                    "to which the repair phase is not carried over", rest.stats)
    if rest.status not in ("complete", "partial"):
        rest.reason = f"after repairing the start (robots {list(fixed.repair.moved)} moved): {rest.reason}"
        return rest
    kin = problem.kinematics
    confs = fixed.configurations + rest.configurations[1:]
    events = [event_name(kin, *m) for m in fixed.moves] + list(rest.events)
    # a partial plan keeps its robots off target (they end at the repaired start)
    plan = dataclasses.replace(rest, configurations=confs, makespan=len(confs) - 1, events=events, angles_deg=[],
                               lower_bound=int(kin.joint_distance(problem.start, confs[-1]).max()),
                               repair=fixed.repair)
    if rest.trajectories is not None:  # timed: the repair phase's moves one after another, then the rest's
        plan.trajectories, plan.motion_time_s, plan.stats["repair_motion_s"] = repair_trajectories(
            problem, fixed.configurations, rest.trajectories, options["speed"])
    check = validate_plan(problem, plan)
    if not check.valid:
        raise ModelError(f"the plan from the repaired start fails validation: {check.problems[:2]}")
    return plan


def repair_trajectories(problem: Problem, repair: list[np.ndarray], rest: list[dict],
                        speed: float) -> tuple[list[dict], float, float]:
    """Timed trajectories of a plan from a colliding start: the repair phase's single-joint
    moves one after another, then the trajectories of the plan from its end.

    Parameters
    ----------
    problem : Problem
        The problem (its start may collide).
    repair : list of numpy.ndarray
        The repair phase's configurations ``start … c_k`` (``(N, J)`` ints).
    rest : list of dict
        The trajectories (``{joint: (K, 2) [t_s, deg]}`` per robot) of the plan from ``c_k``,
        starting at ``t = 0`` (:func:`~supcoord.problems.trajectory.plan_trajectories`).
    speed : float
        Joint speed in degrees per second.

    Returns
    -------
    tuple
        ``(trajectories, motion_time_s, repair_s)``: per robot ``{joint: (K, 2) [t_s, deg]}``
        (continuous angles), the last time (s) and the repair phase's duration (s), after
        which ``rest`` runs shifted by it.  Step ``i`` of the repair phase takes its turn's
        angle over ``speed`` and nothing else moves meanwhile: the repair phase's motion is
        exactly the configurations' (the rule of :mod:`supcoord.problems.repair_phase`).

    Examples
    --------
    >>> from supcoord.problems.repair_phase import parse_problem_any_start
    >>> p = parse_problem_any_start({"layout": {"kind": "points", "xy": [[0, 0], [20, 0]]},
    ...     "kinematics": {"kind": "rotary", "arm": 12.0, "steps": 8},
    ...     "collision": {"buffer": 1.0}, "start": [0, 4], "target": [4, 0]})
    >>> plan = solve_any_start(p, speed=45.0)
    >>> plan.stats["repair_motion_s"], plan.trajectories[0]["theta"][:2].tolist()
    (1.0, [[0.0, 0.0], [1.0, -45.0]])
    """
    speed = check_speed(speed)
    angles = continuous_angles(problem, repair)
    n, nj = angles.shape[1], angles.shape[2]
    points: list[list[list[tuple[float, float]]]] = [[[(0.0, float(angles[0, p, j]))] for j in range(nj)]
                                                     for p in range(n)]
    t = 0.0
    for i in range(len(repair) - 1):
        turn = angles[i + 1] - angles[i]
        end = t + float(np.abs(turn).max()) / speed
        for p in np.nonzero(np.any(turn != 0, axis=1))[0]:
            for j, pts in enumerate(points[p]):
                if pts[-1][0] < t:
                    pts.append((t, float(angles[i, p, j])))
                pts.append((end, float(angles[i + 1, p, j])))
        t = end
    turns = angles[-1] - np.asarray(wrapped_angles(problem, repair[-1:])[0])  # whole turns of wrapping joints
    out = []
    for p in range(n):
        robot = {}
        for j, name in enumerate(joint_names(problem)):
            head = points[p][j] + ([(t, points[p][j][-1][1])] if points[p][j][-1][0] < t else [])
            tail = np.asarray(rest[p][name], dtype=float) + [t, turns[p, j]]
            robot[name] = np.vstack([np.array(head), tail[tail[:, 0] > t]])
        out.append(robot)
    return out, t + max(float(a[-1, 0]) for robot in rest for a in map(np.asarray, robot.values())), t
