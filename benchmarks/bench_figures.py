"""Benchmark: writing a plan's animated GIF, blitted frames vs full redraws.

Both methods draw the same frames (same figure size, dpi, substeps, collision colouring):

- ``blit``: :func:`supcoord.figures.save_plan_gif`: the static layout drawn
  once, the arms updated in place and blitted, one shared palette without dithering, each
  frame quantised and written by Pillow;
- ``redraw``: what the first version did, ``matplotlib.animation.FuncAnimation`` clearing
  and redrawing the axes every frame, written by ``PillowWriter`` (a palette per frame).

The plans are the uncoordinated straight-line plans (every joint the short way to its
target, all at once) of random SDSS-V problems (alpha-beta 12 x 7, random start and
target): the motion of a real plan, and collisions to colour.  Each point runs in a fresh
subprocess (``--run``) with a timeout, so peak RSS is per run.

    python benchmarks/bench_figures.py                        # writes results/figures.md
    python benchmarks/bench_figures.py --rings 1 2 --out /tmp/f.md
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent


def straight_plan(problem):
    import numpy as np

    from supcoord.problems import Plan

    kin = problem.kinematics
    confs = [problem.start.copy()]
    while not np.array_equal(confs[-1], problem.target):
        step = np.clip(kin.signed_delta(confs[-1], problem.target), -1, 1)
        confs.append(kin.wrap(confs[-1] + step))
    return Plan("complete", confs)


def redraw_gif(problem, plan, path, substeps=4, fps=10, dpi=80):
    """The first version's method: a full redraw of every frame through FuncAnimation."""
    from matplotlib.animation import FuncAnimation, PillowWriter

    from supcoord.figures.problem_figures import add_legend, draw_layout, new_figure, plot_configuration, plot_target, plt
    from supcoord.figures.plan_figures import interpolate_plan

    frames = interpolate_plan(problem, plan, substeps)
    fig, ax = new_figure(problem, 4.0, legend_width=1.6)

    def draw(i):
        ax.clear()
        q = frames[i]
        hits = {p for a, b, _ in problem.collisions(q) for p in (a, b)}
        draw_layout(ax, problem, f"step {i / substeps:.2f}", numbers=problem.n <= 60)
        plot_target(ax, problem)
        plot_configuration(ax, problem, q, highlight=hits)
        add_legend(ax, problem.kinematics.kind, ["collision"], loc="upper left", bbox_to_anchor=(1.02, 1.0),
                   fontsize=6)

    anim = FuncAnimation(fig, draw, frames=len(frames), interval=1000 // fps)
    anim.save(str(path), writer=PillowWriter(fps=fps), dpi=dpi)
    plt.close(fig)


def run_one(rings: int, method: str, seed: int) -> dict:
    from supcoord.figures import save_plan_gif
    from supcoord.problems import preset_problem

    problem = preset_problem("sdss-v", rings=rings, seed=seed, alpha_steps=12, beta_steps=7)
    plan = straight_plan(problem)
    path = Path(tempfile.mkdtemp()) / "plan.gif"
    t0 = time.perf_counter()
    if method == "blit":
        save_plan_gif(problem, plan, path, substeps=4, fps=10, dpi=80)
    else:
        redraw_gif(problem, plan, path, substeps=4, fps=10, dpi=80)
    seconds = time.perf_counter() - t0
    from PIL import Image

    frames = Image.open(path).n_frames
    return {"rings": rings, "positioners": problem.n, "method": method, "steps": len(plan.configurations) - 1,
            "frames": frames, "seconds": seconds, "kbytes": path.stat().st_size / 1e3,
            "peak_mib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}


def machine() -> dict:
    cpu = "unknown"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    ram = "unknown"
    try:
        kib = int(Path("/proc/meminfo").read_text().split()[1])
        ram = f"{kib / 2**20:.1f} GiB"
    except (OSError, ValueError, IndexError):
        pass
    uptime = subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()
    return {"nproc": os.cpu_count(), "ram": ram, "cpu": cpu, "python": platform.python_version(), "uptime": uptime}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rings", type=int, nargs="+", default=[1, 2, 3, 6])
    ap.add_argument("--methods", nargs="+", default=["blit", "redraw"], choices=["blit", "redraw"])
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--timeout", type=float, default=600)
    ap.add_argument("--out", default=str(HERE / "results" / "figures.md"))
    ap.add_argument("--run", nargs=3, metavar=("RINGS", "METHOD", "SEED"), help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.run:
        print(json.dumps(run_one(int(args.run[0]), args.run[1], int(args.run[2]))))
        return
    before = machine()
    rows = []
    print(f"{'robots':>6} {'method':>7} {'steps':>5} {'frames':>6} {'seconds':>8} {'kB':>7} {'peak MiB':>8}")
    for rings in args.rings:
        for method in args.methods:
            cmd = [sys.executable, __file__, "--run", str(rings), method, str(args.seed)]
            try:
                proc = subprocess.run(cmd, capture_output=True, text=True, timeout=args.timeout)
                row = json.loads(proc.stdout.strip().splitlines()[-1])
            except subprocess.TimeoutExpired:
                row = {"rings": rings, "positioners": 1 + 3 * rings * (rings + 1), "method": method, "timeout": True}
            rows.append(row)
            if row.get("timeout"):
                print(f"{row['positioners']:>6} {method:>7}  timeout after {args.timeout:g} s")
            else:
                print(f"{row['positioners']:>6} {method:>7} {row['steps']:>5} {row['frames']:>6} {row['seconds']:>8.2f} "
                      f"{row['kbytes']:>7.0f} {row['peak_mib']:>8.0f}", flush=True)
    after = machine()
    lines = ["# Animated GIF of a plan: blitted frames (save_plan_gif) vs full redraws (FuncAnimation)", "",
             f"Command: `python benchmarks/{Path(__file__).name} {' '.join(sys.argv[1:])}`".rstrip(), "",
             f"Date: {time.strftime('%Y-%m-%d %H:%M:%S %Z')}; machine: {before['nproc']} CPUs ({before['cpu']}), "
             f"{before['ram']} RAM, Python {before['python']}.", "",
             f"Load before: `{before['uptime']}`; after: `{after['uptime']}` (the machine is shared: seconds are "
             "noisy, the ratio within a row pair is what to read).", "",
             "Problems: `preset_problem('sdss-v', rings, seed=1, alpha_steps=12, beta_steps=7)`, the uncoordinated "
             "straight-line plan, 4 substeps a step, dpi 80, both methods colouring collisions. BDD nodes: not "
             "applicable (no symbolic work).", "",
             "| robots | steps | frames | blit s | redraw s | speed-up | blit kB | redraw kB | blit peak MiB | redraw peak MiB |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    by = {(r["rings"], r["method"]): r for r in rows}
    for rings in args.rings:
        b, r = by.get((rings, "blit"), {}), by.get((rings, "redraw"), {})
        def cell(row, key, fmt):
            return "timeout" if row.get("timeout") else (format(row[key], fmt) if key in row else "-")
        speed = (f"{r['seconds'] / b['seconds']:.1f}x" if "seconds" in b and "seconds" in r else "-")
        ref = b if "steps" in b else r
        lines.append(f"| {ref.get('positioners', '-')} | {ref.get('steps', '-')} | {ref.get('frames', '-')} | "
                     f"{cell(b, 'seconds', '.2f')} | {cell(r, 'seconds', '.2f')} | {speed} | {cell(b, 'kbytes', '.0f')} | "
                     f"{cell(r, 'kbytes', '.0f')} | {cell(b, 'peak_mib', '.0f')} | {cell(r, 'peak_mib', '.0f')} |")
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    Path(args.out).write_text("\n".join(lines) + "\n")
    print(f"written to {args.out}")


if __name__ == "__main__":
    main()
