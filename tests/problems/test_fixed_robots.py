"""Robots kept fixed: PROBLEM.json ``fixed`` and ``keep_fixed`` (``--keep``), the offline machinery (issue 37)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from supcoord.errors import FormatError, InputError
from supcoord.planning import solve
from supcoord.problems import parse_problem, validate_plan
from supcoord.problems.fixed_robots import keep_fixed, parse_robot_list

HEX = {"layout": {"kind": "hex", "rings": 1, "pitch": 22.4},
       "kinematics": {"kind": "rotary", "arm": 15.0, "steps": 12},
       "collision": {"buffer": 2.0}, "start": [0] * 7, "target": [6] * 7}


def test_fixed_robots_stay_at_their_start_in_the_plan():
    problem = parse_problem(dict(HEX, fixed=[6, 2]))
    assert sorted(problem.held) == [2, 6]
    assert problem.target[2, 0] == 0 and problem.target[6, 0] == 0 and problem.target[1, 0] == 6
    plan = solve(problem, improve=0)
    assert plan.status == "complete"
    for p in (2, 6):
        assert all(c[p, 0] == 0 for c in plan.configurations)
    assert validate_plan(problem, plan).valid


def test_the_validator_refuses_a_plan_that_moves_a_fixed_robot():
    free = parse_problem(HEX)
    plan = solve(free, improve=0)
    kept = parse_problem(dict(HEX, fixed=[2]))
    moved_3 = [c.copy() for c in plan.configurations]
    moved_3[-1][2] = 0  # ends at its start, but moved on the way
    plan.configurations = moved_3
    check = validate_plan(kept, plan)
    assert not check.valid and any("offline positioners 2 move" in p for p in check.problems)


def test_keep_fixed_is_the_same_as_the_file_field():
    by_file = parse_problem(dict(HEX, fixed=[2, 6]))
    by_call = keep_fixed(parse_problem(HEX), [6, 2])
    assert by_file.held == by_call.held
    assert np.array_equal(by_file.target, by_call.target)
    assert by_call.tables() is not parse_problem(HEX).tables()
    assert sorted(by_call.unary()) == [2, 6]


def test_fixed_round_trips_through_json():
    problem = parse_problem(dict(HEX, fixed=[1]))
    again = parse_problem(json.loads(json.dumps(problem.to_json())))
    assert again.held == problem.held and np.array_equal(again.target, problem.target)


def test_alpha_beta_fixed_robots_keep_their_start_angles():
    data = {"layout": {"kind": "points", "xy": [[0, 0], [22.4, 0]]},
            "kinematics": {"kind": "alpha-beta", "alpha": 7.4, "beta": 15.0, "alpha_steps": 12, "beta_steps": 7,
                           "beta_range": [0, 180]},
            "collision": {"buffer": 2.0}, "start": {"alpha_beta_deg": [[10.5, 170.0], [190.0, 170.0]]},
            "target": {"alpha_beta_deg": [[90.0, 20.0], [200.0, 30.0]]}, "fixed": [1]}
    problem = parse_problem(data)
    assert np.allclose(problem.angles_deg(problem.target)[1], [190.0, 170.0])
    assert 1 in problem.held


@pytest.mark.parametrize("value, error, text", [
    ([7], InputError, "fixed[0]: 7 is not a robot index in [0, 6]"),
    ([-1], InputError, "fixed[0]: -1 is not a robot index"),
    ([1, 1], InputError, "fixed[1]: robot 1 is listed twice"),
    (["1"], InputError, "fixed[0]: '1' is not a robot index"),
    (3, FormatError, "fixed must be a list of robot indices, got 3"),
])
def test_bad_fixed_is_one_line_naming_file_field_and_value(value, error, text):
    with pytest.raises(error) as exc:
        parse_problem(dict(HEX, fixed=value), "field.json")
    line = exc.value.one_line()
    assert "\n" not in line and line.startswith("field.json") and text in line


def test_keep_errors_name_the_option():
    with pytest.raises(InputError, match=r"--keep: '9' is not a robot index in \[0, 6\]") as exc:
        parse_robot_list("3,9", 7, "--keep")
    assert "--keep" in exc.value.one_line()
    with pytest.raises(InputError, match="'x' is not a robot index"):
        parse_robot_list("x", 7, "--keep")
    assert parse_robot_list(" 3,1,3", 7, "--keep") == [1, 3]


def test_keeping_a_robot_whose_start_meets_a_neighbours_target_is_refused():
    data = {"layout": {"kind": "points", "xy": [[0, 0], [20, 0]]},
            "kinematics": {"kind": "rotary", "arm": 12.0, "steps": 4},
            "collision": {"buffer": 1.0}, "start": [0, 1], "target": [1, 2]}
    with pytest.raises(InputError, match="robot 0 kept at its start collides with robot 1 at its target"):
        keep_fixed(parse_problem(data), [0], "--keep")
