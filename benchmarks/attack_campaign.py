"""The attack campaign of issue 34, rerun: hostile inputs and outputs that must lose nothing.

Command-line runs (through the console script, each in its own process with a time
limit) and library calls (in a child process, each call under an interval timer):

- *data loss*: outputs through hard and symbolic links to the results database or an
  input, over an input by another spelling, a SQLite file of another application or a
  corrupt one as the database, a full disk (``ulimit -f 1``, as ``RLIMIT_FSIZE`` on the
  child) during ``study export`` and ``solve --out``;
- *tracebacks*: ``layout.fibre`` of the wrong type, non-ASCII, 5,001-digit and duplicate
  ``offline`` keys, repeated JSON keys, an impossible file name;
- *library*: mutated problems (float target, out-of-range start, NaN buffers, ``priority =
  None``, a list ``start``, ``kinematics = None``) through ``solve``, ``validate_plan``,
  ``plan_from_moves`` and ``save_plan_strip``; malformed plans through ``validate_plan``;
  huge sizes; a plan of another problem; parameter names in library errors.

Each run is counted as clean or as a traceback (exit 1, or a raw exception from the
library), a hang (no answer within the time limit), data lost (a protected file's bytes
changed, or a partial output left) or a bad message (exit 2 with more than one line).
The memory-budget class (``--max-memory`` overruns) is measured by ``memory_budget.py`` and
not counted here.

    python benchmarks/attack_campaign.py          # writes benchmarks/results/attack_campaign.md
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import shutil
import sqlite3
import subprocess
import sys
import tempfile
import textwrap
import time
from dataclasses import dataclass, field
from pathlib import Path

HERE = Path(__file__).resolve().parent
EXAMPLES = HERE.parent / "docs" / "examples"
RESULTS = HERE / "results" / "attack_campaign.md"
CLI_SECONDS = 120
LIBRARY_SECONDS = 30

STUDY = 'name = "s"\ntime_limit = 60\n[[cases]]\nkind = "paper"\nmodel = "literal"\nsteps = 6\npositioners = [2, 3]\n'


@dataclass
class Outcome:
    kind: str  # "cli" or "library"
    attack: str
    verdict: str  # clean, traceback, hang, data lost, bad message
    detail: str = ""


@dataclass
class Case:
    attack: str
    argv: list[str]
    protected: list[str] = field(default_factory=list)  # files whose bytes must not change
    absent: list[str] = field(default_factory=list)  # outputs that must not exist afterwards
    file_limit: int | None = None  # RLIMIT_FSIZE of the child (bytes)
    links: list[tuple[str, str, str]] = field(default_factory=list)  # ("hard"/"symbolic", target, link name)


def _supcoord() -> list[str]:
    return [sys.executable, "-m", "supcoord.cli"]


def _run(argv: list[str], cwd: Path, file_limit: int | None = None, seconds: float = CLI_SECONDS):
    def limit():
        if file_limit is not None:
            import resource

            resource.setrlimit(resource.RLIMIT_FSIZE, (file_limit, file_limit))

    return subprocess.run(_supcoord() + argv, cwd=cwd, capture_output=True, text=True, timeout=seconds,
                          preexec_fn=limit)


def _setup(tmp: Path) -> None:
    (tmp / "s.toml").write_text(STUDY)
    proc = _run(["study", "run", "s.toml", "--workers", "0", "-q"], tmp)
    if proc.returncode != 0:
        raise SystemExit(f"setting up the study failed: {proc.stderr}")
    shutil.copy(EXAMPLES / "three_rotary.json", tmp / "p.json")
    shutil.copy(EXAMPLES / "hex19_rotary.json", tmp / "hex.json")
    _run(["solve", "p.json", "--out", "plan.json"], tmp)
    _run(["demo", "--out", "gens", "-q"], tmp)
    for name in ("G.gen", "S.gen"):
        shutil.copy(tmp / "gens" / name, tmp / name)
    con = sqlite3.connect(tmp / "user.sqlite")
    con.execute("CREATE TABLE cases (a, b)")
    con.execute("INSERT INTO cases VALUES (1, 2)")
    con.commit()
    con.close()
    shutil.copy(tmp / "s.sqlite", tmp / "corrupt.sqlite")
    data = bytearray((tmp / "corrupt.sqlite").read_bytes())
    start = 4096 if len(data) >= 8192 else len(data) // 2
    for i in range(start, min(len(data), start + 4096)):
        data[i] ^= 0xFF
    (tmp / "corrupt.sqlite").write_bytes(bytes(data))
    unfold = json.loads((EXAMPLES / "sdss_v_unfold.json").read_text())
    text = json.dumps(unfold)
    docs = {
        "fibre_list": {"layout": {"kind": "instrument", "name": "sdss-v-apo", "fibre": ["boss"]}, "start": "folded",
                       "target": "folded"},
        "fibre_object": {"layout": {"kind": "instrument", "name": "sdss-v-lco", "fibre": {"boss": 1}},
                         "start": "folded", "target": "folded"},
        "name_object": {"layout": {"kind": "instrument", "name": {"a": 1}}, "start": "folded", "target": "folded"},
    }
    for key, label in (("²", "sup2"), ("٣", "arabic3"), ("３", "fullwidth3"), ("9" * 5001, "digits5001"),
                       ("-0", "minus0")):
        docs[f"offline_{label}"] = {**unfold, "offline": {key: [0, 180]}}
    docs["offline_1_01"] = {**unfold, "offline": {"1": [0, 180], "01": [0, 180]}}
    for name, doc in docs.items():
        (tmp / f"{name}.json").write_text(json.dumps(doc))
    (tmp / "offline_repeated_key.json").write_text(text[:-1] + ', "offline": {"1": [0, 180], "1": [0, 180]}}')
    (tmp / "repeated_target.json").write_text(text[:-1] + ', "target": "folded"}')
    (tmp / "plan_repeated.json").write_text('{"status": "complete", "status": "infeasible", "configurations": []}')


def _cases() -> list[Case]:
    """The command-line attacks; each case's links are made just before it runs and removed after."""
    db = ["s.sqlite", "s.toml"]
    H, S = "hard", "symbolic"
    cases = [
        Case("export through a hard link to the database", ["study", "export", "s.toml", "--out", "h.csv"], db,
             links=[(H, "s.sqlite", "h.csv")]),
        Case("export through a symbolic link to the database", ["study", "export", "s.toml", "--out", "l.csv"], db,
             links=[(S, "s.sqlite", "l.csv")]),
        Case("export over the database by another spelling", ["study", "export", "s.toml", "--out", "./s.sqlite"], db),
        Case("export over the study file", ["study", "export", "s.toml", "--format", "csv", "--out", "s.toml"], db),
        Case("export through a hard link to the study file", ["study", "export", "s.toml", "--out", "h2.csv"], db,
             links=[(H, "s.toml", "h2.csv")]),
        Case("export parquet through a hard link to the database",
             ["study", "export", "s.sqlite", "--format", "parquet", "--out", "h.parquet"], db,
             links=[(H, "s.sqlite", "h.parquet")]),
        Case("plot: a figure name that is a hard link to the database", ["study", "plot", "s.sqlite", "--out", "figs"],
             db, links=[(H, "s.sqlite", "figs/time.png")]),
        Case("run with --db a SQLite file of another application",
             ["study", "run", "s.toml", "--db", "user.sqlite", "--workers", "0"], ["user.sqlite", "s.toml"]),
        Case("show a SQLite file of another application", ["study", "show", "user.sqlite"], ["user.sqlite"]),
        Case("export a SQLite file of another application", ["study", "export", "user.sqlite", "--out", "u.csv"],
             ["user.sqlite"], ["u.csv"]),
        Case("run with --db the study file", ["study", "run", "s.toml", "--db", "s.toml", "--workers", "0"], db),
        Case("run with --db a symbolic link to the database",
             ["study", "run", "s.toml", "--db", "l.sqlite", "--workers", "0"], db, links=[(S, "s.sqlite", "l.sqlite")]),
        Case("run with --db a hard link to the database",
             ["study", "run", "s.toml", "--db", "h.sqlite", "--workers", "0"], db, links=[(H, "s.sqlite", "h.sqlite")]),
        Case("show a corrupt database", ["study", "show", "corrupt.sqlite"], ["corrupt.sqlite"]),
        Case("export a corrupt database", ["study", "export", "corrupt.sqlite", "--out", "c.csv"], ["corrupt.sqlite"],
             ["c.csv"]),
        Case("run on a corrupt database", ["study", "run", "s.toml", "--db", "corrupt.sqlite", "--workers", "0"],
             ["corrupt.sqlite"]),
        Case("export with a full disk (ulimit -f 1)", ["study", "export", "s.sqlite", "--out", "full.csv"], db,
             ["full.csv"], file_limit=512),
        Case("solve --out with a full disk (ulimit -f 1)", ["solve", "hex.json", "--out", "full_plan.json"],
             ["hex.json"], ["full_plan.json"], file_limit=512),
        Case("solve --out over the problem by another spelling", ["solve", "p.json", "--out", "./p.json"], ["p.json"]),
        Case("solve --out through a hard link to the problem", ["solve", "p.json", "--out", "h.json"], ["p.json"],
             links=[(H, "p.json", "h.json")]),
        Case("solve --out through a symbolic link", ["solve", "p.json", "--out", "l.json"], ["p.json", "plan.json"],
             links=[(S, "plan.json", "l.json")]),
        Case("solve --figure through a hard link", ["solve", "p.json", "--figure", "h.png"], ["p.json", "plan.json"],
             links=[(H, "plan.json", "h.png")]),
        Case("solve --trajectories-csv through a hard link",
             ["solve", "p.json", "--speed", "30", "--trajectories-csv", "h3.csv"], ["plan.json"],
             links=[(H, "plan.json", "h3.csv")]),
        Case("check --figure through a hard link to the problem", ["check", "p.json", "plan.json", "--figure", "h4.png"],
             ["p.json", "plan.json"], links=[(H, "p.json", "h4.png")]),
        Case("supcon --export through a hard link to the plant", ["supcon", "--plant", "G.gen", "--spec", "S.gen", "--export", "h.gen"],
             ["G.gen", "S.gen"], links=[(H, "G.gen", "h.gen")]),
        Case("demo --out with G.gen a hard link to the problem", ["demo", "--out", "demo"], ["p.json"],
             links=[(H, "p.json", "demo/G.gen")]),
    ]
    for name in ("fibre_list", "fibre_object", "name_object", "offline_sup2", "offline_arabic3", "offline_fullwidth3",
                 "offline_digits5001", "offline_minus0", "offline_1_01", "offline_repeated_key", "repeated_target"):
        cases.append(Case(f"problem file {name}", ["solve", f"{name}.json", "--timeout", "60"], [f"{name}.json"]))
    cases.append(Case("plan file with a repeated key", ["check", "p.json", "plan_repeated.json"], ["p.json"]))
    cases.append(Case("problem file name of 5,000 characters", ["solve", "x" * 5000]))
    return cases


