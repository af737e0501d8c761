"""The results database and the resume bookkeeping beyond the done rule: what a row holds
after a round trip, refusals that name the file, the best row of any version, the order
of the cases to run, and the ``skip_larger`` rule's memory of failures.  Written against
docs/study.md; each test fails on a mutant the mutation run (benchmarks/mutation_run.py)
found surviving."""

from __future__ import annotations

import dataclasses
import json
import sqlite3
from pathlib import Path

import numpy as np
import pytest

from supcoord.errors import InputError
from supcoord.study.execute import _Skips
from supcoord.study.resume import pending, records
from supcoord.study.spec import study_from_dict
from supcoord.study.store import ResultStore


def test_refusals_name_the_file(tmp_path):
    missing = tmp_path / "none.sqlite"
    with pytest.raises(InputError) as info:
        ResultStore(missing, create=False)
    assert str(info.value) == f"{missing}: no results database here yet (run the study first)"
    assert info.value.where == str(missing) and info.value.value == str(missing)
    with ResultStore(missing):  # created
        pass
    with ResultStore(missing, create=False) as db:  # now there: opened
        assert db.rows() == []
    nodir = tmp_path / "no" / "r.sqlite"
    with pytest.raises(InputError) as info:
        ResultStore(nodir)
    assert f"directory {str(nodir.parent)!r} does not exist" in str(info.value)
    assert info.value.value == str(nodir)  # the output check names the file in its message
    text = tmp_path / "notes.sqlite"
    text.write_bytes(b"this is not SQLite at all, just text " * 100)
    with pytest.raises(InputError) as info:
        ResultStore(text)
    assert "not a results database" in str(info.value)
    assert info.value.where == str(text) and info.value.value == str(text)


def test_an_older_database_gains_the_new_columns(tmp_path):
    path = tmp_path / "old.sqlite"
    con = sqlite3.connect(path)
    con.execute("CREATE TABLE cases (study TEXT, status TEXT)")  # an old layout: no key, no limits
    con.execute("INSERT INTO cases VALUES ('s', 'ok')")
    con.commit()
    con.close()
    with ResultStore(path) as db:
        db.record({"key": "k", "study": "s", "status": "timeout", "time_limit": 5.0, "memory_limit_mb": 100.0})
        rows = db.rows("s")
        assert len(rows) == 2 and {r["status"] for r in rows} == {"ok", "timeout"}
        assert ("k", None, "timeout", 5.0, 100.0, None) in db.finished()


def test_a_row_round_trips_numpy_numbers_flags_huge_integers_and_json(tmp_path):
    with ResultStore(tmp_path / "r.sqlite") as db:
        db.record({"key": "k", "study": "s", "status": "ok", "seconds": np.float64(1.25), "size": np.int64(7),
                   "states": 2**63, "verdict": -(2**63), "makespan": 2**63 - 1, "load": True,
                   "params": {"b": 1, "a": [1, 2], "p": Path("y")}, "extra": {"z": 1, "a": Path("x")}})
        (row,) = db.rows()
        assert row["seconds"] == 1.25 and isinstance(row["seconds"], float) and row["size"] == 7
        # integers past SQLite's 64 bits are kept as their digits (in a TEXT column: exactly)
        assert row["states"] == str(2**63) and row["verdict"] == str(-(2**63)) and row["makespan"] == 2**63 - 1
        assert row["load"] == 1
        assert row["params"] == '{"a": [1, 2], "b": 1, "p": "y"}'  # canonical JSON: keys sorted, paths as text
        assert row["extra"] == {"a": "x", "z": 1}
        raw = db.con.execute("SELECT extra FROM cases").fetchone()[0]
        assert raw == '{"a": "x", "z": 1}'
        db.record({"key": "k2", "study": "s", "status": "ok", "extra": '{"given": "as text"}'})
        db.record({"key": "k3", "study": "t", "status": "ok"})
        assert db.rows("t")[0]["extra"] == {} and [r["key"] for r in db.rows("t")] == ["k3"]
        assert {r["key"] for r in db.rows("s")} == {"k", "k2"} and len(db.rows()) == 3
        assert {r["key"]: r["extra"] for r in db.rows("s")}["k2"] == {"given": "as text"}
        run = db.start_run(study="s", workers=np.int64(2), command="run")
        db.finish_run(run, ended="finished", ran=np.int64(3), wall_seconds=np.float64(2.5))
        (r,) = db.runs()
        assert (r["workers"], r["ran"], r["wall_seconds"], r["ended"]) == (2, 3, 2.5, "finished")
        # every write is committed at once: another connection sees it
        other = sqlite3.connect(tmp_path / "r.sqlite")
        assert other.execute("SELECT count(*) FROM cases").fetchone()[0] == 3
        other.close()


