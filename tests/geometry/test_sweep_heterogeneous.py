"""Swept tables of two *different* robots against the testing oracle's own geometry.

Each example draws a pair of alpha-beta robots that differ in everything a pair may
differ in (arm lengths, buffers, each robot's own angle tables, uneven ones included)
on a lattice that wraps or has hard stops, and compares every entry of the project's
swept tables (both movers) with the oracle (:mod:`supcoord.testing.oracle`, which shares
no code with :mod:`supcoord.geometry`): the exact least distance of each single-joint turn,
and dense sampling of it.  The wrap step of an own alpha table (360° → 0°) is the one the
sweep-length bound most easily forgets, so the strategy makes it the largest step often.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from supcoord.geometry import AlphaBeta
from supcoord.geometry.pair_tables import swept_table
from supcoord.problems import parse_problem
from supcoord.testing.oracle.distance import segment_gap
from supcoord.testing.oracle.oracle_model import Arm
from supcoord.testing.oracle.tables import PairTables

#: a least distance this close to the buffers' sum is a tie (rounding decides it either way)
TIE = 1e-7
#: dense samples of a turn (beside the oracle's exact least distance)
SAMPLES = 257


def _table(draw, lo: float, hi: float, n: int, wraps: bool, wrap_gap: bool) -> np.ndarray:
    """``n`` strictly increasing angles in ``[lo, hi)`` (wrapping) or ``[lo, hi]`` (hard stops);
    ``wrap_gap``: kept inside ``[lo + g, hi − g']`` so the step across the wrap is the largest."""
    if wrap_gap:
        lo, hi = lo + draw(st.floats(20.0, 60.0)), hi - draw(st.floats(20.0, 60.0))
    cuts = draw(st.lists(st.floats(0.2, 1.0), min_size=n - 1, max_size=n - 1))
    span = (hi - lo) * (1.0 if not wraps or wrap_gap else (n - 1) / n)
    pos = np.concatenate([[0.0], np.cumsum(cuts)])
    out = lo + span * pos / pos[-1]
    if wraps and not wrap_gap:
        out = out + draw(st.floats(0.0, 360.0 / n - 1e-3))
    return np.round(out, 6)


@st.composite
def robot_pairs(draw):
    """Two robots with the same numbers of positions and wrapping, different everything else."""
    na, nb = draw(st.integers(4, 7)), draw(st.integers(2, 4))
    wraps = draw(st.booleans())
    beta_range = draw(st.sampled_from([(0.0, 180.0), (-30.0, 150.0), (20.0, 200.0)]))
    alpha_range = None if wraps else draw(st.sampled_from([(0.0, 360.0), (-90.0, 200.0), (10.0, 350.0)]))
    robots = []
    for _ in range(2):
        alpha, beta = draw(st.floats(3.0, 9.0)), draw(st.floats(8.0, 18.0))
        own = {}
        if draw(st.booleans()):
            lo, hi = (0.0, 360.0) if wraps else alpha_range
            own["alpha_deg"] = _table(draw, lo, hi, na, wraps, wraps and draw(st.booleans()))
        if draw(st.booleans()):
            own["beta_deg"] = _table(draw, *beta_range, nb, False, False)
        robots.append(dict(alpha=alpha, beta=beta, own=own, buffer=draw(st.floats(0.2, 3.0))))
    reach = sum(r["alpha"] + r["beta"] for r in robots)
    dist = draw(st.floats(0.45, 0.95)) * reach
    angle = draw(st.floats(0.0, 2 * np.pi))
    return dict(na=na, nb=nb, wraps=wraps, beta_range=beta_range, alpha_range=alpha_range, robots=robots,
                base=(dist * np.cos(angle), dist * np.sin(angle)))


def _project(case) -> tuple[list[AlphaBeta], np.ndarray]:
    kins = [AlphaBeta(r["alpha"], r["beta"], case["na"], case["nb"], case["beta_range"],
                      alpha_range=case["alpha_range"], **r["own"]) for r in case["robots"]]
    return kins, np.array([[0.0, 0.0], list(case["base"])])


def _oracle_arm(case, r) -> Arm:
    spec = {"kind": "alpha-beta", "alpha": r["alpha"], "beta": r["beta"], "alpha_steps": case["na"],
            "beta_steps": case["nb"], "beta_range": list(case["beta_range"])}
    if case["alpha_range"] is not None:
        spec["alpha_range"] = list(case["alpha_range"])
    arm = Arm.from_json(spec)
    tables = [r["own"].get("alpha_deg"), r["own"].get("beta_deg")]
    return arm if all(t is None for t in tables) else arm.with_tables(tables)


def _oracle_least(case, mover: int, moves, pos):
    """Per (move, i_a, j_b): the oracle's exact least distance of the turn, the least of
    dense samples of it, and whether the move stays inside the hard stops."""
    arms = [_oracle_arm(case, r) for r in case["robots"]]
    need = case["robots"][0]["buffer"] + case["robots"][1]["buffer"]
    pt = PairTables(arms[0], complex(*case["base"]), need, arms[1])
    n = len(pos)
    m_idx, i_idx, j_idx = (a.ravel() for a in np.meshgrid(np.arange(len(moves)), np.arange(n), np.arange(n),
                                                          indexing="ij"))
    d = np.zeros((len(m_idx), 2), dtype=np.int64)
    for m, (joint, delta) in enumerate(moves):
        d[m_idx == m, joint] = delta
    q_mov = pos[i_idx] if mover == 0 else pos[j_idx]
    end = q_mov + d
    steps, wraps = np.array([case["na"], case["nb"]]), np.array([case["wraps"], False])
    inside = np.all(wraps | ((end >= 0) & (end < steps)), axis=1)
    qa, qb = pos[i_idx].astype(float), pos[j_idx].astype(float)
    da, db = (d, np.zeros_like(d)) if mover == 0 else (np.zeros_like(d), d)
    sel = np.nonzero(inside)[0]
    exact = np.full(len(m_idx), np.inf)
    dense = np.full(len(m_idx), np.inf)
    exact[sel] = pt.least_on_turn(qa[sel], da[sel], qb[sel], db[sel])
    t = np.linspace(0.0, 1.0, SAMPLES)[None, :, None]
    a0, a1 = arms[0].segment(qa[sel, None, :] + t * da[sel, None, :])
    b0, b1 = arms[1].segment(qb[sel, None, :] + t * db[sel, None, :])
    o = complex(*case["base"])
    dense[sel] = segment_gap(a0, a1, o + b0, o + b1).min(axis=1)
    shape = (len(moves), n, n)
    return exact.reshape(shape), dense.reshape(shape), inside.reshape(shape), need


def _check_pair(case) -> None:
    kins, bases = _project(case)
    pos = kins[0].all_positions()
    assert np.array_equal(pos, Arm.from_json({"kind": "alpha-beta", "alpha": 1, "beta": 1, "alpha_steps": case["na"],
                                              "beta_steps": case["nb"]}).positions())
    moves = kins[0].moves()
    bsum = case["robots"][0]["buffer"] + case["robots"][1]["buffer"]
    # the same pair as a problem: the tables the planner reads (its batch route)
    layout = {"kind": "points", "xy": bases.tolist()}
    data = {"layout": layout, "kinematics": {"kind": "alpha-beta", "alpha": 5.0, "beta": 10.0,
                                            "alpha_steps": case["na"], "beta_steps": case["nb"],
                                            "beta_range": list(case["beta_range"])},
            "collision": {"buffer": [r["buffer"] for r in case["robots"]]},
            "start": [[0, 0], [0, 0]], "target": [[0, 0], [0, 0]]}
    if case["alpha_range"] is not None:
        data["kinematics"]["alpha_range"] = list(case["alpha_range"])
    problem = parse_problem(data, check_collisions=False)
    problem = dataclasses.replace(problem, robot_kinematics=kins, _tables=None, _pairs=None)
    for mover in (0, 1):
        exact, dense, inside, need = _oracle_least(case, mover, moves, pos)
        assert need == pytest.approx(bsum)
        direct = swept_table(kins[0], bases[0], bases[1], bsum, mover, kin_b=kins[1])
        k = [i for i, (a, b) in enumerate(problem.pairs) if (int(a), int(b)) == (0, 1)]
        via_problem = np.asarray(problem.tables().swept(k[0], mover)) if k else None
        for name, table in (("swept_table", direct), ("Problem.tables().swept", via_problem)):
            if table is None:  # the problem found the pair too far apart to meet: so must the oracle
                assert (exact[inside] >= bsum - TIE).all()
                continue
            table = np.asarray(table, dtype=bool)
            assert table[~inside].all(), f"{name}: a move past a hard stop is not blocked"
            free = ~table & inside
            # free in the table: neither the exact turn nor dense sampling comes closer than the sum
            bad = free & ((exact < bsum - TIE) | (dense < bsum - TIE))
            assert not bad.any(), (f"{name} (mover {mover}) calls {int(bad.sum())} moves free that collide, e.g. "
                                   f"move {moves[np.argwhere(bad)[0][0]]} at {np.argwhere(bad)[0][1:].tolist()}: "
                                   f"least {float(exact[tuple(np.argwhere(bad)[0])]):.6f} < {bsum:.6f}")
            # blocked in the table: the oracle finds the turn closer than the sum (exact tables)
            wrong = table & inside & (exact > bsum + TIE)
            assert not wrong.any(), f"{name} (mover {mover}) blocks {int(wrong.sum())} free moves"


# the case: a six-angle own alpha table whose largest step is the one across 360° → 0°
SIX = dict(na=6, nb=3, wraps=True, beta_range=(0.0, 180.0), alpha_range=None,
           robots=[dict(alpha=7.4, beta=15.0, own={"alpha_deg": np.array([40.0, 90.0, 140.0, 190.0, 240.0, 290.0])},
                        buffer=1.0),
                   dict(alpha=6.0, beta=12.0, own={}, buffer=2.0)],
           base=(24.0, 3.0))


@pytest.mark.slow
@pytest.mark.timeout(300)
@settings(max_examples=60, deadline=None)
@given(case=robot_pairs())
@example(case=SIX)
def test_swept_tables_of_different_robots_agree_with_the_oracle(case):
    _check_pair(case)


def test_the_six_angle_wrap_lattice_has_turns_the_wrap_bound_must_cover():
    """The issue's lattice: only the step across the wrap (110°) exceeds the others (50°), and
    some turn across it collides only part-way (both ends free), so a sweep length without
    that step would call it free."""
    kins, bases = _project(SIX)
    moves = kins[0].moves()
    exact, dense, inside, bsum = _oracle_least(SIX, 0, moves, kins[0].all_positions())
    pos = kins[0].all_positions()
    static = PairTables(_oracle_arm(SIX, SIX["robots"][0]), complex(*SIX["base"]), bsum,
                        _oracle_arm(SIX, SIX["robots"][1])).static_gap()
    wrap = np.zeros_like(inside)
    for m, (joint, delta) in enumerate(moves):
        if joint == 0:
            start = pos[:, 0]
            wrap[m] = ((start == 5) & (delta == 1) | (start == 0) & (delta == -1))[:, None]
    mid = np.zeros_like(inside)
    for m, mv in enumerate(moves):
        nxt, ok = kins[0].step_array(pos, *mv)
        end = np.full_like(static, -1.0)
        end[ok] = static[kins[0].flat_index(nxt[ok])]
        mid[m] = (static >= bsum) & (end >= bsum) & (exact[m] < bsum - 1e-3)
    assert (wrap & mid).any()
    _check_pair(SIX)
