"""Planning's caches live in planning (:mod:`supcoord.planning.caches`), not on the problem,
and the readers of the pair tables share one vocabulary (:mod:`supcoord.geometry.table_index`)."""

from __future__ import annotations

import dataclasses
import gc

import numpy as np
import pytest

from supcoord.geometry import chain_motion
from supcoord.geometry.chain_motion import chain_geometry
from supcoord.geometry.collision import CollisionTables
from supcoord.geometry.table_index import Mover
from supcoord.planning import caches
from supcoord.planning.caches import caches_for
from supcoord.planning.descent import descent
from supcoord.planning.guards import blocked_entries, blocked_entry, blocked_lookup, blocked_table, conflict_graph
from supcoord.planning.optimum import optimal_makespan
from supcoord.planning.schedule import asap_schedule, timeline_schedule
from supcoord.problems.plan import exchanged
from supcoord.problems.presets import preset_problem


def _problem(seed: int = 0):
    return preset_problem("sdss-v", rings=1, seed=seed, alpha_steps=8, beta_steps=5)


def _lazy(problem):
    """``problem`` with lazy collision tables (entries decided as read)."""
    return dataclasses.replace(problem, _tables=CollisionTables(problem.kinematics, problem.bases, problem.buffers,
                                                                kins=problem.robot_kinematics, unary=problem.unary(),
                                                                lazy=True))


@pytest.mark.timeout(30)
@pytest.mark.parametrize("lazy", [False, True], ids=["whole", "lazy"])
def test_planning_writes_nothing_onto_the_problem_or_its_kinematics(lazy):
    problem = _problem()
    if lazy:
        problem = _lazy(problem)
    before = set(vars(problem))
    steps, _ = descent(problem, problem.start, max_steps=3)
    moves = [mv for step in steps for mv in step]
    asap_schedule(problem, moves)
    timeline_schedule(problem, moves)
    optimal_makespan(problem, members=[0, 1])
    for k in range(len(problem.pairs)):
        blocked_entry(problem, k, Mover.A, 0, 0, 0)
    cache = caches_for(problem)
    assert cache.conflict_graph is not None and cache.pair_graph is not None and cache.free_simultaneous
    assert (cache.entries is not None) == lazy and (len(cache.blocked) > 0) != lazy
    # the only attribute a problem gains is its own (problems: the pair geometry keys)
    assert set(vars(problem)) - before <= {"_pair_geometry_keys"}
    assert "_chain_geometry" not in vars(problem.kinematics)  # the descent's chain geometry is held apart


@pytest.mark.timeout(30)
def test_one_cache_per_tables_shared_by_copies_and_dropped_with_them():
    problem = _problem()
    cache = caches_for(problem)
    assert caches_for(problem) is cache
    assert caches_for(exchanged(problem)) is cache  # same tables, another start and target
    assert conflict_graph(exchanged(problem)) is conflict_graph(problem)
    other = _lazy(_problem(seed=1))
    assert caches_for(other) is not cache
    conflict_graph(other)
    blocked_entries(other, 0, Mover.B, 0, 0, 0)  # every kind of cache filled
    assert blocked_lookup(other)(0, Mover.B, 0, 0, 0) is not None
    key = id(other.tables())
    assert key in caches._CACHES
    del other
    gc.collect()
    assert key not in caches._CACHES  # gone with its tables


@pytest.mark.timeout(30)
def test_chain_geometry_is_held_per_kinematics_object_and_dropped_with_it():
    problem = _problem()
    kin = problem.kinematics
    geo = chain_geometry(kin)
    assert chain_geometry(kin) is geo and geo.kin is kin
    assert "_chain_geometry" not in vars(kin)
    other = _problem(seed=3).kinematics
    chain_geometry(other)
    key = id(other)
    assert key in chain_motion._CHAINS
    del other
    gc.collect()
    assert key not in chain_motion._CHAINS  # gone with its kinematics


def test_geometry_key_is_the_tables_public_key():
    problem = _problem()
    tables = problem.tables()
    for k, (a, b) in enumerate(problem.pairs.tolist()):
        key = tables.geometry_key(a, b)
        assert problem.geometry_key(a, b) == key == problem.pair_geometry_key(k)
        (ox, oy), bsum, ua, ub = tables._key(k)
        assert key == (ox, oy, bsum, ua, ub)


@pytest.mark.timeout(30)
@pytest.mark.parametrize("lazy", [False, True], ids=["whole", "lazy"])
def test_many_pairs_at_once_read_like_the_whole_tables(lazy):
    """``swept_entries`` and ``blocked_entries`` over entries of several pairs and both movers
    at once equal the whole tables; ``blocked_lookup`` then knows what was decided."""
    problem = _problem(seed=2)
    whole = {(k, mv): (problem.tables().swept(k, mv), blocked_table(problem, k, mv))
             for k in range(len(problem.pairs)) for mv in Mover}
    if lazy:
        problem = _lazy(problem)
    tables = problem.tables()
    rng = np.random.default_rng(0)
    n_moves, n_pos = len(problem.kinematics.moves()), problem.kinematics.n_positions
    pair = rng.integers(0, len(problem.pairs), 300)
    mover = rng.integers(0, 2, 300)
    move, at_a, at_b = rng.integers(0, n_moves, 300), rng.integers(0, n_pos, 300), rng.integers(0, n_pos, 300)
    swept = [bool(whole[k, mv][0][m, x, y]) for k, mv, m, x, y in zip(pair, mover, move, at_a, at_b)]
    assert tables.swept_entries(pair, mover, move, at_a, at_b).tolist() == swept
    blocked = [bool(whole[k, mv][1][m, x, y]) for k, mv, m, x, y in zip(pair, mover, move, at_a, at_b)]
    assert blocked_entries(problem, pair, mover, move, at_a, at_b).tolist() == blocked
    assert any(blocked) and not all(blocked)
    lookup = blocked_lookup(problem)
    known = [lookup(*(int(v) for v in e)) for e in zip(pair, mover, move, at_a, at_b)]
    assert known == blocked


def test_mover_names_the_member_moving():
    assert [int(m) for m in Mover] == [0, 1]
    assert Mover.A.other is Mover.B and Mover.B.other is Mover.A
