"""Mutation testing with mutmut, one module at a time with the tests that matter for it.

``benchmarks/mutations.py`` checks a curated set of bugs; this runs `mutmut
<https://mutmut.readthedocs.io>`_ (3.x), which generates every small mutant of a module
(operators, constants, comparisons, dropped arguments …) and runs, for each, the tests
that call the mutated function.  Each module gets a scratch copy of ``src/`` and
``tests/`` with a ``[tool.mutmut]`` section naming that module alone and its test files, so
a run stays within minutes on two shared cores; hypothesis runs its ``quick`` profile.

    python benchmarks/mutation_run.py --list                 # the modules and their tests
    python benchmarks/mutation_run.py store timing           # run these modules (niced)
    python benchmarks/mutation_run.py --report               # write results/mutation_score.md from the runs kept
    python benchmarks/mutation_run.py --show store           # the diff of every surviving mutant of a module
    python benchmarks/mutation_run.py --sample 40 --seed 0 validator   # a uniform random sample of 40 mutants
    python benchmarks/mutation_run.py --sample 40 --seed 1 validator   # a fresh one (earlier samples left out)
    python benchmarks/mutation_run.py timing --mutants NAME …  # these mutants again (the module first)
    python benchmarks/mutation_run.py --no-report timing     # run without rewriting the report after

A module too large to check whole in one sitting is checked on a uniform random sample of
its mutants (``--sample``, a fixed ``--seed``): verdicts of earlier runs are reused for the
sampled mutants they decided, the others run, and ``--report`` gives the sample's score with
its Wilson 95 % interval, labelled as an estimate, besides the module's full counts.  A
sample with another seed leaves out the mutants of the module's earlier samples (the tests
written for those survivors would bias it), and each sample keeps its mutants' first
verdicts: the report gives the first-pass score (unbiased) apart from the score now.

Runs are kept in ``--work`` (default: ``supcoord-mutation`` in the temporary directory),
one folder per module, so ``--report`` and ``--show`` read them later and a module run
again resumes.  ``benchmarks/results/mutation_survivors.toml`` holds, per surviving mutant,
why it is equivalent (or which test now kills it); ``--report`` quotes it, and
``benchmarks/results/mutation_notes.md``, how the runs were made.

Needs ``pip install mutmut`` (not a dependency of supcoord).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import random
import re
import shutil
import subprocess
import sys
import tempfile
import time
import tomllib
from collections import Counter
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "benchmarks" / "results" / "mutation_score.md"
SURVIVORS = ROOT / "benchmarks" / "results" / "mutation_survivors.toml"
WORK = Path(tempfile.gettempdir()) / "supcoord-mutation"
UNDECIDED = ("not checked", "check was interrupted by user", "skipped")
NO_MUTANT = "supcoord.no-such-mutant"  # a name no mutant has: mutmut generates the mutants and collects its statistics


@dataclass(frozen=True)
class Target:
    name: str
    area: str
    files: tuple[str, ...]  # relative to src/supcoord
    tests: tuple[str, ...]


TARGETS = [
    Target("store", "study store", ("study/store.py", "study/resume.py", "study/execute.py"),
           ("tests/study/test_study_resume.py", "tests/study/test_study_store_rows.py", "tests/study/test_study_spec.py",
            "tests/study/test_study_store_mutants.py")),
    Target("timing", "timing", ("problems/timing.py", "geometry/sweeps_apart.py"),
           ("tests/problems/test_timing_buffers.py", "tests/geometry/test_sweeps_apart.py",
            "tests/problems/test_timing_mutants.py")),
    Target("supcon", "synthesis fixpoints", ("synthesis/supcon.py",),
           ("tests/synthesis/test_supcon.py", "tests/synthesis/test_supcon_lift.py", "tests/synthesis/test_supcon_accessible.py",
            "tests/synthesis/test_supcon_mutants.py", "tests/synthesis/test_supcon_flat_mutants.py")),
    Target("reachability", "synthesis fixpoints", ("synthesis/reachability.py",),
           ("tests/synthesis/test_reachability.py", "tests/synthesis/test_reachability_within.py",
            "tests/synthesis/test_reachability_names.py", "tests/synthesis/test_reachability_schedules.py",
            "tests/synthesis/test_reachability_mutants.py")),
    Target("forcibility", "forcibility and witness", ("synthesis/forcibility.py", "synthesis/witness.py"),
           ("tests/synthesis/test_forcibility.py", "tests/synthesis/test_forcibility_bfa.py", "tests/synthesis/test_witness.py",
            "tests/synthesis/test_witness_env_choice.py", "tests/synthesis/test_forcibility_mutants.py")),
    Target("gen-reader", ".gen reader and writer", ("des/io/gen_parser.py", "des/io/gen_build.py", "des/io/gen_write.py"),
           ("tests/des/test_gen_mutants.py", "tests/des/test_gen_reader_mutants.py", "tests/des/test_gen_xml_lines.py", "tests/des/test_gen_sections.py", "tests/des/test_gen_refusal_values.py", "tests/des/test_gen_compat.py",
            "tests/des/test_gen_compat_export.py", "tests/des/test_io.py")),
    Target("geometry", "geometry bounds and swept checks",
           ("geometry/alpha_beta.py", "geometry/sweep.py", "geometry/pair_tables.py"),
           ("tests/geometry/test_sweep.py", "tests/geometry/test_collision.py", "tests/geometry/test_sweep_heterogeneous.py",
            "tests/geometry/test_geometry_mutants.py", "tests/geometry/test_alpha_beta_mutants.py",
            # the fast checks of these functions: the lazy entries, batch and heap tests (5-40 s each)
            # exercise batch.py and entries.py through the tables, and the heterogeneous oracle
            # sweep takes 76 s; the six-angle wrap test stays.
            "-k", "not lazy_entries and not release_free_heap and not tables_survive_eviction and not batch_swept"
                  " and not swept_entries_and_lines and not different_robots_agree")),
    Target("validator", "validator", ("problems/validate.py", "problems/validate_motion.py"),
           ("tests/problems/test_validate.py", "tests/problems/test_validate_messages.py",
            "tests/problems/test_validate_mutants.py", "tests/problems/test_partial_plan.py",
            "tests/problems/test_trajectories.py", "tests/planning/test_start_repair.py",
            "tests/planning/test_start_repair_timed.py",
            # the angle and trajectory plans, partial plans, bisection and repaired starts (timed too),
            # not the 95 s timing of tight plans nor the repairs' solves (3-10 s) (test_safety: see the notes)
            "-k", "not tight_plans_passes_the_validator and not random_colliding_starts"
                  " and not solve_from_a_colliding_start and not timed_plans_from_colliding_starts")),
    Target("descent", "window certificates and descent", ("planning/descent.py", "planning/windows.py"),
           ("tests/planning/test_planner.py", "tests/planning/test_descent_properties.py",
            "tests/planning/test_windows_mutants.py",
            # the fast solves of test_planner.py, the small components' windows against the oracle
            # (its grids and the oracle sweeps of
            # test_planner_oracle.py and test_descent_merged.py take minutes a mutant)
            "-k", "descent_steps_are_serialisable or tight_layouts_have_both_verdicts or alpha_beta_grid_plan_is_valid"
                  " or blockers_of_a_relaxed_path or conflict_components_split or symbolic_verdict_and_rank_equal_the_oracle"
                  " or test_descent_properties or test_windows_mutants")),
]
BY_NAME = {t.name: t for t in TARGETS}


def _prepare(t: Target, work: Path) -> Path:
    """A scratch project for ``t``: ``src/``, ``tests/`` and pyproject.toml with its mutmut section."""
    d = work / t.name
    if d.exists():  # a run to resume: mutmut keeps its verdicts in mutants/ and redoes changed files
        for sub in ("src", "tests"):
            shutil.rmtree(d / sub, ignore_errors=True)
    d.mkdir(parents=True, exist_ok=True)
    shutil.copytree(ROOT / "src", d / "src", ignore=shutil.ignore_patterns("__pycache__", "*.egg-info"))
    shutil.copytree(ROOT / "tests", d / "tests", ignore=shutil.ignore_patterns("__pycache__"))
    section = ["", "[tool.mutmut]", 'source_paths = ["src"]',
               "only_mutate = [" + ", ".join(f'"src/supcoord/{f}"' for f in t.files) + "]",
               "pytest_add_cli_args_test_selection = [" + ", ".join(f'"{x}"' for x in t.tests) + "]",
               'pytest_add_cli_args = ["-p", "no:cacheprovider", "--timeout", "300"]',
               "use_git_change_detection = false", ""]
    (d / "pyproject.toml").write_text((ROOT / "pyproject.toml").read_text() + "\n".join(section))
    return d


def _verdicts(d: Path) -> dict[Path, dict]:
    """mutmut's kept results of a run folder: ``*.meta`` file -> its JSON."""
    return {m: json.loads(m.read_text()) for m in (d / "mutants").rglob("*.meta")} if (d / "mutants").is_dir() else {}


