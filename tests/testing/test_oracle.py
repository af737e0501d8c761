"""The independent oracle (``supcoord.testing.oracle``) tested on its own.

Its parts against the project's geometry (allowed here, never inside the oracle) and
against dense brute force: hex bases, kinematics, the true reach, segment distance,
the certified swept check and the exact minimum of a turn; constructed tight cases (a
route with 0.0005 mm of clearance is free, a move 10⁻⁷ mm too close collides, a touch
at exactly the buffer sum is free); its numpy breadth-first search against a plain
one over the same tables; its plans against the project's validator; refusals; and
undecided entries that change an answer raise instead of being given a side.
"""

from __future__ import annotations

import ast
import math
from collections import deque
from pathlib import Path

import numpy as np
import pytest
from hypothesis import event, example, given, settings
from hypothesis import strategies as st
from strategies import tight_route

from supcoord.geometry.kinematics import kinematics_from_spec
from supcoord.geometry.layout import layout_from_spec
from supcoord.geometry.segments import segment_distance
from supcoord.problems import Plan, parse_problem, validate_plan
from supcoord.problems.plan import apply_moves
from supcoord.testing.oracle import (
    FREE,
    HIT,
    UNDECIDED,
    OracleInputError,
    OracleUndecided,
    oracle_bases,
    oracle_bounds,
    oracle_motion,
    oracle_moves,
    oracle_optimal_makespan,
    oracle_reach,
    oracle_reachable,
    oracle_solve,
)
from supcoord.testing.oracle.bfs import Space
from supcoord.testing.oracle.certified_sweep import MAX_OPEN
from supcoord.testing.oracle.tight_problems import tight_problem
from supcoord.testing.oracle.distance import segment_gap
from supcoord.testing.oracle.oracle_model import Arm, OracleProblem, hex_bases
from supcoord.testing.oracle.certified_sweep import certify
from supcoord.testing.oracle.tables import PairTables, joint_options

ORACLE = Path(__file__).resolve().parents[2] / "src" / "supcoord" / "testing" / "oracle"


