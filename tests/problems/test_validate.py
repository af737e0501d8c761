"""The independent validator; plans of the independent oracle; compaction; PLAN.json."""

import copy
import dataclasses
import json

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from supcoord.errors import FormatError, InputError
from supcoord.geometry.layout import hex_grid
from supcoord.problems import (
    Plan,
    compact_moves,
    event_name,
    load_plan,
    lower_bound,
    parse_event,
    parse_plan,
    parse_problem,
    plan_from_moves,
    validate_plan,
)
from supcoord.problems.plan import apply_moves
from supcoord.problems.validate import hex_bases_by_angle
from supcoord.testing.oracle import FREE, HIT, oracle_motion
from supcoord.testing.oracle.oracle_model import OracleProblem
from supcoord.testing.oracle.certified_sweep import TIE
from supcoord.testing.oracle.tables import PairTables

from problem_cases import THREE, oracle_plan_moves

TWO_AB = {
    "layout": {"kind": "points", "xy": [[0, 0], [22.4, 0]]},
    "kinematics": {"kind": "alpha-beta", "alpha": 7.4, "beta": 15.0, "alpha_steps": 12, "beta_steps": 7,
                   "beta_range": [0, 180]},
    "collision": {"buffer": 2.0},
    "start": [[0, 6], [6, 6]],
    "target": [[6, 0], [0, 0]],
}


@pytest.fixture(scope="module")
def three():
    return parse_problem(copy.deepcopy(THREE), "three.json")


@pytest.fixture(scope="module")
def three_moves(three):
    return oracle_plan_moves(three)


def test_oracle_plans_pass_the_validator(three, three_moves):
    assert three_moves is not None
    single = Plan("complete", apply_moves(three, three_moves), lower_bound=lower_bound(three))
    result = validate_plan(three, single)
    assert result.valid, result.problems
    assert result.collisions == 0 and result.at_target == 3 and result.min_clearance >= 0
    plan = plan_from_moves(three, three_moves)
    assert plan.makespan < len(three_moves) and plan.makespan >= plan.lower_bound == 6
    result = validate_plan(three, plan)
    assert result.valid, result.problems
    assert [parse_event(three.kinematics, e) for e in plan.events] == list(three_moves)


def test_alpha_beta_oracle_plan_passes_the_validator():
    p = parse_problem(copy.deepcopy(TWO_AB))
    moves = oracle_plan_moves(p)
    assert moves is not None
    plan = plan_from_moves(p, moves)
    result = validate_plan(p, plan)
    assert result.valid, result.problems
    assert plan.makespan >= lower_bound(p) == 6


def test_validator_catches_collisions(three):
    # 0 points at 1 (+x) while 1 turns round to point back at 0 (−x)
    confs = [np.array([[0], [k % 12], [0]]) for k in range(0, -7, -1)]
    result = validate_plan(three, Plan("complete", confs))
    assert not result.valid and result.collisions > 0
    assert any("positioners 0 and 1 collide" in p for p in result.problems)


def test_validator_catches_swept_collision_that_end_points_miss():
    data = {"layout": {"kind": "points", "xy": [[0, 0], [5, -5]]},
            "kinematics": {"kind": "rotary", "arm": 10.0, "steps": 4},
            "collision": {"buffer": 1.0}, "start": [0, 0], "target": [1, 0]}
    p = parse_problem(data)
    result = validate_plan(p, Plan("complete", [np.array([[0], [0]]), np.array([[1], [0]])]))
    assert not result.valid and result.collisions == 1
    assert "step 0->1: positioners 0 and 1 collide" in result.problems[0]
    assert result.min_clearance < -1.9  # a's arm passes through b's base
    (inc,) = result.incidents
    # a's arm (length 10) lies across b's arm, the segment y = −5, x ∈ [5, 15], for θ ∈ [−45°, −30°]
    assert inc.step == 0 and inc.positioners == [0, 1] and 1 / 3 - 0.02 <= inc.t <= 0.5 + 0.02
    assert inc.distance < 0.1 and inc.required == 2.0


