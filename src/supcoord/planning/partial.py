"""Partial plans: the most robots on target when not every robot can reach its target.

Write ``P(O)`` for the problem with the robots of ``O`` *off target*: each ends at its start
(collision-free there) instead of its target; every other robot ends at its target.  After
the planner's certificate of infeasibility (a group ``G`` of robots that cannot all reach
their targets even with every other robot removed), :func:`partial_search` looks for a set
``O`` for which ``P(O)`` has a plan, of least cost: the total ``weight`` of its robots
(``weight`` in PROBLEM.json; every robot 1 without it, so the fewest robots), ties broken
towards robots of lower priority (larger ``priority`` number), then fewer robots.

Every infeasible verdict of ``P(O)`` is kept as a *nogood* ``(G, A)``: ``G`` the certified
group, ``A = O ∩ G`` the members that were off target.  The sub-problem of ``G`` alone in
``P(O')`` is the same whenever ``O' ∩ G = A``, so no such ``O'`` has a plan; a group found
with ``A = ∅`` needs at least one of its members off target in *every* plan.

1. **Greedy.**  ``O := ∅``; while ``P(O)`` has no plan: take its certificate ``(G, A)``
   and put off target the member of ``G ∖ A`` of least weight, then the one whose removal
   breaks the most nogoods that hold for ``O``, then of lowest priority.
2. **Exact** where the conflict components (:func:`.graph_order.conflict_components`)
   holding the certified groups have at most :data:`EXACT_ROBOTS` robots that can move:
   every subset of them, cheapest first, not excluded by a nogood, is tried until one has a
   plan.  Components are independent (no guard joins two), and the greedy answer leaves
   every other component whole and solvable, so the first subset with a plan is of least
   cost: ``optimal``.
3. **Minimal** otherwise: each robot off target is put back in turn (the most valuable
   first) where a nogood does not already exclude it, so that no single robot of the answer
   could have reached its target as well.

What is guaranteed: the plan is a plan of the whole problem (validated); every robot off
target names a certified group it belongs to, or ``"not proven: budget"``; ``optimal`` is
true where the exact search ran, or where the robots off target are as few as disjoint
groups certified with ``A = ∅`` (each needs one of its members off target), and then the
number on target is at least the maximum of the discretised single-move model over plans
whose robots off target end at their starts (step 6 may put more back).
``on_target_bound`` is ``N`` minus the number of such disjoint groups: no plan has more
robots on target, wherever its robots off target end; where ``on_target`` equals it, no
plan of the discretised model has more.

4. **Finer lattice** (where ``solve`` was given one and the whole problem has a certificate
   there too): the robots off target are put back all at once on the finer lattice; each
   certificate found there keeps the robots it names that were being put back off target,
   and the others are tried again, until ``P(O)`` has a plan on the finer lattice (it is the
   answer, planned on that lattice) or no robot is left to put back; then the same on the
   next finer lattice, if ``solve`` gave one (a lattice's certificate holds on that lattice
   only: on the SDSS-V APO wok a robot certified off target on 13 × 7 and 19 × 10 reaches
   its target on 28 × 15).  Before each sub-problem of the whole problem there, each robot
   being put back is tried with its neighbours alone (:func:`sub_problem` of the robot and the
   robots whose reach meets its own, ends as in ``P(O)``): a certificate of that small problem
   is one of ``P(O)`` on that lattice (its group cannot reach those ends even with every other
   robot removed), so the robots it names that were being put back stay off target without
   planning all the others.  A plan there may hold
   more robots on target than the problem's lattice allows, so its answer is not ``optimal``
   and its bound is every robot.

5. **Folded end** (``off_target_end="folded"``): the robots off target are asked to end
   folded (:func:`~supcoord.problems.off_target.folded_ends`: beta at 180°, alpha where it
   starts) instead of at their starts, all at once, else one at a time, each kept folded
   where ``P(O)`` so has a plan; the others end at their starts (rotary robots, which have no
   joint to fold, always).  The set ``O`` and the guarantees above are those of the search
   with every robot off target at its start (not run after step 4's finer lattice).

6. **Parking** (:mod:`.partial_park`; not after step 4's finer lattice): a robot off target
   whose start blocks the target of another robot off target (their segments collide) is
   parked at another position of its lattice that it reaches from its start, free of every
   other robot's end, and that robot is put back on target where ``P(O)`` with those ends
   has a plan; then the next, until a round puts none back (a cascade: the robot put back
   frees its own start).  Such robots end ``"parked"`` at the position named in their entry.
   Nogoods found with a parked member are not kept (they speak of robots at their starts).
   Step 5 then folds only the robots left at their starts.

If the budget ends during the search, the best set found so far is the answer (its robots
named by their certificates, ``optimal`` false); before any set is found, every robot not
yet decided stays at its start with ``"not proven: budget"``.
"""

