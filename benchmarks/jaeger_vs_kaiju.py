#!/usr/bin/env python
"""The paths SDSS-V's robots would run, checked continuously: supcoord's jaeger export and kaiju's smoothed paths.

Run with supcoord's venv; kaiju runs in ``--kaiju-python`` (any Python with kaiju 1.4.1, e.g.
built by ``install-kaiju.sh``)::

    python benchmarks/jaeger_vs_kaiju.py --grids apo,lco --seeds 0-9 --kaiju-python KAIJU_PY \
        --out benchmarks/results/jaeger_paths

For every kaiju instance ``{grid}_s{seed}`` (``kaiju_side.py instances``: kaiju's random
decollided targets on the measured wok), both directions, as jaeger sends a path pair: the fold
(targets → folded lattice) and the unfold (back). Each planner plans the fold once:

* supcoord: the instrument problem with **no collision options** (the instrument's own
  definition, kaiju's), ``supcoord.solve`` with the defaults, exported with ``jaeger_paths``
  (2 RPM, 1 s delay, ``--acceleration`` limit: trapezoidal ramps) and ``jaeger_paths(...,
  reverse=True)``; each export checked by ``check_jaeger`` in its direction, and by kaiju's own
  collision check along its points (``kaiju_side.py replay``: every 0.1° of motion, kaiju's
  ``isCollided`` with its step margin). The unfold's replay is the fold's once the unfold's points
  are checked to be the fold's mirrored in time (the same poses; ``--replay-both`` replays both);
* kaiju: MDP (``kaiju_side.py plan --planner mdp``; jaeger's default planner) and the two paths
  of ``getPathPair`` jaeger sends (Savitzky–Golay smoothed, RDP simplified; 2 RPM), with the 1 s
  delay, checked by ``check_jaeger``: collisions, the first colliding pair and time, the closest
  approach.

Motion times exclude the delay: supcoord's with the acceleration profile (and without, for
reference), kaiju's the smoothed path's last time. Writes OUT.json (every row and a per-wok
summary) and OUT.md; ``--merge`` joins runs (e.g. one per wok, run side by side).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
KAIJU_SIDE = os.path.join(HERE, "kaiju_side.py")
#: supcoord export's joint acceleration limit (deg/s²): 2 RPM (12°/s) reached in 0.5 s
ACCELERATION = 24.0


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


def _check(problem, paths: dict, reverse: bool, prefix: str) -> dict:
    """``check_jaeger`` of one jaeger file as row fields named ``{prefix}_...``."""
    from supcoord.problems.validate_jaeger import check_jaeger

    c0 = time.process_time()
    res = check_jaeger(problem, paths, reverse=reverse)
    return {f"{prefix}_check_cpu_s": time.process_time() - c0, f"{prefix}_points": res.points,
            f"{prefix}_check_valid": res.valid, f"{prefix}_collisions": res.collisions,
            f"{prefix}_first_collision": res.first, f"{prefix}_min_clearance_mm": res.min_clearance_mm,
            f"{prefix}_max_speed": res.max_speed_deg_s, f"{prefix}_check_problems": res.problems[:3]}


def _replay(inst: dict, inst_path: str, paths: dict, work: str, name: str, args) -> dict:
    """kaiju's own collision check (``kaiju_side.py replay``) along a jaeger file's points."""
    plan_file = os.path.join(work, f"{name}_plan.json")
    with open(plan_file, "w") as f:
        json.dump(_as_plan(paths, inst["robot_ids"]), f)
    rep = os.path.join(work, f"{name}_replay.json")
    _run([args.kaiju_python, KAIJU_SIDE, "replay", "--instance", inst_path, "--angles", plan_file, "--out", rep])
    with open(rep) as f:
        r = json.load(f)
    return {"supcoord_kaiju_poses": r["poses"], "supcoord_kaiju_flagged": r["poses_flagged"],
            "supcoord_kaiju_min_clearance_mm": r["min_clearance_mm"]}


def _mirrored(fold: dict, back: dict) -> bool:
    """``back`` is ``fold`` run backwards in time: every joint's angle at ``T + 2·delay − t`` in ``back``
    is its angle at ``t`` in ``fold`` (at every point of either, each joint holding its last angle), so
    kaiju's replay of one visits exactly the poses of the other."""
    total = max(pts[-1][1] for p in fold.values() for pts in p.values()) + \
        min(pts[0][1] for p in fold.values() for pts in p.values())
    if fold.keys() != back.keys():
        return False
    for k in fold:
        for arm in ("alpha", "beta"):
            f, g = np.array(fold[k][arm], float), np.array(back[k][arm], float)
            g = np.stack([g[::-1, 0], total - g[::-1, 1]], axis=1)   # back, mirrored into fold's time
            t = np.union1d(f[:, 1], g[:, 1])
            if not np.allclose(np.interp(t, f[:, 1], f[:, 0]), np.interp(t, g[:, 1], g[:, 0]), rtol=0, atol=1e-9):
                return False
    return True


