"""``validate_plan`` returns a typed, frozen :class:`ValidationResult` whose ``to_json()`` is
the object ``supcoord check --json`` prints: its fields in the documented order, and
``motion_time_s`` only for a plan with trajectories."""

from __future__ import annotations

import dataclasses
import json

import pytest

import supcoord
from supcoord.cli.main import main
from supcoord.problems import Plan, ValidationResult, parse_problem, validate_plan

FIELDS = ["valid", "collisions", "at_target", "problems", "steps", "min_clearance", "incidents", "undecided",
          "undecided_depth"]


def _problem():
    return parse_problem({"layout": {"kind": "points", "xy": [[0, 0], [20, 0]]},
                          "kinematics": {"kind": "rotary", "arm": 8.0, "steps": 4},
                          "collision": {"buffer": 1.0}, "start": [0, 0], "target": [1, 0]})


def test_the_result_is_typed_frozen_and_its_json_has_the_documented_fields():
    p = _problem()
    r = validate_plan(p, Plan("complete", [p.start, p.target]))
    assert isinstance(r, ValidationResult) and supcoord.ValidationResult is ValidationResult
    assert (r.valid, r.collisions, r.at_target, r.steps, r.motion_time_s) == (True, 0, 2, 1, None)
    assert list(r.to_json()) == FIELDS
    assert all(getattr(r, k) == v for k, v in r.to_json().items())  # the JSON is made from the fields
    assert "motion_time_s" not in r.to_json()  # only a plan with trajectories has a motion time
    with pytest.raises(dataclasses.FrozenInstanceError):
        r.valid = False


def test_a_plan_with_trajectories_reports_its_motion_time():
    p = _problem()
    timed = supcoord.solve(p, speed=30.0)
    r = validate_plan(p, Plan("complete", trajectories=timed.trajectories, motion_time_s=timed.motion_time_s))
    assert r.valid and r.motion_time_s == pytest.approx(timed.motion_time_s)
    assert list(r.to_json()) == FIELDS + ["motion_time_s"]


def test_check_json_is_the_results_json(tmp_path, capsys):
    p = _problem()
    problem_file, plan_file = tmp_path / "p.json", tmp_path / "plan.json"
    p.dump(problem_file)
    plan = Plan("complete", [p.start, p.target])
    plan.dump(plan_file, p.kinematics)
    assert main(["check", str(problem_file), str(plan_file), "--json"]) == 0
    assert json.loads(capsys.readouterr().out) == validate_plan(p, plan).to_json()
