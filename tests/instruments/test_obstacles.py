"""Fixed obstacles, robots held in place (offline) and the real SDSS-V woks as layouts.

Obstacle distances here are computed by a point-to-segment routine written in this file,
not by supcoord's geometry.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import supcoord
from supcoord.errors import FormatError, InputError
from supcoord.planning import Local
from supcoord.problems.problem import parse_problem

pytestmark = pytest.mark.timeout(120)

KIN = {"kind": "alpha-beta", "alpha": 7.4, "beta": 15.0, "alpha_steps": 12, "beta_steps": 7, "beta_range": [0, 180]}


def _two(obstacles, start, target, **extra):
    data = {"layout": {"kind": "points", "xy": [[0.0, 0.0], [40.0, 0.0]], "obstacles": obstacles},
            "kinematics": KIN, "collision": {"buffer": 1.0}, "start": {"alpha_beta_deg": start},
            "target": {"alpha_beta_deg": target}, **extra}
    return parse_problem(data, "o.json")


def _point_segment(p, a, b):
    p, a, b = (np.asarray(v, float) for v in (p, a, b))
    ab = b - a
    t = 0.0 if not ab.any() else min(1.0, max(0.0, float(np.dot(p - a, ab) / np.dot(ab, ab))))
    return float(np.linalg.norm(p - (a + t * ab)))


def _beta_arm(base, a_deg, b_deg, alpha=7.4, beta=15.0):
    a, b = math.radians(a_deg), math.radians(b_deg)
    elbow = np.asarray(base) + alpha * np.array([math.cos(a), math.sin(a)])
    return elbow, elbow + beta * np.array([math.cos(a + b), math.sin(a + b)])


def _clearance_along(problem, plan, robot, point, samples=200):
    """Least distance from ``point`` to the robot's beta arm along the plan (linear in angle)."""
    ang = problem.angles_deg(np.array(plan.configurations))[:, robot]
    best = math.inf
    for a0, a1 in zip(ang[:-1], ang[1:]):
        step = a1 - a0
        step[0] = (step[0] + 180.0) % 360.0 - 180.0  # alpha wraps: the short way round
        for t in np.linspace(0, 1, samples):
            e, f = _beta_arm(problem.bases[robot], *(a0 + t * step))
            best = min(best, _point_segment(point, e, f))
    return best


def test_a_robot_goes_round_an_obstacle():
    p = _two([{"xy": [0.0, 15.0], "buffer": 1.0}], [[0.0, 0.0], [0.0, 180.0]], [[180.0, 0.0], [0.0, 180.0]])
    assert set(p.unary()) == {0}
    plan = supcoord.solve(p)
    assert plan.status == "complete"
    alpha = p.angles_deg(np.array(plan.configurations))[:, 0, 0]
    assert np.all((alpha >= 180.0) | (alpha == 0.0))  # clockwise, under the obstacle
    assert _clearance_along(p, plan, 0, [0.0, 15.0]) >= 2.0
    free = _two([], [[0.0, 0.0], [0.0, 180.0]], [[180.0, 0.0], [0.0, 180.0]])
    assert not free.unary()


@pytest.mark.parametrize("options", [{}, {"route": Local(descent="none")}, {"route": "monolithic"}, {"improve": 0}])
def test_a_robot_without_neighbours_still_goes_round_an_obstacle(options):
    # 200 mm apart: no neighbour pair, so no pair table carries robot 0's obstacle; the
    # short way round (alpha 0 -> 180 counter-clockwise) passes it
    p = parse_problem({"layout": {"kind": "points", "xy": [[0.0, 0.0], [200.0, 0.0]],
                                  "obstacles": [{"xy": [0.0, 15.0], "buffer": 1.0}]},
                       "kinematics": KIN, "collision": {"buffer": 1.0},
                       "start": {"alpha_beta_deg": [[0.0, 0.0], [0.0, 180.0]]},
                       "target": {"alpha_beta_deg": [[150.0, 0.0], [0.0, 180.0]]}}, "o.json")
    assert len(p.pairs) == 0 and set(p.unary()) == {0}
    plan = supcoord.solve(p, **options)
    assert plan.status == "complete" and supcoord.validate_plan(p, plan).valid
    alpha = p.angles_deg(np.array(plan.configurations))[:, 0, 0]
    assert not np.any((alpha > 60.0) & (alpha < 150.0))  # never past the obstacle at 90 deg
    assert _clearance_along(p, plan, 0, [0.0, 15.0]) >= 2.0