def test_validator_catches_jumps_and_wrong_ends(three, three_moves):
    good = apply_moves(three, three_moves)
    jump = good[:2] + good[3:]
    assert any("more than one step" in p for p in validate_plan(three, Plan("complete", jump)).problems)
    r = validate_plan(three, Plan("complete", good[1:]))
    assert not r.valid and any("not the start" in p for p in r.problems)
    r = validate_plan(three, Plan("complete", good[:-1]))
    assert not r.valid and r.at_target == 2 and any("not the target" in p for p in r.problems)
    r = validate_plan(three, Plan("complete", good, makespan=3))
    assert any("makespan is 3" in p for p in r.problems)
    bad = [c.copy() for c in good]
    bad[1][0, 0] = 12
    assert any("out of the joint ranges" in p for p in validate_plan(three, Plan("complete", bad)).problems)
    r = validate_plan(three, Plan("infeasible", [], reason="blocked"))
    assert not r.valid and r.at_target == 0 and "blocked" in r.problems[0]


def test_wrap_is_one_step():
    data = {"layout": {"kind": "points", "xy": [[0, 0]]}, "kinematics": {"kind": "rotary", "arm": 5.0, "steps": 12},
            "collision": {"buffer": 1.0}, "start": [11], "target": [1]}
    p = parse_problem(data)
    assert lower_bound(p) == 2
    plan = plan_from_moves(p, [(0, 0, 1), (0, 0, 1)])
    assert [c.ravel().tolist() for c in plan.configurations] == [[11], [0], [1]]
    assert plan.events == ["v0", "v0"]
    assert validate_plan(p, plan).valid


def test_compaction_merges_independent_moves(three):
    # positioners 0 and 2 are 44.8 mm apart: moves of 0 and 2 alone never collide
    moves = [(0, 0, 1), (2, 0, 1), (0, 0, 1), (2, 0, 1)]
    confs = compact_moves(three, moves)
    assert [c.ravel().tolist() for c in confs] == [[0, 0, 0], [1, 0, 1], [2, 0, 2]]
    with pytest.raises(InputError, match="move 0"):
        compact_moves(three, [(5, 0, 1)])
    with pytest.raises(InputError, match="target"):
        plan_from_moves(three, moves)


def test_events_and_plan_json(tmp_path, three, three_moves):
    ab = parse_problem(copy.deepcopy(TWO_AB)).kinematics
    assert event_name(ab, 3, 1, -1) == "wb3" and parse_event(ab, "va12") == (12, 0, 1)
    with pytest.raises(InputError, match="unknown move event"):
        parse_event(ab, "v3")
    plan = plan_from_moves(three, three_moves, stats={"seconds": 0.0})
    path = tmp_path / "plan.json"
    plan.dump(path, three.kinematics)
    back = load_plan(path, three)
    assert back.status == "complete" and back.events == plan.events and back.makespan == plan.makespan
    assert all(np.array_equal(a, b) for a, b in zip(back.configurations, plan.configurations))
    data = json.loads(path.read_text())
    for key, value, message in [("status", "done", "status"), ("configurations", [[0, 0]], r"configurations\[0\]"),
                                ("configurations", [[0, 0, "a"]], r"configurations\[0\]\[2\]"),
                                ("makespan", "3", "makespan"), ("events", [1], "events")]:
        bad = dict(data, **{key: value})
        with pytest.raises(FormatError, match=message):
            parse_plan(bad, three, "plan.json")
    with pytest.raises(FormatError, match="JSON object"):
        parse_plan([], three)
    with pytest.raises(InputError, match="plan file not found"):
        load_plan(tmp_path / "none.json", three)


plan_values = st.recursive(
    st.none() | st.booleans() | st.integers(-20, 20) | st.floats(allow_nan=False) | st.text(max_size=4),
    lambda children: st.lists(children, max_size=4) | st.dictionaries(st.text(max_size=8), children, max_size=3),
    max_leaves=10,
)