def _restore(before: dict[Path, dict]) -> None:
    """Put back the verdicts a new run of some mutants forgot (mutmut regenerates the
    mutants of a fresh copy of ``src/`` and clears the others' results): a mutant whose
    function is unchanged (same hash) and that this run did not decide keeps its verdict."""
    for path, old in before.items():
        if not path.exists():
            continue
        new = json.loads(path.read_text())
        same = {f for f, h in old.get("hash_by_function_name", {}).items()
                if new.get("hash_by_function_name", {}).get(f) == h}
        changed = False
        for key, code in old.get("exit_code_by_key", {}).items():
            func = key.rsplit(".", 1)[-1].rsplit("__mutmut_", 1)[0]
            if code is not None and new["exit_code_by_key"].get(key, code) is None and func in same:
                new["exit_code_by_key"][key] = code
                if key in old.get("durations_by_key", {}):
                    new.setdefault("durations_by_key", {})[key] = old["durations_by_key"][key]
                changed = True
        if changed:
            tmp = path.with_suffix(".meta.tmp")
            tmp.write_text(json.dumps(new, indent=4))
            os.replace(tmp, path)


def run(t: Target, work: Path, children: int, limit: float, mutants: list[str] = ()) -> dict:
    before = _verdicts(work / t.name)
    d = _prepare(t, work)
    env = dict(os.environ, HYPOTHESIS_PROFILE="quick")
    env.pop("PYTHONPATH", None)
    cmd = ["nice", "-n", "15", sys.executable, "-m", "mutmut", "run", "--max-children", str(children), *mutants]
    t0 = time.time()
    with open(d / "run.log", "w") as log:
        try:
            proc = subprocess.run(cmd, cwd=d, env=env, stdout=log, stderr=subprocess.STDOUT, timeout=limit)
            code = proc.returncode
        except subprocess.TimeoutExpired:
            code = "time limit"
    seconds = time.time() - t0
    _restore(before)
    (d / "run.json").write_text(f'{{"seconds": {seconds:.0f}, "exit": "{code}", '
                                f'"finished": "{time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())}"}}\n')
    return {"seconds": seconds, "exit": code}


