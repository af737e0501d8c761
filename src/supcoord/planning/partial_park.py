"""Parking (step 6 of :mod:`.partial`): robots left off target moved out of their neighbours' way.

A robot the partial search leaves off target ends at its start.  Where that start collides
with a neighbour's target, the neighbour is kept off target too, and the neighbour's start
may block a third robot's target: a cascade (on the SDSS-V LCO wok, one robot whose target is
proven unreachable keeps three more off target this way).  Nothing asks an off-target robot
to stay at its start: it may end at any position of its lattice it can reach.  This step
tries, for each robot ``q`` off target whose target collides with robots off target at their
current ends (:func:`blockers`), to *park* each of them at a position of its own lattice that

- lies in the part of its joint space its start reaches, alone among the fixed obstacles,
  its joint rules and the robots held in place (:func:`reachable_cells`, breadth-first over
  single moves);
- collides with none of the ends that stay: the targets of the robots on target (``q``'s
  among them), the positions of held robots, the ends of the other robots off target;

the one that collides with the fewest targets of robots still off target (so that they may
follow), then the nearest to its start (:func:`parking_cells`).  ``q`` is then put back on
target where the whole problem with those ends has a plan (the planner's own attempt: exact
and checked as every other step); where the planner's certificate names a parked robot, the
next positions in that order are tried, up to :data:`PARK_TRIES`.  Each success changes the
ends around it, so the robots off target are tried again, until a round puts none back: the
cascade.

A robot is parked only where that puts a robot back on target; every other robot off target
keeps its end.  What is not searched: parking positions other than the one chosen per
blocker, and robots kept off target by their motion rather than by an end collision.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from ..geometry.segments import segment_distance
from ..problems.plan import Plan
from ..problems.problem import Problem

__all__ = ["PARK_TRIES", "ParkedRobot", "ParkStats", "reachable_cells", "blockers", "parking_cells", "park"]

#: parking positions tried per robot put back: the best of :func:`parking_cells` first, the
#: next where the planner's certificate names a parked robot
PARK_TRIES = 4


@dataclass(frozen=True)
class ParkedRobot:
    """One robot parked off target: ``robot``, its lattice position ``at`` (one index per
    joint), and the robots ``freed`` whose targets its start blocked, put back on target."""

    robot: int
    at: tuple[int, ...]
    freed: tuple[int, ...]

    def to_json(self) -> dict:
        """``{"robot", "at", "freed"}`` of ``stats["partial"]["parked"]``."""
        return {"robot": int(self.robot), "at": [int(v) for v in self.at], "freed": [int(v) for v in self.freed]}


@dataclass
class ParkStats:
    """What parking did: ``attempts`` (whole problems tried), the robots ``parked`` (last
    position of each) and the robots ``put_back`` on target, in order."""

    attempts: int = 0
    parked: list[ParkedRobot] = field(default_factory=list)
    put_back: list[int] = field(default_factory=list)


def reachable_cells(problem: Problem, robot: int) -> tuple[np.ndarray, np.ndarray]:
    """The lattice positions ``robot`` reaches from its start by single moves, alone with the
    fixed obstacles, its joint rules and the robots held in place.

    Parameters
    ----------
    problem : Problem
        The problem.
    robot : int
        Its index.

    Returns
    -------
    cells : ndarray of int, shape (C, J)
        The positions (lattice indices), its start first, in breadth-first order.
    depth : ndarray of int, shape (C,)
        The single moves from its start to each.

    Examples
    --------
    >>> from supcoord.problems.problem import parse_problem
    >>> p = parse_problem({"layout": {"kind": "points", "xy": [[0, 0], [20, 0]]},
    ...                    "kinematics": {"kind": "rotary", "arm": 15.0, "steps": 12},
    ...                    "collision": {"buffer": 2.0}, "start": [6, 0], "target": [6, 0]})
    >>> cells, depth = reachable_cells(p, 0)
    >>> len(cells), cells[:3].ravel().tolist(), int(depth.max())
    (12, [6, 7, 5], 6)
    """
    kin = problem.kin(robot)
    free = ~_held_hits(problem, robot)
    unary = problem.unary().get(robot)
    if unary is not None:
        free &= ~unary[0]
    start = np.asarray(problem.start[robot], dtype=np.int64)
    seen = {kin.flat_position(start): 0}
    order, queue = [start], deque([start])
    while queue:
        q = queue.popleft()
        d = seen[kin.flat_position(q)]
        for joint, delta in kin.moves():
            nxt = kin.step(q, joint, delta)
            if nxt is None or not free[kin.flat_position(nxt)] or kin.flat_position(nxt) in seen:
                continue
            step = np.zeros(len(q), dtype=np.int64)
            step[joint] = delta
            if problem.own_motion_blocked(robot, q, step)[0]:
                continue
            seen[kin.flat_position(nxt)] = d + 1
            order.append(np.asarray(nxt, dtype=np.int64))
            queue.append(nxt)
    cells = np.array(order, dtype=np.int64)
    return cells, np.array([seen[kin.flat_position(c)] for c in cells], dtype=np.int64)


def _neighbours(problem: Problem, robot: int) -> list[int]:
    pairs = problem.pairs
    near = pairs[np.any(pairs == robot, axis=1)].ravel()
    return sorted({int(p) for p in near} - {int(robot)})


def _hits(problem: Problem, robot: int, cells: np.ndarray, other: int, position: np.ndarray) -> np.ndarray:
    """Does ``robot`` at each of ``cells`` collide with ``other`` at ``position``?"""
    mine = problem.kin(robot).segments(cells) + problem.bases[robot]
    theirs = problem.kin(other).segments(np.asarray(position)[None]) + problem.bases[other]
    d = segment_distance(mine[:, 0], mine[:, 1], theirs[:, 0], theirs[:, 1])
    return np.asarray(d < problem.buffers[robot] + problem.buffers[other])


def _held_hits(problem: Problem, robot: int) -> np.ndarray:
    """Over every position of ``robot``'s lattice: does it collide with a robot held in place?"""
    kin = problem.kin(robot)
    cells = kin.all_positions()
    out = np.zeros(len(cells), dtype=bool)
    for other in _neighbours(problem, robot):
        if other in problem.held and other != robot:
            out |= _hits(problem, robot, cells, other, problem.start[other])
    return out