@pytest.mark.slow  # plans on the real wok's obstacles: seconds
def test_obstacles_on_both_sides_make_it_infeasible():
    # the elbow circle (radius 7.4) passes within 0.6 mm of both: alpha can turn neither way
    p = _two([{"xy": [0.0, 8.0], "buffer": 1.0}, {"xy": [0.0, -8.0], "buffer": 1.0}],
             [[0.0, 0.0], [0.0, 180.0]], [[180.0, 0.0], [0.0, 180.0]])
    plan = supcoord.solve(p, when_incomplete="infeasible")
    assert plan.status == "infeasible" and plan.reason


def test_an_offline_robot_never_moves_and_the_others_avoid_it():
    # robot 1 held with its arm 2.5 mm above robot 0's fibre: robot 0 must turn away below it
    p = _two([], [[0.0, 0.0], [90.0, 180.0]], [[180.0, 0.0], [90.0, 180.0]], offline={"1": [160.0, 20.0]})
    assert p.held == {1: tuple(int(v) for v in p.start[1])}
    assert np.array_equal(p.angles_deg(p.start)[1], [160.0, 20.0])
    plan = supcoord.solve(p)
    assert plan.status == "complete"
    confs = np.array(plan.configurations)
    assert np.all(confs[:, 1] == confs[0, 1])
    assert p.to_json()["offline"] == {"1": [160.0, 20.0]}
    assert supcoord.validate_plan(p, plan).valid
    with pytest.raises(InputError, match=r"offline: '7' is not a robot index in \[0, 1\]"):
        _two([], [[0.0, 0.0], [0.0, 180.0]], [[180.0, 0.0], [0.0, 180.0]], offline={"7": [0, 0]})


def test_obstacle_errors_are_one_line():
    with pytest.raises(InputError, match=r"start: robot 0 is 0.000 mm from obstacle 0, less than their buffers' sum"):
        _two([{"xy": [10.0, 0.0], "buffer": 1.0}], [[0.0, 0.0], [0.0, 180.0]], [[180.0, 0.0], [0.0, 180.0]])
    with pytest.raises(FormatError, match=r"layout.obstacles\[0\] must be"):
        _two([{"xy": [1, 2], "segment": [[0, 0], [1, 1]]}], [[0.0, 0.0], [0.0, 180.0]], [[180.0, 0.0], [0.0, 180.0]])
    with pytest.raises(InputError, match=r"layout.obstacles\[0\].buffer must be in \[0, 1e6\] mm, got -1"):
        _two([{"xy": [1, 2], "buffer": -1}], [[0.0, 0.0], [0.0, 180.0]], [[180.0, 0.0], [0.0, 180.0]])


def test_unary_tables_are_folded_into_every_pair_table():
    p = _two([{"xy": [0.0, 15.0], "buffer": 1.0}], [[0.0, 0.0], [0.0, 180.0]], [[180.0, 0.0], [0.0, 180.0]])
    U, V = p.unary()[0]
    t = p.tables()
    assert np.array_equal(t.static(0), t.static(0) | U[:, None]) and U.any()
    sw = t.swept(0, 0)
    assert np.all(sw[V] if sw.ndim == 2 else sw[np.broadcast_to(V[:, :, None], sw.shape)])
    sim = t.simultaneous(0)
    assert np.all(sim[0][np.broadcast_to(U[None, :, None], sim[0].shape)])