def _cli(tmp: Path) -> list[Outcome]:
    out = []
    for case in _cases():
        for how, target, name in case.links:
            (tmp / name).parent.mkdir(exist_ok=True)
            (os.link if how == "hard" else os.symlink)(tmp / target, tmp / name)
        before = {f: (tmp / f).read_bytes() for f in case.protected}
        try:
            proc = _run(case.argv, tmp, case.file_limit)
        except subprocess.TimeoutExpired:
            out.append(Outcome("cli", case.attack, "hang", f"no answer within {CLI_SECONDS} s"))
            continue
        finally:
            for _, _, name in case.links:
                (tmp / name).unlink()
        lines = proc.stderr.strip().splitlines()
        changed = [f for f in case.protected if (tmp / f).read_bytes() != before[f]]
        left = [f for f in case.absent if (tmp / f).exists()]
        partial = [p.name for p in tmp.rglob(".*") if p.is_file()]  # a temporary file left behind
        if proc.returncode == 1 or "Traceback" in proc.stderr:
            verdict, detail = "traceback", (lines or ["?"])[-1]
        elif changed or left or partial:
            verdict, detail = "data lost", f"changed {changed}, left {left + partial}"
        elif proc.returncode == 2 and len(lines) != 1:
            verdict, detail = "bad message", f"{len(lines)} lines"
        elif proc.returncode not in (0, 2, 3):
            verdict, detail = "traceback", f"exit {proc.returncode}"
        else:
            verdict = "clean"
            detail = f"exit {proc.returncode}: " + (lines[0].replace(str(tmp) + os.sep, "")[:150] if lines else "")
        out.append(Outcome("cli", case.attack, verdict, detail))
    return out


