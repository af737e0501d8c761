"""The one-motion checker's inlined distance decides exactly what the pose-by-pose formula does.

:func:`supcoord.geometry.chain_motion.chain_motion_collides` evaluates the distance of the
two chains at a time ``t`` in one function (``_distance``) instead of placing each segment
(:func:`~supcoord.geometry.chain_motion._pose`) and then measuring
(:func:`~supcoord.geometry.chain_motion.segment_distance_floats`).  The operations are the
same, in the same order, so the distances must be equal to the last bit and the verdicts
identical to the refinement written out with the two calls (``_reference`` below), on
heterogeneous robots (rotary arms, alpha-beta lattices with offsets, hard stops, per-robot
lattices, a wrapping alpha joint one step past its ends), single- and two-joint moves of one
or both robots, and buffers just above a sampled distance (by the tolerance or less, decided
at that sample) or slightly below it (a deep refinement).  A buffer equal to a distance that
stays constant over a stretch (a segment turning about its own end) would take the
refinement to the tolerance everywhere there: exponential, so not drawn here.
"""

from __future__ import annotations

import numpy as np
import pytest

from supcoord.geometry import AlphaBeta, Rotary
from supcoord.geometry.chain_motion import _distance, _pose, chain_geometry, chain_motion_collides, \
    segment_distance_floats


def _kinematics(rng: np.random.Generator, kind: int):
    if kind == 0:
        return Rotary(float(rng.uniform(8, 16)), int(rng.integers(6, 14)))
    if kind == 1:
        return AlphaBeta(7.4, 15.0, int(rng.integers(6, 14)), int(rng.integers(4, 8)), (0.0, 180.0),
                         offsets=(float(rng.uniform(-10, 10)), float(rng.uniform(-1, 1))))
    if kind == 2:  # hard stops and an off-axis segment
        return AlphaBeta(float(rng.uniform(7, 8)), 15.0, 9, 5, (0.0, 180.0), alpha_range=(0.0, 360.0),
                         segment=((0.5, -0.3), (14.7, 0.2)), offsets=(float(rng.uniform(-20, 20)), -0.5))
    alpha = np.unique(np.round(rng.uniform(0, 360, 8), 1))
    beta = np.unique(np.round(rng.uniform(0, 180, 5), 1))
    return AlphaBeta(7.4, 15.0, len(alpha), len(beta), (0.0, 180.0), alpha_deg=alpha, beta_deg=beta)


def _motion(rng: np.random.Generator, kin, joints: int):
    """A position and a delta turning ``joints`` joints (at most the robot's) by one position."""
    while True:
        q = tuple(int(rng.integers(j.steps)) for j in kin.joints)
        d = [0] * kin.n_joints
        for j in rng.permutation(kin.n_joints)[:joints]:
            d[j] = int(rng.choice((-1, 1)))
        if all(j.wraps or 0 <= x + v < j.steps for j, x, v in zip(kin.joints, q, d)):
            return q, tuple(d)


