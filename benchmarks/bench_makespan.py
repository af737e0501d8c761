"""Benchmark: plan quality — makespan against the optimum (small cases) and the lower bound.

Small cases (2–4 positioners, tight layouts where the arms overlap far more than on a
real grid, random seeded starts and targets): the planner's makespan (``solve``, local
and monolithic routes) against

- the **optimal makespan** of :func:`supcoord.testing.optimal_makespan_naive`
  (explicit breadth-first search in the simultaneous semantics, where every joint
  moves −1, 0, +1 per step — wider than the single-move model, so a lower bound for
  every plan either route can return), and
- the **lower bound** ``LB`` (largest single-joint distance).

Small hex grids at the SDSS-V pitch (7 and 19 rotary positioners, 7 alpha-beta): the
optimum from the symbolic twin :func:`supcoord.planning.optimum.optimal_makespan`
(the same semantics, breadth-first over BDDs; equal to the explicit one where both
run, tested), with a time budget.  Larger grids come from ``results/scaling.csv``
(makespan / LB), summarised here.
Writes ``results/makespan.csv`` and ``results/makespan.md``.

    python benchmarks/bench_makespan.py            # the table (a few minutes)
    python benchmarks/bench_makespan.py --quick    # fewer seeds, printed and written to /tmp
"""

from __future__ import annotations

import argparse
import csv
import os
import statistics
import sys
import time

import numpy as np

ROT = {"kind": "rotary", "arm": 15.0, "steps": 12}
AB_SMALL = {"kind": "alpha-beta", "alpha": 7.4, "beta": 15.0, "alpha_steps": 6, "beta_steps": 4, "beta_range": [0, 180]}
AB_SDSS = {"kind": "alpha-beta", "alpha": 7.4, "beta": 15.0, "alpha_steps": 12, "beta_steps": 7, "beta_range": [0, 180]}
LAYOUTS = {
    "rotary 2 (20 mm)": (ROT, [[0, 0], [20, 0]]),
    "rotary 3 (triangle, 18 mm)": (ROT, [[0, 0], [18, 0], [9, 15]]),
    "rotary 3 (line, 19 mm)": (ROT, [[0, 0], [19, 0], [38, 0]]),
    "rotary 4 (19 mm)": (ROT, [[0, 0], [19, 0], [9.5, 16], [28.5, 16]]),
    "rotary 3 (triangle, 21 mm)": (ROT, [[0, 0], [21, 0], [10.5, 18.2]]),
    "rotary 4 (rhombus, 21 mm)": (ROT, [[0, 0], [21, 0], [10.5, 18.2], [31.5, 18.2]]),
    "rotary 4 (line, 21 mm)": (ROT, [[0, 0], [21, 0], [42, 0], [63, 0]]),
    "alpha-beta 6x4, 2 (12 mm)": (AB_SMALL, [[0, 0], [12, 0]]),
    "alpha-beta 12x7, 2 (SDSS-V pitch 22.4 mm)": (AB_SDSS, [[0, 0], [22.4, 0]]),
    "alpha-beta 12x7, 2 (16 mm)": (AB_SDSS, [[0, 0], [16, 0]]),
}
FIELDS = ["case", "seed", "positioners", "status", "optimal", "lower_bound", "local", "monolithic",
          "local_ratio_opt", "mono_ratio_opt", "local_seconds", "optimal_seconds"]


def run(seeds: list[int]) -> list[dict]:
    from supcoord.planning.planner import solve
    from supcoord.problems import random_problem
    from supcoord.testing import optimal_makespan_naive

    rows = []
    for case, (kin, xy) in LAYOUTS.items():
        for seed in seeds:
            p = random_problem(np.array(xy, float), kin, 2.0, seed=seed)
            t0 = time.perf_counter()
            opt = optimal_makespan_naive(p)
            t1 = time.perf_counter()
            local = solve(p)
            t2 = time.perf_counter()
            mono = solve(p, route="monolithic")
            row = {"case": case, "seed": seed, "positioners": p.n, "status": local.status, "optimal": opt,
                   "lower_bound": local.lower_bound, "local_seconds": t2 - t1, "optimal_seconds": t1 - t0}
            if local.status != mono.status:
                raise SystemExit(f"MISMATCH {case} seed {seed}: local {local.status}, monolithic {mono.status}")
            if local.status == "complete":
                if opt is None:
                    raise SystemExit(f"MISMATCH {case} seed {seed}: a plan, but no simultaneous plan exists")
                row.update(local=local.makespan, monolithic=mono.makespan, local_ratio_opt=local.makespan / max(1, opt),
                           mono_ratio_opt=mono.makespan / max(1, opt))
            rows.append(row)
            print(f"{case:42s} seed {seed:2d} {local.status:10s} optimal {opt} LB {local.lower_bound} "
                  f"local {row.get('local')} monolithic {row.get('monolithic')}", file=sys.stderr, flush=True)
    return rows


