"""Partial plans (issue 37): the most robots on target, checked against the independent oracle.

The oracle (:mod:`supcoord.testing.oracle.subsets`) tries every set of robots off target,
fewest first, with its own breadth-first search; it shares no code with the planner.  Two
maxima: robots off target at their starts (``oracle_most_on_target``), and off target anywhere
they can be brought (``oracle_most_on_target_anywhere``), which the parking step
(:mod:`supcoord.planning.partial_park`) reaches towards.  The benchmark
``benchmarks/partial_oracle.py`` runs the same checks on 300 cases.
"""

import itertools

import numpy as np
import pytest

import supcoord.planning.partial as partial_module
from supcoord.errors import BudgetExceeded, InputError
from supcoord.planning import solve
from supcoord.planning.partial import partial_search
from supcoord.problems.off_target import BUDGET_REASON
from supcoord.problems.problem import parse_problem
from supcoord.problems.validate import validate_plan
from supcoord.testing.oracle import oracle_check_steps, oracle_solve
from supcoord.testing.oracle.subsets import (ends_at_start, oracle_group_unsolvable, oracle_most_on_target,
                                              oracle_most_on_target_anywhere)
from supcoord.testing.partial_cases import tight_case

TRIANGLE = {"layout": {"kind": "points", "xy": [[0.0, 0.0], [18.0, 0.0], [9.0, 15.0]]},
            "kinematics": {"kind": "rotary", "arm": 15.0, "steps": 12},
            "collision": {"buffer": 2.0}, "start": [5, 5, 9], "target": [11, 0, 1]}


def plan_ends(data, plan):
    """PROBLEM.json ending where the partial plan says: each robot off target at its start or
    where it is parked (rotary robots: one index)."""
    out = ends_at_start(data, [e.robot for e in plan.off_target])
    for e in plan.off_target:
        if e.end == "parked":
            out["target"][e.robot] = e.at[0] if isinstance(out["target"][e.robot], int) else list(e.at)
    return out


def _check_against_oracle(data, plan, problem):
    """Every claim of a partial plan, checked by the oracle and the validator: ``optimal``
    (at least the most robots on target with the others at their starts; exactly that where
    no robot is parked), and at most the most on target with the others anywhere, at most
    ``on_target_bound``."""
    assert plan.status == "partial", plan.reason
    off = [e.robot for e in plan.off_target]
    parked = plan.stats["partial"].get("park_put_back", [])
    assert plan.on_target == problem.n - len(off)
    best = oracle_most_on_target(data)
    anywhere = oracle_most_on_target_anywhere(data)
    if plan.optimal:
        assert plan.on_target >= best.on_target, (off, best)
    if not parked:
        assert plan.on_target <= best.on_target
    assert plan.on_target <= anywhere <= plan.on_target_bound
    result = validate_plan(problem, plan)
    assert result.valid and result.at_target == plan.on_target, result.problems
    assert oracle_check_steps(plan_ends(data, plan), plan.configurations) is None  # the oracle's replay
    for e in plan.off_target:
        assert e.end in ("start", "parked") and e.certificate is not None and e.robot in e.certificate.members
        assert (e.end == "parked") == (e.at is not None)
        assert e.reason.startswith("certificate: group [")
        assert oracle_group_unsolvable(data, e.certificate.members, e.certificate.at_start), e


@pytest.mark.parametrize("seed", range(30))
def test_partial_plans_of_small_problems_agree_with_the_oracle(seed):
    data = tight_case(seed, sizes=(3, 4))
    assert data is not None
    _check_against_oracle(data, solve(parse_problem(data)), parse_problem(data))


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(4))
def test_partial_plans_of_five_and_six_robots_agree_with_the_oracle(seed):
    data = tight_case(seed, sizes=(5, 6))
    assert data is not None
    _check_against_oracle(data, solve(parse_problem(data)), parse_problem(data))


@pytest.mark.parametrize("seed", range(6))
def test_without_the_exact_search_the_set_is_minimal_and_the_bound_holds(monkeypatch, seed):
    """The greedy choice and the put-back pass alone (as on a large field): no robot off target
    could have been put back, the oracle's maximum lies within the bound, optimal only where
    disjoint groups prove it."""
    monkeypatch.setattr(partial_module, "EXACT_ROBOTS", 0)
    data = tight_case(seed, sizes=(3, 4))
    p = parse_problem(data)
    plan = solve(p)
    assert plan.stats["partial"]["method"] == "minimal"
    _check_against_oracle(data, plan, p)
    off = [e.robot for e in plan.off_target]
    for r in off:  # inclusion-minimal, by the oracle: no robot put back with the others' ends as they are
        ends = plan_ends(data, plan)
        ends["target"][r] = data["target"][r]
        try:
            assert oracle_solve(ends) is None
        except InputError:  # its target collides with a neighbour's end
            pass


def test_the_triangle_leaves_one_robot_at_its_start():
    p = parse_problem(TRIANGLE)
    plan = solve(p)
    assert [e.robot for e in plan.off_target] == [0] and plan.optimal and plan.on_target_bound == 2
    assert np.array_equal(plan.configurations[-1], [[5], [0], [1]])
    assert plan.reason.startswith("2 of 3 robots reach their targets; off target: robot 0 (group [0, 1, 2] has no plan")
    assert plan.stats["certificate"] == [0, 1, 2] and plan.stats["partial"]["method"] == "exact"
    assert solve(p, when_incomplete="infeasible").status == "infeasible"
    with pytest.raises(InputError, match="when_incomplete"):
        solve(p, when_incomplete="all")


