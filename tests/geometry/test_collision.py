"""Segment distance, neighbour pairs, static and swept tables against direct geometry."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from supcoord.geometry import AlphaBeta, Rotary, hex_grid
from supcoord.geometry.collision import (
    MAX_TABLE_ENTRIES,
    CollisionTables,
    distance_table,
    motion_collides,
    neighbour_pairs,
    placed_segments,
    segment_distance,
    static_table,
    swept_table,
)
from supcoord.problems.validate import segment_distance_ericson

coord = st.floats(-10, 10, allow_nan=False, allow_infinity=False)
point = st.tuples(coord, coord)


def _brute(p0, p1, q0, q1, n=250):
    t = np.linspace(0, 1, n)[:, None]
    a = np.asarray(p0) + t * (np.asarray(p1) - np.asarray(p0))
    b = np.asarray(q0) + t * (np.asarray(q1) - np.asarray(q0))
    return np.linalg.norm(a[:, None] - b[None], axis=-1).min()


@given(point, point, point, point)
def test_segment_distance_vs_sampling(p0, p1, q0, q1):
    d = float(segment_distance(p0, p1, q0, q1))
    brute = _brute(p0, p1, q0, q1)
    step = max(math.dist(p0, p1), math.dist(q0, q1)) / 249
    assert d <= brute + 1e-9  # the sampled distance can only be larger
    assert brute <= d + step + 1e-9  # ... by at most one sampling step
    assert math.isclose(d, float(segment_distance_ericson(p0, p1, q0, q1)), abs_tol=1e-7)
    assert math.isclose(d, float(segment_distance(q1, q0, p1, p0)), abs_tol=1e-12)


def test_segment_distance_special_cases():
    assert segment_distance([0, 0], [2, 0], [1, -1], [1, 1]) == 0  # crossing
    assert segment_distance([0, 0], [2, 0], [3, 0], [5, 0]) == 1  # collinear, apart
    assert segment_distance([0, 0], [2, 0], [1, 0], [5, 0]) == 0  # collinear, overlapping
    assert math.isclose(segment_distance([0, 0], [0, 0], [3, 4], [3, 4]), 5)  # points
    # vectorised: (3, 1) against (1, 4) broadcast to (3, 4)
    p = np.random.default_rng(0).normal(size=(3, 1, 2, 2))
    q = np.random.default_rng(1).normal(size=(1, 4, 2, 2))
    d = segment_distance(p[..., 0, :], p[..., 1, :], q[..., 0, :], q[..., 1, :])
    assert d.shape == (3, 4)
    assert math.isclose(d[2, 3], float(segment_distance(p[2, 0, 0], p[2, 0, 1], q[0, 3, 0], q[0, 3, 1])))


@settings(max_examples=50)
@given(st.lists(point, min_size=1, max_size=30, unique=True), st.floats(0.5, 5), st.floats(0, 1))
def test_neighbour_pairs_vs_brute_force(points, reach, buffer):
    pairs = {tuple(p) for p in neighbour_pairs(points, reach, buffer).tolist()}
    expect = {(a, b) for a in range(len(points)) for b in range(a + 1, len(points))
              if math.dist(points[a], points[b]) < 2 * reach + 2 * buffer}
    assert pairs == expect


KINEMATICS = [Rotary(10.0, 12), AlphaBeta(4.0, 8.0, 8, 5, (0.0, 180.0)), AlphaBeta(3.0, 6.0, 6, 4, (-180.0, 150.0))]


@pytest.mark.parametrize("kin", KINEMATICS, ids=["rotary", "alpha-beta", "moons-like"])
def test_static_table_vs_direct_geometry(kin):
    base_b = (14.0, 5.0)
    table = static_table(kin, (0, 0), base_b, 3.0)
    pos = kin.all_positions()
    for i, j in np.random.default_rng(1).integers(0, len(pos), size=(300, 2)):
        (a0, a1), (b0, b1) = kin.segments(pos[i]), kin.segments(pos[j]) + base_b
        direct = float(segment_distance_ericson(a0, a1, b0, b1)) < 3.0
        assert table[i, j] == direct
    assert 0 < table.mean() < 1


def _dense_min_distance(kin, base_a, qa, da, base_b, qb, db, n=600):
    t = np.linspace(0, 1, n + 1)[:, None]
    sa = kin.segments(qa + t * da) + base_a
    sb = kin.segments(qb + t * db) + base_b
    return segment_distance_ericson(sa[:, 0], sa[:, 1], sb[:, 0], sb[:, 1]).min()


@pytest.mark.parametrize("kin", KINEMATICS, ids=["rotary", "alpha-beta", "moons-like"])
@pytest.mark.parametrize("mover", [0, 1])
def test_swept_table_vs_dense_sampling(kin, mover):
    base_b, bsum = np.array([13.0, 6.0]), 2.5
    table = swept_table(kin, (0, 0), base_b, bsum, mover)
    static = static_table(kin, (0, 0), base_b, bsum)
    pos = kin.all_positions()
    rng = np.random.default_rng(2)
    swept_only = 0
    for m, (joint, delta) in enumerate(kin.moves()):
        d = np.zeros(kin.n_joints)
        d[joint] = delta
        for i, j in rng.integers(0, len(pos), size=(150, 2)):
            mine = pos[i] if mover == 0 else pos[j]
            nxt = kin.step(mine, joint, delta)
            entry = table[m, i, j]
            if nxt is None:
                assert entry  # past a hard stop: blocked
                continue
            if mover == 0:
                dense = _dense_min_distance(kin, 0, pos[i], d, base_b, pos[j], 0 * d)
                assert static[i, j] <= entry and static[kin.flat_index(nxt), j] <= entry
            else:
                dense = _dense_min_distance(kin, 0, pos[i], 0 * d, base_b, pos[j], d)
                assert static[i, j] <= entry and static[i, kin.flat_index(nxt)] <= entry
            slack = float(kin.sweep_length(d)) / 600 + 1e-3
            if dense < bsum:
                assert entry
            elif dense >= bsum + slack:
                assert not entry
            swept_only += int(entry and not static[i, j])
    assert table.any() and not table.all()


def test_swept_collision_that_the_end_points_miss():
    """Arm of a turns clockwise by 90° through the base of b, whose arm points away."""
    kin = Rotary(10.0, 4)
    base_b = (5.0, -5.0)
    static = static_table(kin, (0, 0), base_b, 2.0)
    assert not static[0, 0] and not static[1, 0]  # a at 0° and at −90°: 5 mm away
    m = kin.moves().index((0, +1))
    assert swept_table(kin, (0, 0), base_b, 2.0, 0)[m, 0, 0]
    assert motion_collides(kin, (0, 0), [0], [1], kin, base_b, [0], [0], 2.0)
    # b moving instead of a (b's arm sweeps from +x to −y, away from a): free
    assert not swept_table(kin, (0, 0), base_b, 2.0, 1)[m, 0, 0]


def test_motion_collides_simultaneous_vs_dense():
    kin = AlphaBeta(4.0, 8.0, 8, 5, (0.0, 180.0))
    rng = np.random.default_rng(3)
    pos = kin.all_positions()
    base_b = np.array([12.0, 0.0])
    qa, qb = pos[rng.integers(0, len(pos), 200)], pos[rng.integers(0, len(pos), 200)]
    da = rng.integers(-1, 2, size=(200, 2))
    db = rng.integers(-1, 2, size=(200, 2))
    got = motion_collides(kin, (0, 0), qa, da, kin, base_b, qb, db, 2.0)
    for k in range(200):
        dense = _dense_min_distance(kin, 0, qa[k], da[k], base_b, qb[k], db[k], n=1000)
        slack = float(kin.sweep_length(da[k]) + kin.sweep_length(db[k])) / 1000 + 1e-3
        if dense < 2.0:
            assert got[k]
        elif dense >= 2.0 + slack:
            assert not got[k]


def test_collision_tables_share_by_offset_and_mirror():
    kin = Rotary(15.0, 12)
    bases = hex_grid(1, 22.4)
    tables = CollisionTables(kin, bases, 2.0)
    assert len(tables.pairs) == 12  # centre–ring (6) + ring–ring neighbours (6)
    for k, (a, b) in enumerate(tables.pairs):
        assert np.array_equal(tables.static(k), static_table(kin, bases[a], bases[b], 4.0))
        for mover in (0, 1):
            assert np.array_equal(tables.swept(k, mover), swept_table(kin, bases[a], bases[b], 4.0, mover))
    stats = tables.statistics()
    assert stats.pairs == 12 and 0 < stats.colliding_fraction < 1 and stats.positioners == len(bases)


def test_distance_table_matches_segments():
    kin = AlphaBeta(4.0, 8.0, 8, 5, (0.0, 180.0))
    D = distance_table(kin, (0, 0), (9.0, 3.0))
    pos = kin.all_positions()
    sa = placed_segments(kin, (0, 0), pos)
    sb = placed_segments(kin, (9.0, 3.0), pos)
    i, j = 17, 33
    assert math.isclose(D[i, j], float(segment_distance(sa[i, 0], sa[i, 1], sb[j, 0], sb[j, 1])))


def test_too_fine_discretisation_is_a_user_error():
    from supcoord.errors import InputError

    with pytest.raises(InputError, match="at most 7071 positions"):  # 1° steps: 65,160 positions
        AlphaBeta(7.4, 15.0, 360, 181, (0.0, 180.0))
    with pytest.raises(InputError, match="at most 7071"):
        Rotary(15.0, 7072)
    kin = AlphaBeta(7.4, 15.0, 84, 84, (0.0, 180.0))  # 7,056 positions: the tables' bound is the same
    assert kin.n_positions**2 <= MAX_TABLE_ENTRIES


@pytest.mark.parametrize("kin", KINEMATICS[:2], ids=["rotary", "alpha-beta"])
def test_simultaneous_table_vs_swept_and_motion(kin):
    from supcoord.geometry.collision import simultaneous_table

    base_b, bsum = np.array([13.0, 6.0]), 2.5
    sim = simultaneous_table(kin, (0, 0), base_b, bsum)
    assert np.array_equal(sim[0, 0], static_table(kin, (0, 0), base_b, bsum))
    assert np.array_equal(sim[1:, 0], swept_table(kin, (0, 0), base_b, bsum, 0))
    assert np.array_equal(sim[0, 1:], swept_table(kin, (0, 0), base_b, bsum, 1))
    pos, moves = kin.all_positions(), [None] + kin.moves()
    rng = np.random.default_rng(5)
    for _ in range(300):
        u, v = rng.integers(0, len(moves), 2)
        i, j = rng.integers(0, len(pos), 2)
        da, db = np.zeros(kin.n_joints), np.zeros(kin.n_joints)
        blocked = False
        for d, mv, q in ((da, moves[u], pos[i]), (db, moves[v], pos[j])):
            if mv is not None:
                d[mv[0]] = mv[1]
                blocked |= kin.step(q, *mv) is None
        expect = blocked or bool(motion_collides(kin, (0, 0), pos[i], da, kin, base_b, pos[j], db, bsum))
        assert sim[u, v, i, j] == expect
    tables = CollisionTables(kin, [[0, 0], base_b, [-13.0, -6.0]], 1.25)
    k01 = [k for k, (a, b) in enumerate(tables.pairs) if (a, b) == (0, 1)][0]
    assert np.array_equal(tables.simultaneous(k01), sim)


def test_segments_module_is_the_collision_distance():
    """One segment distance: collision re-exports geometry.segments' function."""
    from supcoord.geometry import collision, segments

    assert collision.segment_distance is segments.segment_distance
    assert collision.point_segment_distance is segments.point_segment_distance
    assert float(segments.point_segment_distance([1, 1], [0, 0], [2, 0])) == 1.0
    assert float(segments.point_segment_distance([3, 4], [0, 0], [0, 0])) == 5.0  # a point-like segment


@pytest.mark.timeout(30)
def test_segment_distance_in_blocks_equals_one_pass():
    """Long inputs go in blocks (:data:`.segments.BLOCK`): the same numbers as one pass, and as
    the interleaved ``(..., 2)`` form."""
    from supcoord.geometry import segments

    rng = np.random.default_rng(4)
    n = 2 * segments.BLOCK + 1234
    c = rng.normal(size=(8, n)) * 10
    c[2:4, :50] = c[0:2, :50]  # point-like segments
    blocked = segments.segment_distance_xy(*c)
    assert np.array_equal(blocked, segments._segment_distance_xy(*c))
    assert np.array_equal(blocked, segment_distance(c[0:2].T, c[2:4].T, c[4:6].T, c[6:8].T))
    assert (blocked == 0).any() and (blocked > 0).any()
