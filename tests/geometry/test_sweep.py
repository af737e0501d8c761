"""Exact swept checks, the true reach and sweep length, against dense brute force.

The brute force here uses the validator's segment distance (an independent algorithm) on
densely sampled poses, so it shares no formula with :mod:`supcoord.geometry.sweep`.
"""

import dataclasses
import math

import numpy as np
import pytest

from supcoord.geometry import AlphaBeta, Rotary
from supcoord.geometry.collision import CollisionTables, static_table, swept_table
from supcoord.geometry.layout import hex_grid
from supcoord.geometry.sweep import (
    annulus_clear,
    arc_segment_distance,
    bisect_turns,
    rotation_certain,
    rotation_clearance,
    turn_radii,
    turn_slack,
)
from supcoord.planning.planner import solve
from supcoord.problems.problem import parse_problem
from supcoord.problems.validate import segment_distance_ericson, validate_plan


def _turn(points, centre, phi):
    """Points ``(..., 2)`` turned by the angles ``phi`` ``(S,)`` about ``centre``: ``(S, ..., 2)``."""
    rel = np.asarray(points, float) - centre
    c, s = np.cos(phi), np.sin(phi)
    c, s = c.reshape((-1,) + (1,) * (rel.ndim - 1)), s.reshape((-1,) + (1,) * (rel.ndim - 1))
    return centre + np.stack([c * rel[..., 0] - s * rel[..., 1], s * rel[..., 0] + c * rel[..., 1]], axis=-1)


def _dense_turn_min(seg, centre, angle, other, samples=40001):
    moved = _turn(seg, np.asarray(centre, float), np.linspace(0.0, angle, samples))
    other = np.asarray(other, float)
    return float(segment_distance_ericson(moved[:, 0], moved[:, 1], other[0], other[1]).min())


@pytest.mark.timeout(120)
@pytest.mark.slow
def test_rotation_clearance_vs_dense_sampling():
    rng = np.random.default_rng(7)
    for trial in range(400):
        seg, other = rng.uniform(-6, 6, (2, 2, 2))
        centre = seg[0] if trial % 3 == 0 else rng.uniform(-4, 4, 2)  # beta turns about an end
        angle = rng.uniform(-1.2, 1.2)
        exact = float(rotation_clearance(seg, centre, angle, other))
        dense = _dense_turn_min(seg, centre, angle, other)
        lever = max(np.linalg.norm(seg - centre, axis=1).max(), np.linalg.norm(other - centre, axis=1).max())
        step = lever * abs(angle) / 40000
        assert exact <= dense + 1e-9, (trial, exact, dense)  # every sample is an actual pose
        assert dense <= exact + step + 1e-9, (trial, exact, dense)  # and one lies within a step of the minimum


def test_arc_segment_distance_cases():
    # the arc's interior point nearest to the segment (radius normal to it)
    assert math.isclose(float(arc_segment_distance([0, 0], [1, 0], math.pi, [-3, 2], [3, 2])), 1.0)
    # the same arc turned the other way never comes near the segment above the x axis
    assert math.isclose(float(arc_segment_distance([0, 0], [1, 0], -math.pi / 2, [-3, 2], [3, 2])), 2.0)
    # a point-like segment: its distance to the arc
    assert math.isclose(float(arc_segment_distance([0, 0], [2, 0], math.pi / 2, [0, 3], [0, 3])), 1.0)
    # a point on the centre does not move
    assert math.isclose(float(arc_segment_distance([1, 1], [1, 1], 1.0, [1, 4], [5, 4])), 3.0)


