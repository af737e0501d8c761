"""PROBLEM.json parsing and validation, random problems; fuzzing the parser."""

import copy
import json

import numpy as np
import pytest
from hypothesis import given, settings

from supcoord.errors import FormatError, InputError
from supcoord.problems import Problem, load_problem, parse_problem, random_problem
from supcoord.problems.validate import segment_distance_ericson

from problem_cases import ALPHA_BETA, ROTARY, SDSS_SHORT, mutated_problems



def test_parse_and_round_trip():
    for data in (ROTARY, ALPHA_BETA):
        p = parse_problem(copy.deepcopy(data), "x.json")
        again = parse_problem(json.loads(json.dumps(p.to_json())))
        assert np.array_equal(p.start, again.start) and np.array_equal(p.target, again.target)
        assert np.allclose(p.bases, again.bases) and p.kinematics == again.kinematics
        assert p.priority == again.priority
    p = parse_problem(copy.deepcopy(ALPHA_BETA))
    assert p.n == 3 and p.start.shape == (3, 2) and p.priority == [1, 2, 3]  # default priority


def _mutated(data, path, value):
    d = copy.deepcopy(data)
    *head, last = path
    node = d
    for key in head:
        node = node[key]
    if value is _DELETE:
        del node[last]
    else:
        node[last] = value
    return d


_DELETE = object()
CASES = [
    (ROTARY, ("start",), [0] * 6, FormatError, "start has 6 positions"),
    (ROTARY, ("target", 2), 12, InputError, r"target\[2\]: theta position 12 is out of range"),
    (ROTARY, ("target", 2), "3", FormatError, r"target\[2\] must be an integer"),
    (ROTARY, ("target", 2), True, FormatError, r"target\[2\] must be an integer"),
    (ROTARY, ("priority",), [1, 2], FormatError, "priority must be a list of 7 integers"),
    (ROTARY, ("priority", 0), 1.5, FormatError, r"priority\[0\]"),
    (ROTARY, ("layout", "kind"), "square", FormatError, "layout.kind"),
    (ROTARY, ("kinematics", "kind"), "scara", FormatError, "kinematics.kind"),
    (ROTARY, ("kinematics", "steps"), 0, InputError, "kinematics.steps"),
    (ROTARY, ("collision", "buffer"), -1, InputError, "collision.buffer"),
    (ROTARY, ("collision",), _DELETE, FormatError, "'collision' is missing"),
    (ROTARY, ("collision", "buffer"), [1, 2], FormatError, "collision.buffer"),
    (ALPHA_BETA, ("start", 1), [0, 7], InputError, r"start\[1\]: beta position 7 is out of range"),
    (ALPHA_BETA, ("start", 1), 3, FormatError, r"start\[1\] must be a list of 2 integers"),
    (ALPHA_BETA, ("kinematics", "beta_range"), [0], InputError, "beta_range"),
    (ALPHA_BETA, ("layout", "xy", 1), [0, 0], InputError, "repeats"),
]


@pytest.mark.parametrize("data,path,value,exc,message", CASES)
def test_user_errors_name_field_and_value(data, path, value, exc, message):
    with pytest.raises(exc, match=message) as info:
        parse_problem(_mutated(data, path, value), "problem.json")
    assert info.value.where == "problem.json"
    assert str(info.value).startswith("problem.json: ")


def test_colliding_start_and_target_name_the_positioners():
    d = _mutated(ROTARY, ("start",), [0, 6, 0, 0, 0, 0, 0])  # centre points +x, positioner 1 (on +x) points −x
    with pytest.raises(InputError, match=r"start configuration collides: positioners 0 and 1") as info:
        parse_problem(d, "p.json")
    assert info.value.value == [0, 1]
    d = _mutated(ALPHA_BETA, ("target",), [[0, 0], [6, 0], [0, 6]])  # 0 and 1 reach straight at each other
    with pytest.raises(InputError, match=r"target configuration collides: positioners 0 and 1"):
        parse_problem(d, "p.json")


def test_load_problem_file_errors(tmp_path):
    with pytest.raises(InputError, match="problem file not found"):
        load_problem(tmp_path / "missing.json")
    bad = tmp_path / "bad.json"
    bad.write_text("{\"layout\": ")
    with pytest.raises(FormatError, match="not valid JSON") as info:
        load_problem(bad)
    assert info.value.where == str(bad)
    bad.write_bytes(b"\xff\xfe\x00")
    with pytest.raises(FormatError):
        load_problem(bad)
    good = tmp_path / "good.json"
    good.write_text(json.dumps(ROTARY))
    assert isinstance(Problem.load(good), Problem)


def _ericson_collisions(p):
    seg = p.kinematics.segments(p.start) + p.bases[:, None]
    tgt = p.kinematics.segments(p.target) + p.bases[:, None]
    out = 0
    for s in (seg, tgt):
        for a in range(p.n):
            for b in range(a + 1, p.n):
                if segment_distance_ericson(s[a, 0], s[a, 1], s[b, 0], s[b, 1]) < p.buffers[a] + p.buffers[b]:
                    out += 1
    return out


