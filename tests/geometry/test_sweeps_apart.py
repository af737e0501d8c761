"""Two motions at independent times (``supcoord.geometry.sweeps_apart``) against a dense oracle.

The oracle shares no code with the module: its own chain formula for the poses, the
validator's closest-points segment distance (Ericson §5.1.9, not :mod:`supcoord.geometry.segments`),
and a dense ``(s, t)`` grid.  The grid's least distance is at least the true one, and at most
the true one plus ``(L_a + L_b)·h/2`` (``h`` the grid step), which gives:

- soundness: a pair declared apart has no grid point closer than ``bsum``;
- completeness away from the boundary: a pair whose grid minimum clears ``bsum`` by more than
  that slack (and a margin) is declared apart.
"""

import math

import numpy as np
import pytest

from supcoord.errors import InputError
from supcoord.geometry.sweeps_apart import sweeps_apart
from supcoord.problems.validate import segment_distance_ericson

pytestmark = pytest.mark.timeout(120)

ALPHA, BETA = 7.4, 15.0
REACH = ALPHA + BETA
GRID = 121


def _segments(row, s):
    """The oracle's placed segment of a motion row at times ``s``: ``(len(s), 2, 2)``."""
    bx, by, l1, s0x, s0y, s1x, s1y, a0, da, b0, db = row
    a = a0 + s * da
    ab = a + b0 + s * db
    ex, ey = bx + l1 * np.cos(a), by + l1 * np.sin(a)
    c, sn = np.cos(ab), np.sin(ab)
    p0 = np.stack([ex + s0x * c - s0y * sn, ey + s0x * sn + s0y * c], axis=-1)
    p1 = np.stack([ex + s1x * c - s1y * sn, ey + s1x * sn + s1y * c], axis=-1)
    return np.stack([p0, p1], axis=1)


def _grid_min(ra, rb):
    s = np.linspace(0.0, 1.0, GRID)
    sa, sb = _segments(ra, s), _segments(rb, s)
    A = np.repeat(sa, GRID, axis=0)
    B = np.tile(sb, (GRID, 1, 1))
    return float(segment_distance_ericson(A[:, 0], A[:, 1], B[:, 0], B[:, 1]).min())


def _random_pairs(rng, count):
    rows_a, rows_b, la, lb = [], [], [], []
    for _ in range(count):
        offset = rng.uniform(14.0, 40.0)
        phi = rng.uniform(0, 2 * math.pi)
        base_b = (offset * math.cos(phi), offset * math.sin(phi))
        out = []
        for base in ((0.0, 0.0), base_b):
            da = math.radians(rng.choice([0.0, 1.0, -1.0]) * rng.uniform(5, 40))
            db = math.radians(rng.choice([0.0, 1.0, -1.0]) * rng.uniform(5, 45))
            tip_y = rng.uniform(-0.4, 0.4)
            radius = math.hypot(BETA, tip_y)  # of the segment about the elbow
            out.append(((*base, ALPHA, 0.0, 0.0, BETA, tip_y, rng.uniform(0, 2 * math.pi), da,
                         rng.uniform(0, math.pi), db),
                        (ALPHA + radius) * abs(da) + radius * abs(db)))
        (ra, a_len), (rb, b_len) = out
        rows_a.append(ra)
        rows_b.append(rb)
        la.append(a_len)
        lb.append(b_len)
    return np.array(rows_a), np.array(rows_b), np.array(la), np.array(lb)


def test_declared_apart_only_when_no_pose_pair_comes_closer_and_always_when_far_enough():
    rng = np.random.default_rng(20261128)
    ra, rb, la, lb = _random_pairs(rng, 400)
    grid = np.array([_grid_min(a, b) for a, b in zip(ra, rb)])
    # put bsum near each pair's least distance, on both sides, to reach every branch
    bsum = np.maximum(0.1, grid + rng.uniform(-0.6, 0.6, len(grid)))
    got = sweeps_apart(ra, la, rb, lb, bsum)
    slack = (la + lb) / (GRID - 1) / 2
    assert not np.any(got & (grid < bsum)), np.nonzero(got & (grid < bsum))
    far = grid - slack >= bsum + 0.05
    assert far.sum() > 40 and np.all(got[far]), np.nonzero(far & ~got)
    assert (~got).sum() > 100 and (got & ~far).sum() > 10  # both answers, and apart near the boundary


def test_a_standing_robot_and_the_rows_checks():
    # robot b stands (no turn): apart exactly when robot a's swept arc keeps bsum from b's segment
    a = np.array([[0.0, 0.0, ALPHA, 0.0, 0.0, BETA, 0.0, 0.0, math.pi / 2, 0.0, 0.0]])  # 0° -> 90°
    b = np.array([[30.0, 0.0, ALPHA, 0.0, 0.0, BETA, 0.0, math.pi, 0.0, 0.0, 0.0]])  # pointing at a's base
    length = np.array([REACH * math.pi / 2])
    # a at 0° reaches (22.4, 0); b's segment runs from (22.6, 0) to (7.6, 0): they cross
    assert not sweeps_apart(a, length, b, np.zeros(1), 1.0)[0]
    b[0, 7] = math.pi / 2  # b up: its segment from (30, 7.4) to (30, 22.4), 7.6 mm from a's tip
    assert sweeps_apart(a, length, b, np.zeros(1), 4.0)[0]
    assert not sweeps_apart(a, length, b, np.zeros(1), 9.0)[0]
    with pytest.raises(InputError, match="tol"):
        sweeps_apart(a, length, b, np.zeros(1), 4.0, tol=0)
    with pytest.raises(InputError, match="equal count"):
        sweeps_apart(a, length, np.repeat(b, 2, axis=0), np.zeros(2), 4.0)