@pytest.mark.parametrize("beta_range", [(0.0, 180.0), (150.0, 180.0), (-30.0, 60.0), (90.0, 270.0), (-200.0, -170.0)])
@pytest.mark.parametrize("arms", [(10.0, 5.0), (7.4, 15.0), (3.0, 3.0)])
def test_alpha_beta_reach_is_the_true_maximum(beta_range, arms):
    kin = AlphaBeta(arms[0], arms[1], 6, 4, beta_range)
    alpha, beta = np.meshgrid(np.linspace(0, 2 * np.pi, 73), np.radians(np.linspace(*beta_range, 2001)))
    s = np.linspace(0, 1, 21)[:, None, None]
    x = arms[0] * np.cos(alpha) + s * arms[1] * np.cos(alpha + beta)
    y = arms[0] * np.sin(alpha) + s * arms[1] * np.sin(alpha + beta)
    brute = float(np.hypot(x, y).max())
    assert brute <= kin.reach + 1e-9
    assert kin.reach <= brute + 1e-3 * max(arms)


@pytest.mark.parametrize("beta_range", [(0.0, 180.0), (150.0, 180.0), (-30.0, 60.0)])
def test_sweep_length_bounds_every_point_path(beta_range):
    kin = AlphaBeta(10.0, 5.0, 8, 5, beta_range)
    rng = np.random.default_rng(3)
    t = np.linspace(0, 1, 401)[:, None, None]
    for joint, delta in kin.moves():
        d = np.zeros(2)
        d[joint] = delta
        bound = float(kin.sweep_length(d))
        for q in rng.uniform([0, 0], [8, 4], (30, 2)):
            seg = kin.segments(q + t * d)  # (T, 1, 2, 2)
            for s in np.linspace(0, 1, 11):
                path = seg[:, 0, 0] + s * (seg[:, 0, 1] - seg[:, 0, 0])
                assert np.linalg.norm(np.diff(path, axis=0), axis=1).sum() <= bound + 1e-9


def test_folded_beta_range_finds_the_elbow_pair():
    """alpha 10, beta 5, beta in [150°, 180°], bases 16 mm apart: only the elbows can meet."""
    data = {"layout": {"kind": "points", "xy": [[0, 0], [16, 0]]},
            "kinematics": {"kind": "alpha-beta", "alpha": 10, "beta": 5, "alpha_steps": 8, "beta_steps": 3,
                           "beta_range": [150, 180]},
            "collision": {"buffer": 1.0}, "start": [[0, 0], [4, 0]], "target": [[0, 0], [4, 0]]}
    kin = AlphaBeta(10, 5, 8, 3, (150, 180))
    assert kin.reach == 10.0
    with pytest.raises(Exception, match="collide"):  # both elbows pointing at each other: 4 mm apart
        parse_problem(data)
    data["start"] = data["target"] = [[4, 0], [0, 0]]  # both pointing away
    problem = parse_problem(data)
    assert problem.pairs.tolist() == [[0, 1]]
    data["target"] = [[0, 0], [0, 0]]
    plan = solve(parse_problem(data))
    assert plan.status == "complete" and validate_plan(parse_problem(data), plan).valid


def _tight_pass(clearance):
    """Rotary a turns 0 → 1 (0° → −30°) past b's fibre with ``clearance`` mm to spare over
    the buffers; the long way round is blocked by c's base, so the tight pass is the only route."""
    kin, bsum = Rotary(10.0, 12), 2.0
    direction = np.array([math.cos(math.radians(-15)), math.sin(math.radians(-15))])
    seg_b = np.array([[0.0, 0.0], [-10.0, 0.0]])  # b at position 6: pointing −x

    def gap(dist):
        other = seg_b + dist * direction
        return float(rotation_clearance(kin.segments([0.0]), [0, 0], -math.pi / 6, other)) - bsum

    lo, hi = 15.0, 30.0
    for _ in range(200):
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if gap(mid) < clearance else (lo, mid)
    base_b = hi * direction
    data = {"layout": {"kind": "points", "xy": [[0, 0], base_b.tolist(), [-11.0, 0.0]]},
            "kinematics": {"kind": "rotary", "arm": 10, "steps": 12}, "collision": {"buffer": 1.0},
            "start": [0, 6, 6], "target": [1, 6, 6]}
    return parse_problem(data), base_b