def _reference(geo_a, base_a, qa, da, geo_b, base_b, qb, db, bsum, tol=1e-6, coarse=4) -> bool:
    """The refinement of :mod:`supcoord.geometry.chain_motion` with the pose-by-pose distance."""
    a0, b0 = geo_a.angles(qa)
    a1, b1 = geo_a.angles(tuple(x + d for x, d in zip(qa, da)))
    c0, e0 = geo_b.angles(qb)
    c1, e1 = geo_b.angles(tuple(x + d for x, d in zip(qb, db)))
    length = geo_a.length(da) + geo_b.length(db)
    pa = (float(base_a[0]), float(base_a[1]), geo_a.l1, geo_a.s0x, geo_a.s0y, geo_a.s1x, geo_a.s1y, a0, a1 - a0,
          b0, b1 - b0)
    pb = (float(base_b[0]), float(base_b[1]), geo_b.l1, geo_b.s0x, geo_b.s0y, geo_b.s1x, geo_b.s1y, c0, c1 - c0,
          e0, e1 - e0)

    def dist(t):
        return segment_distance_floats(*_pose(pa, t), *_pose(pb, t))

    d_start, d_end = dist(0.0), dist(1.0)
    if d_start < bsum or d_end < bsum:
        return True
    if (d_start + d_end - length) / 2 >= bsum:
        return False
    grid = [k / coarse for k in range(coarse + 1)]
    ds = [d_start] + [dist(t) for t in grid[1:-1]] + [d_end]
    if min(ds) < bsum:
        return True
    stack = [(grid[k], grid[k + 1], ds[k], ds[k + 1]) for k in range(coarse)]
    while stack:
        t0, t1, d0, d1 = stack.pop()
        span = length * (t1 - t0)
        if (d0 + d1 - span) / 2 >= bsum:
            continue
        if span / 2 <= tol:
            return True
        mid = (t0 + t1) / 2
        dm = dist(mid)
        if dm < bsum:
            return True
        stack.append((t0, mid, d0, dm))
        stack.append((mid, t1, dm, d1))
    return False


@pytest.mark.timeout(60)
def test_inlined_distance_is_the_pose_formula_to_the_bit():
    rng = np.random.default_rng(7)
    for _ in range(4000):
        pa, pb = (tuple(rng.uniform(-40, 40, 2)) + (float(rng.choice([0.0, rng.uniform(5, 10)])),)
                  + tuple(rng.uniform(-16, 16, 4)) + tuple(rng.uniform(-7, 7, 4)) for _ in range(2))
        t = float(rng.choice([0.0, 1.0, 0.5, rng.random()]))
        assert _distance(pa, pb)(t) == segment_distance_floats(*_pose(pa, t), *_pose(pb, t)), (pa, pb, t)


@pytest.mark.timeout(120)
def test_verdicts_are_the_pose_by_pose_refinement_also_when_grazing():
    rng = np.random.default_rng(13)
    verdicts, grazing = [], 0
    for trial in range(150):
        ka, kb = _kinematics(rng, trial % 4), _kinematics(rng, (trial // 4) % 4)
        ga, gb = chain_geometry(ka), chain_geometry(kb)
        qa, da = _motion(rng, ka, int(rng.integers(0, ka.n_joints + 1)))
        qb, db = _motion(rng, kb, int(rng.integers(0 if any(da) else 1, kb.n_joints + 1)))
        direction = rng.uniform(0, 2 * np.pi)
        base_b = tuple(rng.uniform(12, 36) * np.array([np.cos(direction), np.sin(direction)]))
        if trial % 3:
            bsum = float(rng.uniform(1, 6))
        else:  # a buffer at a distance the refinement samples: just above it, or slightly below
            pa = (0.0, 0.0, ga.l1, ga.s0x, ga.s0y, ga.s1x, ga.s1y) + _angles(ga, qa, da)
            pb = (base_b[0], base_b[1], gb.l1, gb.s0x, gb.s0y, gb.s1x, gb.s1y) + _angles(gb, qb, db)
            t = float(rng.choice([0.0, 0.25, 0.5, 0.375, 1.0]))
            bsum = segment_distance_floats(*_pose(pa, t), *_pose(pb, t)) + float(rng.choice([-1e-3, -1e-4, 1e-9, 1e-6]))
            grazing += 1
        want = _reference(ga, (0.0, 0.0), qa, da, gb, base_b, qb, db, bsum)
        assert chain_motion_collides(ga, (0.0, 0.0), qa, da, gb, base_b, qb, db, bsum) == want, \
            (ka, qa, da, kb, base_b, qb, db, bsum)
        verdicts.append(want)
    assert grazing > 35 and 0.1 < np.mean(verdicts) < 0.9  # both verdicts, many grazing cases


def _angles(geo, q, d):
    a0, b0 = geo.angles(q)
    a1, b1 = geo.angles(tuple(x + v for x, v in zip(q, d)))
    return (a0, a1 - a0, b0, b1 - b0)
