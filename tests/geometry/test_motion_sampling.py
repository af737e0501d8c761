"""The certified sampling of simultaneous motions (``motion._bisect_collides``) places the
segments on one-dimensional coordinate rows and keeps its open intervals as one array per
field: the same distances bit for bit as ``placed_segments`` + ``segment_coords``, and the same
verdicts as the bisection written out the old way (one ``(n, 5)`` row matrix), on every
robot kind and on buffers placed exactly at sampled distances."""

import numpy as np
import pytest

from supcoord.geometry import motion
from supcoord.geometry.kinematics import AlphaBeta, Rotary
from supcoord.geometry.obstacles import FixedSegment
from supcoord.geometry.segments import segment_coords, segment_distance_xy

from .test_chain_motion import _kinematics


def _entries(rng: np.random.Generator, kin, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Random bases, fractional start positions and deltas of up to two positions per joint."""
    steps = np.array([j.steps for j in kin.joints], float)
    q = rng.uniform(0.0, 1.0, (n, kin.n_joints)) * (steps - 1)
    d = rng.integers(-2, 3, (n, kin.n_joints)).astype(float)
    base = rng.normal(0.0, 12.0, (n, 2))
    return base, q, d


def _old_coords(kin, base, q, d, i, t):
    return segment_coords(motion.placed_segments(kin, base[i], q[i] + t[:, None] * d[i]))


@pytest.mark.parametrize("kind", [0, 1, 2, 3, 4])
def test_coordinate_rows_are_bitwise_placed_segments(kind):
    rng = np.random.default_rng(kind)
    kin = FixedSegment(((1.0, -2.0), (-0.0, 3.5))) if kind == 4 else _kinematics(rng, kind)
    base, q, d = _entries(rng, kin, 300)
    moving = motion._Moving(kin, base, q, d)
    assert (moving.chain is None) == (kind == 4)
    i = rng.integers(0, 300, 2000)
    t = np.concatenate([[0.0, 1.0, 0.5], rng.uniform(0.0, 1.0, 1997)])
    new, old = moving.coords(i, t), _old_coords(kin, base, q, d, i, t)
    for a, b in zip(new, old):
        assert np.array_equal(np.asarray(a).view(np.int64), np.ascontiguousarray(b).view(np.int64))


def _old_bisect(kin_a, base_a, qa, da, kin_b, base_b, qb, db, bsum, length, tol, coarse):
    """The bisection as it was written before: one row matrix ``(entry, t0, t1, d0, d1)``."""
    hit = np.zeros(len(qa), dtype=bool)

    def dist(e, t):
        sa = _old_coords(kin_a, base_a, qa, da, e, t)
        sb = _old_coords(kin_b, base_b, qb, db, e, t)
        return segment_distance_xy(*sa, *sb)

    grid = np.linspace(0.0, 1.0, coarse + 1)
    e = np.repeat(np.arange(len(qa)), coarse + 1)
    d = dist(e, np.tile(grid, len(qa))).reshape(len(qa), coarse + 1)
    hit |= (d < bsum[:, None]).any(axis=1)
    ee, ii = (g.ravel() for g in np.meshgrid(np.arange(len(qa)), np.arange(coarse), indexing="ij"))
    rows = np.stack([ee, grid[ii], grid[ii + 1], d[ee, ii], d[ee, ii + 1]], axis=1)
    while len(rows):
        rows = rows[~hit[rows[:, 0].astype(int)]]
        e = rows[:, 0].astype(int)
        bound = (rows[:, 3] + rows[:, 4] - length[e] * (rows[:, 2] - rows[:, 1])) / 2
        open_ = bound < bsum[e]
        stuck = open_ & (length[e] * (rows[:, 2] - rows[:, 1]) / 2 <= tol)
        hit[e[stuck]] = True
        rows = rows[open_ & ~stuck & ~hit[e]]
        if not len(rows):
            break
        e = rows[:, 0].astype(int)
        mid = (rows[:, 1] + rows[:, 2]) / 2
        dm = dist(e, mid)
        hit[e[dm < bsum[e]]] = True
        rows = np.concatenate([np.stack([e, rows[:, 1], mid, rows[:, 3], dm], axis=1),
                               np.stack([e, mid, rows[:, 2], dm, rows[:, 4]], axis=1)])
    return hit


@pytest.mark.parametrize("kinds", [(1, 1), (2, 3), (0, 0), (3, 4)])
def test_bisection_verdicts_are_the_row_matrix_ones(kinds):
    rng = np.random.default_rng(10 + kinds[0] * 5 + kinds[1])
    kin_a = _kinematics(rng, kinds[0])
    kin_b = FixedSegment(((0.0, 0.0), (6.0, 1.0))) if kinds[1] == 4 else _kinematics(rng, kinds[1])
    n = 400
    base_a, qa, da = _entries(rng, kin_a, n)
    base_b, qb, db = _entries(rng, kin_b, n)
    base_b = base_a + rng.normal(0.0, 12.0, (n, 2))  # neighbours: within reach of each other
    length = kin_a.sweep_length(da) + kin_b.sweep_length(db)
    # buffers around the distances at the coarse samples (some exactly equal: the strict `<`)
    ends = segment_distance_xy(*_old_coords(kin_a, base_a, qa, da, np.arange(n), np.full(n, 0.5)),
                               *_old_coords(kin_b, base_b, qb, db, np.arange(n), np.full(n, 0.5)))
    bsum = ends + rng.choice([-1.0, -1e-3, 0.0, 0.0, 1e-9, 1e-3, 0.5], n)
    # a coarse tolerance keeps the intervals few where a buffer grazes the distance's minimum
    args = (kin_a, base_a, qa, da, kin_b, base_b, qb, db, bsum, length, 1e-3, 4)
    new, old = motion._bisect_collides(*args), _old_bisect(*args)
    assert 0 < old.sum() < n
    assert np.array_equal(new, old)


def test_isinstance_dispatch_covers_the_chain_robots():
    assert motion._Moving(Rotary(10.0, 8), np.zeros((1, 2)), np.zeros((1, 1)), np.zeros((1, 1))).chain is not None
    kin = AlphaBeta(7.4, 15.0, 9, 5)
    assert motion._Moving(kin, np.zeros((1, 2)), np.zeros((1, 2)), np.zeros((1, 2))).chain == kin.chain()
