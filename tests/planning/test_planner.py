"""The symbolic planner against the independent oracle, the validator, and the monolithic route.

Verdicts, ranks, certificates and optimal makespans are checked against
:mod:`supcoord.testing.oracle` (its own geometry and breadth-first search, none of the
planner's tables); :func:`~supcoord.testing.explicit_search.reachable_naive` and
:func:`~supcoord.testing.explicit_search.blockers_naive`, explicit twins of the *encoding* over the
planner's own guards, check that the BDDs encode those guards.
"""

import math

import numpy as np
import pytest

from supcoord.bdd.context import Budget
from supcoord.errors import BudgetExceeded, InputError
from supcoord.planning.graph_order import conflict_components
from supcoord.planning.move_layers import move_layers, witness_moves
from supcoord.planning.model import CoordinationModel
from supcoord.planning.planner import solve, solve_window
from supcoord.planning.routes import Local, Monolithic
from supcoord.planning.schedule import asap_schedule, plan_from_schedule
from supcoord.problems import random_problem, validate_plan
from supcoord.problems.plan import apply_moves
from supcoord.testing.oracle import (
    MAX_CONFIGURATIONS,
    oracle_bounds,
    oracle_moves,
    oracle_optimal_makespan,
    oracle_solve,
)

ROT = {"kind": "rotary", "arm": 15.0, "steps": 12}
AB = {"kind": "alpha-beta", "alpha": 7.4, "beta": 15.0, "alpha_steps": 6, "beta_steps": 4, "beta_range": [0, 180]}
AB_SDSS = {"kind": "alpha-beta", "alpha": 7.4, "beta": 15.0, "alpha_steps": 12, "beta_steps": 7, "beta_range": [0, 180]}

# tight layouts: arms overlap their neighbours' far more than on a real grid (19.25 mm, not
# 19: arms of 15 mm with buffers of 2 mm on bases 19 mm apart touch at exactly the buffer
# sum, where rounding decides; tests/planning/test_planner_oracle.py checks those ties)
LAYOUTS = {
    "rot2": (ROT, [[0, 0], [20, 0]]),
    "rot3": (ROT, [[0, 0], [18, 0], [9, 15]]),
    "rot3line": (ROT, [[0, 0], [19.25, 0], [38.5, 0]]),
    "rot4": (ROT, [[0, 0], [19.25, 0], [9.625, 16], [28.875, 16]]),
    "ab2": (AB, [[0, 0], [12, 0]]),
    "ab3": (AB, [[0, 0], [16, 0], [8, 13]]),
}


def _problem(name, seed):
    kin, xy = LAYOUTS[name]
    return random_problem(np.array(xy, float), kin, 2.0, seed=seed)


def _cases():
    for name in LAYOUTS:
        for seed in range(5 if name != "rot4" else 3):
            yield name, seed


def _oracle(p):
    """The oracle's shortest single-move distance of ``p`` (None: no plan)."""
    return oracle_solve(p.to_json())


@pytest.mark.parametrize("name,seed", list(_cases()))
def test_symbolic_verdict_and_rank_equal_the_oracle(name, seed):
    p = _problem(name, seed)
    distance = _oracle(p)
    model = CoordinationModel(p)
    everyone = list(range(p.n))
    res = solve_window(model, everyone, None, p.start)
    assert res.feasible == (distance is not None)
    if distance is not None:
        assert res.rank == distance == len(res.moves)  # rank(q0) = the shortest plan's length
        confs = apply_moves(p, res.moves)
        assert np.array_equal(confs[-1], p.target)
    for route in ("local", "monolithic"):
        plan = solve(p, route, simultaneous=None, when_incomplete="infeasible")  # the oracle's distance is the single-move model's
        assert plan.status == ("complete" if distance is not None else "infeasible")
        if distance is None:
            assert "positioners" in plan.reason and plan.stats["certificate"]
            # the certificate is a relaxed subproblem that really is infeasible
            assert oracle_solve(p.to_json(), members=plan.stats["certificate"]) is None
        else:
            result = validate_plan(p, plan)
            assert result.valid, result.problems
            assert plan.lower_bound <= plan.makespan <= distance <= plan.stats["single_moves"]


def test_tight_layouts_have_both_verdicts():
    verdicts = {_oracle(_problem(n, s)) is None for n, s in _cases()}
    assert verdicts == {True, False}
    ab = {_oracle(_problem(n, s)) is None for n, s in _cases() if n.startswith("ab")}
    assert False in ab


