"""CCC of the coupled model on its settled states: the same verdict, rank and witness, without ``V``.

In the coupled reading (:mod:`.coupled`) the uncontrollable events ``k_i`` and ``e_i``
change only the level ``lvl_i`` and are due exactly when the positions say so: with
``c_i`` the number of neighbours in ``P_i``'s zone, ``k_i`` while ``lvl_i < min(c_i, 2)``
and ``e_i`` while ``lvl_i ≥ 1 ∧ c_i = 0``.  Positions do not change while they fire, so
from any state ``x`` each positioner's levels follow one short deterministic chain and
the chains of different positioners commute: every maximal run of uncontrollable
events from ``x`` has the same length ``D(x) = Σ_i d_i(x)`` and ends in the same
**settled** state ``settle(x)`` (no uncontrollable event defined), where::

    d_i = [lvl_i ≥ 1]                 if c_i = 0     (one e_i)
    d_i = max(min(c_i, 2) − lvl_i, 0)  if c_i ≥ 1     (k_i up to min(c_i, 2))

**Theorem.**  Under preemptive semantics, with target ``T`` (every positioner on its
target, every level 0) where no arm is in another's safety zone, for every state ``x ≠ T``:

- if some uncontrollable event is defined at ``x``: ``rank(x) = D(x) + rank(settle(x))``;
- otherwise: ``rank(x) = min_c (1 + rank(δ(x, c)))`` over the controllable events.

*Proof.*  The second line is preemptive ``Force`` where ``U(x) = ∅``.  For the first,
induction on ``D(x)``: ``rank(x) = 1 + max_u rank(δ(x, u))``, every ``δ(x, u)`` has
``D − 1`` and the same settled state, and the branch that fires a pending ``k`` first
never passes through ``T`` (levels only return to 0 by ``e``), so the maximum is
``D(x) − 1 + rank(settle(x))`` (``∞`` if that is).  ∎

So ``rank(q0)`` is a **shortest path** in the graph of settled states, an edge per
controllable event ``c`` of weight ``1 + D(δ(y, c))``.  And CCC of
``V = supcon(G, allevents(G) ‖ S)`` equals forcibility in ``G``: ``S`` counts every move
and disables nothing, so ``B0 = ∅``; the winning set ``W(∞)`` reaches the target and is
closed under uncontrollable events (at ``T`` because none is defined there), so it lies
inside supcon's greatest fixpoint, where ``V`` keeps every transition between winning
states, and ``V``'s layers are ``G``'s.  The condition on the target is needed: where a
collision event is pending at ``T``, supcon also removes ``T`` when that event leads
to a blocking state, and ``V`` may be empty where ``G`` wins (found by
``tests/paper/test_settled.py``'s random instances); such instances take the monolithic
route.

The settled states are encoded symbolically by :mod:`.settled_graph` (positions and one
"stale level" bit per positioner, one relation per event and weight).  :func:`settled_ccc`
runs A* on sets: buckets ``(g, h)`` expanded in order of ``f = g + h``, with ``h`` the
additive pattern databases of :mod:`.settled_bound` (consistent: an edge lowers ``h`` by
at most its weight), so every state is expanded at its distance and the first ``f`` that
reaches ``T`` is ``dist(T)``; the sweep of that ``f`` is finished, so every state of
every shortest path is expanded.  "Not forcible" is proved when nothing is left to
expand, or, before any BDD is built, by a group of positioners whose relaxation (their
arms alone, :mod:`.settled_bound`) cannot reach their targets: every settled edge is a
move of that relaxation or leaves the group's arms in place, so ``T`` is unreachable.
The verdict alone depends on the positions only: a move is enabled by the positions (the
stale bits change weights, not moves), so ``q0`` is forcible exactly when the target
configuration is reachable from the start with every arm's move free of its neighbours
and allowed by the priorities of the arms in its zone (``tests/paper/test_positions_verdict.py``);
a blocked group asks this of some arms alone.
Between the two, a greedy search on the explicit settled states
(:mod:`.settled_witness`) looks for a forcing string: one that replay accepts proves
"forcible" at once and bounds the A*'s distance from above (the A* still proves the rank).
When it finds none, projection refinement (:mod:`.settled_refine`) over-approximates the
configurations from which the target is reachable on every closed neighbourhood: one that
excludes the start's positions proves "not forcible"; otherwise a greedy search on
configurations that drops every one outside the sets looks for the string, then the
forward refinement inside them and the search again (:func:`refined_answer`); the A* then
keeps only the states inside the last sets (the others cannot reach ``T``, so no shortest
path is lost).
The witness is then read forward as :func:`~supcoord.synthesis.witness` reads it on
``V`` (the controller forces the event of least successor rank, ties by name; the
environment fires its smallest event), testing successors against the states on
shortest paths: it is the same string.

References
----------
- M. Macktoobian, D. Gillet, J.-P. Kneib, IFAC LSS 2019, doi:10.1016/j.ifacol.2019.06.011
  (CCC, the shortest forcible path, the Remark on preemption).
- P. E. Hart, N. J. Nilsson, B. Raphael, A formal basis for the heuristic determination
  of minimum cost paths, IEEE Trans. SSC 4(2), 1968 (admissible, consistent bounds).
- S. Edelkamp, F. Reffel, OBDDs in heuristic search, KI 1998 (symbolic best-first
  search with a BDD-partitioned heuristic).
"""

