"""The public descent (:func:`supcoord.planning.descent.descent`, :func:`descent_step`) on a
tight lattice, every step it returns checked by the independent validator.

A descent step moves several robots at once.  The swept tables vouch for one joint of one
robot turning against a neighbour standing at any pose of the step; two neighbours *each*
turning one joint at the same time are a different motion, which only the merged-motion
check of the descent sees.  On an 8 × 5 lattice with 0.5 mm buffers there are pairs of such
moves that are free one at a time in every order and collide together; the testing oracle
(:mod:`supcoord.testing.oracle`, its own geometry) finds them, and the descent must not
return them as one step.
"""

from __future__ import annotations

import dataclasses
import itertools
from functools import lru_cache

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from supcoord.planning.descent import descent, descent_step
from supcoord.problems import Plan, parse_problem, validate_plan
from supcoord.testing.oracle.distance import segment_gap
from supcoord.testing.oracle.oracle_model import Arm
from supcoord.testing.oracle.certified_sweep import FREE, HIT
from supcoord.testing.oracle.tables import PairTables

KIN = {"kind": "alpha-beta", "alpha": 7.4, "beta": 15.0, "alpha_steps": 8, "beta_steps": 5, "beta_range": [0, 180]}
BUFFER = 0.5
MOVES = ((1, 0), (-1, 0), (0, 1), (0, -1))


@lru_cache(maxsize=None)
def merged_only(dist: float, angle_deg: float) -> tuple[tuple[tuple[int, ...], ...], ...]:
    """Per the oracle: single-joint moves ``(qa, da, qb, db)`` of two robots ``dist`` mm apart
    that are free one at a time (each against the other at both of its poses) and collide
    when made together."""
    arm = Arm.from_json(KIN)
    o = dist * np.exp(1j * np.radians(angle_deg))
    pt = PairTables(arm, o, 2 * BUFFER)
    pos = arm.positions()
    rows = [(qa, da, qb, db) for qa, qb in itertools.product(pos, repeat=2)
            for da, db in itertools.product(np.array(MOVES), repeat=2)
            if 0 <= qa[1] + da[1] < 5 and 0 <= qb[1] + db[1] < 5]
    qa, da, qb, db = (np.array([r[i] for r in rows]) for i in range(4))
    z = np.zeros_like(da)

    def verdict(qa, da, qb, db):
        g = [segment_gap(*arm.segment((qa + s * da).astype(float)),
                         *(o + v for v in arm.segment((qb + s * db).astype(float)))) for s in (0, 1)]
        return pt.motion(qa, da, qb, db, g[0], g[1])

    serial = ((verdict(qa, da, qb, z) == FREE) & (verdict(qa, da, qb + db, z) == FREE)
              & (verdict(qa, z, qb, db) == FREE) & (verdict(qa + da, z, qb, db) == FREE))
    sel = np.nonzero(serial & (verdict(qa, da, qb, db) == HIT))[0]
    return tuple(tuple(tuple(int(v) for v in a[s]) for a in (qa, da, qb, db)) for s in sel)


def _pair(dist: float, angle_deg: float, start, target):
    a = np.radians(angle_deg)
    data = {"layout": {"kind": "points", "xy": [[0.0, 0.0], [dist * np.cos(a), dist * np.sin(a)]]},
            "kinematics": KIN, "collision": {"buffer": BUFFER},
            "start": [list(map(int, s)) for s in start], "target": [list(map(int, t)) for t in target]}
    return parse_problem(data, check_collisions=False)


def _after(problem, c, step):
    out = c.copy()
    for p, j, d in step:
        q = out[p].copy()
        q[j] += d
        out[p] = problem.kinematics.wrap(q)
    return out


def _assert_steps_valid(problem, c, steps):
    """Each returned step, run as one simultaneous motion from where the last one ended."""
    for k, step in enumerate(steps):
        nxt = _after(problem, c, step)
        one = dataclasses.replace(problem, start=c, target=nxt)
        r = validate_plan(one, Plan("complete", [c, nxt]))
        assert r.valid, (k, step, c.tolist(), r.problems[:2])
        c = nxt
    return c


def test_single_joint_neighbours_are_checked_together_when_both_move():
    cases = merged_only(22.4, 0.0)
    assert len(cases) >= 5  # the class exists on this lattice: free one at a time, colliding together
    for qa, da, qb, db in cases:
        start = np.array([qa, qb])
        target = start + np.array([da, db])
        target[:, 0] %= 8
        problem = _pair(22.4, 0.0, start, target)
        step = descent_step(problem, problem.start.copy())
        assert step  # robot 0 (first by priority) can always make its move alone
        _assert_steps_valid(problem, problem.start.copy(), [step])
        assert len({p for p, _, _ in step}) == 1, (qa, da, qb, db, step)  # not both at once
        steps, end = descent(problem, problem.start.copy())
        _assert_steps_valid(problem, problem.start.copy(), steps)


@pytest.mark.timeout(120)
@settings(max_examples=30, deadline=None)
@given(dist=st.sampled_from([20.0, 22.4, 26.0, 30.0]), angle=st.sampled_from([0.0, 30.0, 60.0, 90.0]),
       data=st.data())
def test_descent_steps_on_a_tight_lattice_pass_the_validator(dist, angle, data):
    """Random starts and targets of a pair (one joint or two off target each, or anywhere),
    the merged-only moves of the oracle among them: every descent step is valid."""
    cases = merged_only(dist, angle)
    if cases and data.draw(st.booleans()):
        qa, da, qb, db = data.draw(st.sampled_from(cases))
        start = np.array([qa, qb])
        target = start + np.array([da, db]) * data.draw(st.sampled_from([1, 2]))
        target[:, 0] %= 8
        target[:, 1] = np.clip(target[:, 1], 0, 4)
    else:
        start = np.array([[data.draw(st.integers(0, 7)), data.draw(st.integers(0, 4))] for _ in range(2)])
        target = np.array([[data.draw(st.integers(0, 7)), data.draw(st.integers(0, 4))] for _ in range(2)])
    problem = _pair(dist, angle, start, target)
    for conf in (problem.start, problem.target):  # start and target themselves must be free
        r = validate_plan(dataclasses.replace(problem, start=conf, target=conf), Plan("complete", [conf]))
        if not r.valid:
            return
    steps, _ = descent(problem, problem.start.copy(), max_steps=12)
    _assert_steps_valid(problem, problem.start.copy(), steps)