def test_layers_equal_forcibility_layers():
    from supcoord.synthesis import forcible_layers

    p = _problem("rot3", 0)
    model = CoordinationModel(p)
    S = model.system([0, 1, 2], None)
    G = S.to_generator()
    mine = move_layers(S, S.marked)
    theirs = forcible_layers(G, G.marked)
    assert len(mine.layers) == len(theirs.layers)
    assert all(a == b for a, b in zip(mine.layers, theirs.layers))
    assert mine.rank(S.init) == theirs.rank(G.init)


def test_priority_breaks_ties():
    flipped = 0
    for seed in range(10):
        p = _problem("rot2", seed)
        model = CoordinationModel(p)
        S = model.system([0, 1], None)
        lay = move_layers(S, S.marked)
        p.priority[:] = [1, 2]  # the model holds this problem: its priority list, changed in place
        a = witness_moves(S, lay, p.start)
        p.priority[:] = [2, 1]
        b = witness_moves(S, lay, p.start)
        assert len(a) == len(b) == lay.rank(S.init)
        if a[0][0] != b[0][0]:
            assert (a[0][0], b[0][0]) == (0, 1)  # the higher priority moves first
            flipped += 1
    assert flipped > 0


@pytest.mark.parametrize("rings,seed", [(1, 0), (1, 1), (1, 2)])
@pytest.mark.slow
def test_local_and_monolithic_agree_on_grids(rings, seed):
    p = random_problem({"kind": "hex", "rings": rings, "pitch": 22.4}, ROT, 2.0, seed=seed)
    local = solve(p)
    mono = solve(p, Monolithic(fixpoint="supervisor" if rings == 1 else "search"))
    assert local.status == mono.status == "complete"
    for plan in (local, mono):
        assert validate_plan(p, plan).valid
    assert mono.stats["single_moves"] <= local.stats["single_moves"]  # rank(q0): the shortest


def test_alpha_beta_grid_plan_is_valid():
    p = random_problem({"kind": "hex", "rings": 1, "pitch": 22.4}, AB_SDSS, 2.0, seed=0, near=2)
    plan = solve(p)
    assert plan.status == "complete" and validate_plan(p, plan).valid


def test_conflict_components_split_distant_groups():
    xy = [[0, 0], [20, 0], [200, 0], [219, 0]]
    p = random_problem(np.array(xy, float), ROT, 2.0, seed=1)
    assert conflict_components(p) == [[0, 1], [2, 3]]
    plan = solve(p)
    assert plan.status == "complete" and plan.stats["components"] == 2
    assert validate_plan(p, plan).valid


def test_schedule_never_longer_than_the_sequence_and_valid():
    p = _problem("rot3", 0)
    moves = oracle_moves(p.to_json())
    length = len(moves)
    from supcoord.problems import Plan

    confs = asap_schedule(p, moves)
    assert len(confs) - 1 <= length and np.array_equal(confs[-1], p.target)
    assert validate_plan(p, Plan("complete", confs)).valid


def test_optimal_makespan_is_a_yardstick():
    p = _problem("rot3", 0)
    opt = oracle_optimal_makespan(p.to_json())
    plan = solve(p)
    assert plan.lower_bound <= opt <= plan.makespan


def test_budgets_and_bad_arguments():
    p = random_problem({"kind": "hex", "rings": 1, "pitch": 22.4}, ROT, 2.0, seed=0)
    with pytest.raises(BudgetExceeded) as info:
        solve(p, budget=Budget(timeout=1e-9))
    assert info.value.stats["route"] == "local"
    with pytest.raises(InputError):
        solve(p, route="nope")
    with pytest.raises(InputError):
        solve(p, Monolithic(fixpoint="nope"))
    with pytest.raises(InputError):
        solve(p, Local(descent="nope"))
    with pytest.raises(InputError):
        CoordinationModel(p, order="spiral")


# -- the scalable route's parts: descent, bidirectional search, blockers, orders, schedules ---------------

