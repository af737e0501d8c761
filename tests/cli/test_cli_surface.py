"""The command line's surface, for every command registered in ``supcoord.cli.main``.

The contract (docs/cli.md, docs/formats.md):

- ``supcoord COMMAND --help`` exits 0 and shows an example;
- ``--json`` prints exactly one JSON object on stdout (progress and logs go to stderr),
  with the keys docs/cli.md and docs/formats.md promise;
- a user error exits 2 with exactly one line on stderr starting ``supcoord: error:``,
  and never a traceback — checked by hypothesis fuzzing of the files each command
  reads (.gen/.json generators for ``supcon`` and ``force``, PROBLEM.json for ``solve``
  and ``check``, PLAN.json for ``check``);
- a budget that runs out exits 3 with ``"status": "unknown"``.

Commands are run in-process through :func:`supcoord.cli.main.main`, so an exception
that escapes it (which the console script would print as a traceback, exit 1) fails
the test with the input that caused it; a few runs go through a real subprocess.
"""

from __future__ import annotations

import argparse
import contextlib
import copy
import io
import json
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from supcoord.cli.main import build_parser, main

DATA = Path(__file__).resolve().parents[2] / "src" / "supcoord" / "data" / "classic" / "small_factory"
#: examples per fuzz test; SUPCOORD_FUZZ_EXAMPLES=1000 for a longer hunt
FUZZ = settings(max_examples=int(os.environ.get("SUPCOORD_FUZZ_EXAMPLES", "60")), deadline=None,
                suppress_health_check=list(HealthCheck))


def registered_commands() -> dict[str, argparse.ArgumentParser]:
    for action in build_parser()._actions:
        if isinstance(action, argparse._SubParsersAction):
            return dict(action.choices)
    return {}


COMMANDS = registered_commands()
FILE_COMMANDS = ["supcon", "force", "solve", "check"]


