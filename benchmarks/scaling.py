"""Benchmark: exact coupled coordination on SDSS-V-like hex grids, 7 … 547 positioners.

A thin wrapper over the study ``benchmarks/studies/scaling.toml`` (``docs/study.md``):

- problems: ``random_problem({"kind": "hex", "rings": R, "pitch": 22.4}, KIN, buffer=2.0, seed=S)``
  (random collision-free starts and targets, random priorities), rotary arms (15 mm, 12
  steps) and SDSS-V alpha-beta robots (7.4 / 15 mm, 12 × 7 steps, beta in [0°, 180°]);
- routes: ``local`` (``supcoord.planning.windows``, 5 seeds) and ``monolithic`` (the plain
  method of the seed paper on the whole grid, until its first time-out per kinematics);
- every case in a fresh process with a time limit (300 s local, 60 s monolithic) and a
  memory limit (6 GiB), on 2 Dask workers, each committed to the results database as it
  ends (the study shares the README study's database, so cases both hold run once).

It runs the cases not yet in the database, then writes ``results/scaling.csv``,
``results/scaling.md`` and ``results/scaling.png`` from the database: verdict
(``complete`` = a plan the independent validator accepted, ``infeasible`` = a certificate
naming positioners, ``unknown`` = the time limit ran out), seconds to solve (the validator
timed apart), CPU seconds, peak BDD nodes, peak RSS, makespan, lower bound, windows.

    python benchmarks/scaling.py                       # run what is missing, write the results
    python benchmarks/scaling.py --no-run              # only rewrite the results from the database
    python benchmarks/scaling.py --quick               # smoke run: 7 and 19 positioners, one seed, to /tmp
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import os
import statistics
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
FIELDS = ["kinematics", "route", "positioners", "rings", "seed", "status", "valid", "seconds", "cpu_seconds",
          "validate_seconds", "bdd_nodes", "peak_rss_mb", "makespan", "lower_bound", "ratio", "windows",
          "largest_window", "single_moves", "schedule", "certificate", "note", "load", "started"]


def point(r: dict) -> dict:
    """A database row as a row of the tables (``unknown``: the time or memory limit ran out)."""
    _, kind, route = r["series"].split()
    extra = r.get("extra") or {}
    status = r["verdict"] if r["status"] == "ok" else ("unknown" if r["status"] in ("timeout", "out-of-memory")
                                                      else r["status"])
    row = {"kinematics": kind, "route": route, "positioners": r["positioners"], "rings": r.get("rings"),
           "seed": r["seed"], "status": status, "valid": extra.get("valid"), "seconds": r["seconds"],
           "cpu_seconds": r["cpu_seconds"], "validate_seconds": extra.get("validate_seconds"),
           "bdd_nodes": r["bdd_nodes"], "peak_rss_mb": r["peak_rss_mb"], "makespan": r["makespan"],
           "lower_bound": r["lower_bound"], "windows": extra.get("windows"), "largest_window": extra.get("largest_window"),
           "single_moves": extra.get("single_moves"), "schedule": extra.get("schedule"),
           "certificate": " ".join(map(str, extra.get("certificate") or [])), "load": r["load"], "started": r["started"],
           "note": "" if r["status"] in ("ok",) else r["message"]}
    if row["makespan"] and row["lower_bound"]:
        row["ratio"] = row["makespan"] / max(1, row["lower_bound"])
    if r["status"] == "timeout" and row["seconds"] is None:
        row["seconds"] = r["wall_seconds"]
    return row


def fmt(v, digits: int = 2) -> str:
    if v is None or v == "":
        return ""
    if isinstance(v, float):
        return f"{v:.{digits}f}"
    return str(v)


def run_commands(db: str, db_rows: list[dict]) -> list[str]:
    """The commands of the runs (the database's ``runs`` table) that recorded ``db_rows``."""
    from supcoord.study import ResultStore

    used = {r["run"] for r in db_rows}
    with ResultStore(db) as store:
        return list(dict.fromkeys(run["command"] for run in store.runs() if run["run"] in used and run["command"]))


def write_markdown(path: str, rows: list[dict], command: str, db_rows: list[dict], ran_by: list[str]) -> None:
    ran = [r for r in db_rows if r.get("cpu")]
    loads = [r["load"] for r in ran if r.get("load") is not None]
    limits = sorted({(r["series"].split()[2], r["time_limit"]) for r in ran})
    lines = [
        "# Scaling benchmark (`benchmarks/scaling.py`)", "",
        (f"Command: `{command}` (the study `benchmarks/studies/scaling.toml`; results database "
        "`results/readme.sqlite`)  "),
        f"Its cases were run by: {'; '.join(f'`{c}`' for c in ran_by) or 'this command'}  ",
        f"Cases started between {min(r['started'] for r in ran)} and {max(r['started'] for r in ran)} (UTC)  ",
        f"Machine: {', '.join(sorted({r['cpu'] for r in ran}))}; code {', '.join(sorted({r['version'] for r in ran}))}  ",
        (f"Load (1 min) at the start of a case: median {statistics.median(loads):.1f}, max {max(loads):.1f} — the "
        "machine is shared with other jobs, wall-clock times are noisy (CPU seconds less so)."), "",
        "Problems: hex grid, pitch 22.4 mm, buffer 2.0 mm, random collision-free starts and targets "
        "(`random_problem`, seeded), random priorities. Rotary: arm 15 mm, 12 steps. Alpha-beta: 7.4 / 15 mm, "
        "12 × 7 steps, beta in [0°, 180°]. Each case is a fresh process (2 Dask workers); time limits: "
        + ", ".join(f"{route} {limit:g} s" for route, limit in limits)
        + " (monolithic: run until its first time-out per kinematics); memory limit 6 GiB.",
        ("`seconds` = solve time without the validator (`validate s`: the independent validator's time on the plan); "
        "`status` complete = a plan the validator accepted, infeasible = a certificate (the positioners named), "
        "unknown = the time limit ran out. `ratio` = makespan / lower bound (the largest single-joint distance)."), "",
        "## Summary (local route)", "",
        ("| kinematics | positioners | seeds | complete | infeasible | unknown | median s | max s | max CPU s | "
        "max peak RSS MB | max BDD nodes | median makespan / LB |"),
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for kind in ("rotary", "alpha-beta"):
        for n in sorted({r["positioners"] for r in rows if r["kinematics"] == kind}):
            rs = [r for r in rows if r["kinematics"] == kind and r["positioners"] == n and r["route"] == "local"]
            if not rs:
                continue
            secs = [r["seconds"] for r in rs if r.get("seconds") is not None]
            ratios = [r["ratio"] for r in rs if r.get("ratio") is not None]
            count = {s: sum(r["status"] == s for r in rs) for s in ("complete", "infeasible")}
            lines.append(
                f"| {kind} | {n} | {len(rs)} | {count['complete']} | {count['infeasible']} | "
                f"{len(rs) - sum(count.values())} | {fmt(statistics.median(secs)) if secs else ''} | "
                f"{fmt(max(secs)) if secs else ''} | {fmt(max((r.get('cpu_seconds') or 0) for r in rs))} | "
                f"{fmt(max((r.get('peak_rss_mb') or 0) for r in rs), 0)} | {max((r.get('bdd_nodes') or 0) for r in rs)} | "
                f"{fmt(statistics.median(ratios)) if ratios else ''} |")
    lines += ["", "## Every point", "",
              ("| kinematics | route | positioners | seed | status | seconds | CPU s | validate s | BDD nodes | "
              "peak RSS MB | makespan | LB | ratio | windows | largest window | load | certificate / note |"),
              "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        note = r.get("certificate") or r.get("note") or ""
        if r.get("status") == "complete" and r.get("valid") is False:
            note = "INVALID PLAN " + note
        lines.append(
            f"| {r['kinematics']} | {r['route']} | {r['positioners']} | {r['seed']} | {r['status']} | "
            f"{fmt(r.get('seconds'))} | {fmt(r.get('cpu_seconds'))} | {fmt(r.get('validate_seconds'))} | "
            f"{fmt(r.get('bdd_nodes'))} | {fmt(r.get('peak_rss_mb'), 0)} | {fmt(r.get('makespan'))} | "
            f"{fmt(r.get('lower_bound'))} | {fmt(r.get('ratio'))} | {fmt(r.get('windows'))} | "
            f"{fmt(r.get('largest_window'))} | {fmt(r.get('load'), 1)} | {note} |")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def plot(path: str, rows: list[dict]) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(12, 4.5))
    styles = {("rotary", "local"): ("C0", "o-"), ("alpha-beta", "local"): ("C1", "s-"),
              ("rotary", "monolithic"): ("C0", "x--"), ("alpha-beta", "monolithic"): ("C1", "+--")}
    for (kind, route), (color, style) in styles.items():
        rs = [r for r in rows if r["kinematics"] == kind and r["route"] == route and r.get("seconds") is not None]
        solved = [r for r in rs if r["status"] in ("complete", "infeasible")]
        sizes = sorted({r["positioners"] for r in solved})  # every series in order of its x
        if sizes:
            med = [statistics.median(r["seconds"] for r in solved if r["positioners"] == n) for n in sizes]
            ax1.plot(sizes, med, style, color=color, label=f"{kind}, {route} (median)")
        out = sorted((r["positioners"], r["seconds"]) for r in rs if r["status"] == "unknown")
        if out:
            ax1.plot([p[0] for p in out], [p[1] for p in out], "^", color=color, mfc="none", ms=8,
                     label=f"{kind}, {route}: ran out of time")
        rat = sorted((r["positioners"], r["ratio"]) for r in rs if r.get("ratio") is not None)
        if rat and route == "local":
            ax2.plot([p[0] for p in rat], [p[1] for p in rat], style[0], color=color, alpha=0.7, label=f"{kind}, {route}")
    ax1.set(xscale="log", yscale="log", xlabel="positioners", ylabel="seconds to solve (wall)",
            title="solve time (▲: ran out of time, at its limit)")
    ax2.set(xscale="log", xlabel="positioners", ylabel="makespan / lower bound", title="plan quality (local route)")
    ax2.axhline(1, color="grey", lw=0.8, ls=":")
    for ax in (ax1, ax2):
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--study", default=os.path.join(HERE, "studies", "scaling.toml"))
    ap.add_argument("--db", help="results database (default: the study's)")
    ap.add_argument("--workers", type=int, help="Dask worker processes (default: the study's, 2)")
    ap.add_argument("--no-run", action="store_true", help="only write the results from the database")
    ap.add_argument("--any-version", action="store_true", help="cases run by any code version count as done")
    ap.add_argument("--quick", action="store_true", help="rings 1 2, seed 0, 30 s limits, results to /tmp")
    ap.add_argument("--out-dir", default=os.path.join(HERE, "results"))
    args = ap.parse_args(argv)
    from supcoord.study import load_study, results_rows, run_study

    study = load_study(args.study)
    db = args.db
    if args.quick:
        study.cases = [dataclasses.replace(c, time_limit=30.0) for c in study.cases
                       if c.params["rings"] <= 2 and c.params["seed"] == 0]
        if args.out_dir == ap.get_default("out_dir"):
            args.out_dir = "/tmp/supcoord-scaling"
        db = db or os.path.join(args.out_dir, "scaling.sqlite")
    os.makedirs(args.out_dir, exist_ok=True)
    db = str(study.database_path(db))
    if not args.no_run:
        run_study(study, db, workers=args.workers, progress=lambda s: print(s, file=sys.stderr, flush=True),
                  any_version=args.any_version,
                  command="python benchmarks/scaling.py " + " ".join(argv if argv is not None else sys.argv[1:]))
    db_rows = results_rows(db, study=study)
    rows = sorted((point(r) for r in db_rows if r["status"] != "skipped"),
                  key=lambda r: (r["kinematics"] != "rotary", r["positioners"], r["seed"], r["route"]))
    with open(os.path.join(args.out_dir, "scaling.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=FIELDS, extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)
    command = "python benchmarks/scaling.py " + " ".join(argv if argv is not None else sys.argv[1:])
    write_markdown(os.path.join(args.out_dir, "scaling.md"), rows, command.strip(), db_rows, run_commands(db, db_rows))
    plot(os.path.join(args.out_dir, "scaling.png"), rows)
    print(f"wrote {args.out_dir}/scaling.csv, scaling.md, scaling.png", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