def rows(grid: str, seed: int, args, work: str) -> list[dict]:
    """The fold row and the unfold row of one kaiju instance.

    supcoord plans the fold once (no collision options) and exports the pair, as kaiju's
    ``getPathPair`` does: the fold (``jaeger_paths``) and the way back (``reverse=True``); kaiju's
    MDP plans the fold once and ``getPathPair`` gives its two smoothed paths.  Each of the four
    files is checked by ``check_jaeger`` in its own direction; supcoord's also by kaiju's replay.
    """
    from supcoord.planning.planner import solve
    from supcoord.problems.jaeger import jaeger_paths
    from supcoord.problems.problem import parse_problem

    inst_path = os.path.join(args.instances, f"{grid}_s{seed}.json")
    with open(inst_path) as f:
        inst = json.load(f)
    problem = parse_problem(_problem(inst))
    base = {"grid": grid, "seed": seed, "collision": problem.collision_statement()["definition"],
            "acceleration_deg_s2": args.acceleration}
    c0 = time.process_time()
    plan = solve(problem)
    base.update(supcoord_cpu_s=time.process_time() - c0, supcoord_status=plan.status)
    kp = os.path.join(work, f"{grid}_s{seed}_mdp_fold.json")
    _run([args.kaiju_python, KAIJU_SIDE, "plan", "--instance", inst_path, "--planner", "mdp", "--direction", "fold",
          "--out", kp])
    with open(kp) as f:
        k = json.load(f)
    base.update(kaiju_solved=k["solved"], kaiju_cpu_s=k["cpu_seconds"])
    out = []
    for direction, reverse, smoothed, motion in (
            ("fold", False, "path_smoothed", "motion_time_smoothed_s"),
            ("unfold", True, "path_smoothed_back", "motion_time_smoothed_back_s")):
        r = dict(base, direction=direction)
        name = f"{grid}_s{seed}_{direction}"
        if plan.status == "complete":
            exp = jaeger_paths(problem, plan, acceleration=args.acceleration, reverse=reverse)
            flat = jaeger_paths(problem, plan, reverse=reverse)
            paths = exp.to_json()
            r.update(supcoord_motion_s=exp.motion_time_s - exp.start_delay_s,
                     supcoord_motion_no_accel_s=flat.motion_time_s - flat.start_delay_s,
                     supcoord_export_max_speed=exp.max_speed_deg_s)
            r.update(_check(problem, paths, reverse, "supcoord"))
            if reverse and not args.replay_both:
                r.update({k: v for k, v in out[0].items() if k.startswith("supcoord_kaiju_")})
                r["supcoord_kaiju_replay_of"] = "fold" if _mirrored(out_paths, paths) else "fold, NOT mirrored"
            else:
                r.update(_replay(inst, inst_path, paths, work, f"{name}_supcoord", args))
                r["supcoord_kaiju_replay_of"] = direction
            out_paths = paths
            with open(os.path.join(work, f"{name}_supcoord_paths.json"), "w") as f:
                json.dump(paths, f)
        if smoothed in k:
            paths = {rid: {arm: [[d, t + 1.0] for t, d in pts] for arm, pts in p.items()}
                     for rid, p in k[smoothed].items()}
            r["kaiju_motion_s"] = k[motion]
            r.update(_check(problem, paths, reverse, "kaiju"))
            with open(os.path.join(work, f"{name}_kaiju_smoothed.json"), "w") as f:
                json.dump(paths, f)
        out.append(r)
    return out


