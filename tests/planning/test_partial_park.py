"""Parking (step 6 of the partial search): a robot left off target moved out of its
neighbours' way, so that they reach their targets.

The hex7 field below: robot 2 cannot reach its target, and at its start it sits on robot 1's
target (their segments touch), so with every robot off target at its start robot 1 is kept
off target too; parked elsewhere in its own part of joint space, robot 2 frees it.  The small
random fields are checked against the independent oracle's most robots on target with the
others anywhere they can be brought (one breadth-first search over every configuration).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import supcoord.planning.partial as partial_module
from supcoord.errors import BudgetExceeded, FormatError
from supcoord.planning import solve
from supcoord.planning.partial import partial_search
from supcoord.planning.partial_park import reachable_cells
from supcoord.problems.off_target import parse_off_target
from supcoord.problems.problem import parse_problem
from supcoord.problems.validate import validate_plan
from supcoord.testing.oracle import oracle_check_steps
from supcoord.testing.oracle.subsets import oracle_most_on_target, oracle_most_on_target_anywhere
from supcoord.testing.partial_cases import tight_case

from .test_partial import plan_ends

HEX7 = {"layout": {"kind": "hex", "rings": 1, "pitch": 17.0},
        "kinematics": {"kind": "rotary", "arm": 15.0, "steps": 12},
        "collision": {"buffer": 2.0}, "start": [1, 2, 1, 8, 7, 11, 1], "target": [9, 9, 3, 8, 6, 9, 1]}


@pytest.fixture(scope="module")
def hex7():
    problem = parse_problem(HEX7)
    return problem, solve(problem, improve=0)


def test_parking_a_robot_frees_its_neighbours_target(hex7):
    problem, plan = hex7
    ends = problem.target.copy()
    ends[2] = problem.start[2]
    assert (1, 2, 0.0) in problem.collisions(ends)  # robot 2 at its start sits on robot 1's target
    assert plan.status == "partial" and plan.on_target == 4
    entries = {e.robot: e for e in plan.off_target}
    assert sorted(entries) == [0, 2, 5] and entries[2].end == "parked" and entries[2].at == (11,)
    assert plan.stats["partial"]["parked"] == [{"robot": 2, "at": [11], "freed": [1]}]
    assert plan.stats["partial"]["park_put_back"] == [1]
    last = plan.configurations[-1]
    assert last[1].tolist() == problem.target[1].tolist() and last[2].tolist() == [11]
    assert any(np.array_equal(c, [11]) for c in reachable_cells(problem, 2)[0])
    result = validate_plan(problem, plan)
    assert result.valid and result.at_target == 4, result.problems
    assert "robot 2 (" in plan.reason and "parked at lattice position (11)" in plan.reason


def test_without_parking_the_count_is_lower(monkeypatch, hex7):
    monkeypatch.setattr(partial_module, "park", lambda *args: None)
    problem, parked = hex7
    plan = solve(problem, improve=0)
    assert plan.on_target == 3 and parked.on_target == 4
    assert all(e.end == "start" for e in plan.off_target) and "parked" not in plan.stats["partial"]


def test_the_validator_refuses_a_parked_end_the_plan_does_not_reach(hex7):
    problem, plan = hex7
    moved = tuple(dataclasses.replace(e, at=(10,)) if e.end == "parked" else e for e in plan.off_target)
    assert not validate_plan(problem, dataclasses.replace(plan, off_target=moved)).valid
    at_start = tuple(dataclasses.replace(e, end="start", at=None) if e.end == "parked" else e
                     for e in plan.off_target)
    assert not validate_plan(problem, dataclasses.replace(plan, off_target=at_start)).valid
    outside = tuple(dataclasses.replace(e, at=(12,)) if e.end == "parked" else e for e in plan.off_target)
    result = validate_plan(problem, dataclasses.replace(plan, off_target=outside))
    assert not result.valid and "not a position of its lattice" in result.problems[0]


def test_parked_entries_read_back_and_malformed_ones_are_refused(hex7):
    problem, plan = hex7
    entries = plan.to_json(problem)["off_target"]
    assert parse_off_target(entries, problem.n) == plan.off_target
    parked = next(e for e in entries if e["end"] == "parked")
    for bad, match in ((dict(parked, at=None), "at must list"), (dict(parked, at=[-1]), "at must list"),
                       (dict(parked, end="start"), "only where end is")):
        with pytest.raises(FormatError, match=match):
            parse_off_target([bad], problem.n)


@pytest.mark.parametrize("seed", [4, 11, 31])
def test_parking_reaches_the_oracles_most_on_target_anywhere(seed):
    """Fields where the most on target with the others at their starts is less than with the
    others anywhere: the plan reaches the latter, valid for the validator and the oracle."""
    data = tight_case(seed)
    problem = parse_problem(data)
    plan = solve(problem)
    anywhere = oracle_most_on_target_anywhere(data)
    assert oracle_most_on_target(data).on_target < anywhere == plan.on_target <= plan.on_target_bound
    assert any(e.end == "parked" for e in plan.off_target)
    assert validate_plan(problem, plan).valid
    assert oracle_check_steps(plan_ends(data, plan), plan.configurations) is None


def test_a_budget_ending_while_parking_keeps_the_answer_found_before(hex7):
    """The budget ends at the first sub-problem with a robot parked: the answer is the search's
    set before parking, every robot at its start, named by its certificate; still valid."""
    problem, _ = hex7
    verdict = solve(problem, when_incomplete="infeasible", improve=0)

    def attempt(sub):
        elsewhere = np.any((sub.target != problem.start) & (sub.target != problem.target), axis=1)
        if elsewhere.any():
            raise BudgetExceeded("time budget exceeded")
        plan = solve(sub, when_incomplete="infeasible", improve=0, simultaneous=None)
        return plan if plan.status == "complete" else (plan.stats["certificate"], "search")

    found = partial_search(problem, verdict.stats["certificate"], "search", attempt)
    assert found.stats.method == "budget" and not found.optimal and found.on_target == 3
    assert found.stats.parking.attempts >= 1 and found.stats.parking.put_back == []
    assert all(e.end == "start" and e.certificate is not None for e in found.off_target)
    plan = dataclasses.replace(found.plan, status="partial", off_target=found.off_target)
    assert validate_plan(problem, plan).valid