@pytest.mark.timeout(60)
@pytest.mark.parametrize("clearance", [5e-4, 1.2e-4, 1e-7])
def test_tight_pass_is_free_and_solved(clearance):
    problem, base_b = _tight_pass(clearance)
    kin = problem.kinematics
    dense = _dense_turn_min(kin.segments([0.0]), [0, 0], -math.pi / 6, np.array([[0.0, 0.0], [-10.0, 0.0]]) + base_b,
                            samples=200001)
    assert 2.0 + clearance - 1e-9 <= dense <= 2.0 + clearance + 1e-6  # independent: the pass really has that clearance
    m = kin.moves().index((0, +1))
    assert not swept_table(kin, (0, 0), base_b, 2.0, 0)[m, 0, 6]
    plan = solve(problem)
    assert plan.status == "complete" and plan.makespan == 1
    assert validate_plan(problem, plan).valid


@pytest.mark.timeout(60)
def test_tight_pass_that_grazes_is_blocked():
    problem, base_b = _tight_pass(-1e-6)  # 1 µm inside the buffers: a collision
    kin = problem.kinematics
    m = kin.moves().index((0, +1))
    assert not static_table(kin, (0, 0), base_b, 2.0)[0, 6] and not static_table(kin, (0, 0), base_b, 2.0)[1, 6]
    assert swept_table(kin, (0, 0), base_b, 2.0, 0)[m, 0, 6]
    plan = solve(problem)  # b has to turn out of the way and back
    assert plan.status == "complete" and validate_plan(problem, plan).valid
    assert plan.stats["single_moves"] >= 3
    assert any(c[1] != 6 for c in plan.configurations)


def _random_turns(seed, n):
    """``n`` random turns: segments, centres (a third at the segment's first end, as beta turns),
    angles up to ±π, standing segments (some far, some inside the annulus) and buffer sums."""
    rng = np.random.default_rng(seed)
    seg, other = rng.uniform(-6, 6, (n, 2, 2)), rng.uniform(-6, 6, (n, 2, 2))
    centre = np.where((np.arange(n) % 3 == 0)[:, None], seg[:, 0], rng.uniform(-4, 4, (n, 2)))
    scale = rng.choice([0.05, 1.0, 3.0], n)[:, None, None]  # standing segments near, around or far from the centre
    other = centre[:, None] + scale * (other - centre[:, None])
    angle = rng.uniform(-1, 1, n) * rng.choice([0.1, 0.6, np.pi], n)
    bsum = rng.uniform(0.0, 3.0, n)
    return seg, centre, angle, other, bsum


@pytest.mark.timeout(60)
def test_rotation_certain_is_sound():
    """Every entry the cheap tests call free keeps the buffers; every one they call hit does not."""
    seg, centre, angle, other, bsum = _random_turns(11, 6000)
    exact = rotation_clearance(seg, centre, angle, other)
    for depth in (0, 1, 2, 3):
        free, hit = rotation_certain(seg, centre, angle, other, bsum, depth=depth)
        assert not np.any(free & hit)
        assert np.all(exact[free] >= bsum[free]), depth
        assert np.all(exact[hit] < bsum[hit]), depth
        assert free.mean() > 0.2 and hit.mean() > 0.2  # both sides are exercised
    # deeper bisection decides more
    assert rotation_certain(seg, centre, angle, other, bsum, depth=3)[0].sum() > \
        rotation_certain(seg, centre, angle, other, bsum, depth=0)[0].sum()


@pytest.mark.timeout(60)
def test_annulus_clear_is_sound():
    seg, centre, angle, other, bsum = _random_turns(12, 6000)
    r_min, r_max = turn_radii(seg, centre)
    clear = annulus_clear(centre, r_min, r_max, other, bsum)
    exact = rotation_clearance(seg, centre, angle, other)
    assert 0.05 < clear.mean() < 0.95
    assert np.all(exact[clear] >= bsum[clear])
    # both cases occur: the standing segment outside the annulus, and inside its hole
    far = np.maximum(np.linalg.norm(other[:, 0] - centre, axis=1), np.linalg.norm(other[:, 1] - centre, axis=1))
    assert np.any(clear & (far < r_min)) and np.any(clear & (far > r_max))


