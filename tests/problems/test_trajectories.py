"""PLAN.json angles and trajectories (the timing model), and the validator on joint angles.

The timing model (``supcoord.problems.timing``): a robot's move lasts ``max |Δθ| / speed``;
it waits for a neighbour's move of an earlier step only where their swept sets can meet,
and shares one interval with a neighbour's move of its own step only then; breakpoints
where a joint's velocity does not change are dropped.
"""

import contextlib
import copy
import csv
import dataclasses
import io
import json

import numpy as np
import pytest

from supcoord.cli.main import main
from supcoord.errors import FormatError, InputError
from supcoord.geometry.kinematics import AlphaBeta, Rotary
from supcoord.planning import solve
from supcoord.problems import Plan, Problem, load_plan, parse_plan, parse_problem, validate_plan
from supcoord.problems.trajectory import plan_trajectories, trajectories_csv, with_motion

pytestmark = pytest.mark.timeout(60)

THREE = {
    "layout": {"kind": "points", "xy": [[0, 0], [22.4, 0], [44.8, 0]]},
    "kinematics": {"kind": "rotary", "arm": 15.0, "steps": 12},
    "collision": {"buffer": 2.0},
    "start": [0, 0, 0],
    "target": [6, 6, 6],
}
AB3 = {
    "layout": {"kind": "points", "xy": [[0, 0], [22.4, 0], [11.2, 19.4]]},
    "kinematics": {"kind": "alpha-beta", "alpha": 7.4, "beta": 15.0, "alpha_steps": 12, "beta_steps": 7,
                   "beta_range": [0, 180]},
    "collision": {"buffer": 2.0},
    "start": [[0, 6], [6, 6], [9, 6]],
    "target": [[6, 0], [0, 0], [3, 3]],
}


def run(*argv):
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main([str(a) for a in argv])
    return code, out.getvalue(), err.getvalue()


def _wrapping(problem):
    return np.array([[j.wraps for j in problem.kin(p).joints] for p in range(problem.n)])


@pytest.fixture(scope="module")
def solved():
    out = {}
    for name, data in (("rotary", THREE), ("alpha-beta", AB3)):
        problem = parse_problem(copy.deepcopy(data))
        plan = solve(problem, speed=12.5)
        assert plan.status == "complete"
        out[name] = (problem, plan)
    return out


@pytest.mark.parametrize("kind", ["rotary", "alpha-beta"])
def test_solved_plan_angles_are_the_problems_angles(solved, kind, tmp_path):
    problem, plan = solved[kind]
    wraps = _wrapping(problem)
    raw = problem.angles_deg(np.array(plan.configurations))
    want = np.where(wraps, np.mod(raw, 360.0), raw)
    got = np.array(plan.angles_deg)
    assert got.shape == raw.shape and np.allclose(got, want, atol=1e-9)
    assert np.all((got[..., wraps[0]] >= 0) & (got[..., wraps[0]] < 360))
    data = plan.to_json(problem)
    assert len(data["angles_deg"]) == len(data["configurations"])
    assert isinstance(data["motion_time_s"], float) and len(data["trajectories"]) == problem.n
    # round trip through the file
    path = tmp_path / "plan.json"
    plan.dump(path, problem)
    back = load_plan(path, problem)
    assert back.motion_time_s == plan.motion_time_s
    assert all(np.array_equal(a, b) for a, b in zip(back.angles_deg, plan.angles_deg))
    for r1, r2 in zip(back.trajectories, plan.trajectories):
        assert r1.keys() == r2.keys() and all(np.array_equal(r1[k], r2[k]) for k in r1)
    assert back.to_json(problem) == data
    result = validate_plan(problem, back)
    assert result.valid, result.problems
    assert result.motion_time_s == pytest.approx(plan.motion_time_s)


def test_solve_without_speed_has_angles_but_no_trajectories():
    problem = parse_problem(copy.deepcopy(THREE))
    plan = solve(problem)
    assert plan.trajectories is None and plan.motion_time_s is None and len(plan.angles_deg) == len(plan.configurations)
    assert "trajectories" not in plan.to_json(problem)
    with pytest.raises(InputError, match="speed"):
        solve(problem, speed=0)


