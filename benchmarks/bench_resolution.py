"""Lattice resolution against time: the SDSS-V preset (127 robots) at coarse to fine lattices.

Each case is ``supcoord.preset_problem("sdss-v", rings, seed, alpha_steps=A, beta_steps=B)``
solved with ``supcoord.solve(problem, improve=0)`` in a fresh process (its own peak RSS)
under a timeout; with ``--variants`` the same case also runs with the window searches'
``DISPLACED`` bounds changed (``windows.DISPLACED``; ``none`` = no few-displaced searches),
side by side in the same run.  ``--profile N`` adds the N functions of largest own time
(cProfile) per case.  Writes ``results/resolution.md`` and ``.json`` with the command,
machine and load.

    python benchmarks/bench_resolution.py                                # 13x7, 24x13, 36x19
    python benchmarks/bench_resolution.py --steps 36x19 --variants 1,2 none --profile 8
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
import cProfile, io, json, pstats, resource, sys, time
import supcoord
from supcoord.planning import windows
a, b, rings, seed, variant, top = sys.argv[1:7]
if variant != "default":
    windows.DISPLACED = () if variant == "none" else tuple(int(v) for v in variant.split(","))
problem = supcoord.preset_problem("sdss-v", rings=int(rings), seed=int(seed), alpha_steps=int(a), beta_steps=int(b))
prof = cProfile.Profile() if int(top) else None
t0, c0 = time.perf_counter(), time.process_time()
if prof:
    prof.enable()
plan = supcoord.solve(problem, improve=0)
if prof:
    prof.disable()
out = {"status": plan.status, "wall_s": time.perf_counter() - t0, "cpu_s": time.process_time() - c0,
       "rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, "robots": problem.n,
       "makespan": plan.makespan, **{k: plan.stats.get(k) for k in ("windows", "largest_window", "windows_few_displaced",
                                                                     "windows_abandoned", "bdd_nodes")}}
if prof:
    rows = sorted(pstats.Stats(prof).stats.items(), key=lambda kv: -kv[1][2])[:int(top)]
    out["profile"] = [[f"{fn[0].split('/')[-1]}:{fn[1]}({fn[2]})", round(v[2], 1), round(v[3], 1)] for fn, v in rows]
print(json.dumps(out))
"""


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", default="13x7,24x13,36x19", help="comma-separated AxB lattices")
    ap.add_argument("--rings", type=int, default=6, help="hex rings (6: 127 robots)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--variants", nargs="+", default=["default"],
                    help="windows.DISPLACED per run: default, none, or bounds such as 1,2")
    ap.add_argument("--profile", type=int, default=0, help="report the N functions of largest own time")
    ap.add_argument("--timeout", type=float, default=1200.0, help="seconds per case")
    ap.add_argument("--out", default=str(HERE / "results" / "resolution"), help="writes OUT.md and OUT.json")
    args = ap.parse_args()
    sys.path.insert(0, str(ROOT / "src"))
    from supcoord.study.machine import code_version, cpu_model, load, machine

    rows = []
    load_before = load()
    for text in args.steps.split(","):
        a, b = (int(v) for v in text.lower().split("x"))
        for variant in args.variants:
            cmd = [sys.executable, "-c", CHILD, str(a), str(b), str(args.rings), str(args.seed), variant,
                   str(args.profile)]
            try:
                out = subprocess.run(cmd, capture_output=True, text=True, timeout=args.timeout,
                                     env={"PYTHONPATH": str(ROOT / "src"), "PATH": "/usr/bin:/bin"})
                res = json.loads(out.stdout.strip().splitlines()[-1]) if out.returncode == 0 else \
                    {"status": f"error: {out.stderr.strip().splitlines()[-1] if out.stderr.strip() else out.returncode}"}
            except subprocess.TimeoutExpired:
                res = {"status": f"unknown (timeout {args.timeout:g} s)"}
            row = {"steps": text, "variant": variant, **res}
            rows.append(row)
            print(json.dumps({k: v for k, v in row.items() if k != "profile"}), flush=True)
    header = {"command": "python benchmarks/bench_resolution.py " + " ".join(sys.argv[1:]), "code": code_version(),
              "machine": f"{machine()}, {cpu_model()}", "load_before": load_before, "load_after": load(),
              "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())}
    Path(args.out + ".json").write_text(json.dumps({"header": header, "rows": rows}, indent=1) + "\n")
    lines = [f"# Lattice resolution: SDSS-V preset, {args.rings} rings, seed {args.seed}", "",
             f"Command: `{header['command']}`; supcoord {header['code']}.", "",
             f"Machine: {header['machine']}; load {load_before} before, {header['load_after']} after; {header['date']}. "
             "Each case in a fresh process, `solve(problem, improve=0)`; the variant is `windows.DISPLACED` "
             "(default: (1, 2); none: no few-displaced searches)"
             + (f"; timed under cProfile (--profile {args.profile}), which slows every case." if args.profile else ".")
             , "",
             "| positions | variant | answer | wall s | CPU s | peak RSS MB | windows | few-displaced | abandoned | "
             "largest | BDD nodes |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['steps']} | {r['variant']} | {r['status']} | {r.get('wall_s', 0):.1f} | {r.get('cpu_s', 0):.1f} | "
                     f"{r.get('rss_mb', 0):.0f} | {r.get('windows', '')} | {r.get('windows_few_displaced') or 0} | "
                     f"{r.get('windows_abandoned', '')} | {r.get('largest_window', '')} | {r.get('bdd_nodes', '')} |")
    for r in rows:
        if r.get("profile"):
            lines += ["", f"Profile, {r['steps']} {r['variant']} (own s, cumulative s):", ""]
            lines += [f"- `{name}` {own} / {cum}" for name, own, cum in r["profile"]]
    Path(args.out + ".md").write_text("\n".join(lines) + "\n")
    print(f"written {args.out}.md")


if __name__ == "__main__":
    main()