@pytest.mark.timeout(60)
def test_bisect_turns_is_sound_at_every_depth():
    """The sampled bound alone (no annulus): open entries aside, its verdicts match the closed form."""
    seg, centre, angle, other, bsum = _random_turns(13, 6000)
    exact = rotation_clearance(seg, centre, angle, other)
    _, r_max = turn_radii(seg, centre)

    def turned(k, width):  # every segment turned by k/width of its angle: (n, 2, 2)
        c, s = np.cos(angle * k / width)[:, None], np.sin(angle * k / width)[:, None]
        rel = seg - centre[:, None]
        return centre[:, None] + np.stack([c * rel[..., 0] - s * rel[..., 1], s * rel[..., 0] + c * rel[..., 1]],
                                          axis=-1)

    for depth in (0, 1, 2, 3):
        width = 2 ** depth
        poses = [turned(k, width) for k in range(width + 1)]
        dist = np.stack([segment_distance_ericson(p[:, 0], p[:, 1], other[:, 0], other[:, 1]) for p in poses], axis=1)

        def pose_distance(e, k, dist=dist):
            return dist[e, k]

        slack = np.stack([turn_slack(r_max, angle, 2 ** level) for level in range(depth + 1)], axis=-1)
        hit, open_ = bisect_turns(dist[:, 0], dist[:, -1], slack, bsum, pose_distance, depth)
        free = ~hit & ~open_ & (np.minimum(dist[:, 0], dist[:, -1]) >= bsum)
        assert free.mean() > 0.1 and (depth == 0 or hit.mean() > 0.05)  # depth 0 samples no pose inside
        assert np.all(exact[free] >= bsum[free]), depth
        assert np.all(exact[hit] < bsum[hit]), depth


@pytest.mark.timeout(60)
@pytest.mark.parametrize("unary", [False, True], ids=["plain", "unary"])
def test_batch_swept_matches_the_pairwise_tables(unary):
    """:meth:`CollisionTables.prepare` (:func:`.batch.batch_swept`, with its cheap tests) gives
    exactly the tables :func:`swept_table` computes pair by pair, robots with their own arms,
    lattices and stops; with unary tables (obstacles, held robots) folded in on either side."""
    rng = np.random.default_rng(5)
    bases = hex_grid(2, 16.0)
    kins = [AlphaBeta(float(rng.uniform(6, 10)), float(rng.uniform(8, 15)), int(rng.integers(5, 9)),
                      int(rng.integers(3, 6)), [(0.0, 180.0), (-30.0, 150.0), (150.0, 180.0)][p % 3],
                      alpha_range=None if p % 4 else (0.0, 300.0)) for p in range(len(bases))]
    folded = {p: (rng.random(kins[p].n_positions) < 0.1, rng.random((len(kins[p].moves()), kins[p].n_positions)) < 0.1)
              for p in range(0, len(bases), 2)} if unary else None
    batch = CollisionTables(kins[0], bases, 1.5, kins=kins, unary=folded)
    batch.prepare(range(len(batch.pairs)))
    single = CollisionTables(kins[0], bases, 1.5, kins=kins, unary=folded)
    for k in range(len(batch.pairs)):
        for mover in (0, 1):
            assert np.array_equal(batch.swept(k, mover), single.swept(k, mover)), (k, mover)


