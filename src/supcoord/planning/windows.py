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

from ..errors import InputError, ModelError
from ..problems.plan import Move
from ..problems.problem import Problem
from .descent import descent
from .graph_order import conflict_components
from .guards import blocked_entry, conflict_graph
from .model import CoordinationModel
from .search import WindowBudget, blockers, search, shortest_moves
from .solve_stats import WindowStats

__all__ = ["solve_local", "apply_moves_from", "LEVELS", "SMALL_COMPONENT", "DESCENTS", "DIRECTIONS", "Local", "LocalResult",
           "Certificate", "WindowOutcome", "WindowObserver"]

#: node caps of one window's bidirectional search, tried in turn over every stuck positioner;
#: the last (None) is uncapped, so a round always ends with a move or a verdict
LEVELS: tuple[int | None, ...] = (20_000, 200_000, 2_000_000, None)
#: components with at most this many configurations are solved by one exact window
#: (shortest single-move plan) instead of descent + windows
SMALL_COMPONENT = 100_000
#: before a window's full search, plans with at most this many members (other than the
#: positioner being finished) away from their place at once are searched, in turn
DISPLACED: tuple[int, ...] = (1, 2)
#: what moves the robots between the windows' rounds: ``"greedy"`` the serialisable greedy
#: descent (:mod:`.descent`), ``"none"`` nothing (windows only)
DESCENTS = ("greedy", "none")
#: the direction the local route solves in: ``"easier"`` the one where the greedy descent leaves
#: fewer robots short (both descents run), ``"forward"`` start → target, ``"reverse"`` target →
#: start read backwards (one descent: for a problem whose easier direction is already known)
DIRECTIONS = ("easier", "forward", "reverse")


@dataclass(frozen=True)
class Certificate:
    """A certificate of infeasibility: the positioners that cannot all reach their targets
    even with every other positioner removed, and ``how`` that was shown (in words)."""

    members: list[int]
    how: str


@dataclass
class WindowOutcome:
    """What the windows around one positioner gave: ``kind`` ``"solved"`` (its ``moves``),
    ``"infeasible"`` (``members`` and ``how`` certify it) or ``"gave_up"`` (its node cap was hit;
    ``region``: the positioners whose positions decided it)."""

    kind: str
    moves: list[Move] = field(default_factory=list)
    members: list[int] = field(default_factory=list)
    how: str = ""
    region: list[int] = field(default_factory=list)


class WindowObserver:
    """Hooks called as the local route works (each does nothing here): subclass it to watch a
    run, as the tests do to see which parts of the route a problem reaches.  The hooks only
    watch: what they return is ignored and the run is the same with or without them."""

    def descended(self, steps: list[list[Move]]) -> None:
        """A greedy descent ended after ``steps`` simultaneous steps (possibly none)."""

    def few_displaced_solved(self, moves: list[Move]) -> None:
        """A window's search with few members displaced at once found ``moves``."""

    def window(self, outcome: WindowOutcome) -> None:
        """The windows grown around one stuck positioner ended with ``outcome``."""

    def whole_component(self, outcome: WindowOutcome) -> None:
        """One exact window over a small conflict component ended with ``outcome``."""


