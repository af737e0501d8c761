#!/usr/bin/env python
"""supcoord vs SDSS-V's kaiju on kaiju's own instances (run with supcoord's venv).

::

    source .venv/bin/activate
    PY=$KAIJU_PYTHON   # a venv with kaiju: ../shared/tools/install-kaiju.sh PYTHON
    $PY benchmarks/kaiju_side.py instances --out /tmp/kaiju_instances --seeds 10 --grids hex61,hex127,apo,lco
    nice python benchmarks/vs_kaiju.py --grids hex61 --seeds 0-2 --timeout 300 \
        --reuse /tmp/kaiju_meas --out benchmarks/results/vs_kaiju [--append] [--steps 37x19]

kaiju runs only through ``subprocess`` with kaiju's venv (``--kaiju-python``, default
``$KAIJU_PYTHON``) and ``benchmarks/kaiju_side.py``. For every instance
``{grid}_s{seed}.json`` of ``--instances`` and every direction (``fold``: kaiju's random
targets -> folded lattice (10, 170) deg; ``unfold``: lattice -> targets):

* supcoord: a PROBLEM.json is built (below), ``supcoord solve PROBLEM --out PLAN --speed 12
  --json -q --timeout T --max-memory 8G`` runs as a child process (CPU = user + system time
  from ``resource.getrusage(RUSAGE_CHILDREN)`` deltas; peak RSS = the child's ``ru_maxrss``
  from ``os.wait4``), then ``supcoord check PROBLEM PLAN --json`` and kaiju's own collision
  check (``kaiju_side.py replay --buffer 2.0 --ang-step 0.1``) along the plan's timed
  trajectories (what the robots do: each at its own pace), every 0.1° of the fastest joint.
* kaiju: ``kaiju_side.py plan --planner greedy|mdp --direction fold|unfold`` (a result file
  ``{grid}_s{seed}_{planner}_{direction}.json`` in ``--reuse`` is used instead when present;
  kaiju's unfold is by construction its fold path reversed in time, planned by the same call,
  so a reused fold file also gives the unfold row, marked ``derived from fold``).

Problem built for supcoord:

* hex grids: ``{"kind": "points"}`` layout with every kaiju base rotated by +90 deg,
  (x, y) -> (-y, x) (kaiju's alpha = 0 points along wok -y, supcoord's along +x; collisions
  are invariant under the rotation, so the angles mean the same), alpha-beta kinematics with
  alpha 7.4 mm, beta 14.7276 mm (kaiju's beta collision segment from the elbow), alpha range
  [0, 360], beta range [0, 180], buffer 2.0 mm.
* apo, lco: ``{"kind": "instrument", "name": "sdss-v-apo"}`` (or ``sdss-v-lco``; kaiju's
  geometry, fiducials, GFAs and fiducial rule built in; robots in positionerTable row order =
  the instance's order). ``--timeout-apo`` bounds both woks.
* ``collision.margin`` = kaiju's maxDisplacement at its 0.1 deg step (0.0782 mm): kaiju
  flags two robots closer than 4.0 + 0.0782 mm, so supcoord is asked to keep that distance;
  ``obstacle_margin`` 0 on the wok (kaiju flags a robot closer than 5.0 mm to a fiducial or
  GFA, with no step margin: its own targets may lie 5.001 mm from a fiducial).
* steps: ``--steps AxB`` sets ``alpha_steps`` x ``beta_steps`` (default 37x19 = 10 deg steps,
  the instrument's default); starts/targets are exact angles (``alpha_beta_deg``). Where
  supcoord planned on a finer lattice (``supcoord.problems.refine``: the asked one had only a
  single-move certificate) the steps column shows it (``13x7 → 19x10``).

Writes ``OUT.json`` (every row, the header and the raw sub-results) and ``OUT.md``.
``--append`` merges with the rows already in ``OUT.json`` (same key replaced), so a long
campaign can run grid by grid; the header keeps every command line.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import resource
import shlex
import signal
import statistics
import subprocess
import sys
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))
KAIJU_SIDE = os.path.join(HERE, "kaiju_side.py")
SPEED = 12.0  # deg/s = kaiju's 2 RPM
MARGIN = 0.0782  # kaiju maxDisplacement at 0.1 deg (0.07819 mm), rounded up
HEX_ALPHA, HEX_BETA = 7.4, 14.727625158384331


def _fail(msg: str, code: int = 2):
    print(f"vs_kaiju: error: {msg}", file=sys.stderr)
    sys.exit(code)


def parse_seeds(s: str) -> list[int]:
    out = []
    for part in s.split(","):
        if "-" in part:
            a, b = part.split("-")
            out += list(range(int(a), int(b) + 1))
        elif part:
            out.append(int(part))
    return out


def build_problem(inst: dict, direction: str, steps: tuple[int, int] | None) -> dict:
    targets, folded = inst["targets_deg"], inst["folded_deg"]
    start, target = (targets, folded) if direction == "fold" else (folded, targets)
    kin = {}
    if steps:
        kin = {"alpha_steps": steps[0], "beta_steps": steps[1]}
    if inst["kind"] == "hex":
        xy = [[-y, x] for x, y in inst["base_xy_mm"]]
        kin = {"kind": "alpha-beta", "alpha": HEX_ALPHA, "beta": HEX_BETA,
               "alpha_steps": 37, "beta_steps": 19, **kin,
               "alpha_range": [0, 360], "beta_range": [0, 180]}
        prob = {"layout": {"kind": "points", "xy": xy}, "kinematics": kin,
                "collision": {"buffer": 2.0, "margin": MARGIN}}
    elif inst["grid"] in ("apo", "lco"):
        prob = {"layout": {"kind": "instrument", "name": f"sdss-v-{inst['grid']}"},
                "collision": {"margin": MARGIN, "obstacle_margin": 0.0}}
        if kin:
            prob["kinematics"] = kin
    else:
        _fail(f"no supcoord layout for grid {inst['grid']}")
    prob["start"] = {"alpha_beta_deg": start}
    prob["target"] = {"alpha_beta_deg": target}
    prob["name"] = f"{inst['grid']}_s{inst['seed']}_{direction}"
    prob["_comment"] = "built by benchmarks/vs_kaiju.py from a kaiju_side.py instance"
    return prob


def run_child(cmd: list[str], stdout_path: str, stderr_path: str, hard_timeout: float) -> dict:
    """Run cmd; wall, CPU (RUSAGE_CHILDREN delta), peak RSS (wait4), exit code."""
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    w0 = time.perf_counter()
    with open(stdout_path, "w") as fo, open(stderr_path, "w") as fe:
        p = subprocess.Popen(cmd, stdout=fo, stderr=fe, start_new_session=True)
        killed = []

        def kill():
            killed.append(True)
            try:
                os.killpg(p.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass

        timer = threading.Timer(hard_timeout, kill)
        timer.start()
        _, status, ru = os.wait4(p.pid, 0)
        timer.cancel()
        p.returncode = os.waitstatus_to_exitcode(status)
    wall = time.perf_counter() - w0
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    return {"rc": p.returncode, "wall_s": wall, "cpu_s": cpu, "peak_rss_mb": ru.ru_maxrss / 1024.0,
            "hard_killed": bool(killed)}


def load_json(path: str):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def supcoord_row(args, inst, direction, work) -> tuple[dict, dict]:
    tag = f"{inst['grid']}_s{inst['seed']}_{direction}"
    steps_tag = f"{args.steps[0]}x{args.steps[1]}" if args.steps else "default"
    base = os.path.join(work, f"{tag}_{steps_tag}")
    prob_path, plan_path = base + ".problem.json", base + ".plan.json"
    with open(prob_path, "w") as f:
        json.dump(build_problem(inst, direction, args.steps), f)
    if os.path.exists(plan_path):
        os.remove(plan_path)
    timeout = args.timeout_apo if inst["grid"] in ("apo", "lco") else args.timeout
    cmd = ["nice", args.supcoord, "solve", prob_path, "--out", plan_path, "--speed", str(SPEED),
           "--json", "-q", "--timeout", str(timeout), "--max-memory", args.max_memory]
    if args.improve is not None:
        cmd += ["--improve", str(args.improve)]
    print(f"[{time.strftime('%H:%M:%S')}] supcoord {tag} steps {steps_tag}", file=sys.stderr, flush=True)
    res = run_child(cmd, base + ".solve.out", base + ".solve.err", timeout + 300)
    out = load_json(base + ".solve.out") or {}
    status = out.get("status")
    row = {"planner": "supcoord", "steps": steps_tag, "improve": args.improve, "timeout_s": timeout, "rc": res["rc"],
           "status": status, "cpu_s": res["cpu_s"], "wall_s": res["wall_s"],
           "peak_rss_mb": res["peak_rss_mb"], "command": shlex.join(portable(c, run_places(args)) for c in cmd)}
    raw = {"solve": {k: v for k, v in out.items() if k in ("status", "makespan", "lower_bound", "reason",
                                                          "stats", "motion_time_s", "stage")}}
    if res["hard_killed"]:
        row["status"] = status = "killed"
    if status == "complete":
        row["solved"] = "yes"
        row["motion_time_s"] = out.get("motion_time_s")
        row["makespan_steps"] = out.get("makespan")
        row["lower_bound_steps"] = out.get("lower_bound")
        if out.get("lattice"):  # solve refined the lattice (a single-move certificate on the asked one)
            row["lattice"] = "x".join(str(s) for s in out["lattice"])
    elif status == "infeasible":
        row["solved"] = "no (infeasible, certified)"
    elif res["rc"] == 3 or status in (None, "timeout", "unknown", "killed"):
        err = open(base + ".solve.err").read()[-400:]
        why = out.get("reason") or err.strip().splitlines()[-1:] or [""]
        why = why if isinstance(why, str) else why[0]
        if "memory" in why.lower() or out.get("stage") == "memory":
            row["solved"] = f"unknown (memory limit {args.max_memory})"
        elif "node" in why.lower():
            row["solved"] = "unknown (BDD node budget)"
        elif res["rc"] == 3 or status == "killed":
            row["solved"] = f"unknown (timeout {timeout} s)"
        else:
            row["solved"] = f"error (exit {res['rc']})"
        row["reason"] = why[:300]
    else:
        row["solved"] = f"{status} (exit {res['rc']})"
    if status == "complete" and os.path.exists(plan_path):
        # supcoord's own check
        c = run_child(["nice", args.supcoord, "check", prob_path, plan_path, "--json", "-q",
                       "--timeout", "900"], base + ".check.out", base + ".check.err", 1200)
        chk = load_json(base + ".check.out") or {}
        raw["check"] = chk
        row["check"] = ("valid" if chk.get("valid") else f"INVALID ({chk.get('collisions')} collisions, "
                        f"{chk.get('problems')})") if chk else f"check failed (exit {c['rc']})"
        row["check_wall_s"] = c["wall_s"]
        # kaiju's own collision check of the plan's angles
        rep = base + ".replay.json"
        r = run_child(["nice", args.kaiju_python, KAIJU_SIDE, "replay", "--instance", inst["_path"],
                       "--angles", plan_path, "--out", rep, "--buffer", "2.0", "--ang-step", "0.1"],
                      base + ".replay.out", base + ".replay.err", 1800)
        rj = load_json(rep)
        if rj:
            row["kaiju_replay_poses"] = rj["poses"]
            row["kaiju_replay_flagged"] = rj["poses_flagged"]
            row["kaiju_replay_robots_flagged"] = rj["robots_flagged"]
            row["kaiju_replay_min_clearance_mm"] = rj["min_clearance_mm"]
            raw["replay"] = {k: rj[k] for k in ("poses", "poses_flagged", "robots_flagged", "min_clearance_mm",
                                                "min_clearance_by_kind_mm", "max_displacement_mm",
                                                "first_flagged") if k in rj}
        else:
            row["kaiju_replay_flagged"] = f"replay failed (exit {r['rc']})"
        row["replay_wall_s"] = r["wall_s"]
        # robots off target in the final configuration (by supcoord's check)
        row["off_target"] = (len(inst["robot_ids"]) - chk["at_target"]) if "at_target" in chk else None
    print(f"[{time.strftime('%H:%M:%S')}]   -> {row['solved']} cpu {row['cpu_s']:.1f} s wall "
          f"{row['wall_s']:.1f} s rss {row['peak_rss_mb']:.0f} MB motion {row.get('motion_time_s')} "
          f"replay flagged {row.get('kaiju_replay_flagged')}", file=sys.stderr, flush=True)
    return row, raw


def kaiju_row(args, inst, planner, direction, work) -> dict:
    tag = f"{inst['grid']}_s{inst['seed']}_{planner}"
    src, derived = None, False
    if args.reuse:
        p = os.path.join(args.reuse, f"{tag}_{direction}.json")
        if os.path.exists(p):
            src = p
        elif direction == "unfold" and os.path.exists(os.path.join(args.reuse, f"{tag}_fold.json")):
            src, derived = os.path.join(args.reuse, f"{tag}_fold.json"), True
    cmd_wall = None
    if src is None:
        src = os.path.join(work, f"{tag}_{direction}.kaiju.json")
        cmd = ["nice", args.kaiju_python, KAIJU_SIDE, "plan", "--instance", inst["_path"], "--planner", planner,
               "--direction", direction, "--out", src]
        print(f"[{time.strftime('%H:%M:%S')}] kaiju {tag} {direction}", file=sys.stderr, flush=True)
        res = run_child(cmd, src + ".out", src + ".err", 3600)
        cmd_wall = res["wall_s"]
        if res["rc"] != 0:
            return {"planner": f"kaiju-{planner}", "solved": f"error (exit {res['rc']})",
                    "reason": open(src + ".err").read()[-300:]}
    k = load_json(src)
    row = {"planner": f"kaiju-{planner}", "solved": "yes" if k["solved"] else "no (kaiju failed)",
           "deadlocked": len(k["deadlocked"]), "off_target": len(k["off_target"]),
           "cpu_s": k["cpu_seconds"], "wall_s": k["wall_seconds"],
           "motion_time_s": k["motion_time_s"], "motion_time_smoothed_s": k.get("motion_time_smoothed_s"),
           "n_steps": k["n_steps"], "source": portable(os.path.abspath(src), run_places(args)) + (
               " (fold, reversed: derived from fold)" if derived else ""),
           "command_wall_s": cmd_wall}
    return row


#: what the directories of a run stand for in the commands a results file records
PLACES_NOTE = ("In the commands, `$KAIJU_PYTHON` is the Python of kaiju's virtualenv, `$INSTANCES` the "
               "directory of `kaiju_side.py instances`, `$WORK` the working directory, `$REUSE` a directory of "
               "`kaiju_side.py plan` results and `$OUT` where the results were written before they were copied "
               "here; `supcoord` is the supcoord command of the run.")


def portable(arg: str, places: dict[str, str]) -> str:
    """``arg`` of a recorded command without this machine's paths (results files are read elsewhere).

    A path under one of ``places`` (directory or file -> the name it stands for, e.g. ``"$WORK"``)
    is written under that name, another absolute path inside the repository relative to its
    root, any other absolute path as ``$OUT/`` and its file name; ``--opt=PATH`` likewise.
    """
    if arg.startswith("--") and "=" in arg:
        opt, value = arg.split("=", 1)
        return f"{opt}={portable(value, places)}"
    if not os.path.isabs(arg):
        return arg
    real = os.path.abspath(arg)
    for path, name in sorted(places.items(), key=lambda kv: -len(kv[0])):
        path = os.path.abspath(path)
        if real == path or real.startswith(path.rstrip(os.sep) + os.sep):
            return name + real[len(path.rstrip(os.sep)):]
    repo = os.path.dirname(HERE)
    if real.startswith(repo + os.sep):
        return os.path.relpath(real, repo)
    return "$OUT/" + os.path.basename(real)


def run_places(args) -> dict[str, str]:
    """:func:`portable`'s names for the run's directories and programs."""
    places = {args.work: "$WORK", args.instances: "$INSTANCES", args.kaiju_python: "$KAIJU_PYTHON",
              args.supcoord: "supcoord"}
    if args.reuse:
        places[args.reuse] = "$REUSE"
    return places


def machine_info() -> dict:
    model = ""
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return {"nproc": os.cpu_count(), "uname_m": platform.machine(), "cpu_model": model,
            "python": platform.python_version(),
            "supcoord_version": subprocess.run([sys.executable, "-c", "import supcoord;print(supcoord.__version__)"],
                                               capture_output=True, text=True).stdout.strip()}


def uptime() -> str:
    return time.strftime("%H:%M:%S UTC", time.gmtime()) + " " + \
        subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip().split("load average")[-1]


def fmt(v, nd=2):
    if v is None or v == "":
        return ""
    if isinstance(v, float):
        return f"{v:.{nd}f}"
    return str(v)


def ratio_rows(rows: list[dict]) -> None:
    """Attach supcoord/kaiju-mdp (and -greedy) ratios to the supcoord rows."""
    idx = {(r["grid"], r["seed"], r["direction"], r["planner"]): r for r in rows}
    for r in rows:
        if r["planner"] != "supcoord":
            continue
        for kp in ("mdp", "greedy"):
            k = idx.get((r["grid"], r["seed"], r["direction"], f"kaiju-{kp}"))
            if not k or "cpu_s" not in k:
                continue
            if k.get("cpu_s"):
                r[f"cpu_ratio_{kp}"] = r["cpu_s"] / k["cpu_s"]
            if r.get("solved") == "yes" and k.get("solved") == "yes":
                r[f"motion_ratio_{kp}"] = r["motion_time_s"] / k["motion_time_s"]


def dist(vals: list[float]) -> str:
    if not vals:
        return "no instance solved by both"
    g = math.exp(sum(math.log(v) for v in vals) / len(vals))
    return (f"n = {len(vals)}: min {min(vals):.3f}, median {statistics.median(vals):.3f}, "
            f"geometric mean {g:.3f}, max {max(vals):.3f}")


def write_md(path: str, data: dict) -> None:
    rows = data["rows"]
    h = data["header"]
    L = ["# supcoord vs kaiju (SDSS-V's planner) on kaiju's instances", "",
         "Generated by `benchmarks/vs_kaiju.py` (see its docstring for the method). " + PLACES_NOTE, "",
         "## Runs", ""]
    for run in h["runs"]:
        L += [f"- `{run['command']}`", f"  - date {run['date']}; load at start {run['load_start']}, "
              f"at end {run.get('load_end', '(interrupted)')}"]
    m = h["machine"]
    L += ["", f"Machine: `nproc` = {m['nproc']}, `uname -m` = {m['uname_m']}, CPU {m['cpu_model']}, "
          f"Python {m['python']} (supcoord {m['supcoord_version']}); kaiju 1.4.1 in its own venv. The 2 cores "
          "are shared with other jobs: wall times are inflated, CPU s is the better figure.", "",
          "supcoord problems: collision.margin 0.0782 mm (kaiju's maxDisplacement at its 0.1° step: kaiju "
          "flags two robots closer than 4.0 + 0.0782 mm, so the margin is what lets supcoord's plans pass "
          "kaiju's check); `--speed 12` (kaiju's 2 RPM); `--max-memory " + h.get("max_memory", "8G") +
          "`. kaiju rows: raw path motion time (steps × 0.1°/12°/s); smoothed motion in its own column. "
          "kaiju's unfold is its fold path reversed (same planning call); supcoord plans unfold directly.", "",
          "## Results", "",
          "| grid | seed | direction | planner | steps | solved | deadlocked | off target | CPU s | wall s | "
          "motion s (12°/s) | kaiju smoothed s | peak RSS MB | kaiju replay flagged poses | "
          "supcoord check | motion ratio / mdp | CPU ratio / mdp |",
          "|" + "---|" * 17]
    order = {"hex61": 0, "hex127": 1, "hex547": 2, "apo": 3, "lco": 4}
    pl = {"supcoord": 0, "kaiju-greedy": 1, "kaiju-mdp": 2}
    for r in sorted(rows, key=lambda r: (order.get(r["grid"], 9), r["seed"], r["direction"] != "fold",
                                        pl.get(r["planner"], 9), r.get("steps", ""))):
        flagged = r.get("kaiju_replay_flagged")
        if isinstance(flagged, int):
            flagged = f"{flagged} / {r['kaiju_replay_poses']}"
        L.append("| " + " | ".join([
            r["grid"], str(r["seed"]), r["direction"], r["planner"],
            r.get("steps", "") + (f" → {r['lattice']}" if r.get("lattice") else ""), r.get("solved", ""),
            fmt(r.get("deadlocked")), fmt(r.get("off_target")), fmt(r.get("cpu_s")), fmt(r.get("wall_s")),
            fmt(r.get("motion_time_s")), fmt(r.get("motion_time_smoothed_s")),
            fmt(r.get("peak_rss_mb"), 0), fmt(flagged), r.get("check", ""),
            fmt(r.get("motion_ratio_mdp"), 3), fmt(r.get("cpu_ratio_mdp"), 1)]) + " |")
    L += ["", "## Motion-time ratio supcoord / kaiju (instances both solve)", ""]
    L += ["One value per (instance, direction) solved by both, per supcoord step setting "
          "(below 1: supcoord's plan is faster). `default` = 37x19.", ""]
    for st in sorted({r.get("steps", "") for r in rows if r["planner"] == "supcoord"}):
        for kp in ("mdp", "greedy"):
            for d in ("fold", "unfold", None):
                vals = [r[f"motion_ratio_{kp}"] for r in rows if f"motion_ratio_{kp}" in r
                        and r.get("steps") == st and (d is None or r["direction"] == d)]
                L.append(f"- steps {st}, vs kaiju-{kp}, {d or 'both directions'}: {dist(vals)}")
    L += ["", "Solved counts:", "", "| grid | direction | supcoord | kaiju-greedy | kaiju-mdp |", "|---|---|---|---|---|"]
    keys = sorted({(r["grid"], r["direction"]) for r in rows}, key=lambda k: (order.get(k[0], 9), k[1]))
    for g, d in keys:
        cells = []
        for p in ("supcoord", "kaiju-greedy", "kaiju-mdp"):
            rr = [r for r in rows if r["grid"] == g and r["direction"] == d and r["planner"] == p]
            if p == "supcoord":
                cells.append(", ".join(
                    f"{st}: {sum(r.get('solved') == 'yes' for r in rr if r.get('steps') == st)}/"
                    f"{sum(r.get('steps') == st for r in rr)}" for st in sorted({r.get('steps') for r in rr})))
                continue
            cells.append(f"{sum(r.get('solved') == 'yes' for r in rr)}/{len(rr)}" if rr else "")
        L.append(f"| {g} | {d} | " + " | ".join(cells) + " |")
    if data.get("notes"):
        L += ["", "## Notes", ""] + data["notes"]
    with open(path, "w") as f:
        f.write("\n".join(L) + "\n")


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--grids", default="hex61,hex127,apo")
    ap.add_argument("--seeds", default="0-2", help="e.g. 0-2 or 0,3")
    ap.add_argument("--instances", default="/tmp/kaiju_instances")
    ap.add_argument("--directions", default="fold,unfold")
    ap.add_argument("--planners", default="supcoord,greedy,mdp")
    ap.add_argument("--timeout", type=float, default=300, help="supcoord solve timeout, s (hex grids)")
    ap.add_argument("--timeout-apo", type=float, default=600, help="supcoord solve timeout on the woks (apo, lco), s")
    ap.add_argument("--max-memory", default="8G")
    ap.add_argument("--steps", default=None, help="alpha_steps x beta_steps, e.g. 13x7 (default 37x19)")
    ap.add_argument("--improve", type=int, default=None,
                    help="supcoord solve --improve N (default: supcoord's own default)")
    ap.add_argument("--reuse", default=None, help="directory of kaiju_side.py plan results to reuse")
    ap.add_argument("--kaiju-python", default=os.environ.get("KAIJU_PYTHON", "kaiju-venv/bin/python"),
                    help="the Python of a venv with kaiju (default: $KAIJU_PYTHON)")
    ap.add_argument("--supcoord", default=os.path.join(os.path.dirname(sys.executable), "supcoord"))
    ap.add_argument("--work", default="/tmp/vs_kaiju_work")
    ap.add_argument("--out", default=os.path.join(HERE, "results", "vs_kaiju"), help="writes OUT.json, OUT.md")
    ap.add_argument("--append", action="store_true", help="merge with the rows already in OUT.json")
    ap.add_argument("--deadline", default=None, help="HH:MM UTC: start no new instance after it")
    ap.add_argument("--report-only", action="store_true", help="rewrite OUT.md from OUT.json; run nothing")
    ap.add_argument("--note", action="append", default=[], help="a line for the Notes section (kept in OUT.json)")
    args = ap.parse_args(argv)
    if args.report_only:
        data = load_json(args.out + ".json")
        if not data:
            _fail(f"{args.out}.json: nothing to report")
        data.setdefault("notes", []).extend(args.note)
        ratio_rows(data["rows"])
        with open(args.out + ".json", "w") as f:
            json.dump(data, f, indent=1)
        write_md(args.out + ".md", data)
        return
    if not os.path.exists(args.kaiju_python):
        _fail(f"kaiju's python {args.kaiju_python} not found (install kaiju: ../shared/tools/install-kaiju.sh, "
              "or pass --kaiju-python)")
    if not os.path.exists(args.supcoord):
        _fail(f"supcoord CLI {args.supcoord} not found (pass --supcoord)")
    args.steps = tuple(int(x) for x in args.steps.lower().split("x")) if args.steps else None
    os.makedirs(args.work, exist_ok=True)
    data = load_json(args.out + ".json") if args.append else None
    if not data:
        data = {"format": "supcoord-benchmark/vs-kaiju/1", "header": {"runs": [], "machine": machine_info(),
                                                                      "max_memory": args.max_memory},
                "rows": [], "raw": {}}
    argv0 = portable(os.path.abspath(sys.argv[0]), {}) if sys.argv[0] else "benchmarks/vs_kaiju.py"
    run = {"command": shlex.join([argv0] + [portable(a, run_places(args)) for a in sys.argv[1:]]),
           "date": time.strftime("%Y-%m-%d %H:%M:%S UTC", time.gmtime()), "load_start": uptime()}
    data["header"]["runs"].append(run)
    data["header"]["machine"] = machine_info()
    planners = args.planners.split(",")
    directions = args.directions.split(",")

    def save():
        ratio_rows(data["rows"])
        with open(args.out + ".json", "w") as f:
            json.dump(data, f, indent=1)
        write_md(args.out + ".md", data)

    def put(row):
        key = (row["grid"], row["seed"], row["direction"], row["planner"], row.get("steps", ""))
        data["rows"] = [r for r in data["rows"]
                        if (r["grid"], r["seed"], r["direction"], r["planner"], r.get("steps", "")) != key]
        data["rows"].append(row)

    for grid in args.grids.split(","):
        for seed in parse_seeds(args.seeds):
            if args.deadline and time.strftime("%H:%M", time.gmtime()) >= args.deadline:
                print(f"vs_kaiju: deadline {args.deadline} passed, stopping before {grid} s{seed}", file=sys.stderr)
                break
            path = os.path.join(args.instances, f"{grid}_s{seed}.json")
            inst = load_json(path)
            if inst is None:
                _fail(f"{path}: no such instance (make it with kaiju_side.py instances)")
            inst["_path"] = path
            for direction in directions:
                ident = {"grid": grid, "robots": len(inst["robot_ids"]), "seed": seed, "direction": direction}
                for planner in planners:
                    if planner == "supcoord":
                        row, raw = supcoord_row(args, inst, direction, args.work)
                        data["raw"][f"{grid}_s{seed}_{direction}_{row['steps']}"] = raw
                    else:
                        row = kaiju_row(args, inst, planner, direction, args.work)
                    put(ident | row)
                    save()
    run["load_end"] = uptime()
    save()


if __name__ == "__main__":
    main()