@pytest.mark.timeout(60)
def test_tables_survive_eviction_and_are_read_only(monkeypatch):
    """With the distance and unpacked-table caches at one byte (every table but the newest
    dropped), static, swept and distance tables, read in any order and again, are exactly
    those of a run that keeps everything; and no caller can write into a shared table."""
    from supcoord.geometry import collision
    from supcoord.geometry.table_store import PackedTables, RecentArrays

    rng = np.random.default_rng(7)
    bases = hex_grid(2, 16.0)
    kins = [AlphaBeta(float(rng.uniform(6, 10)), float(rng.uniform(8, 15)), int(rng.integers(5, 9)),
                      int(rng.integers(3, 6)), (0.0, 180.0)) for p in range(len(bases))]
    kept = CollisionTables(kins[0], bases, 1.5, kins=kins)
    kept.prepare(range(len(kept.pairs)))
    monkeypatch.setattr(collision, "DIST_CACHE_BYTES", 1)
    monkeypatch.setattr(collision, "UNPACKED_CACHE_BYTES", 1)
    tight = CollisionTables(kins[0], bases, 1.5, kins=kins)
    tight.prepare(range(len(tight.pairs)))
    assert len(tight._dist) == 0 and len(tight._bits._recent) == 1
    order = list(range(len(kept.pairs))) * 2
    rng.shuffle(order)
    for k in order:
        for mover in (0, 1):
            assert np.array_equal(tight.swept(k, mover), kept.swept(k, mover)), (k, mover)
        assert np.array_equal(tight.static(k), kept.static(k)), k
        a, b = (int(x) for x in kept.pairs[k])
        direct = collision.distance_table(kins[a], bases[a], bases[b], kins[b])  # at the bases, not the offset
        assert np.allclose(tight.distances(k), direct, rtol=0, atol=1e-9), k
        for table in (tight.swept(k, 0), tight.static(k), tight.distances(k)):
            with pytest.raises(ValueError):
                table[(0,) * table.ndim] = True
    assert len(tight._dist) == 1 and tight._bits.packed_bytes * 6 < sum(kept.swept(k, 0).nbytes * 3 for k in range(
        len(kept.pairs)))
    # the stores themselves
    store = RecentArrays(100)
    store.put("a", np.zeros(60, np.uint8))
    store.put("b", np.zeros(30, np.uint8))
    assert store.get("a") is not None  # a is now the most recent
    store.put("c", np.zeros(30, np.uint8))
    assert "b" not in store and "a" in store and "c" in store and store.nbytes == 90
    packed = PackedTables(0)
    t = rng.random((3, 5, 11)) < 0.5
    assert np.array_equal(packed.put("t", t), t) and np.array_equal(packed.get("t"), t)
    assert packed.packed_bytes == 3 * 5 * 2


@pytest.mark.slow  # every entry and line of two 19-robot tables, one at a time: seconds
@pytest.mark.timeout(60)
def test_swept_entries_and_lines_read_like_the_tables():
    """``swept_entry`` and ``swept_line`` (the schedule's and the plan improvement's readers)
    equal the unpacked tables, on a grid of identical robots (mirrored tables stored once)
    and on robots with their own geometry."""
    rng = np.random.default_rng(3)
    bases = hex_grid(2, 16.0)
    kin = AlphaBeta(8.0, 12.0, 7, 5, (0.0, 180.0))
    kins = [AlphaBeta(float(rng.uniform(6, 10)), float(rng.uniform(8, 15)), 7, 5, (0.0, 180.0)) for _ in bases]
    for tables in (CollisionTables(kin, bases, 1.5), CollisionTables(kins[0], bases, 1.5, kins=kins)):
        mirrored = 0
        for k in range(len(tables.pairs)):
            for mover in (0, 1):
                mirrored += tables._swept_key(k, mover)[1]
                table = tables.swept(k, mover)
                M, P, Q = table.shape
                for m in range(M):
                    for i in rng.integers(0, P, 4).tolist():
                        assert np.array_equal(tables.swept_line(k, mover, m, at_a=i), table[m, i, :])
                    for j in rng.integers(0, Q, 4).tolist():
                        assert np.array_equal(tables.swept_line(k, mover, m, at_b=j), table[m, :, j])
                    for i, j in zip(rng.integers(0, P, 20).tolist(), rng.integers(0, Q, 20).tolist()):
                        assert tables.swept_entry(k, mover, m, i, j) == bool(table[m, i, j])
        assert (mirrored > 0) == (tables._distinct is None)  # the mirror route is taken on the grid