@dataclass(frozen=True)
class Local:
    """Options of the local route (the default; :func:`solve_local`).

    ``order``: the shared model's variable order (``"rcm"`` or ``"hex"``); ``levels``: the
    windows' node caps, tried in turn (BDD nodes; the last must be None, uncapped);
    ``descent``: one of :data:`DESCENTS`; ``direction``: one of :data:`DIRECTIONS`;
    ``small_component``: conflict components of at most this many configurations are solved by
    one exact window; ``observer``: hooks that watch the run (:class:`WindowObserver`).  No
    option changes a verdict; they change the work and the plan found."""

    order: str = "rcm"
    levels: tuple[int | None, ...] = LEVELS
    descent: str = "greedy"
    small_component: int = SMALL_COMPONENT
    observer: WindowObserver | None = None
    direction: str = "easier"

    name = "local"

    def check(self) -> None:
        """Refuse options the route cannot run (:class:`~supcoord.errors.InputError`,
        :class:`~supcoord.errors.ModelError`)."""
        if self.descent not in DESCENTS:
            raise InputError(f"unknown descent {self.descent!r} (use {' or '.join(DESCENTS)})", value=self.descent,
                             where="descent")
        if self.direction not in DIRECTIONS:
            raise InputError(f"unknown direction {self.direction!r} (use {', '.join(DIRECTIONS)})",
                             value=self.direction, where="direction")
        if not self.levels or self.levels[-1] is not None:
            raise ModelError("the last window level must be uncapped (None)", value=self.levels)

    def watcher(self) -> WindowObserver:
        """The observer, or one that does nothing."""
        return self.observer if self.observer is not None else WindowObserver()


@dataclass
class LocalResult:
    """The local route's answer: ``moves`` start → target (None: no plan), or the
    ``certificate`` of infeasibility; ``stats`` the work done."""

    moves: list[Move] | None
    certificate: Certificate | None
    stats: WindowStats