LIBRARY_CHILD = textwrap.dedent('''
    import copy, json, signal, sys, tempfile, warnings
    import numpy as np
    import supcoord
    from supcoord.errors import SupcoordError
    warnings.simplefilter("ignore")
    examples, seconds = sys.argv[1], float(sys.argv[2])
    problem = supcoord.load_problem(examples + "/three_rotary.json")
    plan = supcoord.solve(problem)
    other = supcoord.load_problem(examples + "/hex19_rotary.json")
    out = tempfile.mkdtemp()

    def mutated(field, make):
        p = copy.deepcopy(problem)
        setattr(p, field, make(p))
        return p

    def bad_plan(field, value):
        q = copy.deepcopy(plan)
        setattr(q, field, value)
        return q

    problems = {
        "target a float array": ("target", lambda p: p.target.astype(float) + 0.5),
        "start[0] = 99": ("start", lambda p: np.where(np.arange(p.n)[:, None] == 0, 99, p.start)),
        "NaN buffers": ("buffers", lambda p: np.full(p.n, np.nan)),
        "priority = None": ("priority", lambda p: None),
        "a list start": ("start", lambda p: p.start.tolist()),
        "kinematics = None": ("kinematics", lambda p: None),
        "target of another size": ("target", lambda p: np.zeros((1, 1), dtype=np.int64)),
        "bases with NaN": ("bases", lambda p: np.full_like(p.bases, np.nan)),
    }
    calls = {}
    for name, (field, make) in problems.items():
        calls[f"solve, {name}"] = lambda f=field, m=make: supcoord.solve(mutated(f, m))
        calls[f"validate_plan, {name}"] = lambda f=field, m=make: supcoord.validate_plan(mutated(f, m), plan)
        calls[f"plan_from_moves, {name}"] = lambda f=field, m=make: supcoord.plan_from_moves(mutated(f, m), [])
        calls[f"save_plan_strip, {name}"] = lambda f=field, m=make: supcoord.save_plan_strip(
            mutated(f, m), plan, out + "/s.png")
    plans = {
        "huge integers": ("configurations", [np.full((3, 1), 10**30, dtype=object)]),
        "text": ("configurations", ["abc"]), "None": ("configurations", None),
        "fractions": ("configurations", [np.full((3, 1), 1.5)]), "lattice 7": ("lattice", 7),
        "status 3": ("status", 3), "NaN angles": ("angles_deg", [np.full((3, 1), np.nan)]),
        "trajectories junk": ("trajectories", [{"theta": "x"}]), "events None": ("events", None),
    }
    for name, (field, value) in plans.items():
        calls[f"validate_plan, plan {name} (must not raise)"] = lambda f=field, v=value: (
            None if supcoord.validate_plan(problem, bad_plan(f, v)).valid is False else 1 / 0)
    calls.update({
        "plan_from_moves, junk moves": lambda: supcoord.plan_from_moves(problem, [("x", 1, 2), None, 5]),
        "plan_from_moves, moves not a list": lambda: supcoord.plan_from_moves(problem, 5),
        "random_instance(10**100, 8)": lambda: supcoord.random_instance(10**100, 8),
        "random_instance(3, 10**100)": lambda: supcoord.random_instance(3, 10**100),
        "paper_example(10**100)": lambda: supcoord.paper_example(10**100),
        "save_plan_strip, a plan of another problem": lambda: supcoord.save_plan_strip(
            problem, supcoord.solve(other), out + "/o.png"),
        "load_problem('x' * 5000)": lambda: supcoord.load_problem("x" * 5000),
        "load_problem('a\\\\0b')": lambda: supcoord.load_problem("a\\0b"),
        "Context(cache_size='')": lambda: supcoord.Context(cache_size=""),
        "solve_paper(route='bogus') names the parameter": lambda: _names_parameter(),
    })

    def _names_parameter():
        try:
            supcoord.solve_paper(3, 8, "literal", route="bogus")
        except SupcoordError as exc:
            if "--" in exc.one_line():
                raise RuntimeError("the library error names a command-line flag: " + exc.one_line())
            raise

    def hang(signum, frame):
        raise TimeoutError("hang")

    signal.signal(signal.SIGALRM, hang)
    for name, call in calls.items():
        signal.setitimer(signal.ITIMER_REAL, seconds)
        try:
            call()
            verdict, detail = "clean", "answered"
        except SupcoordError as exc:
            verdict, detail = "clean", type(exc).__name__ + ": " + exc.one_line()[:140]
        except TimeoutError:
            verdict, detail = "hang", "no answer within %g s" % seconds
        except Exception as exc:
            verdict, detail = "traceback", type(exc).__name__ + ": " + str(exc)[:140]
        finally:
            signal.setitimer(signal.ITIMER_REAL, 0)
        print(json.dumps([name, verdict, detail]), flush=True)
''')