def _sample_files(d: Path) -> list[Path]:
    """The samples kept in a module's run folder: ``sample.json`` (the first, seed 0) and
    ``sample-SEED.json`` (each fresh sample drawn after it), in the order they were drawn."""
    return sorted(d.glob("sample*.json"), key=lambda f: json.loads(f.read_text()).get("drawn", ""))


def sample(t: Target, work: Path, children: int, limit: float, size: int, seed: int, also: list[str] = ()) -> dict:
    """Check a uniform random sample of ``size`` of ``t``'s mutants (``random.Random(seed)``
    over their sorted names, leaving out the mutants of the module's earlier samples, so a
    fresh sample is not the one the tests were written for): the sampled mutants a run
    decided before keep their verdict, the others are run, with the mutants ``also`` names
    (in the same run: mutmut's clean run of the tests is paid once).  The sample is kept in
    ``sample-SEED.json`` for :func:`report`, with each sampled mutant's *first* verdict, the
    one of the ``--sample`` runs, before any test was written for its survivors."""
    st = statuses(t, work)
    if not st:  # generate the mutants and collect the tests' statistics, run none
        run(t, work, children, limit, [f"{NO_MUTANT}"])
        st = statuses(t, work) or {}
    d = work / t.name
    f = d / "sample.json" if seed == 0 else d / f"sample-{seed}.json"
    if f.exists():  # the same sample again (a run its limit stopped): resume it
        kept = json.loads(f.read_text())
    else:
        earlier = {n for g in _sample_files(d) for n in json.loads(g.read_text())["names"]}
        pool = sorted(set(st) - earlier)
        kept = {"seed": seed, "size": min(size, len(pool)), "excluded": len(earlier),
                "drawn": time.strftime("%Y-%m-%d %H:%M:%S UTC", time.gmtime()),
                "names": sorted(random.Random(seed).sample(pool, min(size, len(pool)))), "first": {}}
        f.write_text(json.dumps(kept) + "\n")
    todo = [n for n in kept["names"] if st.get(n) == "not checked"] + list(also)
    r = run(t, work, children, limit, todo) if todo else {"seconds": 0.0, "exit": 0}
    if "first" in kept:
        now = statuses(t, work) or {}
        for n in kept["names"]:
            if n not in kept["first"] and now.get(n, "not checked") not in UNDECIDED:
                kept["first"][n] = now[n]
        f.write_text(json.dumps(kept) + "\n")
    return r