from __future__ import annotations

import heapq
import time
from dataclasses import dataclass
from typing import Callable

from ..bdd.context import BDD, Context, ThrottledCheck
from ..errors import BudgetExceeded, InputError, ModelError
from ..synthesis.ccc import CCCResult
from .coupled import CoupledModel
from .settled_bound import CERTIFICATE_SIZE, GROUP_SIZE, PatternBound
from .settled_graph import SettledGraph, State, check_settled_route, settle, successor_events, target_in_zone
from .settled_refine import Projections, proj_bdd, refine
from .settled_sets_bound import within_sets
from .settled_witness import GREEDY_LIMIT, GreedyWitness, greedy_witness, position_witness

__all__ = ["RANK_CPU", "SettledGraph", "RankBounds", "settle", "target_in_zone", "settled_ccc", "settled_ccc_naive",
           "refined_answer"]

#: CPU seconds (of the calling process, from the call of :func:`settled_ccc`) after which the
#: search for the rank stops once a checked forcing string has proved "forcible": the answer
#: is then the verdict, the string and :class:`RankBounds`.  At 19 positioners the seeds 0-9
#: answer within a minute of CPU with it (``benchmarks/results/coupled_19_seeds.md``)
RANK_CPU = 50.0


@dataclass(frozen=True)
class RankBounds:
    """``lower ≤ rank(q0) ≤ upper`` (events), the rank not proved: a budget ended the search
    for it after a forcing string, checked by replay, had proved the verdict "forcible".

    Attributes
    ----------
    lower : int
        ``D(q0)`` plus the least ``f`` the A* had not finished sweeping: every settled
        state of smaller ``f`` was expanded and the target was not among them (at least
        ``D(q0) + h(settle(q0))``, the pattern-database bound, when the budget ended
        before the search).
    upper : int
        The length of the witness returned (a forcing string is an upper bound on the
        rank), or less where the A* had already reached the target by a shorter path.
    stopped : str
        The budget's one-line message.

    Examples
    --------
    >>> RankBounds(48, 78, "time budget exceeded in settled")
    RankBounds(lower=48, upper=78, stopped='time budget exceeded in settled')
    """

    lower: int
    upper: int
    stopped: str


@dataclass
class _Search:
    """The A*'s state, filled in as it goes: a budget that stops it leaves what it proved."""

    layers: list[BDD]  # F(g): the expanded settled states at distance exactly g from settle(q0)
    found: int | None  # distance of T from settle(q0) (an upper bound until the search ends), None: unreachable
    buckets: int = 0  # (g, h) buckets expanded
    lower: int = 0  # dist(T) >= lower: every state of f < lower was expanded without meeting T


