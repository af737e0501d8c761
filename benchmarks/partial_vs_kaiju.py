#!/usr/bin/env python
"""Robots on target when not all can be: supcoord's partial plans vs kaiju MDP and jaeger's deadlock resolution.

Run with supcoord's venv; kaiju runs in ``--kaiju-python`` (kaiju 1.4.1's venv) through
``benchmarks/kaiju_side.py``::

    nice python benchmarks/partial_vs_kaiju.py --cases hex127:0-2,apo-unreachable:0-2,apo-offline:0-2,apo-close:0-2 \\
        --kaiju-python $KAIJU_PYTHON --work $WORK --out benchmarks/results/partial_vs_kaiju --resume

Cases (``GRID:SEEDS``; seeds of one case run before the next case's, round-robin over the
cases, so that an interrupted run has every kind):

* ``hex127``, ``hex547``: kaiju's own hex grids with kaiju's random decollided targets
  (``kaiju_side.py instances``), in the direction where kaiju deadlocks: from the folded
  lattice to the targets (kaiju ``direct``; supcoord's problem as ``vs_kaiju.py`` builds it for
  ``unfold``, steps 13x7);
* ``apo-KIND``, ``lco-KIND`` with KIND ``offline``, ``close``, ``unreachable``: a field of
  ``supcoord.instruments.hard_wok_field(wok, seed, KIND)`` (3 offline robots / clusters /
  unreachable targets), from the folded lattice to the targets, the instrument's own collision
  definition; kaiju's instance from the same PROBLEM.json (``kaiju_side.py field``) and kaiju
  planning as jaeger does, from the targets to the lattice (its path run backwards).

Rows per case:

* **supcoord**: ``supcoord solve PROBLEM --out PLAN --speed 12 --json -q --timeout T``
  (default options: partial plans), then ``supcoord check PROBLEM PLAN --json`` (the robots on
  target are the check's ``at_target`` less the offline robots, which stand at their own
  angles), and kaiju's collision check of the plan (``kaiju_side.py replay``, every 0.1° of
  the fastest joint, buffer 2 mm plus kaiju's step margin);
* **kaiju MDP**: the first plan of the jaeger run below (kaiju ``pathGenMDP2`` on the instance as
  given): the robots at their destination at the end of kaiju's path. In the ``direct``
  direction that is where kaiju leaves them; in the fold direction a failed fold cannot be run
  backwards, so the count is an upper bound of what kaiju gives;
* **jaeger**: ``kaiju_side.py jaeger`` (``jaeger_deadlocks.py``: jaeger 1.9.1's decollision and
  ``_resolve_deadlocks`` with 5 retries over kaiju MDP): the robots on their own targets after
  the last plan, not moved by jaeger. When the retries run out jaeger raises and runs nothing;
  the count is then what its last plan would have given (an upper bound), and the row says so.

``upper bound`` is the number of active robots less those with a target proved unreachable
(``HardField.certificates``). ``supcoord >= both`` compares the counts above. Writes
``OUT.json`` (every row) and ``OUT.md``; ``--resume`` keeps the rows of ``OUT.json`` and runs
only the missing cases.
"""

from __future__ import annotations

import argparse
import json
import os
import shlex
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

from vs_kaiju import (KAIJU_SIDE, SPEED, build_problem, load_json, machine_info, parse_seeds,  # noqa: E402
                      portable, run_child, uptime)

HEX = ("hex61", "hex127", "hex547")
CASE_ORDER = {c: i for i, c in enumerate(["hex61", "hex127", "hex547"] + [f"{w}-{k}" for w in ("apo", "lco")
                                                                           for k in ("unreachable", "offline",
                                                                                     "close")])}
WOKS = {"apo": "sdss-v-apo", "lco": "sdss-v-lco"}


def parse_cases(spec: str) -> list[tuple[str, int]]:
    """``hex127:0-2,apo-offline:0-1`` -> ``[(hex127, 0), (apo-offline, 0), (hex127, 1), ...]``."""
    per = []
    for part in spec.split(","):
        name, _, seeds = part.partition(":")
        per.append([(name, s) for s in parse_seeds(seeds or "0")])
    out = []
    for i in range(max(len(p) for p in per)):
        out += [p[i] for p in per if i < len(p)]
    return out