def test_robots_far_apart_keep_their_own_time():
    # alpha 30° a step, beta 45° a step; the robots are far apart (no neighbour pair)
    data = {"layout": {"kind": "points", "xy": [[0, 0], [100, 0]]},
            "kinematics": {"kind": "alpha-beta", "alpha": 7.4, "beta": 15.0, "alpha_steps": 12, "beta_steps": 5,
                           "beta_range": [0, 180]},
            "collision": {"buffer": 2.0}, "start": [[0, 0], [0, 0]], "target": [[3, 1], [0, 2]]}
    problem = parse_problem(data)
    assert len(problem.pairs) == 0
    confs = [np.array(c) for c in ([[0, 0], [0, 0]], [[1, 0], [0, 1]], [[2, 0], [0, 1]], [[2, 1], [0, 1]],
                                   [[3, 1], [0, 2]], [[3, 1], [0, 2]])]  # the last step moves nothing
    v = 15.0
    trajs, total = plan_trajectories(problem, confs, v)
    assert total == pytest.approx((30 + 30 + 45 + 30) / v)  # robot 0 never waits for robot 1
    assert np.allclose(trajs[0]["alpha"], [[0, 0], [4, 60], [7, 60], [9, 90]])  # v, v, 0, v
    assert np.allclose(trajs[0]["beta"], [[0, 0], [4, 0], [7, 45], [9, 45]])
    assert np.allclose(trajs[1]["beta"], [[0, 0], [6, 90], [9, 90]])  # two steps at v, back to back
    assert np.allclose(trajs[1]["alpha"], [[0, 0], [9, 0]])
    plan = with_motion(Plan("complete", confs), problem, v)
    assert plan.motion_time_s == total
    r = validate_plan(problem, Plan("complete", trajectories=plan.trajectories, motion_time_s=total))
    assert r.valid and r.motion_time_s == pytest.approx(total), r.problems
    r = validate_plan(problem, Plan("complete", trajectories=plan.trajectories, motion_time_s=total + 1))
    assert not r.valid and "motion_time_s" in r.problems[0]


def test_a_move_that_can_meet_a_neighbours_earlier_move_waits_for_it():
    # robot 1 turns its arm away from robot 0 (step 0), then robot 0 reaches into the space it
    # left (step 1): run at once, the two arms cross; robot 2, far away, moves at once
    data = {"layout": {"kind": "points", "xy": [[0, 0], [30, 0], [200, 0]]},
            "kinematics": {"kind": "alpha-beta", "alpha": 7.4, "beta": 15.0, "alpha_steps": 4, "beta_steps": 5,
                           "beta_range": [0, 180]},
            "collision": {"buffer": 2.0}, "start": [[1, 0], [2, 0], [2, 0]], "target": [[0, 0], [1, 0], [1, 0]]}
    problem = parse_problem(data)
    assert [list(map(int, pq)) for pq in problem.pairs] == [[0, 1]]
    confs = [np.array(c) for c in ([[1, 0], [2, 0], [2, 0]], [[1, 0], [1, 0], [2, 0]], [[0, 0], [1, 0], [1, 0]])]
    assert validate_plan(problem, Plan("complete", confs, makespan=2)).valid
    v = 15.0
    trajs, total = plan_trajectories(problem, confs, v)
    assert total == pytest.approx(12.0)
    assert np.allclose(trajs[1]["alpha"], [[0, 180], [6, 90], [12, 90]])
    assert np.allclose(trajs[0]["alpha"], [[0, 90], [6, 90], [12, 0]])  # waits for robot 1's move
    assert np.allclose(trajs[2]["alpha"], [[0, 180], [6, 90], [12, 90]])  # does not wait for step 0
    r = validate_plan(problem, Plan("complete", trajectories=trajs, motion_time_s=total))
    assert r.valid, r.problems
    # the wait is needed: robot 0 moving at once reaches robot 1's arm
    eager = copy.deepcopy(trajs)
    eager[0]["alpha"] = np.array([[0, 90.0], [6, 0.0], [12, 0.0]])
    r = validate_plan(problem, Plan("complete", trajectories=eager, motion_time_s=total))
    assert not r.valid and "positioners 0 and 1 collide" in r.problems[0]


