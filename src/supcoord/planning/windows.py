"""The scalable route: greedy descent, then exact symbolic windows grown by blockers.

Write ``C(S, c)`` for the guarded model of :mod:`.model` with members ``S`` moving
from the configuration ``c`` and the others frozen at ``c``, ``R(S, c)`` for the
*relaxed* window (only ``S``, the others removed, from ``c|_S``), and, for an
unfinished positioner ``p``, ``D(S) = {x : x_p = target_p ∧ x_q = target_q for the
members q already at target}``.

Algorithm (``c := start``)::

    for each small conflict component K (≤ SMALL_COMPONENT configurations):
        one exact window C(K, c): a shortest plan of K, or infeasible, certificate K
    loop:
        c := the end of the greedy descent from c               (.descent)
        if every positioner is at target: done
        for cap in LEVELS (node caps; the last is None):
            for each unfinished p, by priority:                 (a "round")
                S := {p}
                loop:                                           (grow)
                    search C(S, c) inside "at most b members other than p away from
                      c" for b = 1, 2 (a subgraph: its path is a plan; none proves nothing)
                    search C(S, c) from c and from D(S)          (.search, bidirectional)
                    if it connects them: append a shortest witness, c := its end; next p
                    if S = K (p's component):  infeasible, certificate K
                    search R(S, c):
                        D(S) unreachable:      infeasible, certificate S
                        else Blk := the outsiders forbidding a move of its shortest path
                    (if R(S, c) is over the cap: Blk := the blockers of the closed side of C(S, c);
                     Blk = ∅:                  infeasible, certificate S)
                    S := S ∪ Blk
                a search over the cap abandons p for this round (no verdict)
            after a success at a cheap level finish the round; at a dearer level go
            back to the descent at once; no success at this cap: next cap

A round's windows are solved one after another from the current configuration with no
descent in between, so distant windows stay independent and the schedule runs them in
parallel.  An abandoned ``p`` is not retried at the same cap while the positions of
``S ∪ N(S)`` (all that its windows read) are unchanged.

Why it is exact (sound and complete, within the budgets):

1. **Every move is a move of the whole.**  The descent's steps are serialisable single
   moves (:mod:`.descent`).  A move allowed in ``C(S, c)`` is guarded by every
   neighbour of the mover (inside ``S`` by the pair guard, outside by the unary guard
   at its actual, frozen position), so a window's witness is a valid move sequence of
   the whole problem from ``c``.  The descent never moves a positioner that is at
   target; a window's success puts ``p`` at target and leaves the finished members at
   target, so the number of positioners at target grows with every round: at most
   ``N`` rounds.  Every configuration ``c`` the algorithm visits is reachable from the
   start by single moves, and the configuration graph is undirected (the tables are
   symmetrised), so *the target is reachable from c iff it is from the start*.
2. **Relaxation certifies infeasibility.**  Removing positioners only removes guard
   conjuncts, so a plan of the whole, restricted to the moves of ``S``, is a plan of the
   relaxed problem of ``S`` from ``start|_S``; and the moves start → c restricted to
   ``S`` lead from ``start|_S`` to ``c|_S`` in it, so (undirected again) ``R(S, c)`` and
   the relaxed problem from the start reach the same configurations.  If ``R(S, c)``
   cannot reach ``D(S) ⊇ {target|_S}``, no plan of the whole exists: ``S`` names the
   positioners involved.  The certificate is checkable from the start alone.
3. **No blocker means the relaxation was computed.**  If no frozen outsider ever
   forbids a move the members allow (``Blk = ∅``, :func:`.search.blockers`),
   the closed side of the search of ``C(S, c)`` (``Reach(c)`` or ``CoReach(D(S))``) is
   closed under the relaxed moves too, so it is a union of connected components of
   ``R(S, c)``'s graph holding one end and not the other; point 2 applies.  When
   ``R(S, c)`` reaches ``D(S)`` but ``C(S, c)`` does not, some outsider forbids a move of
   the relaxed path (otherwise it would be a path of ``C(S, c)``), so ``Blk ≠ ∅`` and
   the window grows.
4. **The last window is the monolithic method.**  ``S = K`` with everyone outside
   ``K`` frozen adds no guard (no conflict pair leaves ``K``): ``C(K, c)`` is the exact
   problem of ``K`` from ``c``; by point 1, ``K`` at target is reachable from ``c`` iff
   from the start, and if even the weaker ``D(K)`` is unreachable, ``K`` is infeasible.
   Components are independent (they share no guard), so the whole problem is
   feasible iff every component is.

5. **Caps only reorder the work.**  An abandoned search gives no verdict; the last
   level is uncapped, so every round ends with a success or a certificate, and by
   point 1 there are at most ``N`` successes.

Windows grow only by positioners that actually block (like M*'s subdimensional
expansion), so most stay a few robots wide; the user's budgets
(``ctx.check_budget`` inside every fixpoint and descent step) bound the rest and end
the run with status "unknown".

References
----------
- M. Fabian et al., local modular and compositional supervisory synthesis (the
  abstraction/relaxation arguments); A. Vahidi et al. 2006.
- G. Wagner, H. Choset, M*: subdimensional expansion for multirobot path planning, 2011.
- C. Sayres et al., kaiju (SDSS-V path planning: greedy and local, not exact — the contrast).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import ModelError
from ..problems.plan import Move
from ..problems.problem import Problem
from .descent import descent
from .graph_order import conflict_components
from .guards import blocked_entry, conflict_graph
from .model import CoordinationModel
from .search import WindowBudget, blockers, search, shortest_moves

__all__ = ["solve_local", "apply_moves_from", "LEVELS"]

#: node caps of one window's bidirectional search, tried in turn over every stuck positioner;
#: the last (None) is uncapped, so a round always ends with a move or a verdict
LEVELS: tuple[int | None, ...] = (20_000, 200_000, 2_000_000, None)
#: components with at most this many configurations are solved by one exact window
#: (shortest single-move plan) instead of descent + windows
SMALL_COMPONENT = 100_000
#: before a window's full search, plans with at most this many members (other than the
#: positioner being finished) away from their place at once are searched, in turn
DISPLACED: tuple[int, ...] = (1, 2)


@dataclass
class _Outcome:
    kind: str  # "solved" | "infeasible" | "gave_up"
    moves: list[Move] = field(default_factory=list)
    members: list[int] = field(default_factory=list)
    how: str = ""
    region: list[int] = field(default_factory=list)


class _Windows:
    """The exact window searches of one run (fresh BDD manager per window of ≥ 2 members,
    its variables in least-cutwidth order; singletons on the shared model)."""

    def __init__(self, problem: Problem, model: CoordinationModel, stats: dict[str, Any]):
        self.problem = problem
        self.model = model
        self.stats = stats
        self.adj = conflict_graph(problem)

    def _model(self, members: list[int]) -> CoordinationModel:
        if len(members) == 1:
            return self.model
        ctx = self.model.ctx
        wm = CoordinationModel(self.problem, order="cutwidth", members=members, backend=ctx.backend,
                               budget=ctx.budget, progress=ctx.progress, guards_from=self.model)
        return wm

    def _count(self, members: list[int]) -> None:
        self.stats["windows"] += 1
        self.stats["largest_window"] = max(self.stats["largest_window"], len(members))

    def _note_nodes(self, wm: CoordinationModel) -> None:
        if wm is not self.model:
            self.stats["window_peak_nodes"] = max(self.stats.get("window_peak_nodes", 0), wm.ctx.peak_nodes())

    def grow(self, p: int, c: np.ndarray, done: np.ndarray, comp: list[int], cap: int | None) -> _Outcome:
        """Windows around ``p`` grown by blockers (module docstring), each capped at ``cap`` nodes."""
        problem, stats = self.problem, self.stats
        members = [p]
        while True:
            wm = self._model(members)
            S = wm.system(members, c, init=c, merged=True)
            finished = [q for q in members if q == p or done[q]]
            goal = wm.state(finished, problem.target) & S.invariant  # D(S)
            self._count(members)
            bounded = self._few_displaced(wm, S, goal, p, members, c, cap)
            if bounded is not None:
                self._note_nodes(wm)
                return _Outcome("solved", moves=bounded, members=members)
            try:
                res = search(S, goal, max_nodes=cap)
            except WindowBudget:
                self._note_nodes(wm)
                stats["windows_abandoned"] += 1
                return _Outcome("gave_up", region=self._region(members))
            if res.distance is not None:
                moves = shortest_moves(S, res, c)
                self._note_nodes(wm)
                key = str(len(members))
                stats["window_sizes"][key] = stats["window_sizes"].get(key, 0) + 1
                return _Outcome("solved", moves=moves, members=members)
            if len(members) == len(comp):
                return _Outcome("infeasible", members=comp, how="exhaustive symbolic search of their conflict component")
            # grow by the outsiders in the way of one relaxed shortest path (M*'s rule),
            # or by every blocker when the relaxed search is too large
            R = wm.system(members, None, init=c, merged=True)
            relaxed = None
            if len(members) > 1:
                stats["relaxed_checks"] += 1
            try:
                relaxed = search(R, goal & R.invariant, max_nodes=cap)
            except WindowBudget:
                pass
            if relaxed is not None and relaxed.distance is None:
                return _Outcome("infeasible", members=members, how="exhaustive symbolic search of this relaxed "
                                                                    "subproblem")
            if relaxed is not None:
                found = path_blockers(problem, shortest_moves(R, relaxed, c), c, set(members))
                if not found:  # the relaxed path would be a path of C(S, c), which has none
                    raise ModelError("a relaxed path that no outsider blocks, yet the window failed", value=members)
            else:
                found = blockers(S, res.closed, c)
                if not found:  # point 3 of the module docstring
                    return _Outcome("infeasible", members=members,
                                    how="their reachable configurations were computed exactly and no other "
                                        "positioner restricts them")
            self._note_nodes(wm)
            members = sorted(set(members) | set(found))

    def _few_displaced(self, wm: CoordinationModel, S: Any, goal: Any, p: int, members: list[int], c: np.ndarray,
                       cap: int | None) -> list[Move] | None:
        """A plan of ``C(S, c)`` in which at most ``b`` members other than ``p`` are away from
        their place in ``c`` at any time, for ``b`` in :data:`DISPLACED` (None: none found).

        Robots step aside one or two at a time: a search inside that subgraph stays small
        where the whole window's does not (the last robot of SDSS-V's APO wok, seed 1,
        fold: 2 s against 60 s for 17 members).  A failure proves nothing, so the full
        search follows."""
        others = [q for q in members if q != p]
        if not others:
            return None
        for bound in DISPLACED:
            if bound >= len(others):
                return None
            R = S.restricted(wm.displaced_at_most(others, c, bound))
            try:
                res = search(R, goal & R.invariant, max_nodes=cap)
            except WindowBudget:
                return None
            if res.distance is not None:
                self.stats["windows_few_displaced"] = self.stats.get("windows_few_displaced", 0) + 1
                key = str(len(members))
                self.stats["window_sizes"][key] = self.stats["window_sizes"].get(key, 0) + 1
                return shortest_moves(R, res, c)
        return None

    def whole(self, comp: list[int], c: np.ndarray) -> _Outcome:
        """One exact window over a whole conflict component (point 4 of the module docstring)."""
        wm = self._model(comp)
        S = wm.system(comp, c, init=c, merged=True)
        self._count(comp)
        res = search(S, S.marked)
        self._note_nodes(wm)
        if res.distance is None:
            return _Outcome("infeasible", members=comp, how="exhaustive symbolic search of their conflict component")
        return _Outcome("solved", moves=shortest_moves(S, res, c), members=comp)

    def _region(self, members: list[int]) -> list[int]:
        """``S ∪ N(S)``: the positioners whose positions decide the windows' outcome."""
        out = set(members)
        for q in members:
            out.update(r for _, r, _ in self.adj[q])
        return sorted(out)


