"""The timing of plans whose robots differ (buffers, own lattices), checked by the validator.

:mod:`supcoord.problems.timing` decides which moves of neighbours are *apart* (need no
order) from the pair's clearance, the sum of the **two** robots' buffers.  Every test here
times a plan whose neighbours have different buffers and hands the timed trajectories
alone to the independent validator (:func:`supcoord.problems.validate_plan`).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from supcoord.geometry.kinematics import AlphaBeta, Rotary
from supcoord.problems import Plan, parse_problem, validate_plan
from supcoord.problems.trajectory import plan_trajectories

AB = {"kind": "alpha-beta", "alpha": 7.4, "beta": 15.0, "alpha_steps": 4, "beta_steps": 5, "beta_range": [0, 180]}


def _three(buffers):
    """Robot 1 turns away from robot 0 (step 1) once robot 2 has cleared its way (step 0);
    then robot 0 turns 40° into the place robot 1's arm left, 3.5 mm short of where it was.
    Robot 0's own lattice makes its move short (2.7 s against robot 2's and 1's 6 s), so
    without its order after robot 1's move it arrives while robot 1 is still waiting."""
    d = 44.8 + 3.5
    data = {"layout": {"kind": "points", "xy": [[0, 0], [d, 0], [d, 40.0]]}, "kinematics": AB,
            "collision": {"buffer": buffers}, "start": [[1, 0], [2, 0], [3, 0]], "target": [[0, 0], [1, 0], [0, 0]]}
    problem = parse_problem(data)
    kins = [AlphaBeta(7.4, 15.0, 4, 5, (0, 180), alpha_deg=[0.0, 40.0, 180.0, 270.0]),
            AlphaBeta(7.4, 15.0, 4, 5, (0, 180)), AlphaBeta(7.4, 15.0, 4, 5, (0, 180))]
    problem = dataclasses.replace(problem, robot_kinematics=kins, _tables=None, _pairs=None)
    confs = [np.array(c) for c in ([[1, 0], [2, 0], [3, 0]], [[1, 0], [2, 0], [0, 0]], [[1, 0], [1, 0], [0, 0]],
                                   [[0, 0], [1, 0], [0, 0]])]
    return problem, confs


@pytest.mark.parametrize("buffers", [[0.2, 6.0, 1.0], [6.0, 0.2, 1.0]], ids=["small-first", "small-second"])
def test_a_move_near_a_neighbour_with_a_large_buffer_waits_for_it(buffers):
    # clearance 6.2 mm: the 3.5 mm the two moves' sweeps come to is not apart, whichever
    # robot has the small buffer (twice the small one, 0.4 mm, would call them apart)
    problem, confs = _three(buffers)
    assert [list(map(int, p)) for p in problem.pairs] == [[0, 1], [1, 2]]
    assert validate_plan(problem, Plan("complete", confs, makespan=3)).valid
    stats: dict = {}
    trajs, total = plan_trajectories(problem, confs, 15.0, stats)
    assert stats["apart"] == 0 and stats["ordered"] == 2
    assert total == pytest.approx(6.0 + 6.0 + 40.0 / 15.0)  # robot 0 waits for robot 1, which waits for 2
    r = validate_plan(problem, Plan("complete", trajectories=trajs, motion_time_s=total))
    assert r.valid, r.problems
    # the order is needed: robot 0 turning at once meets robot 1's arm (3.5 mm < 6.2 mm)
    eager = [dict(t) for t in trajs]
    eager[0]["alpha"] = np.array([[0.0, 40.0], [40.0 / 15.0, 0.0], [total, 0.0]])
    r = validate_plan(problem, Plan("complete", trajectories=eager, motion_time_s=total))
    assert not r.valid and "positioners 0 and 1 collide" in r.problems[0]


# --- random plans of robots that differ -----------------------------------------------------

