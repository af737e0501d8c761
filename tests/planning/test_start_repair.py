"""Colliding starts repaired first, with the fewest robots moved (issue 37).

The colliding pairs and the minimum number of robots to move are computed here
independently of the planner: the pairs with the oracle's geometry
(:mod:`supcoord.testing.oracle`), the minimum by brute force over subsets of robots.
"""

from __future__ import annotations

import dataclasses
import itertools

import numpy as np
import pytest

from supcoord.errors import InputError
from supcoord.planning.start_repair import RepairResult, repair_start, solve_any_start
from supcoord.problems import Plan, validate_plan
from supcoord.problems.repair_phase import Repair, parse_problem_any_start, start_collisions
from supcoord.testing.oracle.distance import segment_gap
from supcoord.testing.oracle.oracle_model import OracleProblem


def oracle_pairs(data: dict, conf: list[int]) -> list[tuple[int, int]]:
    """Colliding pairs of a rotary configuration, by the oracle's geometry."""
    prob = OracleProblem.from_json(dict(data, start=conf, target=conf))
    ends = [prob.arm_of(p).segment(np.array([conf[p]])) for p in range(prob.n)]
    out = []
    for a, b in itertools.combinations(range(prob.n), 2):
        d = segment_gap(ends[a][0] + prob.bases[a], ends[a][1] + prob.bases[a],
                        ends[b][0] + prob.bases[b], ends[b][1] + prob.bases[b])
        if float(d) < prob.need(a, b):
            out.append((a, b))
    return out


def brute_minimum(n: int, pairs: list[tuple[int, int]], held: set[int] = frozenset()) -> int:
    """The fewest robots (none held) touching every pair: every subset, smallest first."""
    free = [p for p in range(n) if p not in held]
    for size in range(len(free) + 1):
        for s in itertools.combinations(free, size):
            if all(a in s or b in s for a, b in pairs):
                return size
    raise AssertionError("no cover")


def random_case(rng: np.random.Generator, rings: int = 1) -> dict | None:
    """A hex field of rotary robots whose random start collides and whose target does not."""
    data = {"layout": {"kind": "hex", "rings": rings, "pitch": 22.4},
            "kinematics": {"kind": "rotary", "arm": 15.0, "steps": 12}, "collision": {"buffer": 2.0}}
    n = 1 + 3 * rings * (rings + 1)
    for _ in range(200):
        target = rng.integers(0, 12, n).tolist()
        if not oracle_pairs(data, target):
            break
    else:
        return None
    start = rng.integers(0, 12, n).tolist()
    return dict(data, start=start, target=target) if oracle_pairs(data, start) else None


def test_random_colliding_starts_repaired_with_the_fewest_robots():
    rng = np.random.default_rng(37)
    seen = minimum = 0
    while seen < 25:
        data = random_case(rng)
        if data is None:
            continue
        seen += 1
        problem = parse_problem_any_start(data)
        pairs = oracle_pairs(data, data["start"])
        assert start_collisions(problem) == pairs
        least = brute_minimum(problem.n, pairs)
        result = repair_start(problem)
        moved = set(result.repair.moved)
        assert all(a in moved or b in moved for a, b in pairs), (data, result.repair)
        assert result.repair.lower_bound == least, (data, result.repair)  # exact on components this small
        assert len(moved) >= least
        assert result.repair.minimum == (len(moved) == least)
        minimum += result.repair.minimum
        end = result.configurations[-1].ravel().tolist()
        assert not oracle_pairs(data, end), (data, end)
        unmoved = [p for p in range(problem.n) if p not in moved]
        assert all(end[p] == data["start"][p] for p in unmoved)
        plan = Plan("complete", result.configurations + [problem.target], repair=result.repair)
        # the repair phase itself passes the validator's rule (the plan's last step may not)
        check = validate_plan(problem, plan)
        assert not [p for p in check.problems if p.startswith("repair")], check.problems
    assert minimum >= 22, f"only {minimum} of {seen} repairs moved the fewest robots"


def test_solve_from_a_colliding_start_is_complete_and_valid():
    rng = np.random.default_rng(7)
    done = 0
    while done < 4:
        data = random_case(rng)
        if data is None:
            continue
        problem = parse_problem_any_start(data)
        plan = solve_any_start(problem, improve=0)
        if plan.status != "complete":
            continue
        done += 1
        assert plan.repair is not None and plan.configurations[0].ravel().tolist() == data["start"]
        assert validate_plan(problem, plan).valid
        k = plan.repair.steps
        assert not oracle_pairs(data, plan.configurations[k].ravel().tolist())


TWO = {"layout": {"kind": "points", "xy": [[0, 0], [20, 0]]},
       "kinematics": {"kind": "rotary", "arm": 15.0, "steps": 24}, "collision": {"buffer": 2.0}}


