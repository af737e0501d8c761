"""``solve``: a coordination problem → a validated plan, a certificate of infeasibility, or "unknown".

Two routes over the guarded model of :mod:`.model`, both exact with respect to
the discretised single-move model (``docs/formats.md``):

- ``"monolithic"`` — the plain method of the seed paper on the whole grid in layout
  order: ``G`` = every positioner's guarded moves, ``V = supcon(G, allevents(G))`` (with
  only controllable events and a trivial specification, the trim part of ``G``), then
  forcibility layers ``W(0) = Qm``, ``W(k+1) = W(k) ∪ Pre(W(k))`` inside ``V``: feasible iff
  ``q0 ∈ W(∞)``, and ``rank(q0)`` is the length of a shortest single-move plan.
- ``"local"`` (default) — the scalable route (:mod:`.windows`): a greedy
  simultaneous descent whose steps are serialisable single moves
  (:mod:`.descent`), then exact symbolic windows around each stuck
  positioner (bidirectional frontier search, :mod:`.search`), grown by the
  positioners that block a relaxed path, with relaxed subproblems as certificates of
  infeasibility and the whole conflict component as the last (exact) window.

A witness is read forward through the layers (:func:`.layers.witness_moves`, which
interleaves positioners so that few simultaneous steps hold them).  The single moves
are then scheduled into simultaneous steps
(:mod:`.schedule`: the shorter of the timeline and the as-soon-as-possible
schedules), and the schedule is shortened by re-planning the positioners that set
the makespan in space-time (:mod:`.improve`).  Every complete plan is checked
with the independent validator before it is returned.

Where the single-move model has no plan, the simultaneous model (several joints and
robots moving at once, :mod:`.optimum`) is searched before the answer: a plan found
there is returned, and an ``infeasible`` verdict says which model it holds for.

References
----------
- M. Macktoobian, D. Gillet, J.-P. Kneib, IFAC LSS 2019, doi:10.1016/j.ifacol.2019.06.011
  (supcon + CCC on positioners).
- W. M. Wonham, K. Cai, *Supervisory Control of Discrete-Event Systems*, 2019.
"""

from __future__ import annotations

import time
from typing import Any, Callable, Sequence

import numpy as np

from ..bdd.context import BDD, Budget
from ..des.symbolic_ops import allevents
from ..errors import BudgetExceeded, InputError
from ..problems.plan import Move, Plan, event_name, exchanged, lower_bound, reversed_moves
from ..problems.consistency import check_problem
from ..problems.problem import Problem
from ..problems.refine import at_lattice, finer_steps
from ..problems.trajectory import check_speed, with_motion
from ..problems.validate import validate_plan
from ..synthesis.supcon import supcon
from .descent import descent
from .guards import conflict_graph
from .improve import improve_plan
from .layers import move_layers, witness_moves
from .model import CoordinationModel
from .schedule import plan_from_schedule
from .search import search, shortest_moves
from .windows import solve_local

__all__ = ["ROUTES", "solve", "solve_window", "WindowResult"]

ROUTES = ("local", "monolithic")


class WindowResult:
    """The outcome of one exact symbolic solve: ``rank`` (None: infeasible), ``moves``,
    ``layers`` sizes count, ``nodes``."""

    def __init__(self, rank: int | None, moves: list[Move], stats: dict[str, Any]):
        self.rank = rank
        self.moves = moves
        self.stats = stats

    @property
    def feasible(self) -> bool:
        return self.rank is not None


def solve_window(model: CoordinationModel, members: Sequence[int], frozen: np.ndarray | None,
                 init: np.ndarray, *, supervisor: bool = False, want_moves: bool = True,
                 goal: BDD | None = None, mode: str = "bidirectional") -> WindowResult:
    """Exact symbolic solve of the members from ``init`` to their targets (or to ``goal``),
    the others frozen at ``frozen`` (or removed when None).

    Default: layers from ``q0`` and from the goal until they meet
    (:func:`.search.search`, ``mode`` "bidirectional" or "forward"), the
    witness read from the shortest-path layers.  With ``supervisor`` (the paper's
    method): ``V = supcon(G, allevents(G))`` first, then backward layers inside ``V``
    from the target, stopped at ``q0``.  Both give ``rank`` = the length of a shortest
    move sequence (None: unreachable)."""
    ctx = model.ctx
    t0 = time.perf_counter()
    S = model.system(members, frozen, init=init)
    stats: dict[str, Any] = {"members": len(members)}
    target = S.marked if goal is None else goal & S.invariant
    if not supervisor:
        res = search(S, target, mode=mode)
        rank = res.distance
        moves: list[Move] = []
        if rank is not None and want_moves:
            moves = shortest_moves(S, res, init)
        stats.update(rank=rank, layers=len(res.fwd) + len(res.bwd), seconds=time.perf_counter() - t0)
        return WindowResult(rank, moves, stats)
    G = S.to_generator()
    sup = supcon(G, allevents(ctx, G))
    stats["supervisor_states"] = sup.stats["states"]
    stats["supervisor_nodes"] = sup.stats["bdd_nodes"]
    if sup.supervisor.init == ctx.false:
        stats["seconds"] = time.perf_counter() - t0
        return WindowResult(None, [], stats)
    lay = move_layers(S, target, stop_at=S.init, within=sup.supervisor.invariant)  # until q0 ∈ W(k)
    rank = lay.rank(S.init)
    moves = witness_moves(S, lay, init) if (rank is not None and want_moves) else []
    stats.update(rank=rank, layers=len(lay.layers), seconds=time.perf_counter() - t0)
    return WindowResult(rank, moves, stats)