def _astar(graph: SettledGraph, check: Callable[..., None], search: _Search, allowed: BDD | None = None,
           check_bound: Callable[..., None] | None = None) -> _Search:
    """A* on sets (Edelkamp and Reffel): expand the buckets ``(g, h)`` in order of
    ``f = g + h``, then of ``g``, until every state with ``f ≤ dist(T)`` is expanded (the
    states of all shortest paths, for the witness), or nothing is left to expand.
    ``search``: filled in as the search goes; its ``found`` on entry is the weight of a
    known path to ``T`` (a checked witness), or None.  ``h``'s partition is built as the
    sweeps need it: up to ``f`` (and never above a known distance).
    ``allowed``: the states kept (None: all); every state outside it must have no path to ``T``.
    ``check(stage, **info)`` is called before each bucket, ``check_bound`` (default ``check``)
    while ``h``'s partition is built.

    ``h`` is consistent (:mod:`.settled_bound`: an edge lowers it by at most its weight), so a
    state is first expanded at its distance; ``open_[g]`` holds the states generated at
    tentative distance ``g``, pruned lazily against the expanded ones."""
    ctx = graph.ctx
    false = ctx.false
    cap = search.found  # a known path bounds every f expanded, so every h used
    part = graph.h_partition(lambda: (check_bound or check)("settled bound", cap=cap))
    exact: list[BDD] = []
    at_most: list[BDD] = []  # at_most[b]: h ≤ b
    open_: dict[int, BDD] = {0: graph.start}
    closed, layers = false, search.layers
    layers.append(false)
    best: int | None = 0 if graph.start & graph.target != false else search.found
    f = graph.heuristic(graph.start_raw[0])
    if f is None:  # even the relaxation of the bound cannot reach the target
        search.found = None
        return search
    while True:
        if best is not None and f > best:
            break
        search.lower = f  # dist(T) < f would have put T into a sweep already finished
        exact = part.upto(f if cap is None else min(f, cap))  # a sweep of f reads h ≤ f only
        _unions(at_most, exact)
        for g in list(open_):
            open_[g] &= ~closed
            if open_[g] == false:
                del open_[g]
        if not open_:  # every state reachable from settle(q0) is expanded
            break
        for g in range(f + 1):  # successors of (g, f) land at a larger g: one sweep per f
            x = open_.get(g, false)
            if x == false or f - g >= len(exact):
                continue
            x &= exact[f - g]
            if x == false:
                continue
            check("settled", f=f, g=g, best=best)
            search.buckets += 1
            closed |= x
            open_[g] &= ~x
            while len(layers) <= g:
                layers.append(false)
            layers[g] |= x
            reached = _successors(graph, x, lambda: check("settled", f=f, g=g, best=best))
            fresh = ~closed if allowed is None else allowed & ~closed
            for w, y in reached.items():
                y &= fresh
                if y != false:
                    open_[g + w] = open_.get(g + w, false) | y
                    if y & graph.target != false:
                        best = search.found = g + w if best is None else min(best, g + w)
        for g, x in open_.items():  # consistency: nothing generated below the f just swept
            if g <= f and x & at_most[min(f - g, len(at_most) - 1)] & ~closed != false:
                raise ModelError(f"a state of f <= {f} was left unexpanded: the bound is not consistent", value=f)
        f += 1
    search.found = best
    return search


def _unions(at_most: list[BDD], exact: list[BDD]) -> None:
    """Extend ``at_most`` to ``at_most[b] = exact[0] ∨ … ∨ exact[b]`` for every ``b`` of ``exact``."""
    for b in range(len(at_most), len(exact)):
        at_most.append(exact[b] if b == 0 else at_most[-1] | exact[b])


def _successors(graph: SettledGraph, x: BDD, check: Callable[[], None]) -> dict[int, BDD]:
    """``{w: states one edge of weight w from x}``; ``check()`` before each image (a
    bucket's images take seconds at 19 positioners)."""
    reached: dict[int, BDD] = {}
    for move in graph.moves:
        check()
        reached[move.weight] = reached.get(move.weight, graph.ctx.false) | graph.post(move, x)
    return reached


def _corridor(graph: SettledGraph, search: _Search) -> list[BDD]:
    """``O[r]``: the states of ``F(K − r)`` at distance exactly ``r`` from ``T`` (on a
    shortest path), ``K`` the distance found."""
    ctx, K = graph.ctx, search.found
    false = ctx.false
    O = [graph.target]
    for r in range(1, K + 1):
        u = false
        for move in graph.moves:
            if move.weight <= r and O[r - move.weight] != false:
                u |= graph.pre(move, O[r - move.weight])
        O.append(u & search.layers[K - r])
    return O