import itertools

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from supcoord.errors import SupcoordError
from supcoord.planning.descent import descent
from supcoord.planning.graph_order import cutwidth_order
from supcoord.planning.guards import blocked_table, conflict_graph
from supcoord.planning.move_layers import MoveLayers
from supcoord.planning.schedule import timeline_schedule
from supcoord.planning.search import blockers, search, witness_layers
from supcoord.planning.windows import LEVELS, path_blockers
from supcoord.problems import Plan
from supcoord.problems.problem import parse_problem
from supcoord.testing.explicit_search import blockers_naive, reachable_naive


def _subproblem(p, members):
    """The relaxed subproblem of ``members``: only they, from their starts to their targets."""
    data = p.to_json()
    data["layout"] = {"kind": "points", "xy": p.bases[members].tolist()}
    for key in ("start", "target", "priority"):
        data[key] = [data[key][i] for i in members]
    return parse_problem(data)


def _single_move_valid(p, c, move):
    """Is ``move`` allowed at configuration ``c`` by the (symmetrised) swept tables?"""
    q, joint, d = move
    kin = p.kinematics
    if kin.step(c[q], joint, d) is None:
        return False
    m = kin.moves().index((joint, d))
    flat = kin.flat_index(c)
    return not any(blocked_table(p, k, side)[m, flat[q], flat[r]] for k, r, side in conflict_graph(p)[q])


@st.composite
def small_problems(draw):
    """2–3 positioners at random distances (feasible and infeasible), random starts and targets."""
    kind = draw(st.sampled_from(["rot2", "rot3", "ab2"]))
    kin = AB if kind == "ab2" else ROT
    d = draw(st.floats(10.0 if kind == "ab2" else 15.0, 30.0))
    xy = [[0, 0], [d, 0]] if kind != "rot3" else [[0, 0], [d, 0], [d / 2, d * draw(st.floats(0.7, 1.0))]]
    seed = draw(st.integers(0, 10**6))
    try:
        return random_problem(np.array(xy, float), kin, 2.0, seed=seed)
    except InputError:  # too dense to draw a collision-free configuration
        return random_problem(np.array(xy, float) * 1.6, kin, 2.0, seed=seed)


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(small_problems())
@pytest.mark.slow
def test_local_route_verdicts_equal_the_oracle(p):
    """Drawn distances may put arms at exactly the buffer sum (15 + 4 = 19 mm): the oracle's
    bounds (ties free, ties blocked) then frame the answer instead of one distance."""
    lo, hi = oracle_bounds(p.to_json())
    plan = solve(p, simultaneous=None, when_incomplete="infeasible")  # the oracle's bounds are the single-move model's
    if hi is not None:
        assert plan.status == "complete"
    if lo is None:
        assert plan.status == "infeasible"
    if plan.status == "infeasible":
        sub = plan.stats["certificate"]
        assert oracle_bounds(p.to_json(), members=sub)[1] is None  # really infeasible, the others removed
        assert _subproblem(p, sub).n == len(sub)
    else:
        assert validate_plan(p, plan).valid
        assert plan.lower_bound <= plan.makespan <= len(plan.events)
        assert lo is not None and lo <= len(plan.events)
    default = solve(p, when_incomplete="infeasible")  # with the simultaneous search: a plan wherever the single-move model has one
    if default.status == "complete":
        assert validate_plan(p, default).valid
    else:
        assert plan.status == "infeasible" and default.stats["certificate_model"] in ("simultaneous", "single-move")


@settings(max_examples=15, deadline=None)
@given(st.integers(0, 10**6), st.sampled_from(["rot", "ab"]))
def test_descent_steps_are_serialisable_and_free_when_merged(seed, kind):
    kin, pitch = (ROT, 22.4) if kind == "rot" else (AB_SDSS, 22.4)
    p = random_problem({"kind": "hex", "rings": 1, "pitch": pitch}, kin, 2.0, seed=seed)
    steps, end = descent(p, p.start)
    c = p.start.copy()
    confs = [c.copy()]
    rng = np.random.default_rng(seed)
    for step in steps:
        for order in (step, step[::-1], [step[i] for i in rng.permutation(len(step))]):  # any order is valid
            x = c.copy()
            for mv in order:
                assert _single_move_valid(p, x, mv), (step, order, mv)
                x[mv[0]] = p.kinematics.step(x[mv[0]], mv[1], mv[2])
        c = x
        confs.append(c.copy())
    assert np.array_equal(c, end)
    # the simultaneous steps themselves are collision-free (the validator, with the end as target)
    data = p.to_json()
    data["target"] = [p.kinematics.position_to_json(q) for q in end]
    q = parse_problem(data)
    assert validate_plan(q, Plan("complete", confs)).valid
    # the descent only moves positioners towards their targets: it never passes one
    dist = p.kinematics.joint_distance
    assert np.all(dist(end, p.target) <= dist(p.start, p.target))


