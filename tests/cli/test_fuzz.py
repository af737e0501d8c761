"""Fuzzing every reader through the command line: mutated files never give a traceback.

Seeds are files the tool writes itself (a PROBLEM.json, the PLAN.json of its solution, a
plant as ``.gen`` and as a JSON generator); :mod:`supcoord.testing.fuzz` mutates them at
the byte level and at the structure level (a JSON value replaced by a hostile one, a
``.gen`` number, tag or state range changed), hypothesis choosing the seeds. Every run must end
with exit 0 (an answer), 2 (one line on standard error naming the file) or 3 (a budget),
never with an exception. The campaign script ``benchmarks/fuzz_campaign.py`` runs the
same mutations, many more of them, through the installed command in subprocesses under
memory and time limits.
"""

from __future__ import annotations

import contextlib
import io
import json
import random

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from supcoord.bdd.budget import current_rss
from supcoord.cli.main import main
from supcoord.testing.fuzz import mutate_gen, mutate_json

THREE = {
    "layout": {"kind": "points", "xy": [[0, 0], [22.4, 0], [44.8, 0]]},
    "kinematics": {"kind": "rotary", "arm": 15.0, "steps": 12},
    "collision": {"buffer": 2.0},
    "start": [0, 0, 0],
    "target": [6, 6, 6],
}

FUZZ = settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture,
                                                                      HealthCheck.too_slow])
SEEDS = st.integers(0, 2**32 - 1)


def _memory() -> str:
    """A memory budget 2 GiB above what this test process already holds (the budget is on
    the resident size of the whole process, which the test run shares)."""
    return f"{(current_rss() + 2**31) // 2**20}M"


def run(*argv):
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main([str(a) for a in argv])
    return code, out.getvalue(), err.getvalue()


def _assert_clean(code: int, err: str, name: str) -> None:
    assert code in (0, 2, 3), (code, err)
    if code == 2:
        lines = err.strip().splitlines()
        assert len(lines) == 1 and name in lines[0], err


@pytest.fixture(scope="module")
def seeds(tmp_path_factory):
    d = tmp_path_factory.mktemp("seeds")
    (d / "problem.json").write_text(json.dumps(THREE))
    code, _, _ = run("solve", d / "problem.json", "--out", d / "plan.json", "--quiet")
    assert code == 0
    from supcoord.des.families import small_factories
    from supcoord.des.io import write_generator

    plants, specs = small_factories(1)
    write_generator(plants[0], d / "m.gen")
    write_generator(specs[0], d / "b.gen")
    write_generator(plants[0], d / "m.json")
    return {name: (d / name).read_bytes() for name in ("problem.json", "plan.json", "m.gen", "b.gen", "m.json")}


@pytest.mark.timeout(240)
@FUZZ
@given(seed=SEEDS)
def test_mutated_problem_files(seeds, tmp_path, seed):
    path = tmp_path / "problem.json"
    path.write_bytes(mutate_json(seeds["problem.json"], random.Random(seed)))
    code, _, err = run("solve", path, "--json", "--quiet", "--timeout", "20", "--max-memory", _memory())
    _assert_clean(code, err, "problem.json")


@pytest.mark.timeout(240)
@FUZZ
@given(seed=SEEDS)
def test_mutated_plan_files(seeds, tmp_path, seed):
    (tmp_path / "problem.json").write_bytes(seeds["problem.json"])
    path = tmp_path / "plan.json"
    path.write_bytes(mutate_json(seeds["plan.json"], random.Random(seed)))
    code, _, err = run("check", tmp_path / "problem.json", path, "--json", "--quiet", "--timeout", "20")
    _assert_clean(code, err, "plan.json")


#: the .gen mutations at half the others' number: a mutated range of up to MAX_STATES states is
#: a valid file, read in about two seconds per command, and hypothesis seeks those out (a 60-example
#: run took 40 s of CPU); benchmarks/fuzz_campaign.py runs thousands
FUZZ_GEN = settings(FUZZ, max_examples=30)


@pytest.mark.timeout(240)
@FUZZ_GEN
@given(seed=SEEDS)
@pytest.mark.slow
def test_mutated_gen_files(seeds, tmp_path, seed):
    path = tmp_path / "m.gen"
    path.write_bytes(mutate_gen(seeds["m.gen"], random.Random(seed)))
    code, _, err = run("supcon", "--plant", path, "--json", "--quiet", "--timeout", "20", "--max-memory", _memory())
    _assert_clean(code, err, "m.gen")
    code, _, err = run("force", path, "--json", "--quiet", "--timeout", "20", "--max-memory", _memory())
    _assert_clean(code, err, "m.gen")