def run_grids(grids: list[tuple[str, dict, int, int]], timeout: float) -> list[dict]:
    """Hex grids ``(kind, kinematics, rings, number of seeds)`` against the symbolic optimum."""
    from supcoord.bdd.context import Budget
    from supcoord.errors import BudgetExceeded
    from supcoord.planning.optimum import optimal_makespan
    from supcoord.planning.planner import solve
    from supcoord.problems import random_problem

    rows = []
    for kind, kin, rings, n_seeds in grids:
        for seed in range(n_seeds):
            p = random_problem({"kind": "hex", "rings": rings, "pitch": 22.4}, kin, 2.0, seed=seed)
            t0 = time.perf_counter()
            plan = solve(p)
            t1 = time.perf_counter()
            if plan.status == "complete" and plan.makespan == plan.lower_bound:
                opt, status = plan.makespan, "optimal by the lower bound (LB <= optimum <= plan)"
            else:
                try:
                    opt = optimal_makespan(p, budget=Budget(timeout=timeout)).makespan
                    status = "symbolic optimum"
                except BudgetExceeded:
                    opt, status = None, f"optimum unknown after {timeout:g} s"
            t2 = time.perf_counter()
            row = {"case": f"hex {kind} {p.n}", "seed": seed, "positioners": p.n, "status": plan.status,
                   "optimal": opt, "lower_bound": plan.lower_bound, "local": plan.makespan,
                   "local_seconds": t1 - t0, "optimal_seconds": t2 - t1, "note": status}
            if plan.status == "complete" and opt is not None:
                row["local_ratio_opt"] = plan.makespan / max(1, opt)
            rows.append(row)
            print(f"{row['case']:42s} seed {seed:2d} {plan.status:10s} optimal {opt} LB {plan.lower_bound} "
                  f"local {plan.makespan} ({status}, {t2 - t1:.0f} s)", file=sys.stderr, flush=True)
    return rows


