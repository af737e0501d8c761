"""Targets that cannot be reached together (issue 37): each conflict checked independently.

Static pairs against the oracle's geometry, planned groups against the oracle's exhaustive
search of the group's robots alone (:mod:`supcoord.testing.oracle`).
"""

from __future__ import annotations

import csv
import io
import itertools

import numpy as np
import pytest

from supcoord.errors import InputError
from supcoord.planning.conflicts import (CSV_COLUMNS, conflicts_csv, find_conflicts, planned_conflicts,
                                         static_conflicts, sub_problem, target_names)
from supcoord.planning import solve
from supcoord.problems import parse_problem, random_problem
from supcoord.testing.oracle import oracle_solve
from supcoord.testing.oracle.distance import segment_gap
from supcoord.testing.oracle.oracle_model import OracleProblem
from supcoord.testing.oracle.tight_problems import tight_problem

ROTARY = {"kinematics": {"kind": "rotary", "arm": 15.0, "steps": 12}, "collision": {"buffer": 2.0}}


def oracle_pairs(data: dict, conf: list[int]) -> set[tuple[int, int]]:
    """Colliding pairs of a rotary configuration, by the oracle's geometry."""
    prob = OracleProblem.from_json(dict(data, start=conf, target=conf))
    ends = [prob.arm_of(p).segment(np.array([conf[p]])) for p in range(prob.n)]
    return {(a, b) for a, b in itertools.combinations(range(prob.n), 2)
            if float(segment_gap(ends[a][0] + prob.bases[a], ends[a][1] + prob.bases[a],
                                 ends[b][0] + prob.bases[b], ends[b][1] + prob.bases[b])) < prob.need(a, b)}


def test_static_pairs_are_exactly_the_pairs_colliding_at_target():
    rng = np.random.default_rng(3)
    found = 0
    for _ in range(30):
        data = dict(ROTARY, layout={"kind": "hex", "rings": 1, "pitch": 22.4}, start=[0] * 7,
                    target=rng.integers(0, 12, 7).tolist())
        problem = parse_problem(data, check_collisions=False)
        static = static_conflicts(problem)
        assert all(c.kind == "static-pair" for c in static)
        claimed = {c.robots for c in static}
        assert claimed == oracle_pairs(data, data["target"]), data
        found += len(claimed)
    assert found > 10


def test_a_target_on_an_obstacle_or_a_held_robot_is_named_alone():
    data = dict(ROTARY, layout={"kind": "points", "xy": [[0, 0], [22.4, 0], [60, 0]],
                                "obstacles": [{"xy": [0, 15], "buffer": 1.0}]},
                start=[0, 6, 0], target=[9, 6, 6], fixed=[1])
    problem = parse_problem(data, check_collisions=False)
    kinds = sorted((c.kind, c.robots) for c in static_conflicts(problem))
    assert kinds == [("static-held", (0,)), ("static-obstacle", (0,))] or kinds == [("static-obstacle", (0,))]
    # robot 0 at position 9 points up (θ = −270° = +90°) onto the obstacle at (0, 15)
    assert ("static-obstacle", (0,)) in kinds


def random_field(seed: int) -> dict:
    """Four rotary robots close together, random collision-free start and target."""
    bases = np.array([[0, 0], [20, 0], [10, 17], [30, 17]], float)
    return random_problem(bases, ROTARY["kinematics"], 2.0, seed=seed).to_json()


def test_every_planned_group_has_no_plan_by_the_oracle():
    checked = 0
    for seed in (0, 3, 10, 22):  # tight fields with a group (seeds ending in 7 are ties: left out)
        data = tight_problem(seed, kind="rotary", n=4)
        problem = parse_problem(data)
        report = planned_conflicts(problem, max_groups=4)
        assert report.searched == "complete"
        for c in report.conflicts:
            assert c.kind == "planned-group"
            assert oracle_solve(data, members=list(c.robots)) is None, (seed, c)
            checked += 1
        left = [p for p in range(problem.n) if not any(p in c.robots for c in report.conflicts)]
        if left:  # the robots left after the groups have a plan
            assert oracle_solve(data, members=left) is not None, (seed, left)
    assert checked >= 4, f"only {checked} planned groups met"


def test_sub_problem_keeps_the_members_geometry():
    problem = parse_problem(random_field(1))
    sub = sub_problem(problem, [1, 3])
    assert sub.n == 2 and np.array_equal(sub.bases, problem.bases[[1, 3]])
    assert np.array_equal(sub.start, problem.start[[1, 3]]) and np.array_equal(sub.target, problem.target[[1, 3]])
    assert solve(sub, improve=0).status in ("complete", "infeasible")


def test_csv_has_a_header_and_one_row_per_conflict():
    data = dict(ROTARY, layout={"kind": "points", "xy": [[0, 0], [20, 0]]}, start=[6, 0], target=[0, 6])
    problem = parse_problem(data, check_collisions=False)
    report = find_conflicts(problem)
    rows = list(csv.DictReader(io.StringIO(conflicts_csv(report.conflicts))))
    assert tuple(rows[0]) == CSV_COLUMNS
    assert [(r["kind"], r["size"], r["robots"]) for r in rows] == [("static-pair", "2", "0 1")]
    assert rows[0]["targets"] == " ".join(target_names(problem))


def test_target_ids_name_the_targets_and_are_checked():
    data = dict(ROTARY, layout={"kind": "points", "xy": [[0, 0], [20, 0]]}, start=[6, 0], target=[0, 6],
                target_ids=["t-17", 42])
    problem = parse_problem(data, check_collisions=False)
    assert target_names(problem) == ["t-17", "42"]
    assert find_conflicts(problem).conflicts[0].targets == ("t-17", "42")
    bad = parse_problem(dict(data, target_ids=["a b", "c"]), "f.json", check_collisions=False)
    with pytest.raises(InputError, match="f.json: target_ids must be a list of 2 strings"):
        target_names(bad)
    with pytest.raises(InputError, match="max_groups"):
        find_conflicts(problem, max_groups=-1)