@st.composite
def plan_objects(draw):
    confs = draw(st.lists(st.lists(st.integers(-2, 14), min_size=3, max_size=3), max_size=5))
    data = {"status": draw(st.sampled_from(["complete", "infeasible", "unknown"])), "configurations": confs}
    if draw(st.booleans()):
        data[draw(st.sampled_from(["status", "configurations", "makespan", "events", "reason", "stats"]))] = \
            draw(plan_values)
    return data


@settings(max_examples=150)
@given(plan_objects())
def test_fuzz_plans_give_an_answer_or_a_format_error(data):
    problem = parse_problem(copy.deepcopy(THREE))
    try:
        plan = parse_plan(data, problem, "plan.json")
    except FormatError as exc:
        assert exc.where == "plan.json"
        return
    result = validate_plan(problem, plan)
    assert isinstance(result.valid, bool) and result.collisions >= 0 and 0 <= result.at_target <= 3
    assert not result.valid or (plan.configurations and np.array_equal(plan.configurations[-1], problem.target))


@pytest.mark.parametrize("rings", range(9))
def test_validator_hex_construction_agrees_with_the_layout(rings):
    # two independent constructions of formats.md's ordering (edge walk vs axial sort by angle)
    assert np.allclose(hex_bases_by_angle(rings, 10.4), hex_grid(rings, 10.4), atol=1e-9)


def test_validator_rebuilds_hex_bases_and_reports_a_wrong_one():
    data = {"layout": {"kind": "hex", "rings": 1, "pitch": 22.4},
            "kinematics": {"kind": "rotary", "arm": 5.0, "steps": 12},
            "collision": {"buffer": 1.0}, "start": [0] * 7, "target": [0] * 7}
    p = parse_problem(data)
    assert validate_plan(p, Plan("complete", [p.start])).valid
    p = dataclasses.replace(p, bases=p.bases[[0, 2, 1, 3, 4, 5, 6]])  # as if the layout had swapped two positioners
    r = validate_plan(p, Plan("complete", [p.start]))
    assert not r.valid and "layout: base of positioner 1 is [11.2, 19.399] but the hex ordering" in r.problems[0]


def test_incidents_are_listed_up_to_the_limit(three):
    # 0 stands at +x while 1 turns backwards through pointing at 0, and again forwards
    confs = [np.array([[0], [-k % 12], [0]]) for k in range(7)]
    confs += confs[::-1][1:]
    r = validate_plan(three, Plan("complete", confs))
    assert r.collisions == len(r.incidents) >= 2
    assert all(i.positioners == [0, 1] and i.distance < i.required == 4.0 for i in r.incidents)
    assert [i.step for i in r.incidents] == sorted(i.step for i in r.incidents)


# --- the validator and the tables are independent implementations of one definition ----------

AB_KIN = {"kind": "alpha-beta", "alpha": 7.4, "beta": 15.0, "alpha_steps": 12, "beta_steps": 7, "beta_range": [0, 180]}
ROT_KIN = {"kind": "rotary", "arm": 15.0, "steps": 12}


@settings(max_examples=60, deadline=None)
@given(kin=st.sampled_from([AB_KIN, ROT_KIN]), dist=st.floats(8.0, 40.0), angle=st.floats(0, 2 * np.pi),
       data=st.data())