@pytest.mark.parametrize("name,seed", [("rot3", 0), ("rot3", 1), ("rot4", 0), ("ab2", 0), ("ab3", 2), ("ab3", 4)])
def test_bidirectional_and_forward_search_find_the_oracle_distance(name, seed):
    p = _problem(name, seed)
    distance = _oracle(p)
    model = CoordinationModel(p, members=range(p.n), order="cutwidth")
    for merged in (False, True):
        S = model.system(list(range(p.n)), None, merged=merged)
        for mode in ("bidirectional", "forward"):
            res = search(S, S.marked, mode=mode)
            assert res.distance == distance
            if distance is None:
                # the closed side holds exactly one of its two ends: q0 (Reach) or the goal (CoReach)
                assert res.closed is not None
                holds_init = res.closed & S.init != model.ctx.false
                holds_goal = res.closed & S.marked != model.ctx.false
                assert holds_init != holds_goal
                if mode == "forward":
                    assert holds_init  # forward search closes Reach(q0)
                continue
            moves = witness_moves(S, MoveLayers(witness_layers(S, res), model.ctx.false, True, {}), p.start)
            assert len(moves) == distance and np.array_equal(apply_moves(p, moves)[-1], p.target)


@pytest.mark.parametrize("name,seed", [("rot3", 0), ("rot4", 1), ("rot4", 2), ("ab3", 0), ("ab3", 3)])
def test_blockers_and_reach_equal_the_explicit_twin(name, seed):
    p = _problem(name, seed)
    model = CoordinationModel(p)
    for r in (1, 2):
        for members in itertools.combinations(range(p.n), r):
            members = list(members)
            S = model.system(members, p.start, init=p.start)
            res = search(S, model.ctx.false, mode="forward")  # an empty goal: the whole Reach(q0)
            naive = reachable_naive(p, members, p.start)
            assert model.ctx.count(res.closed, S.variables) == len(naive)
            assert blockers(S, res.closed, p.start) == blockers_naive(p, members, p.start)


def test_blockers_of_a_relaxed_path_block_it():
    p = _problem("rot4", 0)
    members = [0]
    moves = oracle_moves(p.to_json(), members=members)  # a path of 0 alone, the others removed
    assert moves and {q for q, _, _ in moves} == {0}
    found = path_blockers(p, moves, p.start, set(members))
    c = p.start.copy()
    hit = set()
    for q, j, d in moves:  # replay with everyone else frozen: the blocked moves name the blockers
        m = p.kinematics.moves().index((j, d))
        flat = p.kinematics.flat_index(c)
        hit |= {r for k, r, side in conflict_graph(p)[q] if r not in members and blocked_table(p, k, side)[m, flat[q], flat[r]]}
        c[q] = p.kinematics.step(c[q], j, d)
    assert found == sorted(hit)


def test_cutwidth_order_is_least_by_brute_force():
    p = random_problem({"kind": "hex", "rings": 2, "pitch": 22.4}, ROT, 2.0, seed=0)
    adj = conflict_graph(p)
    for members in ([0, 1, 2, 3, 4, 5, 6], [1, 2, 7, 8, 9, 10], [5, 6, 16, 17, 0]):
        def cost(order, members=members):
            cuts = []
            for i in range(1, len(order)):
                left = set(order[:i])
                cuts.append(sum(1 for a in left for _, b, _ in adj[a] if b in members and b not in left))
            return max(cuts), sum(cuts)
        best = min(cost(list(o)) for o in itertools.permutations(members))
        assert cost(cutwidth_order(p, members)) == best


@pytest.mark.parametrize("name,seed", [("rot3", 0), ("rot4", 2), ("ab3", 0), ("ab3", 1)])
def test_timeline_schedule_is_valid_and_never_longer_than_the_sequence(name, seed):
    p = _problem(name, seed)
    moves = oracle_moves(p.to_json())
    assert moves is not None, "the cases are chosen feasible"
    length = len(moves)
    confs = timeline_schedule(p, moves)
    assert len(confs) - 1 <= length and np.array_equal(confs[-1], p.target)
    assert validate_plan(p, Plan("complete", confs)).valid