def summary(rows: list[dict]) -> list[dict]:
    """Per wok: the counts and medians the issue asks for."""
    import statistics

    out = []
    for grid in sorted({r["grid"] for r in rows}):
        rs = [r for r in rows if r["grid"] == grid]
        done = [r for r in rs if r.get("supcoord_check_valid") is not None]
        ratios = [r["supcoord_motion_s"] / r["kaiju_motion_s"] for r in done if r.get("kaiju_motion_s")]
        ratios0 = [r["supcoord_motion_no_accel_s"] / r["kaiju_motion_s"] for r in done if r.get("kaiju_motion_s")]
        ks = [r for r in rs if r.get("kaiju_check_valid") is not None]
        cpu = [r for r in rs if r["direction"] == "fold"]
        out.append({
            "grid": grid, "instance_directions": len(rs), "seeds": sorted({r["seed"] for r in rs}),
            "supcoord_complete": sum(r["supcoord_status"] == "complete" for r in rs),
            "supcoord_check_valid": sum(bool(r.get("supcoord_check_valid")) for r in rs),
            "supcoord_kaiju_clean": sum(r.get("supcoord_kaiju_flagged") == 0 for r in rs),
            "supcoord_within_speed": sum(r.get("supcoord_max_speed", 1e9) <= 12.0 * (1 + 1e-9) for r in rs),
            "supcoord_min_clearance_mm": min((r["supcoord_min_clearance_mm"] for r in done), default=None),
            "supcoord_kaiju_min_clearance_mm": min((r["supcoord_kaiju_min_clearance_mm"] for r in done), default=None),
            "motion_ratio_median": statistics.median(ratios) if ratios else None,
            "motion_ratio_range": [min(ratios), max(ratios)] if ratios else None,
            "motion_ratio_no_accel_median": statistics.median(ratios0) if ratios0 else None,
            "supcoord_cpu_median_s": statistics.median(r["supcoord_cpu_s"] for r in cpu) if cpu else None,
            "kaiju_cpu_median_s": statistics.median(r["kaiju_cpu_s"] for r in cpu) if cpu else None,
            "kaiju_solved": sum(bool(r.get("kaiju_solved")) for r in cpu),
            "kaiju_paths_checked": len(ks),
            "kaiju_paths_colliding": sum(bool(r["kaiju_collisions"]) for r in ks),
            "kaiju_paths_invalid": sum(not r["kaiju_check_valid"] for r in ks),
            "kaiju_closest_mm": min((r["kaiju_min_clearance_mm"] for r in ks), default=None)})
    return out