from __future__ import annotations

import itertools
import time
from dataclasses import dataclass, field, replace
from typing import Callable, Sequence

import numpy as np

from ..errors import BudgetExceeded
from ..problems.off_target import (BUDGET_REASON, ENDS, GroupCertificate, OffTarget, folded_ends, group_reason,
                                   partial_end)
from ..problems.plan import Plan, lower_bound
from ..problems.problem import Problem
from .graph_order import conflict_components
from .partial_park import ParkedRobot, ParkStats, park

__all__ = ["WHEN_INCOMPLETE", "EXACT_ROBOTS", "Nogood", "PartialStats", "PartialResult", "partial_search",
           "reduced_problem", "sub_problem", "neighbourhood"]

#: what ``solve`` answers when no plan puts every robot on target: ``"partial"`` a partial
#: plan (the most robots on target), ``"infeasible"`` the verdict with its certificate
WHEN_INCOMPLETE = ("partial", "infeasible")
#: the exact search runs where the certified groups' conflict components hold at most this
#: many robots that can move (at most ``2**EXACT_ROBOTS`` sub-problems)
EXACT_ROBOTS = 6

#: one attempt: ``P(O)`` → its complete plan, or the certificate ``(members, how)`` of its
#: infeasibility; raises :class:`~supcoord.errors.BudgetExceeded` when the budget ends.  A
#: finer lattice's attempt may carry ``alone(P, members)``: the certificate ``(members, how)``
#: of the robots ``members`` of ``P`` alone on that lattice, or None where they have a plan
Attempt = Callable[[Problem], "Plan | tuple[list[int], str]"]


@dataclass(frozen=True)
class Nogood:
    """No ``P(O)`` with ``O ∩ members == at_start`` has a plan: the robots ``members`` cannot
    all end where ``P(O)`` puts them (``how``: why, in words)."""

    members: frozenset[int]
    at_start: frozenset[int]
    how: str

    def forbids(self, off: frozenset[int]) -> bool:
        """Does this nogood exclude the set ``off`` of robots off target?"""
        return (off & self.members) == self.at_start

    def certificate(self) -> GroupCertificate:
        """The group certificate PLAN.json writes."""
        return GroupCertificate(tuple(sorted(self.members)), self.how, tuple(sorted(self.at_start)))


@dataclass
class PartialStats:
    """What the search did: ``attempts`` (sub-problems solved), ``nogoods`` found, the
    ``method`` that gave the answer (``"greedy"``, ``"minimal"``, ``"exact"``,
    ``"budget"``), the ``candidates`` of the exact search, and ``seconds``."""

    attempts: int = 0
    nogoods: int = 0
    method: str = "greedy"
    candidates: list[int] = field(default_factory=list)
    seconds: float = 0.0

    #: step 4: sub-problems tried on the finer lattice, and the robots it put back on target
    finer_attempts: int = 0
    finer_put_back: list[int] = field(default_factory=list)
    #: step 4: neighbourhoods tried alone on the finer lattice (in ``to_json`` where any was)
    finer_alone: int = 0
    #: step 5: sub-problems tried with robots off target folded (in ``to_json`` where any was)
    fold_attempts: int = 0
    #: step 6: the parking step's sub-problems, robots parked and robots it put back
    #: (:mod:`.partial_park`; in ``to_json`` where it tried any)
    parking: ParkStats = field(default_factory=ParkStats)

    def to_json(self) -> dict:
        """The ``stats["partial"]`` object of PLAN.json."""
        return {"attempts": self.attempts, "nogoods": self.nogoods, "method": self.method,
                "candidates": list(self.candidates), "seconds": self.seconds,
                "finer_attempts": self.finer_attempts, "finer_put_back": list(self.finer_put_back),
                **({"fold_attempts": self.fold_attempts} if self.fold_attempts else {}),
                **({"park_attempts": self.parking.attempts, "park_put_back": list(self.parking.put_back),
                    "parked": [p.to_json() for p in self.parking.parked]} if self.parking.attempts else {}),
                **({"finer_alone": self.finer_alone} if self.finer_alone else {})}