#: the simultaneous search after a single-move certificate: at most this many joints in all
#: (measured: 5 alpha-beta robots of 6×4 positions take ~6 s, 7 exceed 2 million nodes after
#: ~50 s), this many live BDD nodes, and pair tables of at most this many entries
#: (``3^J·3^J·positions²``); limits of work, not seconds, so the answer is the same on any machine
SIMULTANEOUS_JOINTS = 10
SIMULTANEOUS_NODES = 2_000_000
SIMULTANEOUS_TABLE = 20_000_000


def _reason(problem: Problem, members: Sequence[int], how: str, simultaneous: dict[str, Any]) -> str:
    """The reason of an infeasible verdict: the certificate, and the motion model it holds for."""
    ids = ", ".join(str(p) for p in sorted(members))
    lattice = " × ".join(str(s) for s in problem.kinematics.shape)
    head = (f"positioners {ids} cannot all reach their targets even with every other positioner removed ({how}), "
            f"moving between the {lattice} positions of their joints' lattices (a finer lattice, "
            f"kinematics steps, may hold a plan)")
    if simultaneous["model"] == "simultaneous":
        return (f"{head}; no plan exists for the whole problem on these lattices, even with several joints and "
                f"positioners moving at once (every joint -1, 0 or +1 position per step: {simultaneous['how']})")
    return (f"{head}; no plan exists for the whole problem on these lattices in which one joint moves at a time "
            f"(the single-move model); moves of several joints at once: {simultaneous['how']}")


def _simultaneous_search(problem: Problem, members: Sequence[int], budget: Budget) -> dict[str, Any]:
    """After a single-move certificate ``members``: search the simultaneous model
    (:func:`.optimum.optimal_makespan`), first the relaxed sub-problem of ``members`` (a
    simultaneous plan of the whole, restricted to them, is one of it: unreachable there
    extends the certificate to simultaneous moves), then, if that has a plan, the whole
    problem (a plan there is returned).  ``{"model", "how", "path"}``."""
    from .optimum import optimal_makespan

    kin = problem.kinematics
    table = (3 ** kin.n_joints) ** 2 * kin.n_positions ** 2
    if table > SIMULTANEOUS_TABLE:
        return {"model": "single-move", "path": None,
                "how": f"not searched (a pair's simultaneous table would hold {table:,} entries at this resolution)"}
    if len(members) * kin.n_joints > SIMULTANEOUS_JOINTS:
        return {"model": "single-move", "path": None,
                "how": f"not searched ({len(members)} positioners: more than {SIMULTANEOUS_JOINTS} joints)"}
    remaining = None if budget.timeout is None else max(budget.timeout - budget.elapsed(), 1e-3)
    limit = SIMULTANEOUS_NODES if budget.max_nodes is None else min(SIMULTANEOUS_NODES, budget.max_nodes)
    sub = Budget(max_nodes=limit, timeout=remaining, max_memory=budget.max_memory)
    try:
        relaxed = optimal_makespan(problem, members=members, budget=sub)
        if relaxed["makespan"] is None:
            return {"model": "simultaneous", "path": None,
                    "how": "an exhaustive symbolic search of the same positioners alone"}
        if problem.n * kin.n_joints > SIMULTANEOUS_JOINTS:
            return {"model": "single-move", "path": None, "alone": relaxed["makespan"],
                    "how": f"these positioners alone can reach their targets in {relaxed['makespan']} steps; the whole "
                           f"problem ({problem.n} positioners, more than {SIMULTANEOUS_JOINTS} joints) was not searched"}
        whole = optimal_makespan(problem, budget=sub, want_path=True)
    except BudgetExceeded as exc:
        budget.check("simultaneous search")  # the user's own time or memory ran out: "unknown"
        return {"model": "single-move", "path": None,
                "how": f"the simultaneous search did not finish within its budget ({exc})"}
    if whole["makespan"] is None:
        return {"model": "simultaneous", "path": None, "how": "an exhaustive symbolic search of the whole problem"}
    return {"model": "simultaneous", "path": whole["path"], "how": "a plan found by the simultaneous search"}