def two_robot_plan(path0: list[int], moved: tuple[int, ...] = (0,)) -> tuple:
    """Robot 0 along ``path0`` (positions; 24 per turn, position 1 is −15°) while robot 1
    points at it (position 12, −x); the whole path is the repair phase; target [6, 12]."""
    problem = parse_problem_any_start(dict(TWO, start=[path0[0], 12], target=[6, 12]))
    confs = [np.array([[q], [12]]) for q in path0]
    return problem, Plan("complete", confs, repair=Repair(moved, len(path0) - 1, True, 1))


def test_validator_accepts_a_repair_that_moves_the_pair_apart():
    problem, plan = two_robot_plan([1, 2, 3, 4, 5, 6])  # -15°, -30°, ...: away from robot 1
    assert start_collisions(problem) == [(0, 1)]
    check = validate_plan(problem, plan)
    assert check.valid, check.problems


def test_validator_rejects_a_repair_that_brings_a_colliding_pair_closer():
    problem, plan = two_robot_plan([1, 0, 23, 22, 21, 20, 19, 18])  # towards robot 1 (θ = 0) and past it
    check = validate_plan(problem, plan)
    assert not check.valid
    assert any("repair step 0->1" in p and "closer than" in p for p in check.problems), check.problems
    assert not any("repair step 1->2" in p for p in check.problems), check.problems  # 0 -> 23: apart


def test_validator_rejects_a_repair_that_leaves_the_pair_colliding():
    problem, plan = two_robot_plan([1])
    check = validate_plan(problem, plan)
    assert not check.valid
    assert any("still collides" in p for p in check.problems), check.problems


def test_validator_rejects_a_robot_moved_that_is_in_no_colliding_pair():
    three = dict(TWO, layout={"kind": "points", "xy": [[0, 0], [20, 0], [60, 0]]})
    problem = parse_problem_any_start(dict(three, start=[1, 12, 0], target=[6, 12, 0]))
    confs = [np.array([[q], [12], [0]]) for q in (1, 2, 3, 4, 5, 6)]
    plan = Plan("complete", confs, repair=Repair((0, 2), 5, True, 1))
    assert any("positioners [2] are in no pair colliding" in p for p in validate_plan(problem, plan).problems)
    confs = [np.array([[q], [12], [0 if k < 2 else 1]]) for k, q in enumerate((1, 2, 3, 4, 5, 6))]
    bad = dataclasses.replace(plan, configurations=confs, repair=Repair((0,), 5, True, 1))
    assert any("positioners [2] move but are not in repair.moved" in p
               for p in validate_plan(problem, bad).problems)


def test_held_robots_never_move_in_a_repair_and_two_held_ones_refused():
    data = dict(TWO, start=[0, 12], target=[6, 12], fixed=[1])
    problem = parse_problem_any_start(data)
    result = repair_start(problem)
    assert result.repair.moved == (0,)
    assert all(c[1, 0] == 12 for c in result.configurations)
    with pytest.raises(InputError, match="target configuration collides: positioners 0 and 1"):
        parse_problem_any_start(dict(data, fixed=[0, 1]))  # held from start to target: they stay colliding
    both = dataclasses.replace(problem, held={0: (0,), 1: (12,)})
    with pytest.raises(InputError, match="held .* robots 0 and 1 collide"):
        repair_start(both)


def test_a_free_start_needs_no_repair():
    problem = parse_problem_any_start(dict(TWO, start=[6, 18], target=[18, 6]))
    result = repair_start(problem)
    assert isinstance(result, RepairResult) and result.repair == Repair((), 0, True, 0)
    assert solve_any_start(problem, improve=0).repair is None


def test_a_robot_squeezed_between_two_is_not_moved_closer_to_either():
    # robot 0 collides with 1 (to its right, pointing back at it) and with 2 (below, pointing up):
    # turning either way brings it closer to one of them, so the repair moves 1 and 2 instead
    data = {"layout": {"kind": "points", "xy": [[0, 0], [20, 0], [0, -18]]},
            "kinematics": {"kind": "rotary", "arm": 15.0, "steps": 24}, "collision": {"buffer": 2.0},
            "start": [1, 12, 18], "target": [12, 0, 6]}
    problem = parse_problem_any_start(data)
    assert start_collisions(problem) == [(0, 1), (0, 2)]
    result = repair_start(problem)
    assert result.repair.moved == (1, 2) and result.repair.lower_bound == 1 and not result.repair.minimum
    plan = Plan("complete", result.configurations + [problem.target], repair=result.repair)
    assert not [p for p in validate_plan(problem, plan).problems if p.startswith("repair")]