@pytest.mark.timeout(120)
@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("bounds", [True, False], ids=["bounds", "dense"])
def test_batch_swept_with_bounds_matches_the_pairwise_tables_on_random_layouts(seed, bounds, monkeypatch):
    """The batch route computes exact distances only where a lower bound leaves the
    end-point prefilter open (:func:`.batch._far_bounds`, :func:`.batch._prefilter`; tables
    of at least ``BOUND_MIN_ENTRIES`` entries, forced here for these small ones) and every
    distance with the dense prefilter otherwise: on scattered robots of random arms, coarse
    steps (long sweeps) and buffers, every table equals the pair-by-pair one either way, and
    with bounds both kinds of entries (bounded, exact) occur."""
    from supcoord.geometry import batch as batch_module
    from supcoord.geometry.batch import KinematicsArrays, _far_bounds

    if bounds:
        monkeypatch.setattr(batch_module, "BOUND_MIN_ENTRIES", 0)

    rng = np.random.default_rng(seed)
    bases = rng.uniform(0, 40, (12, 2))
    kins = [AlphaBeta(float(rng.uniform(4, 10)), float(rng.uniform(6, 15)), int(rng.integers(3, 7)),
                      int(rng.integers(3, 5)), (0.0, 180.0)) for _ in range(len(bases))]
    buffer = float(rng.uniform(0.5, 3))
    batch = CollisionTables(kins[0], bases, buffer, kins=kins)
    batch.prepare(range(len(batch.pairs)))
    single = CollisionTables(kins[0], bases, buffer, kins=kins)
    bounded = 0
    for k in range(len(batch.pairs)):
        a, b = (int(x) for x in batch.pairs[k])
        for mover in (0, 1):
            assert np.array_equal(batch.swept(k, mover), single.swept(k, mover)), (k, mover)
        assert np.array_equal(batch.static(k), single.static(k)), k
        sa, sb = KinematicsArrays(kins[a]).segments, KinematicsArrays(kins[b]).segments + (bases[b] - bases[a])
        d, exact, d_t, exact_t = _far_bounds(sa, sb, 2 * buffer + 1.0)
        assert np.array_equal(d_t, d.T) and np.array_equal(exact_t, exact.T)
        true = single.distances(k)
        assert np.all(d[~exact] <= true[~exact]) and np.allclose(d[exact], true[exact], rtol=0, atol=1e-9)
        bounded += int((~exact).sum())
    assert (bounded > 0) == bounds and len(batch.pairs) > 5


@pytest.mark.timeout(60)
@pytest.mark.parametrize("kin", [Rotary(10.0, 12), AlphaBeta(4.0, 8.0, 8, 5, (0.0, 180.0)),
                                 AlphaBeta(3.0, 6.0, 9, 4, (-180.0, 150.0), alpha_range=(0.0, 300.0))],
                         ids=["rotary-wrapping", "alpha-beta", "alpha-stops"])
