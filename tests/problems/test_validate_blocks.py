"""The validator's geometry on blocks of steps against the slow way: step by step, pair by pair.

:mod:`supcoord.problems.validate_motion` checks every (step, pair) of a block of steps at once.
The oracle here does what its docstring says one step and one pair at a time on floats (end
points, samples, rounds of bisection), placing the arms with the kinematics' own
``segments_at_deg`` instead of the validator's chain formula: the collisions, their steps
and pairs and the least clearance must agree (distances to rounding).
"""

import math
from itertools import combinations

import numpy as np
import pytest

from supcoord.problems import Plan, validate_plan
from supcoord.problems.random import random_problem
from supcoord.problems.validate_motion import MAX_OPEN, TIE, TOLERANCE, segment_distance_ericson

ROTARY = {"kind": "rotary", "arm": 15.0, "steps": 12}
#: a coarse first sampling (mm) keeps the slow check fast; the bisection does the rest
RESOLUTION = 1.0
ALPHA_BETA = {"kind": "alpha-beta", "alpha": 7.4, "beta": 15.0, "alpha_steps": 12, "beta_steps": 7,
              "beta_range": [0, 180]}


def _dist(problem, p, q, r, s, a0, turn, t):
    """Distance of robots ``p`` (angles ``a0 + t·turn``) and ``r`` at ``t`` (floats)."""
    kin = problem.kinematics
    sa = kin.segments_at_deg(a0[p] + t * turn[p]) + problem.bases[p]
    sb = kin.segments_at_deg(a0[r] + t * turn[r]) + problem.bases[r]
    return float(segment_distance_ericson(sa[0], sa[1], sb[0], sb[1]))


def _pair_least(problem, a, b, a0, turn, travel, need, samples):
    """One pair over one step: the least distance found and whether the pair is left open."""
    lip = travel[a] + travel[b]
    d0, d1 = _dist(problem, a, 0, b, 0, a0, turn, 0.0), _dist(problem, a, 0, b, 0, a0, turn, 1.0)
    ds = [_dist(problem, a, 0, b, 0, a0, turn, k / samples) if 0 < k < samples else (d0 if k == 0 else d1)
          for k in range(samples + 1)]
    t = np.linspace(0.0, 1.0, samples + 1)
    least = min(ds)
    work = [(t[k], t[k + 1], ds[k], ds[k + 1]) for k in range(samples)
            if (ds[k] + ds[k + 1] - lip / samples) / 2 < need and least >= need]
    depth = 0.0
    while work:  # rounds of bisection, as the validator's
        if len(work) > MAX_OPEN:
            depth = max(depth, max(need - (w[2] + w[3] - lip * (w[1] - w[0])) / 2 for w in work))
            break
        mids = [(w[0] + w[1]) / 2 for w in work]
        dms = [_dist(problem, a, 0, b, 0, a0, turn, m) for m in mids]
        least = min([least] + dms)
        halves = [h for w, m, dm in zip(work, mids, dms) for h in ((w[0], m, w[2], dm), (m, w[1], dm, w[3]))]
        work = []
        for h in halves:
            bound = (h[2] + h[3] - lip * (h[1] - h[0])) / 2
            if bound < need and least >= need:
                if lip * (h[1] - h[0]) / 2 <= TOLERANCE:
                    depth = max(depth, need - bound)
                else:
                    work.append(h)
    return least, depth > 0 and least >= need


def _slow_check(problem, poses, resolution=RESOLUTION):
    """``(collisions [(step, a, b)], least clearance)`` of the motion through ``poses``."""
    kin = problem.kinematics
    reach = kin.reach
    radius = 0.0 if kin.n_joints == 1 else max(math.hypot(*p) for p in kin.chain()[1])
    buf = np.asarray(problem.buffers, float)
    pairs = [(a, b) for a, b in combinations(range(problem.n), 2)
             if math.dist(problem.bases[a], problem.bases[b]) < 2 * reach + 2 * buf.max()]
    hits, clearance = [], math.inf
    for k in range(len(poses) - 1):
        a0, turn = poses[k], poses[k + 1] - poses[k]
        travel = np.radians(np.abs(turn)) @ np.array([reach, radius][:kin.n_joints])
        found = {}
        for a, b in pairs:
            need = buf[a] + buf[b] - TIE
            d0, d1 = _dist(problem, a, 0, b, 0, a0, turn, 0.0), _dist(problem, a, 0, b, 0, a0, turn, 1.0)
            if (d0 + d1 - travel[a] - travel[b]) / 2 >= need:
                found[a, b] = min(d0, d1)
        left = [p for p in pairs if p not in found]
        if left:
            samples = max(1, math.ceil(2 * max(max(travel[a], travel[b]) for a, b in left) / resolution))
            for a, b in left:
                found[a, b] = _pair_least(problem, a, b, a0, turn, travel, buf[a] + buf[b] - TIE, samples)[0]
        for a, b in pairs:
            clearance = min(clearance, found[a, b] - buf[a] - buf[b])
            if found[a, b] < buf[a] + buf[b] - TIE:
                hits.append((k, a, b))
    return hits, clearance


@pytest.mark.parametrize("kinematics", [ROTARY, ALPHA_BETA], ids=["rotary", "alpha-beta"])
@pytest.mark.parametrize("seed", range(3))
def test_blocks_of_steps_find_what_the_slow_check_finds(kinematics, seed):
    problem = random_problem({"kind": "hex", "rings": 1, "pitch": 22.4}, kinematics, 2.0, seed=seed)
    rng = np.random.default_rng(seed)
    poses = [problem.angles_deg(problem.start)]
    for _ in range(4):  # random turns of up to 60°, no joint wrapping the long way
        step = rng.uniform(-60, 60, size=poses[-1].shape) * (rng.random(poses[-1].shape) < 0.6)
        poses.append(poses[-1] + step)
    result = validate_plan(problem, Plan("complete", angles_deg=[p.tolist() for p in poses]), resolution=RESOLUTION)
    hits, clearance = _slow_check(problem, poses)
    assert result.collisions == len(hits)
    assert [(i.step, *i.positioners) for i in result.incidents] == hits[:len(result.incidents)]
    assert result.min_clearance == pytest.approx(clearance, abs=1e-9)


def test_the_slow_check_sees_collisions_between_samples_of_the_end_points():
    """The comparison has teeth: some of its random motions collide only inside a step."""
    problem = random_problem({"kind": "hex", "rings": 1, "pitch": 22.4}, ROTARY, 2.0, seed=0)
    poses = [problem.angles_deg(problem.start)]
    poses.append(poses[0] + 170.0)  # every arm swings most of half a turn: the arms sweep across each other
    hits, _ = _slow_check(problem, poses)
    result = validate_plan(problem, Plan("complete", angles_deg=[p.tolist() for p in poses]), resolution=RESOLUTION)
    assert hits and result.collisions == len(hits)