def _witness(graph: SettledGraph, O: list[BDD]) -> list[str]:
    """The witness :func:`~supcoord.synthesis.witness` reads from ``V``'s layers."""
    model, false = graph.model, graph.ctx.false
    x, left, path = graph.start_raw, len(O) - 1 + graph.start_cost, []
    while x != graph.target_raw:
        pending = successor_events(model, x, controllable=False)
        if pending:  # the environment fires its smallest event (every one has rank − 1)
            name, x = pending[0]
            path.append(name)
            left -= 1
            continue
        for name, z in successor_events(model, x, controllable=True):  # least successor rank (left − 1), then name
            levels, cost = settle(model, *z)
            r = left - 1 - cost
            if r >= 0 and graph.code((z[0], levels)) & O[r] != false:
                break
        else:
            raise ModelError("no controllable event continues a shortest path: corrupted layers", value=left)
        path.append(name)
        x, left = z, left - 1
    return path


def _blocked_text(group: list[int]) -> str:
    names = [f"P{i + 1}" for i in group]
    who = names[0] if len(names) == 1 else ", ".join(names[:-1]) + " and " + names[-1]
    return (f"{who} cannot reach their targets from their starts even with every other arm removed (each move "
            f"free of their swept arms, a positioner with one of them in its safety zone turning only the way "
            f"its priority allows); every move of the coupled model is such a move")


def _refined_text(proj: Projections) -> str:
    names = ", ".join(f"P{i + 1}" for i in proj.excluded)
    what, goal = ("reachable from the start", "the target's") if proj.forward else \
        ("from which the target can be reached", "the start's")
    return (f"the positions of {names} {what} (over-approximated by projection refinement over the "
            f"neighbourhood of every positioner, {proj.rounds} sweeps) exclude {goal}: "
            f"no sequence of moves of the coupled model joins the start to the target")


def refined_answer(model: CoupledModel, bound: PatternBound,
                   ctx: Context | None = None) -> tuple[Projections, GreedyWitness | None]:
    """The backward refinement of :mod:`.settled_refine`, a certificate if it excludes the
    start; else a search on configurations pruned by it
    (:func:`~.settled_witness.position_witness`); else the forward refinement inside it
    (the configurations on a path from the start to the target) and the search pruned by
    that.

    Parameters
    ----------
    model : CoupledModel
        The instance (its target with no arm in another's zone).
    bound : PatternBound
        The bound ordering the searches.
    ctx : Context, optional
        Its budget is checked (stage ``"settled refinement"``, at most every 0.2 s) before each
        group's recomputation and while the configurations are searched.

    Returns
    -------
    tuple of Projections and GreedyWitness or None
        The last sets (``excluded``: a certificate of "not forcible") and the forcing
        string found, checked by replay, if any (neither proves anything otherwise).

    Examples
    --------
    >>> from supcoord.paper.run import coupled_instance
    >>> model = CoupledModel(coupled_instance(3, 8, 0))
    >>> proj, found = refined_answer(model, PatternBound(model))
    >>> proj.excluded, found.length
    (None, 8)
    """
    check = None if ctx is None else _ticker(ThrottledCheck(ctx), "settled refinement")
    back = refine(model, forward=False, check=check)
    if back.excluded is not None:
        return back, None
    found = position_witness(model, bound, back.admits, check=check)
    if found is not None:
        return back, found
    both = refine(model, forward=True, within=back, check=check)
    if both.excluded is not None:
        return both, None
    return both, position_witness(model, bound, both.admits, check=check)


def _ticker(check: ThrottledCheck, stage: str) -> Callable[[], None]:
    """``check(stage)`` as a call without arguments, for the explicit searches."""
    return lambda: check(stage)