@pytest.mark.slow
def test_timeline_schedule_on_a_grid_plan_is_valid_and_shorter_than_asap():
    p = random_problem({"kind": "hex", "rings": 2, "pitch": 22.4}, AB_SDSS, 2.0, seed=1)
    plan = solve(p, validation="none")
    moves = [parse_event_(p, e) for e in plan.events]
    tl, asap = timeline_schedule(p, moves), asap_schedule(p, moves)
    for confs in (tl, asap):
        assert validate_plan(p, Plan("complete", confs)).valid
    assert len(tl) <= len(asap)


def parse_event_(p, e):
    from supcoord.problems.plan import parse_event

    return parse_event(p.kinematics, e)


@pytest.mark.parametrize("pitch,seed", [(22.4, 0), (22.4, 3), (18.0, 0), (18.0, 5)])
def test_local_and_monolithic_agree_on_rotary_grids_tight_and_infeasible(pitch, seed):
    p = random_problem({"kind": "hex", "rings": 1, "pitch": pitch}, ROT, 2.0, seed=seed)
    local = solve(p, when_incomplete="infeasible")
    mono = solve(p, Monolithic(fixpoint="search"), when_incomplete="infeasible")
    assert local.status == mono.status
    if local.status == "complete":
        assert validate_plan(p, local).valid and validate_plan(p, mono).valid
    else:  # 18 mm pitch: arms overlap across the grid; both certify, the local one names fewer
        cert = local.stats["certificate"]
        assert len(cert) <= len(mono.stats["certificate"])
        if p.kinematics.n_positions ** len(cert) <= MAX_CONFIGURATIONS:  # the oracle confirms it
            assert oracle_solve(p.to_json(), members=cert) is None
        else:  # the whole grid, whose infeasibility the monolithic route decided exactly above
            assert sorted(cert) == list(range(p.n))


@pytest.mark.parametrize("pitch,seed", [pytest.param(17.0, 6, marks=pytest.mark.slow), pytest.param(17.0, 8, marks=pytest.mark.slow),
                                         pytest.param(14.0, 6, marks=pytest.mark.slow),
                                         pytest.param(14.0, 11, marks=pytest.mark.slow)])
def test_local_and_monolithic_agree_on_alpha_beta_grids(pitch, seed):
    """On the problem's own lattice (``finer=None``: both routes decide that model); a plan
    the local route then finds on a finer lattice is valid."""
    p = random_problem({"kind": "hex", "rings": 1, "pitch": pitch}, AB, 2.0, seed=seed)
    local = solve(p, finer=None, when_incomplete="infeasible")
    mono = solve(p, Monolithic(fixpoint="search"), finer=None, when_incomplete="infeasible")
    assert local.status == mono.status
    for plan in (local, mono):
        if plan.status == "complete":
            assert validate_plan(p, plan).valid
    refined = solve(p, when_incomplete="infeasible")
    assert refined.status == local.status or (refined.status == "complete" and refined.lattice is not None)
    if refined.status == "complete":
        assert validate_plan(p, refined).valid


@pytest.mark.parametrize("layout,kin,seed,verdict", [
    ({"kind": "hex", "rings": 2, "pitch": 22.4}, AB_SDSS, 0, "complete"),
    ({"kind": "hex", "rings": 1, "pitch": 18.0}, ROT, 0, "infeasible"),
    ({"kind": "hex", "rings": 1, "pitch": 18.0}, ROT, 1, "infeasible"),
    ({"kind": "hex", "rings": 1, "pitch": 18.0}, ROT, 3, "infeasible"),
])
def test_window_caps_never_change_the_verdict(layout, kin, seed, verdict):
    p = random_problem(layout, kin, 2.0, seed=seed)
    default = solve(p, when_incomplete="infeasible")
    assert default.status == verdict
    for levels in ((50, None),) if verdict == "complete" else ((50, None), (5, 20, None)):  # the grid is slow
        tiny = solve(p, Local(levels=levels), when_incomplete="infeasible")
        assert tiny.status == verdict
        assert tiny.stats["windows_abandoned"] > 0  # the tiny cap was really hit
        if verdict == "complete":
            assert validate_plan(p, tiny).valid
        else:  # a certificate whatever the caps, and a true one (the oracle, the others removed)
            cert = tiny.stats["certificate"]
            assert len(cert) < p.n and oracle_solve(p.to_json(), members=cert) is None
    assert LEVELS[-1] is None
    with pytest.raises(SupcoordError):
        solve(p, Local(levels=(1000,)))


