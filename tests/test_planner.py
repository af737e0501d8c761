"""The symbolic planner against the explicit BFS twin, the validator, and the monolithic route."""

import numpy as np
import pytest

from supcoord.errors import BudgetExceeded, InputError
from supcoord.positioners import bfs_plan_naive, optimal_makespan_naive, random_problem, validate_plan
from supcoord.positioners.coordination import CoordinationModel, conflict_components
from supcoord.positioners.plan import apply_moves
from supcoord.positioners.planner import move_layers, solve, solve_window, witness_moves
from supcoord.positioners.planner_schedule import asap_schedule
from supcoord.symbolic.context import Budget

ROT = {"kind": "rotary", "arm": 15.0, "steps": 12}
AB = {"kind": "alpha-beta", "alpha": 7.4, "beta": 15.0, "alpha_steps": 6, "beta_steps": 4, "beta_range": [0, 180]}
AB_SDSS = {"kind": "alpha-beta", "alpha": 7.4, "beta": 15.0, "alpha_steps": 12, "beta_steps": 7, "beta_range": [0, 180]}

# tight layouts: arms overlap their neighbours' far more than on a real grid
LAYOUTS = {
    "rot2": (ROT, [[0, 0], [20, 0]]),
    "rot3": (ROT, [[0, 0], [18, 0], [9, 15]]),
    "rot3line": (ROT, [[0, 0], [19, 0], [38, 0]]),
    "rot4": (ROT, [[0, 0], [19, 0], [9.5, 16], [28.5, 16]]),
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


@pytest.mark.parametrize("name,seed", list(_cases()))
def test_symbolic_verdict_and_rank_equal_bfs(name, seed):
    p = _problem(name, seed)
    naive = bfs_plan_naive(p)
    model = CoordinationModel(p)
    everyone = list(range(p.n))
    res = solve_window(model, everyone, None, p.start)
    assert res.feasible == (naive is not None)
    if naive is not None:
        assert res.rank == naive[0] == len(res.moves)  # rank(q0) = BFS distance
        confs = apply_moves(p, res.moves)
        assert np.array_equal(confs[-1], p.target)
    for route in ("local", "monolithic"):
        plan = solve(p, route=route)
        assert plan.status == ("complete" if naive is not None else "infeasible")
        if naive is None:
            assert "positioners" in plan.reason and plan.stats["certificate"]
            # the certificate is a relaxed subproblem that really is infeasible
            sub = plan.stats["certificate"]
            assert solve_window(CoordinationModel(p), sub, None, p.start, want_moves=False).rank is None
        else:
            result = validate_plan(p, plan)
            assert result["valid"], result["problems"]
            assert plan.lower_bound <= plan.makespan <= naive[0]


def test_tight_layouts_have_both_verdicts():
    verdicts = {bfs_plan_naive(_problem(n, s)) is None for n, s in _cases()}
    assert verdicts == {True, False}
    ab = {bfs_plan_naive(_problem(n, s)) is None for n, s in _cases() if n.startswith("ab")}
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
        p.priority = [1, 2]
        a = witness_moves(S, lay, p.start)
        p.priority = [2, 1]
        b = witness_moves(S, lay, p.start)
        assert len(a) == len(b) == lay.rank(S.init)
        if a[0][0] != b[0][0]:
            assert (a[0][0], b[0][0]) == (0, 1)  # the higher priority moves first
            flipped += 1
    assert flipped > 0


@pytest.mark.parametrize("rings,seed", [(1, 0), (1, 1), (1, 2)])
def test_local_and_monolithic_agree_on_grids(rings, seed):
    p = random_problem({"kind": "hex", "rings": rings, "pitch": 22.4}, ROT, 2.0, seed=seed)
    local = solve(p)
    mono = solve(p, route="monolithic", supervisor=rings == 1)
    assert local.status == mono.status == "complete"
    for plan in (local, mono):
        assert validate_plan(p, plan)["valid"]
    assert mono.stats["single_moves"] <= local.stats["single_moves"]  # rank(q0): the shortest


def test_alpha_beta_grid_plan_is_valid():
    p = random_problem({"kind": "hex", "rings": 1, "pitch": 22.4}, AB_SDSS, 2.0, seed=0, near=2)
    plan = solve(p)
    assert plan.status == "complete" and validate_plan(p, plan)["valid"]


def test_conflict_components_split_distant_groups():
    xy = [[0, 0], [20, 0], [200, 0], [219, 0]]
    p = random_problem(np.array(xy, float), ROT, 2.0, seed=1)
    assert conflict_components(p) == [[0, 1], [2, 3]]
    plan = solve(p)
    assert plan.status == "complete" and plan.stats["components"] == 2
    assert validate_plan(p, plan)["valid"]


def test_schedule_never_longer_than_the_sequence_and_valid():
    p = _problem("rot3", 0)
    length, moves = bfs_plan_naive(p)
    from supcoord.positioners import Plan

    confs = asap_schedule(p, moves)
    assert len(confs) - 1 <= length and np.array_equal(confs[-1], p.target)
    assert validate_plan(p, Plan("complete", confs))["valid"]


def test_optimal_makespan_is_a_yardstick():
    p = _problem("rot3", 0)
    opt = optimal_makespan_naive(p)
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
        CoordinationModel(p, order="spiral")