def blockers(problem: Problem, ends: np.ndarray, robot: int, off: frozenset[int]) -> list[int]:
    """The robots that ``robot`` at its target collides with where every robot is at ``ends``
    (``(N, J)``), or ``[-1]`` where one of them is not in ``off`` (it cannot be parked)."""
    out = []
    for other in _neighbours(problem, robot):
        if _hits(problem, robot, problem.target[robot][None], other, ends[other])[0]:
            out.append(other if other in off and other not in problem.held else -1)
    return [-1] if -1 in out else out


def parking_cells(problem: Problem, robot: int, ends: np.ndarray, others_off: frozenset[int],
                  cells: tuple[np.ndarray, np.ndarray]) -> list[tuple[int, ...]]:
    """Where to park ``robot`` (module docstring): its reachable ``cells``
    (:func:`reachable_cells`) other than its target, free of every other robot at ``ends``,
    those colliding with the fewest targets of the robots ``others_off`` first, then the nearest.

    Parameters
    ----------
    problem : Problem
        The problem.
    robot : int
        The robot to park.
    ends : ndarray of int, shape (N, J)
        Where every robot ends (lattice indices).
    others_off : frozenset of int
        The other robots off target, whose targets it had better leave free.
    cells : tuple of ndarray
        ``robot``'s reachable positions and their depths (single moves; :func:`reachable_cells`).

    Returns
    -------
    list of tuple of int
        The lattice positions (one index per joint), best first; empty where every cell collides.

    Examples
    --------
    Robot 0 at its start (position 0, pointing at robot 1) sits on robot 1's target (6,
    pointing back): the nearest positions free of it come first.

    >>> from supcoord.problems.problem import parse_problem
    >>> p = parse_problem({"layout": {"kind": "points", "xy": [[0, 0], [20, 0]]},
    ...                    "kinematics": {"kind": "rotary", "arm": 15.0, "steps": 12},
    ...                    "collision": {"buffer": 2.0}, "start": [0, 0], "target": [5, 6]})
    >>> ends = np.array([[0], [6]])
    >>> parking_cells(p, 0, ends, frozenset(), reachable_cells(p, 0))[:3]
    [(2,), (10,), (3,)]
    """
    positions, depth = cells
    bad = np.all(positions == problem.target[robot], axis=1)  # there it would be on target, not parked
    crowd = np.zeros(len(positions), dtype=np.int64)
    for other in _neighbours(problem, robot):
        bad |= _hits(problem, robot, positions, other, ends[other])
        if other in others_off:
            crowd += _hits(problem, robot, positions, other, problem.target[other])
    ok = np.flatnonzero(~bad)
    return [tuple(int(v) for v in positions[i]) for i in ok[np.lexsort((depth[ok], crowd[ok]))]]