@pytest.mark.slow  # reads a 500-robot wok problem: seconds
@pytest.mark.parametrize("name", ["sdss-v-apo", "sdss-v-lco"])
def test_the_real_woks_are_layouts(name):
    n = 500
    data = {"layout": {"kind": "instrument", "name": name}, "kinematics": {"alpha_steps": 7, "beta_steps": 4},
            "start": {"alpha_beta_deg": [[10.0, 170.0]] * n}, "target": {"alpha_beta_deg": [[10.0, 170.0]] * n}}
    p = parse_problem(data, "w.json")
    assert p.n == 500 and len(p.obstacles) == 66 and len(p.robot_kinematics) == 500
    assert np.array_equal(p.angles_deg(p.start), np.full((500, 2), [10.0, 170.0]))
    assert p.joint_rules and len(p.joint_rules) == 42
    assert p.to_json()["layout"] == {"kind": "instrument", "name": name}
    assert "alpha" not in p.to_json()["kinematics"]


@pytest.mark.slow  # reads the 500-robot wok problems: seconds
def test_instrument_errors_name_field_and_value():
    base = {"start": {"alpha_beta_deg": [[10.0, 170.0]] * 500}, "target": {"alpha_beta_deg": [[10.0, 170.0]] * 500}}
    with pytest.raises(InputError, match=r"layout.name: unknown instrument 'sdss-v-xyz' \(known: sdss-v-apo, sdss-v-lco\)"):
        parse_problem({"layout": {"kind": "instrument", "name": "sdss-v-xyz"}, **base}, "w.json")
    with pytest.raises(InputError, match=r"kinematics.alpha cannot be set for instrument 'sdss-v-apo'"):
        parse_problem({"layout": {"kind": "instrument", "name": "sdss-v-apo"}, "kinematics": {"alpha": 7.4}, **base},
                      "w.json")
    # every robot folded at alpha 0, beta 0 points its arm at a neighbour or a fiducial
    bad = dict(base, start={"alpha_beta_deg": [[0.0, 0.0]] * 500})
    with pytest.raises(InputError, match=r"w.json: start"):
        parse_problem({"layout": {"kind": "instrument", "name": "sdss-v-apo"}, **bad}, "w.json")


def test_the_obstacle_margin_can_differ_from_the_robots_margin():
    # robot 0's beta tip at (22.4, 0) mm; an obstacle 5.05 mm above it: clear by 0.05 mm of 1 + 4
    obstacle = [{"xy": [22.4, 5.05], "buffer": 4.0}]
    start, target = [[0.0, 0.0], [0.0, 180.0]], [[0.0, 0.0], [90.0, 180.0]]
    with pytest.raises(InputError, match="obstacle 0"):
        _two(obstacle, start, target, collision={"buffer": 1.0, "margin": 0.1})  # the margin applies to both
    p = _two(obstacle, start, target, collision={"buffer": 1.0, "margin": 0.1, "obstacle_margin": 0.0})
    assert p.to_json()["collision"] == {"buffer": 1.0, "margin": 0.1, "obstacle_margin": 0.0}
    q = parse_problem(p.to_json())
    assert np.allclose(q.buffers, p.buffers) and np.allclose(q.obstacle_buffers, p.obstacle_buffers)
    assert np.allclose(p.buffers[0] + p.obstacle_buffers[0], 5.0) and np.allclose(p.buffers.sum(), 2.1)
    with pytest.raises(InputError, match="obstacle_margin"):
        _two(obstacle, start, target, collision={"buffer": 1.0, "obstacle_margin": -1})


@pytest.mark.timeout(120)
def test_a_robot_with_an_obstacle_moving_two_joints_across_the_wrap_is_scheduled():
    # robot 0 (wrapping alpha, a fiducial beside it) turns alpha across 360 -> 0 and beta in
    # one step of the schedule: its motion from the position before the wrap must be checked
    # (once an internal ValueError: an index one past the last alpha position)
    from supcoord.testing.oracle.tight_problems import tight_angle_problem

    data = tight_angle_problem(98, n=6, max_product=10**9)
    data["layout"]["obstacles"] = [{"xy": [3.0, 14.0], "buffer": 1.0}]
    p = parse_problem(data)
    assert 0 in p.unary()
    for options in ({"improve": 0, "finer": None}, {}):
        plan = supcoord.solve(p, **options)
        assert plan.status == "complete" and supcoord.validate_plan(p, plan).valid