def write_md(path: str, rows: list[dict], meta: dict) -> None:
    acc = meta.get("acceleration_deg_s2")
    L = ["# The paths the robots run, checked continuously (supcoord's jaeger export, kaiju's smoothed paths)", "",
         f"Command: `{_clean(meta['command'])}`; {meta['date']}; {meta.get('machine', '')}; kaiju 1.4.1. "
         "Both directions of kaiju's instances: fold (kaiju's random decollided targets → folded lattice) "
         "and unfold (back), each planner planning the fold once and sending the pair, as jaeger does "
         "(kaiju: `getPathPair`'s toDestination/fromDestination; supcoord: `jaeger_paths` and "
         "`jaeger_paths(..., reverse=True)`). Collision definition: the instrument's own (kaiju's 4.0 mm + "
         "0.0782 mm step margin between robots, 5.0 mm to fiducials and GFAs), no options. supcoord's "
         f"export: 2 RPM, 1 s delay, acceleration limit {acc} deg/s² (trapezoidal ramps); motion times "
         "exclude the 1 s delay.", ""]
    if meta.get("note"):
        L += [meta["note"], ""]
    L += ["## Per wok", "",
          "| wok | instance-directions | supcoord plans valid (continuous check of the export) | kaiju's check "
          "clean | speed ≤ 12°/s | closest approach, supcoord export (mm beyond required) | motion / kaiju MDP "
          "smoothed, median (range) | same, no acceleration limit | CPU s median supcoord / kaiju MDP "
          "| kaiju smoothed paths colliding | kaiju closest approach mm |",
          "|---|---|---|---|---|---|---|---|---|---|---|"]
    for w in summary(rows):
        n = w["instance_directions"]
        rng = w["motion_ratio_range"] or [None, None]
        L.append(f"| {w['grid']} | {n} (seeds {_seeds(w['seeds'])}) | {w['supcoord_check_valid']}/{n} | "
                 f"{w['supcoord_kaiju_clean']}/{n} | {w['supcoord_within_speed']}/{n} | "
                 f"{_f(w['supcoord_min_clearance_mm'])} | {_f(w['motion_ratio_median'])} ({_f(rng[0])}–"
                 f"{_f(rng[1])}) | {_f(w['motion_ratio_no_accel_median'])} | {_f(w['supcoord_cpu_median_s'], 1)} / "
                 f"{_f(w['kaiju_cpu_median_s'], 1)} | {w['kaiju_paths_colliding']}/{w['kaiju_paths_checked']} | "
                 f"{_f(w['kaiju_closest_mm'])} |")
    L += ["", "## Every instance-direction", "",
          "| instance | dir | supcoord: check of export | collisions | min clearance mm | kaiju replay flagged / poses "
          "| max speed °/s | motion s | kaiju MDP smoothed: check | collisions | first collision | min clearance mm "
          "| motion s |",
          "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        first = r.get("kaiju_first_collision")
        fc = (f"{'/'.join(first['positioner_ids'])} at {first['time_s']:.2f} s ({first['clearance_mm']:.2g} mm)"
              if first else "")
        L.append(f"| {r['grid']} s{r['seed']} | {r['direction']} | {r.get('supcoord_check_valid')} | "
                 f"{r.get('supcoord_collisions')} | {_f(r.get('supcoord_min_clearance_mm'))} | "
                 f"{r.get('supcoord_kaiju_flagged')} / {r.get('supcoord_kaiju_poses')} | "
                 f"{_f(r.get('supcoord_max_speed'), 2)} | {_f(r.get('supcoord_motion_s'), 2)} | "
                 f"{r.get('kaiju_check_valid')} | {r.get('kaiju_collisions')} | {fc} | "
                 f"{_f(r.get('kaiju_min_clearance_mm'))} | {_f(r.get('kaiju_motion_s'), 2)} |")
    L += ["", "Collisions count (step, pair) incidents between consecutive breakpoint times of the union of all "
          "robots' points, as `supcoord check --jaeger` does; min clearance is the closest approach beyond the "
          "required distance (negative: overlap). The required distance between robots is kaiju's own "
          "acceptance, 4.0782 mm; kaiju's `getPathPair` itself smooths with the buffers shrunk by its "
          "`collisionShrink` (0.08 mm each) and does not re-check the result (kaiju 1.4.1). kaiju replay: "
          "kaiju's `isCollided` at every 0.1° of the exported motion (`kaiju_side.py replay`). Other "
          "problems the check found in kaiju's paths (first per instance-direction; all in the JSON): "
          + "; ".join(f"{r['grid']} s{r['seed']} {r['direction']}: {p}" for r in rows
                      for p in [q for q in r.get("kaiju_check_problems", []) if "collide" not in q][:1])]
    with open(path, "w") as f:
        f.write("\n".join(L) + "\n")


def _seeds(seeds: list[int]) -> str:
    return f"{seeds[0]}–{seeds[-1]}" if seeds == list(range(seeds[0], seeds[-1] + 1)) else ",".join(map(str, seeds))


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
    ap.add_argument("--seeds", default="0-9")
    ap.add_argument("--acceleration", type=float, default=ACCELERATION,
                    help="joint acceleration limit of supcoord's export (deg/s²)")
    ap.add_argument("--instances", default="/tmp/kaiju_instances")
    ap.add_argument("--kaiju-python", required=True)
    ap.add_argument("--work", default="/tmp/jaeger_vs_kaiju_work")
    ap.add_argument("--out", default=os.path.join(HERE, "results", "jaeger_paths"))
    ap.add_argument("--replay-both", action="store_true",
                    help="run kaiju's replay on the unfold export too (default: only after checking that its "
                         "points are the fold's mirrored in time, so the replay would visit the same poses)")
    ap.add_argument("--merge", nargs="+", metavar="RUN.json", help="merge the rows of these runs into OUT; run nothing")
    ap.add_argument("--resume", action="store_true", help="keep OUT.json's rows and run only the missing ones")
    ap.add_argument("--report-only", action="store_true", help="rewrite OUT.md from OUT.json; run nothing")
    args = ap.parse_args(argv)
    if args.report_only:
        with open(args.out + ".json") as f:
            saved = json.load(f)
        write_md(args.out + ".md", saved["rows"], saved["meta"])
        return 0
    if args.merge:
        runs = []
        for path in args.merge:
            with open(path) as f:
                runs.append(json.load(f))
        merged = sorted((r for run in runs for r in run["rows"]), key=lambda r: (r["grid"], r["seed"], r["direction"]))
        meta = dict(runs[0]["meta"], runs=[run["meta"] for run in runs])
        meta["command"] = " ; ".join(run["meta"]["command"] for run in runs)
        with open(args.out + ".json", "w") as f:
            json.dump({"meta": meta, "summary": summary(merged), "rows": merged}, f, indent=1)
        write_md(args.out + ".md", merged, meta)
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
                       f"--acceleration {args.acceleration:g} --kaiju-python KAIJU_PY",
            "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
            "machine": f"{os.cpu_count()} cores, load {os.getloadavg()[0]:.1f} at the start (shared, run niced)",
            "acceleration_deg_s2": args.acceleration}
    done: list[dict] = []
    if args.resume and os.path.exists(args.out + ".json"):
        with open(args.out + ".json") as f:
            saved = json.load(f)
        done, meta = saved["rows"], saved["meta"]
    for s in seeds:
        for g in grids:
            if any(r["grid"] == g and r["seed"] == s for r in done):
                continue
            done += rows(g, s, args, args.work)
            meta["load_end"] = os.getloadavg()[0]
            print(json.dumps(done[-2:]), flush=True)
            with open(args.out + ".json", "w") as f:
                json.dump({"meta": meta, "summary": summary(done), "rows": done}, f, indent=1)
            write_md(args.out + ".md", done, meta)
    return 0


if __name__ == "__main__":
    sys.exit(main())
