"""The memory-budget class of issue 34's attack campaign: does ``--max-memory`` hold?

Each run is a ``supcoord`` command with ``--max-memory`` in a process of its own, under a
wall-clock limit.  The peak resident memory is the largest ``ru_maxrss`` of the whole
process tree, read from the kernel's accounting of the waited-for descendants
(``RUSAGE_CHILDREN`` around the run), so a command that forks its work into a child is
measured too.  A run *overruns* when that peak is more than 5 % above its budget; it must
end with exit status 3 and ``"status": "unknown"`` on standard output when the budget ran out
(or with its answer, exit 0, when the budget sufficed), and print no traceback.

    python benchmarks/memory_budget.py     # writes benchmarks/results/memory_budget.md
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

HERE = Path(__file__).resolve().parent
RESULTS = HERE / "results" / "memory_budget.md"
EXAMPLES = HERE.parent / "docs" / "examples"
SECONDS = 600
TOLERANCE = 0.05

#: (what, argv after ``supcoord``, budget in MiB); the first two are the issue's reproducers
RUNS: list[tuple[str, list[str], int]] = [
    ("paper coupled monolithic, 20 positioners", ["paper", "--positioners", "20", "--steps", "8", "--model",
                                                   "coupled", "--route", "monolithic"], 500),
    ("paper coupled monolithic, 20 positioners", ["paper", "--positioners", "20", "--steps", "8", "--model",
                                                   "coupled", "--route", "monolithic"], 300),
    ("paper literal monolithic, 100 positioners", ["paper", "--positioners", "100", "--steps", "12", "--route",
                                                    "monolithic"], 150),
    ("paper literal monolithic, 100 positioners", ["paper", "--positioners", "100", "--steps", "12", "--route",
                                                    "monolithic"], 200),
    ("paper literal modular, 1000 positioners (a budget that suffices)", ["paper", "--positioners", "1000",
                                                                          "--steps", "12"], 1000),
    ("solve, APO wok", ["solve", str(EXAMPLES / "sdss_v_apo.json")], 400),
]


@dataclass
class Outcome:
    what: str
    budget_mib: int
    exit_status: int | None  # None: killed at the wall-clock limit
    status: str
    peak_mib: float
    seconds: float
    traceback: bool

    @property
    def overrun(self) -> float:
        return self.peak_mib / self.budget_mib - 1

    @property
    def verdict(self) -> str:
        if self.exit_status is None:
            return "hang"
        if self.traceback or self.exit_status not in (0, 3):
            return "error"
        return "overrun" if self.overrun > TOLERANCE else "held"


def _run(what: str, argv: list[str], budget: int, cwd: Path) -> Outcome:
    before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    t0 = time.perf_counter()
    cmd = [sys.executable, "-m", "supcoord.cli", *argv, "--max-memory", f"{budget}M", "--json"]
    try:
        proc = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=SECONDS)
        code, out, err = proc.returncode, proc.stdout, proc.stderr
    except subprocess.TimeoutExpired as exc:
        code, out, err = None, exc.stdout or "", exc.stderr or ""
        out, err = (s.decode() if isinstance(s, bytes) else s for s in (out, err))
    seconds = time.perf_counter() - t0
    peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    if peak <= before:  # the accounting keeps the largest child ever waited for
        peak = before
    try:
        status = json.loads(out).get("status", "?")
    except (json.JSONDecodeError, AttributeError):
        status = "no JSON"
    return Outcome(what, budget, code, status, peak / 1024, seconds, "Traceback" in err)


def _machine() -> str:
    from supcoord.study.machine import cpu_model

    return cpu_model()


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=str(RESULTS), help="the results file (Markdown)")
    args = parser.parse_args(argv)
    started = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    load0 = os.getloadavg()[0]
    outcomes = []
    # RUSAGE_CHILDREN keeps the largest descendant so far: each run is measured from a fresh
    # interpreter of its own
    with tempfile.TemporaryDirectory(prefix="memory-budget-") as tmp:
        for what, argv_, budget in RUNS:
            code = (f"import sys; sys.path.insert(0, {str(HERE)!r}); import memory_budget as m, json, dataclasses; "
                    f"o = m._run({what!r}, {argv_!r}, {budget}, __import__('pathlib').Path({tmp!r})); "
                    f"print(json.dumps(dataclasses.asdict(o)))")
            proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=SECONDS + 60)
            outcome = Outcome(**json.loads(proc.stdout.strip().splitlines()[-1]))
            outcomes.append(outcome)
            print(f"{outcome.what} @ {outcome.budget_mib} MiB: exit {outcome.exit_status}, {outcome.status}, "
                  f"peak {outcome.peak_mib:.0f} MiB ({outcome.overrun:+.1%}), {outcome.seconds:.1f} s: "
                  f"{outcome.verdict}", flush=True)
    load1 = os.getloadavg()[0]
    held = sum(o.verdict == "held" for o in outcomes)
    lines = [
        "# Memory budgets (issue 34): `--max-memory` as a hard limit",
        "",
        "Command: `python benchmarks/memory_budget.py`  ",
        f"Date: {started}  ",
        f"Machine: {_machine()}; load average (1 min) {load0:.1f} at the start, {load1:.1f} at the end",
        "",
        f"Peak: the largest resident set of the command's process tree (the kernel's `ru_maxrss` of "
        f"the waited-for descendants). *held*: the peak within {TOLERANCE:.0%} of the budget and exit 0 "
        f"(answered) or 3 (`\"status\": \"unknown\"`), no traceback; *overrun*, *error* and *hang* "
        f"(no end within {SECONDS} s) otherwise.",
        "",
        f"**{held} of {len(outcomes)} held.**",
        "",
        "| command | budget (MiB) | exit | status | peak (MiB) | peak / budget | seconds | verdict |",
        "|---|---|---|---|---|---|---|---|",
        *[f"| {o.what} | {o.budget_mib} | {o.exit_status} | {o.status} | {o.peak_mib:.0f} | "
          f"{o.peak_mib / o.budget_mib:.3f} | {o.seconds:.1f} | {o.verdict} |" for o in outcomes],
        "",
    ]
    Path(args.out).write_text("\n".join(lines), encoding="utf-8")
    return 0 if held == len(outcomes) else 1


if __name__ == "__main__":
    sys.exit(main())
