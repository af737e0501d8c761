"""Every shipped example runs clean, as a user would run it.

- every problem in ``docs/examples/`` (``*.json``): ``supcoord solve`` then ``supcoord
  check`` on the plan it wrote (the APO wok: by ``docs/instruments.md``'s block, in
  ``test_readme_commands.py``);
- every study in ``docs/examples/`` (``*.toml``): ``supcoord study run`` into a fresh
  database;
- every study in ``benchmarks/studies/`` at its smallest: the parsed study keeps, of
  each series (a kind with its model, route, family …), the case of the smallest size
  and seed, so every kind and route it declares runs once (of series that differ only in
  the plan-improvement setting, the first; a case with the same
  parameters as a smallest case of a study earlier in name order, as ``scaling.toml``
  shares ``readme.toml``'s, is run by that study's test only, whichever worker runs it).

A crashed case, a case whose parameters the library refuses (``error``), a non-zero
exit, a traceback or a warning fails the test.  Files are found by globbing, so a new
example is covered without touching this file.  (The notebooks: ``test_notebooks.py``.)
"""

from __future__ import annotations

import dataclasses
import json
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
#: examples solved and checked by a block of the user docs, not again here (a full wok takes about
#: a minute of CPU): test_readme_commands.py runs that block and asserts its plan is complete and
#: checks valid with every robot at target, with nothing on standard error
SOLVED_BY_DOCS = {"sdss_v_apo.json": ("docs/instruments.md", "supcoord solve docs/examples/sdss_v_apo.json ")}
PROBLEMS = sorted(p for p in (ROOT / "docs" / "examples").glob("*.json") if p.name not in SOLVED_BY_DOCS)
#: the studies of docs/examples, each run as written by a block of the user docs and not again
#: here: test_readme_commands.py runs the block and asserts that every case of the study is ``ok``
STUDIES_RUN_BY_DOCS = {"study_small.toml": ("docs/study.md", "supcoord study run docs/examples/study_small.toml ")}
STUDIES = sorted((ROOT / "docs" / "examples").glob("*.toml"))
BENCHMARK_STUDIES = sorted((ROOT / "benchmarks" / "studies").glob("*.toml"))
#: what a clean run never prints on standard error
NOISE = ("Traceback", "Warning", "warning:", "Exception ignored")


def supcoord(*argv, cwd: Path, timeout: float = 240) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "supcoord.cli", *map(str, argv)], capture_output=True, text=True,
                          cwd=cwd, timeout=timeout)


def clean(proc: subprocess.CompletedProcess) -> None:
    noise = [word for word in NOISE if word in proc.stderr]
    assert proc.returncode == 0 and not noise, f"exit {proc.returncode}, {noise}:\n{proc.stderr[-3000:]}"


def test_the_examples_are_found():
    assert PROBLEMS and STUDIES and BENCHMARK_STUDIES


def test_every_example_study_is_run_by_the_docs():
    assert {p.name for p in STUDIES} == set(STUDIES_RUN_BY_DOCS)


def test_the_examples_left_to_the_docs_are_run_there():
    for name, (doc, command) in {**SOLVED_BY_DOCS, **STUDIES_RUN_BY_DOCS}.items():
        assert (ROOT / "docs" / "examples" / name).exists()
        assert f"\n{command}" in (ROOT / doc).read_text(), (name, doc)


@pytest.mark.slow
@pytest.mark.timeout(240)
@pytest.mark.parametrize("path", PROBLEMS, ids=lambda p: p.name)
def test_a_problem_solves_and_its_plan_checks(path, tmp_path):
    solved = supcoord("solve", path, "--out", tmp_path / "plan.json", "--json", cwd=tmp_path)
    clean(solved)
    plan = json.loads(solved.stdout)
    assert plan["status"] in ("complete", "partial", "infeasible"), plan.get("reason")
    if plan["status"] == "infeasible":
        assert plan["reason"]
        return
    checked = supcoord("check", path, tmp_path / "plan.json", "--json", cwd=tmp_path)
    clean(checked)
    result = json.loads(checked.stdout)
    assert result["valid"] is True
    if path.suffix == ".json" and plan["status"] == "complete":
        assert result["at_target"] == len(plan["configurations"][0])


#: the time limit (s) of a benchmark case run here: what this module proves of a case is that it
#: runs, then finishes or stops at its limit as ``timeout``, never ``crashed`` or ``error``; a
#: case the study lets run out of time at its smallest (``readme.toml``'s monolithic route on the
#: 7 alpha-beta robots: 60 s) proves that as well in 10 s (its model is built and its search
#: under way), and every other smallest case ends in a few seconds of CPU
SMOKE_TIME_LIMIT = 10.0


#: parameters that choose how much work a case does, not which code reads the study's
#: parameters: series that differ from an earlier one only in these are not run again
#: (``nextgen.toml`` declares every instrument with and without the plan improvement; the
#: improvement itself runs in every other solve case and in the planner's tests)
SCALE_ONLY = ("improve",)


def _same_code(case) -> str:
    return repr((case.kind, sorted((k, repr(v)) for k, v in case.params.items() if k not in SCALE_ONLY)))


def smallest(study):
    """The study with one case per series: the smallest size, then the smallest seed, each
    limited to :data:`SMOKE_TIME_LIMIT` seconds; of series that differ only in
    :data:`SCALE_ONLY`, the first."""
    best = {}
    for case in study.cases:
        rank = (case.size or 0, case.params.get("seed") or 0, case.block)
        if case.series not in best or rank < best[case.series][0]:
            best[case.series] = (rank, case)
    kept: dict[str, object] = {}
    for _, case in best.values():
        kept.setdefault(_same_code(case), case)
    cases = [dataclasses.replace(case, time_limit=min(case.time_limit, SMOKE_TIME_LIMIT)) for case in kept.values()]
    return dataclasses.replace(study, cases=cases)


@pytest.mark.slow
@pytest.mark.timeout(300)
@pytest.mark.parametrize("path", BENCHMARK_STUDIES, ids=lambda p: p.name)
def test_a_benchmark_study_runs_at_its_smallest(path, tmp_path):
    from supcoord.study import load_study, results_rows, run_study

    study = load_study(path)
    small = smallest(study)
    kinds = {(c.kind, c.params.get("route"), c.params.get("model")) for c in study.cases}
    assert {(c.kind, c.params.get("route"), c.params.get("model")) for c in small.cases} == kinds
    earlier = {c.params_key for other in BENCHMARK_STUDIES[:BENCHMARK_STUDIES.index(path)]
               for c in smallest(load_study(other)).cases}
    todo = dataclasses.replace(small, cases=[c for c in small.cases if c.params_key not in earlier])
    lines: list[str] = []
    summary = run_study(todo, tmp_path / "r.sqlite", workers=0, progress=lines.append)
    rows = results_rows(tmp_path / "r.sqlite") if todo.cases else []
    bad = [(r["series"], r["status"], r["message"]) for r in rows if r["status"] in ("crashed", "error", "lost")]
    assert not bad and summary.ran == len(todo.cases), "\n".join(lines)