def wilson(k: int, n: int, z: float = 1.96) -> tuple[float, float]:
    """Wilson score interval of a proportion ``k / n`` (95 % for ``z = 1.96``)."""
    if n == 0:
        return 0.0, 1.0
    p, zz = k / n, z * z
    centre, half = (p + zz / (2 * n)) / (1 + zz / n), z * math.sqrt(p * (1 - p) / n + zz / (4 * n * n)) / (1 + zz / n)
    return max(0.0, centre - half), min(1.0, centre + half)


def statuses(t: Target, work: Path) -> dict[str, str] | None:
    """``mutant name -> status`` of the kept run of ``t`` (``None``: not run)."""
    d = work / t.name
    if not (d / "mutants").is_dir():
        return None
    proc = subprocess.run([sys.executable, "-m", "mutmut", "results", "--all", "true"], cwd=d,
                          capture_output=True, text=True, timeout=600)
    out = {}
    for line in proc.stdout.splitlines():
        name, sep, status = line.strip().rpartition(": ")
        if sep and name:
            out[name] = status
    return out


def show(t: Target, work: Path, names: list[str]) -> str:
    d = work / t.name
    parts = []
    for n in names:
        proc = subprocess.run([sys.executable, "-m", "mutmut", "show", n], cwd=d, capture_output=True, text=True,
                              timeout=120)
        parts.append(proc.stdout)
    return "\n".join(parts)


def _survivor_notes() -> dict[str, dict[str, str]]:
    return tomllib.loads(SURVIVORS.read_text()) if SURVIVORS.exists() else {}


#: how the runs were made and what each found (hand-written, quoted by the report)
NOTES_FILE = ROOT / "benchmarks" / "results" / "mutation_notes.md"


def _earlier(out: Path) -> dict[str, tuple[list[str], list[str]]]:
    """``module -> (table row's cells, detail lines)`` of the results file written before: a module whose
    run is not kept in ``--work`` (another machine, a cleaned temporary directory) keeps them."""
    if not out.exists():
        return {}
    rows, details, name = {}, {}, None
    for line in out.read_text().splitlines():
        cells = [c.strip() for c in line.split("|")]
        if line.startswith("| ") and len(cells) > 2 and cells[1] in BY_NAME and "not run" not in line:
            rows[cells[1]] = cells[1:-1]
        if line.startswith("## "):
            name = line[3:].strip() if line[3:].strip() in BY_NAME else None
            if name:
                details[name] = ["", line]
        elif name:
            details[name].append(line)
    for lines in details.values():
        while lines and not lines[-1]:
            lines.pop()
    return {k: (v, details.get(k, [])) for k, v in rows.items()}


