"""The validator's small helpers against independent opinions: a step the short way round
on every lattice size (odd, even, two positions), robots that differ in wrapping, angles
given besides the configurations that disagree with them, and the wording of a bad event.

Each test targets a class of input that ``tests/problems/test_validate.py`` never gives
(mutants of ``_step_delta``, ``_wrapping``, ``_angles_off``, ``_check_angles_match`` and
``_check_events`` survived it)."""

from __future__ import annotations

import copy
import dataclasses

import numpy as np
import pytest

from supcoord.geometry.alpha_beta import AlphaBeta
from supcoord.problems import Plan, parse_problem, plan_from_moves, validate_plan
from supcoord.problems.validate import ANGLE_TOL, _angles_off, _step_delta, _wrapping

from problem_cases import THREE, oracle_plan_moves

TWO_AB = {
    "layout": {"kind": "points", "xy": [[0, 0], [60.0, 0]]},
    "kinematics": {"kind": "alpha-beta", "alpha": 7.4, "beta": 15.0, "alpha_steps": 12, "beta_steps": 7,
                   "beta_range": [0, 180]},
    "collision": {"buffer": 2.0},
    "start": [[0, 6], [6, 6]],
    "target": [[6, 0], [0, 0]],
}


def _short_way_oracle(a: int, b: int, n: int, wraps: bool) -> tuple[int, bool]:
    """The step ``a -> b`` on a joint of ``n`` positions (by enumeration): the signed number of
    positions of the shorter way round where the joint wraps (a tie of a half turn: the
    negative way; two positions: the positive way), the literal difference where it does
    not; and whether that is a jump of more than one position."""
    if not wraps:
        d = b - a
    else:
        ways = [d for d in range(-n, n + 1) if (a + d - b) % n == 0]
        d = min(ways, key=lambda d: (abs(d), d if n != 2 else -d))
    return d, abs(d) > 1


@pytest.mark.parametrize("n", [2, 3, 4, 5, 6, 7])
@pytest.mark.parametrize("wraps", [True, False])
def test_step_delta_is_the_short_way_round_on_every_lattice_size(n, wraps):
    pairs = [(a, b) for a in range(n) for b in range(n)]
    c0 = np.array([[a, 0] for a, _ in pairs])
    c1 = np.array([[b, 0] for _, b in pairs])
    steps, wrap = np.array([n, 3]), np.array([wraps, False])
    problems: list[str] = []
    delta = _step_delta(c0, c1, steps, wrap, 4, problems)
    want = [_short_way_oracle(a, b, n, wraps) for a, b in pairs]
    jumps = [i for i, (_, jump) in enumerate(want) if jump]
    assert delta[:, 1].tolist() == [0] * len(pairs)
    assert delta[:, 0].tolist() == [max(-1, min(1, d)) for d, _ in want]  # a jump is clipped to one step
    if jumps:
        shown = ", ".join(str(i) for i in jumps[:10]) + (f", ... ({len(jumps)} in all)" if len(jumps) > 10 else "")
        assert problems == [f"step 4->5: positioners {shown} move a joint by more than one step"]
    else:
        assert problems == []


def _differing_robots():
    """Two alpha-beta robots far apart: robot 0's alpha joint wraps, robot 1's has hard stops."""
    problem = parse_problem(copy.deepcopy(TWO_AB), "two.json")
    kins = [AlphaBeta(7.4, 15.0, 12, 7, (0.0, 180.0)), AlphaBeta(7.4, 15.0, 12, 7, (0.0, 180.0), alpha_range=(0, 330))]
    return dataclasses.replace(problem, robot_kinematics=kins, _tables=None, _pairs=None)


def test_wrapping_is_each_robots_own():
    problem = _differing_robots()
    assert _wrapping(problem).tolist() == [[True, False], [False, False]]
    shared = parse_problem(copy.deepcopy(TWO_AB), "two.json")
    assert _wrapping(shared).tolist() == [[True, False], [True, False]]