# -- plan quality: the symbolic optimum and the space-time improvement --------------------------------

from supcoord.planning.improve import improve_plan
from supcoord.planning.optimum import optimal_makespan


@pytest.mark.parametrize("name,seed", [("rot2", 0), ("rot3", 0), ("rot3", 1), ("rot3line", 2), ("rot4", 2),
                                       ("ab2", 0), ("ab2", 3)])
def test_symbolic_optimal_makespan_equals_the_oracle(name, seed):
    p = _problem(name, seed)
    opt = oracle_optimal_makespan(p.to_json())
    assert optimal_makespan(p).makespan == opt
    plan = solve(p, when_incomplete="infeasible")
    if opt is None:
        assert plan.status == "infeasible"
    else:  # every plan is a path of the simultaneous semantics: never shorter than its optimum
        assert plan.lower_bound <= opt <= plan.makespan


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_grid_plans_are_never_shorter_than_the_optimum(seed):
    p = random_problem({"kind": "hex", "rings": 1, "pitch": 22.4}, ROT, 2.0, seed=seed)
    opt = optimal_makespan(p).makespan
    plan = solve(p)
    assert opt is not None and opt <= plan.makespan


@settings(max_examples=6, deadline=None)
@given(st.integers(0, 10**6), st.sampled_from(["rot", "ab"]))
def test_improvement_keeps_plans_valid_and_never_longer(seed, kind):
    kin = ROT if kind == "rot" else AB_SDSS
    p = random_problem({"kind": "hex", "rings": 2 if kind == "rot" else 1, "pitch": 22.4}, kin, 2.0, seed=seed)
    plan = solve(p, improve=0)
    if plan.status != "complete" or plan.lattice is not None:  # improve_plan works on the problem's lattice
        return
    confs, stats = improve_plan(p, plan.configurations)
    assert len(confs) - 1 <= plan.makespan == stats.makespan_before
    assert np.array_equal(confs[0], p.start) and np.array_equal(confs[-1], p.target)
    assert validate_plan(p, Plan("complete", confs)).valid


def test_improvement_shortens_a_known_plan():
    p = random_problem({"kind": "hex", "rings": 2, "pitch": 22.4}, ROT, 2.0, seed=0)
    before = solve(p, improve=0)
    after = solve(p)
    assert after.makespan < before.makespan  # 14 -> 7 (the optimum, 7, is measured in bench_makespan)
    assert validate_plan(p, after).valid


@pytest.mark.timeout(60)
@pytest.mark.parametrize("name,seed", [("rot3", 0), ("rot4", 1), ("rot4", 2), ("ab3", 0), ("ab3", 3)])
@pytest.mark.slow
def test_few_displaced_windows_reach_what_the_explicit_twin_reaches(name, seed):
    """``displaced_at_most`` counts the members away from ``c``; the restricted system moves
    only through such configurations (explicit twin: the same breadth-first search, told to
    enter no configuration with more members away)."""
    p = _problem(name, seed)
    model = CoordinationModel(p)
    members = list(range(p.n))
    s0 = tuple(int(v) for v in p.kinematics.flat_index(p.start))
    S = model.system(members, p.start, init=p.start)
    for bound in (0, 1, 2):
        region = model.displaced_at_most(members, p.start, bound)
        assert model.ctx.count(region & S.invariant, S.variables) == sum(
            math.comb(p.n, k) * (p.kinematics.n_positions - 1) ** k for k in range(bound + 1))
        R = S.restricted(region)
        res = search(R, model.ctx.false, mode="forward")
        naive = reachable_naive(p, members, p.start,
                                keep=lambda t: sum(a != b for a, b in zip(t, s0)) <= bound)
        assert model.ctx.count(res.closed, S.variables) == len(naive)
    assert len(naive) < len(reachable_naive(p, members, p.start)) or p.n <= 2