def _finer_solve(problem: Problem, budget: Budget, options: dict[str, Any]) -> dict[str, Any]:
    """``problem`` solved on the finer lattice of :func:`~supcoord.problems.refine.finer_steps`:
    ``{"steps"}`` (None: no finer lattice within the tables' bound), ``"plan"`` (None where the
    budget ran out, then ``"why"``)."""
    steps = finer_steps(problem)
    if steps is None:
        return {"steps": None}
    try:
        return {"steps": steps, "plan": solve(at_lattice(problem, steps), budget=budget, refine=False, **options)}
    except BudgetExceeded as exc:  # the coarse certificate still holds: say what is not known
        return {"steps": steps, "plan": None, "why": exc.one_line()}


def _on_finer_lattice(problem: Problem, verdict: Plan, finer: dict[str, Any]) -> Plan:
    """After the single-move certificate ``verdict``, what the finer lattice gave
    (:func:`_finer_solve`): its plan (with ``lattice``) if it has one, else ``verdict`` with
    what the finer lattice gave (which is about that lattice only)."""
    steps = finer["steps"]
    if steps is None:
        verdict.stats["refined"] = {"status": "not searched", "why": "no finer lattice within the tables' bound"}
        return verdict
    shape = " × ".join(map(str, steps))
    plan = finer["plan"]
    if plan is None:
        verdict.stats["refined"] = {"lattice": list(steps), "status": "unknown", "why": finer["why"]}
        verdict.reason += f"; the finer {shape} lattice was not searched to the end ({finer['why']})"
        return verdict
    if plan.status == "complete":
        plan.lattice = steps
        plan.stats["refined"] = {"lattice": list(steps), "status": "complete", "from": list(problem.kinematics.shape),
                                 "certificate": verdict.stats["certificate"], "seconds": verdict.stats["seconds"]}
        plan.stats["seconds"] += verdict.stats["seconds"]  # both lattices' work
        return plan
    verdict.stats["refined"] = {"lattice": list(steps), "status": plan.status,
                                "certificate": plan.stats.get("certificate")}
    verdict.reason += f"; on the finer {shape} lattice too: {plan.reason}"
    return verdict


def _easier_direction(problem: Problem, model: CoordinationModel,
                      stats: dict[str, Any]) -> tuple[Problem, tuple[list, np.ndarray]]:
    """``problem``, or the same problem with start and target exchanged when the greedy
    descent leaves strictly fewer robots short of their goal that way.

    The single-move configuration graph is undirected (the guards are symmetrised,
    :mod:`.guards`), so a plan target → start, reversed with every move undone, is a plan
    start → target, and a certificate that the target cannot be reached from the start
    is one that the start cannot be reached from the target: the verdict is the same
    either way.  Only the work differs, as for SDSS-V's robots, which fold into their
    lattice far more easily than they unfold from it (kaiju plans folds and reverses them).
    Returns the problem to solve and its descent (``(steps, end)``), which the windows reuse.
    """
    conflict_graph(problem)  # the tables and guards, shared with the exchanged problem
    flipped = exchanged(problem)
    short, runs = [], []
    for candidate in (problem, flipped):
        steps, end = descent(candidate, candidate.start, check=model.ctx.check_budget)
        short.append(int((~candidate.at_target(end)).sum()))
        runs.append((steps, end))
    stats["descent_short"] = {"forward": short[0], "reverse": short[1]}
    stats["direction"] = "reverse" if short[1] < short[0] else "forward"
    return (flipped, runs[1]) if short[1] < short[0] else (problem, runs[0])