def test_angles_off_by_a_turn_are_the_same_only_where_the_robot_wraps():
    problem = _differing_robots()
    want = np.array([[10.0, 20.0], [10.0, 20.0]])
    turned = want + [[360.0, 0.0], [360.0, 0.0]]
    assert _angles_off(problem, turned, want).tolist() == [1]
    assert _angles_off(problem, want + [[0.0, 360.0], [0.0, 0.0]], want).tolist() == [0]  # beta never wraps
    assert _angles_off(problem, want + [[-360.0, 0], [0, 0]], want).tolist() == []  # 1: no difference
    # the poses of one robot (rows = the robot): three poses, each a turn off in alpha
    poses = np.array([[10.0, 20.0], [40.0, 50.0], [70.0, 80.0]])
    off_a_turn = poses + [360.0, 0.0]
    assert _angles_off(problem, off_a_turn, poses, rows=0).tolist() == []
    assert _angles_off(problem, off_a_turn, poses, rows=1).tolist() == [0, 1, 2]
    # within the tolerance and just beyond it
    assert _angles_off(problem, poses + [0.5 * ANGLE_TOL, 0.0], poses, rows=1).tolist() == []
    assert _angles_off(problem, poses + [0.0, 3 * ANGLE_TOL], poses, rows=0).tolist() == [0, 1, 2]
    # exactly ANGLE_TOL off agrees ("more than ANGLE_TOL" differs): from 0 the difference is exact
    zero = np.zeros((1, 2))
    assert (zero + [ANGLE_TOL, 0.0] - zero)[0, 0] == ANGLE_TOL
    assert _angles_off(problem, zero + [ANGLE_TOL, 0.0], zero, rows=1).tolist() == []
    assert _angles_off(problem, zero + [0.0, -ANGLE_TOL], zero, rows=1).tolist() == []


@pytest.fixture(scope="module")
def three():
    return parse_problem(copy.deepcopy(THREE), "three.json")


@pytest.fixture(scope="module")
def three_plan(three):
    return plan_from_moves(three, oracle_plan_moves(three))


def test_angles_given_besides_the_configurations_must_be_theirs(three, three_plan):
    confs = three_plan.configurations
    angles = [three.angles_deg(c) for c in confs]
    r = validate_plan(three, dataclasses.replace(three_plan, angles_deg=angles))
    assert r.valid, r.problems
    turned = [a + 360.0 for a in angles]  # the rotary joint wraps: a turn off is the same angle
    assert validate_plan(three, dataclasses.replace(three_plan, angles_deg=turned)).valid
    k = len(confs) // 2
    wrong = [a.copy() for a in angles]
    wrong[k][2, 0] += 1.0
    wrong[k + 1][0, 0] -= 1.0
    r = validate_plan(three, dataclasses.replace(three_plan, angles_deg=wrong))
    assert not r.valid
    # the first pose that differs is reported, once, with its robot
    assert [p for p in r.problems if p.startswith("angles_deg")] == [
        f"angles_deg[{k}] are not the angles of configurations[{k}] (positioners 2)"]
    r = validate_plan(three, dataclasses.replace(three_plan, angles_deg=angles[:-1]))
    assert f"angles_deg has {len(confs) - 1} poses but configurations has {len(confs)}" in r.problems


@pytest.mark.parametrize("case,event,message", [
    ("three", "v3", "events[{k}] = 'v3' is not a move event of this rotary problem with 3 positioners "
                    "(vP, wP, P in [0, 2])"),
    ("ab", "v0", "events[{k}] = 'v0' is not a move event of this alpha-beta problem with 2 positioners "
                 "(vaP, waP, vbP, wbP, P in [0, 1])"),
])
def test_a_bad_event_is_named_with_the_events_of_its_problem(case, event, message, three, three_plan):
    if case == "three":
        problem, plan = three, three_plan
    else:
        problem = parse_problem(copy.deepcopy(TWO_AB), "two.json")
        plan = plan_from_moves(problem, oracle_plan_moves(problem))
    k = len(plan.events) // 2
    events = plan.events[:k] + [event] + plan.events[k:]
    r = validate_plan(problem, Plan("complete", plan.configurations, events=events))
    assert not r.valid
    assert message.format(k=k) in r.problems