def solve_local(problem: Problem, model: CoordinationModel, stats: dict[str, Any], *, greedy: bool = True,
                levels: tuple[int | None, ...] = LEVELS,
                descended: tuple[list, np.ndarray] | None = None) -> tuple[list[Move] | None, Any]:
    """``(moves, None)`` with a move sequence start → target, or ``(None, (S, how))``.

    ``greedy=False`` skips the descent (windows only); ``levels`` are the window node
    caps (the last must be None); ``descended``: the descent from the start, already
    computed (:func:`.descent.descent`'s ``(steps, end)``).  Windows never compute
    ``supcon``: every event is controllable and the specification trivial."""
    if not levels or levels[-1] is not None:
        raise ModelError("the last window level must be uncapped (None)", value=levels)
    c = problem.start.copy()
    moves: list[Move] = []
    comps = conflict_components(problem)
    comp_of = {p: i for i, k in enumerate(comps) for p in k}
    stats.update(components=len(comps), largest_component=max((len(k) for k in comps), default=0), windows=0,
                 largest_window=0, window_sizes={}, relaxed_checks=0, windows_abandoned=0, descent_steps=0,
                 descent_moves=0, at_target=int(problem.at_target(c).sum()))
    by_priority = sorted(range(problem.n), key=lambda p: (problem.priority[p], p))
    win = _Windows(problem, model, stats)
    for comp in comps:  # small components: one exact window, a shortest single-move plan
        if len(comp) > 1 and problem.kinematics.n_positions ** len(comp) <= SMALL_COMPONENT:
            out = win.whole(comp, c)
            if out.kind == "infeasible":
                return None, (out.members, out.how)
            moves.extend(out.moves)
            c = apply_moves_from(problem, c, out.moves)
    memo: dict[int, tuple[int, list[int], np.ndarray]] = {}  # p -> (level, region, c[region]) of a give-up
    while True:
        if greedy:
            if descended is not None and np.array_equal(c, problem.start):
                steps, c = descended[0], descended[1].copy()
            else:
                steps, c = descent(problem, c, check=model.ctx.check_budget)
            descended = None
            stats["descent_steps"] += len(steps)
            for step in steps:
                moves.extend(step)
                stats["descent_moves"] += len(step)
        done = problem.at_target(c)
        stats["at_target"] = int(done.sum())
        if done.all():
            return moves, None
        # a round: every stuck positioner once at the cheapest level; windows solved one
        # after another from the current configuration (no descent in between, so that
        # distant windows stay independent and the schedule runs them in parallel)
        progress = False
        for li, cap in enumerate(levels):
            for p in [q for q in by_priority if not done[q]]:
                if done[p]:
                    continue  # finished by an earlier window of this round
                m = memo.get(p)
                if m is not None and m[0] >= li and np.array_equal(c[m[1]], m[2]):
                    continue  # same neighbourhood, same cap: the same give-up
                out = win.grow(p, c, done, comps[comp_of[p]], cap)
                if out.kind == "infeasible":
                    return None, (out.members, out.how)
                if out.kind == "gave_up":
                    memo[p] = (li, out.region, c[out.region].copy())
                    continue
                moves.extend(out.moves)
                c = apply_moves_from(problem, c, out.moves)
                done = problem.at_target(c)
                progress = True
                if li > 0:
                    break  # an expensive success: back to the descent and the cheap level
            if progress:
                break
        if not progress:  # cannot happen: the last level is uncapped
            raise ModelError("no window concluded at the uncapped level", value=int((~done).sum()))


def path_blockers(problem: Problem, moves: list[Move], c: np.ndarray, members: set[int]) -> list[int]:
    """The positioners outside ``members``, frozen at ``c``, that forbid some move of the
    member-only sequence ``moves`` from ``c`` (symmetrised swept tables), sorted."""
    kin = problem.kinematics
    adj = conflict_graph(problem)
    idx = {mv: i for i, mv in enumerate(kin.moves())}
    x = c.copy()
    flat_c = kin.flat_index(c)
    found: set[int] = set()
    for q, joint, d in moves:
        i = int(kin.flat_index(x[q]))
        m = idx[(joint, d)]
        for k, r, side in adj[q]:
            if r not in members and r not in found and blocked_entry(problem, k, side, m, i, int(flat_c[r])):
                found.add(r)
        x[q] = kin.step(x[q], joint, d)
    return sorted(found)


def apply_moves_from(problem: Problem, c: np.ndarray, moves: list[Move]) -> np.ndarray:
    """The configuration after ``moves`` from ``c``."""
    kin = problem.kinematics
    out = c.copy()
    for p, joint, d in moves:
        out[p] = kin.step(out[p], joint, d)
    return out
