"""``solve``: a coordination problem → a validated plan, a certificate of infeasibility, or "unknown".

The front door over the planner's routes (:mod:`.routes`): the local route (default) or
the monolithic one finds a single-move plan or a certificate; after a certificate, the
finer-lattice route and the simultaneous search may still find a plan.

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
from dataclasses import dataclass, replace
from typing import Any, Callable

import numpy as np

from ..bdd.context import Budget
from ..errors import BudgetExceeded, InputError
from ..problems.consistency import check_problem
from ..problems.off_target import ENDS, partial_summary
from ..problems.plan import Plan, event_name, lower_bound, reversed_moves
from ..problems.problem import Problem
from ..problems.refine import at_lattice, finer_steps
from ..problems.trajectory import check_speed, with_motion
from ..problems.validate import validate_plan
from .improve import improve_plan
from .partial import WHEN_INCOMPLETE, PartialResult, partial_search, reduced_problem, sub_problem
from .move_layers import MoveLayers, move_layers, witness_moves  # noqa: F401  (old import path: positioners.planner)
from .model import CoordinationModel
from .routes import (ROUTES, SIMULTANEOUS_JOINTS, SIMULTANEOUS_NODES, SIMULTANEOUS_TABLE,  # noqa: F401
                     FinerLattice, Local, Monolithic, Route, RouteResult, Simultaneous, SimultaneousResult,
                     WindowResult, route_named, route_runner, simultaneous_search, solve_window)
from .schedule import plan_from_schedule
from .solve_stats import Refined, SolveStats
from .windows import Certificate

__all__ = ["ROUTES", "solve", "solve_window", "WindowResult", "Local", "Monolithic", "Simultaneous", "FinerLattice",
           "VALIDATIONS", "Solved", "WHEN_INCOMPLETE"]

#: what checks a plan before it is returned: ``"independent"`` the independent validator
#: (:func:`~supcoord.problems.validate.validate_plan`), ``"none"`` nothing (for studies that
#: validate apart)
VALIDATIONS = ("independent", "none")


@dataclass(frozen=True)
class _Settings:
    """Everything one ``solve`` was asked, typed (the finer lattice reuses it)."""

    route: Route
    backend: str
    progress: Callable | None
    improve: int | None
    speed: float | None
    simultaneous: Simultaneous | None
    finer: FinerLattice | None
    validation: str


@dataclass
class Solved:
    """A plan and the typed statistics of the run that found it (``plan.stats`` is written
    from ``stats`` by the front door)."""

    plan: Plan
    stats: SolveStats
    #: the single-move certificate behind an ``infeasible`` plan (None otherwise)
    certificate: Certificate | None = None


@dataclass
class _Finer:
    """What the finer-lattice route gave: its ``steps`` (None: no finer lattice within the
    tables' bound), what it ``solved`` (None where the budget ran out, then ``why``)."""

    steps: tuple[int, ...] | None
    solved: Solved | None = None
    why: str = ""


def _reason(problem: Problem, certificate: Certificate, simultaneous: SimultaneousResult) -> str:
    """The reason of an infeasible verdict: the certificate, and the motion model it holds for."""
    ids = ", ".join(str(p) for p in sorted(certificate.members))
    lattice = " × ".join(str(s) for s in problem.kinematics.shape)
    head = (f"positioners {ids} cannot all reach their targets even with every other positioner removed "
            f"({certificate.how}), moving between the {lattice} positions of their joints' lattices (a finer lattice, "
            f"kinematics steps, may hold a plan)")
    if simultaneous.model == "simultaneous":
        return (f"{head}; no plan exists for the whole problem on these lattices, even with several joints and "
                f"positioners moving at once (every joint -1, 0 or +1 position per step: {simultaneous.how})")
    return (f"{head}; no plan exists for the whole problem on these lattices in which one joint moves at a time "
            f"(the single-move model); moves of several joints at once: {simultaneous.how}")


def _finer_lattice(problem: Problem, settings: _Settings, budget: Budget) -> _Finer:
    """The finer-lattice route: ``problem`` on the lattice of
    :func:`~supcoord.problems.refine.finer_steps`, by the same route (no finer lattice again)."""
    steps = finer_steps(problem)
    if steps is None:
        return _Finer(None)
    try:
        fine = at_lattice(problem, steps)
        check_problem(fine)
        return _Finer(steps, _solve(fine, replace(settings, finer=None), budget))
    except BudgetExceeded as exc:  # the coarse certificate still holds: say what is not known
        return _Finer(steps, None, exc.one_line())


def _on_finer_lattice(problem: Problem, verdict: Solved, finer: _Finer) -> Solved:
    """After the single-move certificate ``verdict``, what the finer lattice gave: its plan
    (with ``lattice``) if it has one, else ``verdict`` with what the finer lattice gave (which
    is about that lattice only)."""
    stats, steps = verdict.stats, finer.steps
    if steps is None:
        stats.refined = Refined("not searched", why="no finer lattice within the tables' bound")
        return verdict
    shape = " × ".join(map(str, steps))
    if finer.solved is None:
        stats.refined = Refined("unknown", lattice=tuple(steps), why=finer.why)
        verdict.plan.reason += f"; the finer {shape} lattice was not searched to the end ({finer.why})"
        return verdict
    plan, fine = finer.solved.plan, finer.solved.stats
    if plan.status == "complete":
        plan.lattice = steps
        fine.refined = Refined("complete", lattice=tuple(steps), original=tuple(problem.kinematics.shape),
                               certificate=stats.certificate, seconds=stats.seconds)
        fine.seconds += stats.seconds  # both lattices' work
        return finer.solved
    stats.refined = Refined(plan.status, lattice=tuple(steps), certificate=fine.certificate)
    verdict.plan.reason += f"; on the finer {shape} lattice too: {plan.reason}"
    return verdict


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


def _certified(problem: Problem, settings: _Settings, budget: Budget, stats: SolveStats,
               certificate: Certificate, t0: float) -> Solved:
    """After a single-move ``certificate``: the finer lattice first where the whole problem is
    beyond the simultaneous search (a plan there ends it), then the simultaneous search of the
    certificate's robots (and of the whole problem if they can move), then the verdict."""
    stats.certificate = sorted(int(p) for p in certificate.members)
    lb = lower_bound(problem)
    finer, simultaneous = None, settings.simultaneous
    if (settings.finer is not None and simultaneous is not None
            and problem.n * problem.kinematics.n_joints > simultaneous.joints):
        # the whole problem is beyond the simultaneous search, so the answer is a plan on the
        # finer lattice or the certificate: the finer lattice first, and a plan there ends it
        # without the simultaneous search of the certificate's robots (for the time this
        # saves: benchmarks/results/vs_kaiju_apo_s7.md); smaller problems are searched whole
        stats.certificate_model = "single-move"
        stats.seconds = time.perf_counter() - t0
        finer = _finer_lattice(problem, settings, budget)
        if finer.solved is not None and finer.solved.plan.status == "complete":
            return _on_finer_lattice(problem, Solved(Plan("infeasible", [], None, lb, [], "", {}), stats), finer)
    sim = simultaneous_search(problem, certificate.members, budget, simultaneous) if simultaneous is not None else \
        SimultaneousResult("single-move", "not searched (simultaneous=False)")
    stats.certificate_model = sim.model
    if sim.path is None:
        stats.seconds = time.perf_counter() - t0
        verdict = Solved(Plan("infeasible", [], None, lb, [], _reason(problem, certificate, sim), {}), stats)
        return verdict if finer is None else _on_finer_lattice(problem, verdict, finer)
    stats.plan_model = "simultaneous"  # no single-move plan exists: no single-move events
    return _checked(problem, settings, Plan("complete", sim.path, len(sim.path) - 1, lb, [], "", {}), stats, t0)


def _scheduled(problem: Problem, settings: _Settings, found: RouteResult, stats: SolveStats) -> Plan:
    """The route's single moves scheduled and improved in the direction the windows solved,
    then read backwards if that was the exchanged problem (see :func:`_backwards`)."""
    work, moves, model = found.work, found.moves, found.model
    assert moves is not None
    _phase(settings.progress, "schedule", single_moves=len(moves))
    plan = plan_from_schedule(work, moves)
    stats.schedule = plan.stats["schedule"]
    stats.single_moves = len(moves)
    improve = settings.improve
    if (improve is None or improve > 0) and plan.makespan > plan.lower_bound:
        confs, st = improve_plan(work, plan.configurations, improve, check=lambda: model.ctx.check_budget("improve"))
        stats.makespan_scheduled = plan.makespan
        stats.improve_seconds = st.seconds
        stats.improved_groups = st.improved
        stats.improve_replans = st.replans
        plan = Plan("complete", confs, len(confs) - 1, plan.lower_bound, plan.events, "", {})
    return _backwards(problem, plan, moves) if work is not problem else plan


def _checked(problem: Problem, settings: _Settings, plan: Plan, stats: SolveStats, t0: float) -> Solved:
    """A complete ``plan`` validated (a plan that fails is a bug: never handed out), with its
    joint angles and, given a speed, its trajectories."""
    stats.seconds = time.perf_counter() - t0
    if settings.validation == "independent":
        _phase(settings.progress, "validate", steps=len(plan.configurations) - 1)
        result = validate_plan(problem, plan)
        if not result.valid:
            raise RuntimeError(f"internal error: the planner's plan fails validation: {result.problems[:3]}")
        stats.min_clearance = result.min_clearance
        stats.validate_seconds = time.perf_counter() - t0 - stats.seconds
    if settings.speed is not None:
        _phase(settings.progress, "timing", steps=len(plan.configurations) - 1)
    plan.stats = {}
    plan = with_motion(plan, problem, settings.speed)
    if "timing" in plan.stats:
        stats.timing = plan.stats["timing"]
    return Solved(plan, stats)


def _solve(problem: Problem, settings: _Settings, budget: Budget) -> Solved:
    """``problem`` solved by ``settings.route``, then (after a certificate) by the finer
    lattice and the simultaneous search; the plan scheduled, improved and checked."""
    t0 = time.perf_counter()
    route = settings.route

    def new_model(p: Problem, order: str) -> CoordinationModel:
        return CoordinationModel(p, order=order, backend=settings.backend, budget=budget, progress=settings.progress)

    _phase(settings.progress, "model", positioners=problem.n)  # collision tables and the guarded model
    runner = route_runner(problem, route, new_model)
    stats = SolveStats()
    stats.route, stats.order, stats.positioners = route.name, route.order, problem.n
    try:
        found = runner.run(stats)
    except BudgetExceeded as exc:
        exc.stats.update({k: v for k, v in stats.to_json().items() if k not in exc.stats})
        exc.stats.update(seconds=time.perf_counter() - t0,
                         bdd_nodes=max(runner.model.ctx.peak_nodes(), stats.window_peak_nodes()))
        raise
    stats.bdd_nodes = max(found.model.ctx.peak_nodes(), stats.window_peak_nodes())
    if found.moves is None:
        assert found.certificate is not None
        certificate = found.certificate
        del runner, found  # the route's models and windows: memory the finer lattice needs
        solved = _certified(problem, settings, budget, stats, certificate, t0)
        if solved.plan.status == "infeasible":
            solved.certificate = certificate
        return solved
    return _checked(problem, settings, _scheduled(problem, settings, found, stats), stats, t0)


def _settings(route: Route | str, backend: str, progress: Callable | None, improve: int | None,
              speed: float | None, simultaneous: Simultaneous | None, finer: FinerLattice | None,
              validation: str) -> _Settings:
    """The arguments of :func:`solve` checked and typed (:class:`~supcoord.errors.InputError`)."""
    if isinstance(route, str) or not isinstance(route, (Local, Monolithic)):
        route = route_named(route)  # type: ignore[arg-type]  (refuses anything but a route's name)
    route.check()
    if improve is not None and (isinstance(improve, bool) or not isinstance(improve, (int, np.integer)) or improve < 0):
        raise InputError(f"improve must be a number of re-plannings >= 0 (0: off) or None, got {improve!r}",
                         value=improve, where="improve")
    check_speed(speed)
    if simultaneous is not None and not isinstance(simultaneous, Simultaneous):
        raise InputError(f"simultaneous must be a Simultaneous or None, got {simultaneous!r}", value=simultaneous,
                         where="simultaneous")
    if finer is not None and not isinstance(finer, FinerLattice):
        raise InputError(f"finer must be a FinerLattice or None, got {finer!r}", value=finer, where="finer")
    if validation not in VALIDATIONS:
        raise InputError(f"unknown validation {validation!r} (use {' or '.join(VALIDATIONS)})", value=validation,
                         where="validation")
    return _Settings(route, backend, progress, improve, speed, simultaneous, finer, validation)


def solve(problem: Problem, route: Route | str = "local", *, budget: Budget | None = None,
          backend: str = "auto", progress: Callable | None = None, improve: int | None = None,
          speed: float | None = None, simultaneous: Simultaneous | None = Simultaneous(),
          finer: FinerLattice | None = FinerLattice(), validation: str = "independent",
          when_incomplete: str = "partial", off_target_end: str = "start") -> Plan:
    """Solve ``problem``: a ``complete`` plan (validated), else a ``partial`` one (the most
    robots on target, the others named with a reason) or ``infeasible`` with a reason.

    The route finds a single-move plan or a certificate; the plan is scheduled, shortened and
    validated; after a certificate the finer lattice and the simultaneous model may still hold
    a plan (module docstring).

    Parameters
    ----------
    problem : Problem
        The coordination problem (:func:`~supcoord.problems.problem.parse_problem`).
    route : Local, Monolithic or str, default "local"
        The route and its options (:mod:`.routes`), or a name of :data:`~.routes.ROUTES`.
    budget : Budget, optional
        Limits of the run: live BDD nodes, wall-clock seconds, bytes of memory.
    backend : str, default "auto"
        The BDD backend (``"auto"``, ``"cudd"`` or ``"python"``).
    progress : callable, optional
        ``progress(stage, info)``, told of each phase and fixpoint iteration.
    improve : int, optional
        Space-time re-plannings that may shorten the plan (None: :func:`.improve.default_replans`;
        0: off): work, not seconds, so the same input gives the same plan anywhere.  The
        improvement also stops early when two rounds in a row keep the makespan and take
        few of the robots that set it out of the last steps (:mod:`.improve`).
    speed : float, optional
        Joint speed in degrees per second: the plan gets ``trajectories`` and
        ``motion_time_s`` (:mod:`supcoord.problems.trajectory`).
    simultaneous : Simultaneous or None, default Simultaneous()
        The simultaneous search after a single-move certificate (None: not searched).
    finer : FinerLattice or None, default FinerLattice()
        The finer lattice after a certificate of a problem too large for the simultaneous
        search (None: not tried).
    validation : str, default "independent"
        One of :data:`VALIDATIONS`.
    when_incomplete : str, default "partial"
        What to answer where no plan puts every robot on its target (one of
        :data:`~.partial.WHEN_INCOMPLETE`): ``"partial"`` a plan with the most robots on target
        that the search of :mod:`.partial` finds, each robot off target ending at its start
        (or parked where that frees another robot's target: step 6 of :mod:`.partial`);
        ``"infeasible"`` the verdict and its certificate.
    off_target_end : str, default "start"
        Where a partial plan's robots off target end (one of
        :data:`~supcoord.problems.off_target.ENDS`): ``"start"``, or ``"folded"`` where a plan
        reaches it (:func:`~supcoord.problems.off_target.folded_ends`; step 5 of :mod:`.partial`).

    Returns
    -------
    Plan
        ``"complete"`` (``configurations`` in lattice positions, ``makespan`` in steps,
        ``events`` the single-move witness), ``"partial"`` (the same, plus ``off_target``,
        ``on_target``, ``optimal``, ``on_target_bound`` and ``stats["partial"]``) or
        ``"infeasible"`` (``reason``, ``stats["certificate"]``).  The routes taken: ``stats["route"]``, ``stats["refined"]``
        (the finer lattice), ``stats["plan_model"]`` (``"simultaneous"``: that search's plan).

    Raises
    ------
    InputError
        Not a problem; an unknown route or option value; a negative ``improve``; a bad speed.
    ModelError
        Window node caps whose last level is not uncapped (None).
    BudgetExceeded
        The budget ran out; its ``stats`` carry what was learned so far.

    References
    ----------
    .. [1] M. Macktoobian, D. Gillet, J.-P. Kneib, "Supervisory coordination of robotic fiber
       positioners in multi-object spectrographs", IFAC-PapersOnLine (IFAC LSS 2019),
       doi:10.1016/j.ifacol.2019.06.011 (the seed paper: supcon + CCC on positioners).
    .. [2] W. M. Wonham, K. Cai, *Supervisory Control of Discrete-Event Systems*, Springer, 2019.

    Examples
    --------
    >>> from supcoord.problems.problem import parse_problem
    >>> from supcoord.planning import Monolithic, solve
    >>> p = parse_problem({"layout": {"kind": "points", "xy": [[0, 0], [22.4, 0], [44.8, 0]]},
    ...                    "kinematics": {"kind": "rotary", "arm": 15.0, "steps": 12},
    ...                    "collision": {"buffer": 2.0}, "start": [0, 0, 0], "target": [6, 6, 6]})
    >>> plan = solve(p)
    >>> plan.status, plan.stats["route"], len(plan.events), plan.makespan >= plan.lower_bound
    ('complete', 'local', 18, True)
    >>> solve(p, Monolithic(fixpoint="search"), improve=0).stats["single_moves"]
    18
    >>> q = parse_problem({"layout": {"kind": "points", "xy": [[0, 0], [18, 0], [9, 15]]},
    ...                    "kinematics": {"kind": "rotary", "arm": 15.0, "steps": 12},
    ...                    "collision": {"buffer": 2.0}, "start": [5, 5, 9], "target": [11, 0, 1]})
    >>> plan = solve(q)
    >>> plan.status, plan.on_target, plan.optimal, [e.robot for e in plan.off_target]
    ('partial', 2, True, [0])
    >>> solve(q, when_incomplete="infeasible").status
    'infeasible'
    """
    t0 = time.perf_counter()
    check_problem(problem)  # a Problem, and still consistent (a field replaced after parsing is refused)
    settings = _settings(route, backend, progress, improve, speed, simultaneous, finer, validation)
    if when_incomplete not in WHEN_INCOMPLETE:
        raise InputError(f"when_incomplete must be one of {', '.join(WHEN_INCOMPLETE)}, got {when_incomplete!r}",
                         value=when_incomplete, where="when_incomplete")
    if off_target_end not in ENDS:
        raise InputError(f"off_target_end must be one of {', '.join(ENDS)}, got {off_target_end!r}",
                         value=off_target_end, where="off_target_end")
    budget = budget or Budget()
    solved = _solve(problem, settings, budget)
    solved.plan.stats = solved.stats.to_json()
    if solved.certificate is not None and when_incomplete == "partial":
        return _partial(problem, settings, budget, solved, t0, off_target_end)
    return solved.plan


def _partial(problem: Problem, settings: _Settings, budget: Budget, verdict: Solved, t0: float,
             off_target_end: str = "start") -> Plan:
    """After the infeasible ``verdict``: the partial plan (:func:`.partial.partial_search`,
    each sub-problem by the route alone, single moves, no improvement), its robots off target
    then planned once more as asked (improvement, speed) and the plan validated whole.  Every
    sub-problem is solved in the direction the whole problem's descent found easier (one
    descent each instead of two; the verdict is the same either way)."""
    settings = _known_direction(settings, verdict.stats.direction)
    quick = replace(settings, improve=0, speed=None, simultaneous=None, finer=None, validation="none")

    def attempt(sub: Problem) -> Plan | tuple[list[int], str]:
        solved = _solve(sub, quick, budget)
        if solved.certificate is None:
            return solved.plan
        return sorted(int(m) for m in solved.certificate.members), solved.certificate.how

    assert verdict.certificate is not None
    found = partial_search(problem, list(verdict.certificate.members), verdict.certificate.how, attempt,
                           settings.progress, _finer_attempt(problem, verdict, quick, budget), off_target_end)
    plan, stats = _final_plan(problem, settings, budget, found), dict(verdict.plan.stats)
    stats.update({k: v for k, v in plan.stats.items() if k not in stats})
    stats.update(partial=found.stats.to_json(), seconds=time.perf_counter() - t0)
    if found.off_target:
        out = Plan("partial", plan.configurations, plan.makespan, plan.lower_bound, plan.events,
                   partial_summary(problem.n, found.on_target, found.off_target), stats, plan.angles_deg,
                   plan.trajectories, plan.motion_time_s, plan.lattice, off_target=found.off_target,
                   on_target=found.on_target, optimal=found.optimal, on_target_bound=found.on_target_bound)
    else:  # the search put every robot back (on a finer lattice than the whole problem's searches)
        out = Plan("complete", plan.configurations, plan.makespan, plan.lower_bound, plan.events, "", stats,
                   plan.angles_deg, plan.trajectories, plan.motion_time_s, plan.lattice)
    if settings.validation == "independent":
        _phase(settings.progress, "validate", steps=len(out.configurations) - 1)
        result = validate_plan(problem, out)
        if not result.valid:
            raise RuntimeError(f"internal error: the planner's {out.status} plan fails validation: {result.problems[:3]}")
        out.stats["min_clearance"] = result.min_clearance
    return out


def _finer_attempt(problem: Problem, verdict: Solved, quick: _Settings, budget: Budget) -> tuple[Callable, ...]:
    """Step 4 of :mod:`.partial`: ``P(O)`` solved on the finer lattice where the whole problem
    has a certificate there too (``stats.refined``), then on the lattice finer again
    (:func:`~supcoord.problems.refine.finer_steps` of it, where within the tables' bound);
    none where the finer lattice was not searched."""
    refined = verdict.stats.refined
    if refined is None or refined.status != "infeasible" or not refined.lattice:
        return ()
    first = tuple(refined.lattice)
    again = finer_steps(problem, first)
    return tuple(_lattice_attempt(problem, steps, quick, budget) for steps in (first, again) if steps is not None)


def _lattice_attempt(problem: Problem, steps: tuple[int, ...], quick: _Settings, budget: Budget) -> Callable:
    """``P(O)`` solved on the lattice ``steps`` (the problem built there at the first call);
    its ``alone(P(O), members)`` solves the robots ``members`` of it alone there."""
    built: list[Problem] = []

    def finer(sub: Problem) -> Problem:
        if not built:
            built.append(at_lattice(problem, steps))
        off = frozenset(int(r) for r in np.flatnonzero(np.any(sub.target != problem.target, axis=1)))
        return reduced_problem(built[0], off)

    def attempt(sub: Problem) -> Plan | tuple[list[int], str]:
        solved = _solve(finer(sub), quick, budget)
        if solved.certificate is not None:
            return sorted(int(m) for m in solved.certificate.members), solved.certificate.how
        solved.plan.lattice = tuple(steps)
        return solved.plan

    def alone(sub: Problem, members: list[int]) -> tuple[list[int], str] | None:
        solved = _solve(sub_problem(finer(sub), members), quick, budget)
        if solved.certificate is None:
            return None
        return sorted(members[int(m)] for m in solved.certificate.members), solved.certificate.how

    attempt.alone = alone  # type: ignore[attr-defined]  (step 4's neighbourhoods alone)
    return attempt


def _known_direction(settings: _Settings, direction: str | None) -> _Settings:
    """``settings`` whose local route solves in ``direction`` (``"forward"``/``"reverse"``)
    where it would have chosen the easier one itself."""
    route = settings.route
    if direction is None or not isinstance(route, Local) or route.direction != "easier":
        return settings
    return replace(settings, route=replace(route, direction=direction))


def _final_plan(problem: Problem, settings: _Settings, budget: Budget, found: PartialResult) -> Plan:
    """The plan of the robots off target ``found``: planned again with the improvement and speed
    asked for where the search's own plan had neither (its plan if the budget ends first)."""
    off = frozenset(e.robot for e in found.off_target)
    folded = frozenset(e.robot for e in found.off_target if e.end == "folded")
    parked = {e.robot: e.at for e in found.off_target if e.end == "parked"}  # step 6 of .partial
    lattice = found.plan.lattice  # the finer lattice's plan (step 4 of .partial), else None
    reduced = reduced_problem(problem if lattice is None else at_lattice(problem, lattice), off, folded, parked)
    if found.stats.method != "budget" and (settings.improve != 0 or settings.speed is not None):
        try:
            solved = _solve(reduced, replace(settings, simultaneous=None, finer=None, validation="none"), budget)
            if solved.plan.status == "complete":
                solved.plan.stats = solved.stats.to_json()
                solved.plan.lattice = lattice
                return solved.plan
        except BudgetExceeded:
            pass  # the search's own plan, unimproved
    plan = with_motion(replace(found.plan, stats=dict(found.plan.stats)), reduced, settings.speed)
    return plan


def _phase(progress: Callable | None, stage: str, **info: Any) -> None:
    """Tell ``progress`` that a phase without fixpoint iterations starts (its heartbeat
    then keeps the line alive until the next report)."""
    if progress is not None:
        progress(stage, info)