@pytest.mark.timeout(240)
@FUZZ
@given(seed=SEEDS)
def test_mutated_json_generators(seeds, tmp_path, seed):
    path = tmp_path / "m.json"
    path.write_bytes(mutate_json(seeds["m.json"], random.Random(seed)))
    code, _, err = run("supcon", "--plant", path, "--json", "--quiet", "--timeout", "20", "--max-memory", _memory())
    _assert_clean(code, err, "m.json")


def test_seeds_are_read(seeds, tmp_path):
    """The unmutated seeds are accepted, so the fuzzing starts from valid files."""
    for name in ("problem.json", "plan.json", "m.gen", "m.json"):
        (tmp_path / name).write_bytes(seeds[name])
    assert run("check", tmp_path / "problem.json", tmp_path / "plan.json", "--json")[0] == 0
    assert run("supcon", "--plant", tmp_path / "m.gen", "--json")[0] == 0
    assert run("supcon", "--plant", tmp_path / "m.json", "--json")[0] == 0


@pytest.mark.timeout(60)
def test_runaway_json_generator_is_refused_at_once(tmp_path):
    """A 140-byte JSON generator asking for 10^12 states ran past 300 s and 3.7 GB: it is
    refused before anything is allocated (at most MAX_STATES states)."""
    path = tmp_path / "g.json"
    path.write_text('{"name": "G", "states": 1000000000000, "init": 0, "marked": [0], '
                    '"events": [{"name": "a", "controllable": true}], "transitions": [[0, "a", 0]]}')
    code, _, err = run("supcon", "--plant", path, "--json")
    assert code == 2 and path.name in err and "states" in err and len(err.strip().splitlines()) == 1


@pytest.mark.timeout(60)
def test_a_ten_million_state_gen_file_is_answered_or_stopped_by_its_budget(tmp_path):
    """A 234-byte .gen of 10^7 states (a <Consecutive> range) ran past 400 s: within the
    readers' bound, it is either answered or stopped by --timeout (exit 3), never left running."""
    path = tmp_path / "g.gen"
    path.write_text("<Generator> \"G\" <Alphabet> \"a\" </Alphabet> <States> <Consecutive> 1 10000000 </Consecutive> "
                    "</States> <TransRel> </TransRel> <InitStates> 1 </InitStates> <MarkedStates> 1 </MarkedStates> "
                    "</Generator>")
    code, out, err = run("supcon", "--plant", path, "--json", "--timeout", "5")
    assert code in (0, 3), err
    assert json.loads(out)["status"] in ("ok", "unknown")


@pytest.mark.timeout(60)
def test_an_unterminated_quote_after_blanks_is_answered_at_once(tmp_path):
    """Found by this suite: an unterminated quote after a run of blanks in <TransRel> made
    the bulk reader's regular expression backtrack exponentially (the command hung)."""
    path = tmp_path / "g.gen"
    path.write_text('<Generator> "G" <Alphabet> "a" "b" </Alphabet> <States> I W </States>\n<TransRel>\n'
                    'I "a" W\nW            "           W\nW "b" I\n</TransRel> <InitStates> I </InitStates>\n'
                    '<MarkedStates> I </MarkedStates> </Generator>\n')
    code, _, err = run("force", path, "--json", "--quiet")
    assert code == 2 and "g.gen" in err and len(err.strip().splitlines()) == 1


@pytest.mark.timeout(60)
def test_a_five_thousand_digit_attribute_is_no_traceback(tmp_path):
    """Found by the campaign (spec .gen, seeds 781 and 2104): a 5,000-digit number where the
    bulk reader classifies bare words hit Python's integer-conversion limit."""
    from supcoord.des.families import small_factories
    from supcoord.des.io import write_generator

    plants, specs = small_factories(1)
    for i, g in enumerate(plants):
        write_generator(g, tmp_path / f"p{i}.gen")
    write_generator(specs[0], tmp_path / "s.gen")
    (tmp_path / "bad.gen").write_bytes(mutate_gen((tmp_path / "s.gen").read_bytes(), random.Random(781)))
    code, _, err = run("supcon", "--plant", tmp_path / "p0.gen", tmp_path / "p1.gen", "--spec", tmp_path / "bad.gen",
                       "--json")
    _assert_clean(code, err, "bad.gen")
