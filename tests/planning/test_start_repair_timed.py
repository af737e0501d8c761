"""Timed plans (``speed``) from a colliding start: the repair phase first, then the plan (issue 37).

The motion is checked here independently of the planner and of the validator: the
trajectories are sampled densely in time and every pair's distance computed with the
oracle's geometry (:mod:`supcoord.testing.oracle`).  The rule: a pair that collides at
``t = 0`` (a given of the input) never comes closer than it is there, and only robots of
``repair.moved`` move, until every start collision is resolved; no other pair ever collides.
"""

from __future__ import annotations

import copy
import itertools

import numpy as np

from supcoord.planning.start_repair import solve_any_start
from supcoord.problems import Plan, validate_plan
from supcoord.problems.repair_phase import Repair, parse_problem_any_start
from supcoord.testing.oracle.distance import segment_gap
from supcoord.testing.oracle.oracle_model import OracleProblem

HEX = {"layout": {"kind": "hex", "rings": 1, "pitch": 22.4},
       "kinematics": {"kind": "rotary", "arm": 15.0, "steps": 12}, "collision": {"buffer": 2.0}}
#: a sampled check cannot see a touch between samples: slack (mm) of the sampled distances
SLACK = 1e-6


def gaps(prob: OracleProblem, q: np.ndarray) -> np.ndarray:
    """``(S, P)``: each pair's distance minus its buffers' sum (mm) at fractional positions ``q`` ``(S, N)``."""
    ends = [prob.arm_of(p).segment(q[:, p:p + 1]) for p in range(prob.n)]
    out = []
    for a, b in itertools.combinations(range(prob.n), 2):
        d = segment_gap(ends[a][0] + prob.bases[a], ends[a][1] + prob.bases[a],
                        ends[b][0] + prob.bases[b], ends[b][1] + prob.bases[b])
        out.append(np.asarray(d, float).ravel() - prob.need(a, b))
    return np.array(out).T


def sampled_positions(prob: OracleProblem, trajectories: list[dict], samples: int = 600) -> tuple[np.ndarray, ...]:
    """Times (s) and the robots' fractional positions ``(S, N)`` there (oracle's angle convention)."""
    times = np.unique(np.concatenate([np.linspace(0.0, max(float(np.asarray(t["theta"])[-1, 0]) for t in trajectories),
                                                  samples)] + [np.asarray(t["theta"])[:, 0] for t in trajectories]))
    q = np.empty((len(times), prob.n))
    for p, t in enumerate(trajectories):
        arm = prob.arm_of(p)
        deg = np.interp(times, np.asarray(t["theta"])[:, 0], np.asarray(t["theta"])[:, 1])
        q[:, p] = (np.radians(deg) - arm.zero[0]) / arm.per_step[0]
    return times, q


def colliding_case(rng: np.random.Generator) -> dict:
    """A hex field of 7 rotary robots whose random start collides and whose random target does not."""
    prob = OracleProblem.from_json(dict(HEX, start=[0] * 7, target=[0] * 7))
    while True:
        start, target = rng.integers(0, 12, 7), rng.integers(0, 12, 7)
        if (gaps(prob, start[None].astype(float)) < 0).any() and not (gaps(prob, target[None].astype(float)) < 0).any():
            return dict(HEX, start=start.tolist(), target=target.tolist())


def test_timed_plans_from_colliding_starts_separate_the_colliding_pairs_first():
    rng = np.random.default_rng(37)
    done = 0
    while done < 2:
        data = colliding_case(rng)
        problem = parse_problem_any_start(data)
        plan = solve_any_start(problem, improve=0, speed=30.0)
        if plan.status != "complete":
            continue
        done += 1
        assert plan.repair is not None and plan.trajectories is not None
        check = validate_plan(problem, plan)
        assert check.valid, check.problems
        assert abs(check.motion_time_s - plan.motion_time_s) < 1e-9
        prob = OracleProblem.from_json(data)
        times, q = sampled_positions(prob, plan.trajectories)
        assert np.allclose(np.mod(q[0], 12), data["start"]) and np.allclose(np.mod(q[-1], 12), data["target"])
        g = gaps(prob, q)
        colliding = g[0] < 0
        free = np.nonzero(~(g < 0).any(axis=1))[0][0]  # the first sample with no collision
        assert free > 0 and times[free] <= plan.stats["repair_motion_s"] + 1e-9
        assert np.all(g[:free, colliding] >= g[0, colliding] - SLACK)  # never closer than at the start
        assert np.all(g[:, ~colliding] >= -SLACK) and np.all(g[free:] >= -SLACK)  # no collision created
        still = [p for p in range(prob.n) if p not in plan.repair.moved]
        assert np.allclose(q[:free, still], q[0, still])  # only the robots the repair moves