def test_rows_come_ordered_by_series_size_seed_and_start(tmp_path):
    with ResultStore(tmp_path / "r.sqlite") as db:
        for key, series, size, seed, started in (("a", "y", 1, 0, "2"), ("b", "x", 2, 0, "1"), ("c", "x", 1, 1, "1"),
                                                 ("d", "x", 1, 0, "3"), ("e", "x", 1, 0, "2")):
            db.record({"key": key, "study": "s", "series": series, "size": size, "seed": seed, "started": started})
        assert [r["key"] for r in db.rows("s")] == ["e", "d", "c", "b", "a"]


def _paper(positioners, **block):
    return study_from_dict({"time_limit": 10, "cases": [{"kind": "paper", "steps": 6, "positioners": positioners,
                                                         **block}]})


def test_any_version_takes_an_ok_row_else_the_latest(tmp_path):
    study = _paper([2, 3, 4])
    a, b, c = study.cases
    with ResultStore(tmp_path / "r.sqlite") as db:
        rows = [(a, "v1", "ok", "2026-01-01"), (a, "v2", "timeout", "2026-01-02"),  # ok wins though older
                (b, "v1", "timeout", "2026-01-02"), (b, "v2", "crashed", "2026-01-01"),  # the latest wins
                (c, "v1", "crashed", None), (c, "v2", "error", "2026-01-01")]  # no start time: oldest
        for case, version, status, started in rows:
            db.record({"key": case.key(version), "params_key": case.params_key, "status": status,
                       "time_limit": 10, "started": started})
        db.record({"key": "stray", "params_key": None, "status": "ok", "started": "2030-01-01"})
        best = records(study, db, "v3", any_version=True)
        assert [best[x.params_key][0] for x in (a, b, c)] == ["ok", "timeout", "error"]
        assert records(study, db, "v2") == {a.params_key: ("timeout", 10, None), b.params_key: ("crashed", 10, None),
                                            c.params_key: ("error", 10, None)}
        assert records(study, db, "v3") == {}
        assert [x.params["positioners"] for x in pending(study, db, "v3", any_version=True)] == []
        assert len(pending(study, db, "v3")) == 3


def test_pending_cases_come_smallest_first(tmp_path):
    study = study_from_dict({"time_limit": 10, "cases": [
        {"kind": "paper", "steps": 6, "positioners": [5, 3]},
        {"kind": "paper", "steps": 6, "positioners": [4, 2]}]})
    sizes = [c.size for c in study.cases]
    assert sizes == [5, 3, 4, 2]
    with ResultStore(tmp_path / "r.sqlite") as db:
        assert [c.size for c in pending(study, db, "v")] == [2, 3, 4, 5]
        # a case of no size counts as size 0: first; equal sizes keep the order of their blocks
        unsized = dataclasses.replace(study.cases[3], size=None)  # of the later block
        sized_one = dataclasses.replace(study.cases[0], size=1)
        mixed = dataclasses.replace(study, cases=[sized_one, study.cases[1], unsized])
        assert [c.size for c in pending(mixed, db, "v")] == [None, 1, 3]


