"""The one-motion checker on floats against the vectorised one and the kinematics it claims to follow.

:func:`supcoord.geometry.chain_motion.chain_motion_collides` must give the verdicts of
:func:`supcoord.geometry.motion.motion_collides` (the same certificate on numpy arrays),
on every kind of robot the planners meet: rotary arms, uniform alpha-beta lattices,
hard-stopped alpha joints, per-robot lattices holding exact angles, calibration offsets
and an off-axis colliding segment; and its chain poses must be the kinematics' segments
at the fractional positions of the motion (including a wrapping joint one step past its
ends).
"""

import numpy as np
import pytest

from supcoord.errors import InputError
from supcoord.geometry import AlphaBeta, Rotary
from supcoord.geometry.chain_motion import _pose, chain_geometry, chain_motion_collides, segment_distance_floats
from supcoord.geometry.motion import motion_collides, placed_segments
from supcoord.geometry.obstacles import obstacle_motion_collides
from supcoord.geometry.segments import segment_distance
from supcoord.problems.validate import segment_distance_ericson


def _kinematics(rng: np.random.Generator, kind: int):
    if kind == 0:
        return Rotary(float(rng.uniform(8, 16)), int(rng.integers(6, 14)))
    if kind == 1:
        return AlphaBeta(7.4, 15.0, int(rng.integers(6, 14)), int(rng.integers(4, 8)), (0.0, 180.0))
    if kind == 2:  # hard stops, an off-axis segment, offsets
        return AlphaBeta(float(rng.uniform(7, 8)), 15.0, 9, 5, (0.0, 180.0), alpha_range=(0.0, 360.0),
                         segment=((0.5, -0.3), (14.7, 0.2)), offsets=(float(rng.uniform(-20, 20)), -0.5))
    # a per-robot lattice: uneven steps, wrapping alpha
    alpha = np.sort(rng.uniform(0, 360, 8))
    alpha = alpha[np.concatenate([[True], np.diff(alpha) > 1.0])]
    beta = np.sort(rng.uniform(0, 180, 5))
    beta = beta[np.concatenate([[True], np.diff(beta) > 1.0])]
    return AlphaBeta(7.4, 15.0, len(alpha), len(beta), (0.0, 180.0), alpha_deg=alpha, beta_deg=beta,
                     offsets=(float(rng.uniform(-10, 10)), 0.0))


def _motion(rng: np.random.Generator, kin):
    """A random position and a delta of at most one position per joint inside the hard stops."""
    while True:
        q = np.array([rng.integers(j.steps) for j in kin.joints])
        d = rng.integers(-1, 2, kin.n_joints)
        end = q + d
        if all(j.wraps or 0 <= e < j.steps for j, e in zip(kin.joints, end)):
            return q, d


@pytest.mark.timeout(60)
def test_segment_distance_floats_is_the_vectorised_formula():
    rng = np.random.default_rng(3)
    pts = rng.uniform(-5, 5, (3000, 4, 2))
    pts[::7, 1] = pts[::7, 0]  # point-like segments
    pts[::11, 3] = pts[::11, 2]
    want = segment_distance(pts[:, 0], pts[:, 1], pts[:, 2], pts[:, 3])
    got = np.array([segment_distance_floats(*p.ravel()) for p in pts])
    assert np.allclose(got, want, rtol=0, atol=1e-12)
    assert (want == 0).sum() > 100  # crossings were exercised


@pytest.mark.timeout(60)
def test_chain_poses_are_the_kinematics_segments():
    rng = np.random.default_rng(5)
    for trial in range(300):
        kin = _kinematics(rng, trial % 4)
        geo = chain_geometry(kin)
        q, d = _motion(rng, kin)
        a0, b0 = geo.angles(tuple(q))
        a1, b1 = geo.angles(tuple(q + d))
        base = rng.uniform(-30, 30, 2)
        params = (base[0], base[1], geo.l1, geo.s0x, geo.s0y, geo.s1x, geo.s1y, a0, a1 - a0, b0, b1 - b0)
        for t in (0.0, 0.3, 1.0):
            want = placed_segments(kin, base, q + t * d).ravel()
            assert np.allclose(_pose(params, t), want, rtol=0, atol=1e-9), (kin, q, d, t)