def log(msg: str) -> None:
    print(f"[{time.strftime('%H:%M:%S')}] {msg}", file=sys.stderr, flush=True)


def prepare(args, case: str, seed: int) -> dict:
    """The instance: its kaiju JSON, the supcoord PROBLEM.json, the direction, the upper bound."""
    work = args.work
    tag = f"{case}_s{seed}"
    inst_path = os.path.join(work, f"{tag}.instance.json")
    prob_path = os.path.join(work, f"{tag}.problem.json")
    if case in HEX:
        if not os.path.exists(inst_path):
            tmp = os.path.join(work, "kaiju_instances")
            run_child(["nice", args.kaiju_python, KAIJU_SIDE, "instances", "--out", tmp, "--seeds", str(seed + 1),
                       "--grids", case], os.path.join(work, f"{tag}.inst.out"), os.path.join(work, f"{tag}.inst.err"),
                      3600)
            os.replace(os.path.join(tmp, f"{case}_s{seed}.json"), inst_path)
        inst = load_json(inst_path)
        prob = build_problem(inst, "unfold", (13, 7))
        with open(prob_path, "w") as f:
            json.dump(prob, f)
        return {"tag": tag, "instance": inst_path, "problem": prob_path, "kaiju_direction": "direct",
                "robots": len(inst["robot_ids"]), "offline": 0, "certified_unreachable": 0}
    from supcoord.instruments import hard_wok_field

    wok, _, kind = case.partition("-")
    field = hard_wok_field(WOKS[wok], seed=seed, kind=kind)
    with open(prob_path, "w") as f:
        json.dump(field.problem(name=tag), f)
    if not os.path.exists(inst_path):
        res = run_child(["nice", args.kaiju_python, KAIJU_SIDE, "field", "--problem", prob_path, "--seed", str(seed),
                         "--out", inst_path], os.path.join(work, f"{tag}.inst.out"),
                        os.path.join(work, f"{tag}.inst.err"), 3600)
        if res["rc"]:
            raise RuntimeError(open(os.path.join(work, f"{tag}.inst.err")).read()[-500:])
    return {"tag": tag, "instance": inst_path, "problem": prob_path, "kaiju_direction": "fold",
            "robots": len(field.start), "offline": len(field.offline),
            "certified_unreachable": len(field.certificates),
            "unreachable_robots": list(field.unreachable), "offline_robots": sorted(field.offline),
            "clusters": [list(c) for c in field.clusters]}


def supcoord_row(args, case: dict) -> dict:
    base = os.path.join(args.work, case["tag"])
    plan = base + ".plan.json"
    if os.path.exists(plan):
        os.remove(plan)
    cmd = ["nice", args.supcoord, "solve", case["problem"], "--out", plan, "--speed", str(SPEED), "--json", "-q",
           "--timeout", str(args.timeout), "--max-memory", args.max_memory]
    if args.improve is not None:
        cmd += ["--improve", str(args.improve)]
    log(f"supcoord {case['tag']}")
    res = run_child(cmd, base + ".solve.out", base + ".solve.err", args.timeout + 300)
    out = load_json(base + ".solve.out") or {}
    row = {"status": out.get("status") or ("killed" if res["hard_killed"] else f"exit {res['rc']}"),
           "rc": res["rc"], "cpu_s": res["cpu_s"], "wall_s": res["wall_s"], "peak_rss_mb": res["peak_rss_mb"],
           "command": shlex.join(portable(c, places(args)) for c in cmd)}
    if not out:
        row["reason"] = open(base + ".solve.err").read().strip()[-300:]
    pl = load_json(plan) if os.path.exists(plan) else None
    if pl:
        row.update(plan_summary(pl))
        chk = run_child(["nice", args.supcoord, "check", case["problem"], plan, "--json", "-q", "--timeout", "1800"],
                        base + ".check.out", base + ".check.err", 2400)
        cj = load_json(base + ".check.out") or {}
        row["check"] = "valid" if cj.get("valid") else f"INVALID ({cj.get('problems') or cj or chk['rc']})"[:200]
        row["check_wall_s"] = chk["wall_s"]
        if "at_target" in cj:
            row["on_target"] = cj["at_target"] - case["offline"]
        if args.replay:
            rep = base + ".replay.json"
            r = run_child(["nice", args.kaiju_python, KAIJU_SIDE, "replay", "--instance", case["instance"],
                           "--angles", plan, "--out", rep, "--buffer", "2.0", "--ang-step", "0.1"],
                          base + ".replay.out", base + ".replay.err", 3600)
            rj = load_json(rep)
            row["kaiju_replay"] = (f"{rj['poses_flagged']} / {rj['poses']} poses flagged" if rj
                                   else f"replay failed (exit {r['rc']})")
            row["kaiju_replay_ok"] = bool(rj) and rj["poses_flagged"] == 0
    elif out.get("status") == "infeasible":
        row["on_target"] = 0
        row["reason"] = str(out.get("reason", ""))[:300]
    log(f"  -> {row['status']} on target {row.get('on_target')} check {row.get('check')} "
        f"cpu {row['cpu_s']:.1f} s rss {row['peak_rss_mb']:.0f} MB")
    return row


