"""``blocked_table`` folds in the way back of every move in one gather: the same table as
the move-by-move loop over ``step_array`` it replaced, on wrapping joints, hard stops and
both movers."""

import numpy as np
import pytest

from supcoord.geometry import AlphaBeta, Rotary
from supcoord.planning.guards import blocked_table
from supcoord.problems.random import random_problem


def _loop(problem, pair, mover):
    kin = problem.kinematics
    w = problem.tables().swept(pair, mover)
    if mover == 1:
        w = np.swapaxes(w, 1, 2)
    pos, moves = kin.all_positions(), kin.moves()
    out = w.copy()
    for m, (joint, delta) in enumerate(moves):
        rev = moves.index((joint, -delta))
        nxt, ok = kin.step_array(pos, joint, delta)
        idx = np.nonzero(ok)[0]
        out[m, idx] |= w[rev, kin.flat_index(nxt[idx])]
    return out


@pytest.mark.parametrize("kin", [Rotary(10.0, 9), AlphaBeta(7.4, 15.0, 8, 5, (0.0, 180.0)),
                                 AlphaBeta(10.0, 5.0, 7, 4, (150.0, 180.0), alpha_range=(0.0, 300.0))])
def test_gathered_way_back_is_the_loop(kin, monkeypatch):
    problem = random_problem({"kind": "hex", "rings": 1, "pitch": 1.4 * kin.reach}, kin, buffer=1.5, seed=3)
    tables = problem.tables()
    assert problem.tables() is tables
    # random swept tables (the real ones already satisfy the way back): the fold then matters
    rng = np.random.default_rng(len(kin.moves()))
    shape = (len(kin.moves()), kin.n_positions, kin.n_positions)
    keys = {problem.pair_geometry_key(k) + (mv,) for k in range(len(problem.pairs)) for mv in (0, 1)}
    fake = {key: rng.random(shape) < 0.1 for key in sorted(keys)}  # one table per geometry, as stored
    monkeypatch.setattr(tables, "swept", lambda pair, mover: fake[problem.pair_geometry_key(pair) + (mover,)])
    for pair in range(len(problem.pairs)):
        for mover in (0, 1):
            new, old = blocked_table(problem, pair, mover), _loop(problem, pair, mover)
            assert np.array_equal(new, old)
            w = tables.swept(pair, mover)
            w = w if mover == 0 else np.swapaxes(w, 1, 2)
            assert (old != w).any()
