"""Neighbours whose moves are apart run at once: the timing's use of the clearance and of a
duration function.

Written for a survivor of a uniform sample of the timing's mutants
(``benchmarks/mutation_run.py --sample 40 --seed 0 timing``): no selected test had two
neighbours' moves that are apart, so the clearance handed to ``sweeps_apart`` could be
anything that makes every pair "not apart" (the plan's order kept: slower, still valid);
none gave ``plan_timing`` a ``duration`` (a survivor of the fresh sample, seed 1).
"""

from __future__ import annotations

import numpy as np

from supcoord.problems import Plan, parse_problem, validate_plan
from supcoord.problems.timing import plan_timing
from supcoord.problems.trajectory import continuous_angles, plan_trajectories

AB = {"kind": "alpha-beta", "alpha": 7.4, "beta": 15.0, "alpha_steps": 4, "beta_steps": 5, "beta_range": [0, 180]}
FOLDED = {"layout": {"kind": "points", "xy": [[0, 0], [36.0, 0]]}, "kinematics": AB,
          "collision": {"buffer": 1.0}, "start": [[1, 4], [1, 4]], "target": [[2, 4], [0, 4]]}


def test_neighbours_folded_far_apart_move_at_the_same_time():
    # beta folded (180°): the elbow 7.4 mm from the base, the tip 15 - 7.4 = 7.6 mm on the
    # other side, so each arm stays within 7.6 mm of its base whatever alpha does; bases
    # 36 mm apart (neighbours: 2 x 22.4 mm reach > 36 mm) leave 36 - 2 x 7.6 = 20.8 mm,
    # more than the 2 mm clearance: robot 1's move (step 1) need not wait for robot 0's (step 0)
    problem = parse_problem(FOLDED)
    assert [list(map(int, p)) for p in problem.pairs] == [[0, 1]]
    confs = [np.array([[1, 4], [1, 4]]), np.array([[2, 4], [1, 4]]), np.array([[2, 4], [0, 4]])]
    t = plan_timing(problem, confs, 15.0, continuous_angles(problem, confs))
    assert (t.stats["pairs"], t.stats["apart"], t.stats["ordered"]) == (1, 1, 0)
    assert np.allclose(t.start, [0.0, 0.0]) and np.allclose(t.end, [6.0, 6.0])  # 90° at 15°/s each
    trajs, total = plan_trajectories(problem, confs, 15.0, {})
    assert total == 6.0
    assert validate_plan(problem, Plan("complete", trajectories=trajs, motion_time_s=total)).valid


def test_a_duration_function_gives_each_move_its_time():
    # the same two folded neighbours; each move turns alpha 90°, so a duration of
    # 1 s + |turn| / 30 °/s makes each 4 s, both from 0 (apart)
    problem = parse_problem(FOLDED)
    confs = [np.array([[1, 4], [1, 4]]), np.array([[2, 4], [1, 4]]), np.array([[2, 4], [0, 4]])]
    t = plan_timing(problem, confs, 15.0, continuous_angles(problem, confs), duration=lambda turn: 1.0 + turn / 30.0)
    assert np.allclose(t.start, [0.0, 0.0]) and np.allclose(t.end, [4.0, 4.0]) and t.motion_time_s == 4.0