def plan_summary(pl: dict) -> dict:
    """A PLAN.json's robots off target and their reasons, counted by kind."""
    offs = [o for o in pl.get("off_target") or [] if isinstance(o, dict)]
    kinds: dict[str, int] = {}
    for o in offs:
        why = str(o.get("reason", ""))
        why = "certified group" if why.startswith("certificate") else why
        kinds[why] = kinds.get(why, 0) + 1
    return {"off_target": len(offs), "off_target_robots": sorted(int(o["robot"]) for o in offs),
            "reasons": [f"{v} {k}" for k, v in sorted(kinds.items())], "claimed_on_target": pl.get("on_target"),
            "optimal": pl.get("optimal"), "on_target_bound": pl.get("on_target_bound")}


def jaeger_row(args, case: dict) -> tuple[dict, dict]:
    """kaiju MDP (the first plan) and jaeger's resolution, from one ``kaiju_side.py jaeger`` run."""
    base = os.path.join(args.work, case["tag"])
    out_path = base + ".jaeger.json"
    cmd = ["nice", args.kaiju_python, KAIJU_SIDE, "jaeger", "--instance", case["instance"], "--planner", "mdp",
           "--direction", case["kaiju_direction"], "--out", out_path]
    if args.kaiju_timeout:
        cmd += ["--max-wall", str(args.kaiju_timeout)]
    if not (args.reuse_kaiju and os.path.exists(out_path)):
        log(f"kaiju MDP + jaeger {case['tag']} ({case['kaiju_direction']})")
        res = run_child(cmd, base + ".jaeger.out", base + ".jaeger.err", 6 * 3600)
        if res["rc"]:
            err = open(base + ".jaeger.err").read().strip()[-300:]
            return {"status": f"error (exit {res['rc']})", "reason": err}, {"status": "error", "reason": err}
        rss = res["peak_rss_mb"]
    else:
        rss = None
    j = load_json(out_path)
    first = j["plans"][0] if j["plans"] else {}
    active = j["active"]
    mdp = {"status": "failed (deadlock)" if first.get("did_fail") else "solved",
           "on_target": first.get("at_destination_active", first.get("at_destination")),
           "deadlocked": first.get("deadlocked"), "cpu_s": first.get("cpu_seconds"),
           "note": "upper bound: a failed fold cannot be run backwards" if case["kaiju_direction"] == "fold"
           and first.get("did_fail") else ""}
    jae = {"status": (j["error"] if j["error"].startswith("time limit") else "raises: " + j["error"])
           if j["error"] else ("solved" if j["attempts"] == 0 else
                                                                  f"solved after {j['attempts']} moves"),
           "on_target": j["on_target"], "attempts": j["attempts"], "plans": len(j["plans"]),
           "moved": len(set(j["unlocked"]) | set(j["decollided"])), "offline_moved": j["offline_moved"],
           "cpu_s": j["cpu_seconds"], "wall_s": j["wall_seconds"], "peak_rss_mb": rss,
           "note": ("" if not j["error"] else "what the last plan gives" if j["error"].startswith("time limit")
                    else "upper bound: jaeger raises and runs nothing"),
           "command": shlex.join(portable(c, places(args)) for c in cmd)}
    assert active == case["robots"] - case["offline"]
    log(f"  -> kaiju MDP {mdp['status']} on target {mdp['on_target']}; jaeger {jae['status']} "
        f"on target {jae['on_target']}")
    return mdp, jae


