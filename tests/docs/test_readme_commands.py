"""Every ```bash block of the README and the user docs runs as written, as a user would run it.

Each block is run by ``bash`` exactly as written, in a fresh directory laid out like a clone
of the project (``docs/`` and ``benchmarks/studies/`` copied in), with this test's environment
standing in for ``.venv``: ``.venv`` links to the running interpreter's environment, so
``source .venv/bin/activate`` and ``.venv/bin/supcoord`` work as written, and its ``bin`` is on
``PATH`` as after ``source .venv/bin/activate``.  Every command of a block must exit with 0
(or the status the block documents) and print no Python traceback.  The blocks of one file
run in order in one directory, so a block may use what an earlier one wrote (the README's
``supcoord-demo/``).
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
#: files whose ```bash blocks are run (the README and the user docs with command blocks)
FILES = ("README.md", "docs/cli.md", "docs/study.md", "docs/instruments.md", "docs/examples/README.md")

#: blocks not run, by their first line, and why
EXCLUDED = {
    ("README.md", "python3 -m venv .venv && .venv/bin/pip install -q . && .venv/bin/supcoord demo"):
        "a fresh virtualenv and install (needs the package index; .ci/run does it); what it leaves, "
        "`.venv/bin/supcoord demo`, is run as written before the README's other blocks",
    ("README.md", "python3 -m venv .venv && .venv/bin/pip install -q -e '.[test]' && .venv/bin/python -m pytest -q -n 2"):
        "the whole test suite in a fresh virtualenv (CONTRIBUTING.md gives its time; .ci/run runs it)",
    ("docs/study.md", "supcoord study run big.toml --scheduler tcp://login01:8786"):
        "needs a Dask scheduler on a cluster's login node",
}
#: what the excluded install block leaves behind, run as written before the README's other blocks
README_SETUP = ".venv/bin/supcoord demo"
#: exit statuses a block documents besides 0 (none does so far)
STATUS = {}
#: what the blocks of a file must print, as a whole line of their standard output, and the plan
#: they write with its status: docs/instruments.md solves and checks the 500-robot APO example,
#: the one place in the suite that solves it (test_cli_solve.py and test_examples_smoke.py leave
#: it to this block), so its plan must be complete and check valid with every robot at target
PRINTS = {"docs/instruments.md": (r"VALID: \d+ steps, 0 collisions, 500/500 positioners at target",
                                  "apo_plan.json", "complete")}
#: studies that a file's blocks run as written, each the one place in the suite that runs it
#: (test_examples_smoke.py leaves it to this block): after the blocks every case of its results
#: database must be ``ok``
STUDIES = {"docs/study.md": "docs/examples/study_small.sqlite"}
#: what a clean run never prints on standard error (as tests/docs/test_examples_smoke.py)
NOISE = ("Traceback", "Warning", "warning:", "Exception ignored")


def bash_blocks(name: str) -> list[str]:
    """The ```bash blocks of file ``name`` (relative to the project), in order."""
    return re.findall(r"^```bash\n(.*?)^```", (ROOT / name).read_text(), flags=re.S | re.M)


def to_run(name: str) -> list[str]:
    return [b for b in bash_blocks(name) if (name, b.splitlines()[0]) not in EXCLUDED]


@pytest.fixture
def clone(tmp_path: Path) -> tuple[Path, dict]:
    """A directory laid out like the project's clone, and the environment of an activated ``.venv``."""
    shutil.copytree(ROOT / "docs", tmp_path / "docs", ignore=shutil.ignore_patterns("img"))
    shutil.copytree(ROOT / "benchmarks" / "studies", tmp_path / "benchmarks" / "studies",
                    ignore=shutil.ignore_patterns("*.db", "*.db-*"))
    env_dir = Path(sys.prefix)
    venv = tmp_path / ".venv"
    if (env_dir / "bin" / "activate").exists():
        venv.symlink_to(env_dir, target_is_directory=True)
    else:  # no virtualenv: a stand-in whose activate puts this interpreter's bin on PATH
        (venv / "bin").mkdir(parents=True)
        for tool in ("supcoord", "python", "python3", "pip"):
            if (Path(sys.executable).parent / tool).exists():
                (venv / "bin" / tool).symlink_to(Path(sys.executable).parent / tool)
        (venv / "bin" / "activate").write_text(f'export PATH="{Path(sys.executable).parent}:$PATH"\n')
    env = dict(os.environ, PATH=f"{venv / 'bin'}{os.pathsep}{os.environ.get('PATH', '')}", VIRTUAL_ENV=str(venv),
               MPLBACKEND="Agg")
    env.pop("PYTHONPATH", None)
    return tmp_path, env


def run_block(block: str, cwd: Path, env: dict, allowed: set[int], timeout: float) -> subprocess.CompletedProcess:
    """Run ``block`` as written; fail on a command that exits outside ``allowed`` or on a traceback."""
    # the ERR trap reports every failing command without stopping the block, as a shell would go on
    script = 'trap \'echo "@@failed $? $BASH_COMMAND" >&2\' ERR\n' + block
    r = subprocess.run(["bash", "-c", script], cwd=cwd, env=env, capture_output=True, text=True, timeout=timeout,
                       stdin=subprocess.DEVNULL)
    failed = [line for line in r.stderr.splitlines() if line.startswith("@@failed ")
              and int(line.split()[1]) not in allowed]
    shown = f"\n--- block ---\n{block}\n--- stderr ---\n{r.stderr[-3000:]}"
    assert not failed and r.returncode in allowed | {0}, f"commands failed: {failed}{shown}"
    assert "Traceback" not in r.stdout + r.stderr, f"a traceback{shown}"
    return r


def test_every_block_is_run_or_excluded_with_a_reason():
    blocks = {(name, b.splitlines()[0]) for name in FILES for b in bash_blocks(name)}
    stale = [key for key in EXCLUDED if key not in blocks]
    assert not stale, f"excluded blocks that no longer exist: {stale}"
    assert sum(len(to_run(name)) for name in FILES) >= 5
    # the README's top: exactly two commands before anything else, each a fresh-machine command
    assert [b.strip() for b in bash_blocks("README.md")[:2]] == [k[1] for k in EXCLUDED if k[0] == "README.md"]


def fresh_shell(env: dict) -> dict:
    """``env`` as a new terminal has it after the README's install: ``.venv`` not activated."""
    venv_bins = {str(Path(sys.prefix) / "bin"), str(Path(sys.executable).parent), str(Path(env["VIRTUAL_ENV"]) / "bin")}
    path = os.pathsep.join(d for d in env["PATH"].split(os.pathsep) if d not in venv_bins)
    return {k: v for k, v in env.items() if k != "VIRTUAL_ENV"} | {"PATH": path}


@pytest.mark.slow
@pytest.mark.timeout(900)
def test_readme_blocks_run_as_written(clone):
    """The README is read on a fresh machine: its blocks run in a shell where ``.venv`` is not
    activated, so they must say how ``supcoord`` gets on the PATH themselves."""
    cwd, env = clone
    env = fresh_shell(env)
    run_block(README_SETUP, cwd, env, {0}, 300)
    assert (cwd / "supcoord-demo" / "G.gen").exists()
    for block in to_run("README.md"):
        run_block(block, cwd, env, STATUS.get(("README.md", block.splitlines()[0]), {0}), 600)
    # the caption under the plan figure states the plan's number of steps
    steps = re.search(r"(\d+) simultaneous steps", (ROOT / "README.md").read_text())
    import json

    plan = json.loads((cwd / "plan.json").read_text())
    assert steps and int(steps.group(1)) == plan["makespan"], (steps and steps.group(0), plan["makespan"])


@pytest.mark.slow
@pytest.mark.timeout(900)
@pytest.mark.parametrize("name", [f for f in FILES if f != "README.md"])
def test_doc_blocks_run_as_written(clone, name):
    cwd, env = clone
    if any("jq " in b for b in to_run(name)) and shutil.which("jq") is None:
        pytest.skip(f"{name} pipes into jq, which is not installed")
    runs = [run_block(block, cwd, env, STATUS.get((name, block.splitlines()[0]), {0}), 840) for block in to_run(name)]
    if name in PRINTS:
        line, plan_file, status = PRINTS[name]
        out, err = "".join(r.stdout for r in runs), "".join(r.stderr for r in runs)
        assert re.search(f"^{line}$", out, flags=re.M), out[-3000:]
        assert not [word for word in NOISE if word in err], err[-3000:]
        import json

        assert json.loads((cwd / plan_file).read_text())["status"] == status
    if name in STUDIES:
        from supcoord.study import results_rows

        rows = results_rows(cwd / STUDIES[name])
        assert rows and {row["status"] for row in rows} == {"ok"}, [(r["series"], r["status"]) for r in rows]


@pytest.mark.slow
def test_instruments_python_blocks_run(clone, monkeypatch):
    """docs/instruments.md's Python blocks (not doctests) run as written."""
    cwd, _ = clone
    monkeypatch.chdir(cwd)
    blocks = re.findall(r"^```python\n(.*?)^```", (ROOT / "docs" / "instruments.md").read_text(), flags=re.S | re.M)
    assert len(blocks) >= 2
    for block in blocks:
        scope: dict = {}
        exec(compile(block, "docs/instruments.md", "exec"), scope)
    assert scope["problem"].n == 500 and scope["problem"].warnings == []
    assert (cwd / "apo_random.json").exists()


def test_a_failing_command_in_a_block_fails_the_run(clone):
    """The harness itself: a failing line in the middle of a block, or a traceback, is caught."""
    cwd, env = clone
    with pytest.raises(AssertionError, match="commands failed"):
        run_block("true\nls no-such-file\ntrue", cwd, env, {0}, 60)
    with pytest.raises(AssertionError, match="traceback"):
        run_block("python3 -c 'raise SystemExit(\"Traceback (most recent call last):\")' || true", cwd, env,
                  {0}, 60)
    found = run_block("source .venv/bin/activate\ncommand -v supcoord", cwd, env, {0}, 60).stdout
    assert found.strip().endswith("supcoord")
    if shutil.which("supcoord", path=fresh_shell(env)["PATH"]) is None:  # not installed system-wide as well
        with pytest.raises(AssertionError, match="commands failed"):
            run_block("supcoord --version", cwd, fresh_shell(env), {0}, 60)