def park(problem: Problem, off: frozenset[int], ends: np.ndarray,
         attempt: Callable[[frozenset, dict], frozenset[int] | None],
         order: list[int], excluded: Callable[[frozenset[int], frozenset[int]], bool], stats: ParkStats) -> None:
    """Step 6 of :mod:`.partial` (module docstring): put robots of ``off`` back on target by
    parking the robots off target whose ends block their targets.

    Parameters
    ----------
    problem : Problem
        The whole problem.
    off : frozenset of int
        The robots off target, each ending at its row of ``ends``.
    ends : ndarray of int, shape (N, J)
        Where every robot ends now (lattice indices).
    attempt : callable
        ``attempt(off, parked)``: None where the problem with the robots of ``off`` off target
        (at their starts, or at ``parked[r]``) has a complete plan (it keeps the plan), else
        the robots its certificate names.
    order : list of int
        The robots of ``off`` in the order to try them (the most valuable first).
    excluded : callable
        ``excluded(off, parked)``: a nogood already shows that those ends have no plan.
    stats : ParkStats
        Updated in place: the robots parked and put back so far stand if ``attempt`` raises.
    """
    parked: dict[int, tuple[int, ...]] = {}
    cells: dict[int, tuple[np.ndarray, np.ndarray]] = {}
    ends = np.array(ends, copy=True)
    tried = {_key(problem, q, ends) for q in off}  # the search before put each back with these ends
    changed = True
    while changed:
        changed = False
        for q in [r for r in order if r in off]:
            moved = _try_one(problem, q, off, ends, parked, cells, tried, attempt, excluded, stats)
            if moved is None:
                continue
            off = off - {q}
            parked = {r: at for r, at in {**parked, **moved}.items() if r in off}
            for r, at in moved.items():
                ends[r] = at
            ends[q] = problem.target[q]
            stats.put_back.append(q)
            freed = {p.robot: p.freed for p in stats.parked}
            stats.parked = [p for p in stats.parked if p.robot not in moved and p.robot in off] + [
                ParkedRobot(r, at, tuple(sorted(set(freed.get(r, ())) | {q}))) for r, at in moved.items()]
            changed = True


def _key(problem: Problem, q: int, ends: np.ndarray) -> tuple:
    """``q`` put back with its neighbours at ``ends``: what an attempt for it depends on."""
    trial = np.array(ends[[q] + _neighbours(problem, q)], copy=True)
    trial[0] = problem.target[q]
    return q, trial.tobytes()


def _try_one(problem: Problem, q: int, off: frozenset[int], ends: np.ndarray, parked: dict, cells: dict,
             tried: set, attempt: Callable, excluded: Callable, stats: ParkStats) -> dict | None:
    """Put ``q`` back on target, parking the robots that block its target (the ``k``-th
    position of :func:`parking_cells` each, ``k < PARK_TRIES``): the positions of the robots it
    parked where the problem so has a plan, else None."""
    rest = off - {q}
    block = blockers(problem, ends, q, rest)
    if -1 in block:
        return None
    for k in range(PARK_TRIES if block else 1):
        trial = np.array(ends, copy=True)
        trial[q] = problem.target[q]
        moved: dict[int, tuple[int, ...]] = {}
        for r in block:
            if r not in cells:
                cells[r] = reachable_cells(problem, r)
            ranked = parking_cells(problem, r, trial, rest - {r}, cells[r])
            if len(ranked) <= k:
                return None
            trial[r] = moved[r] = ranked[k]
        key = _key(problem, q, trial)
        now = {**{r: a for r, a in parked.items() if r in rest}, **moved}
        if key in tried or excluded(rest, frozenset(now)) or problem.collisions(trial):
            continue
        tried.add(key)
        stats.attempts += 1
        named = attempt(rest, now)
        if named is None:
            return moved
        if not named & set(moved):  # the certificate holds wherever these robots park
            return None
    return None