@dataclass
class PartialResult:
    """The answer of :func:`partial_search`: ``plan``, a complete plan of ``P(off)`` (where
    the budget ended before one was found: nothing moves), the ``off_target`` entries,
    ``optimal``, ``on_target`` and ``on_target_bound`` (robots), and the search's ``stats``."""

    plan: Plan
    off_target: tuple[OffTarget, ...]
    optimal: bool
    on_target: int
    on_target_bound: int
    stats: PartialStats


def reduced_problem(problem: Problem, off: frozenset[int], folded: frozenset[int] = frozenset(),
                    parked: dict[int, tuple[int, ...]] | None = None) -> Problem:
    """``P(off)``: ``problem`` with each robot of ``off`` ending at its start, folded if it is
    in ``folded`` (:func:`~supcoord.problems.off_target.folded_ends`), or at ``parked[r]`` (a
    lattice position) if it is parked; the same collision tables and caches
    (:func:`dataclasses.replace`)."""
    parked = parked or {}
    entries = tuple(OffTarget(r, "", None, "parked" if r in parked else "folded" if r in folded else "start",
                              parked.get(r)) for r in sorted(off))
    return replace(problem, target=partial_end(problem.start, problem.target, entries,
                                               folded_ends(problem) if folded else None))


def sub_problem(problem: Problem, members: Sequence[int]) -> Problem:
    """The problem of the robots ``members`` alone (the others removed; obstacles stay), as
    points at their bases; robot ``members[i]`` is robot ``i`` there.

    Parameters
    ----------
    problem : Problem
        The whole problem.
    members : sequence of int
        The robots kept, in the order they take there.

    Returns
    -------
    Problem
        Their problem: the same kinematics, buffers (mm), ends, priorities and held robots;
        its collision tables computed afresh for its own pairs.

    Examples
    --------
    >>> from supcoord.problems.problem import parse_problem
    >>> p = parse_problem({"layout": {"kind": "points", "xy": [[0, 0], [18, 0], [9, 15]]},
    ...                    "kinematics": {"kind": "rotary", "arm": 15.0, "steps": 12},
    ...                    "collision": {"buffer": 2.0}, "start": [5, 5, 9], "target": [11, 0, 1]})
    >>> q = sub_problem(p, [2, 0])
    >>> q.n, q.start.ravel().tolist(), q.bases.tolist()
    (2, [9, 5], [[9.0, 15.0], [0.0, 0.0]])
    """
    idx = [int(p) for p in members]
    new = {p: i for i, p in enumerate(idx)}
    kins = None if problem.robot_kinematics is None else [problem.robot_kinematics[p] for p in idx]
    layout = {"kind": "points", "xy": problem.bases[idx].tolist()}
    return replace(
        problem, layout=layout, bases=problem.bases[idx], buffers=problem.buffers[idx], start=problem.start[idx],
        target=problem.target[idx], priority=[problem.priority[p] for p in idx], robot_kinematics=kins,
        held={new[p]: q for p, q in problem.held.items() if p in new},
        joint_rules={new[p]: r for p, r in problem.joint_rules.items() if p in new},
        extra={}, warnings=[], _tables=None, _pairs=None, _unary=None)


