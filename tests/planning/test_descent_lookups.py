"""The descent's memoised, byte-level reading of the blocked tables decides condition (1)
exactly as the definition does.

:func:`supcoord.planning.descent._serialisable` reads the bit-packed tables through a flat
view of bytes and memoised flat poses (:class:`~supcoord.planning.descent._Lookups`); here it
is compared with condition (1) written out on the unpacked tables
(:func:`~supcoord.planning.guards.blocked_table`): every move of ``M_p`` from every pose
part-way through ``M_p`` against every pose part-way through ``M_q``, on random poses and
move sets of every neighbour pair (single- and two-joint sets, a wrapping alpha joint),
with eager and with lazy tables.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from supcoord.geometry import collision
from supcoord.planning.descent import _Lookups, _serialisable, motion_free, _motion_hit
from supcoord.planning.guards import blocked_table, conflict_graph
from supcoord.problems.presets import preset_problem


def _reference(problem, k, side, cp, mp, cq, mq) -> bool:
    """Condition (1) of :mod:`supcoord.planning.descent` on the unpacked table."""
    kin = problem.kinematics
    table = blocked_table(problem, k, side)
    moves = kin.moves()

    def flat(q, ms):
        v = np.array(q, dtype=np.int64)
        for j, d in ms:
            v[j] += d
        return kin.flat_position(kin.wrap(v))

    subsets = lambda ms: [s for r in range(len(ms) + 1) for s in itertools.combinations(ms, r)]  # noqa: E731
    for mv in mp:
        for a in subsets([x for x in mp if x != mv]):
            for b in subsets(mq):
                if table[moves.index(mv), flat(cp, a), flat(cq, b)]:
                    return False
    return True


def _move_set(rng, kin, q):
    """A random set of at most one move per joint, inside the hard stops, from ``q``."""
    while True:
        out = []
        for j, jt in enumerate(kin.joints):
            d = int(rng.integers(-1, 2))
            if d and (jt.wraps or 0 <= q[j] + d < jt.steps):
                out.append((j, d))
        if out:
            return out


def _check(problem, rng, trials):
    T = _Lookups(problem)
    kin = problem.kinematics
    blocked = 0
    for _ in range(trials):
        p = int(rng.integers(problem.n))
        if not conflict_graph(problem)[p]:
            continue
        k, q, side = conflict_graph(problem)[p][int(rng.integers(len(conflict_graph(problem)[p])))]
        cp = tuple(int(rng.integers(j.steps)) for j in kin.joints)
        cq = tuple(int(rng.integers(j.steps)) for j in kin.joints)
        mp = _move_set(rng, kin, cp)
        mq = _move_set(rng, kin, cq) if rng.random() < 0.6 else []
        want = _reference(problem, k, side, cp, mp, cq, mq)
        assert _serialisable(T, k, side, cp, mp, cq, mq) == want, (k, side, cp, mp, cq, mq)
        blocked += not want
    return blocked


@pytest.mark.timeout(60)
def test_serialisable_reads_the_tables_as_defined():
    problem = preset_problem("sdss-v", rings=1, alpha_steps=8, beta_steps=5, seed=3)
    assert not problem.tables().lazy
    blocked = _check(problem, np.random.default_rng(0), 1500)
    assert 100 < blocked < 1400  # both verdicts were reached


@pytest.mark.timeout(60)
def test_serialisable_on_lazy_tables(monkeypatch):
    monkeypatch.setattr(collision, "LAZY_TABLE_BYTES", 0)
    problem = preset_problem("sdss-v", rings=1, alpha_steps=8, beta_steps=5, seed=4)
    assert problem.tables().lazy
    blocked = _check(problem, np.random.default_rng(1), 600)
    assert 30 < blocked < 570


@pytest.mark.timeout(60)
def test_motion_hit_on_tuples_is_motion_free_on_arrays():
    problem = preset_problem("sdss-v", rings=1, alpha_steps=8, beta_steps=5, seed=5)
    rng = np.random.default_rng(2)
    kin = problem.kinematics
    hits = []
    for _ in range(300):
        k = int(rng.integers(len(problem.pairs)))
        side = int(rng.integers(2))
        x = np.array([rng.integers(j.steps) for j in kin.joints])
        y = np.array([rng.integers(j.steps) for j in kin.joints])
        dx = np.zeros(kin.n_joints, dtype=np.int64)
        for j, d in _move_set(rng, kin, x):
            dx[j] = d
        dy = np.zeros(kin.n_joints, dtype=np.int64)
        for j, d in (_move_set(rng, kin, y) if rng.random() < 0.5 else []):
            dy[j] = d
        free = motion_free(problem, k, side, x, dx, y, dy)
        cold = _motion_hit(problem, {}, k, side, tuple(x.tolist()), tuple(dx.tolist()), tuple(y.tolist()),
                           tuple(dy.tolist()), 1e-6)
        assert cold == (not free), (k, side, x, dx, y, dy)
        hits.append(cold)
    assert 0 < sum(hits) < len(hits)
