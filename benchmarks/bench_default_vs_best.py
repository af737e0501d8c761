#!/usr/bin/env python
"""The default fixpoint schedule against the best one, on every instance.

Every family of :mod:`supcoord.des.families` at every size from the smallest, the
classic models, the seed paper's models (literal and coupled) and the classic
libFAUDES files run through ``supcon`` with each ``--method`` — ``bfs``, ``chaining``,
``saturation`` over the plain event steps (``plain``: saturation without its local
closures) and ``default`` (what ``supcoord supcon`` runs) — each point in a fresh
process with a time limit.  The families and the classic models go through the
command line exactly as a user runs them (components written as libFAUDES ``.gen``
files, ``supcoord supcon --plant … --spec … --route symbolic --json``: the
specifications lifted to the plant alphabet, the ``rcm`` order); the paper's models
through the library.

Per instance it prints ``default / best``, with seconds floored at ``FLOOR`` (below
it the time is noise) and, beside it, the same ratio of CUDD's computed-table lookups
(``cudd_lookups`` of ``--json``: the work, the same on every machine).

    python benchmarks/bench_default_vs_best.py                # writes results/default_vs_best.md
    python benchmarks/bench_default_vs_best.py --quick        # small sizes, prints only
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import tempfile
import time
from datetime import datetime, timezone

METHODS = ["bfs", "chaining", "plain", "default"]
FLOOR = 0.05  # seconds: below this, times are noise (ratios use max(t, FLOOR))
FAMILIES = {  # family -> sizes, from the smallest
    "machine_line": list(range(1, 17)) + [20, 24],
    "transfer_line_chain": list(range(1, 9)),
    "dining_philosophers": [2, 3, 4, 6, 8, 10, 12, 15],
    "small_factories": [1, 2, 3, 5, 8],
    "coupled_factories": [1, 2, 3, 5, 7],
}
CLASSIC = ["small_factory", "transfer_line", "agv", "cat_mouse", "dining_philosophers"]
PAPER_LITERAL = [2, 5, 10, 30]
PAPER_COUPLED = [3, 4]
QUICK_FAMILIES = {"machine_line": list(range(1, 10)), "transfer_line_chain": [1, 2, 3],
                  "dining_philosophers": [2, 3, 4, 6], "coupled_factories": [1, 2, 3]}


# -- workers (each in a fresh process) -------------------------------------------------------------


def _write_family(family: str, size: int, directory: str) -> tuple[list[str], list[str]]:
    from supcoord.des import families
    from supcoord.des.io import write_generator

    plants, specs = families.FAMILIES[family](size)
    paths = ([], [])
    for kind, comps in enumerate((plants, specs)):
        for i, g in enumerate(comps):
            path = os.path.join(directory, f"{'ps'[kind]}{i:02d}_{g.name}.gen")
            write_generator(g, path)
            paths[kind].append(path)
    return paths


def _classic_files(name: str, directory: str) -> tuple[list[str], list[str]]:
    from supcoord.des import classic
    from supcoord.des.io import write_generator

    m = classic.load(name)
    return _write_family_components(m.plants, m.specs, directory, write_generator)


def _write_family_components(plants, specs, directory, write):
    paths = ([], [])
    for kind, comps in enumerate((plants, specs)):
        for i, g in enumerate(comps):
            path = os.path.join(directory, f"{'ps'[kind]}{i:02d}_{g.name}.gen")
            write(g, path)
            paths[kind].append(path)
    return paths


def cli_point(plants: list[str], specs: list[str], method: str, timeout: float) -> dict:
    """``supcoord supcon`` on the files, in a fresh process; its ``--json`` object."""
    cmd = [sys.executable, "-m", "supcoord.cli", "supcon", "--plant", *plants, "--route", "symbolic", "--json"]
    if specs:
        cmd[cmd.index("--route"):cmd.index("--route")] = ["--spec", *specs]
    if method == "plain":  # the command line with the local closures off (the launcher in main)
        cmd = [sys.executable, os.path.abspath(__file__), "--plain-cli", *cmd[1:], "--method", "saturation"]
    elif method != "default":
        cmd += ["--method", method]
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return {"status": "timeout"}
    if p.returncode:
        return {"status": f"exit {p.returncode}: {p.stderr.strip().splitlines()[-1] if p.stderr.strip() else ''}"}
    return _point(json.loads(p.stdout))


def _point(out: dict) -> dict:
    """The synthesis seconds (the stages of ``effort``) and work (all CUDD lookups)."""
    effort = out["effort"]
    return {"status": out["status"], "states": out["states"], "seconds": sum(effort["stage_seconds"].values()),
            "cudd_lookups": effort["cudd_lookups"] + effort["closure_lookups"],
            "closures": [effort["closures_built"], effort["closures_abandoned"]]}


def paper_worker(model: str, size: int, method: str) -> dict:
    """supcon of a paper model in this process: seconds, sizes and CUDD's counts."""
    from supcoord.bdd import Context
    from supcoord.synthesis import reachability as R
    from supcoord.synthesis import supcon

    Context()  # load dd.cudd before timing
    ctx = Context()
    if model == "paper_literal":
        from supcoord.paper.literal import literal_models, random_instance

        G, E = literal_models(random_instance(size, 8, seed=1), ctx)
    else:
        from supcoord.paper.coupled import CoupledModel, coupled_models
        from supcoord.paper.run import coupled_instance

        G, E = coupled_models(CoupledModel(coupled_instance(size, 8, 0)), ctx, order="auto")
    R.LOCAL_CLOSURES = method != "plain"
    res = supcon(G, E, method="saturation" if method in ("plain", "default") else method, count_transitions=False)
    return _point({"status": "ok", "states": res.stats["states"], "effort": res.stats["effort"]})


