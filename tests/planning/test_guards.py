"""The undirectedness lemma the planner's certificates rest on.

``B[m, i, j] == B[rev(m), step_m(i), j]`` for every move ``m`` of the mover from ``i``
inside the hard stops and every position ``j`` of the other: a move is blocked exactly
when its way back is, so the configuration graph is undirected and "reachable from the
current configuration" equals "reachable from the start" (``planning/windows.py``,
points 1–3).
"""

import numpy as np
import pytest

from supcoord.geometry import AlphaBeta, Rotary
from supcoord.geometry.collision import distance_table, placed_segments
from supcoord.geometry.sweep import rotation_clearance
from supcoord.planning.guards import blocked_table
from supcoord.problems.random import random_problem

KINEMATICS = [Rotary(10.0, 9), AlphaBeta(7.4, 15.0, 8, 5, (0.0, 180.0)), AlphaBeta(10.0, 5.0, 7, 4, (150.0, 180.0))]


def _problem(kin, seed):
    pitch = 1.5 * kin.reach
    return random_problem({"kind": "hex", "rings": 1, "pitch": pitch}, kin, buffer=1.5, seed=seed)


def _lemma_violations(kin, table):
    """Entries ``(m, i, j)`` where ``table[m, i, j] != table[rev(m), step_m(i), j]``."""
    pos, moves = kin.all_positions(), kin.moves()
    bad = []
    for m, (joint, delta) in enumerate(moves):
        rev = moves.index((joint, -delta))
        nxt, ok = kin.step_array(pos, joint, delta)
        idx = np.nonzero(ok)[0]
        diff = table[m, idx] != table[rev, kin.flat_index(nxt[idx])]
        bad += [(m, int(idx[i]), int(j)) for i, j in zip(*np.nonzero(diff))]
    return bad


@pytest.mark.timeout(120)
@pytest.mark.parametrize("kin", KINEMATICS, ids=["rotary", "alpha-beta", "folded"])
def test_blocked_tables_are_symmetric(kin):
    problem = _problem(kin, 3)
    assert len(problem.pairs)
    for k in range(len(problem.pairs)):
        for side in (0, 1):
            table = blocked_table(problem, k, side)
            assert table.any() and not table.all()
            assert _lemma_violations(kin, table) == []


@pytest.mark.timeout(120)
@pytest.mark.parametrize("kin", KINEMATICS[:2], ids=["rotary", "alpha-beta"])
def test_blocked_tables_are_symmetric_whatever_the_swept_table(kin):
    """The symmetrisation, not the luck of the geometry, makes the lemma hold: flip random
    entries of the swept tables and the blocked tables are still symmetric."""
    problem = _problem(kin, 5)
    tables = problem.tables()
    rng = np.random.default_rng(0)
    original = tables.swept

    def noisy(k, mover):
        w = original(k, mover).copy()
        flips = rng.integers(0, w.size, size=max(1, w.size // 50))
        w.flat[flips] = ~w.flat[flips]
        return w

    tables.swept = noisy
    asymmetric = 0
    for k in range(len(problem.pairs)):
        for side in (0, 1):
            w = noisy(k, side)
            asymmetric += len(_lemma_violations(kin, w if side == 0 else np.swapaxes(w, 1, 2)))
            assert _lemma_violations(kin, blocked_table(problem, k, side)) == []
    assert asymmetric > 0  # the injected tables really were asymmetric


@pytest.mark.timeout(120)
@pytest.mark.parametrize("kin", KINEMATICS, ids=["rotary", "alpha-beta", "folded"])
def test_exact_swept_tables_are_symmetric_up_to_rounding(kin):
    """The exact swept table alone satisfies the lemma, except where the clearance is a tie
    with the buffers to floating-point rounding (there the symmetrisation decides)."""
    problem = _problem(kin, 7)
    tables = problem.tables()
    colliding = 0
    for k in range(len(problem.pairs)):
        a, b = problem.pairs[k]
        bsum = problem.buffers[a] + problem.buffers[b]
        w = tables.swept(k, 0)
        for m, i, j in _lemma_violations(kin, w):
            joint, delta = kin.moves()[m]
            q = kin.all_positions()[i]
            centre, angle = kin.rotation(q, joint, delta)
            seg = placed_segments(kin, problem.bases[a], q)
            other = placed_segments(kin, problem.bases[b], kin.all_positions()[j])
            clearance = float(rotation_clearance(seg, centre + problem.bases[a], angle, other))
            assert abs(clearance - bsum) < 1e-9, (m, i, j, clearance, bsum)
        static = distance_table(kin, problem.bases[a], problem.bases[b]) < bsum
        colliding += int(static.sum())
        assert np.all(w >= static[None])  # every move's swept table contains the start pose's collisions
    assert colliding


@pytest.mark.timeout(120)
@pytest.mark.parametrize("kin", KINEMATICS, ids=["rotary", "alpha-beta", "alpha-beta-tight"])
def test_blocked_bits_read_like_the_table(kin, monkeypatch):
    """The planner's hot readers take the blocked tables' bits (:func:`blocked_entry`,
    :func:`blocked_column`); with the unpacked cache at one byte (every table but the newest
    dropped and unpacked again when asked), they and the unpacked table agree entry for entry."""
    from supcoord.planning import caches
    from supcoord.planning.guards import blocked_bits, blocked_column, blocked_entry

    monkeypatch.setattr(caches, "BLOCKED_CACHE_BYTES", 1)
    problem = _problem(kin, 4)
    rng = np.random.default_rng(4)
    expected = {}
    for k in range(len(problem.pairs)):
        for side in (0, 1):
            table = blocked_table(problem, k, side)
            assert not table.flags.writeable and blocked_bits(problem, k, side).dtype == np.uint8
            expected[k, side] = table.copy()
    for (k, side), table in expected.items():
        again = blocked_table(problem, k, side)  # unpacked anew from the bits
        assert np.array_equal(again, table)
        M, P, Q = table.shape
        for m in range(M):
            for j in rng.choice(Q, size=min(Q, 5), replace=False).tolist():
                assert np.array_equal(blocked_column(problem, k, side, m, j), table[m, :, j])
            for i, j in zip(rng.integers(0, P, 40).tolist(), rng.integers(0, Q, 40).tolist()):
                assert blocked_entry(problem, k, side, m, i, j) == bool(table[m, i, j])
    assert any(t.any() for t in expected.values()) and not all(t.all() for t in expected.values())