def test_skip_larger_remembers_the_smallest_failure_of_each_series(tmp_path):
    study = study_from_dict({"time_limit": 10, "cases": [
        {"kind": "paper", "steps": 6, "positioners": [2, 3, 4, 5, 6], "seed": [0, 1], "skip_larger": "positioners"},
        {"kind": "paper", "steps": 8, "positioners": [2, 3], "skip_larger": "positioners"}]})
    by = {(c.params["positioners"], c.params["seed"], c.params["steps"]): c for c in study.cases}
    with ResultStore(tmp_path / "r.sqlite") as db:
        for key, status in (((5, 0, 6), "timeout"), ((3, 1, 6), "out-of-memory"), ((6, 0, 6), "timeout")):
            case = by[key]
            db.record({"key": case.key("v"), "params_key": case.params_key, "status": status, "time_limit": 10,
                       "memory_limit_mb": case.memory_limit_mb})
        skips = _Skips(study, db, "v")
        # seeds share a series: 3 ran out of memory (seed 1), so 4, 5 and 6 of any seed are not run
        assert skips.reason(by[(3, 0, 6)]) is None and skips.reason(by[(2, 1, 6)]) is None
        assert skips.reason(by[(4, 0, 6)]) == "not run: positioners = 3 already ran out of memory"
        assert skips.reason(by[(6, 1, 6)]) == "not run: positioners = 3 already ran out of memory"
        assert skips.reason(by[(3, 0, 8)]) is None  # another series (steps 8)
        # a later, smaller failure replaces a larger one; an equal one keeps the first status
        skips.note(by[(2, 0, 6)], "timeout")
        assert skips.reason(by[(3, 0, 6)]) == "not run: positioners = 2 already ran out of time"
        skips.note(by[(2, 1, 6)], "out-of-memory")
        assert skips.reason(by[(3, 0, 6)]) == "not run: positioners = 2 already ran out of time"
        # waits only for a strictly smaller case of its own series
        assert skips.waits_for(by[(3, 0, 8)], [by[(2, 0, 8)]]) and not skips.waits_for(by[(3, 0, 8)], [by[(3, 0, 8)]])
        assert not skips.waits_for(by[(3, 0, 8)], [by[(2, 0, 6)]])
        # failures of a run under a smaller limit than asked now are not remembered
        raised = study_from_dict({"time_limit": 20, "memory_limit": 8192, "cases": [
            {"kind": "paper", "steps": 6, "positioners": [2, 3, 4, 5, 6], "seed": [0, 1],
             "skip_larger": "positioners"}]})
        assert all(_Skips(raised, db, "v").reason(c) is None for c in raised.cases)
        assert json.dumps(sorted(_Skips(study, db, "v").failed.values())) == '[[3, "out-of-memory"]]'
        # another code version remembers nothing, unless any version counts
        assert _Skips(study, db, "v2").failed == {}
        assert _Skips(study, db, "v2", any_version=True).reason(by[(4, 1, 6)]) is not None
        # a case without skip_larger waits for nothing
        plain = _paper([2, 3]).cases
        assert not skips.waits_for(plain[1], [plain[0]]) and skips.reason(plain[1]) is None


def test_skip_larger_series_differ_by_every_other_parameter(tmp_path):
    """One block, two series (steps 6 and 8): a failure in one skips nothing of the other."""
    study = study_from_dict({"time_limit": 10, "cases": [
        {"kind": "paper", "steps": [6, 8], "positioners": [2, 3, 4], "skip_larger": "positioners"}]})
    by = {(c.params["positioners"], c.params["steps"]): c for c in study.cases}
    assert len({c.block for c in study.cases}) == 1
    with ResultStore(tmp_path / "r.sqlite") as db:
        case = by[(2, 6)]
        db.record({"key": case.key("v"), "params_key": case.params_key, "status": "timeout", "time_limit": 10})
        skips = _Skips(study, db, "v")
        assert skips.reason(by[(3, 6)]) is not None and skips.reason(by[(3, 8)]) is None
        assert skips.waits_for(by[(3, 6)], [by[(2, 6)]]) and not skips.waits_for(by[(3, 6)], [by[(2, 8)]])
