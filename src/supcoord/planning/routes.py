"""The planner's routes: the ways :func:`.planner.solve` answers a problem.

Each route is a small class built from its own options (a frozen dataclass) and returns a
typed result:

- :class:`Monolithic` → :class:`MonolithicRoute`: the plain method of the seed paper on the
  whole grid in layout order: ``G`` = every positioner's guarded moves, ``V = supcon(G,
  allevents(G))`` (with only controllable events and a trivial specification, the trim part
  of ``G``), then forcibility layers ``W(0) = Qm``, ``W(k+1) = W(k) ∪ Pre(W(k))`` inside ``V``:
  feasible iff ``q0 ∈ W(∞)``, and ``rank(q0)`` is the length of a shortest single-move plan.
- :class:`~.windows.Local` → :class:`LocalRoute` (the default): the scalable route
  (:mod:`.windows`): a greedy simultaneous descent whose steps are serialisable single
  moves (:mod:`.descent`), then exact symbolic windows around each stuck positioner
  (bidirectional frontier search, :mod:`.search`), grown by the positioners that block a
  relaxed path, with relaxed subproblems as certificates of infeasibility and the whole
  conflict component as the last (exact) window.
- :class:`Simultaneous` → :func:`simultaneous_search`: after a single-move certificate, the
  simultaneous model (several joints and robots moving at once, :mod:`.optimum`).

The finer-lattice route (:class:`FinerLattice`) solves the problem once more on a finer
lattice with the same route; it lives beside the front door (:mod:`.planner`), whose
route functions it calls.

References
----------
- M. Macktoobian, D. Gillet, J.-P. Kneib, IFAC LSS 2019, doi:10.1016/j.ifacol.2019.06.011
  (supcon + CCC on positioners).
- W. M. Wonham, K. Cai, *Supervisory Control of Discrete-Event Systems*, 2019.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace
from typing import Callable, Sequence, Union

import numpy as np

from ..bdd.context import BDD, Budget
from ..des.symbolic_ops import allevents
from ..errors import BudgetExceeded, InputError
from ..problems.plan import Move, exchanged
from ..problems.problem import Problem
from ..synthesis.supcon import supcon
from .descent import descent
from .guards import conflict_graph
from .move_layers import move_layers, witness_moves
from .model import CoordinationModel
from .search import search, shortest_moves
from .solve_stats import DescentShort, MonolithicStats, SolveStats, WindowStats
from .windows import Certificate, Local, WindowObserver, solve_local

__all__ = ["ROUTES", "Route", "Local", "Monolithic", "Simultaneous", "FinerLattice", "RouteResult",
           "SimultaneousResult", "LocalRoute", "MonolithicRoute", "route_named", "route_runner",
           "simultaneous_search", "solve_window", "WindowResult", "FIXPOINTS",
           "SIMULTANEOUS_JOINTS", "SIMULTANEOUS_NODES", "SIMULTANEOUS_TABLE"]

#: the routes' names, as ``supcoord solve --route`` spells them
ROUTES = ("local", "monolithic")
#: how the monolithic route decides its one window: ``"supervisor"`` (the seed paper:
#: ``supcon`` first, then backward layers inside the supervisor) or ``"search"``
#: (bidirectional layers, :func:`.search.search`)
FIXPOINTS = ("supervisor", "search")

#: the simultaneous search after a single-move certificate: at most this many joints in all,
#: this many live BDD nodes, and pair tables of at most this many entries (``3^J·3^J·positions²``); limits of
#: work, not seconds, so the answer is the same on any machine
SIMULTANEOUS_JOINTS = 10
SIMULTANEOUS_NODES = 2_000_000
SIMULTANEOUS_TABLE = 20_000_000


@dataclass(frozen=True)
class Monolithic:
    """Options of the monolithic route: ``order``, the variable order (``"hex"`` or
    ``"rcm"``); ``fixpoint``, one of :data:`FIXPOINTS`."""

    order: str = "hex"
    fixpoint: str = "supervisor"

    name = "monolithic"

    def check(self) -> None:
        """Refuse a fixpoint the route does not know (:class:`~supcoord.errors.InputError`)."""
        if self.fixpoint not in FIXPOINTS:
            raise InputError(f"unknown fixpoint {self.fixpoint!r} (use {' or '.join(FIXPOINTS)})",
                             value=self.fixpoint, where="fixpoint")


Route = Union[Local, Monolithic]


@dataclass(frozen=True)
class Simultaneous:
    """Options of the simultaneous search after a single-move certificate: at most ``joints``
    joints in all, ``nodes`` live BDD nodes (the user's budget may lower it), pair tables of at
    most ``table`` entries."""

    joints: int = SIMULTANEOUS_JOINTS
    nodes: int = SIMULTANEOUS_NODES
    table: int = SIMULTANEOUS_TABLE


@dataclass(frozen=True)
class FinerLattice:
    """The finer-lattice route after a single-move certificate of a problem too large for the
    simultaneous search: the same problem on the lattice of
    :func:`~supcoord.problems.refine.finer_steps` (steps two-thirds as long), solved by the
    same route with the same options (no finer lattice again)."""


def route_named(name: str, order: str | None = None) -> Route:
    """The route called ``name`` (one of :data:`ROUTES`) with its default options and, given,
    the variable ``order``.

    Raises
    ------
    InputError
        An unknown name."""
    if not isinstance(name, str) or name not in ROUTES:
        raise InputError(f"unknown route {name!r} (use {' or '.join(ROUTES)})", value=name)
    route = Local() if name == "local" else Monolithic()
    return route if order is None else replace(route, order=order)


@dataclass
class RouteResult:
    """What a route gave: ``moves`` start → target of ``work`` (None: no plan) or the
    ``certificate``; ``work`` is the problem the moves solve (the problem, or its start and
    target exchanged), ``model`` its guarded model."""

    moves: list[Move] | None
    certificate: Certificate | None
    work: Problem
    model: CoordinationModel


@dataclass
class WindowResult:
    """The outcome of one exact symbolic solve: ``rank`` (None: infeasible), ``moves``, the
    ``members`` count, the ``layers`` count, ``seconds``, and with ``supcon`` the
    supervisor's states and BDD nodes."""

    rank: int | None
    moves: list[Move] = field(default_factory=list)
    members: int = 0
    layers: int = 0
    seconds: float = 0.0
    supervisor_states: int | None = None
    supervisor_nodes: int | None = None

    @property
    def feasible(self) -> bool:
        return self.rank is not None


def solve_window(model: CoordinationModel, members: Sequence[int], frozen: np.ndarray | None,
                 init: np.ndarray, *, fixpoint: str = "search", want_moves: bool = True,
                 goal: BDD | None = None, mode: str = "bidirectional") -> WindowResult:
    """Exact symbolic solve of the members from ``init`` to their targets (or to ``goal``),
    the others frozen at ``frozen`` (or removed when None).

    ``fixpoint="search"``: layers from ``q0`` and from the goal until they meet
    (:func:`.search.search`, ``mode`` "bidirectional" or "forward"), the witness read from
    the shortest-path layers.  ``fixpoint="supervisor"`` (the paper's method): ``V =
    supcon(G, allevents(G))`` first, then backward layers inside ``V`` from the target,
    stopped at ``q0``.  Both give ``rank`` = the length of a shortest move sequence (None:
    unreachable)."""
    ctx = model.ctx
    t0 = time.perf_counter()
    S = model.system(members, frozen, init=init)
    target = S.marked if goal is None else goal & S.invariant
    if fixpoint == "search":
        res = search(S, target, mode=mode)
        rank = res.distance
        moves = shortest_moves(S, res, init) if rank is not None and want_moves else []
        return WindowResult(rank, moves, len(members), len(res.fwd) + len(res.bwd), time.perf_counter() - t0)
    G = S.to_generator()
    sup = supcon(G, allevents(ctx, G))
    states, nodes = sup.stats["states"], sup.stats["bdd_nodes"]
    if sup.supervisor.init == ctx.false:
        return WindowResult(None, [], len(members), 0, time.perf_counter() - t0, states, nodes)
    lay = move_layers(S, target, stop_at=S.init, within=sup.supervisor.invariant)  # until q0 ∈ W(k)
    rank = lay.rank(S.init)
    moves = witness_moves(S, lay, init) if (rank is not None and want_moves) else []
    return WindowResult(rank, moves, len(members), len(lay.layers), time.perf_counter() - t0, states, nodes)


#: builds the guarded model of a problem in a variable order (the front door's budget,
#: backend and progress)
ModelMaker = Callable[[Problem, str], CoordinationModel]


class MonolithicRoute:
    """The monolithic route on ``problem``: one exact window over every positioner."""

    def __init__(self, problem: Problem, options: Monolithic, new_model: ModelMaker):
        self.problem = problem
        self.options = options
        self.model = new_model(problem, options.order)

    def run(self, stats: SolveStats) -> RouteResult:
        problem = self.problem
        everyone = list(range(problem.n))
        res = solve_window(self.model, everyone, None, problem.start, fixpoint=self.options.fixpoint)
        stats.search = own = MonolithicStats()
        own.windows = 1
        own.largest_window = problem.n
        own.single_moves = res.rank
        if res.supervisor_states is not None:
            own.supervisor_states = res.supervisor_states
        if res.feasible:
            return RouteResult(res.moves, None, problem, self.model)
        return RouteResult(None, Certificate(everyone, "exhaustive search"), problem, self.model)


class LocalRoute:
    """The local route on ``problem``: the greedy descent in the easier direction, then the
    exact windows of :func:`.windows.solve_local`."""

    def __init__(self, problem: Problem, options: Local, new_model: ModelMaker):
        self.problem = problem
        self.options = options
        self.new_model = new_model
        self.model = new_model(problem, options.order)

    def run(self, stats: SolveStats) -> RouteResult:
        work, descended = self.problem, None  # what the windows solve: the problem, or target and start exchanged
        if self.options.descent == "greedy" and self.problem.n > 1:
            work, descended = easier_direction(self.problem, self.model, stats, self.options.watcher(),
                                               self.options.direction)
            if work is not self.problem:
                self.model = self.new_model(work, self.options.order)
        stats.search = WindowStats()
        res = solve_local(work, self.model, self.options, descended=descended, stats=stats.search)
        return RouteResult(res.moves, res.certificate, work, self.model)


#: the class that runs each route's options
RUNNERS: dict[type, type] = {Local: LocalRoute, Monolithic: MonolithicRoute}


def route_runner(problem: Problem, route: Route, new_model: ModelMaker) -> LocalRoute | MonolithicRoute:
    """The runner of ``route`` on ``problem`` (its model built)."""
    return RUNNERS[type(route)](problem, route, new_model)


def easier_direction(problem: Problem, model: CoordinationModel, stats: SolveStats,
                     observer: WindowObserver, direction: str = "easier") -> tuple[Problem, tuple[list, np.ndarray]]:
    """``problem``, or the same problem with start and target exchanged when the greedy
    descent leaves strictly fewer robots short of their goal that way.

    The single-move configuration graph is undirected (the guards are symmetrised,
    :mod:`.guards`), so a plan target → start, reversed with every move undone, is a plan
    start → target, and a certificate that the target cannot be reached from the start
    is one that the start cannot be reached from the target: the verdict is the same
    either way.  Only the work differs, as for SDSS-V's robots, which fold into their
    lattice far more easily than they unfold from it (kaiju plans folds and reverses them).
    Returns the problem to solve and its descent (``(steps, end)``), which the windows reuse.
    ``direction`` ``"forward"`` or ``"reverse"`` (:data:`.windows.DIRECTIONS`) runs that
    descent only (``stats.descent_short`` stays None).
    """
    conflict_graph(problem)  # the tables and guards, shared with the exchanged problem
    flipped = exchanged(problem)
    if direction != "easier":
        work = problem if direction == "forward" else flipped
        steps, end = descent(work, work.start, check=model.ctx.check_budget)
        observer.descended(steps)
        stats.direction = direction
        return work, (steps, end)
    short, runs = [], []
    for candidate in (problem, flipped):
        steps, end = descent(candidate, candidate.start, check=model.ctx.check_budget)
        observer.descended(steps)
        short.append(int((~candidate.at_target(end)).sum()))
        runs.append((steps, end))
    stats.descent_short = DescentShort(forward=short[0], reverse=short[1])
    stats.direction = "reverse" if short[1] < short[0] else "forward"
    return (flipped, runs[1]) if short[1] < short[0] else (problem, runs[0])


@dataclass
class SimultaneousResult:
    """The simultaneous search's answer: the ``model`` a certificate holds for
    (``"simultaneous"`` or ``"single-move"``), ``how`` (in words), and a ``path`` of
    configurations when the whole problem has a plan (else None)."""

    model: str
    how: str
    path: list[np.ndarray] | None = None


def simultaneous_search(problem: Problem, members: Sequence[int], budget: Budget,
                        options: Simultaneous = Simultaneous()) -> SimultaneousResult:
    """After a single-move certificate ``members``: search the simultaneous model
    (:func:`.optimum.optimal_makespan`), first the relaxed sub-problem of ``members`` (a
    simultaneous plan of the whole, restricted to them, is one of it: unreachable there
    extends the certificate to simultaneous moves), then, if that has a plan, the whole
    problem (a plan there is returned)."""
    from .optimum import optimal_makespan

    kin = problem.kinematics
    table = (3 ** kin.n_joints) ** 2 * kin.n_positions ** 2
    if table > options.table:
        return SimultaneousResult("single-move", f"not searched (a pair's simultaneous table would hold {table:,} "
                                                 f"entries at this resolution)")
    if len(members) * kin.n_joints > options.joints:
        return SimultaneousResult("single-move", f"not searched ({len(members)} positioners: more than "
                                                 f"{options.joints} joints)")
    remaining = None if budget.timeout is None else max(budget.timeout - budget.elapsed(), 1e-3)
    limit = options.nodes if budget.max_nodes is None else min(options.nodes, budget.max_nodes)
    sub = Budget(max_nodes=limit, timeout=remaining, max_memory=budget.max_memory)
    try:
        relaxed = optimal_makespan(problem, members=members, budget=sub)
        if relaxed.makespan is None:
            return SimultaneousResult("simultaneous", "an exhaustive symbolic search of the same positioners alone")
        if problem.n * kin.n_joints > options.joints:
            return SimultaneousResult(
                "single-move", f"these positioners alone can reach their targets in {relaxed.makespan} steps; the "
                               f"whole problem ({problem.n} positioners, more than {options.joints} joints) was not "
                               f"searched")
        whole = optimal_makespan(problem, budget=sub, want_path=True)
    except BudgetExceeded as exc:
        budget.check("simultaneous search")  # the user's own time or memory ran out: "unknown"
        return SimultaneousResult("single-move", f"the simultaneous search did not finish within its budget ({exc})")
    if whole.makespan is None:
        return SimultaneousResult("simultaneous", "an exhaustive symbolic search of the whole problem")
    return SimultaneousResult("simultaneous", "a plan found by the simultaneous search", whole.path)