def report(work: Path, out: Path) -> None:
    notes = _survivor_notes()
    earlier = _earlier(out)
    lines = ["# Mutation score (mutmut)", "",
             "Command: `python benchmarks/mutation_run.py MODULE …` then `python benchmarks/mutation_run.py --report`  ",
             f"Date: {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}  ",
             f"Machine: {platform.node()} ({platform.machine()}, {os.cpu_count()} CPUs, shared), "
             f"Python {platform.python_version()}, mutmut {_mutmut_version()}  ", "",
             "Each module's mutants run against its own tests only (the list in `benchmarks/mutation_run.py`); "
             "a mutant is *killed* when a test fails or times out. *No tests*: the mutant is in a function none "
             "of the module's selected tests calls (listed per module below). *Equivalent* survivors behave "
             "exactly as the original (the reason is given for each). "
             "*Full score* = killed / (mutants − no tests − equivalent), given only where every mutant was "
             "decided (none *not checked*). Where a run stopped at its time limit, *checked so far* is the same "
             "ratio over the mutants it decided (the first functions of the files, not a random choice), and "
             "*sampled estimate* is the score of a uniform random sample of the module's mutants with its "
             "Wilson 95 % interval (the second table).", "",
             "| module | files | mutants | killed | survived | equivalent | no tests | not checked | full score "
             "| checked so far | sampled estimate [95 % interval] | last run |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    estimates = _estimates(work, notes)
    details = []
    for t in TARGETS:
        st = statuses(t, work)
        if not st:  # not run here, or stopped before mutmut listed its mutants
            row, kept = earlier.get(t.name, (None, []))
            lines.append(_row(t, row[2:8], row[-1], row[10] if len(row) == 12 else "") if row else
                         f"| {t.name} | {', '.join(t.files)} | – | – | – | – | – | – | not run | – | – | – |")
            details += [_renote(line, notes.get(t.name, {})) for line in kept]
            continue
        meta = (work / t.name / "run.json").read_text() if (work / t.name / "run.json").exists() else "{}"
        counts = Counter("killed" if s in ("killed", "timeout", "segfault") else s for s in st.values())
        note = _by_name(notes.get(t.name, {}), st)
        survivors = sorted(n for n, s in st.items() if s in ("survived", "suspicious"))
        equivalent = [n for n in survivors if note.get(n, "").startswith("equivalent")]
        untested = sorted(n for n, s in st.items() if s == "no tests")
        unchecked = sum(counts.get(k, 0) for k in ("not checked", "check was interrupted by user", "skipped"))
        live = len(st) - len(equivalent) - unchecked - len(untested)
        killed = counts.get("killed", 0)
        lines.append(_row(t, [str(x) for x in (len(st), killed, len(survivors) - len(equivalent), len(equivalent),
                                               len(untested), unchecked)], _short(meta), estimates.get(t.name, "")))
        if survivors or untested:
            details += ["", f"## {t.name}", ""]
        if untested:
            funcs = Counter(n.rsplit("__mutmut_", 1)[0] for n in untested)
            details.append("No tests (functions the selected tests never call): "
                           + ", ".join(f"`{f}` ({c})" for f, c in sorted(funcs.items())) + ".")
            details.append("")
        details += [f"- `{n}` ({st[n]}): {note.get(n, 'not yet examined')}" for n in survivors]
    text = "\n".join(lines + _sampled(work, notes)) + "\n\n" + NOTES_FILE.read_text() + "\n".join(details) + "\n"
    tmp = out.with_suffix(".md.tmp")
    tmp.write_text(text)
    os.replace(tmp, out)
    print(text)


def _row(t: Target, counts: list[str], last: str, estimate: str = "") -> str:
    """A row of the main table from its counts (mutants, killed, survived, equivalent, no tests,
    not checked): the full score only when nothing is *not checked*, else the partial ratio
    labelled as such, and the sampled estimate when there is one."""
    try:
        total, killed, survived, equivalent, untested, unchecked = (int(x) for x in counts)
    except ValueError:  # an earlier row without counts
        return f"| {t.name} | {', '.join(t.files)} | {' | '.join(['–'] * 8)} | {estimate or '–'} | {last} |"
    live = killed + survived
    ratio = f"{100 * killed / live:.0f} %" if live else "–"
    full, partial = (ratio, "–") if unchecked == 0 else ("– (partial run)", f"{ratio} of {live}")
    estimate = "–" if estimate in ("", "–") else estimate
    return (f"| {t.name} | {', '.join(t.files)} | {total} | {killed} | {survived} | {equivalent} | {untested} | "
            f"{unchecked} | {full} | {partial} | {estimate} | {last} |")


def _estimates(work: Path, notes: dict[str, dict[str, str]]) -> dict[str, str]:
    """``module -> "score [interval] (n of N)"`` of the module's last kept sample (:func:`_sampled`):
    its first pass when it has one (the unbiased estimate), else its score now."""
    out = {}
    for line in _sampled(work, notes):
        cells = [c.strip() for c in line.split("|")]
        if line.startswith("| ") and len(cells) > 2 and cells[1] in BY_NAME:
            first = cells[8].split(" (")[0]
            label = f"first pass, seed {cells[2].split('seed ')[1].split(',')[0].rstrip(')')}"
            out[cells[1]] = (f"{first} ({label})" if first != "–" and "not kept" not in cells[8]
                             else f"{cells[9]} ({cells[2].split(' (')[0]}, after tests)")
    return out


def _score(killed: int, survived: int) -> str:
    """``killed / (killed + survived)`` with its Wilson 95 % interval, in percent."""
    if not killed + survived:
        return "–"
    lo, hi = wilson(killed, killed + survived)
    return f"{100 * killed / (killed + survived):.0f} % [{100 * lo:.0f} %, {100 * hi:.0f} %]"


def _kinds(got: dict[str, str], note: dict[str, str]) -> Counter:
    """Counts of a sample's verdicts, survivors noted equivalent counted apart."""
    return Counter("killed" if v in ("killed", "timeout", "segfault") else
                   "equivalent" if v in ("survived", "suspicious") and note.get(n, "").startswith("equivalent")
                   else "survived" if v == "suspicious" else v for n, v in got.items())


def _sampled(work: Path, notes: dict[str, dict[str, str]]) -> list[str]:
    """The table of the modules checked on a uniform random sample (``--sample``): the sample's
    score and its Wilson 95 % interval, an estimate of the module's score, not the score; the
    *first* score is the sample's with the tests as they were when it was drawn (unbiased),
    the *now* score after the tests written for its survivors (biased upwards)."""
    rows = []
    for t in TARGETS:
        files = _sample_files(work / t.name)
        st = statuses(t, work) if files else None
        if not st:
            continue
        for f in files:
            s = json.loads(f.read_text())
            got = {n: st.get(n, "not checked") for n in s["names"]}
            note = _by_name(notes.get(t.name, {}), got)
            kind = _kinds(got, note)
            killed, survived = kind.get("killed", 0), kind.get("survived", 0)
            unchecked = sum(kind.get(k, 0) for k in UNDECIDED)
            if "first" in s:  # equivalent mutants are out of the first score too (the notes decide them)
                first = _kinds(s["first"], note)
                before = f"{_score(first.get('killed', 0), first.get('survived', 0))} ({len(s['first'])} decided)"
            elif "first_counts" in s:  # a sample drawn before first verdicts were kept: its report's counts
                before = f"{_score(s['first_counts']['killed'], s['first_counts']['survived'])} (counts noted)"
            else:
                before = "not kept (see the notes)"
            fresh = f", fresh: {s['excluded']} earlier-sampled left out" if s.get("excluded") else ""
            rows.append(f"| {t.name} | {s['size']} of {len(st)} (seed {s['seed']}{fresh}) | {killed} | {survived} | "
                        f"{kind.get('equivalent', 0)} | {kind.get('no tests', 0)} | {unchecked} | {before} | "
                        f"{_score(killed, survived)} |")
    if not rows:
        return []
    return ["", "**Sampled estimates** (`--sample SIZE --seed SEED`): a uniform random sample of a module's "
                "mutants (a fresh sample leaves out the mutants of the module's earlier samples; verdicts of earlier "
                "runs reused, the rest run); the score of the sample with its Wilson 95 % interval estimates the "
                "module's score. It is not the module's full score (the table above). *First pass*: the sample's "
                "score with the tests as they were when it was drawn, an unbiased estimate; *now*: after the tests "
                "written for its survivors, biased upwards (the tests were written looking at this sample).", "",
            "| module | sample | killed | survived | equivalent | no tests | not checked | first pass [95 %] "
            "| now [95 %] |",
            "|---|---|---|---|---|---|---|---|---|", *rows]


def _renote(line: str, note: dict[str, str]) -> str:
    """A survivor's line of an earlier report with its note as ``mutation_survivors.toml`` has it now."""
    m = re.match(r"- `([^`]+)` \(([^)]+)\): ", line)
    if m is None:
        return line
    now = _by_name(note, {m.group(1): m.group(2)}).get(m.group(1))
    return f"- `{m.group(1)}` ({m.group(2)}): {now}" if now else line


def _by_name(note: dict[str, str], st: dict[str, str]) -> dict[str, str]:
    """``note`` keyed by the mutants of ``st``: a kept run from before a function moved to
    another file of the module (``x_f__mutmut_3`` in ``a.py``, noted in ``b.py``) finds its
    note by the function's mutant name when that name is noted once."""
    tails = Counter(k.rsplit(".", 1)[-1] for k in note)
    by_tail = {k.rsplit(".", 1)[-1]: v for k, v in note.items() if tails[k.rsplit(".", 1)[-1]] == 1}
    return {n: note.get(n, by_tail.get(n.rsplit(".", 1)[-1], "")) for n in st if n in note
            or n.rsplit(".", 1)[-1] in by_tail}


def _short(meta: str) -> str:

    try:
        m = json.loads(meta)
    except ValueError:
        return "?"
    return f"{m.get('seconds', '?')} s, {m.get('finished', '?')}" + ("" if m.get("exit") in ("0", 0) else
                                                                     f" (exit {m.get('exit')})")


def _mutmut_version() -> str:
    try:
        from importlib.metadata import version

        return version("mutmut")
    except Exception:  # noqa: BLE001
        return "?"


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("modules", nargs="*", help=f"modules to run: {', '.join(BY_NAME)}")
    ap.add_argument("--mutants", nargs="*", default=[],
                    help="only these mutants (mutmut's names or patterns such as 'supcoord.problems.timing.*'); "
                         "with --sample: these as well as the sample")
    ap.add_argument("--list", action="store_true", help="list the modules and their tests")
    ap.add_argument("--report", action="store_true", help=f"write {RESULTS.relative_to(ROOT)} from the kept runs")
    ap.add_argument("--show", metavar="MODULE", help="print the diff of every surviving mutant of MODULE")
    ap.add_argument("--work", type=Path, default=WORK, help="where the runs are kept")
    ap.add_argument("--children", type=int, default=1, help="mutants run at once (default 1: the machine is shared)")
    ap.add_argument("--limit", type=float, default=1500, help="seconds per module (default 1500)")
    ap.add_argument("--out", type=Path, default=RESULTS)
    ap.add_argument("--no-report", action="store_true", help="run the modules without writing the report after")
    ap.add_argument("--sample", type=int, metavar="SIZE",
                    help="check a uniform random sample of SIZE of each module's mutants (estimate, see the report)")
    ap.add_argument("--seed", type=int, default=0, help="the sample's random seed (default 0)")
    args = ap.parse_args()
    unknown = [m for m in args.modules + ([args.show] if args.show else []) if m not in BY_NAME]
    if unknown:
        ap.error(f"unknown module {unknown[0]!r}: one of {', '.join(BY_NAME)}")
    if args.mutants and not args.modules:  # --mutants takes every name after it, a module too
        ap.error("--mutants needs a module before it, e.g. `timing --mutants NAME …`")
    if args.list:
        for t in TARGETS:
            print(f"{t.name:13} {', '.join(t.files)}\n{'':13} tests: {' '.join(t.tests)}")
        return 0
    if args.show:
        t = BY_NAME[args.show]
        st = statuses(t, args.work) or {}
        print(show(t, args.work, sorted(n for n, s in st.items() if s in ("survived", "suspicious"))))
        return 0
    for name in args.modules:
        if args.sample:
            r = sample(BY_NAME[name], args.work, args.children, args.limit, args.sample, args.seed, args.mutants)
        else:
            r = run(BY_NAME[name], args.work, args.children, args.limit, args.mutants)
        print(f"{name}: {r['seconds']:.0f} s, exit {r['exit']}", flush=True)
    if args.report or (args.modules and not args.no_report):
        report(args.work, args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