def grid_summary(path: str) -> list[str]:
    if not os.path.exists(path):
        return ["(no `results/scaling.csv` yet: run `benchmarks/scaling.py`)"]
    with open(path) as f:
        rows = [r for r in csv.DictReader(f) if r["route"] == "local" and r["ratio"]]
    out = ["| kinematics | positioners | plans | makespan (median, max) | LB | makespan / LB (median, max) |",
           "|---|---|---|---|---|---|"]
    for kind in ("rotary", "alpha-beta"):
        for n in sorted({int(r["positioners"]) for r in rows if r["kinematics"] == kind}):
            rs = [r for r in rows if r["kinematics"] == kind and int(r["positioners"]) == n]
            ms = [int(float(r["makespan"])) for r in rs]
            ratios = [float(r["ratio"]) for r in rs]
            lbs = sorted({int(float(r["lower_bound"])) for r in rs})
            out.append(f"| {kind} | {n} | {len(rs)} | {statistics.median(ms):g}, {max(ms)} | "
                       f"{', '.join(map(str, lbs))} | {statistics.median(ratios):.2f}, {max(ratios):.2f} |")
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--grid-seeds", type=int, nargs=3, default=[10, 3, 3], metavar=("ROT7", "ROT19", "AB7"),
                    help="seeds of the hex grids with a symbolic optimum")
    ap.add_argument("--grid-timeout", type=float, default=600.0)
    ap.add_argument("--out-dir", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "results"))
    args = ap.parse_args()
    command = "python benchmarks/bench_makespan.py " + " ".join(sys.argv[1:])
    if args.quick:
        args.seeds, args.grid_seeds, args.grid_timeout = 2, [2, 0, 0], 60.0
        if args.out_dir == ap.get_default("out_dir"):
            args.out_dir = "/tmp/supcoord-makespan"
    os.makedirs(args.out_dir, exist_ok=True)
    started = time.strftime("%Y-%m-%d %H:%M", time.gmtime())
    load0 = os.getloadavg()
    rows = run(list(range(args.seeds)))
    rot7, rot19, ab7 = args.grid_seeds
    grid_rows = run_grids([("rotary", ROT, 1, rot7), ("rotary", ROT, 2, rot19), ("alpha-beta", AB_SDSS, 1, ab7)],
                          args.grid_timeout)
    load1 = os.getloadavg()
    with open(os.path.join(args.out_dir, "makespan.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=FIELDS + ["note"], extrasaction="ignore")
        w.writeheader()
        w.writerows(rows + grid_rows)
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from scaling import machine

    lines = [
        "# Plan quality (`benchmarks/bench_makespan.py`)", "",
        f"Command: `{command}`  ", f"Date: {started} (UTC)  ", f"Machine: {machine()}  ",
        f"Load (`uptime`): {' / '.join(f'{x:.2f}' for x in load0)} at the start, "
        f"{' / '.join(f'{x:.2f}' for x in load1)} at the end.", "",
        "Makespan of the planner's plans against the optimal makespan (explicit BFS in the simultaneous "
        "semantics: every joint −1/0/+1 per step, pairs checked as they move together — a lower bound for any "
        "plan) and the lower bound LB (largest single-joint distance). Tight layouts, seeds "
        f"0…{args.seeds - 1}, buffer 2 mm. Both routes must agree on the verdict (checked).", "",
        "## Summary (feasible cases)", "",
        "| case | cases (infeasible) | local / optimal: mean, max | monolithic / optimal: mean, max | "
        "local = optimal | optimal / LB mean |", "|---|---|---|---|---|---|",
    ]
    for case in LAYOUTS:
        rs = [r for r in rows if r["case"] == case]
        ok = [r for r in rs if r["status"] == "complete"]
        if not ok:
            lines.append(f"| {case} | {len(rs)} ({len(rs)}) | | | | |")
            continue
        lr = [r["local_ratio_opt"] for r in ok]
        mr = [r["mono_ratio_opt"] for r in ok]
        eq = sum(r["local"] == r["optimal"] for r in ok)
        olb = [r["optimal"] / max(1, r["lower_bound"]) for r in ok]
        lines.append(f"| {case} | {len(rs)} ({len(rs) - len(ok)}) | {statistics.mean(lr):.2f}, {max(lr):.2f} | "
                     f"{statistics.mean(mr):.2f}, {max(mr):.2f} | {eq}/{len(ok)} | {statistics.mean(olb):.2f} |")
    lines += ["", "## Every case", "",
              "| case | seed | status | optimal | LB | local | monolithic | local s | optimum s |",
              "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['case']} | {r['seed']} | {r['status']} | {r['optimal']} | {r['lower_bound']} | "
                     f"{r.get('local', '')} | {r.get('monolithic', '')} | {r['local_seconds']:.2f} | "
                     f"{r['optimal_seconds']:.2f} |")
    lines += ["", "## Small hex grids (SDSS-V pitch 22.4 mm) against the symbolic optimum", "",
              "| case | seed | status | optimal | LB | local | local / optimal | local s | optimum s | note |",
              "|---|---|---|---|---|---|---|---|---|---|"]
    for r in grid_rows:
        ratio = f"{r['local_ratio_opt']:.2f}" if r.get("local_ratio_opt") is not None else ""
        lines.append(f"| {r['case']} | {r['seed']} | {r['status']} | {r['optimal']} | {r['lower_bound']} | "
                     f"{r['local']} | {ratio} | {r['local_seconds']:.2f} | {r['optimal_seconds']:.1f} | {r['note']} |")
    done = [r for r in grid_rows if r.get("local_ratio_opt") is not None]
    for case in sorted({r["case"] for r in done}):
        rs = [r["local_ratio_opt"] for r in done if r["case"] == case]
        eq = sum(1 for r in done if r["case"] == case and r["local"] == r["optimal"])
        lines.append(f"\n{case}: local / optimal mean {statistics.mean(rs):.2f}, max {max(rs):.2f}, "
                     f"optimal in {eq} of {len(rs)}.")
    lines += ["", "## Grids (from `results/scaling.csv`, local route)", "",
              "No optimum is computable there; the ratio to LB is an upper bound on the ratio to the optimum.", ""]
    lines += grid_summary(os.path.join(args.out_dir, "scaling.csv"))
    with open(os.path.join(args.out_dir, "makespan.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print(f"wrote {args.out_dir}/makespan.csv, makespan.md", file=sys.stderr)


if __name__ == "__main__":
    main()
