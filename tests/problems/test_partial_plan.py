"""PLAN.json's partial plans: read back, bounded, and validated by the partial rule (issue 37)."""

import copy
import json

import numpy as np
import pytest

from supcoord.errors import FormatError
from supcoord.problems.off_target import GroupCertificate, OffTarget, group_reason, parse_off_target
from supcoord.problems.plan import Plan, parse_plan
from supcoord.problems.problem import parse_problem
from supcoord.problems.validate import validate_plan

# two robots far apart: robot 1 stays at its start, robot 0 turns one step to its target
FAR = {"layout": {"kind": "points", "xy": [[0.0, 0.0], [100.0, 0.0]]},
       "kinematics": {"kind": "rotary", "arm": 15.0, "steps": 12},
       "collision": {"buffer": 2.0}, "start": [0, 0], "target": [1, 5]}
CERT = GroupCertificate((1,), "exhaustive symbolic search")
ENTRY = OffTarget(1, group_reason(CERT), CERT)


def _partial(configurations, entries=(ENTRY,)):
    return Plan("partial", [np.array(c).reshape(-1, 1) for c in configurations], off_target=tuple(entries),
                on_target=1, optimal=True, on_target_bound=1)


def test_a_partial_plan_is_valid_when_the_listed_robots_end_at_their_starts():
    p = parse_problem(FAR)
    r = validate_plan(p, _partial([[0, 0], [1, 0]]))
    assert r.valid and r.at_target == 1, r.problems


@pytest.mark.parametrize("configurations, entries, why", [
    ([[0, 0], [1, 1]], (ENTRY,), "robot 1 listed but not at its start"),
    ([[0, 0], [0, 0]], (ENTRY,), "robot 0 not listed and not at its target"),
    ([[0, 0], [1, 0]], (), "nobody listed"),
    ([[0, 0], [1, 0]], (ENTRY, ENTRY), "robot 1 listed twice"),
])
def test_a_partial_plan_is_invalid_otherwise(configurations, entries, why):
    assert not validate_plan(parse_problem(FAR), _partial(configurations, entries)).valid, why


def test_a_complete_plan_must_still_reach_every_target():
    plan = Plan("complete", [np.array([[0], [0]]), np.array([[1], [0]])])
    assert not validate_plan(parse_problem(FAR), plan).valid


def test_a_partial_plan_given_by_angles_alone_is_checked_the_same_way():
    p = parse_problem(FAR)
    plan = _partial([[0, 0], [1, 0]])
    plan.angles_deg = [p.angles_deg(c) for c in plan.configurations]
    plan.configurations = []
    r = validate_plan(p, plan)
    assert r.valid and r.at_target == 1, r.problems
    plan.angles_deg[-1] = p.angles_deg(np.array([[1], [1]]))
    assert not validate_plan(p, plan).valid


def test_plan_json_reads_back_what_it_wrote():
    p = parse_problem(FAR)
    plan = _partial([[0, 0], [1, 0]])
    back = parse_plan(json.loads(json.dumps(plan.to_json(p))), p)
    assert back.status == "partial" and back.off_target == plan.off_target
    assert (back.on_target, back.optimal, back.on_target_bound) == (1, True, 1)
    assert validate_plan(p, back).valid


def _entry(**change):
    e = {"robot": 1, "reason": "not proven: budget", "certificate": None, "end": "start"}
    e.update(change)
    return e


@pytest.mark.parametrize("value", [
    [_entry(robot=2)], [_entry(robot=-1)], [_entry(robot=True)], [_entry(), _entry()],
    [_entry(end="parked")], [_entry(reason="x" * 5000)], [_entry(reason=3)],
    [_entry(certificate={"members": [5]})], [_entry(certificate={"members": []})],
    [_entry(certificate={"members": [0], "at_start": [1]})], [_entry(certificate=[0, 1])],
    [_entry(extra=1)], [{"reason": "r"}], "robot 1", [_entry()] * 3,
])
def test_malformed_off_target_entries_are_refused(value):
    with pytest.raises(FormatError):
        parse_off_target(value, 2, "plan.json")


@pytest.mark.parametrize("change", [
    {"status": "complete"},          # off_target on a complete plan
    {"off_target": []},              # a partial plan names nobody
    {"on_target": 3}, {"on_target": -1}, {"on_target_bound": 0}, {"optimal": "yes"},
])
def test_malformed_partial_fields_are_refused(change):
    p = parse_problem(FAR)
    data = _partial([[0, 0], [1, 0]]).to_json(p)
    data = dict(copy.deepcopy(data), **change)
    with pytest.raises(FormatError):
        parse_plan(data, p, "plan.json")


def test_weight_is_read_and_written():
    p = parse_problem(dict(FAR, weight=[2, 0.5]))
    assert p.weight == (2.0, 0.5) and p.to_json()["weight"] == [2.0, 0.5] and not p.warnings
    for bad in ([1], [1, -1], [1, float("nan")], [1, "a"], [1, True], "heavy"):
        with pytest.raises(FormatError, match="weight"):
            parse_problem(dict(FAR, weight=bad))