def _backwards(problem: Problem, plan: Plan, moves: list) -> Plan:
    """``plan`` of the exchanged problem (target → start, from ``moves``) read backwards: a
    plan of ``problem``, its single-move events those of ``moves`` reversed, each undone.

    Every step of a plan read backwards is the same merged motion run the other way, so
    the plan stays collision-free (the validator checks it again), and the timing model of
    :mod:`supcoord.problems.trajectory` is symmetric in time.  The schedule and the
    improvement are not: each packs moves as early as the moves before it allow, so the end
    it starts from shapes the plan.  Scheduling and improving in the direction the windows
    solved, then reading the plan backwards, is what kaiju does too (it plans folds and
    reverses them); with the reversed moves scheduled from the folded end instead, the
    unfolds of kaiju's SDSS-V instances (APO and LCO woks, seeds 0-9, 13 x 7 lattice) took
    more motion time than the folds of the same instances on 19 of 20 (APO seed 0: 45.4
    against 38.0 s at 12 deg/s, both 12 steps).
    """
    events = [event_name(problem.kinematics, p, j, d) for p, j, d in reversed_moves(moves)]
    return Plan("complete", plan.configurations[::-1], plan.makespan, lower_bound(problem), events, "", {})


def solve(problem: Problem, *, route: str = "local", order: str | None = None, backend: str = "auto",
          budget: Budget | None = None, progress: Callable | None = None, supervisor: bool | None = None,
          validate: bool = True, greedy: bool = True, levels: tuple[int | None, ...] | None = None,
          improve: int | None = None, speed: float | None = None, simultaneous: bool = True,
          refine: bool = True) -> Plan:
    """Solve ``problem``: a ``complete`` plan (validated), or ``infeasible`` with a reason.

    ``route``: ``"local"`` or ``"monolithic"``; ``order``: variable order ``"rcm"`` or
    ``"hex"`` (defaults: rcm for local, hex for monolithic); ``supervisor``: with the
    monolithic route, compute ``supcon`` before forcibility (default: on); the local
    route ignores it (its windows never need ``supcon``); ``greedy``/``levels``:
    the local route's descent and window node caps (:func:`.windows.solve_local`;
    neither changes a verdict); ``improve``: how many space-time re-plannings may shorten the
    scheduled plan (:mod:`.improve`; None: :func:`.improve.default_replans`, 0: off) — work,
    not seconds, so the same input gives the same plan on any machine and load.  ``events`` is the exact single-move witness, the
    configurations its (improved) simultaneous schedule, ``angles_deg`` their joint angles; ``speed``
    (degrees per second; None: none) adds ``trajectories`` and ``motion_time_s``
    (:mod:`supcoord.problems.trajectory`).  Where the single-move model has no plan,
    ``simultaneous`` (default) searches the simultaneous model before answering (every joint
    −1, 0 or +1 per step, :func:`.optimum.optimal_makespan`): first the certificate's robots
    alone, then the whole problem; a plan found there is returned without ``events`` (no
    single-move sequence exists), and ``stats["certificate_model"]`` says which model an
    ``infeasible`` verdict holds for (the reason says it in words).  A problem of more than
    :data:`SIMULTANEOUS_JOINTS` joints is never searched whole with simultaneous moves: there,
    ``refine`` (default) first solves the same problem once more on a finer lattice
    (:mod:`supcoord.problems.refine`, steps two-thirds as long).  A plan found there is returned
    with its ``lattice``; otherwise the certificate's robots alone are searched with
    simultaneous moves (for the reason), and ``stats["refined"]`` says what the finer lattice
    gave.  A budget that runs out raises
    :class:`BudgetExceeded` whose ``stats`` carry what was learned.
    """
    check_problem(problem)  # a Problem, and still consistent (a field replaced after parsing is refused)
    if not isinstance(route, str) or route not in ROUTES:
        raise InputError(f"unknown route {route!r} (use {' or '.join(ROUTES)})", value=route)
    if improve is not None and (isinstance(improve, bool) or not isinstance(improve, (int, np.integer)) or improve < 0):
        raise InputError(f"improve must be a number of re-plannings >= 0 (0: off) or None, got {improve!r}",
                         value=improve, where="improve")
    check_speed(speed)
    t0 = time.perf_counter()
    budget = budget or Budget()
    order = order or ("rcm" if route == "local" else "hex")
    _phase(progress, "model", positioners=problem.n)  # collision tables and the guarded model
    model = CoordinationModel(problem, order=order, backend=backend, budget=budget, progress=progress)
    stats: dict[str, Any] = {"route": route, "order": order, "positioners": problem.n}
    work, descended = problem, None  # what the windows solve: problem itself, or target and start exchanged
    try:
        if route == "local" and greedy and problem.n > 1:
            work, descended = _easier_direction(problem, model, stats)
            if work is not problem:
                model = CoordinationModel(work, order=order, backend=backend, budget=budget, progress=progress)
        if route == "monolithic":
            everyone = list(range(problem.n))
            res = solve_window(model, everyone, None, problem.start, supervisor=supervisor is None or supervisor)
            stats.update(windows=1, largest_window=problem.n, single_moves=res.rank)
            if "supervisor_states" in res.stats:
                stats["supervisor_states"] = res.stats["supervisor_states"]
            moves, certificate = (res.moves, None) if res.feasible else (None, (everyone, "exhaustive search"))
        else:
            moves, certificate = solve_local(work, model, stats, greedy=greedy, descended=descended,
                                             **({} if levels is None else {"levels": levels}))
    except BudgetExceeded as exc:
        exc.stats.update({k: v for k, v in stats.items() if k not in exc.stats})
        exc.stats.update(seconds=time.perf_counter() - t0,
                         bdd_nodes=max(model.ctx.peak_nodes(), stats.get("window_peak_nodes", 0)))
        raise
    stats["bdd_nodes"] = max(model.ctx.peak_nodes(), stats.get("window_peak_nodes", 0))
    lb = lower_bound(problem)
    if moves is None:
        members, how = certificate
        stats["certificate"] = sorted(int(p) for p in members)
        options = dict(route=route, order=order, backend=backend, progress=progress, supervisor=supervisor,
                       validate=validate, greedy=greedy, levels=levels, improve=improve, speed=speed,
                       simultaneous=simultaneous)
        finer = None
        if refine and simultaneous and problem.n * problem.kinematics.n_joints > SIMULTANEOUS_JOINTS:
            # the whole problem is beyond the simultaneous search, so the answer is a plan on the
            # finer lattice or the certificate: the finer lattice first, and a plan there ends it
            # without the simultaneous search of the certificate's robots (kaiju's APO seed 7:
            # 88 s instead of 158-168 s, benchmarks/results/vs_kaiju_apo_s7.md, with lazy tables
            # at 19 x 10 too); smaller problems are searched whole instead
            del model, descended  # the coarse lattice's windows: memory the finer one needs
            stats["certificate_model"] = "single-move"
            stats["seconds"] = time.perf_counter() - t0
            finer = _finer_solve(problem, budget, options)
            if finer["steps"] is not None and finer["plan"] is not None and finer["plan"].status == "complete":
                return _on_finer_lattice(problem, Plan("infeasible", [], None, lb, [], "", stats), finer)
        sim = _simultaneous_search(problem, members, budget) if simultaneous else \
            {"model": "single-move", "path": None, "how": "not searched (simultaneous=False)"}
        stats["certificate_model"] = sim["model"]
        if sim["path"] is None:
            stats["seconds"] = time.perf_counter() - t0
            verdict = Plan("infeasible", [], None, lb, [], _reason(problem, members, how, sim), stats)
            return verdict if finer is None else _on_finer_lattice(problem, verdict, finer)
        stats["plan_model"] = "simultaneous"  # no single-move plan exists: no single-move events
        plan = Plan("complete", sim["path"], len(sim["path"]) - 1, lb, [], "", {})
    else:
        # scheduled and improved in the direction the windows solved (see _backwards)
        _phase(progress, "schedule", single_moves=len(moves))
        plan = plan_from_schedule(work, moves)
        stats["schedule"] = plan.stats["schedule"]
        stats["single_moves"] = len(moves)
    if moves is not None and (improve is None or improve > 0) and plan.makespan > plan.lower_bound:
        confs, st = improve_plan(work, plan.configurations, improve,
                                 check=lambda: model.ctx.check_budget("improve"))
        stats.update(makespan_scheduled=plan.makespan, improve_seconds=st["seconds"], improved_groups=st["improved"],
                     improve_replans=st["replans"])
        plan = Plan("complete", confs, len(confs) - 1, plan.lower_bound, plan.events, "", {})
    if moves is not None and work is not problem:
        plan = _backwards(problem, plan, moves)
    stats["seconds"] = time.perf_counter() - t0
    if validate:
        _phase(progress, "validate", steps=len(plan.configurations) - 1)
        result = validate_plan(problem, plan)
        if not result["valid"]:  # a bug: never hand out a colliding plan
            raise RuntimeError(f"internal error: the planner's plan fails validation: {result['problems'][:3]}")
        stats["min_clearance"] = result["min_clearance"]
        stats["validate_seconds"] = time.perf_counter() - t0 - stats["seconds"]
    plan.stats = stats
    if speed is not None:
        _phase(progress, "timing", steps=len(plan.configurations) - 1)
    return with_motion(plan, problem, speed)


def _phase(progress: Callable | None, stage: str, **info: Any) -> None:
    """Tell ``progress`` that a phase without fixpoint iterations starts (its heartbeat
    then keeps the line alive until the next report)."""
    if progress is not None:
        progress(stage, info)
