"""Partial plans whose robots off target end folded (``off_target_end="folded"``, issue 37).

The folded configuration is checked here from its definition (beta at 180°, alpha where the
robot starts) with the problem's own angles, and every plan by the validator; a plan whose
entries say another end than the one it reaches is refused.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import supcoord.planning.partial as partial_module
from supcoord.errors import InputError
from supcoord.planning import solve
from supcoord.planning.partial import partial_search
from supcoord.problems.problem import parse_problem
from supcoord.problems.validate import validate_plan

#: three alpha-beta robots in a line, no plan puts all three on target; robot 2 can end folded
LINE = {"layout": {"kind": "points", "xy": [[0.0, 0.0], [7.552936, 0.0], [15.105873, 0.0]]},
        "kinematics": {"kind": "alpha-beta", "alpha": 7.274, "beta": 15.357, "alpha_steps": 12,
                       "beta_steps": 3, "beta_range": [150.0, 180.0]},
        "collision": {"buffer": 2.013}, "start": [[3, 0], [2, 1], [2, 1]], "target": [[4, 1], [4, 2], [10, 2]]}


@pytest.fixture(scope="module")
def plans():
    """The plans without parking (step 6), which here would park robot 2 instead of folding it."""
    problem = parse_problem(LINE)
    with pytest.MonkeyPatch.context() as m:
        m.setattr(partial_module, "park", lambda *args: None)
        return problem, solve(problem, improve=0), solve(problem, improve=0, off_target_end="folded")


def test_parking_puts_more_robots_on_target_than_folding(plans):
    problem, _, folded = plans
    parked = solve(problem, improve=0, off_target_end="folded")
    assert folded.on_target == 0 and parked.on_target == 2
    assert [(e.robot, e.end) for e in parked.off_target] == [(2, "parked")]
    assert validate_plan(problem, parked).valid


def test_folded_end_keeps_the_robots_off_target_and_folds_where_reachable(plans):
    problem, at_start, folded = plans
    assert at_start.status == folded.status == "partial"
    assert [e.robot for e in folded.off_target] == [e.robot for e in at_start.off_target]
    assert folded.on_target == at_start.on_target and folded.optimal == at_start.optimal
    assert all(e.end == "start" for e in at_start.off_target)
    ends = {e.robot: e.end for e in folded.off_target}
    assert "folded" in ends.values()
    last = folded.configurations[-1]
    for robot, end in ends.items():
        alpha, beta = problem.kin(robot).joint_angles_deg(last[robot])
        start_alpha = problem.kin(robot).joint_angles_deg(problem.start[robot])[0]
        if end == "folded":
            assert beta == 180.0 and alpha == start_alpha
        else:
            assert np.array_equal(last[robot], problem.start[robot])
    assert validate_plan(problem, folded).valid
    assert "ends folded" in folded.reason


def test_the_validator_refuses_an_end_the_plan_does_not_reach(plans):
    problem, at_start, folded = plans
    robot = next(e.robot for e in folded.off_target if e.end == "folded")
    says_start = tuple(dataclasses.replace(e, end="start") if e.robot == robot else e for e in folded.off_target)
    assert not validate_plan(problem, dataclasses.replace(folded, off_target=says_start)).valid
    says_folded = tuple(dataclasses.replace(e, end="folded") if e.robot == robot else e for e in at_start.off_target)
    assert not validate_plan(problem, dataclasses.replace(at_start, off_target=says_folded)).valid


def test_an_unknown_off_target_end_is_refused():
    problem = parse_problem(LINE)
    with pytest.raises(InputError, match="off_target_end must be one of start, folded, got 'parked'"):
        solve(problem, off_target_end="parked")
    with pytest.raises(ValueError, match="off_target_end"):
        partial_search(problem, [1, 2], "search", lambda q: ([1, 2], "search"), off_target_end="parked")


def test_rotary_robots_have_no_fold_and_end_at_their_starts():
    problem = parse_problem({"layout": {"kind": "points", "xy": [[0, 0], [18, 0], [9, 15]]},
                             "kinematics": {"kind": "rotary", "arm": 15.0, "steps": 12},
                             "collision": {"buffer": 2.0}, "start": [5, 5, 9], "target": [11, 0, 1]})
    plan = solve(problem, improve=0, off_target_end="folded")
    assert plan.status == "partial" and all(e.end == "start" for e in plan.off_target)
    assert "fold_attempts" not in plan.stats["partial"] and validate_plan(problem, plan).valid