def places(args) -> dict[str, str]:
    return {args.work: "$WORK", args.kaiju_python: "$KAIJU_PYTHON", args.supcoord: "supcoord"}


def fmt(v, nd=1) -> str:
    if v is None or v == "":
        return ""
    return f"{v:.{nd}f}" if isinstance(v, float) else str(v)


def runs(r: dict, part: str) -> tuple[int | None, str]:
    """What kaiju MDP or jaeger (``part``) puts on target in a motion that can run, and in words.

    A failed kaiju plan runs in the ``direct`` direction (kaiju leaves the deadlocked robots
    where they are, collision-free), not in the fold direction (a fold that does not reach the
    lattice cannot be run backwards), so there it puts no robot on target; jaeger runs
    nothing when it raises; a jaeger run stopped by the benchmark's time limit has no answer
    (None)."""
    x = r.get(part) or {}
    if "on_target" not in x:
        return None, x.get("status", "not run")
    last = x["on_target"]
    if part == "kaiju_mdp":
        if x["status"] == "solved" or r["kaiju_direction"] == "direct":
            return last, f"{last} ({x['status']})"
        return 0, f"0 (fold failed; {last} reach the lattice)"
    if x["status"].startswith("time limit"):
        return None, f"not finished: stopped after {x['plans']} plans ({last} on target in the last)"
    if x["status"].startswith("raises"):
        return 0, f"0 (raises after {x['plans']} plans; the last leaves {last} on target)"
    return last, f"{last} ({x['status']})"


def proven(r: dict, s: dict) -> str:
    """How many of the robots with a proven-unreachable target supcoord's plan leaves off target."""
    want = set(r.get("field", {}).get("unreachable_robots", []))
    if not want or "off_target_robots" not in s:
        return ""
    return f"{len(want & set(s['off_target_robots']))} of {len(want)}"


def unique_runs(runs: list[dict]) -> list[dict]:
    """Each run once, by date: a run saved before it ended (no ``load_end``) and again at its end
    is the same run; the entry with the end is kept."""
    by: dict[tuple, dict] = {}
    for run in runs:
        key = (run["command"], run["date"])
        if key not in by or "load_end" in run:
            by[key] = run
    return sorted(by.values(), key=lambda x: x["date"])