@pytest.mark.parametrize("mover", [0, 1])
def test_reversed_moves_equal_their_own_turns(kin, mover):
    """A reversed move's rows are copied from its forward move (:meth:`Kinematics.reversed_moves`,
    :func:`.batch.fill_reversed`): they equal the reversed turn decided on its own
    (:func:`turn_collides` from the far end, turning the other way), across wraps and next to
    hard stops, where the move is blocked."""
    from supcoord.geometry.motion import turn_collides

    base_b, bsum = np.array([11.0, 5.0]), 2.5
    table = swept_table(kin, (0, 0), base_b, bsum, mover)
    pos = kin.all_positions()
    reversed_moves = kin.reversed_moves()
    assert reversed_moves and all(kin.moves()[r] == (kin.moves()[m][0], -kin.moves()[m][1])
                                  for r, m in reversed_moves.items())
    checked = stops = 0
    for r in reversed_moves:
        joint, delta = kin.moves()[r]
        _, ok = kin.step_array(pos, joint, delta)
        ii, jj = (g.ravel() for g in np.meshgrid(np.nonzero(ok)[0], np.arange(len(pos)), indexing="ij"))
        if mover == 0:
            direct = turn_collides(kin, (0, 0), pos[ii], joint, np.full(len(ii), delta), kin, base_b, pos[jj], bsum)
            got = table[r, ii, jj]
        else:
            direct = turn_collides(kin, base_b, pos[ii], joint, np.full(len(ii), delta), kin, (0, 0), pos[jj], bsum)
            got = table[r, jj, ii]
        assert np.array_equal(got, direct), (r, int(np.count_nonzero(got != direct)))
        stopped = np.nonzero(~ok)[0]
        assert np.all(table[r, stopped] if mover == 0 else table[r][:, stopped])
        checked += len(ii)
        stops += len(stopped)
    assert checked > 100 and (stops > 0) == any(not j.wraps for j in kin.joints)


_FRAGMENTED_HEAP = """
import numpy as np
from supcoord.bdd.budget import current_rss
from supcoord.geometry import table_store
np.ones(2**20).sum()  # a freed 8 MB map raises glibc's map threshold: the tables below use the heap
kept, big = [], []
for _ in range(150):
    big.append(np.ones(2**18))  # 2 MB, written: resident
    kept.append(np.ones(1024))  # 8 KB and kept (a packed table), between the big ones
del big
freed = current_rss()  # the heap keeps the free pages
table_store.release_free_heap()
print(freed, current_rss(), table_store._TRIM[0] is not None)
"""


@pytest.mark.timeout(60)
def test_release_free_heap_returns_freed_table_memory(monkeypatch):
    """Tables of a few MB freed between small arrays that stay (the packed tables) leave the
    C heap holding free pages; :func:`.table_store.release_free_heap` gives them back (glibc,
    as on the machines this runs on; in a fresh interpreter, whose heap is known), and is a
    no-op where the C library has no trim."""
    import os
    import subprocess
    import sys

    from supcoord.geometry import table_store

    if sys.platform != "linux":
        pytest.skip("the heap trim is glibc's")
    env = {k: v for k, v in os.environ.items() if not k.startswith("MALLOC_")}  # glibc's defaults (Dask sets some)
    out = subprocess.run([sys.executable, "-c", _FRAGMENTED_HEAP], capture_output=True, text=True, check=True,
                         timeout=50, env=env)
    freed, after, found = out.stdout.split()
    assert found == "True"
    assert int(freed) - int(after) > 200 * 2**20, (freed, after)  # most of the 300 MB given back
    monkeypatch.setattr(table_store, "_TRIM", [])
    monkeypatch.setattr(table_store.ctypes, "CDLL", lambda *a, **k: (_ for _ in ()).throw(OSError("no libc")))
    table_store.release_free_heap()  # no C library to trim: nothing happens
    assert table_store._TRIM == [None]