@pytest.mark.parametrize("kin", [ROTARY["kinematics"], ALPHA_BETA["kinematics"]], ids=["rotary", "alpha-beta"])
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_random_problems_are_collision_free_and_deterministic(kin, seed):
    layout = {"kind": "hex", "rings": 2, "pitch": 22.4}
    p = random_problem(layout, kin, 2.0, seed)
    q = random_problem(layout, kin, 2.0, seed)
    assert np.array_equal(p.start, q.start) and np.array_equal(p.target, q.target) and p.priority == q.priority
    assert json.dumps(p.to_json()) == json.dumps(q.to_json())
    assert _ericson_collisions(p) == 0
    assert sorted(p.priority) == list(range(1, 20))
    r = random_problem(layout, kin, 2.0, seed + 100)
    assert not (np.array_equal(p.start, r.start) and np.array_equal(p.target, r.target))


def test_random_problem_near_and_too_dense():
    layout = {"kind": "hex", "rings": 2, "pitch": 22.4}
    p = random_problem(layout, ALPHA_BETA["kinematics"], 2.0, 4, near=1, priority="index")
    assert np.all(p.kinematics.joint_distance(p.start, p.target) <= 1)
    assert p.priority == list(range(1, 20))
    with pytest.raises(InputError, match="collision-free configuration"):
        random_problem({"kind": "hex", "rings": 1, "pitch": 1.0}, ROTARY["kinematics"], 2.0, 0, attempts=3)


@settings(max_examples=300)
@given(mutated_problems())
def test_fuzz_parser_raises_only_user_errors(data):
    try:
        p = parse_problem(data, "fuzz.json")
    except (InputError, FormatError) as exc:
        assert exc.where == "fuzz.json"
        assert "\n" not in exc.one_line()
        return
    assert p.start.shape == p.target.shape == (p.n, p.kinematics.n_joints)


# --- the "preset" shorthand and unknown fields ---------------------------------------------

def test_preset_fills_in_what_the_file_leaves_out():
    p = parse_problem(copy.deepcopy(SDSS_SHORT), "short.json")
    kin = p.kinematics.to_json()
    assert p.layout == {"kind": "hex", "rings": 1, "pitch": 22.4}
    assert (kin["kind"], kin["alpha"], kin["beta"], kin["beta_range"]) == ("alpha-beta", 7.4, 15.0, [0.0, 180.0])
    assert np.all(p.buffers == 2.0) and p.warnings == []
    again = parse_problem(json.loads(json.dumps(p.to_json())))
    assert again.to_json() == p.to_json() and again.extra["preset"] == "sdss-v"
    # what the file gives wins over the preset
    mine = _mutated(_mutated(SDSS_SHORT, ("collision",), {"buffer": 1.0}), ("layout", "pitch"), 30.0)
    p = parse_problem(mine)
    assert np.all(p.buffers == 1.0) and p.layout["pitch"] == 30.0 and p.kinematics.alpha == 7.4
    moons = parse_problem(_mutated(_mutated(SDSS_SHORT, ("preset",), "MOONS"), ("layout", "pitch"), 30.0))
    assert moons.kinematics.beta_range == (-180.0, 150.0) and moons.kinematics.beta == 17.0


@pytest.mark.parametrize("path,value,exc,message", [
    (("preset",), "sdss", InputError, "preset must be one of 'sdss-v', 'desi', 'moons', 'pfs', 'spec-s5', 'must', 'wst', got 'sdss'"),
    (("preset",), 3, InputError, "preset must be one of"),
    (("preset",), "moons", FormatError, "layout.pitch is missing and preset 'moons' has no pitch"),
    (("kinematics", "kind"), "rotary", InputError, "preset 'sdss-v' describes alpha-beta positioners"),
    (("kinematics", "beta_steps"), _DELETE, FormatError, "kinematics.beta_steps is missing"),
])
def test_preset_errors_name_the_field(path, value, exc, message):
    with pytest.raises(exc, match=message) as info:
        parse_problem(_mutated(SDSS_SHORT, path, value), "short.json")
    assert info.value.where == "short.json"


def test_unknown_fields_are_warnings_naming_the_field():
    data = _mutated(_mutated(ROTARY, ("prority",), [7, 6, 5, 4, 3, 2, 1]), ("kinematics", "arms"), 15.0)
    data = _mutated(_mutated(data, ("_comment",), "ignored"), ("collision", "buffers"), 1.0)
    p = parse_problem(data, "w.json")
    assert p.priority == [1, 2, 3, 4, 5, 6, 7]  # the typo is not read ...
    assert p.warnings == [  # ... but it is reported, one line each
        "w.json: unknown field 'prority' ignored (known: layout, kinematics, collision, start, target, priority, weight, offline, "
        "fixed, fibre, name, description, comment, preset, seed, target_ids)",
        "w.json: unknown field 'kinematics.arms' ignored (known: kind, arm, steps)",
        "w.json: unknown field 'collision.buffers' ignored (known: buffer, margin, obstacle_margin)",
    ]
    assert parse_problem(copy.deepcopy(ALPHA_BETA)).warnings == []


def test_checked_step_names_the_move_past_a_hard_stop():
    from supcoord.geometry import AlphaBeta
    from supcoord.problems.plan import checked_step

    kin = AlphaBeta(7.4, 15.0, 6, 4)
    assert checked_step(kin, [5, 1], 0, (2, 0, +1)).tolist() == [0, 1]
    with pytest.raises(InputError, match=r"move 7 \(vb2\) drives positioner 2 past a hard stop"):
        checked_step(kin, [0, 3], 7, (2, 1, +1))