# -- classes of input the sampled survivors (seed 0) showed untested: the segment distance
# beyond a segment's end, offline robots, joint rules and fixed obstacles --------------------


def _point_segment(p, a, b):
    """Distance from point ``p`` to segment ``[a, b]`` (the textbook projection, clamped)."""
    ab = b - a
    t = 0.0 if not ab.any() else min(1.0, max(0.0, float(np.dot(p - a, ab) / np.dot(ab, ab))))
    return float(np.linalg.norm(p - (a + t * ab)))


def _cross(p1, q1, p2, q2):
    def orient(a, b, c):
        return np.sign((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
    return orient(p1, q1, p2) * orient(p1, q1, q2) < 0 and orient(p2, q2, p1) * orient(p2, q2, q1) < 0


def test_segment_distance_is_the_least_end_point_distance_of_segments_that_do_not_cross():
    """Two segments that do not cross are nearest at an end point of one of them, so the
    distance is the least of four point-to-segment distances (0 where they cross)."""
    from supcoord.problems.validate import segment_distance_ericson

    rng = np.random.default_rng(3)
    pts = rng.uniform(-10, 10, size=(400, 4, 2))
    pts[::7, 1] = pts[::7, 0] + 3 * (pts[::7, 3] - pts[::7, 2])  # nearly parallel, different lengths
    got = segment_distance_ericson(pts[:, 0], pts[:, 1], pts[:, 2], pts[:, 3])
    for (p1, q1, p2, q2), d in zip(pts, got):
        want = 0.0 if _cross(p1, q1, p2, q2) else min(
            _point_segment(p1, p2, q2), _point_segment(q1, p2, q2), _point_segment(p2, p1, q1),
            _point_segment(q2, p1, q1))
        assert d == pytest.approx(want, abs=1e-9)


def _standing(problem, conf):
    """``problem`` from ``conf`` to ``conf`` and the plan that stays there."""
    c = np.array(conf)
    return dataclasses.replace(problem, start=c, target=c.copy()), Plan("complete", [c, c.copy()])


def test_an_offline_robot_that_moves_is_refused_and_one_that_stays_is_not():
    p = parse_problem(TWO_AB)
    start = np.array([[0, 6], [6, 6]])
    moved = start.copy()
    moved[1, 0] = 7
    held = dataclasses.replace(p, start=start, target=moved, held={1: (6, 6)})
    res = validate_plan(held, Plan("complete", [start, moved]))
    assert "offline positioners 1 move" in " ".join(res.problems) and not res.valid
    still, plan = _standing(dataclasses.replace(p, held={1: (6, 6)}), start)
    assert validate_plan(still, plan).valid


@pytest.mark.parametrize("alpha_pos,beta_pos,forbidden", [(6, 1, True), (6, 4, False), (0, 1, False)])
def test_a_joint_rule_forbids_the_half_plane_it_names(alpha_pos, beta_pos, forbidden):
    """Rule (c0, c1) = (0, 0.5) on robot 0: beta < 0.5 alpha (degrees) is forbidden.  On the
    12 x 7 lattice alpha = 30 alpha_pos and beta = 30 beta_pos: (180, 30) is inside
    (30 < 90), (180, 120) and (0, 30) are not."""
    p = dataclasses.replace(parse_problem(TWO_AB), joint_rules={0: (0.0, 0.5)})
    one, plan = _standing(p, [[alpha_pos, beta_pos], [6, 6]])
    res = validate_plan(one, plan)
    assert ("forbidden region of their joint rule" in " ".join(res.problems)) == forbidden
    assert res.valid == (not forbidden)


def test_a_robot_lying_on_a_fixed_obstacle_is_a_collision():
    """A segment through robot 0's base: its first arm starts there (distance 0); the same
    segment 200 mm away touches nothing."""
    p = parse_problem(TWO_AB)
    for seg, hit in (([[-5.0, 0.0], [5.0, 0.0]], True), ([[200.0, 200.0], [205.0, 200.0]], False)):
        q = dataclasses.replace(p, obstacles=np.array([seg]), obstacle_buffers=np.array([0.5]))
        one, plan = _standing(q, [[0, 6], [6, 6]])
        assert validate_plan(one, plan).valid == (not hit)


# --- survivors of the validator's samples (seeds 0 and 1) once its selection had the angle,
# trajectory and repair plans: the bases it checks, the wording of a trajectory plan's
# problems, the angles of a repaired plan -------------------------------------------------

def test_the_bases_checked_are_the_layouts_points_not_the_problems_copy():
    # two arms stretched at each other (alpha 0° and 180°, beta 0°) 30 mm apart: 22.4 + 22.4 > 30
    data = dict(copy.deepcopy(TWO_AB), start=[[0, 0], [6, 0]], target=[[0, 0], [6, 0]])
    data["layout"]["xy"] = [[0, 0], [30.0, 0]]
    problem = parse_problem(data, check_collisions=False)
    moved = dataclasses.replace(problem, bases=np.array([[0.0, 0.0], [100.0, 0.0]]))
    r = validate_plan(moved, Plan("complete", [problem.start]))
    assert not r.valid and r.problems[0].startswith("configuration 0: positioners 0 and 1 collide")


def test_the_collision_of_trajectories_given_besides_configurations_is_named_as_theirs():
    data = dict(copy.deepcopy(TWO_AB), start=[[0, 0], [3, 6]], target=[[0, 0], [3, 6]])
    data["layout"]["xy"] = [[0, 0], [30.0, 0]]
    problem = parse_problem(data, check_collisions=False)
    # the configurations stay put: robot 0 stretched along +x (its beta link 7.4 to 22.4 mm),
    # robot 1 folded at alpha 90° (its beta link on x = 30 mm): 7.6 mm apart.  The
    # trajectories turn robot 1's alpha to 180° and back: its elbow comes to x = 30 - 7.4 =
    # 22.6 mm, 0.2 mm from robot 0's tip, under the 4 mm clearance
    trajs = [{"alpha": np.array([[0.0, 0.0], [2.0, 0.0]]), "beta": np.array([[0.0, 0.0], [2.0, 0.0]])},
             {"alpha": np.array([[0.0, 90.0], [1.0, 180.0], [2.0, 90.0]]),
              "beta": np.array([[0.0, 180.0], [2.0, 180.0]])}]
    r = validate_plan(problem, Plan("complete", [problem.start], trajectories=trajs, motion_time_s=2.0))
    assert not r.valid and any("collide" in p for p in r.problems)
    assert all(p.startswith("trajectories: ") for p in r.problems), r.problems


def test_a_repaired_plans_angles_must_be_its_configurations():
    from supcoord.problems.repair_phase import Repair, parse_problem_any_start

    # robot 0 turns away from robot 1 (rotary arms 15 mm, bases 20 mm apart), the whole plan a repair
    two = {"layout": {"kind": "points", "xy": [[0, 0], [20, 0]]},
           "kinematics": {"kind": "rotary", "arm": 15.0, "steps": 24}, "collision": {"buffer": 2.0}}
    problem = parse_problem_any_start(dict(two, start=[1, 12], target=[6, 12]))
    confs = [np.array([[q], [12]]) for q in range(1, 7)]
    plan = Plan("complete", confs, repair=Repair((0,), 5, True, 1))
    angles = [problem.angles_deg(c).tolist() for c in confs]
    assert validate_plan(problem, dataclasses.replace(plan, angles_deg=angles)).valid
    angles[2][0][0] += 5.0
    r = validate_plan(problem, dataclasses.replace(plan, angles_deg=angles))
    assert not r.valid and r.problems == ["angles_deg[2] are not the angles of configurations[2] (positioners 0)"]