class _Windows:
    """The exact window searches of one run (fresh BDD manager per window of ≥ 2 members,
    its variables in least-cutwidth order; singletons on the shared model)."""

    def __init__(self, problem: Problem, model: CoordinationModel, stats: WindowStats, observer: WindowObserver):
        self.problem = problem
        self.model = model
        self.stats = stats
        self.observer = observer
        self.adj = conflict_graph(problem)

    def _model(self, members: list[int]) -> CoordinationModel:
        if len(members) == 1:
            return self.model
        ctx = self.model.ctx
        wm = CoordinationModel(self.problem, order="cutwidth", members=members, backend=ctx.backend,
                               budget=ctx.budget, progress=ctx.progress, guards_from=self.model)
        return wm

    def _note_nodes(self, wm: CoordinationModel) -> None:
        if wm is not self.model:
            self.stats.window_peak_nodes = max(self.stats.window_peak_nodes, wm.ctx.peak_nodes())

    def grow(self, p: int, c: np.ndarray, done: np.ndarray, comp: list[int], cap: int | None) -> WindowOutcome:
        """Windows around ``p`` grown by blockers (module docstring), each capped at ``cap`` nodes."""
        out = self._grow(p, c, done, comp, cap)
        self.observer.window(out)
        return out

    def _grow(self, p: int, c: np.ndarray, done: np.ndarray, comp: list[int], cap: int | None) -> WindowOutcome:
        problem, stats = self.problem, self.stats
        members = [p]
        while True:
            wm = self._model(members)
            S = wm.system(members, c, init=c, merged=True)
            finished = [q for q in members if q == p or done[q]]
            goal = wm.state(finished, problem.target) & S.invariant  # D(S)
            stats.count_window(len(members))
            bounded = self._few_displaced(wm, S, goal, p, members, c, cap)
            if bounded is not None:
                self._note_nodes(wm)
                return WindowOutcome("solved", moves=bounded, members=members)
            try:
                res = search(S, goal, max_nodes=cap)
            except WindowBudget:
                self._note_nodes(wm)
                stats.windows_abandoned += 1
                return WindowOutcome("gave_up", region=self._region(members))
            if res.distance is not None:
                moves = shortest_moves(S, res, c)
                self._note_nodes(wm)
                stats.count_solved(len(members))
                return WindowOutcome("solved", moves=moves, members=members)
            if len(members) == len(comp):
                return WindowOutcome("infeasible", members=comp,
                                     how="exhaustive symbolic search of their conflict component")
            found = self._blockers(wm, S, res, goal, members, c, cap)
            if isinstance(found, WindowOutcome):
                return found
            self._note_nodes(wm)
            members = sorted(set(members) | set(found))

    def _blockers(self, wm: CoordinationModel, S: Any, res: Any, goal: Any, members: list[int], c: np.ndarray,
                  cap: int | None) -> list[int] | WindowOutcome:
        """The outsiders in the way of one relaxed shortest path (M*'s rule), or every blocker
        of the closed side of ``res`` when the relaxed search is too large; an infeasible
        outcome where the relaxation proves it (points 2 and 3 of the module docstring)."""
        R = wm.system(members, None, init=c, merged=True)
        relaxed = None
        if len(members) > 1:
            self.stats.relaxed_checks += 1
        try:
            relaxed = search(R, goal & R.invariant, max_nodes=cap)
        except WindowBudget:
            pass
        if relaxed is not None and relaxed.distance is None:
            return WindowOutcome("infeasible", members=members,
                                 how="exhaustive symbolic search of this relaxed subproblem")
        if relaxed is not None:
            found = path_blockers(self.problem, shortest_moves(R, relaxed, c), c, set(members))
            if not found:  # the relaxed path would be a path of C(S, c), which has none
                raise ModelError("a relaxed path that no outsider blocks, yet the window failed", value=members)
            return found
        found = blockers(S, res.closed, c)
        if not found:  # point 3 of the module docstring
            return WindowOutcome("infeasible", members=members,
                                 how="their reachable configurations were computed exactly and no other "
                                     "positioner restricts them")
        return found

    def _few_displaced(self, wm: CoordinationModel, S: Any, goal: Any, p: int, members: list[int], c: np.ndarray,
                       cap: int | None) -> list[Move] | None:
        """A plan of ``C(S, c)`` in which at most ``b`` members other than ``p`` are away from
        their place in ``c`` at any time, for ``b`` in :data:`DISPLACED` (None: none found).

        Robots step aside one or two at a time: a search inside that subgraph stays small
        where the whole window's does not (the runs with and without it:
        benchmarks/results/resolution.md).  A failure proves nothing, so the full search
        follows."""
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
                self.stats.windows_few_displaced += 1
                self.stats.count_solved(len(members))
                moves = shortest_moves(R, res, c)
                self.observer.few_displaced_solved(moves)
                return moves
        return None

    def whole(self, comp: list[int], c: np.ndarray) -> WindowOutcome:
        """One exact window over a whole conflict component (point 4 of the module docstring)."""
        wm = self._model(comp)
        S = wm.system(comp, c, init=c, merged=True)
        self.stats.count_window(len(comp))
        res = search(S, S.marked)
        self._note_nodes(wm)
        if res.distance is None:
            out = WindowOutcome("infeasible", members=comp,
                                how="exhaustive symbolic search of their conflict component")
        else:
            out = WindowOutcome("solved", moves=shortest_moves(S, res, c), members=comp)
        self.observer.whole_component(out)
        return out

    def _region(self, members: list[int]) -> list[int]:
        """``S ∪ N(S)``: the positioners whose positions decide the windows' outcome."""
        out = set(members)
        for q in members:
            out.update(r for _, r, _ in self.adj[q])
        return sorted(out)


