"""CPU time, peak memory and the plan improvement's share on one preset problem (issue 39).

One case per process (so the peak RSS is its own): ``supcoord.solve(preset_problem(name,
rings, seed), improve=...)`` with the default options otherwise; prints one JSON line with
the CPU seconds (user + system of this process), the peak RSS, the makespan before and
after the improvement, its re-plannings and seconds, and the motion time at 12 deg/s.
``--profile FILE`` writes a cProfile of the solve (``python -m pstats FILE``); ``--phases``
adds the CPU seconds of the planner's phases (model and tables, descent, windows, the two
schedules, improvement, motion timing, validation), timed around each phase's function.

    python benchmarks/bench_improve.py desi 41 0
    python benchmarks/bench_improve.py desi 6 0 --alpha 13 --beta 7 --profile prof.out
    python benchmarks/bench_improve.py desi 41 0 --alpha 13 --beta 7 --phases
"""

from __future__ import annotations

import argparse
import cProfile
import functools
import json
import resource
import time

import supcoord
import supcoord.planning.model as model_module
import supcoord.planning.planner as planner_module
import supcoord.planning.routes as routes_module
import supcoord.planning.schedule as schedule_module
from supcoord.problems.presets import preset_problem

#: (module or class, function name, label) of the phases ``--phases`` times
PHASES = [(model_module.CoordinationModel, "__init__", "model"), (routes_module, "descent", "descent"),
          (routes_module, "solve_local", "windows"), (schedule_module, "timeline_schedule", "timeline_schedule"),
          (schedule_module, "asap_schedule", "asap_schedule"), (planner_module, "improve_plan", "improve"),
          (planner_module, "with_motion", "motion_timing"), (planner_module, "validate_plan", "validate")]


def timed_phases() -> dict[str, float]:
    """Wrap each of :data:`PHASES` with a CPU-time accumulator; returns the accumulators."""
    spent: dict[str, float] = {}
    for owner, name, label in PHASES:
        def timed(*args, _f=getattr(owner, name), _label=label, **kwargs):
            t = time.process_time()
            try:
                return _f(*args, **kwargs)
            finally:
                spent[_label] = spent.get(_label, 0.0) + time.process_time() - t
        setattr(owner, name, functools.wraps(getattr(owner, name))(timed))
    return spent


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("name")
    ap.add_argument("rings", type=int)
    ap.add_argument("seed", type=int)
    ap.add_argument("--alpha", type=int, default=36, help="alpha lattice positions (preset default 36)")
    ap.add_argument("--beta", type=int, default=19, help="beta lattice positions (preset default 19)")
    ap.add_argument("--improve", type=int, default=None, help="re-plannings (default: the solver's)")
    ap.add_argument("--profile", default=None, help="write a cProfile of the solve here")
    ap.add_argument("--phases", action="store_true", help="add the CPU seconds of each phase")
    args = ap.parse_args()
    spent = timed_phases() if args.phases else None
    c0 = time.process_time()
    problem = preset_problem(args.name, rings=args.rings, seed=args.seed, alpha_steps=args.alpha,
                             beta_steps=args.beta)
    built = time.process_time() - c0
    prof = cProfile.Profile() if args.profile else None
    if prof is not None:
        prof.enable()
    plan = supcoord.solve(problem, improve=args.improve, speed=12.0)
    if prof is not None:
        prof.disable()
        prof.dump_stats(args.profile)
    usage = resource.getrusage(resource.RUSAGE_SELF)
    st = plan.stats
    print(json.dumps({"case": f"{args.name}-r{args.rings}-s{args.seed}", "robots": problem.n,
                      "lattice": [args.alpha, args.beta], "status": plan.status, "build_cpu_s": round(built, 2),
                      "cpu_s": round(usage.ru_utime + usage.ru_stime, 2), "rss_mib": round(usage.ru_maxrss / 1024),
                      "makespan_scheduled": st.get("makespan_scheduled"), "makespan": plan.makespan,
                      "improve_s": st.get("improve_seconds"), "replans": st.get("improve_replans"),
                      "motion_s": plan.motion_time_s, "solve_s": st.get("seconds"),
                      **({"phases_cpu_s": {k: round(v, 2) for k, v in spent.items()}} if spent is not None else {})}))


if __name__ == "__main__":
    main()