def test_moves_whose_sweeps_stay_apart_do_not_wait_for_each_other():
    # the same neighbours, robot 0 turning away from robot 1 (down, 90° -> 270° by 180°):
    # its move is apart from robot 1's, so both start at once
    data = {"layout": {"kind": "points", "xy": [[0, 0], [30, 0]]},
            "kinematics": {"kind": "alpha-beta", "alpha": 7.4, "beta": 15.0, "alpha_steps": 4, "beta_steps": 5,
                           "beta_range": [0, 180]},
            "collision": {"buffer": 2.0}, "start": [[1, 0], [2, 0]], "target": [[2, 0], [1, 0]]}
    problem = parse_problem(data)
    confs = [np.array(c) for c in ([[1, 0], [2, 0]], [[1, 0], [1, 0]], [[2, 0], [1, 0]])]
    assert validate_plan(problem, Plan("complete", confs, makespan=2)).valid
    trajs, total = plan_trajectories(problem, confs, 15.0)
    assert total == pytest.approx(6.0)
    assert np.allclose(trajs[0]["alpha"], [[0, 90], [6, 180]])
    assert np.allclose(trajs[1]["alpha"], [[0, 180], [6, 90]])


def test_a_wrapping_joint_turns_the_short_way_in_the_trajectory():
    data = {"layout": {"kind": "points", "xy": [[0, 0]]}, "kinematics": {"kind": "rotary", "arm": 5.0, "steps": 12},
            "collision": {"buffer": 1.0}, "start": [11], "target": [1]}
    problem = parse_problem(data)
    plan = with_motion(Plan("complete", [np.array([[11]]), np.array([[0]]), np.array([[1]])]), problem, 30.0)
    assert np.allclose(np.array(plan.angles_deg)[:, 0, 0], [30, 0, 330])
    assert np.allclose(plan.trajectories[0]["theta"], [[0, 30], [2, -30]])  # continuous, one breakpoint pair
    assert validate_plan(problem, Plan("complete", trajectories=plan.trajectories)).valid
    assert validate_plan(problem, Plan("complete", angles_deg=plan.angles_deg)).valid


def test_cli_csv_matches_the_json(tmp_path):
    pf = tmp_path / "problem.json"
    pf.write_text(json.dumps(AB3))
    out, table = tmp_path / "plan.json", tmp_path / "traj.csv"
    code, stdout, err = run("solve", pf, "--out", out, "--speed", "20", "--trajectories-csv", table, "--json", "-q")
    assert code == 0, err
    plan = json.loads(stdout)
    assert json.loads(out.read_text()) == plan
    rows = list(csv.reader(table.read_text().splitlines()))
    assert rows[0] == ["robot", "joint", "t_s", "deg"]
    expect = [[str(p), name, repr(float(t)), repr(float(a))] for p, robot in enumerate(plan["trajectories"])
              for name, points in robot.items() for t, a in points]
    assert rows[1:] == expect
    assert max(float(r[2]) for r in rows[1:]) == plan["motion_time_s"]
    code, stdout, _ = run("check", pf, out, "--json")
    assert code == 0 and json.loads(stdout)["valid"] and json.loads(stdout)["motion_time_s"] == plan["motion_time_s"]
    for argv, message in [(["--trajectories-csv", tmp_path / "t.csv"], "needs --speed"),
                          (["--speed", "20", "--trajectories-csv", tmp_path / "t.txt"], "must end in .csv"),
                          (["--speed", "0"], "--speed"), (["--speed", "nan"], "--speed")]:
        code, stdout, err = run("solve", pf, *argv, "--json")
        assert code == 2 and stdout == "" and len(err.strip().splitlines()) == 1 and message in err, err
    assert not (tmp_path / "t.csv").exists()
    assert trajectories_csv([{"theta": np.array([[0.0, 1.5]])}]) == "robot,joint,t_s,deg\n0,theta,0.0,1.5\n"


