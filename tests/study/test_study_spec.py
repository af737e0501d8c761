"""Study files, cases and their keys, the done rule, growth fits and the database (no process is started)."""

from __future__ import annotations

import dataclasses
import json

import pytest

from supcoord.errors import InputError
from supcoord.study import ResultStore, load_study, study_from_dict
from supcoord.study.execute import _Skips
from supcoord.study.resume import is_done, pending
from supcoord.study.fit import fit_growth
from supcoord.study.kinds import FAMILY_NAMES, SUPCON_METHODS, default_route
from supcoord.study.spec import parse_memory

PAPER = {"kind": "paper", "steps": 6, "positioners": [2, 3], "seed": [0, 1]}


def test_a_list_is_a_grid_axis_and_defaults_are_filled_in():
    study = study_from_dict({"name": "s", "time_limit": 30, "memory_limit": "1 GiB", "cases": [PAPER]})
    assert [(c.params["positioners"], c.params["seed"]) for c in study.cases] == [(2, 0), (2, 1), (3, 0), (3, 1)]
    case = study.cases[0]
    assert case.params == {"positioners": 2, "steps": 6, "model": "literal", "route": "modular", "seed": 0,
                           "semantics": "preemptive", "count_transitions": None}
    assert (case.time_limit, case.memory_limit_mb, case.size, case.positioners) == (30.0, 1024.0, 2, 2)
    # an explicit default is the same case (same key) as an omitted one
    same = study_from_dict({"cases": [{**PAPER, "route": "modular", "model": "literal"}]})
    assert {c.params_key for c in same.cases} == {c.params_key for c in study.cases}


def test_keys_depend_on_parameters_and_version_not_on_limits():
    a = study_from_dict({"cases": [{"kind": "paper", "steps": 6, "positioners": 3}]}).cases[0]
    b = dataclasses.replace(a, time_limit=1.0)
    c = study_from_dict({"cases": [{"kind": "paper", "steps": 6, "positioners": 3, "seed": 1}]}).cases[0]
    assert a.key("v1") == b.key("v1") != a.key("v2")
    assert a.key("v1") != c.key("v1")


def test_the_same_case_twice_runs_once_and_args_lists_are_not_axes():
    study = study_from_dict({"cases": [PAPER, PAPER,
                                       {"kind": "call", "function": "time:sleep", "args": [0.1]},
                                       {"kind": "call", "function": "time:sleep", "args": [[0.1], [0.2]]}]})
    assert len(study.cases) == 4 + 2  # the first call's args is one value; the second's a list of two


def test_solve_cases_know_their_size_and_series():
    study = study_from_dict({"cases": [
        {"kind": "solve", "problem": "random", "kinematics": {"kind": "rotary", "arm": 15.0, "steps": 12},
         "rings": [1, 2], "route": ["local", "monolithic"]},
        {"kind": "solve", "problem": "preset", "instrument": "sdss-v", "rings": 1}]})
    assert [(c.series, c.size) for c in study.cases] == [
        ("solve rotary local", 7), ("solve rotary monolithic", 7), ("solve rotary local", 19),
        ("solve rotary monolithic", 19), ("solve sdss-v local", 7)]


@pytest.mark.parametrize("block, field, value", [
    ({"kind": "paper", "steps": 6, "positioners": "ten"}, "cases[0].positioners", "'ten'"),
    ({"kind": "paper", "steps": 6, "positioners": [3, 0]}, "cases[0].positioners", "0"),
    ({"kind": "paper", "steps": 6, "positoners": 3}, "cases[0].positoners", "positoners"),
    ({"kind": "paper", "steps": 6}, "cases[0].positioners", "missing"),
    ({"kind": "paper", "steps": 6, "positioners": 3, "model": "coupled", "route": "modular"}, "cases[0].route", "literal"),
    ({"kind": "paper", "steps": 6, "positioners": 3, "model": "coupled", "route": "settled", "semantics": "standard"},
     "cases[0].route", "preemptive"),
    ({"kind": "papr"}, "cases[0].kind", "must be one of"),
    ({"kind": "supcon", "family": "nope", "size": 3}, "cases[0].family", "'nope'"),
    ({"kind": "solve", "problem": "random", "rings": 1}, "cases[0].kinematics", "missing"),
    ({"kind": "solve", "problem": "no/such/file.json"}, "cases[0].problem", "file not found"),
    ({"kind": "force", "size": 3}, "cases[0].family", "either family"),
    ({"kind": "call", "function": "sleep"}, "cases[0].function", "module:name"),
    ({"kind": "paper", "steps": 6, "positioners": 3, "time_limit": -1}, "cases[0].time_limit", "-1"),
    ({"kind": "paper", "steps": 6, "positioners": 3, "memory_limit": "lots"}, "cases[0].memory_limit", "lots"),
    ({"kind": "paper", "steps": 6, "positioners": 3, "skip_larger": "nodes"}, "cases[0].skip_larger", "nodes"),
])
def test_a_bad_block_names_the_file_the_field_and_the_value(tmp_path, block, field, value):
    path = tmp_path / "bad.json"
    path.write_text(json.dumps({"cases": [block]}))
    with pytest.raises(InputError) as info:
        load_study(path)
    line = info.value.one_line()
    assert line.startswith(f"{path}: {field}") and value in line and "\n" not in line, line