def neighbourhood(problem: Problem, robot: int) -> list[int]:
    """``robot`` and the robots whose reach meets its own (:meth:`Problem.pairs`), in order.

    Parameters
    ----------
    problem : Problem
        The problem.
    robot : int
        Its index.

    Returns
    -------
    list of int
        ``robot`` and its neighbours, ascending.

    Examples
    --------
    >>> from supcoord.problems.problem import parse_problem
    >>> p = parse_problem({"layout": {"kind": "points", "xy": [[0, 0], [18, 0], [100, 0]]},
    ...                    "kinematics": {"kind": "rotary", "arm": 15.0, "steps": 12},
    ...                    "collision": {"buffer": 2.0}, "start": [6, 0, 0], "target": [6, 0, 0]})
    >>> neighbourhood(p, 0), neighbourhood(p, 2)
    ([0, 1], [2])
    """
    pairs = problem.pairs
    near = pairs[np.any(pairs == robot, axis=1)].ravel()
    return sorted({int(robot)} | {int(p) for p in near})


class _Search:
    """The state of one search: the problem, the attempt, the nogoods and the best set."""

    def __init__(self, problem: Problem, attempt: Attempt, progress: Callable | None) -> None:
        self.problem, self.attempt_fn, self.progress = problem, attempt, progress
        n = problem.n
        self.weight = np.ones(n) if problem.weight is None else np.asarray(problem.weight, float)
        self.priority = np.asarray(problem.priority, float)
        moving = np.any(problem.start != problem.target, axis=1)
        self.movable = {p for p in range(n) if moving[p] and p not in problem.held}
        self.nogoods: list[Nogood] = []
        self.chosen: dict[int, Nogood] = {}  # the nogood each greedy choice broke
        self.best: frozenset[int] | None = None
        self.best_plan: Plan | None = None
        self.folded: frozenset[int] = frozenset()  # the robots of ``best`` that end folded (step 5)
        self.parked: dict[int, tuple[int, ...]] = {}  # the robots of ``best`` parked, and where (step 6)
        self.stats = PartialStats()

    def key(self, off: frozenset[int]) -> tuple:
        """The cost of ``off``: total weight, then the priorities kept, then size, then indices."""
        robots = sorted(off)
        return (float(self.weight[robots].sum()), -float(self.priority[robots].sum()), len(robots), robots)

    def add(self, members: list[int], off: frozenset[int], how: str) -> Nogood:
        nogood = Nogood(frozenset(int(m) for m in members), frozenset(off & set(members)), how)
        if nogood not in self.nogoods:
            self.nogoods.append(nogood)
            self.stats.nogoods = len(self.nogoods)
        return nogood

    def excluded(self, off: frozenset[int]) -> bool:
        return any(g.forbids(off) for g in self.nogoods)

    def attempt(self, off: frozenset[int]) -> Nogood | None:
        """Solve ``P(off)``: None (a plan; the best so far if cheaper), or its nogood."""
        reduced = reduced_problem(self.problem, off)
        clash = reduced.collisions(reduced.target)
        if clash:  # a robot at its start collides with a neighbour at its target
            a, b, _ = clash[0]
            return self.add([int(a), int(b)], off, "the robots' end positions collide")
        self.stats.attempts += 1
        if self.progress is not None:
            self.progress("partial", {"off_target": len(off), "attempts": self.stats.attempts})
        found = self.attempt_fn(reduced)
        if isinstance(found, Plan):
            if self.best is None or self.key(off) < self.key(self.best):
                self.best, self.best_plan = off, found
            return None
        return self.add(found[0], off, found[1])

    def breaks(self, r: int, off: frozenset[int]) -> int:
        """How many nogoods that hold for ``off`` putting ``r`` off target breaks."""
        return sum(1 for g in self.nogoods if r in g.members and r not in g.at_start and g.forbids(off))

    def greedy(self, first: Nogood) -> None:
        """Step 1 of the module docstring, from the first certificate ``first``."""
        off: frozenset[int] = frozenset()
        nogood: Nogood | None = first
        while nogood is not None:
            choices = sorted((nogood.members - off) & self.movable,
                             key=lambda r: (self.weight[r], -self.breaks(r, off), -self.priority[r], r))
            if not choices:
                raise RuntimeError(f"internal error: certificate {sorted(nogood.members)} names no robot that "
                                   f"can move")
            self.chosen.setdefault(choices[0], nogood)
            off = off | {choices[0]}
            nogood = self.attempt(off)

    def candidates(self) -> list[int]:
        """The movable robots of the conflict components that hold a nogood's robots."""
        touched = set().union(*(g.members for g in self.nogoods))
        return sorted(p for comp in conflict_components(self.problem) if touched & set(comp)
                      for p in comp if p in self.movable)

    def exact(self, robots: list[int]) -> None:
        """Step 2: every subset of ``robots`` cheaper than the best, cheapest first."""
        assert self.best is not None
        subsets = [frozenset(c) for k in range(len(robots) + 1) for c in itertools.combinations(robots, k)]
        for off in sorted(subsets, key=self.key):
            if self.key(off) >= self.key(self.best):
                return
            if not self.excluded(off) and self.attempt(off) is None:
                return

    def minimal(self) -> None:
        """Step 3: each robot off target put back in turn, the most valuable first."""
        assert self.best is not None
        for r in sorted(self.best, key=lambda r: (-self.weight[r], self.priority[r], r)):
            fewer = self.best - {r}
            if r in self.best and not self.excluded(fewer):
                self.attempt(fewer)

    def finer(self, attempt: Attempt) -> None:
        """Step 4 of the module docstring: the robots off target put back on the finer lattice."""
        assert self.best is not None
        back = set(self.best)
        alone: dict[tuple, frozenset[int]] = {}  # (robot, its neighbours off target) -> robots certified
        while back:
            off = self.best - back
            reduced = reduced_problem(self.problem, off)
            clash = [(int(a), int(b)) for a, b, _ in reduced.collisions(reduced.target)]
            if clash:  # a robot put back ends on a neighbour left at its start
                back -= {r for pair in clash for r in pair}
                continue
            kept = self.certified_alone(attempt, reduced, off, back, alone)
            if kept:  # a neighbourhood alone has no plan: its robots put back stay off target
                back -= kept
                continue
            self.stats.finer_attempts += 1
            if self.progress is not None:
                self.progress("partial", {"off_target": len(off), "attempts": self.stats.attempts,
                                          "finer_attempts": self.stats.finer_attempts})
            found = attempt(reduced)
            if isinstance(found, Plan):
                self.stats.finer_put_back = sorted(int(r) for r in back)
                self.best, self.best_plan = off, found
                return
            kept = back & set(int(m) for m in found[0])
            if not kept:  # the finer lattice's certificate names no robot being put back
                return
            back -= kept

    def certified_alone(self, attempt: Attempt, reduced: Problem, off: frozenset[int], back: set[int],
                        memo: dict[tuple, frozenset[int]]) -> set[int]:
        """The robots of ``back`` that a certificate of one robot's neighbourhood alone on the
        finer lattice (``attempt.alone``, where it has one) names; ``memo`` keeps each
        neighbourhood's answer by its robots off target."""
        alone = getattr(attempt, "alone", None)
        if alone is None:
            return set()
        for r in sorted(back):
            near = neighbourhood(self.problem, r)
            key = (r, off & frozenset(near))
            if key not in memo:
                self.stats.finer_alone += 1
                found = alone(reduced, near)
                memo[key] = frozenset() if found is None else frozenset(int(m) for m in found[0])
            kept = back & memo[key]
            if kept:
                return kept
        return set()

    def fold(self) -> None:
        """Step 5 of the module docstring: the robots off target folded where ``P(best)`` with
        them folded has a plan, all at once, else one at a time (robot order)."""
        assert self.best is not None
        folded = folded_ends(self.problem)
        rules = getattr(self.problem, "joint_rules", None) or {}
        can = sorted(r for r in self.best if r not in rules and r not in self.parked
                     and np.any(folded[r] != self.problem.start[r]))
        for more in [can] + ([[r] for r in can] if len(can) > 1 else []):
            want = self.folded | frozenset(more)
            reduced = reduced_problem(self.problem, self.best, want, self.parked)
            if want == self.folded or reduced.collisions(reduced.target):
                continue
            self.stats.fold_attempts += 1
            found = self.attempt_fn(reduced)
            if isinstance(found, Plan):
                self.folded, self.best_plan = want, found
                if len(more) == len(can):
                    return

    def park(self) -> None:
        """Step 6 of the module docstring (:func:`.partial_park.park`): robots off target
        parked where that puts others back on target; each success becomes the best set."""
        assert self.best is not None

        def attempt(off: frozenset[int], parked: dict[int, tuple[int, ...]]) -> frozenset[int] | None:
            found = self.attempt_fn(reduced_problem(self.problem, off, parked=parked))
            if isinstance(found, Plan):
                self.best, self.parked, self.best_plan = off, dict(parked), found
                return None
            if not set(found[0]) & set(parked):  # a certificate with every member at its start or target
                self.add(found[0], off, found[1])
            return frozenset(int(m) for m in found[0])

        def excluded(off: frozenset[int], parked: frozenset[int]) -> bool:
            return any(g.forbids(off) and not g.members & parked for g in self.nogoods)

        order = sorted(self.best, key=lambda r: (-self.weight[r], self.priority[r], r))
        park(self.problem, self.best, reduced_problem(self.problem, self.best).target, attempt, order, excluded,
             self.stats.parking)

    def reason(self, r: int, off: frozenset[int]) -> OffTarget:
        """Why ``r`` is off target in ``off``: a nogood that excludes putting it back (none of
        its other members parked), else the one it was chosen for, else the budget."""
        back = off - {r}
        parked = set(self.parked) - {r}
        tight = [g for g in self.nogoods if r in g.members and g.forbids(back) and not g.members & parked]
        nogood = tight[0] if tight else self.chosen.get(r)
        if nogood is None:
            return OffTarget(r, BUDGET_REASON, None)
        certificate = nogood.certificate()
        return OffTarget(r, group_reason(certificate), certificate)

    def packing(self) -> int:
        """Disjoint nogoods with no member off target (a lower bound on the robots off target)."""
        used: set[int] = set()
        count = 0
        for g in sorted((g for g in self.nogoods if not g.at_start), key=lambda g: len(g.members)):
            if not g.members & used:
                used |= g.members
                count += 1
        return count