TWO = {"layout": {"kind": "points", "xy": [[0, 0], [20, 0]]},
       "kinematics": {"kind": "rotary", "arm": 15.0, "steps": 24}, "collision": {"buffer": 2.0}}


def two_robot_timed(path0: list[int]) -> tuple:
    """Robot 0 along ``path0`` (positions; 24 per turn, position 1 is −15°, one per second)
    while robot 1 points at it; the path but its last step is the repair phase."""
    problem = parse_problem_any_start(dict(TWO, start=[path0[0], 12], target=[path0[-1], 12]))
    confs = [np.array([[q], [12]]) for q in path0]
    deg = np.unwrap(np.radians([problem.angles_deg(c)[0, 0] for c in confs]), period=2 * np.pi)
    trajs = [{"theta": np.array([[float(t), float(np.degrees(a))] for t, a in enumerate(deg)])},
             {"theta": np.array([[0.0, problem.angles_deg(confs[0])[1, 0]], [len(path0) - 1.0, problem.angles_deg(confs[0])[1, 0]]])}]
    plan = Plan("complete", confs, repair=Repair((0,), len(path0) - 2, True, 1), trajectories=trajs,
                motion_time_s=len(path0) - 1.0)
    return problem, plan


def test_validator_accepts_timed_repair_that_moves_the_pair_apart():
    problem, plan = two_robot_timed([1, 2, 3, 4, 5, 6])
    check = validate_plan(problem, plan)
    assert check.valid, check.problems
    assert check.motion_time_s == 5.0


def test_validator_rejects_timed_repair_that_brings_the_pair_closer():
    problem, plan = two_robot_timed([1, 0, 23, 22, 21, 20, 19, 18])
    # the same trajectories without configurations of the repair rule's own: only they break it
    check = validate_plan(problem, plan)
    assert not check.valid
    assert any(p.startswith("trajectories: repair step 0->1") and "closer than" in p for p in check.problems), \
        check.problems


def test_validator_rejects_timed_plans_that_break_the_repair_rule():
    data = dict(HEX, start=[0, 0, 0, 0, 0, 0, 0], target=[0] * 7)
    rng = np.random.default_rng(5)
    while True:
        data = colliding_case(rng)
        problem = parse_problem_any_start(data)
        plan = solve_any_start(problem, improve=0, speed=30.0)
        if plan.status == "complete":
            break
    assert validate_plan(problem, plan).valid
    still = next(p for p in range(problem.n) if p not in plan.repair.moved)
    t_r = plan.stats["repair_motion_s"]
    # a robot outside repair.moved moves during the repair phase
    bad = copy.deepcopy(plan)
    a = np.asarray(bad.trajectories[still]["theta"])
    bad.trajectories[still]["theta"] = np.vstack([a[:1], [[t_r / 2, a[0, 1] + 10.0]], [[t_r, a[0, 1]]],
                                                  a[(a[:, 0] > t_r)]])
    check = validate_plan(problem, bad)
    assert any(p.startswith("trajectories: repair step") and f"positioners [{still}] move" in p
               for p in check.problems), check.problems
    # the plan's motion starts with the repair (not after it): the trajectories never reach its end
    early = copy.deepcopy(plan)
    for robot in early.trajectories:
        t = np.asarray(robot["theta"])
        robot["theta"] = np.vstack([t[:1], t[t[:, 0] > t_r] - [t_r, 0.0]]) if len(t[t[:, 0] > t_r]) else t
    early.motion_time_s = plan.motion_time_s - t_r
    assert not validate_plan(problem, early).valid
    # without its repair field the same timed plan starts in collision
    assert not validate_plan(problem, Plan("complete", plan.configurations, trajectories=plan.trajectories,
                                           motion_time_s=plan.motion_time_s)).valid