def _least_weight_oracle(data, weight):
    """The oracle's least total weight off target (every subset of the moving robots)."""
    moving = [r for r in range(len(data["start"])) if data["start"][r] != data["target"][r]]
    costs = []
    for k in range(len(moving) + 1):
        for off in itertools.combinations(moving, k):
            try:
                works = oracle_solve(ends_at_start(data, off)) is not None
            except InputError:  # colliding ends
                works = False
            if works:
                costs.append(sum(weight[r] for r in off))
    return min(costs)


@pytest.mark.parametrize("seed", [0, 3])
def test_weighted_answers_agree_with_the_oracle(seed):
    data = tight_case(seed, sizes=(3, 4))
    weight = [1.0 + 3.0 * r for r in range(len(data["start"]))]
    p = parse_problem(dict(data, weight=weight))
    plan = solve(p)
    assert plan.optimal and sum(weight[e.robot] for e in plan.off_target) == _least_weight_oracle(data, weight)
    assert validate_plan(p, plan).valid


FAR = {"layout": {"kind": "points", "xy": [[0.0, 0.0], [100.0, 0.0], [200.0, 0.0]]},
       "kinematics": {"kind": "rotary", "arm": 15.0, "steps": 12},
       "collision": {"buffer": 2.0}, "start": [0, 0, 0], "target": [6, 6, 6]}


def _family_attempt(problem, works):
    """An attempt whose sub-problem P(O) has a plan exactly when ``works(O)`` (the search's
    logic alone, without the planner); a certificate names the three robots."""
    def attempt(sub):
        off = frozenset(int(r) for r in np.nonzero(np.all(sub.target == problem.start, axis=1))[0])
        if works(off):
            return solve(sub)
        return [0, 1, 2], "the family"
    return attempt


@pytest.mark.parametrize("weight, priority, expected", [
    (None, [1, 2, 3], [0]),            # fewest robots: {0}
    ([100, 1, 1], [1, 2, 3], [1, 2]),  # {0} worth 100, {1, 2} worth 2
    ([1, 1, 1], [1, 2, 3], [0]),
])
def test_the_search_leaves_off_target_the_least_weight(weight, priority, expected):
    p = parse_problem(dict(FAR, weight=weight, priority=priority) if weight else dict(FAR, priority=priority))
    found = partial_search(p, [0, 1, 2], "the family", _family_attempt(p, lambda off: 0 in off or {1, 2} <= off))
    assert [e.robot for e in found.off_target] == expected and found.optimal


def test_priority_breaks_ties_towards_the_lower_priority_robot():
    # any single robot off target works: the one with the largest priority number goes
    for priority, expected in (([1, 2, 3], [2]), ([3, 1, 2], [0])):
        p = parse_problem(dict(FAR, priority=priority))
        found = partial_search(p, [0, 1, 2], "the family", _family_attempt(p, lambda off: len(off) >= 1))
        assert [e.robot for e in found.off_target] == expected and found.optimal and found.on_target == 2


def test_a_complete_plan_is_unchanged():
    data = dict(TRIANGLE, target=[5, 5, 10])
    plan = solve(parse_problem(data))
    assert plan.status == "complete" and plan.off_target == () and "off_target" not in plan.to_json(parse_problem(data))


def test_a_budget_ending_during_the_search_names_the_undecided_robots():
    """The search's attempts run out of budget at once: nothing moves, the robot the first
    certificate chose keeps that certificate, the others 'not proven: budget'; still valid."""
    p = parse_problem(TRIANGLE)

    def attempt(sub):
        raise BudgetExceeded("time budget exceeded")

    found = partial_search(p, [0, 1, 2], "search", attempt)
    assert found.stats.method == "budget" and not found.optimal and found.on_target == 0
    assert len(found.plan.configurations) == 1
    reasons = {e.robot: e.reason for e in found.off_target}
    assert sorted(reasons) == [0, 1, 2] and list(reasons.values()).count(BUDGET_REASON) == 2
    from supcoord.problems.plan import Plan

    plan = Plan("partial", found.plan.configurations, 0, 0, off_target=found.off_target)
    assert validate_plan(p, plan).valid


@pytest.mark.parametrize("speed", [None, 10.0])
def test_solve_answers_partial_when_the_budget_ends_while_robots_are_left_out(monkeypatch, speed):
    """The first solve certifies; every later one runs out of budget: the plan in which
    nothing moves, valid, with the first choice's certificate and 'not proven: budget'."""
    import supcoord.planning.planner as planner

    calls = []
    first = planner._solve

    def out_of_budget_after_the_first(*args, **kwargs):
        calls.append(1)
        if len(calls) > 1:
            raise BudgetExceeded("time budget exceeded")
        return first(*args, **kwargs)

    monkeypatch.setattr(planner, "_solve", out_of_budget_after_the_first)
    p = parse_problem(TRIANGLE)
    plan = planner.solve(p, speed=speed)
    assert plan.status == "partial" and plan.on_target == 0 and plan.optimal is False
    assert plan.stats["partial"]["method"] == "budget" and len(plan.configurations) == 1
    assert sorted(e.reason == BUDGET_REASON for e in plan.off_target) == [False, True, True]
    assert validate_plan(p, plan).valid