def paper_point(model: str, size: int, method: str, timeout: float) -> dict:
    cmd = [sys.executable, os.path.abspath(__file__), "--paper-worker", model, str(size), method]
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return {"status": "timeout"}
    if p.returncode:
        return {"status": f"exit {p.returncode}"}
    return json.loads(p.stdout.strip().splitlines()[-1])


# -- the table ---------------------------------------------------------------------------------------


def _lookups(r: dict):
    return r.get("cudd_lookups")


def ratio_row(name: str, size, results: dict[str, dict], timeout: float) -> dict:
    secs = {m: (r["seconds"] if r.get("status") == "ok" else None) for m, r in results.items()}  # None: timeout
    done = [t for t in secs.values() if t is not None]
    best = min(done) if done else None
    d = secs.get("default")
    floor_d = max(d, FLOOR) if d is not None else timeout
    ratio = floor_d / max(best, FLOOR) if best is not None else None
    work = {m: _lookups(r) for m, r in results.items() if r.get("status") == "ok"}
    known = [w for w in work.values() if w]
    wratio = (work["default"] / min(known)) if work.get("default") and known else None
    states = next((r.get("states") for r in results.values() if r.get("status") == "ok"), None)
    return {"instance": name, "size": size, "states": states, "seconds": secs,
            "status": {m: r.get("status") for m, r in results.items()}, "ratio": ratio, "work_ratio": wratio,
            "lookups": work}


def instances(quick: bool):
    fams = QUICK_FAMILIES if quick else FAMILIES
    for family, sizes in fams.items():
        for size in sizes:
            yield ("family", family, size)
    for name in (CLASSIC[:2] if quick else CLASSIC):
        yield ("classic", name, None)
    for size in ([2, 3] if quick else PAPER_LITERAL):
        yield ("paper", "paper_literal", size)
    for size in ([3] if quick else PAPER_COUPLED):
        yield ("paper", "paper_coupled", size)


def _best(points: list[dict]) -> dict:
    """The fastest of repeated runs of one point (a timeout or failure if none finished)."""
    done = [p for p in points if p.get("status") == "ok"]
    return min(done, key=lambda p: p["seconds"]) if done else points[0]


def run_all(quick: bool, timeout: float, only: list[str] | None = None, repeat: int = 1) -> list[dict]:
    rows = []
    for kind, name, size in instances(quick):
        if only and f"{name}:{size}" not in only and name not in only:
            continue
        results = {}
        with tempfile.TemporaryDirectory() as d:
            if kind == "family":
                plants, specs = _write_family(name, size, d)
            elif kind == "classic":
                plants, specs = _classic_files(name, d)
            for m in METHODS:
                if kind == "paper":
                    results[m] = _best([paper_point(name, size, m, timeout) for _ in range(repeat)])
                else:
                    results[m] = _best([cli_point(plants, specs, m, timeout) for _ in range(repeat)])
        row = ratio_row(name, size, results, timeout)
        rows.append(row)
        print(_line(row), flush=True)
    return rows


def _fmt(t):
    return "timeout" if t is None else f"{t:.3f}"