@st.composite
def walks(draw):
    """Three or four robots, each its own buffer (and sometimes its own alpha lattice or arm),
    placed close, and a random plan: each step some robots move one joint one position, every
    step certified by the validator before the next is drawn."""
    n = draw(st.integers(3, 4))
    rotary = draw(st.booleans())
    buffers = [draw(st.floats(0.1, 4.0)) for _ in range(n)]
    pitch = draw(st.floats(0.6, 1.0)) * (30.0 if rotary else 44.8) + max(buffers)
    xy = [[pitch * i, 0.0] if i < 3 else [pitch / 2, pitch * 0.87] for i in range(n)]
    if rotary:
        kin = {"kind": "rotary", "arm": 15.0, "steps": 6}
        kins = [Rotary(draw(st.floats(10.0, 15.0)), 6) for _ in range(n)]
    else:
        kin = dict(AB, alpha_steps=6)
        kins = []
        for _ in range(n):
            own = None
            if draw(st.booleans()):
                own = np.sort(np.array(draw(st.lists(st.floats(0.0, 355.0), min_size=6, max_size=6, unique=True))))
                assume(np.all(np.diff(own) > 5.0) and own[0] + 360.0 - own[-1] > 5.0)
            kins.append(AlphaBeta(draw(st.floats(5.0, 8.0)), draw(st.floats(10.0, 15.0)), 6, 5, (0, 180),
                                  alpha_deg=own))
    zero = [0] * n if rotary else [[0, 0]] * n
    data = {"layout": {"kind": "points", "xy": xy}, "kinematics": kin, "collision": {"buffer": buffers},
            "start": zero, "target": zero}
    problem = dataclasses.replace(parse_problem(data, check_collisions=False), robot_kinematics=kins,
                                  _tables=None, _pairs=None)
    k = problem.kinematics
    steps = [j.steps for j in k.joints]
    c = np.array([[draw(st.integers(0, s - 1)) for s in steps] for _ in range(n)])
    one = dataclasses.replace(problem, start=c, target=c)
    assume(validate_plan(one, Plan("complete", [c])).valid)
    confs = [c]
    for _ in range(draw(st.integers(2, 7))):
        nxt = confs[-1].copy()
        for p in range(n):
            if draw(st.booleans()):
                j = draw(st.integers(0, k.n_joints - 1))
                v = nxt[p, j] + draw(st.sampled_from([-1, 1]))
                if k.joints[j].wraps:
                    v %= steps[j]
                if 0 <= v < steps[j]:
                    nxt[p, j] = v
        step = dataclasses.replace(problem, start=confs[-1], target=nxt)
        if np.array_equal(nxt, confs[-1]) or not validate_plan(step, Plan("complete", [confs[-1], nxt])).valid:
            continue
        confs.append(nxt)
    assume(len(confs) > 2)
    return dataclasses.replace(problem, start=confs[0], target=confs[-1]), confs


@pytest.mark.timeout(120)
@settings(max_examples=40, deadline=None)
@given(case=walks(), speed=st.sampled_from([5.0, 15.0]))
def test_timed_plans_of_robots_that_differ_pass_the_validator(case, speed):
    problem, confs = case
    assert validate_plan(problem, Plan("complete", confs)).valid
    stats: dict = {}
    trajs, total = plan_trajectories(problem, confs, speed, stats)
    assert total <= stats["lockstep_s"] + 1e-9
    r = validate_plan(problem, Plan("complete", trajectories=trajs, motion_time_s=total))
    assert r.valid, r.problems[:3]


# --- the timing itself -------------------------------------------------------------------------

def _timing(problem, confs, speed):
    from supcoord.problems.timing import plan_timing
    from supcoord.problems.trajectory import continuous_angles

    return plan_timing(problem, confs, speed, continuous_angles(problem, confs))


def test_each_move_starts_when_the_moves_it_waits_for_have_ended():
    problem, confs = _three([0.2, 6.0, 1.0])
    t = _timing(problem, confs, 15.0)
    assert [(int(s), int(r)) for s, r in zip(t.step, t.robot)] == [(0, 2), (1, 1), (2, 0)]
    assert np.allclose(np.stack([t.start, t.end], axis=1), [[0.0, 6.0], [6.0, 12.0], [12.0, 12.0 + 40.0 / 15.0]])


@pytest.mark.timeout(120)
@settings(max_examples=40, deadline=None)
@given(case=walks(), speed=st.sampled_from([5.0, 15.0]))
def test_a_robots_moves_follow_one_another_and_last_their_own_time(case, speed):
    """Per robot: its moves in step order, each starting no earlier than the previous one
    ended and lasting at least its own turn at ``speed``; every move of the plan starts at 0
    or when some move ends (a move waits only for ends)."""
    problem, confs = case
    t = _timing(problem, confs, speed)
    from supcoord.problems.trajectory import continuous_angles

    angles = continuous_angles(problem, confs)
    own = np.abs(np.diff(angles, axis=0)).max(axis=2) / speed
    for p in range(problem.n):
        mine = np.nonzero(t.robot == p)[0]
        assert np.all(np.diff(t.step[mine]) > 0)
        assert np.all(t.end[mine] - t.start[mine] >= own[t.step[mine], p] - 1e-9)
        assert np.all(t.start[mine][1:] >= t.end[mine][:-1] - 1e-9), (p, t.start[mine], t.end[mine])
    ends = np.concatenate([[0.0], t.end])
    assert all(np.isclose(s, ends).any() for s in t.start)
    assert t.motion_time_s == pytest.approx(float(t.end.max()))


def test_short_moves_counts_and_lockstep_of_the_timing():
    """Moves of any length are timed (a 40° turn at 100°/s takes 0.4 s), the counts name
    every move, lockstep is the sum of each step's slowest move; a plan that stays put has
    no moves and takes no time."""
    problem, confs = _three([0.2, 6.0, 1.0])
    t = _timing(problem, confs, 100.0)
    assert [(int(s), int(r)) for s, r in zip(t.step, t.robot)] == [(0, 2), (1, 1), (2, 0)]
    assert np.allclose(t.end - t.start, [0.9, 0.9, 0.4])
    assert t.stats["moves"] == 3 and t.stats["lockstep_s"] == pytest.approx(0.9 + 0.9 + 0.4)
    still = _timing(problem, [confs[0], confs[0]], 100.0)
    assert still.step.shape == still.robot.shape == still.start.shape == still.end.shape == (0,)
    assert still.motion_time_s == 0.0
    assert still.stats == {"moves": 0, "lockstep_s": 0.0, "pairs": 0, "apart": 0, "ordered": 0, "synchronised": 0}