def write_md(path: str, data: dict) -> None:
    h = data["header"]
    m = h["machine"]
    L = ["# Robots on target: supcoord's partial plans vs kaiju MDP and jaeger's deadlock resolution", "",
         "Generated by `benchmarks/partial_vs_kaiju.py` (its docstring has the method). `$KAIJU_PYTHON` is the "
         "Python of kaiju 1.4.1's virtualenv, `$WORK` the working directory, `$OUT` where the results were "
         "written before they were copied here.", "", "## Runs", ""]
    for run in unique_runs(h["runs"]):
        L += [f"- `{run['command']}`", f"  - {run['date']}; load at start {run['load_start']}, "
              f"at end {run.get('load_end', '(interrupted)')}"]
    L += ["", f"Machine: `nproc` = {m['nproc']}, {m['uname_m']}, CPU {m['cpu_model']}, Python {m['python']} "
          f"(supcoord {m['supcoord_version']}). The 2 cores were shared with other jobs (load above): wall times "
          "are inflated; CPU s is the better figure.", "",
          "## Robots on target", "",
          "Robots on their own targets (offline robots not counted) in a motion that can run; "
          "`supcoord ≥ last plans` compares with the robots kaiju's and jaeger's last plans leave on target "
          "even where that plan cannot run (a failed fold) or jaeger raises or did not finish.", "",
          "| case | robots | offline | upper bound | supcoord | kaiju MDP | jaeger + kaiju MDP | supcoord ≥ both | "
          "supcoord ≥ last plans | proven unreachable among supcoord's off target |",
          "|---|---|---|---|---|---|---|---|---|---|"]
    for r in data["rows"]:
        s, k, j = (r.get(x) or {"status": "not run"} for x in ("supcoord", "kaiju_mdp", "jaeger"))
        (kn, kt), (jn, jt) = runs(r, "kaiju_mdp"), runs(r, "jaeger")
        sn = s.get("on_target")
        cmp = [sn >= n for n in (kn, jn) if n is not None and isinstance(sn, int)]
        ok = "" if not cmp else ("yes" if all(cmp) else "NO") + ("" if len(cmp) == 2 else " (of those finished)")
        over = [n for n in (k.get("on_target"), j.get("on_target")) if isinstance(n, int)]
        last = "" if not over or not isinstance(sn, int) else ("yes" if sn >= max(over) else "NO")
        bound = r["robots"] - r["offline"] - r["certified_unreachable"]
        L.append(f"| {r['case']} s{r['seed']} | {r['robots']} | {r['offline']} | {bound} | "
                 f"{fmt(sn)} ({s['status']}) | {kt} | {jt} | {ok} | {last} | {proven(r, s)} |")
    L += ["", "## Time, memory, checks", "",
          "| case | supcoord CPU s | wall s | peak RSS MB | supcoord check | kaiju's check of the plan | reasons given | "
          "kaiju MDP CPU s | jaeger plans | jaeger robots moved | jaeger CPU s |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in data["rows"]:
        s, k, j = (r.get(x) or {"status": "not run"} for x in ("supcoord", "kaiju_mdp", "jaeger"))
        L.append(f"| {r['case']} s{r['seed']} | {fmt(s.get('cpu_s'))} | {fmt(s.get('wall_s'))} | "
                 f"{fmt(s.get('peak_rss_mb'), 0)} | {s.get('check', '')} | {s.get('kaiju_replay', '')} | "
                 f"{'; '.join(s.get('reasons', [])) or s.get('reason', '')} | {fmt(k.get('cpu_s'))} | "
                 f"{fmt(j.get('plans'))} | {fmt(j.get('moved'))} | {fmt(j.get('cpu_s'))} |")
    if data.get("notes"):
        L += ["", "## Notes", ""] + data["notes"]
    with open(path, "w") as f:
        f.write("\n".join(L) + "\n")


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cases", default="hex127:0-2,apo-unreachable:0-2,apo-offline:0-2,apo-close:0-2")
    ap.add_argument("--kaiju-python", default=os.environ.get("KAIJU_PYTHON", "kaiju-venv/bin/python"))
    ap.add_argument("--supcoord", default=os.path.join(os.path.dirname(sys.executable), "supcoord"))
    ap.add_argument("--timeout", type=float, default=900, help="supcoord solve --timeout, s")
    ap.add_argument("--max-memory", default="4G")
    ap.add_argument("--improve", type=int, default=None,
                    help="supcoord solve --improve N (default: supcoord's; it shortens motions, never changes "
                         "which robots reach their targets)")
    ap.add_argument("--no-replay", dest="replay", action="store_false", help="skip kaiju's check of the plans")
    ap.add_argument("--reuse-kaiju", action="store_true", help="reuse the jaeger runs already in WORK")
    ap.add_argument("--kaiju-timeout", type=float, default=None,
                    help="kaiju_side.py jaeger --max-wall: start no new kaiju plan after this many seconds")
    ap.add_argument("--parts", default="supcoord,kaiju",
                    help="what to run per case: supcoord, kaiju (kaiju MDP + jaeger), or both")
    ap.add_argument("--work", default=os.path.join(os.environ.get("TMPDIR", "/tmp"), "partial_vs_kaiju"))
    ap.add_argument("--out", default=os.path.join(HERE, "results", "partial_vs_kaiju"))
    ap.add_argument("--resume", action="store_true", help="keep OUT.json's rows; run only the missing cases")
    ap.add_argument("--deadline", default=None, help="HH:MM UTC: start no new case after it")
    ap.add_argument("--note", action="append", default=[], help="a line for the Notes section")
    ap.add_argument("--report-only", action="store_true", help="rewrite OUT.md from OUT.json")
    args = ap.parse_args(argv)
    data = load_json(args.out + ".json") if (args.resume or args.report_only) else None
    if args.report_only:
        data["notes"] = data.get("notes", []) + args.note
        for r in data["rows"]:  # the plans' summaries again, where their files are still in WORK
            plan = os.path.join(args.work, f"{r['case']}_s{r['seed']}.plan.json")
            if r.get("supcoord") and os.path.exists(plan):
                r["supcoord"].update(plan_summary(load_json(plan)))
        with open(args.out + ".json", "w") as f:
            json.dump(data, f, indent=1)
        write_md(args.out + ".md", data)
        return
    os.makedirs(args.work, exist_ok=True)
    if not data:
        data = {"format": "supcoord-benchmark/partial-vs-kaiju/1", "header": {"runs": []}, "rows": [], "notes": []}
    data["header"]["machine"] = machine_info()
    data["notes"] += args.note
    run = {"command": shlex.join(["benchmarks/partial_vs_kaiju.py"] +
                                 [portable(a, places(args)) for a in (argv if argv is not None else sys.argv[1:])]),
           "date": time.strftime("%Y-%m-%d %H:%M:%S UTC", time.gmtime()), "load_start": uptime()}
    data["header"]["runs"].append(run)
    parts = set(args.parts.split(","))

    def save():
        """Write OUT.json and OUT.md, merged with what another run (e.g. ``--parts kaiju`` beside
        ``--parts supcoord``) wrote meanwhile: per case, the parts each run has."""
        disk = load_json(args.out + ".json") if os.path.exists(args.out + ".json") else None
        merged = {(r["case"], r["seed"]): r for r in (disk["rows"] if disk else [])}
        for key, r in rows.items():  # only the parts this run made: another run's parts stay as it wrote them
            merged[key] = {**r, **merged[key], **{p: r[p] for p in ran.get(key, ())}} if key in merged else r
        data["rows"] = sorted(merged.values(), key=lambda r: (CASE_ORDER.get(r["case"], 99), r["seed"]))
        if disk:
            data["header"]["runs"] = unique_runs(disk["header"]["runs"] + data["header"]["runs"] + [run])
        with open(args.out + ".json", "w") as f:
            json.dump(data, f, indent=1)
        write_md(args.out + ".md", data)

    rows = {(r["case"], r["seed"]): r for r in data["rows"]}
    ran: dict[tuple, list[str]] = {}
    for name, seed in parse_cases(args.cases):
        row = rows.get((name, seed))
        todo = [p for p in ("supcoord", "kaiju") if p in parts and (row is None or p not in row)]
        if not todo:
            continue
        if args.deadline and time.strftime("%H:%M", time.gmtime()) >= args.deadline:
            log(f"deadline {args.deadline} passed: stopping before {name} s{seed}")
            break
        case = prepare(args, name, seed)
        if row is None:
            row = rows[(name, seed)] = {
                "case": name, "seed": seed, "robots": case["robots"], "offline": case["offline"],
                "certified_unreachable": case["certified_unreachable"], "kaiju_direction": case["kaiju_direction"],
                "field": {k: case[k] for k in ("unreachable_robots", "offline_robots", "clusters") if k in case}}
        if "supcoord" in todo:
            row["supcoord"] = supcoord_row(args, case)
            ran.setdefault((name, seed), []).append("supcoord")
            save()
        if "kaiju" in todo:
            row["kaiju_mdp"], row["jaeger"] = jaeger_row(args, case)
            row["kaiju"] = True
            ran.setdefault((name, seed), []).extend(["kaiju_mdp", "jaeger", "kaiju"])
            save()
    run["load_end"] = uptime()
    save()


if __name__ == "__main__":
    main()
