"""Growth of time and memory with the number of robots: DESI and PFS presets up to the full focal planes.

Each case is ``supcoord.solve(preset_problem(name, rings, seed, alpha_steps=A, beta_steps=B),
improve=0)`` in a fresh process (so the peak RSS is its own): random collision-free starts
and targets on a hex grid of the preset's pitch and arms (``supcoord.problems.presets``),
``rings`` rings (``1 + 3·r·(r+1)`` robots: 41 rings = 5,167 ≥ DESI's 5,020; 28 rings =
2,437 ≥ PFS's 2,394).  Reports status, wall and CPU seconds, peak RSS, makespan, BDD
nodes and windows; writes ``results/scale.md``, ``results/scale.json`` and
``results/scale.png`` with the command, machine and load.

    python benchmarks/bench_scale.py                               # DESI 127 … 5,167 and PFS 2,437
    python benchmarks/bench_scale.py --cases desi:6,desi:10 --out /tmp/scale   # a quick look
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
from supcoord.problems.presets import preset_problem
name, rings, seed, a, b = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4]), int(sys.argv[5])
t0, c0 = time.perf_counter(), time.process_time()
problem = preset_problem(name, rings=rings, seed=seed, alpha_steps=a, beta_steps=b)
built = time.perf_counter() - t0
plan = supcoord.solve(problem, improve=0)
print(json.dumps({"robots": problem.n, "status": plan.status, "build_s": built,
                  "wall_s": time.perf_counter() - t0, "cpu_s": time.process_time() - c0,
                  "rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
                  "makespan": plan.makespan, "bdd_nodes": plan.stats.get("bdd_nodes"),
                  "windows": plan.stats.get("windows"), "validate_s": plan.stats.get("validate_seconds")}))
"""

DEFAULT_CASES = "desi:6,desi:10,desi:14,desi:20,desi:30,desi:41,pfs:28"


def run_case(name: str, rings: int, seed: int, steps: tuple[int, int], timeout: float) -> dict:
    cmd = [sys.executable, "-c", CHILD, name, str(rings), str(seed), str(steps[0]), str(steps[1])]
    try:
        out = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout,
                             env={"PYTHONPATH": str(ROOT / "src"), "PATH": "/usr/bin:/bin"})
    except subprocess.TimeoutExpired:
        return {"status": f"unknown (timeout {timeout:g} s)"}
    if out.returncode != 0:
        tail = out.stderr.strip().splitlines()[-1] if out.stderr.strip() else f"exit {out.returncode}"
        return {"status": f"error: {tail}"}
    return json.loads(out.stdout.strip().splitlines()[-1])


def plot(rows: list[dict], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax_t, ax_m) = plt.subplots(1, 2, figsize=(9, 3.6))
    for name, marker in (("desi", "o"), ("pfs", "s")):
        pts = sorted((r["robots"], r["wall_s"], r["rss_mb"]) for r in rows if r["preset"] == name and "robots" in r)
        if pts:
            n, t, m = zip(*pts)
            ax_t.plot(n, t, marker=marker, label=name.upper())
            ax_m.plot(n, [v / 1024 for v in m], marker=marker, label=name.upper())
    ax_t.set(xlabel="robots", ylabel="wall seconds", title="time to a validated plan")
    ax_m.set(xlabel="robots", ylabel="peak RSS (GiB)", title="memory")
    for ax in (ax_t, ax_m):
        ax.grid(alpha=0.3)
        ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", default=DEFAULT_CASES, help="comma-separated preset:rings")
    ap.add_argument("--steps", default="13x7", help="alpha_steps x beta_steps")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--timeout", type=float, default=900.0, help="seconds per case")
    ap.add_argument("--out", default=str(HERE / "results" / "scale"), help="writes OUT.md, OUT.json, OUT.png")
    args = ap.parse_args()
    sys.path.insert(0, str(ROOT / "src"))
    from supcoord.study.machine import code_version, cpu_model, load, machine

    steps = tuple(int(v) for v in args.steps.lower().split("x"))
    rows, load_before, started = [], load(), time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
    for case in args.cases.split(","):
        name, rings = case.split(":")
        res = run_case(name, int(rings), args.seed, steps, args.timeout)
        row = {"preset": name, "rings": int(rings), "load": load(), **res}
        rows.append(row)
        print(json.dumps(row), flush=True)
    out = Path(args.out)
    head = ["# Time and memory with the number of robots (`bench_scale.py`)", "",
            f"Command: `python benchmarks/bench_scale.py {' '.join(sys.argv[1:])}`; supcoord {code_version()}.", "",
            f"Machine: {machine()}, {cpu_model()}; load (1 min) {load_before} before, {load()} after; "
            f"{started}. Each case in a fresh process: `solve(preset_problem(name, rings, seed={args.seed}, "
            f"alpha_steps={steps[0]}, beta_steps={steps[1]}), improve=0)`, validated; `load` is the 1-minute "
            f"load when the case ended (the machine is shared: read CPU seconds).", "",
            "| preset | rings | robots | answer | wall s | CPU s | peak RSS MB | makespan | BDD nodes | windows | "
            "validate s | load |", "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    fmt = lambda v, d=1: "" if v is None else (f"{v:.{d}f}" if isinstance(v, float) else str(v))  # noqa: E731
    for r in rows:
        head.append(f"| {r['preset']} | {r['rings']} | {r.get('robots', '')} | {r['status']} | {fmt(r.get('wall_s'))} | "
                    f"{fmt(r.get('cpu_s'))} | {fmt(r.get('rss_mb'), 0)} | {fmt(r.get('makespan'))} | "
                    f"{fmt(r.get('bdd_nodes'))} | {fmt(r.get('windows'))} | {fmt(r.get('validate_s'))} | "
                    f"{fmt(r.get('load'))} |")
    out.with_suffix(".md").write_text("\n".join(head) + "\n\n![time and memory](scale.png)\n")
    out.with_suffix(".json").write_text(json.dumps({"command": sys.argv, "rows": rows}, indent=1) + "\n")
    plot(rows, out.with_suffix(".png"))
    print(f"wrote {out.with_suffix('.md')}")


if __name__ == "__main__":
    main()
