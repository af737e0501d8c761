#!/usr/bin/env python
"""The paths SDSS-V's robots would run, checked continuously: supcoord's jaeger export and kaiju's smoothed paths.

Run with supcoord's venv; kaiju runs in ``--kaiju-python`` (any Python
with kaiju 1.4.1, e.g. built by ``install-kaiju.sh``)::

    python benchmarks/jaeger_vs_kaiju.py --grids apo,lco --seeds 0-2 --kaiju-python KAIJU_PY \
        --out benchmarks/results/jaeger_paths

For every kaiju instance ``{grid}_s{seed}`` (``kaiju_side.py instances``: kaiju's random
decollided targets on the measured wok) in the fold direction (targets → folded lattice; the
unfold is the same motion backwards in time, kaiju's ``fromDestination`` and supcoord's
``--jaeger-reverse``, so it meets the same poses):

* supcoord: the instrument problem with **no collision options** (the instrument's own
  definition, kaiju's), ``supcoord.solve`` with the defaults, exported with
  ``jaeger_paths`` (2 RPM, 1 s delay), then (1) ``check_jaeger`` on the exported points and
  (2) kaiju's own collision check along those points (``kaiju_side.py replay``: every 0.1°
  of motion, kaiju's ``isCollided`` with its step margin);
* kaiju: MDP (``kaiju_side.py plan --planner mdp``; jaeger's default planner) and the
  ``getPathPair`` path jaeger sends (Savitzky–Golay smoothed, RDP simplified; 2 RPM),
  converted to jaeger's format with the 1 s delay and checked by ``check_jaeger``:
  collisions, the first colliding pair and time, the closest approach.

Writes OUT.json (every row) and OUT.md (the table).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
KAIJU_SIDE = os.path.join(HERE, "kaiju_side.py")


def _run(cmd: list[str]) -> None:
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode:
        raise RuntimeError(f"{' '.join(cmd)} failed: {r.stderr[-2000:]}")


def _problem(inst: dict) -> dict:
    return {"layout": {"kind": "instrument", "name": f"sdss-v-{inst['grid']}"},
            "start": {"alpha_beta_deg": inst["targets_deg"]},
            "target": {"alpha_beta_deg": [inst["folded_lattice_deg"]] * len(inst["targets_deg"])}}


def _as_plan(paths: dict, order: list[int]) -> dict:
    """A jaeger file as PLAN.json trajectories in the instance's robot order (for kaiju's replay)."""
    return {"status": "complete", "trajectories": [
        {arm: [[t, a] for a, t in paths[str(rid)][arm]] for arm in ("alpha", "beta")} for rid in order]}


def row(grid: str, seed: int, args, work: str) -> dict:
    from supcoord.planning.planner import solve
    from supcoord.problems.jaeger import jaeger_paths
    from supcoord.problems.problem import parse_problem
    from supcoord.problems.validate_jaeger import check_jaeger

    inst_path = os.path.join(args.instances, f"{grid}_s{seed}.json")
    with open(inst_path) as f:
        inst = json.load(f)
    problem = parse_problem(_problem(inst))
    out: dict = {"grid": grid, "seed": seed, "direction": "fold",
                 "collision": problem.collision_statement()["definition"]}
    # supcoord, no collision options
    c0 = time.process_time()
    plan = solve(problem)
    out["supcoord_cpu_s"] = time.process_time() - c0
    out["supcoord_status"] = plan.status
    if plan.status == "complete":
        exp = jaeger_paths(problem, plan)
        res = check_jaeger(problem, exp.to_json())
        out.update(supcoord_motion_s=exp.motion_time_s - exp.start_delay_s, supcoord_points=exp.points,
                   supcoord_max_speed=exp.max_speed_deg_s, supcoord_check_valid=res.valid,
                   supcoord_collisions=res.collisions, supcoord_min_clearance_mm=res.min_clearance_mm,
                   supcoord_check_problems=res.problems[:3])
        plan_file = os.path.join(work, f"{grid}_s{seed}_supcoord_plan.json")
        with open(plan_file, "w") as f:
            json.dump(_as_plan(exp.to_json(), inst["robot_ids"]), f)
        rep = os.path.join(work, f"{grid}_s{seed}_supcoord_replay.json")
        _run([args.kaiju_python, KAIJU_SIDE, "replay", "--instance", inst_path, "--angles", plan_file,
              "--out", rep])
        with open(rep) as f:
            r = json.load(f)
        out.update(supcoord_kaiju_poses=r["poses"], supcoord_kaiju_flagged=r["poses_flagged"],
                   supcoord_kaiju_min_clearance_mm=r["min_clearance_mm"])
    # kaiju MDP and its smoothed path
    kp = os.path.join(work, f"{grid}_s{seed}_mdp_fold.json")
    _run([args.kaiju_python, KAIJU_SIDE, "plan", "--instance", inst_path, "--planner", "mdp", "--direction", "fold",
          "--out", kp])
    with open(kp) as f:
        k = json.load(f)
    out.update(kaiju_solved=k["solved"], kaiju_cpu_s=k["cpu_seconds"], kaiju_motion_s=k.get("motion_time_smoothed_s"))
    if "path_smoothed" in k:
        paths = {rid: {arm: [[d, t + 1.0] for t, d in pts] for arm, pts in p.items()}
                 for rid, p in k["path_smoothed"].items()}
        res = check_jaeger(problem, paths)
        out.update(kaiju_points=res.points, kaiju_check_valid=res.valid, kaiju_collisions=res.collisions,
                   kaiju_first_collision=res.first, kaiju_min_clearance_mm=res.min_clearance_mm,
                   kaiju_max_speed=res.max_speed_deg_s, kaiju_check_problems=res.problems[:3])
        with open(os.path.join(work, f"{grid}_s{seed}_kaiju_smoothed.json"), "w") as f:
            json.dump(paths, f)
    return out


def write_md(path: str, rows: list[dict], meta: dict) -> None:
    L = ["# The paths the robots run, checked continuously (supcoord's jaeger export, kaiju's smoothed paths)", "",
         f"Command: `{_clean(meta['command'])}`; {meta['date']}; kaiju 1.4.1. Fold direction (the "
         "unfold is the same motion backwards). Collision definition: the instrument's own (kaiju's 4.0 mm + "
         "0.0782 mm step margin between robots, 5.0 mm to fiducials and GFAs), no options.", "",
         "| instance | supcoord: check of export | collisions | min clearance mm | kaiju replay flagged / poses "
         "| motion s | kaiju MDP smoothed: check | collisions | first collision | min clearance mm | motion s |",
         "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        first = r.get("kaiju_first_collision")
        fc = (f"{'/'.join(first['positioner_ids'])} at {first['time_s']:.2f} s ({first['clearance_mm']:.2g} mm)"
              if first else "")
        L.append(f"| {r['grid']} s{r['seed']} | {r.get('supcoord_check_valid')} | {r.get('supcoord_collisions')} | "
                 f"{_f(r.get('supcoord_min_clearance_mm'))} | {r.get('supcoord_kaiju_flagged')} / "
                 f"{r.get('supcoord_kaiju_poses')} | {_f(r.get('supcoord_motion_s'))} | {r.get('kaiju_check_valid')} | "
                 f"{r.get('kaiju_collisions')} | {fc} | {_f(r.get('kaiju_min_clearance_mm'))} | "
                 f"{_f(r.get('kaiju_motion_s'))} |")
    bad = [r for r in rows if r.get("kaiju_collisions")]
    L += ["", f"kaiju smoothed paths with a collision: {len(bad)} of {sum('kaiju_collisions' in r for r in rows)}; "
          f"closest approach {_f(min((r['kaiju_min_clearance_mm'] for r in rows if r.get('kaiju_min_clearance_mm') is not None), default=None))} mm "
          "beyond the required distance (negative: overlap).", "",
          "Collisions count (step, pair) incidents between consecutive breakpoint times of the union of all "
          "robots' points, as `supcoord check` does. The required distance between robots is kaiju's own "
          "acceptance, 4.0782 mm; kaiju's `getPathPair` itself smooths with the buffers shrunk by its "
          "`collisionShrink` (0.08 mm each) and does not re-check the result (kaiju 1.4.1). Other problems "
          "found (first three per instance, in OUT.json): "
          + "; ".join(f"{r['grid']} s{r['seed']}: {p}" for r in rows for p in r.get("kaiju_check_problems", [])
                      if "collide" not in p)]
    with open(path, "w") as f:
        f.write("\n".join(L) + "\n")


def _clean(command: str) -> str:
    """The command without this machine's paths."""
    words, out, skip = command.split(), [], False
    for w in words:
        if skip:
            skip = False
            continue
        if w in ("--instances", "--work", "--out"):
            skip = True
            continue
        out.append("KAIJU_PY" if w.endswith("/python") else w)
    return " ".join(out)