@pytest.mark.parametrize("kind", ["rotary", "alpha-beta"])
def test_angle_only_and_trajectory_only_plans_validate(solved, kind, tmp_path):
    problem, plan = solved[kind]
    for only in ({"angles_deg": [a.tolist() for a in plan.angles_deg]},
                 {"trajectories": plan.to_json(problem)["trajectories"]}):
        data = dict({"status": "complete"}, **only)
        parsed = parse_plan(json.loads(json.dumps(data)), problem, "plan.json")
        r = validate_plan(problem, parsed)
        assert r.valid and r.at_target == problem.n and r.collisions == 0, r.problems
        pf, lf = tmp_path / "p.json", tmp_path / "plan.json"
        problem.dump(pf)
        lf.write_text(json.dumps(data))
        code, out, _ = run("check", pf, lf, "--json")
        assert code == 0 and json.loads(out)["valid"]


def test_mutated_angle_plans_are_caught(solved):
    problem, plan = solved["rotary"]
    poses = [a.copy() for a in plan.angles_deg]
    k = len(poses) // 2
    collide = [a.copy() for a in poses]
    collide[k][0, 0], collide[k][1, 0] = 0.0, 180.0  # 0 points at 1 while 1 points back at 0
    r = validate_plan(problem, Plan("complete", angles_deg=collide))
    assert not r.valid and r.collisions > 0
    assert any("positioners 0 and 1 collide" in p for p in r.problems)
    late = [a.copy() for a in poses]
    late[-1][2, 0] += 0.01
    r = validate_plan(problem, Plan("complete", angles_deg=late))
    assert not r.valid and any("does not end at the target" in p for p in r.problems) and r.at_target == 2
    trajs = copy.deepcopy(plan.trajectories)
    trajs[1]["theta"][-1, 1] += 0.01
    r = validate_plan(problem, Plan("complete", trajectories=trajs))
    assert not r.valid and any("does not end at the target" in p for p in r.problems)
    # given besides the configurations, angles and trajectories must agree with them
    r = validate_plan(problem, dataclasses.replace(plan, angles_deg=late))
    assert not r.valid and any("are not the angles of configurations" in p for p in r.problems)
    r = validate_plan(problem, dataclasses.replace(plan, trajectories=trajs))
    assert not r.valid and any(p.startswith("trajectories: ") for p in r.problems)


def test_beta_beyond_its_range_is_caught(solved):
    problem, plan = solved["alpha-beta"]
    poses = [a.copy() for a in plan.angles_deg]
    poses[1][0, 1] = 181.0
    r = validate_plan(problem, Plan("complete", angles_deg=poses))
    assert not r.valid and any("pose 1: positioners 0 are out of the joint ranges" in p for p in r.problems)
    trajs = copy.deepcopy(plan.trajectories)
    trajs[2]["beta"] = np.vstack([trajs[2]["beta"][:1], [[0.5, -3.0]], trajs[2]["beta"][1:]])
    r = validate_plan(problem, Plan("complete", trajectories=trajs))
    assert not r.valid and any("out of the joint ranges" in p for p in r.problems)


def test_a_swept_collision_between_two_poses_is_found_by_bisection():
    """a's arm sweeps through b's base between two poses that are both free; at the coarsest
    resolution only the end points are sampled, so only the bisection can find it."""
    data = {"layout": {"kind": "points", "xy": [[0, 0], [5, -5]]},
            "kinematics": {"kind": "rotary", "arm": 10.0, "steps": 4},
            "collision": {"buffer": 1.0}, "start": [0, 0], "target": [1, 0]}
    problem = parse_problem(data)
    poses = [np.array([[0.0], [0.0]]), np.array([[270.0], [0.0]])]
    for plan in (Plan("complete", angles_deg=poses),
                 Plan("complete", trajectories=[{"theta": np.array([[0, 0], [1, -90]])},
                                                {"theta": np.array([[0, 0]])}])):
        r = validate_plan(problem, plan, resolution=100.0)
        assert not r.valid and r.collisions == 1, r
        assert 1 / 3 - 0.02 <= r.incidents[0].t <= 0.5 + 0.02