def settled_ccc(model: CoupledModel, ctx: Context | None = None, *, order: str = "auto",
                group_size: int = GROUP_SIZE, certificate_size: int = CERTIFICATE_SIZE,
                greedy_limit: int = GREEDY_LIMIT, rank_cpu: float | None = RANK_CPU) -> CCCResult:
    """CCC of the coupled model under preemptive semantics on its settled states (module
    docstring): the verdict, ``rank(q0)`` and the witness that :func:`~supcoord.synthesis.ccc`
    returns on ``V``.  ``stats``: seconds (``build``, ``search``, ``witness``), the bounds
    tried, the distance found, the largest layer (BDD nodes), the number of relations.

    Before any BDD is built, a group of positioners whose relaxation cannot reach its
    targets (:meth:`~.settled_bound.PatternBound.blocked_group`, groups of up to
    ``certificate_size`` around each positioner) answers "not forcible" at once, with
    ``stats["certificate"]`` and ``stats["blocked_group"]`` (1-based) saying which.
    Otherwise a greedy search (:func:`~.settled_witness.greedy_witness`, at most
    ``greedy_limit`` settled states) looks for a forcing string, checked by replay: when it
    finds one, "forcible" is proved before the A* starts, ``stats["upper_bound"]`` is its
    length (``rank(q0)`` is at most that) and the context's progress callback hears of it
    (stage ``"settled witness"``); the A* then proves the rank and reads the witness. Each
    later report (relations and A*) carries ``forcible``, ``upper_bound`` and ``witness``,
    and a budget that ends the search for the rank returns the proved verdict with that
    string, ``rank`` None and ``stats["rank_bounds"]`` (:class:`RankBounds`: the rank
    bounded, not proved minimal) instead of raising.  ``rank_cpu`` (CPU seconds of this
    process from the call, default :data:`RANK_CPU`; None: no limit) is such a budget, applied
    only once a string has proved the verdict: the search for the rank then stops at the
    first report past it.
    When the greedy search finds none, :func:`refined_answer` either proves "not forcible"
    (``stats["blocked_group"]``: the group whose set excludes the start or the target,
    ``stats["refinement"]`` the direction, ``stats["certificate"]`` says how) or searches configurations inside its sets, and the
    A* keeps only states inside them, its bound restricted to them too
    (:mod:`.settled_sets_bound`).
    Otherwise a ``ctx`` with a budget raises :class:`~supcoord.errors.BudgetExceeded` when it runs out."""
    t0, cpu0 = time.perf_counter(), time.process_time()
    if rank_cpu is not None and (isinstance(rank_cpu, bool) or not isinstance(rank_cpu, (int, float))
                                 or not 0 < rank_cpu < float("inf")):
        raise InputError(f"rank_cpu must be a positive number of seconds or None, got {rank_cpu!r}",
                         value=rank_cpu, where="rank_cpu")
    check_settled_route(model)
    start = tuple(model.inst.start)
    if start == tuple(model.inst.target):
        return CCCResult(True, [], 0, [], {"route": "settled", "relations": 0, "build_seconds": 0.0,
                                           "search_seconds": 0.0, "witness_seconds": 0.0, "buckets": 0,
                                           "distance": 0, "max_layer_nodes": 0,
                                           "seconds": round(time.perf_counter() - t0, 4)})
    bound = PatternBound(model, group_size)
    group = bound.blocked_group(start, certificate_size)
    if group is not None:
        return CCCResult(False, [], None, [], {
            "route": "settled", "relations": 0, "build_seconds": round(time.perf_counter() - t0, 4),
            "search_seconds": 0.0, "witness_seconds": 0.0, "buckets": 0, "distance": None, "max_layer_nodes": 0,
            "blocked_group": [i + 1 for i in group], "certificate": _blocked_text(group),
            "seconds": round(time.perf_counter() - t0, 4)})
    tick = None if ctx is None else _ticker(ThrottledCheck(ctx), "settled witness")
    found, proj = greedy_witness(model, bound, greedy_limit, check=tick), None
    if found is None:
        proj, found = refined_answer(model, bound, ctx)
        if proj.excluded is not None:
            return CCCResult(False, [], None, [], {
                "route": "settled", "relations": 0, "build_seconds": round(time.perf_counter() - t0, 4),
                "search_seconds": 0.0, "witness_seconds": 0.0, "buckets": 0, "distance": None,
                "max_layer_nodes": 0, "blocked_group": [i + 1 for i in proj.excluded],
                "refinement": "forward" if proj.forward else "backward", "certificate": _refined_text(proj), "seconds": round(time.perf_counter() - t0, 4)})
    if found is None or rank_cpu is None:
        return _rank(model, ctx, order, group_size, bound, found, proj, t0)
    ctx = ctx or Context()
    reported = ctx.progress
    ctx.progress = _rank_allowance(reported, cpu0 + rank_cpu, rank_cpu)
    try:
        return _rank(model, ctx, order, group_size, bound, found, proj, t0)
    finally:
        ctx.progress = reported


def _rank_allowance(reported: Callable[[str, dict], None] | None, deadline: float,
                    seconds: float) -> Callable[[str, dict], None]:
    """A progress callback: ``reported``'s, then the end of the budget past ``deadline``
    (process CPU seconds), so that the reports of the relations and the A* stop the search
    for the rank there."""

    def progress(stage: str, info: dict) -> None:
        if reported is not None:
            reported(stage, info)
        if time.process_time() > deadline:
            raise BudgetExceeded(f"the rank's CPU allowance of {seconds:g} s ran out in {stage}",
                                 stats={"stage": stage, **info}, value=seconds)

    return progress