def _f(v, nd=3):
    return "" if v is None else f"{v:.{nd}f}"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--grids", default="apo,lco")
    ap.add_argument("--seeds", default="0-2")
    ap.add_argument("--instances", default="/tmp/kaiju_instances")
    ap.add_argument("--kaiju-python", required=True)
    ap.add_argument("--work", default="/tmp/jaeger_vs_kaiju_work")
    ap.add_argument("--out", default=os.path.join(HERE, "results", "jaeger_paths"))
    ap.add_argument("--report-only", action="store_true", help="rewrite OUT.md from OUT.json; run nothing")
    args = ap.parse_args(argv)
    if args.report_only:
        with open(args.out + ".json") as f:
            saved = json.load(f)
        write_md(args.out + ".md", saved["rows"], saved["meta"])
        return 0
    lo, _, hi = args.seeds.partition("-")
    seeds = range(int(lo), int(hi or lo) + 1)
    os.makedirs(args.work, exist_ok=True)
    os.makedirs(args.instances, exist_ok=True)
    grids = args.grids.split(",")
    missing = [g for g in grids for s in seeds if not os.path.exists(os.path.join(args.instances, f"{g}_s{s}.json"))]
    if missing:
        _run([args.kaiju_python, KAIJU_SIDE, "instances", "--out", args.instances, "--seeds", str(max(seeds) + 1),
              "--grids", ",".join(sorted(set(missing)))])
    meta = {"command": f"python benchmarks/jaeger_vs_kaiju.py --grids {args.grids} --seeds {args.seeds} "
                       "--kaiju-python KAIJU_PY",
            "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())}
    rows = []
    for s in seeds:
        for g in grids:
            rows.append(row(g, s, args, args.work))
            print(json.dumps(rows[-1]), flush=True)
            with open(args.out + ".json", "w") as f:
                json.dump({"meta": meta, "rows": rows}, f, indent=1)
            write_md(args.out + ".md", rows, meta)
    return 0


if __name__ == "__main__":
    sys.exit(main())
