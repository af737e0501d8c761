"""Planning on SDSS-V's real APO wok: kaiju's instance, both directions, a few resolutions.

The problem is built from a kaiju instance file (``benchmarks/kaiju_side.py instances``; seed 0
of the APO wok is kept in ``results/kaiju_instances/apo_s0.json``): the instrument layout
``sdss-v-apo``, start the folded lattice, target kaiju's random decollided targets (joint
angles; ``unfold``) or the reverse (``fold``).  Each case runs ``supcoord.solve(problem,
improve=0, speed=12)`` in a fresh process (so the peak RSS is its own) and reports status,
wall and CPU seconds, peak RSS, makespan, motion time at kaiju's 12°/s and the planner's
direction choice.  Writes ``results/instrument.md`` with the command, machine and load.

    python benchmarks/bench_instrument.py                       # 13x7 and 19x10, unfold and fold
    python benchmarks/bench_instrument.py --steps 13x7 --directions unfold --out /tmp/i.md
    python benchmarks/bench_instrument.py --steps 37x19 --directions fold --tables default,whole --out /tmp/i.md

``--tables``: ``default`` (lazy tables where the whole ones would exceed
``collision.LAZY_TABLE_BYTES``), ``whole`` (every table computed ahead) or ``lazy``, side by side.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent

CHILD = r"""
import json, resource, sys, time
import supcoord
from supcoord.geometry import collision
from supcoord.problems.problem import parse_problem
data = json.loads(sys.argv[1])
if sys.argv[2] == "whole":
    collision.LAZY_TABLE_BYTES = 2**62  # every table computed ahead, as before lazy tables
elif sys.argv[2] == "lazy":
    collision.LAZY_TABLE_BYTES = -1
problem = parse_problem(data, "apo")
t0, c0 = time.perf_counter(), time.process_time()
plan = supcoord.solve(problem, improve=0, speed=12.0)
print(json.dumps({"status": plan.status, "wall_s": time.perf_counter() - t0, "cpu_s": time.process_time() - c0,
                  "rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, "makespan": plan.makespan,
                  "motion_s": plan.motion_time_s, "planned": plan.stats.get("direction"),
                  "short": plan.stats.get("descent_short"), "lazy": problem.tables().lazy}))
"""


def problem_json(instance: dict, steps: tuple[int, int], direction: str) -> dict:
    folded = {"alpha_beta_deg": instance["folded_deg"]}
    targets = {"alpha_beta_deg": instance["targets_deg"]}
    start, target = (folded, targets) if direction == "unfold" else (targets, folded)
    return {"layout": {"kind": "instrument", "name": "sdss-v-apo"},
            "kinematics": {"alpha_steps": steps[0], "beta_steps": steps[1]}, "start": start, "target": target}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--instance", default=str(HERE / "results" / "kaiju_instances" / "apo_s0.json"))
    ap.add_argument("--steps", default="13x7,19x10", help="comma-separated AxB lattices")
    ap.add_argument("--directions", default="unfold,fold")
    ap.add_argument("--timeout", type=float, default=1200.0, help="seconds per case")
    ap.add_argument("--tables", default="default", help="comma-separated: default, whole, lazy (module docstring)")
    ap.add_argument("--out", default=str(HERE / "results" / "instrument.md"))
    args = ap.parse_args()
    sys.path.insert(0, str(ROOT / "src"))
    from supcoord.study.machine import code_version, cpu_model, load, machine

    instance = json.loads(Path(args.instance).read_text())
    rows = []
    load_before = load()
    for text in args.steps.split(","):
        steps = tuple(int(v) for v in text.lower().split("x"))
        for direction, tables in ((d, t) for d in args.directions.split(",") for t in args.tables.split(",")):
            data = problem_json(instance, steps, direction)
            try:
                out = subprocess.run([sys.executable, "-c", CHILD, json.dumps(data), tables], capture_output=True, text=True,
                                     timeout=args.timeout, env={"PYTHONPATH": str(ROOT / "src"), "PATH": "/usr/bin:/bin"})
                res = json.loads(out.stdout.strip().splitlines()[-1]) if out.returncode == 0 else \
                    {"status": f"error: {out.stderr.strip().splitlines()[-1] if out.stderr.strip() else out.returncode}"}
            except subprocess.TimeoutExpired:
                res = {"status": f"unknown (timeout {args.timeout:g} s)"}
            row = {"steps": text, "direction": direction, "tables": tables, **res}
            rows.append(row)
            print(json.dumps(row), flush=True)
    lines = ["# Planning on SDSS-V's APO wok (kaiju's instance)", "",
             f"Command: `python benchmarks/bench_instrument.py {' '.join(sys.argv[1:])}`; instance "
             f"`{Path(args.instance).name}` (kaiju {instance.get('kaiju_version')}, seed {instance.get('seed')}); "
             f"supcoord {code_version()}.", "",
             f"Machine: {machine()}, {cpu_model()}; load {load_before} before, {load()} after; "
             f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}. Each case in a fresh process; "
             "`solve(problem, improve=0, speed=12)` (no plan improvement; 12°/s is kaiju's 2 RPM).", "",
             "| positions | direction | tables | answer | wall s | CPU s | peak RSS MB | makespan | motion s | planned | descent short (forward / reverse) |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        short = r.get("short") or {}
        kind = r["tables"] if "lazy" not in r else f"{r['tables']} ({'lazy' if r['lazy'] else 'whole'})"
        lines.append(f"| {r['steps']} | {r['direction']} | {kind} | {r['status']} | {r.get('wall_s', 0):.1f} | "
                     f"{r.get('cpu_s', 0):.1f} | {r.get('rss_mb', 0):.0f} | {r.get('makespan', '')} | "
                     f"{(r.get('motion_s') or 0):.1f} | {r.get('planned') or ''} | "
                     f"{short.get('forward', '')} / {short.get('reverse', '')} |")
    Path(args.out).write_text("\n".join(lines) + "\n")
    print(f"written {args.out}")


if __name__ == "__main__":
    main()
