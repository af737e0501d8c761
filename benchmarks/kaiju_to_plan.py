#!/usr/bin/env python
"""Convert a kaiju path (``kaiju_side.py plan`` output) into a supcoord PLAN.json.

Runs with plain Python + numpy (e.g. the project's ``.venv/bin/python``); kaiju is not needed::

    python benchmarks/kaiju_to_plan.py PATH.json --out PLAN.json [--path raw|smoothed]
    supcoord check PROBLEM.json PLAN.json        # PROBLEM.json built from the same instance

Input: the JSON written by ``kaiju_side.py plan``: ``robot_ids`` (the instance's robot order),
``solved``, ``motion_time_s`` and, per robot id, ``path`` (kaiju's raw path) and, unless
planned with ``--no-smooth``, ``path_smoothed`` (kaiju's ``getPathPair`` output), each
``{"alpha": [[t_s, deg], ...], "beta": [[t_s, deg], ...]}``.

Conversion (documented contract):

* ``trajectories``: a list with one entry per robot, in ``robot_ids`` order (the same order
  as the instance's ``robot_ids`` / ``targets_deg`` and as every row of ``angles_deg``),
  each ``{"alpha": [[t_s, deg], ...], "beta": [[t_s, deg], ...]}`` copied unchanged from the
  chosen kaiju path (``--path raw``, the default: kaiju's rough path, the one kaiju
  collision-checked at every step, given by its corners; ``--path smoothed``: the smoothed and
  simplified path jaeger sends to the robots, which kaiju 1.4.1 does not re-check).
  Each joint moves linearly in time between its breakpoints and holds its first/last angle
  before/after them.
* ``angles_deg``: one configuration (an ``[alpha, beta]`` per robot) at every time in the
  union of all robots' alpha and beta breakpoint times (times closer than 1e-9 s merged),
  in increasing time; each robot's angles at such a time are linearly interpolated between
  that robot's own breakpoints (``numpy.interp``).  Between two consecutive configurations
  every joint of every robot therefore moves linearly (no joint has a breakpoint inside the
  interval), so checking the straight joint-space segments between consecutive
  configurations checks exactly the motion kaiju prescribes, with all robots moving at once.
* ``times_s``: the time of each configuration; ``motion_time_s``: the last breakpoint time
  (for the raw path this is (n_steps - 1) * timestep; kaiju's own "path length × timestep"
  is kept as ``kaiju_motion_time_s``).
* ``status``: ``"complete"`` if kaiju solved the instance (every robot at its destination,
  ``didFail`` False), otherwise ``"unknown"`` (kaiju never proves infeasibility); no
  ``configurations`` (kaiju's angles are continuous, not supcoord grid indices).
  ``--drop-angles`` leaves ``angles_deg`` out (the trajectories alone define the same motion;
  ``supcoord check`` accepts either).
* Angles stay in kaiju's convention: alpha = 0 points along the robot's ``planar.alpha_zero_wok_deg``
  in the instance (-90 deg, wok -y, on kaiju's hex grids), alpha and beta counter-clockwise;
  a PROBLEM.json built for supcoord must use the same zero (or shift alpha by that angle).
"""

from __future__ import annotations

import argparse
import json
import sys

import numpy as np


def convert(kaiju_plan: dict, which: str = "raw") -> dict:
    key = {"raw": "path", "smoothed": "path_smoothed"}[which]
    if key not in kaiju_plan:
        print(f"kaiju_to_plan: error: the kaiju plan has no {key!r} (kaiju failed, or it was planned with "
              "--no-smooth)", file=sys.stderr)
        sys.exit(2)
    ids = [str(r) for r in kaiju_plan["robot_ids"]]
    paths = kaiju_plan[key]
    traj = []
    for rid in ids:
        p = paths[rid]
        traj.append({ax: [[float(t), float(d)] for t, d in p[ax]] for ax in ("alpha", "beta")})
    times = np.unique(np.concatenate([np.asarray(tr[ax], dtype=float)[:, 0]
                                      for tr in traj for ax in ("alpha", "beta")]))
    keep = np.concatenate([[True], np.diff(times) > 1e-9])
    times = times[keep]
    angles = np.empty((len(times), len(ids), 2))
    for i, tr in enumerate(traj):
        for j, ax in enumerate(("alpha", "beta")):
            pts = np.asarray(tr[ax], dtype=float)
            angles[:, i, j] = np.interp(times, pts[:, 0], pts[:, 1])
    return {
        "status": "complete" if kaiju_plan.get("solved") else "unknown",
        "angles_deg": angles.tolist(),
        "times_s": times.tolist(),
        "trajectories": traj,
        "motion_time_s": float(times[-1]),
        "kaiju_motion_time_s": kaiju_plan.get("motion_time_s"),
        "robot_ids": kaiju_plan["robot_ids"],
        "reason": "" if kaiju_plan.get("solved") else
        f"kaiju did not reach the destination ({len(kaiju_plan.get('off_target', []))} robots off target, "
        f"{len(kaiju_plan.get('deadlocked', []))} deadlocked)",
        "stats": {"seconds": kaiju_plan.get("wall_seconds"), "cpu_seconds": kaiju_plan.get("cpu_seconds")},
        "source": {"tool": "kaiju " + str(kaiju_plan.get("kaiju_version")),
                   "planner": kaiju_plan.get("planner"), "direction": kaiju_plan.get("direction"),
                   "grid": kaiju_plan.get("grid"), "seed": kaiju_plan.get("seed"),
                   "instance": kaiju_plan.get("instance"), "path": which,
                   "speed_deg_per_s": kaiju_plan.get("speed_deg_per_s")},
    }


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description="kaiju path JSON -> supcoord PLAN.json")
    ap.add_argument("kaiju_plan")
    ap.add_argument("--out", required=True)
    ap.add_argument("--path", choices=["raw", "smoothed"], default="raw")
    ap.add_argument("--drop-angles", action="store_true",
                    help="omit angles_deg and times_s (big grids: the trajectories alone define the plan)")
    args = ap.parse_args(argv)
    with open(args.kaiju_plan) as f:
        plan = convert(json.load(f), args.path)
    n_conf = len(plan["angles_deg"])
    if args.drop_angles:
        del plan["angles_deg"], plan["times_s"]
    with open(args.out, "w") as f:
        json.dump(plan, f)
    print(f"{args.out}: {n_conf} configurations, {len(plan['robot_ids'])} robots, "
          f"motion {plan['motion_time_s']:.3f} s, status {plan['status']}", file=sys.stderr)


if __name__ == "__main__":
    main()