def partial_search(problem: Problem, members: list[int], how: str, attempt: Attempt,
                   progress: Callable | None = None, finer: Attempt | Sequence[Attempt] | None = None,
                   off_target_end: str = "start") -> PartialResult:
    """After a certificate (``members``, ``how``) of ``problem``: the robots to leave off
    target, and a complete plan of the problem with them ending at their starts, or parked
    where that frees other robots' targets (module docstring: the greedy, exact, minimal and
    parking steps, and what is guaranteed).

    Parameters
    ----------
    problem : Problem
        The whole problem (lattice positions; ``weight`` and ``priority`` as read).
    members : list of int
        The certified group of the planner's infeasible verdict on ``problem``.
    how : str
        How that group was certified, in words.
    attempt : callable
        ``attempt(P)`` → a complete :class:`~supcoord.problems.plan.Plan` of ``P`` or the
        certificate ``(members, how)`` of its infeasibility; raises
        :class:`~supcoord.errors.BudgetExceeded` when the budget ends.
    progress : callable, optional
        ``progress("partial", {"off_target", "attempts"})`` before each attempt.
    finer : callable or sequence of callables, optional
        ``finer(P)`` → a complete plan of ``P`` on a finer lattice (its ``lattice`` set) or the
        certificate ``(members, how)`` found there (step 4); several: lattices each finer than
        the last, the next tried where the one before puts no robot back; None: no step 4.
    off_target_end : str, default "start"
        Where the robots off target end (one of :data:`~supcoord.problems.off_target.ENDS`):
        ``"start"``, or ``"folded"`` where a plan reaches it (step 5).

    Returns
    -------
    PartialResult
        The plan of ``P(off)`` (no motion where the budget ended before one was found), the robots
        off target with their reasons, ``optimal``, ``on_target``, ``on_target_bound``.

    Raises
    ------
    ValueError
        ``off_target_end`` is not one of :data:`~supcoord.problems.off_target.ENDS`.
    RuntimeError
        A certificate names no robot that can move (a bug of the planner).

    Examples
    --------
    Three rotary robots packed too tight for all three targets: one stays at its start.

    >>> from supcoord.problems.problem import parse_problem
    >>> from supcoord.planning import solve
    >>> p = parse_problem({"layout": {"kind": "points", "xy": [[0, 0], [18, 0], [9, 15]]},
    ...                    "kinematics": {"kind": "rotary", "arm": 15.0, "steps": 12},
    ...                    "collision": {"buffer": 2.0}, "start": [5, 5, 9], "target": [11, 0, 1]})
    >>> def attempt(q):
    ...     plan = solve(q, when_incomplete="infeasible", improve=0, simultaneous=None)
    ...     return plan if plan.status == "complete" else (plan.stats["certificate"], "search")
    >>> r = partial_search(p, [0, 1, 2], "search", attempt)
    >>> [e.robot for e in r.off_target], r.on_target, r.optimal, r.on_target_bound
    ([0], 2, True, 2)
    """
    if off_target_end not in ENDS:
        raise ValueError(f"off_target_end must be one of {list(ENDS)}, got {off_target_end!r}")
    t0 = time.perf_counter()
    search = _Search(problem, attempt, progress)
    first = search.add(members, frozenset(), how)
    try:
        search.greedy(first)
        robots = search.candidates()
        if len(robots) <= EXACT_ROBOTS:
            search.stats.method, search.stats.candidates = "exact", robots
            search.exact(robots)
        else:
            search.stats.method = "minimal"
            search.minimal()
        budget_ended = False
    except BudgetExceeded:
        budget_ended = True
    levels = () if finer is None else (finer,) if callable(finer) else tuple(finer)
    for level in levels if not budget_ended and search.best else ():
        try:
            search.finer(level)
        except BudgetExceeded:
            break  # the answer found so far stands
        if search.stats.finer_put_back:
            break
    if not budget_ended and search.best and not search.stats.finer_put_back:
        try:
            search.park()
        except BudgetExceeded:
            budget_ended = True  # the robots parked and put back so far stand
    if off_target_end == "folded" and not budget_ended and search.best and not search.stats.finer_put_back:
        try:
            search.fold()
        except BudgetExceeded:
            pass  # the robots folded so far stay folded, the others at their starts
    return _result(search, budget_ended, time.perf_counter() - t0)