def _line(row: dict) -> str:
    secs = " | ".join(_fmt(row["seconds"].get(m)) if row["status"].get(m) in ("ok", "timeout") or
                      row["seconds"].get(m) is not None else row["status"].get(m, "") for m in METHODS)
    r = "" if row["ratio"] is None else f"{row['ratio']:.2f}"
    w = "" if row["work_ratio"] is None else f"{row['work_ratio']:.2f}"
    size = "" if row["size"] is None else row["size"]
    return f"| {row['instance']} | {size} | {row['states'] if row['states'] is not None else ''} | {secs} | {r} | {w} |"


def report(rows: list[dict], args, started: float, load0, load1) -> str:
    cpu = platform.processor() or platform.machine()
    worst = max((r["ratio"] for r in rows if r["ratio"] is not None), default=None)
    wworst = max((r["work_ratio"] for r in rows if r["work_ratio"] is not None), default=None)
    out = [
        "# The default fixpoint schedule against the best one (`benchmarks/bench_default_vs_best.py`)",
        "",
        f"- command: `python benchmarks/bench_default_vs_best.py{' --quick' if args.quick else ''} --timeout {args.timeout:g}"
        f"{f' --repeat {args.repeat}' if args.repeat > 1 else ''}{' --only ' + ' '.join(args.only) if args.only else ''}`",
        f"- date: {datetime.fromtimestamp(started, timezone.utc):%Y-%m-%d %H:%M} UTC; run took "
        f"{time.time() - started:.0f} s",
        f"- machine: {platform.system()} {platform.machine()} ({cpu}), {os.cpu_count()} CPUs, Python "
        f"{platform.python_version()}",
        f"- load (1/5/15 min): {load0[0]:.2f} / {load0[1]:.2f} / {load0[2]:.2f} at the start, "
        f"{load1[0]:.2f} / {load1[1]:.2f} / {load1[2]:.2f} at the end (a shared machine)",
        f"- every point in a fresh process, {args.timeout:g} s at most (the fastest of {args.repeat} runs); seconds = the synthesis, the sum of "
        "`effort.stage_seconds` of `supcoord supcon --json` (product, fixpoints, exact counts; reading the files and "
        "building the BDDs excluded, the same for every method); paper models: `supcon` in the library, same measure",
        f"- ratio = max(default s, {FLOOR}) / max(best s, {FLOOR}) over bfs, chaining, plain saturation and the "
        "default (a timeout counts as the time limit); work ratio = the default's CUDD computed-table lookups / "
        "the fewest of any method (machine-independent)",
        "",
        f"**Max ratio default/best: {worst:.2f}; max work ratio: {wworst:.2f}**" if worst is not None and
        wworst is not None else "",
        "",
        "| instance | size | states | " + " | ".join(f"{m} s" for m in METHODS) + " | default/best | work ratio |",
        "|---|---:|---:|" + "---:|" * len(METHODS) + "---:|---:|",
    ]
    out += [_line(r) for r in rows]
    out += ["", "Raw rows (JSON):", "", "```"] + [json.dumps(r) for r in rows] + ["```", ""]
    return "\n".join(out)


def main() -> None:
    if len(sys.argv) > 1 and sys.argv[1] == "--paper-worker":
        print(json.dumps(paper_worker(sys.argv[2], int(sys.argv[3]), sys.argv[4])))
        return
    if len(sys.argv) > 1 and sys.argv[1] == "--plain-cli":  # the command line with LOCAL_CLOSURES off
        from supcoord.cli.main import main as cli_main
        from supcoord.synthesis import reachability as R

        R.LOCAL_CLOSURES = False
        sys.exit(cli_main(sys.argv[4:]))
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    ap.add_argument("--quick", action="store_true", help="small sizes; prints only")
    ap.add_argument("--timeout", type=float, default=30.0, help="seconds per point")
    ap.add_argument("--only", nargs="+", metavar="NAME[:SIZE]", help="run only these instances")
    ap.add_argument("--repeat", type=int, default=1, help="runs per point, the fastest counts (default 1)")
    ap.add_argument("--out", default=os.path.join(os.path.dirname(__file__), "results", "default_vs_best.md"))
    args = ap.parse_args()
    started, load0 = time.time(), os.getloadavg()
    print("| instance | size | states | " + " | ".join(f"{m} s" for m in METHODS) + " | default/best | work ratio |")
    rows = run_all(args.quick, args.timeout, args.only, args.repeat)
    text = report(rows, args, started, load0, os.getloadavg())
    if not args.quick:
        with open(args.out, "w") as f:
            f.write(text)
        print(f"written to {os.path.relpath(args.out)}")
    else:
        print(text.split("\n\n")[2] if "Max ratio" in text else "")


if __name__ == "__main__":
    main()