def test_the_oracle_imports_nothing_of_the_project_but_errors():
    for path in sorted(ORACLE.glob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and node.level >= 2:
                assert node.level == 3 and node.module == "errors", (path.name, node.module)
            if isinstance(node, ast.ImportFrom) and node.level == 0:
                assert not (node.module or "").startswith("supcoord"), (path.name, node.module)
            if isinstance(node, ast.Import):
                assert not any(a.name.startswith("supcoord") for a in node.names), path.name


# -- geometry against the project's --------------------------------------------------------------

@pytest.mark.parametrize("rings", range(9))
def test_hex_bases_equal_the_project_layout(rings):
    pitch = 22.4 + rings / 7
    mine = hex_bases(rings, pitch)
    theirs = layout_from_spec({"kind": "hex", "rings": rings, "pitch": pitch})
    assert len(mine) == 1 + 3 * rings * (rings + 1)
    assert np.allclose(np.stack([mine.real, mine.imag], -1), theirs, rtol=0, atol=1e-9 * pitch)


def test_problem_bases_equal_the_oracle_bases():
    data = {"layout": {"kind": "hex", "rings": 2, "pitch": 21.7}, "kinematics": {"kind": "rotary", "arm": 5.0,
            "steps": 12}, "collision": {"buffer": 1.0}, "start": [0] * 19, "target": [3] * 19}
    p = parse_problem(data)
    assert np.allclose(oracle_bases(p.to_json()), p.bases, rtol=0, atol=1e-9)
    pts = tight_problem(3)
    assert np.array_equal(oracle_bases(pts), parse_problem(pts).bases)


kinematics_specs = st.one_of(
    st.builds(lambda arm, steps: {"kind": "rotary", "arm": arm, "steps": steps},
              st.floats(1.0, 30.0), st.integers(3, 40)),
    st.builds(lambda a, b, na, nb, lo, span: {"kind": "alpha-beta", "alpha": a, "beta": b, "alpha_steps": na,
                                              "beta_steps": nb, "beta_range": [lo, min(360.0, lo + span)]},
              st.floats(1.0, 20.0), st.floats(1.0, 20.0), st.integers(3, 24), st.integers(2, 12),
              st.floats(-360.0, 300.0), st.floats(1.0, 360.0)),
)


@settings(max_examples=60, deadline=None)
@given(kinematics_specs, st.integers(0, 2**32 - 1))
def test_segments_equal_the_project_kinematics(spec, seed):
    kin = kinematics_from_spec(spec)
    arm = Arm.from_json(spec)
    q = np.random.default_rng(seed).uniform(-1.0, np.array(kin.shape, float), size=(50, kin.n_joints))
    p0, p1 = arm.segment(q)
    theirs = kin.segments(q)
    assert np.allclose(p0, theirs[:, 0, 0] + 1j * theirs[:, 0, 1], atol=1e-9)
    assert np.allclose(p1, theirs[:, 1, 0] + 1j * theirs[:, 1, 1], atol=1e-9)
    assert arm.n_positions == kin.n_positions
    assert np.array_equal(arm.positions(), kin.all_positions())  # ids are the project's flat indices


def _dense_reach(spec: dict, n: int = 4001) -> float:
    if spec["kind"] == "rotary":
        return spec["arm"]
    a, b = spec["alpha"], spec["beta"]
    lo, hi = (math.radians(v) for v in spec["beta_range"])
    beta = np.linspace(lo, hi, n)[:, None]
    s = np.linspace(0.0, 1.0, 101)[None, :]
    return float(np.abs(a + s * b * np.exp(1j * beta)).max())


@settings(max_examples=80, deadline=None)
@given(kinematics_specs)
def test_reach_is_the_dense_maximum(spec):
    reach = oracle_reach(spec)
    dense = _dense_reach(spec)
    assert dense <= reach + 1e-9  # nothing sampled is farther
    if spec["kind"] == "alpha-beta":  # and it is attained: the sample spacing bounds the gap
        span = math.radians(spec["beta_range"][1] - spec["beta_range"][0])
        assert reach - dense <= spec["beta"] * span / 4000 + spec["beta"] / 100 + 1e-9


def test_reach_counts_the_elbow():
    spec = {"kind": "alpha-beta", "alpha": 10, "beta": 5, "alpha_steps": 4, "beta_steps": 3, "beta_range": [150, 180]}
    assert oracle_reach(spec) == 10.0  # the folded fibre is nearer the base than the elbow
    assert abs(_dense_reach(spec) - 10.0) < 1e-12


@settings(max_examples=40, deadline=None)
@given(kinematics_specs)
def test_the_project_reach_is_the_true_reach(spec):
    """``Kinematics.reach`` bounds every point of the colliding segment (issue 13: it ignored the elbow)."""
    assert kinematics_from_spec(spec).reach == pytest.approx(oracle_reach(spec), abs=1e-9)


points = st.complex_numbers(max_magnitude=20.0, allow_nan=False, allow_infinity=False)


@st.composite
def segment_pairs(draw):
    """Random segments, with degenerate ones on purpose: a point, parallel, collinear, shared end."""
    p0, p1, q0, q1 = draw(points), draw(points), draw(points), draw(points)
    shape = draw(st.sampled_from(["random", "point", "parallel", "collinear", "shared"]))
    if shape == "point":
        p1 = p0
    elif shape == "parallel":
        q1 = q0 + (p1 - p0) * draw(st.floats(-2.0, 2.0))
    elif shape == "collinear":
        q0, q1 = p0 + (p1 - p0) * draw(st.floats(-2, 2)), p0 + (p1 - p0) * draw(st.floats(-2, 2))
    elif shape == "shared":
        q0 = p1
    return p0, p1, q0, q1


def _xy(z):
    return np.stack([np.real(z), np.imag(z)], -1)


@settings(max_examples=200, deadline=None)
@given(segment_pairs())
def test_segment_gap_is_the_dense_minimum(seg):
    p0, p1, q0, q1 = seg
    h = 1.0 / 400
    s = np.linspace(0.0, 1.0, 401)
    dense = float(np.abs((p0 + s[:, None] * (p1 - p0)) - (q0 + s[None, :] * (q1 - q0))).min())
    mine = float(segment_gap(p0, p1, q0, q1))
    assert mine <= dense + 1e-9  # the distance of two actual points bounds it
    assert dense - mine <= (abs(p1 - p0) + abs(q1 - q0)) * h / 2 + 1e-9  # the grid's spacing bounds the rest
    assert mine == pytest.approx(float(segment_distance(_xy(p0), _xy(p1), _xy(q0), _xy(q1))), abs=1e-7)


def test_segment_gap_exact_cases():
    assert float(segment_gap(0j, 4 + 0j, 2 - 1j, 2 + 1j)) == 0.0  # crossing
    assert float(segment_gap(0j, 4 + 0j, 4 + 0j, 9 + 3j)) == 0.0  # a shared end
    assert float(segment_gap(0j, 4 + 0j, 6 + 0j, 9 + 0j)) == 2.0  # collinear apart
    assert float(segment_gap(0j, 4 + 0j, 1 + 3j, 3 + 3j)) == 3.0  # parallel, overlapping in x
    assert float(segment_gap(1j, 1j, 0j, 4 + 0j)) == 1.0  # a point


# -- the certified swept check against dense sampling with the project's geometry -------------------

@st.composite
def motions(draw, single: bool = False):
    """A random pair (``b`` at a random offset about ``1.2·reach`` from ``a``), positions,
    joint deltas (one joint of one positioner when ``single``) and a need."""
    spec = draw(kinematics_specs)
    if spec["kind"] == "rotary":
        spec["steps"] = min(spec["steps"], 24)
    arm = Arm.from_json(spec)
    offset = arm.reach * draw(st.floats(0.3, 2.1)) * complex(math.cos(a := draw(st.floats(0, 6.3))), math.sin(a))
    j = arm.n_joints
    qa = [draw(st.integers(0, s - 1)) for s in arm.steps]
    qb = [draw(st.integers(0, s - 1)) for s in arm.steps]
    if single:
        da, db = [0] * j, [0] * j
        (da if draw(st.booleans()) else db)[draw(st.integers(0, j - 1))] = draw(st.sampled_from([1, -1]))
    else:
        da = draw(st.lists(st.integers(-1, 1), min_size=j, max_size=j))
        db = draw(st.lists(st.integers(-1, 1), min_size=j, max_size=j))
    for q, d in ((qa, da), (qb, db)):  # stay inside the hard stops
        if arm.kind == "alpha-beta" and not 0 <= q[1] + d[1] < arm.steps[1]:
            d[1] = -d[1] if 0 <= q[1] - d[1] < arm.steps[1] else 0
    if not any(da) and not any(db):
        da[0] = 1
    return spec, arm, offset, np.array(qa), np.array(da), np.array(qb), np.array(db)


def _dense(spec, offset, qa, da, qb, db, n=20001):
    """Project geometry: the distance at ``n`` equally spaced times."""
    kin = kinematics_from_spec(spec)
    t = np.linspace(0.0, 1.0, n)[:, None]
    sa = kin.segments(qa + t * da)
    sb = kin.segments(qb + t * db) + np.array([offset.real, offset.imag])
    return segment_distance(sa[:, 0], sa[:, 1], sb[:, 0], sb[:, 1])


@settings(max_examples=100, deadline=None)
@given(motions(), st.floats(-0.01, 0.01), st.sampled_from([True, True, False]), st.floats(0.0, 6.0))
@example(({"kind": "rotary", "arm": 2.0, "steps": 4}, Arm.from_json({"kind": "rotary", "arm": 2.0, "steps": 4}),
          2 + 0j, np.array([1]), np.array([1]), np.array([0]), np.array([1])), -0.000286932026038713, True, 0.0)
def test_certified_sweep_agrees_with_dense_sampling(motion, eps, near, anywhere):
    spec, arm, offset, qa, da, qb, db = motion
    d = _dense(spec, offset, qa, da, qb, db)
    h = 1.0 / (len(d) - 1)
    lip = float(arm.speed(da) + arm.speed(db))
    assert np.abs(np.diff(d)).max() <= lip * h + 1e-9  # the Lipschitz bound holds on the samples
    need = max(0.0, float(d.min()) + eps) if near else anywhere
    verdict = oracle_motion(_pair(spec, offset, need), 0, qa, da, 1, qb, db)
    event(f"verdict {verdict}, {'near the least distance' if near else 'any need'}")
    slack = lip * h / 2 + 1e-9  # the true least distance is at most this below the samples'
    # an entry whose distance stays within lip / (2 MAX_OPEN) of the need over a long stretch may
    # hold more than MAX_OPEN open intervals before they settle: undecided, by the oracle's design
    crowded = lip / (2 * MAX_OPEN)
    if d.min() < need - 1e-9:
        assert verdict == HIT
    if d.min() >= need + slack + crowded:
        assert verdict == FREE
    if verdict == FREE:
        assert d.min() >= need - 1e-9
    elif verdict == HIT:
        assert d.min() < need + slack
    else:
        assert verdict == UNDECIDED and abs(d.min() - need) <= slack + crowded


def _pair(spec, offset, need, qa=None, qb=None):
    zero = 0 if spec["kind"] == "rotary" else [0, 0]
    return {"layout": {"kind": "points", "xy": [[0.0, 0.0], [offset.real, offset.imag]]}, "kinematics": spec,
            "collision": {"buffer": need / 2}, "start": [qa or zero, qb or zero], "target": [zero, zero]}


@settings(max_examples=60, deadline=None)
@given(motions(single=True))
def test_least_distance_of_a_turn_is_exact(motion):
    """The critical-time minimum of :mod:`.rotation` against dense sampling, and against the
    branch and bound wherever that decides (two independent methods, one answer)."""
    spec, arm, offset, qa, da, qb, db = motion
    d = _dense(spec, offset, qa, da, qb, db)
    lip = float(arm.speed(da) + arm.speed(db))
    t = PairTables(arm, offset, 1.0)
    exact = float(t.least_on_turn(qa[None], da[None], qb[None], db[None])[0])
    assert exact <= d.min() + 1e-9
    assert d.min() - exact <= lip / (len(d) - 1) / 2 + 1e-9
    decided = []
    for need in (exact - 1e-3, exact + 1e-3, d.min() + 0.02, d.min() - 0.02):
        if need <= 0:
            continue
        tables = PairTables(arm, offset, need)

        def gap(e, tt):
            a0, a1 = arm.segment(qa + tt[:, None] * da)
            b0, b1 = arm.segment(qb + tt[:, None] * db)
            return segment_gap(a0, a1, offset + b0, offset + b1)
        truth = HIT if exact < need else FREE
        bnb = int(certify(gap, np.array([lip]), np.array([need]))[0])
        assert bnb in (truth, UNDECIDED)  # a long stretch near r may leave it open, never wrong
        assert int(tables.motion(qa[None], da[None], qb[None], db[None], None, None)[0]) == truth
        decided.append(bnb != UNDECIDED)
    assert any(decided)


# -- constructed tight cases -----------------------------------------------------------------------

def test_a_route_with_half_a_micrometre_of_clearance_is_free():
    data = tight_route(0.0005)
    assert oracle_motion(data, 0, [0], [1], 1, [0], [0]) == FREE
    assert oracle_solve(data) == 3
    moves = oracle_moves(data)
    assert moves == [(0, 0, 1)] * 3
    p = parse_problem(data)
    result = validate_plan(p, Plan("complete", apply_moves(p, moves)))
    assert result.valid and 0 <= result.min_clearance < 0.01, result


@pytest.mark.parametrize("clearance", [-1e-7, -0.001])
def test_a_move_just_too_close_collides(clearance):
    data = tight_route(clearance, angle_deg=-13.0)  # the least distance at t = 13/30, not a dyadic sample
    assert oracle_motion(data, 0, [0], [1], 1, [0], [0]) == HIT
    assert oracle_solve(data) is None


@pytest.mark.parametrize("clearance,verdict", [(5e-10, FREE), (1e-11, UNDECIDED), (0.0, UNDECIDED),
                                               (-1e-11, UNDECIDED), (-5e-10, HIT)])
def test_clearances_below_the_bisection_tolerance_are_decided_at_critical_times(clearance, verdict):
    """A touch at a grid position (``a``'s tip at 0°, ``b``'s base on +x): ``d`` has a
    tangent minimum at ``t = 0``, where no Lipschitz bound certifies anything below
    10⁻⁹ mm; the exact least distance of the turn decides — except a tie within 10⁻¹⁰ mm,
    which floating point would decide: undecided, never given a side."""
    data = tight_route(0.0)
    data["layout"]["xy"][1] = [14.0 + clearance, 0.0]
    assert oracle_motion(data, 0, [0], [1], 1, [0], [0]) == verdict
    assert oracle_motion(data, 0, [1], [-1], 1, [0], [0]) == verdict  # the same poses backwards
    if verdict == FREE:
        tables = Space(OracleProblem.from_json(data), [0, 1]).pairs[0][2]
        assert tables.edge(0, 0)[0, 0] == FREE and tables.counts["critical_times"] >= 1


@pytest.mark.parametrize("gap,verdict", [(4.000001, FREE), (4.0, UNDECIDED), (3.999999, HIT)])
def test_an_arm_turning_about_its_base_near_the_buffer_sum(gap, verdict):
    """A flat stretch: ``b``'s arm turns away from ``a``'s tip, which stays ``gap`` from
    ``b``'s base — no bound on ``t`` certifies a flat stretch 10⁻⁶ mm above ``r``; the
    critical times do.  Exactly ``r`` is a tie: the search reports both sides."""
    data = {"layout": {"kind": "points", "xy": [[0.0, 0.0], [15.0 + gap, 0.0]]},
            "kinematics": {"kind": "rotary", "arm": 15.0, "steps": 12}, "collision": {"buffer": 2.0},
            "start": [0, 1], "target": [0, 11]}
    for k in (1, 2, 10):
        assert oracle_motion(data, 1, [k], [1], 0, [0], [0]) == verdict
    if verdict == FREE:
        assert oracle_solve(data) == oracle_bounds(data)[0] == 2  # b turns 1 → 0 → 11 past a's tip
    elif verdict == UNDECIDED:
        assert oracle_bounds(data) == (2, None)  # ties blocked: no move leaves the touching start
        with pytest.raises(OracleUndecided):
            oracle_solve(data)
    else:
        with pytest.raises(OracleInputError, match="start configuration collides"):
            oracle_solve(data)


# -- the search ------------------------------------------------------------------------------------

def _plain_bfs(space: Space, goal: bool = True):
    """A plain dict-and-deque BFS over the oracle's own tables (strict: undecided = blocked)."""
    nxt, blk = space._blocked()
    n, k = space.n, space.k
    start = tuple(space.prob.start[p] for p in space.members)
    target = tuple(space.prob.target[p] for p in space.members)
    dist = {start: 0}
    queue = deque([start])
    while queue:
        c = queue.popleft()
        if goal and c == target:
            return dist[c], len(dist)
        for a in range(k):
            for m in range(len(space.moves())):
                j = int(nxt[m, c[a]])
                if j < 0 or any(t[m, c[a], c[b]] != FREE for (x, b), t in blk.items() if x == a):
                    continue
                d = c[:a] + (j,) + c[a + 1:]
                if d not in dist:
                    dist[d] = dist[c] + 1
                    queue.append(d)
    assert n ** k >= len(dist)
    return None, len(dist)


@pytest.mark.parametrize("seed", range(12))
def test_numpy_search_equals_a_plain_search(seed):
    """Undecided entries blocked on both sides (seed 67 has round numbers: ties)."""
    data = tight_problem(seed * 31 + 5, n=2 + seed % 2)
    space = Space(OracleProblem.from_json(data))
    distance, _ = _plain_bfs(space)
    _, strict = space.single(bounds=True)
    assert strict.distance == distance
    _, everything = space.single(goal=False, bounds=True)
    assert everything.reachable == _plain_bfs(space, goal=False)[1]
    if not strict.undecided:
        assert oracle_solve(data) == distance and oracle_reachable(data) == everything.reachable


@pytest.mark.parametrize("seed", range(10))
def test_oracle_plans_pass_the_project_validator(seed):
    data = tight_problem(seed * 13 + 2)
    moves = oracle_moves(data)
    assert (moves is None) == (oracle_solve(data) is None)
    if moves is None:
        return
    assert len(moves) == oracle_solve(data)
    p = parse_problem(data)
    result = validate_plan(p, Plan("complete", apply_moves(p, moves)))
    assert result.valid, result.problems


def test_members_remove_the_others():
    data = tight_route(-0.001)  # a is shut in by b (too close by 1 µm) and c
    assert oracle_solve(data) is None
    assert oracle_solve(data, members=[0, 2]) == 3  # without b: the short way
    assert oracle_solve(data, members=[0, 1]) == 9  # without c: the long way round
    assert oracle_solve(data, members=[0]) == 3
    with pytest.raises(OracleInputError):
        oracle_solve(data, members=[5])


def test_optimal_makespan_is_between_the_lower_bound_and_the_single_moves():
    feasible = 0
    for seed in (1, 2, 3, 6, 8):
        data = tight_problem(seed, n=2 + seed % 2)
        single, opt = oracle_solve(data), oracle_optimal_makespan(data)
        if single is None:
            continue
        feasible += 1  # a single-move plan is a simultaneous one
        p = parse_problem(data)
        lb = int(p.kinematics.joint_distance(p.start, p.target).max())
        assert opt is not None and lb <= opt <= single
    assert feasible >= 3


def test_refusals():
    big = {"layout": {"kind": "points", "xy": [[30.0 * k, 0.0] for k in range(5)]},
           "kinematics": {"kind": "rotary", "arm": 10.0, "steps": 24}, "collision": {"buffer": 1.0},
           "start": [0] * 5, "target": [1] * 5}
    with pytest.raises(OracleInputError, match="exceeds"):
        oracle_solve(big)
    assert oracle_solve(big, members=[0, 1, 2]) == 3
    clash = tight_route(0.0)
    clash["start"] = [9, 0, 9]
    with pytest.raises(OracleInputError, match="start configuration collides: positioners 0 and 2"):
        oracle_solve(clash)


@pytest.mark.parametrize("doubt,answer", [(lambda o: abs(o) < 15, None), (lambda o: abs(o) > 20, 3)])
def test_undecided_entries_raise_only_when_they_change_the_answer(monkeypatch, doubt, answer):
    """Make every free swept entry of some pairs undecided: of a's pairs (its only route
    may or may not exist: the oracle must raise), or of the pair b–c (irrelevant to a's
    route: the answer stands, and the search did read them)."""
    data = tight_route(0.25)
    assert oracle_solve(data) == 3
    original = PairTables.edge

    def doubtful(self, side, joint):
        table = original(self, side, joint).copy()
        if doubt(self.offset):
            table[table == FREE] = UNDECIDED
        return table

    monkeypatch.setattr(PairTables, "edge", doubtful)
    if answer is None:
        with pytest.raises(OracleUndecided, match="undecided swept entries"):
            oracle_solve(data)
    else:
        assert oracle_solve(data) == answer
        assert Space(OracleProblem.from_json(data)).single().undecided > 0


def test_simultaneous_tables_read_single_moves_like_the_edges():
    data = tight_problem(4, n=2)
    space = Space(OracleProblem.from_json(data))
    ((_, _, t),) = space.pairs
    opts = joint_options(space.prob.arm).tolist()
    sim = t.simultaneous()
    for joint in range(space.prob.arm.n_joints):
        u = opts.index([1 if j == joint else 0 for j in range(space.prob.arm.n_joints)])
        ok = space.prob.arm.successors(np.array([opts[u]]))[0] >= 0
        assert np.array_equal(sim[u, 0][ok], t.edge(0, joint)[ok])
        assert np.array_equal(sim[0, u][:, ok], t.edge(1, joint)[:, ok])