def _rank(model: CoupledModel, ctx: Context | None, order: str, group_size: int, bound: PatternBound,
          found: GreedyWitness | None, proj: Projections | None, t0: float) -> CCCResult:
    """The A* for the rank and its witness (:func:`settled_ccc`).  Where ``found`` proved
    "forcible", a budget that ends the relations or the A* gives that verdict, the string
    and :class:`RankBounds` (``stats["rank_bounds"]``, ``rank`` None) instead of raising."""
    _, start_cost = settle(model, tuple(model.inst.start), (0,) * model.inst.size)
    if proj is not None:  # the A* keeps only states inside the sets: its bound may use them too
        bound = within_sets(bound, proj)
    search = _Search([], None if found is None else found.length - start_cost,
                     lower=bound.value(tuple(model.inst.start)) or 0)
    # a proved verdict travels with every later report too (the bench reads them from a killed run)
    proved = {} if found is None else {"forcible": True, "upper_bound": found.length, "witness": list(found.witness)}
    stats = {"route": "settled", "relations": 0, "upper_bound": None if found is None else found.length,
             "greedy_expanded": None if found is None else found.expanded, "buckets": 0, "distance": None,
             "max_layer_nodes": 0, "search_seconds": 0.0, "witness_seconds": 0.0}
    try:
        graph = SettledGraph(model, ctx, order, group_size, bound, report=proved)
        ctx = graph.ctx
        check = ThrottledCheck(ctx)
        t1 = time.perf_counter()
        stats.update(relations=len(graph.moves), build_seconds=round(t1 - t0, 4))
        if found is not None:  # the verdict is proved: say so before the search for the rank
            ctx.check_budget("settled witness", **proved)
        allowed = None if proj is None else proj_bdd(proj, ctx, graph.pos)  # states that may reach T
        check_bound = ThrottledCheck(ctx)
        _astar(graph, lambda stage, **info: check(stage, **info, **proved), search, allowed,
               lambda stage, **info: check_bound(stage, **info, **proved))
    except BudgetExceeded as exc:
        if found is None:
            raise
        stats.setdefault("build_seconds", round(time.perf_counter() - t0, 4))
        upper = found.length if search.found is None else min(found.length, start_cost + search.found)
        stats.update(buckets=search.buckets, seconds=round(time.perf_counter() - t0, 4))
        if start_cost + search.lower == found.length:  # the bound meets the string: it is a shortest one
            stats.update(rank_proved_by="lower bound")
            return CCCResult(True, list(found.witness), found.length, [], stats)
        stats.update(rank_bounds=RankBounds(start_cost + search.lower, upper, exc.one_line()))
        return CCCResult(True, list(found.witness), None, [], stats)
    t2 = time.perf_counter()
    stats.update(buckets=search.buckets, search_seconds=round(t2 - t1, 4), distance=search.found,
                 max_layer_nodes=max((ctx.node_count(f) for f in search.layers), default=0))
    if search.found is None:
        stats.update(seconds=round(time.perf_counter() - t0, 4))
        return CCCResult(False, [], None, [], stats)
    path = _witness(graph, _corridor(graph, search))
    stats.update(witness_seconds=round(time.perf_counter() - t2, 4), seconds=round(time.perf_counter() - t0, 4))
    return CCCResult(True, path, graph.start_cost + search.found, [], stats)


def settled_ccc_naive(model: CoupledModel) -> tuple[bool, int | None]:
    """The explicit twin: Dijkstra on the settled states, ``(forcible, rank(q0))``."""
    size = model.inst.size
    target: State = (tuple(model.inst.target), (0,) * size)
    q0: State = (tuple(model.inst.start), (0,) * size)
    if q0 == target:
        return True, 0
    levels, cost = settle(model, *q0)
    start = (q0[0], levels)
    best = {start: cost}
    queue = [(cost, start)]
    while queue:
        g, y = heapq.heappop(queue)
        if best[y] != g:
            continue
        if y == target:
            return True, g
        for _, z in successor_events(model, y, controllable=True):
            lv, d = settle(model, *z)
            nxt, w = (z[0], lv), 1 + d
            if g + w < best.get(nxt, g + w + 1):
                best[nxt] = g + w
                heapq.heappush(queue, (g + w, nxt))
    return False, None