def _result(search: _Search, budget_ended: bool, seconds: float) -> PartialResult:
    """The search's answer (module docstring): its best set, or every undecided robot at its start."""
    problem = search.problem
    stats = search.stats
    stats.seconds = seconds
    if search.best is None:  # nothing found: every robot that would move stays at its start
        off = frozenset(search.movable)
        stats.method = "budget"
    else:
        off = search.best
        if budget_ended:
            stats.method = "budget"
    entries = tuple(replace(search.reason(r, off), end="parked" if r in search.parked else
                            "folded" if r in search.folded else "start", at=search.parked.get(r)) for r in sorted(off))
    uniform = problem.weight is None or len(set(problem.weight)) == 1
    bound = problem.n - search.packing()
    on_target = problem.n - len(off)
    refined = bool(stats.finer_put_back)  # planned on the finer lattice: the lattice's bounds do not hold
    optimal = not budget_ended and search.best is not None and not refined and (
        stats.method == "exact" or (uniform and on_target == bound))
    if refined:
        bound = problem.n
    plan = search.best_plan
    if plan is None:
        plan = Plan("complete", [problem.start.copy()], 0, lower_bound(reduced_problem(problem, off)), [], "", {})
    return PartialResult(plan, entries, optimal, on_target, bound, stats)