def test_obstacles_are_checked():
    problem = parse_problem(copy.deepcopy(THREE))
    plan = solve(problem)
    blocked = dataclasses.replace(problem, obstacles=np.array([[[7.0, -1.0], [7.0, 1.0]]]),
                                  obstacle_buffers=np.array([0.5]))
    r = validate_plan(blocked, plan)  # positioner 0's arm lies across the obstacle at the start
    assert not r.valid and any("positioner 0 collides with obstacle 0" in p for p in r.problems)
    assert r.incidents[0].positioners == [0] and r.incidents[0].obstacle == 0
    far = dataclasses.replace(problem, obstacles=np.array([[[100.0, 100.0], [101.0, 100.0]]]),
                              obstacle_buffers=np.array([0.5]))
    assert validate_plan(far, plan).valid


def _lattice_problem():
    p = parse_problem(copy.deepcopy(AB3))
    alpha = 360 * np.arange(12) / 12.0
    alpha[0], alpha[6] = 2.5, 183.25  # robot 0's exact start and target
    beta = np.linspace(0, 180, 7)
    beta[3] = 91.7
    kins = [AlphaBeta(7.4, 15.0, 12, 7, (0, 180), alpha_deg=alpha),
            AlphaBeta(7.4, 15.0, 12, 7, (0, 180), beta_deg=beta),
            AlphaBeta(7.4, 14.0, 12, 7, (0, 180))]
    return p, dataclasses.replace(p, robot_kinematics=kins, _tables=None, _pairs=None)


def test_per_robot_lattices_validate_index_plans_through_their_angles():
    uniform, problem = _lattice_problem()
    plan = solve(problem, speed=10.0)
    assert plan.status == "complete"
    assert np.allclose(plan.angles_deg[0][0], [2.5, 180]) and np.allclose(plan.angles_deg[-1][0], [183.25, 0])
    r = validate_plan(problem, plan)
    assert r.valid, r.problems
    for only in (Plan("complete", angles_deg=plan.angles_deg), Plan("complete", trajectories=plan.trajectories)):
        assert validate_plan(problem, only).valid
        r = validate_plan(uniform, only)  # robot 0's exact angles are not the uniform lattice's
        assert not r.valid and any("positioners 0 are more than" in p for p in r.problems)


def test_per_robot_geometry_is_used():
    # robot 0 points +x at robot 1, which points +y: 7.4 mm apart with arms of 15 mm, 1.4 with 21 mm
    data = {"layout": {"kind": "points", "xy": [[0, 0], [22.4, 0]]},
            "kinematics": {"kind": "rotary", "arm": 15.0, "steps": 12},
            "collision": {"buffer": 2.0}, "start": [0, 9], "target": [0, 9]}
    problem = parse_problem(data)
    plan = Plan("complete", [problem.start])
    assert validate_plan(problem, plan).valid
    longer = dataclasses.replace(problem, robot_kinematics=[Rotary(21.0, 12), Rotary(15.0, 12)], _tables=None,
                                 _pairs=None)
    r = validate_plan(longer, plan)
    assert not r.valid and r.collisions == 1 and r.min_clearance == pytest.approx(1.4 - 4.0)