def test_validator_agrees_with_the_swept_tables_on_single_moves(kin, dist, angle, data):
    """Table free ⇒ the validator sees no collision; validator collision ⇒ the table blocks; a
    blocked move the validator passes is a close call (clearance within its sampling error).
    The table entry is computed by the tables' own primitive (``motion_collides``, what
    ``swept_table`` calls for the entries its end-point bounds leave open).  The oracle is the
    third opinion: its verdict decides, and its exact least distance of the turn says how
    close a call was."""
    from supcoord.geometry.collision import motion_collides

    base_b = [dist * np.cos(angle), dist * np.sin(angle)]
    pair = {"layout": {"kind": "points", "xy": [[0.0, 0.0], base_b]}, "kinematics": kin,
            "collision": {"buffer": 2.0}, "start": [0, 0] if kin["kind"] == "rotary" else [[0, 0], [0, 0]],
            "target": [0, 0] if kin["kind"] == "rotary" else [[0, 0], [0, 0]]}
    p = parse_problem(pair, check_collisions=False)
    k = p.kinematics
    i = data.draw(st.integers(0, k.n_positions - 1))
    j = data.draw(st.integers(0, k.n_positions - 1))
    m = data.draw(st.integers(0, len(k.moves()) - 1))
    joint, delta = k.moves()[m]
    qa, qb = k.all_positions()[i], k.all_positions()[j]
    nxt = k.step(qa, joint, delta)
    if nxt is None:  # past a hard stop: no motion to validate
        return
    p = dataclasses.replace(p, start=np.array([qa, qb]), target=np.array([nxt, qb]))
    result = validate_plan(p, Plan("complete", [p.start, p.target]))
    d = np.zeros(k.n_joints)
    d[joint] = delta
    blocked = bool(motion_collides(k, [0.0, 0.0], qa, d, k, base_b, qb, np.zeros(k.n_joints), 4.0))
    if not blocked:
        assert result.valid, result.problems
    if result.collisions:
        assert blocked
    if blocked and result.valid:
        assert result.min_clearance < 0.05 / 2 + 1e-3
    da = d.astype(int)
    oracle = oracle_motion(p.to_json(), 0, qa, da, 1, qb, np.zeros(k.n_joints, dtype=int))
    least = float(PairTables(OracleProblem.from_json(p.to_json()).arm, complex(*base_b), 4.0)
                  .least_on_turn(qa[None], da[None], qb[None], np.zeros((1, k.n_joints), dtype=int))[0])
    if abs(least - 4.0) > TIE:  # a tie (a touch at exactly 4 mm, up to rounding) has no one answer
        assert oracle == (HIT if least < 4.0 else FREE)
        assert blocked == (oracle == HIT)  # the tables' exact turn and the oracle agree
    if oracle == FREE:
        assert result.valid, result.problems
    elif least < 4.0 - 1e-5:  # deeper than the validator's bisection tolerance: it must see it
        assert result.collisions and result.min_clearance < 0


@pytest.mark.parametrize("kin", [ROT_KIN, AB_KIN], ids=["rotary", "alpha-beta"])
@pytest.mark.parametrize("seed", range(4))
def test_planner_plans_on_random_hex_problems_pass_the_validator(kin, seed):
    from supcoord.planning import solve
    from supcoord.problems import random_problem

    p = random_problem({"kind": "hex", "rings": 1, "pitch": 22.4}, kin, 2.0, seed)
    plan = solve(p)
    assert plan.status in ("complete", "infeasible")
    if plan.status == "complete":
        result = validate_plan(p, plan)
        assert result.valid and result.at_target == p.n, result.problems
        assert plan.lower_bound <= plan.makespan


def test_events_must_name_moves_that_lead_to_the_last_configuration(three, three_moves):
    plan = plan_from_moves(three, three_moves)
    assert validate_plan(three, plan).valid
    shuffled = Plan("complete", plan.configurations, events=plan.events[::-1])  # order is not checked
    assert validate_plan(three, shuffled).valid
    for events, message in [(plan.events[:-1], "do not lead from the start to the last configuration"),
                            (plan.events + ["va0"], "'va0' is not a move event of this rotary problem"),
                            (plan.events + ["v3"], "'v3' is not a move event"),
                            (["x"], "events[0] = 'x'")]:
        r = validate_plan(three, Plan("complete", plan.configurations, events=events))
        assert not r.valid and any(message in p for p in r.problems), (events, r.problems)
    ab = parse_problem(copy.deepcopy(TWO_AB))
    moves = oracle_plan_moves(ab)
    r = validate_plan(ab, plan_from_moves(ab, moves))
    assert r.valid, r.problems
    r = validate_plan(ab, Plan("complete", plan_from_moves(ab, moves).configurations, events=["v0"]))
    assert any("'v0' is not a move event of this alpha-beta problem" in p for p in r.problems)