def test_study_level_mistakes_and_bad_files(tmp_path):
    bad = tmp_path / "s.toml"
    for text, expected in (("cases = 3", "cases"), ("name = 'a b'\n[[cases]]\nkind='paper'", "name"),
                           ("[[cases]\nkind=", "not valid TOML"), ("colour = 1\n[[cases]]\nkind='paper'", "colour")):
        bad.write_text(text)
        with pytest.raises(InputError, match=expected) as info:
            load_study(bad)
        assert info.value.one_line().startswith(str(bad))
    with pytest.raises(InputError, match="study file not found"):
        load_study(tmp_path / "missing.toml")


def test_memory_sizes():
    assert parse_memory("6 GiB", "m") == 6144 and parse_memory(512, "m") == 512 and parse_memory("none", "m") is None
    assert parse_memory("1.5gb", "m") == 1536
    with pytest.raises(InputError):
        parse_memory("-3 MB", "m")


def test_the_study_lists_agree_with_the_library():
    from supcoord.des.families import FAMILIES
    from supcoord.paper.run import default_route as library_route
    from supcoord.synthesis.reachability import METHODS

    assert set(FAMILY_NAMES) == set(FAMILIES) and set(SUPCON_METHODS) == set(METHODS)
    assert all(default_route(m, s) == library_route(m, s)
               for m in ("literal", "coupled") for s in ("preemptive", "standard"))


def test_done_means_same_key_and_a_limit_at_least_as_large(tmp_path):
    study = study_from_dict({"time_limit": 10, "cases": [{"kind": "paper", "steps": 6, "positioners": [2, 3, 4, 5],
                                                          "skip_larger": "positioners"}]})
    a, b, c, d = study.cases
    assert is_done(("ok", 1, 1), a) and is_done(("crashed", 1, 1), a) and is_done(("timeout", 10, None), a)
    assert not is_done(("timeout", 5, None), a)  # the limit was raised since: run it again
    assert not is_done(("skipped", 10, None), a) and not is_done(None, a)
    assert not is_done(("crashed", 1, 1), a, ("crashed",)) and is_done(("ok", 1, 1), a, ("crashed",))
    assert not is_done(("lost", 1, 1), a)  # a worker that died: run it again
    with ResultStore(tmp_path / "r.sqlite") as db:
        for case, version, status in ((a, "v", "ok"), (b, "v", "timeout"), (c, "old", "ok")):
            db.record({"key": case.key(version), "params_key": case.params_key, "status": status, "time_limit": 10})
        assert [x.params["positioners"] for x in pending(study, db, "v")] == [4, 5]
        assert [x.params["positioners"] for x in pending(study, db, "other")] == [2, 3, 4, 5]
        assert [x.params["positioners"] for x in pending(study, db, "other", any_version=True)] == [5]
        # skip_larger: 3 ran out of time, so 4 and 5 (larger, same series) are not run
        skips = _Skips(study, db, "v")
        assert skips.reason(a) is None and "positioners = 3" in skips.reason(d)
        # a case of a skip_larger series waits while a smaller one of its series runs (any seed)
        assert skips.waits_for(d, [c]) and not skips.waits_for(c, [d]) and not skips.waits_for(d, [])


def test_the_database_keeps_one_row_per_key_and_huge_numbers(tmp_path):
    with ResultStore(tmp_path / "r.sqlite") as db:
        db.record({"key": "k", "status": "timeout", "bdd_nodes": 10**20, "extra": {"a": [1, 2]}})
        db.record({"key": "k", "status": "ok", "seconds": 2.0})
        rows = db.rows()
        assert len(rows) == 1 and rows[0]["status"] == "ok" and rows[0]["extra"] == {}
        run = db.start_run(study="s", started="t", workers=2)
        db.finish_run(run, ran=1, ended="finished")
        assert db.runs()[0]["ended"] == "finished"
    (tmp_path / "junk.sqlite").write_text("not a database " * 100)
    with pytest.raises(InputError, match="not a results database"):
        ResultStore(tmp_path / "junk.sqlite")


def test_growth_fits_tell_exponential_from_power():
    exp = fit_growth([2, 3, 4, 5, 6], [0.04, 0.24, 1.6, 15, 120])
    assert exp.model == "exponential" and 6 < exp.rate < 8
    power = fit_growth([1, 10, 100, 1000, 5000], [0.05, 0.1, 0.5, 2.1, 10.6])
    assert power.model == "power" and 0.4 < power.rate < 1.0
    assert fit_growth([1, 2], [1, 2]) is None