@pytest.mark.timeout(120)
@pytest.mark.parametrize("seed", range(3))
@pytest.mark.slow
def test_lazy_entries_lines_and_blocked_guards_equal_the_tables(seed):
    """Lazy tables (:attr:`CollisionTables.lazy`) decide each entry on its own
    (:meth:`CollisionTables.swept_entries`): on robots with their own arms, lattices, hard
    stops or a wrapping alpha, unary tables (obstacles, held robots) on either side, both
    movers and every move, every entry, bit and line equals the whole table's; and the
    symmetrised guards read from them (:func:`.guards.blocked_entries`, ``blocked_entry``,
    ``blocked_column``) equal :func:`.guards.blocked_table`."""
    from supcoord.planning import guards
    from supcoord.planning.caches import caches_for
    from supcoord.testing.oracle.tight_problems import tight_angle_problem

    rng = np.random.default_rng(seed)
    bases = hex_grid(2, 16.0)
    kins = [AlphaBeta(float(rng.uniform(6, 10)), float(rng.uniform(8, 15)), int(rng.integers(5, 9)),
                      int(rng.integers(3, 6)), [(0.0, 180.0), (-30.0, 150.0), (150.0, 180.0)][p % 3],
                      alpha_range=None if p % 4 else (0.0, 300.0)) for p in range(len(bases))]
    unary = {p: (rng.random(kins[p].n_positions) < 0.1, rng.random((len(kins[p].moves()), kins[p].n_positions)) < 0.1)
             for p in range(seed % 2, len(bases), 2)}
    whole = CollisionTables(kins[0], bases, 1.5, kins=kins, unary=unary, lazy=False)
    lazy = CollisionTables(kins[0], bases, 1.5, kins=kins, unary=unary, lazy=True)
    assert lazy.lazy and not whole.lazy and len(whole.pairs) > 10
    for k in range(len(whole.pairs)):
        for mover in (0, 1):
            table = whole.swept(k, mover)
            M, P, Q = table.shape
            m, i, j = (x.ravel() for x in np.meshgrid(range(M), range(P), range(Q), indexing="ij"))
            assert np.array_equal(lazy.swept_entries(k, mover, m, i, j), table[m, i, j]), (k, mover)
            for mv in range(M):
                for x in rng.integers(0, P, 2).tolist():
                    assert np.array_equal(lazy.swept_line(k, mover, mv, at_a=x), table[mv, x, :])
                for y in rng.integers(0, Q, 2).tolist():
                    assert np.array_equal(lazy.swept_line(k, mover, mv, at_b=y), table[mv, :, y])
            for mv, x, y in zip(rng.integers(0, M, 20).tolist(), rng.integers(0, P, 20).tolist(),
                                rng.integers(0, Q, 20).tolist()):
                assert lazy.swept_entry(k, mover, mv, x, y) == bool(table[mv, x, y])
        static, dist = whole.static(k), whole.distances(k)
        P, Q = static.shape
        for x in rng.integers(0, P, 3).tolist():
            assert np.array_equal(lazy.static_line(k, at_a=x), static[x, :])
        for y in rng.integers(0, Q, 3).tolist():
            assert np.array_equal(lazy.static_line(k, at_b=y), static[:, y])
        ia, jb = rng.integers(0, P, 200), rng.integers(0, Q, 200)
        view = lazy.distance_view(k)
        assert np.array_equal(view[ia, jb], dist[ia, jb]) and np.array_equal(view.T[jb, ia], dist.T[jb, ia])
    assert not lazy._bits and lazy._decider is not None  # nothing tabulated: entries only
    # the guards, on a tight problem of robots on their own lattices, tables whole or lazy
    data = tight_angle_problem(seed, n=3, max_product=60_000)
    eager_p, lazy_p = parse_problem(data), parse_problem(data)
    lazy_p = dataclasses.replace(lazy_p, _tables=CollisionTables(lazy_p.kinematics, lazy_p.bases, lazy_p.buffers,
                                                                 kins=lazy_p.robot_kinematics, unary=lazy_p.unary(),
                                                                 lazy=True))
    for k in range(len(eager_p.pairs)):
        for side in (0, 1):
            B = guards.blocked_table(eager_p, k, side)
            M, P, Q = B.shape
            m, i, j = (x.ravel() for x in np.meshgrid(range(M), range(P), range(Q), indexing="ij"))
            assert np.array_equal(guards.blocked_entries(lazy_p, k, side, m.tolist(), i.tolist(), j.tolist()),
                                  B[m, i, j]), (k, side)
            for mv in range(M):
                y = int(rng.integers(0, Q))
                assert np.array_equal(guards.blocked_column(lazy_p, k, side, mv, y), B[mv, :, y])
                x = int(rng.integers(0, P))
                assert guards.blocked_entry(lazy_p, k, side, mv, x, y) == bool(B[mv, x, y])
    assert not len(caches_for(lazy_p).blocked)  # no blocked table was built for the lazy problem