def test_plan_json_reading_of_angles_and_trajectories(solved):
    problem, plan = solved["alpha-beta"]
    data = plan.to_json(problem)
    for key, value, message in [
            ("angles_deg", "x", "angles_deg must be a list"),
            ("angles_deg", data["angles_deg"][:-1], "angles_deg has"),
            ("angles_deg", [[[0, "1"]] * 3] * len(data["angles_deg"]), r"angles_deg\[0\]\[0\]"),
            ("trajectories", [{}], "trajectories must list 3"),
            ("trajectories", [{"alpha": [[0, 0]]}] * 3, r"trajectories\[0\] must be an object with the joints"),
            ("trajectories", [{"alpha": [[0, 0], [0, 1]], "beta": [[0, 0]]}] * 3, "times must increase"),
            ("trajectories", [{"alpha": [[-1, 0]], "beta": [[0, 0]]}] * 3, r"trajectories\[0\].alpha\[0\]"),
            ("trajectories", [{"alpha": [], "beta": [[0, 0]]}] * 3, "non-empty"),
            ("motion_time_s", -1, "motion_time_s")]:
        with pytest.raises(FormatError, match=message) as err:
            parse_plan(dict(data, **{key: value}), problem, "plan.json")
        assert err.value.where == "plan.json" and "\n" not in str(err.value)
    only = parse_plan({"status": "complete", "angles_deg": data["angles_deg"], "motion_time_s": None}, problem)
    assert only.configurations == [] and len(only.angles_deg) == len(data["angles_deg"])


@pytest.mark.skipif(not {"held", "joint_rules"} <= {f.name for f in dataclasses.fields(Problem)},
                    reason="problems without offline robots or joint rules")
def test_offline_robots_and_joint_rules_are_checked_on_angles(solved):
    problem, plan = solved["alpha-beta"]
    poses = [a.copy() for a in plan.angles_deg]
    assert validate_plan(problem, Plan("complete", angles_deg=poses)).valid
    moving = int(np.nonzero(np.any(plan.configurations[0] != plan.configurations[1], axis=1))[0][0])
    held = dataclasses.replace(problem, held={moving: tuple(problem.start[moving])})
    for only in (plan, Plan("complete", angles_deg=poses), Plan("complete", trajectories=plan.trajectories)):
        r = validate_plan(held, only)
        assert not r.valid and any(f"offline positioners {moving} move" in p for p in r.problems)
    # beta >= 150 - 0·alpha holds at the start (beta = 180) and fails at the target (beta <= 90)
    ruled = dataclasses.replace(problem, joint_rules={0: (150.0, 0.0)})
    r = validate_plan(ruled, Plan("complete", angles_deg=poses))
    assert not r.valid and any("positioners 0 enter the forbidden region" in p for p in r.problems)


def test_trajectories_of_another_tool_with_their_own_breakpoints():
    # two rotary robots far apart, each with its own breakpoint times; robot 0 spins two full
    # turns and back to its start angle in one segment (checked a turn at a time)
    data = {"layout": {"kind": "points", "xy": [[0, 0], [100, 0]]},
            "kinematics": {"kind": "rotary", "arm": 15.0, "steps": 12},
            "collision": {"buffer": 2.0}, "start": [0, 3], "target": [0, 6]}
    problem = parse_problem(data)
    trajs = [{"theta": np.array([[0.0, 0.0], [2.5, 720.0]])},
             {"theta": np.array([[0.3, 270.0], [1.1, 240.0], [4.0, 180.0]])}]
    r = validate_plan(problem, Plan("complete", trajectories=trajs))
    assert r.valid and r.steps == 4 and r.motion_time_s == 4.0, r.problems
    trajs[0]["theta"][1, 1] = 360.0 * 1000
    r = validate_plan(problem, Plan("complete", trajectories=trajs))
    assert not r.valid and any("not checked for collisions" in p for p in r.problems)