@pytest.mark.timeout(120)
@pytest.mark.slow
def test_chain_motion_agrees_with_motion_collides():
    rng = np.random.default_rng(11)
    verdicts = []
    for trial in range(1500):
        ka, kb = _kinematics(rng, trial % 4), _kinematics(rng, (trial // 4) % 4)
        if ka.n_joints != kb.n_joints and trial % 2:
            continue
        qa, da = _motion(rng, ka)
        qb, db = _motion(rng, kb)
        if not da.any() and not db.any():
            continue
        direction = rng.uniform(0, 2 * np.pi)
        offset = rng.uniform(15, 40) * np.array([np.cos(direction), np.sin(direction)])
        bsum = float(rng.uniform(2, 6))
        want = bool(motion_collides(ka, (0.0, 0.0), qa, da, kb, offset, qb, db, bsum))
        got = chain_motion_collides(chain_geometry(ka), (0.0, 0.0), qa, da, chain_geometry(kb), offset, qb, db, bsum)
        assert got == want, (ka, qa, da, kb, offset, qb, db, bsum)
        verdicts.append(want)
    assert 0.1 < np.mean(verdicts) < 0.9  # both verdicts were reached


@pytest.mark.timeout(30)
def test_chain_motion_refuses_long_moves():
    kin = AlphaBeta(7.4, 15.0, 12, 7, (0.0, 180.0))
    geo = chain_geometry(kin)
    with pytest.raises(InputError):
        chain_motion_collides(geo, (0, 0), (0, 0), (2, 0), geo, (30, 0), (0, 0), (0, 0), 4.0)
    with pytest.raises(InputError):
        chain_motion_collides(geo, (0, 0), (0, 0), (1, 0), geo, (30, 0), (0, 0), (0, 0), 4.0, tol=0.0)


def _true_min_distance(ka, qa, da, kb, offset, qb, db) -> float:
    """The least distance over the motion: dense samples, then a golden-section refinement
    around the best one, with the validator's independent segment distance."""
    def dist(t):
        t = np.atleast_1d(t)
        sa = placed_segments(ka, (0.0, 0.0), qa + t[:, None] * da)
        sb = placed_segments(kb, offset, qb + t[:, None] * db)
        return segment_distance_ericson(sa[:, 0], sa[:, 1], sb[:, 0], sb[:, 1])

    grid = np.linspace(0.0, 1.0, 4001)
    i = int(np.argmin(dist(grid)))
    lo, hi = grid[max(i - 1, 0)], grid[min(i + 1, len(grid) - 1)]
    g = (np.sqrt(5) - 1) / 2
    for _ in range(80):
        x1, x2 = hi - g * (hi - lo), lo + g * (hi - lo)
        if dist(x1)[0] < dist(x2)[0]:
            hi = x2
        else:
            lo = x1
    return float(min(dist(np.array([lo, hi, 0.0, 1.0]))))


@pytest.mark.timeout(120)
@pytest.mark.slow
def test_grazing_motions_are_decided_at_the_tolerance():
    """``bsum`` a hair (2e-4 mm) below or above the true least distance: free and colliding
    respectively — the certificate decides to within its 1e-6 mm tolerance, not coarser."""
    rng = np.random.default_rng(17)
    checked = 0
    while checked < 60:
        ka, kb = _kinematics(rng, checked % 4), _kinematics(rng, 1 + checked % 3)
        qa, da = _motion(rng, ka)
        qb, db = _motion(rng, kb)
        if np.count_nonzero(da) + np.count_nonzero(db) < 2:
            continue
        direction = rng.uniform(0, 2 * np.pi)
        offset = rng.uniform(18, 30) * np.array([np.cos(direction), np.sin(direction)])
        m = _true_min_distance(ka, qa, da, kb, offset, qb, db)
        if not 0.5 < m < 20:
            continue
        for bsum, want in ((m - 2e-4, False), (m + 2e-4, True)):
            got = chain_motion_collides(chain_geometry(ka), (0.0, 0.0), qa, da, chain_geometry(kb), offset, qb, db,
                                        bsum)
            assert got == want, (ka, qa, da, kb, offset, qb, db, m, bsum)
            assert bool(motion_collides(ka, (0.0, 0.0), qa, da, kb, offset, qb, db, bsum)) == want
        checked += 1


@pytest.mark.timeout(60)
def test_one_obstacle_motion_on_floats_agrees_with_arrays():
    """:func:`obstacle_motion_collides` checks one motion on floats and several on arrays."""
    rng = np.random.default_rng(23)
    verdicts = []
    for trial in range(400):
        kin = _kinematics(rng, 1 + trial % 3)
        q, d = _motion(rng, kin)
        if np.count_nonzero(d) < 2:
            continue
        base = rng.uniform(-5, 5, 2)
        obstacles = rng.uniform(-25, 25, (3, 2, 2))
        buffers = rng.uniform(0.5, 3, 3)
        one = obstacle_motion_collides(kin, base, q, d, 2.0, obstacles, buffers)
        many = obstacle_motion_collides(kin, base, np.stack([q, q]), np.stack([d, d]), 2.0, obstacles, buffers)
        assert one.tolist() == many[:1].tolist()
        verdicts.append(bool(one[0]))
    assert 0.1 < np.mean(verdicts) < 0.9