class _Run:
    """One run of the local route: the current configuration ``c``, the moves so far, and the
    give-ups remembered per positioner (module docstring)."""

    def __init__(self, problem: Problem, model: CoordinationModel, options: Local, stats: WindowStats):
        self.problem = problem
        self.model = model
        self.options = options
        self.stats = stats
        self.observer = options.watcher()
        self.win = _Windows(problem, model, stats, self.observer)
        self.c = problem.start.copy()
        self.moves: list[Move] = []
        self.comps = conflict_components(problem)
        self.comp_of = {p: i for i, k in enumerate(self.comps) for p in k}
        self.by_priority = sorted(range(problem.n), key=lambda p: (problem.priority[p], p))
        self.memo: dict[int, tuple[int, list[int], np.ndarray]] = {}  # p -> (level, region, c[region]) of a give-up

    def apply(self, moves: list[Move]) -> None:
        self.moves.extend(moves)
        self.c = apply_moves_from(self.problem, self.c, moves)

    def small_components(self) -> Certificate | None:
        """Each small conflict component solved by one exact window (a shortest single-move
        plan); the certificate of the first infeasible one."""
        n_positions = self.problem.kinematics.n_positions
        for comp in self.comps:
            if len(comp) > 1 and n_positions ** len(comp) <= self.options.small_component:
                out = self.win.whole(comp, self.c)
                if out.kind == "infeasible":
                    return Certificate(out.members, out.how)
                self.apply(out.moves)
        return None

    def descend(self, descended: tuple[list, np.ndarray] | None) -> None:
        """The greedy descent from ``c`` (``descended``: the one from the start, already run)."""
        if descended is not None and np.array_equal(self.c, self.problem.start):
            steps, self.c = descended[0], descended[1].copy()
        else:
            steps, self.c = descent(self.problem, self.c, check=self.model.ctx.check_budget)
            self.observer.descended(steps)
        self.stats.descent_steps += len(steps)
        for step in steps:
            self.moves.extend(step)
            self.stats.descent_moves += len(step)

    def round(self) -> Certificate | None:
        """Every stuck positioner once at the cheapest level; windows solved one after another
        from the current configuration (no descent in between, so that distant windows stay
        independent and the schedule runs them in parallel).  A success at a dear level ends
        the round at once; the certificate of an infeasible window."""
        done = self.problem.at_target(self.c)
        for li, cap in enumerate(self.options.levels):
            progress = False
            for p in [q for q in self.by_priority if not done[q]]:
                if done[p]:
                    continue  # finished by an earlier window of this round
                m = self.memo.get(p)
                if m is not None and m[0] >= li and np.array_equal(self.c[m[1]], m[2]):
                    continue  # same neighbourhood, same cap: the same give-up
                out = self.win.grow(p, self.c, done, self.comps[self.comp_of[p]], cap)
                if out.kind == "infeasible":
                    return Certificate(out.members, out.how)
                if out.kind == "gave_up":
                    self.memo[p] = (li, out.region, self.c[out.region].copy())
                    continue
                self.apply(out.moves)
                done = self.problem.at_target(self.c)
                progress = True
                if li > 0:
                    break  # an expensive success: back to the descent and the cheap level
            if progress:
                return None
        # cannot happen: the last level is uncapped
        raise ModelError("no window concluded at the uncapped level", value=int((~done).sum()))


def solve_local(problem: Problem, model: CoordinationModel, options: Local = Local(), *,
                descended: tuple[list, np.ndarray] | None = None, stats: WindowStats | None = None) -> LocalResult:
    """The local route: a move sequence start → target, or a certificate of infeasibility.

    Parameters
    ----------
    problem, model : Problem, CoordinationModel
        The problem and its guarded model (the shared manager of the singleton windows).
    options : Local
        The route's options (node caps, descent, small components, observer).
    descended : (steps, end), optional
        The greedy descent from the start, already computed (:func:`.descent.descent`).
    stats : WindowStats, optional
        Filled in as the run goes (so that a budget that runs out still reports the work).

    Returns
    -------
    LocalResult
        ``moves`` (None: infeasible), ``certificate`` (None: a plan) and ``stats``.

    Raises
    ------
    ModelError
        Node caps whose last level is not uncapped.
    BudgetExceeded
        The model's budget ran out.

    Windows never compute ``supcon``: every event is controllable and the specification
    trivial."""
    options.check()
    stats = WindowStats() if stats is None else stats
    run = _Run(problem, model, options, stats)
    stats.begin(len(run.comps), max((len(k) for k in run.comps), default=0), int(problem.at_target(run.c).sum()))
    certificate = run.small_components()
    while certificate is None:
        if options.descent == "greedy":
            run.descend(descended)
            descended = None
        done = problem.at_target(run.c)
        stats.at_target = int(done.sum())
        if done.all():
            return LocalResult(run.moves, None, stats)
        certificate = run.round()
    return LocalResult(None, certificate, stats)


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