def test_a_beta_swing_through_a_neighbour_is_found_by_bisection():
    """Robot 0's beta arm swings from +x over +y to −x through robot 1's arm, which hangs down
    from above: both ends are free, the middle is not; the Lipschitz bound of a beta turn
    (the segment's radius about the elbow) is what lets the bisection see it."""
    data = {"layout": {"kind": "points", "xy": [[0, 0], [7.4, 30]]},
            "kinematics": {"kind": "alpha-beta", "alpha": 7.4, "beta": 15.0, "alpha_steps": 12, "beta_steps": 7,
                           "beta_range": [0, 180]},
            "collision": {"buffer": 2.0}, "start": [[0, 0], [9, 0]], "target": [[0, 6], [9, 0]]}
    problem = parse_problem(data)
    poses = [np.array([[0.0, 0.0], [270.0, 0.0]]), np.array([[0.0, 180.0], [270.0, 0.0]])]
    r = validate_plan(problem, Plan("complete", angles_deg=poses), resolution=100.0)
    assert not r.valid and r.collisions == 1 and r.incidents[0].t == pytest.approx(0.5, abs=0.1), r


@pytest.mark.timeout(240)
@pytest.mark.slow
def test_the_timing_of_tight_plans_passes_the_validator_and_needs_its_orders(monkeypatch):
    """The timing's claim (``supcoord.problems.timing``): every motion it makes of a plan is
    safe.  On tight random problems the trajectories alone, checked as a motion by the
    validator, are collision-free; they take at least each robot's own time and at most
    lockstep (each step as long as its slowest joint), synchronised moves share one interval.
    With every pair of moves declared apart (no orders, no synchronisation) some of the same
    plans collide: the orders are what makes them safe."""
    from supcoord import solve
    from supcoord.problems import timing as timing_module
    from supcoord.problems.random import random_problem
    from supcoord.problems.refine import at_lattice
    from supcoord.problems.trajectory import continuous_angles

    ab = {"kind": "alpha-beta", "alpha": 7.4, "beta": 15.0, "alpha_steps": 12, "beta_steps": 7, "beta_range": [0, 180]}
    plans, waited, synchronised = [], 0, 0
    for seed in range(8):
        problem = random_problem({"kind": "hex", "rings": 2, "pitch": 22.4}, ab, 2.0, seed=seed)
        plan = solve(problem, improve=0, speed=10.0)
        assert plan.status == "complete"
        turn = np.abs(np.diff(np.array(plan.angles_deg), axis=0))
        turn[..., 0] = np.minimum(turn[..., 0], 360.0 - turn[..., 0])  # alpha wraps here
        lockstep = float(turn.max(axis=(1, 2)).sum()) / 10.0  # each step its slowest joint
        own = float(turn.max(axis=2).sum(axis=0).max()) / 10.0  # the busiest robot alone
        r = validate_plan(problem, Plan("complete", trajectories=plan.trajectories, motion_time_s=plan.motion_time_s))
        assert r.valid, (seed, r.problems[:3])
        assert own - 1e-9 <= plan.motion_time_s <= lockstep + 1e-9
        if plan.lattice is not None:  # planned on a finer lattice: its configurations index that one
            problem = at_lattice(problem, plan.lattice)
        timing = timing_module.plan_timing(problem, plan.configurations, 10.0,
                                           continuous_angles(problem, plan.configurations))
        assert timing.motion_time_s == plan.motion_time_s
        with monkeypatch.context() as m:  # decided in many blocks: the same timing
            m.setattr(timing_module, "BLOCK", 97)
            blocks = timing_module.plan_timing(problem, plan.configurations, 10.0,
                                               continuous_angles(problem, plan.configurations))
        assert np.array_equal(blocks.start, timing.start) and blocks.stats == timing.stats
        waited += timing.stats["ordered"]
        synchronised += timing.stats["synchronised"]
        plans.append((problem, plan))
    assert waited > 0 and synchronised > 0

    def all_apart(motions_a, length_a, motions_b, length_b, bsum, **_):
        return np.ones(len(length_a), dtype=bool)

    monkeypatch.setattr(timing_module, "sweeps_apart", all_apart)
    collided = 0
    for problem, plan in plans:
        trajs, total = plan_trajectories(problem, plan.configurations, 10.0)
        collided += not validate_plan(problem, Plan("complete", trajectories=trajs, motion_time_s=total)).valid
    assert collided > 0