def _reference_allowed(rp, r, t, u):
    """What ``allowed_mask`` must give, from the whole simultaneous tables of the pairs
    (``CollisionTables.simultaneous``, checked against ``motion_collides`` in test_collision)
    and, for several joints at once, ``motion_collides`` itself, position by position."""
    from supcoord.geometry.motion import motion_collides

    p, pos = rp.problem, rp.pos
    ok = rp.nxt[u] >= 0
    unary = p.unary().get(r)
    if unary is not None:
        ok = ok & ~(unary[0] if u == 0 else unary[1][u - 1] if u < rp.n_single else
                    np.array([bool(p.own_motion_blocked(r, pos[i], rp.deltas[u])[0]) if ok[i] else True
                              for i in range(len(pos))]))
    for k, (a, b) in enumerate(np.asarray(p.pairs).tolist()):
        if r not in (a, b):
            continue
        q, side = (b, 0) if a == r else (a, 1)
        j0, j1 = int(rp.traj[t, q]), int(rp.traj[t + 1, q])
        v = 0 if j0 == j1 else rp.option_of(q, t)
        if u < rp.n_single and v < rp.n_single:
            sim = p.tables().simultaneous(k)
            ok = ok & ~(sim[u, v, :, j0] if side == 0 else sim[v, u, j0, :])
        else:
            idx = np.nonzero(ok)[0]
            ok[idx] = ~motion_collides(p.kin(r), p.bases[r], pos[idx], rp.deltas[u], p.kin(q), p.bases[q],
                                       pos[j0], rp.deltas[v], p.buffers[r] + p.buffers[q])
    return ok


@pytest.mark.timeout(120)
@pytest.mark.parametrize("kind,seed", [("ab", 0), ("ab", 4), pytest.param("angles", 94, marks=pytest.mark.slow),
                                       pytest.param("obstacle", 94, marks=pytest.mark.slow),
                                       pytest.param("obstacle", 98, marks=pytest.mark.slow)])
def test_improvement_masks_equal_the_whole_simultaneous_tables(kind, seed):
    """The re-planner reads swept tables where one robot stands and computes the motions of
    both only where it needs them (end-point bound first): every mask it gives equals the
    one read off the pairs' whole simultaneous tables, for every option, robot and step of a
    plan (shared kinematics, and robots with their own lattices and obstacles); both for a
    re-planner that computes each mask as it is asked and for one whose motions were computed
    first in one batch per neighbour (:meth:`_Replanner.prefetch`), on the same plan, each
    mask against one reference."""
    from supcoord.planning.improve import _Replanner
    from supcoord.problems.problem import parse_problem
    from supcoord.testing.oracle.tight_problems import tight_angle_problem

    if kind == "ab":
        p = random_problem({"kind": "hex", "rings": 1, "pitch": 22.4}, AB_SDSS, 2.0, seed=seed)
    else:
        data = tight_angle_problem(seed, n=6, max_product=10**9)
        if kind == "obstacle":  # a fiducial near the first robots (their own constraints: unary tables)
            data["layout"]["obstacles"] = [{"xy": {94: [9.0, 17.0], 98: [3.0, 14.0]}[seed], "buffer": 1.0}]
        p = parse_problem(data)
        assert bool(p.unary()) == (kind == "obstacle")
    plan = solve(p, improve=0, finer=None)
    assert plan.status == "complete" and plan.makespan >= 2
    confs = [np.asarray(c) for c in plan.configurations]
    batched = _Replanner(p, confs, {"replans": 0, "improved": 0})
    for r in range(p.n):  # batched first, while no mask of this plan has been computed yet
        batched.prefetch(r, plan.makespan)
    assert batched.merged_cache
    rp = _Replanner(p, confs, {"replans": 0, "improved": 0})
    checked = 0
    for r in range(p.n):
        for t in range(plan.makespan):
            for u in range(len(rp.deltas)):
                reference = _reference_allowed(rp, r, t, u)
                assert np.array_equal(rp.allowed_mask(r, t, u), reference), (r, t, u)
                assert np.array_equal(batched.allowed_mask(r, t, u), reference), ("batched", r, t, u)
                checked += 1
    assert checked >= p.n * 2 * 9