def _library() -> list[Outcome]:
    proc = subprocess.run([sys.executable, "-c", LIBRARY_CHILD, str(EXAMPLES), str(LIBRARY_SECONDS)],
                          capture_output=True, text=True, timeout=3600)
    out = [Outcome("library", *json.loads(line)) for line in proc.stdout.splitlines() if line.startswith("[")]
    if proc.returncode != 0:
        out.append(Outcome("library", "the library child", "traceback", (proc.stderr.strip().splitlines() or ["?"])[-1]))
    return out


def _printable(text: str) -> str:
    """``text`` for a Markdown table cell: control characters (a NUL of a file name) escaped, no ``|``."""
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in text).replace("|", "/")


def _machine() -> str:
    from supcoord.study.machine import cpu_model

    return cpu_model()


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=str(RESULTS), help="the results file (Markdown)")
    args = parser.parse_args(argv)
    t0 = time.perf_counter()
    load0 = os.getloadavg()[0]
    started = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    with tempfile.TemporaryDirectory(prefix="attack-") as tmp:
        _setup(Path(tmp))
        outcomes = _cli(Path(tmp)) + _library()
    seconds = time.perf_counter() - t0
    load1 = os.getloadavg()[0]
    verdicts = ("clean", "traceback", "hang", "data lost", "bad message")
    counts = {v: sum(o.verdict == v for o in outcomes) for v in verdicts}
    kinds = {k: sum(o.kind == k for o in outcomes) for k in ("cli", "library")}
    lines = [
        "# Attack campaign (issue 34): hostile inputs and outputs",
        "",
        "Command: `python benchmarks/attack_campaign.py`  ",
        f"Date: {started}; {seconds:.0f} s wall-clock  ",
        f"Machine: {_machine()}; load average (1 min) {load0:.1f} at the start, {load1:.1f} at the end",
        "",
        f"{kinds['cli']} command-line runs (each in its own process, {CLI_SECONDS} s limit) and {kinds['library']} "
        f"library calls (each under a {LIBRARY_SECONDS} s interval timer):",
        "",
        "| verdict | runs |",
        "|---|---|",
        *[f"| {v} | {counts[v]} |" for v in verdicts],
        "| budget overruns | measured by `benchmarks/memory_budget.py` ([memory_budget.md](memory_budget.md)) |",
        "",
        "A *traceback* is exit 1 or a raw exception; *data lost*: a protected file (the database, an "
        "input) changed, or an output or temporary file was left where none may be; *bad message*: exit 2 "
        "with more than one line.",
        "",
        "| | attack | verdict | what happened |",
        "|---|---|---|---|",
        *[f"| {o.kind} | {o.attack} | {o.verdict} | {_printable(o.detail)} |" for o in outcomes],
        "",
    ]
    text = "\n".join(lines)
    Path(args.out).write_text(text, encoding="utf-8")
    print(text)
    return 0 if counts["clean"] == len(outcomes) else 1


if __name__ == "__main__":
    sys.exit(main())