def run(*argv: str) -> tuple[int, str, str]:
    """``(exit status, stdout, stderr)`` of ``supcoord ARGV`` run in-process."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main([str(a) for a in argv])
        except BaseException as exc:  # what the console script would show as a traceback
            raise AssertionError(f"supcoord {' '.join(map(str, argv))} raised {type(exc).__name__}: {exc}\n"
                                 f"stderr so far: {err.getvalue()}") from exc
    return code, out.getvalue(), err.getvalue()


def one_json_object(out: str) -> dict:
    """The single JSON object that is all of ``out`` (fails otherwise)."""
    text = out.strip()
    assert text, "nothing on stdout"
    obj, end = json.JSONDecoder().raw_decode(text)
    assert text[end:].strip() == "", f"more than one JSON value on stdout: {text[end:end + 80]!r}"
    assert isinstance(obj, dict), f"stdout holds a JSON {type(obj).__name__}, not an object"
    return obj


#: a line of the --verbose progress log: ``[m:ss] stage | iteration k | N nodes ...``
#: a fixpoint's line (``[0:03] supcon | iteration 1 | 14,819 nodes …``) or a phase's
#: (``[0:00] load | file problem.json``, ``[0:12] figure | 3/40 | file plan.gif``)
PROGRESS_LINE = re.compile(r"\[\d+:\d\d(:\d\d)?\] \w+( #\d+)? \| ((iteration|layer) [\d,]+ \| [\d,]+ nodes"
                           r"|([\d,]+/[\d,]+ \| )?[a-z_]+ \S)")


def one_error_line(code: int, out: str, err: str, what: str = "") -> str:
    assert "Traceback" not in err and "Traceback" not in out, f"traceback for {what}:\n{err}"
    assert code == 2, f"exit status {code} (expected 2) for {what}; stderr: {err!r}"
    lines = [ln for ln in err.strip().splitlines() if not PROGRESS_LINE.match(ln)]  # --verbose's log may precede
    assert len(lines) == 1, f"{len(lines)} stderr lines (expected 1) for {what}: {err!r}"
    assert lines[0].startswith("supcoord: error: "), f"stderr line lacks 'supcoord: error:' for {what}: {lines[0]!r}"
    return lines[0]


def need(command: str) -> None:
    """Fail (not skip) when a command of the contract is not registered."""
    assert command in COMMANDS, f"'supcoord {command}' is not registered in supcoord.cli.main"


# -- fixtures: small valid inputs for every command ------------------------------------

GEN_SAMPLE = """<Generator> "V"
<Alphabet> "a" +C+ "b" +C+ "u" </Alphabet>
<States> "s0" "s1" "s2" "s3" </States>
<TransRel>
"s0" "a" "s1"
"s1" "u" "s2"
"s1" "b" "s3"
"s2" "b" "s3"
</TransRel>
<InitStates> "s0" </InitStates>
<MarkedStates> "s3" </MarkedStates>
</Generator>
"""

JSON_SAMPLE = json.dumps({
    "name": "V", "states": 3, "init": 0, "marked": [2],
    "events": [{"name": "71", "controllable": True}, {"name": "10", "controllable": False}],
    "transitions": [[0, "71", 1], [1, "10", 2]],
})

#: two rotary positioners far apart, positioner 0 turns one step
PROBLEM = {
    "layout": {"kind": "points", "xy": [[0.0, 0.0], [22.4, 0.0]]},
    "kinematics": {"kind": "rotary", "arm": 15.0, "steps": 12},
    "collision": {"buffer": 2.0},
    "start": [3, 9],
    "target": [4, 9],
    "priority": [1, 2],
}
PLAN = {"status": "complete", "configurations": [[3, 9], [4, 9]], "makespan": 1, "lower_bound": 1,
        "events": ["v0"], "reason": "", "stats": {}}


def write(tmp: Path, name: str, content) -> str:
    path = tmp / name
    if isinstance(content, bytes):
        path.write_bytes(content)
    else:
        path.write_text(content if isinstance(content, str) else json.dumps(content), encoding="utf-8")
    return str(path)


def invocation(command: str, tmp: Path) -> list[str]:
    """A valid ``--json`` invocation of ``command`` on small inputs."""
    if command == "demo":
        return ["demo", "--json", "--no-files"]
    if command == "paper":
        return ["paper", "--positioners", "3", "--steps", "6", "--json"]
    if command == "supcon":
        return ["supcon", "--plant", DATA / "MACH1.gen", DATA / "MACH2.gen", "--spec", DATA / "BUF.gen",
                DATA / "BR.gen", "--export", tmp / "V.gen", "--json"]
    if command == "force":
        return ["force", write(tmp, "V.gen", GEN_SAMPLE), "--json"]
    if command == "solve":
        return ["solve", write(tmp, "problem.json", PROBLEM), "--out", tmp / "plan.json", "--json"]
    if command == "check":
        return ["check", write(tmp, "problem.json", PROBLEM), write(tmp, "plan.json", PLAN), "--json"]
    if command == "conflicts":
        return ["conflicts", write(tmp, "problem.json", PROBLEM), "--out", tmp / "pairs.csv", "--json"]
    if command == "study":  # how far a study is (running one is tests/study/test_study_run.py's)
        return ["study", "show", write(tmp, "s.toml", STUDY), "--json"]
    raise AssertionError(f"tests/cli/test_cli_surface.py has no valid invocation of the new command "
                         f"'supcoord {command}': add one to invocation()")


STUDY = '[[cases]]\nkind = "paper"\nsteps = 6\npositioners = [2, 3]\n'

#: the keys docs/formats.md promises in each command's JSON
KEYS = {
    "demo": {"supervisor", "ccc", "witness", "literal"},
    "paper": {"positioners", "steps", "model", "supervisor_states", "bdd_nodes", "ccc", "witness_length", "seconds"},
    "supcon": {"status", "states", "transitions", "marked", "bdd_nodes", "seconds"},
    "force": {"status", "forcible", "witness", "rank", "layers"},
    "solve": {"status", "configurations", "makespan", "lower_bound", "events", "reason", "stats"},
    "check": {"valid", "collisions", "at_target", "problems"},
    "conflicts": {"conflicts", "searched", "positioners"},
    "study": {"study", "database", "rows", "statuses", "series", "total", "done", "left"},
}


# -- --help ---------------------------------------------------------------------------


def test_the_contract_commands_are_registered():
    assert {"demo", "paper", "force", "check"} <= set(COMMANDS), sorted(COMMANDS)


def test_every_command_help_shows_an_example():
    failing, lacking = [], []
    for name in COMMANDS:
        code, out, err = run(name, "--help")
        if code != 0:
            failing.append(f"{name} (exit {code}: {err.strip()[:120]})")
        elif "example" not in out.lower():
            lacking.append(name)
    assert not failing, f"'supcoord COMMAND --help' failed for: {', '.join(failing)}"
    assert not lacking, f"'supcoord COMMAND --help' shows no example for: {', '.join(lacking)}"


def test_top_level_help_lists_every_command():
    code, out, _ = run("--help")
    assert code == 0
    missing = [name for name in COMMANDS if name not in out]
    assert not missing, f"'supcoord --help' does not list: {missing}"


def test_every_command_offers_json_quiet_verbose():
    lacking = {}
    for name, parser in COMMANDS.items():
        options = {s for a in parser._actions for s in a.option_strings}
        miss = [o for o in ("--json", "--quiet", "--verbose") if o not in options]
        if miss:
            lacking[name] = miss
    assert not lacking, f"commands lacking common options: {lacking}"


@pytest.mark.parametrize("command", ["paper", "supcon", "force", "solve"])
def test_long_running_commands_offer_budgets(command):
    need(command)
    options = {s for a in COMMANDS[command]._actions for s in a.option_strings}
    assert {"--max-nodes", "--timeout"} <= options, f"'supcoord {command}' lacks --max-nodes/--timeout"


def test_no_command_is_a_usage_error():
    code, out, err = run()
    assert code == 2 and "usage" in err.lower()


# -- --json: exactly one JSON object on stdout ----------------------------------------


@pytest.mark.parametrize("command", sorted(set(COMMANDS) | {"supcon", "solve"}))
def test_json_is_exactly_one_object(command, tmp_path):
    need(command)
    argv = invocation(command, tmp_path)
    code, out, err = run(*argv)
    assert code == 0, f"supcoord {' '.join(map(str, argv))} exited {code}: {err}"
    obj = one_json_object(out)
    missing = KEYS.get(command, set()) - set(obj)
    assert not missing, f"'supcoord {command} --json' lacks keys {sorted(missing)}"


def fixpoint_invocation(command: str, tmp: Path) -> list[str]:
    """A valid invocation that surely runs a symbolic fixpoint (``solve``'s local route
    may answer a small problem without one, so ``solve`` takes the monolithic route)."""
    argv = invocation(command, tmp)
    if command == "paper":
        argv += ["--route", "monolithic"]
    if command == "solve":
        argv += ["--route", "monolithic"]
    return argv


@pytest.mark.parametrize("command", ["paper", "supcon", "force", "solve"])
def test_verbose_progress_goes_to_stderr_not_stdout(command, tmp_path):
    need(command)
    code, out, err = run(*fixpoint_invocation(command, tmp_path), "--verbose")
    assert code == 0
    one_json_object(out)
    lines = err.strip().splitlines()
    assert lines, f"'supcoord {command} --verbose' reports no progress on stderr"
    # the log's format: [m:ss] stage | iteration k | N nodes ...
    assert all(PROGRESS_LINE.match(ln) for ln in lines), lines


@pytest.mark.parametrize("command", ["paper", "supcon", "force", "solve"])
def test_quiet_and_plain_runs_write_nothing_on_stderr(command, tmp_path):
    """Without a terminal and without --verbose there is no progress; --quiet too."""
    need(command)
    for extra in ([], ["--quiet"]):
        code, out, err = run(*fixpoint_invocation(command, tmp_path), *extra)
        assert code == 0 and err == "", f"supcoord {command} {extra}: stderr {err!r}"


def test_text_report_without_json(tmp_path):
    code, out, _ = run(*[a for a in invocation("force", tmp_path) if a != "--json"])
    assert code == 0 and "FORCIBLE" in out and not out.lstrip().startswith("{")


def test_solve_then_check(tmp_path):
    need("solve")
    code, out, err = run(*invocation("solve", tmp_path))
    assert code == 0, err
    plan = one_json_object(out)
    assert plan["status"] == "complete"
    code, out, err = run("check", tmp_path / "problem.json", tmp_path / "plan.json", "--json")
    assert code == 0 and one_json_object(out)["valid"], out


# -- budgets: exit 3 with status unknown ------------------------------------------------


@pytest.mark.parametrize("budget", [["--max-nodes", "1"], ["--timeout", "1e-9"]], ids=["max-nodes", "timeout"])
@pytest.mark.parametrize("command", ["paper", "supcon", "force", "solve"])
def test_budget_exits_3_with_partial_statistics(command, budget, tmp_path):
    need(command)
    code, out, err = run(*fixpoint_invocation(command, tmp_path), *budget)
    assert code == 3, f"'supcoord {command} {' '.join(budget)}' exited {code}: {err}"
    obj = one_json_object(out)
    assert obj["status"] == "unknown" and obj["command"] == command, obj
    stats = obj["stats"]
    assert {"stage", "bdd_nodes", "seconds", "iteration"} <= set(stats), stats
    assert stats["bdd_nodes"] > 0 and stats["seconds"] >= 0
    assert ("node budget" if budget[0] == "--max-nodes" else "time budget") in obj["reason"]
    # one line on stderr, saying what stopped and what was learned
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("supcoord: stopped: ") and "so far:" in lines[0], err


@pytest.mark.parametrize("command", ["paper", "supcon"])
def test_budget_without_json_still_exits_3_and_prints_nothing_on_stdout(command, tmp_path):
    argv = [a for a in fixpoint_invocation(command, tmp_path) if a != "--json"]
    code, out, err = run(*argv, "--max-nodes", "1", "--quiet")
    assert code == 3 and out == "" and err.startswith("supcoord: stopped: node budget exceeded"), (code, out, err)


def test_default_node_budget_comes_from_available_memory(tmp_path):
    from supcoord.cli import common

    mem = common.available_memory()
    assert mem is not None and mem > 0, "/proc/meminfo has no MemAvailable"
    expected = int(mem * common.MEMORY_SHARE / common.BYTES_PER_NODE)
    budget = common.budget_from_args(argparse.Namespace(max_nodes=None, timeout=None))
    assert abs(budget.max_nodes - expected) <= expected // 10  # MemAvailable moves a little meanwhile
    assert common.budget_from_args(argparse.Namespace(max_nodes=5, timeout=None)).max_nodes == 5


def test_the_default_node_budget_is_named_when_it_stops_a_run(tmp_path, monkeypatch):
    from supcoord.cli import common

    monkeypatch.setattr(common, "default_max_nodes", lambda: 1)
    code, out, err = run(*fixpoint_invocation("supcon", tmp_path))
    assert code == 3 and "default node budget" in one_json_object(out)["reason"] and "--max-nodes" in err


def test_cudd_out_of_memory_is_exit_3_not_a_traceback(tmp_path, monkeypatch):
    """What dd raises when CUDD's hard memory limit is hit (measured: ValueError from a
    constructor, RuntimeError from an operator) ends the run like a budget."""
    from supcoord.cli import cmd_supcon

    for exc in (RuntimeError("CUDD appears to have run out of memory.\nCurrent settings ..."),
                ValueError("`DdNode *node` is `NULL` pointer."), MemoryError()):
        def boom(args, console, exc=exc):
            raise exc
        monkeypatch.setattr(cmd_supcon, "run", boom)
        code, out, err = run(*invocation("supcon", tmp_path))
        assert code == 3 and one_json_object(out)["status"] == "unknown", (exc, code, err)
        assert "out of memory" in err and "Traceback" not in err


def test_the_timeout_watchdog_stops_code_that_never_checks_the_budget(tmp_path, monkeypatch):
    """--timeout also ends a long stretch without fixpoint iterations (model building,
    counting, export): the watchdog fires WATCHDOG_GRACE seconds after the timeout."""
    import time

    from supcoord.cli import cmd_supcon
    from supcoord.cli import main as main_module

    def slow(args, console):
        console.progress("build", {"nodes": 7, "iteration": 3})
        time.sleep(30)

    monkeypatch.setattr(cmd_supcon, "run", slow)
    monkeypatch.setattr(main_module, "WATCHDOG_GRACE", 0.2)
    code, out, err = run(*invocation("supcon", tmp_path), "--timeout", "0.1")  # (un-interrupted: a bug, exit 1)
    obj = one_json_object(out)
    assert code == 3 and obj["status"] == "unknown", (code, err)
    assert obj["stats"]["stage"] == "build" and obj["stats"]["bdd_nodes"] == 7 and obj["stats"]["watchdog"] is True
    import threading
    assert not any(t.name == "supcoord-watchdog" for t in threading.enumerate()), "the watchdog outlived the command"


def test_other_exceptions_are_bugs_not_user_errors(tmp_path, monkeypatch):
    from supcoord.cli import cmd_supcon

    monkeypatch.setattr(cmd_supcon, "run", lambda args, console: 1 / 0)
    with pytest.raises(AssertionError, match="ZeroDivisionError"):
        run(*invocation("supcon", tmp_path))


def test_a_broken_pipe_is_not_a_traceback(tmp_path):
    """``supcoord … --json | head -c 1``: the reader leaves before the output is written."""
    argv = [sys.executable, "-m", "supcoord.cli", *map(str, invocation("paper", tmp_path))]
    proc = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    proc.stdout.close()  # nobody reads
    err = proc.stderr.read().decode()
    proc.wait(timeout=120)
    assert "Traceback" not in err and proc.returncode == 141, (proc.returncode, err)


# -- progress on a terminal ---------------------------------------------------------------


def run_on_a_terminal(argv: list[str]) -> tuple[int, str, bytes]:
    """Run the console script with stderr on a fresh pseudo-terminal (whose size is
    0 × 0, as under ``script`` or some CI runners): ``(status, stdout, terminal bytes)``."""
    import pty

    controller, terminal = pty.openpty()
    proc = subprocess.Popen([sys.executable, "-m", "supcoord.cli", *map(str, argv)], stdout=subprocess.PIPE,
                            stderr=terminal, stdin=subprocess.DEVNULL)
    os.close(terminal)
    seen = b""
    while True:
        try:
            chunk = os.read(controller, 4096)
        except OSError:  # the process closed the terminal
            break
        if not chunk:
            break
        seen += chunk
    out = proc.stdout.read().decode()
    proc.wait(timeout=120)
    os.close(controller)
    return proc.returncode, out, seen


def test_a_terminal_gets_a_live_status_line_that_is_erased(tmp_path):
    code, out, seen = run_on_a_terminal(fixpoint_invocation("paper", tmp_path))
    assert code == 0
    one_json_object(out)
    text = seen.decode()
    assert re.search(r"reachable \| iteration \d+ \| [\d,]+ nodes .*\| \d+:\d\d", text), text
    assert "force | layer" in text, text
    assert text.rstrip(" ").endswith("\r") and "\n" not in text.replace("\r\n", ""), repr(text[-200:])


def test_a_terminal_gets_nothing_with_quiet(tmp_path):
    code, out, seen = run_on_a_terminal([*fixpoint_invocation("paper", tmp_path), "--quiet"])
    assert code == 0 and seen == b"", seen
    one_json_object(out)


# -- user errors: exit 2, one line ---------------------------------------------------


@pytest.mark.parametrize("command", FILE_COMMANDS)
def test_missing_file_is_one_line(command, tmp_path):
    need(command)
    nope = str(tmp_path / "nope.gen")
    argv = {
        "supcon": ["supcon", "--plant", nope, "--spec", DATA / "BUF.gen"],
        "force": ["force", nope],
        "solve": ["solve", tmp_path / "nope.json"],
        "check": ["check", tmp_path / "nope.json", tmp_path / "nope.json"],
    }[command]
    line = one_error_line(*run(*argv, "--json"), what=command)
    assert "nope" in line, f"the error line does not name the file: {line}"


@pytest.mark.parametrize("command", ["paper", "supcon", "force", "solve"])
def test_bad_budget_values_are_one_line(command, tmp_path):
    need(command)
    one_error_line(*run(*invocation(command, tmp_path), "--max-nodes", "0"), what=f"{command} --max-nodes 0")
    one_error_line(*run(*invocation(command, tmp_path), "--timeout", "-1"), what=f"{command} --timeout -1")


@pytest.mark.parametrize("argv", [
    ["paper", "--positioners", "0", "--steps", "12"],
    ["paper", "--positioners", "3", "--steps", "1"],
    ["force", "GEN", "--target", "no-such-state"],
])
def test_bad_values_are_one_line(argv, tmp_path):
    gen = write(tmp_path, "V.gen", GEN_SAMPLE)
    argv = [gen if a == "GEN" else a for a in argv]
    line = one_error_line(*run(*argv), what=" ".join(argv))
    assert any(tok in line for tok in ("--positioners", "--steps", "--target")), line


@pytest.mark.parametrize("argv, names", [
    (["force", "GEN", "--semantics", "sideways"], ["--semantics", "sideways", "supcoord force --help"]),
    (["paper", "--positioners", "x", "--steps", "4"], ["--positioners", "'x'"]),
    (["supcon", "--plant", "GEN", "--max-nodes", "1.5"], ["--max-nodes", "'1.5'"]),
    (["frobnicate"], ["frobnicate", "supcoord --help"]),
    (["force"], ["V.gen"]),
    (["force", "DIR"], ["is a directory"]),
    (["supcon", "--plant", "GEN", "--export", "DIR/missing/V.gen"], ["--export", "missing", "does not exist"]),
    (["supcon", "--plant", "GEN", "--timeout", "inf"], ["--timeout", "inf"]),
])
def test_usage_and_file_errors_are_one_line(argv, names, tmp_path):
    gen = write(tmp_path, "V.gen", GEN_SAMPLE)
    argv = [a.replace("GEN", gen).replace("DIR", str(tmp_path)) for a in argv]
    line = one_error_line(*run(*argv, "--json"), what=" ".join(argv))
    assert all(n in line for n in names), line
    assert "usage:" not in line


def test_console_script_prints_no_traceback(tmp_path):
    """The real process: a malformed file gives exit 2 and one line, no traceback."""
    bad = write(tmp_path, "bad.gen", "<Generator> \"x\" <Alphabet> \"a\" +C+")
    proc = subprocess.run([sys.executable, "-m", "supcoord.cli", "force", bad, "--json"], capture_output=True,
                          text=True, timeout=120)
    one_error_line(proc.returncode, proc.stdout, proc.stderr, what="python -m supcoord.cli force bad.gen")
    assert "bad.gen" in proc.stderr


# -- fuzzing the files every command reads ---------------------------------------------

TOKENS = "<>/\"'+=%#&;! \n\tabcsuxyzCT0123456789[]{},:.-" + "AlphabetStatesTransRelInitMarkedGenerator"


@st.composite
def mutations(draw, text: str) -> str:
    """``text`` with a few random deletions, insertions, replacements, truncations."""
    for _ in range(draw(st.integers(1, 5))):
        i = draw(st.integers(0, len(text)))
        op = draw(st.sampled_from(["delete", "insert", "replace", "truncate", "duplicate"]))
        chunk = draw(st.text(alphabet=TOKENS, min_size=1, max_size=8))
        if op == "delete":
            text = text[:i] + text[i + len(chunk):]
        elif op == "insert":
            text = text[:i] + chunk + text[i:]
        elif op == "replace":
            text = text[:i] + chunk + text[i + len(chunk):]
        elif op == "truncate":
            text = text[:i]
        else:
            j = draw(st.integers(0, len(text)))
            text = text[:i] + text[min(i, j):max(i, j)] + text[i:]
    return text


#: contents that are malformed whatever the command: garbage, non-UTF-8, cut-off files
broken_gen = st.one_of(
    st.just(""),
    st.binary(min_size=1, max_size=40).map(lambda b: b"\xff\xfe" + b),
    st.integers(1, GEN_SAMPLE.index("</TransRel>")).map(lambda i: GEN_SAMPLE[:i]),
    st.text(alphabet="{}[]:,\"'abc 0123456789", max_size=30).map(lambda t: "garbage " + t),
)
broken_json = st.one_of(
    st.just(""),
    st.binary(min_size=1, max_size=40).map(lambda b: b"\xff\xfe" + b),
    st.integers(1, len(JSON_SAMPLE) - 1).map(lambda i: JSON_SAMPLE[:i]),
    st.sampled_from(["[]", "null", "42", '"text"', "[1, 2]", "{}", '{"states": "many"}']),
)

json_values = st.recursive(
    st.none() | st.booleans() | st.integers(-10**12, 10**12) | st.floats(allow_nan=False) | st.text(max_size=5),
    lambda children: st.lists(children, max_size=3) | st.dictionaries(st.text(max_size=5), children, max_size=3),
    max_leaves=6,
)
small_values = st.sampled_from([0, 1, -1, 2, 3, 12, 0.5, -0.0, 1e300, True, None, "x", "", [], {}, [0], [1, 2, 3],
                                [[0, 0]], "hex", "points", "rotary", "alpha-beta"])


def _paths(node, prefix=()):
    yield prefix
    if isinstance(node, dict):
        for k, v in node.items():
            yield from _paths(v, prefix + (k,))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield from _paths(v, prefix + (i,))


@st.composite
def mutated_json(draw, base: dict) -> dict:
    """``base`` with one to three fields replaced, deleted or extended."""
    data = copy.deepcopy(base)
    for _ in range(draw(st.integers(1, 3))):
        paths = [p for p in _paths(data) if p]
        if not paths:
            break
        path = draw(st.sampled_from(paths))
        *head, last = path
        node = data
        for key in head:
            node = node[key]
        action = draw(st.sampled_from(["replace", "small", "small", "delete", "append"]))
        if action == "delete":
            del node[last]
        elif action == "append" and isinstance(node[last], list):
            node[last].append(copy.deepcopy(draw(small_values)))
        elif action == "replace":
            node[last] = draw(json_values)
        else:
            node[last] = copy.deepcopy(draw(small_values))
    return data


def check_answer_or_user_error(command: str, argv: list, what: str, *, budgets_ok: bool = False) -> None:
    """Exit 0 with one JSON object, or exit 2 with one error line (3 if a budget ran out)."""
    code, out, err = run(*argv)
    assert "Traceback" not in err, f"traceback for {what}"
    if code == 0:
        one_json_object(out)
    elif code == 3 and budgets_ok:
        assert one_json_object(out)["status"] == "unknown"
    else:
        one_error_line(code, out, err, what)


def _gen_file(tmp: Path, content, suffix: str) -> str:
    return write(tmp, f"fuzz{suffix}", content)


@FUZZ
@given(content=st.one_of(mutations(GEN_SAMPLE), broken_gen))
def test_fuzz_force_gen(tmp_path_factory, content):
    need("force")
    path = _gen_file(tmp_path_factory.mktemp("force"), content, ".gen")
    check_answer_or_user_error("force", ["force", path, "--json"], f"force on .gen content {content!r}")


@FUZZ
@given(content=broken_gen)
def test_fuzz_force_broken_gen_exits_2(tmp_path_factory, content):
    need("force")
    path = _gen_file(tmp_path_factory.mktemp("force"), content, ".gen")
    line = one_error_line(*run("force", path, "--json"), what=f"force on .gen content {content!r}")
    assert "fuzz.gen" in line, f"the error does not name the file: {line}"


@FUZZ
@given(content=st.one_of(mutations(JSON_SAMPLE), broken_json,
                         mutated_json(json.loads(JSON_SAMPLE)).map(json.dumps)))
def test_fuzz_force_json_generator(tmp_path_factory, content):
    need("force")
    path = _gen_file(tmp_path_factory.mktemp("force"), content, ".json")
    check_answer_or_user_error("force", ["force", path, "--json"], f"force on .json content {content!r}")


@FUZZ
@given(plant=st.one_of(mutations(GEN_SAMPLE), broken_gen), spec=st.one_of(st.none(), mutations(GEN_SAMPLE)))
def test_fuzz_supcon_gen(tmp_path_factory, plant, spec):
    need("supcon")
    tmp = tmp_path_factory.mktemp("supcon")
    p = write(tmp, "plant.gen", plant)
    s = write(tmp, "spec.gen", spec if spec is not None else GEN_SAMPLE)
    check_answer_or_user_error("supcon", ["supcon", "--plant", p, "--spec", s, "--json"],
                               f"supcon on plant {plant!r} spec {spec!r}")


@FUZZ
@given(content=broken_gen)
def test_fuzz_supcon_broken_gen_exits_2(tmp_path_factory, content):
    need("supcon")
    tmp = tmp_path_factory.mktemp("supcon")
    path = write(tmp, "fuzz.gen", content)
    line = one_error_line(*run("supcon", "--plant", path, "--spec", DATA / "BUF.gen", "--json"),
                          what=f"supcon on plant {content!r}")
    assert "fuzz.gen" in line, f"the error does not name the file: {line}"


@FUZZ
@given(problem=st.one_of(mutated_json(PROBLEM).map(json.dumps), broken_json),
       plan=st.one_of(st.just(PLAN), mutated_json(PLAN)))
def test_fuzz_check_files(tmp_path_factory, problem, plan):
    need("check")
    tmp = tmp_path_factory.mktemp("check")
    argv = ["check", write(tmp, "problem.json", problem), write(tmp, "plan.json", json.dumps(plan)), "--json"]
    check_answer_or_user_error("check", argv, f"check on problem {problem!r} plan {plan!r}")


@FUZZ
@given(problem=broken_json)
def test_fuzz_check_broken_problem_exits_2(tmp_path_factory, problem):
    need("check")
    tmp = tmp_path_factory.mktemp("check")
    line = one_error_line(*run("check", write(tmp, "problem.json", problem), write(tmp, "plan.json", PLAN), "--json"),
                          what=f"check on problem {problem!r}")
    assert "problem.json" in line, f"the error does not name the file: {line}"


@settings(max_examples=30, deadline=None, suppress_health_check=list(HealthCheck))
@given(problem=st.one_of(mutated_json(PROBLEM).map(json.dumps), broken_json))
def test_fuzz_solve_problem(tmp_path_factory, problem):
    need("solve")
    tmp = tmp_path_factory.mktemp("solve")
    argv = ["solve", write(tmp, "problem.json", problem), "--json", "--timeout", "20"]
    check_answer_or_user_error("solve", argv, f"solve on problem {problem!r}", budgets_ok=True)


# -- fuzzing the command line itself ---------------------------------------------------

#: option values a user might type by mistake (or on purpose)
ARG_VALUES = ["-1", "0", "1", "2", "3", "x", "nan", "inf", "-0.5", "", "1e3", "marked", "preemptive", "standard",
              "literal", "coupled", "modular", "monolithic", "saturation", "bfs", "rcm", "hex", "autoref", "s3"]
INT_VALUES = ["-1", "0", "1", "2", "3", "x", "1.5", ""]
FLOAT_VALUES = ["-1", "0", "0.5", "1e-9", "nan", "inf", "x", ""]
#: options that write files: kept at their valid values (inside tmp), never fuzzed
WRITERS = {"--out", "--export", "--figure"}


@st.composite
def fuzzed_argv(draw, command: str, tmp: Path) -> list[str]:
    """A valid invocation with one to three options or operands replaced or added."""
    argv = [str(a) for a in invocation(command, tmp)]
    options = [a for a in COMMANDS[command]._actions
               if a.option_strings and not set(a.option_strings) & (WRITERS | {"-h", "--help", "--json"})]
    files = [str(tmp / "nope.gen"), str(tmp), write(tmp, "empty.json", ""), write(tmp, "sample.gen", GEN_SAMPLE),
             write(tmp, "sample.json", JSON_SAMPLE), write(tmp, "problem.json", PROBLEM)]
    for _ in range(draw(st.integers(1, 3))):
        what = draw(st.sampled_from(["option", "option", "operand"]))
        if what == "operand":
            candidates = [i for i, a in enumerate(argv) if i > 0 and (a.endswith((".gen", ".json")))]
            if candidates:
                argv[draw(st.sampled_from(candidates))] = draw(st.sampled_from(files))
            continue
        action = draw(st.sampled_from(options))
        flag = draw(st.sampled_from(action.option_strings))
        if action.nargs == 0:
            argv.append(flag)
        elif action.choices:
            argv += [flag, draw(st.sampled_from([*action.choices, "bogus", ""]))]
        elif action.type is int:
            argv += [flag, draw(st.sampled_from(INT_VALUES))]
        elif action.type is float:
            argv += [flag, draw(st.sampled_from(FLOAT_VALUES))]
        else:
            argv += [flag, draw(st.sampled_from(ARG_VALUES))]
    if command == "demo" and "--no-files" not in argv:
        argv += ["--out", str(tmp / "demo")]
    if command in ("solve", "supcon", "paper", "force"):
        argv += ["--timeout", "30"]  # the last --timeout wins: a fuzzed one may not hang the suite
    return argv


def test_negative_seed_is_a_user_error():
    """Found by test_fuzz_command_lines (numpy's ValueError, exit 1, until d50e359)."""
    line = one_error_line(*run("paper", "--positioners", "3", "--steps", "6", "--seed", "-1", "--json"),
                          what="paper --seed -1")
    assert "--seed" in line, line


@pytest.mark.parametrize("command", [pytest.param(c, marks=pytest.mark.slow) if c == "demo" else c
                                     for c in sorted(COMMANDS)])  # demo solves and writes figures: slow
def test_fuzz_command_lines(command, tmp_path_factory):
    """Any mix of options and values: an answer (0), a user error (2, one line) or a
    budget (3) — never a traceback, never two JSON objects."""

    @settings(max_examples=int(os.environ.get("SUPCOORD_FUZZ_EXAMPLES", "20")), deadline=None,
              suppress_health_check=list(HealthCheck))
    @given(data=st.data())
    def fuzz(data):
        tmp = tmp_path_factory.mktemp(f"argv-{command}")
        argv = data.draw(fuzzed_argv(command, tmp))
        check_answer_or_user_error(command, argv, "supcoord " + " ".join(argv), budgets_ok=True)

    fuzz()


# -- the progress log's rules ------------------------------------------------------------


def test_progress_log_shows_each_stage_start_and_end_and_counts_restarts():
    from supcoord.progress import ProgressLog

    out = io.StringIO()
    log = ProgressLog(out, interval=3600)  # nothing in between: only starts and ends
    for stage, it in [("reachable", 1), ("reachable", 2), ("reachable", 3), ("supcon", 1), ("supcon", 2)]:
        log(stage, {"nodes": 10 * it, "iteration": it})
    log.close()
    shown = [ln.split("] ", 1)[1].split(" | ")[:2] for ln in out.getvalue().splitlines()]
    assert shown == [["reachable", "iteration 1"], ["reachable", "iteration 3"],
                     ["supcon", "iteration 1"], ["supcon", "iteration 2"]], shown

    out = io.StringIO()
    log = ProgressLog(out, interval=0)  # -vv: every report; a restarted stage is numbered
    for it in (1, 2, 1):
        log("coreachable", {"nodes": 5, "iteration": it})
    assert [ln.split("] ", 1)[1].split(" | ")[0] for ln in out.getvalue().splitlines()] == \
        ["coreachable", "coreachable", "coreachable #2"]