def _improved_valid(kind, seed, from_start=False):
    """A random two-ring problem, its plan without improvement, and the improved plan, checked
    to start at the start, end at the target and pass the validator.  ``from_start``: the
    plan is the planner's single moves scheduled from the start (:func:`plan_from_schedule`),
    also where the planner solved the exchanged problem and scheduled from the target."""
    kin = ROT if kind == "rot" else AB_SDSS
    p = random_problem({"kind": "hex", "rings": 2, "pitch": 22.4}, kin, 2.0, seed=seed)
    plan = solve(p, improve=0, finer=None)
    if from_start:
        plan = plan_from_schedule(p, [parse_event_(p, e) for e in plan.events])
    confs, stats = improve_plan(p, plan.configurations)
    assert np.array_equal(confs[0], p.start) and np.array_equal(confs[-1], p.target)
    assert validate_plan(p, Plan("complete", confs)).valid
    return p, plan, confs, stats


@pytest.mark.timeout(120)
@pytest.mark.parametrize("kind,seed", [("ab", 8)])
@pytest.mark.slow
def test_improvement_regroups_with_the_neighbours_in_the_way(kind, seed, monkeypatch):
    """Where no group of the latest robot with its latest neighbours arrives earlier, a group
    with the neighbours in the way of its path without neighbours does (seeds where that
    happens): the plan is valid and shorter than without those groups."""
    from supcoord.planning import improve as improve_module

    p, plan, confs, stats = _improved_valid(kind, seed, from_start=True)
    assert stats.improved_with_blockers >= 1
    monkeypatch.setattr(improve_module, "_blocker_groups", lambda r, blockers, tried: [])
    without, stats_without = improve_plan(p, plan.configurations)
    assert stats_without.improved_with_blockers == 0 and len(confs) < len(without)


@pytest.mark.timeout(120)
@pytest.mark.parametrize("kind,seed", [("rot", 9), ("ab", 2), pytest.param("ab", 5, marks=pytest.mark.slow)])
def test_improvement_replans_two_neighbours_in_each_others_way_together(kind, seed, monkeypatch):
    """Two neighbours that must give way to each other: planned one at a time neither can
    arrive earlier, planned together (``pair_replan``: the product of their positions in
    space-time) they do (seeds where that happens); the plan is valid, starts at the start,
    ends at the target, and is shorter than without the joint re-plan."""
    from supcoord.planning.improve import _Replanner
    from supcoord.problems.plan import lower_bound

    p, plan, confs, stats = _improved_valid(kind, seed)
    assert stats.improved_with_pairs >= 1
    if (kind, seed) == ("rot", 9):  # down to the largest joint distance, where improvement stops
        assert len(confs) - 1 == lower_bound(p) == 6
        again, stats_again = improve_plan(p, confs)  # nothing left to gain: no work at all
        assert len(again) == len(confs) and stats_again.replans == 0
        idle, _ = improve_plan(p, confs + [confs[-1]])  # one step above the bound: improved down to it
        assert len(idle) == len(confs)
    monkeypatch.setattr(_Replanner, "replan_pair", lambda self, r, q, horizon: False)
    without, _ = improve_plan(p, plan.configurations)
    assert len(confs) < len(without)


@pytest.mark.parametrize("seed", [0, 1])
@pytest.mark.slow
def test_a_plan_solved_the_other_way_is_the_mirror_of_the_exchanged_problems_plan(seed):
    """The windows solve whichever direction the descent finds easier (seed 0: target →
    start, seed 1: start → target, on SDSS-V robots unfolding from their folded lattice);
    the plan is scheduled and improved in that direction and read backwards, so solving
    the exchanged problem gives the same configurations in reverse.  The single-move
    events go from the start, each allowed, to the target."""
    from supcoord import preset_problem
    from supcoord.problems.plan import exchanged

    p = preset_problem("sdss-v", rings=2, seed=seed, alpha_steps=12, beta_steps=7, start="folded")
    plan, other = solve(p, speed=12.0), solve(exchanged(p), speed=12.0)
    assert plan.status == other.status == "complete"
    assert {plan.stats["direction"], other.stats["direction"]} == {"forward", "reverse"}
    assert len(plan.configurations) == len(other.configurations)
    for mine, theirs in zip(plan.configurations, other.configurations[::-1]):
        assert np.array_equal(mine, theirs)
    assert plan.motion_time_s == pytest.approx(other.motion_time_s, rel=1e-12)
    assert validate_plan(p, plan).valid
    moves = [parse_event_(p, e) for e in plan.events]
    visited = apply_moves(p, moves)
    assert all(_single_move_valid(p, c, move) for c, move in zip(visited, moves))
    assert np.array_equal(visited[-1], p.target)
