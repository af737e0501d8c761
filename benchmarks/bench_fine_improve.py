"""Default plan improvement at fine lattices: the SDSS-V preset (127 robots) solved with the defaults.

Each case is ``supcoord.preset_problem("sdss-v", rings, seed, alpha_steps=A, beta_steps=B)``
solved with ``supcoord.solve(problem)`` (default improvement: single, group and pair
re-plans) in a fresh process under a timeout.  With ``--baseline SRC`` every case runs
also with the package found in ``SRC`` (another checkout's ``src`` folder, e.g. an exported
older commit), alternating with this checkout's, so the two are compared side by side under
the same load.  Writes ``results/fine_improve.md`` and ``.json`` with the command, machine
and load::

    python benchmarks/bench_fine_improve.py                                   # 24x13 and 36x19, seed 0
    python benchmarks/bench_fine_improve.py --steps 24x13 --seeds 0 1 --baseline /path/to/old/src
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
a, b, rings, seed = (int(v) for v in sys.argv[1:5])
problem = supcoord.preset_problem("sdss-v", rings=rings, seed=seed, alpha_steps=a, beta_steps=b)
t0, c0 = time.perf_counter(), time.process_time()
plan = supcoord.solve(problem)
s = plan.stats
print(json.dumps({"status": plan.status, "wall_s": time.perf_counter() - t0, "cpu_s": time.process_time() - c0,
                  "rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, "makespan": plan.makespan,
                  "lower_bound": plan.lower_bound, "replans": s.get("improve_replans"),
                  "improve_s": s.get("improve_seconds")}))
"""


def run_case(src: Path, a: int, b: int, rings: int, seed: int, timeout: float) -> dict:
    """One case in a fresh process importing supcoord from ``src``."""
    cmd = [sys.executable, "-c", CHILD, str(a), str(b), str(rings), str(seed)]
    try:
        out = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout,
                             env={"PYTHONPATH": str(src), "PATH": "/usr/bin:/bin"})
    except subprocess.TimeoutExpired:
        return {"status": f"unknown (timeout {timeout:g} s)"}
    if out.returncode != 0:
        return {"status": f"error: {out.stderr.strip().splitlines()[-1] if out.stderr.strip() else out.returncode}"}
    return json.loads(out.stdout.strip().splitlines()[-1])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", default="24x13,36x19", help="comma-separated AxB lattices")
    ap.add_argument("--rings", type=int, default=6, help="hex rings (6: 127 robots)")
    ap.add_argument("--seeds", type=int, nargs="+", default=[0])
    ap.add_argument("--baseline", default=None, help="another checkout's src folder, run side by side")
    ap.add_argument("--timeout", type=float, default=900.0, help="seconds per case")
    ap.add_argument("--out", default=str(HERE / "results" / "fine_improve"), help="writes OUT.md and OUT.json")
    args = ap.parse_args()
    sys.path.insert(0, str(ROOT / "src"))
    from supcoord.study.machine import code_version, cpu_model, load, machine

    codes = [("this", ROOT / "src")] + ([("baseline", Path(args.baseline))] if args.baseline else [])
    rows = []
    load_before = load()
    for text in args.steps.split(","):
        a, b = (int(v) for v in text.lower().split("x"))
        for seed in args.seeds:
            for name, src in codes:
                row = {"steps": text, "seed": seed, "code": name, **run_case(src, a, b, args.rings, seed, args.timeout)}
                rows.append(row)
                print(json.dumps(row), flush=True)
    argv = ["BASELINE_SRC" if args.baseline and a == args.baseline else a for a in sys.argv[1:]]
    header = {"command": "python benchmarks/bench_fine_improve.py " + " ".join(argv), "code": code_version(),
              "machine": f"{machine()}, {cpu_model()}", "load_before": load_before, "load_after": load(),
              "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())}
    Path(args.out + ".json").write_text(json.dumps({"header": header, "rows": rows}, indent=1) + "\n")
    lines = [f"# Default improvement at fine lattices: SDSS-V preset, {args.rings} rings", "",
             f"Command: `{header['command']}`; supcoord {header['code']}.", "",
             f"Machine: {header['machine']}; load {load_before} before, {header['load_after']} after; {header['date']}. "
             "Each case in a fresh process, `solve(problem)` with the defaults; `baseline` is the package given by "
             "`--baseline`, run alternately with this checkout's under the same load.", "",
             "| positions | seed | code | answer | CPU s | wall s | peak RSS MB | makespan | lower bound | re-plannings |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['steps']} | {r['seed']} | {r['code']} | {r['status']} | {r.get('cpu_s', 0):.1f} | "
                     f"{r.get('wall_s', 0):.1f} | {r.get('rss_mb', 0):.0f} | {r.get('makespan', '')} | "
                     f"{r.get('lower_bound', '')} | {r.get('replans', '')} |")
    Path(args.out + ".md").write_text("\n".join(lines) + "\n")
    print(f"written {args.out}.md")


if __name__ == "__main__":
    main()
