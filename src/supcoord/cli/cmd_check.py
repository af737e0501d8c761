"""``supcoord check PROBLEM.json PLAN.json [--figure FILE] [--json]``: independent validation of a plan.

Prints ``{"valid", "collisions", "at_target", "problems", ...}`` (``docs/formats.md``), plus
``steps``, ``min_clearance`` and ``incidents`` (:func:`~supcoord.problems.validate.validate_plan`).
An invalid plan is an answer (exit 0); a missing or malformed file, or a problem whose
start or target itself collides, is a user error (exit 2, one line on stderr), except a start
whose robots collide with each other when the plan has a repair phase (PLAN.json ``repair``).
``--figure`` draws what was found: the collision incidents zoomed (``.png``/``.pdf``/
``.svg``/``.jpg``), or the plan animated with colliding positioners in red (``.gif``).
A plan may be given by its ``configurations``, by ``angles_deg`` alone or by
``trajectories`` alone (a plan made by another tool): all are checked on joint angles;
the figure draws the configurations of an index plan (of the others: start and target).
"""

from __future__ import annotations

import argparse
import dataclasses

from ..errors import InputError, SupcoordError
from .cmd_solve import as_option, figure_suffix
from .common import CommandResult, Console, add_problem_argument

__all__ = ["HELP", "DESCRIPTION", "EXAMPLE", "BUDGETS", "add_arguments", "run"]

EXAMPLE = """examples:
  supcoord check problem.json plan.json --json
  -> {"valid": true, "collisions": 0, "at_target": 19, "problems": [], ...}
  supcoord check problem.json plan.json --figure collisions.png   # draws each collision found
  supcoord check problem.json --jaeger paths.json   # a trajectory in jaeger's format
  supcoord check problem.json plan.json --jaeger paths.json   # against the plan's ends (a partial plan)"""


HELP = "validate a plan geometrically, independently of the planner"
DESCRIPTION = ("Check a PLAN.json against a PROBLEM.json: start and target, one step per joint "
              "per configuration, and no collision during any step (sampled, then bisected until "
              "decided to 1e-6 mm). A plan given only by joint angles (angles_deg) or timed "
              "trajectories is checked on its angles: start and target to 1e-6 deg, joint ranges, "
              "no collision while moving.")
BUDGETS = False  # no --max-nodes/--backend (no BDDs); --timeout and --max-memory are its own


def add_arguments(p: argparse.ArgumentParser) -> None:
    """``supcoord check``'s own options (:func:`.main.build_parser` adds the common ones)."""
    add_problem_argument(p)
    p.add_argument("plan", metavar="PLAN.json", nargs="?",
                   help="the plan to check; with --jaeger, the plan the trajectory was exported from (a partial "
                        "plan's robots off target end where its off_target says)")
    p.add_argument("--jaeger", metavar="PATHS.json",
                   help="check a trajectory in SDSS-V's jaeger format instead of a plan: the motion linear in time "
                        "between its points, every robot at once, and its joint speeds")
    p.add_argument("--reverse", action="store_true",
                   help="with --jaeger: the trajectory runs back, from the targets to the starts (--jaeger-reverse)")
    p.add_argument("--max-rpm", type=float, help="the speed limit for --jaeger in RPM (default the instrument's: "
                                                 "SDSS-V 3)")
    p.add_argument("--resolution", type=float, default=0.05, metavar="MM",
                   help="first sampling of each step, in mm of motion between samples (default 0.05, "
                        "from 1e-4 to 100); the verdict does not depend on it: what the samples leave "
                        "open is bisected")
    p.add_argument("--timeout", type=float, metavar="SECONDS", help="stop cleanly (exit 3) after SECONDS")
    p.add_argument("--max-memory", metavar="SIZE",
                   help="stop cleanly (exit 3) when the resident memory passes SIZE (500M, 8G; default: "
                        "90%% of the memory available at start)")
    p.add_argument("--figure", metavar="FILE",
                   help="draw the result: .gif animates the plan (collisions in red); .png/.pdf/.svg/.jpg "
                        "shows each collision found, or a strip of frames when there is none")


#: fields only a PLAN.json has (a PROBLEM.json has "layout")
PLAN_FIELDS = ("configurations", "angles_deg", "trajectories")


def _peek(path: str) -> object:
    from ..problems.problem import MAX_PROBLEM_BYTES, read_json

    try:
        return read_json(path, "problem", MAX_PROBLEM_BYTES)
    except SupcoordError:
        return None


def _load_problem(problem_path: str, plan_path: str):
    """:func:`load_problem`, with a hint when the two files were given the other way round."""
    from ..problems.problem import load_problem
    from ..problems.repair_phase import load_problem_any_start

    try:
        return load_problem(problem_path)
    except InputError as exc:
        if exc.message.startswith("start configuration collides") and isinstance(plan := _peek(plan_path), dict) \
                and plan.get("repair") is not None:  # a plan that repairs its start first (formats.md)
            return load_problem_any_start(problem_path)
        data = _peek(problem_path)
        found = [k for k in PLAN_FIELDS if k in data] if isinstance(data, dict) and "layout" not in data else []
        if not found:
            raise
        other = _peek(plan_path)
        swapped = f" and {plan_path} looks like a PROBLEM" if isinstance(other, dict) and "layout" in other else ""
        raise InputError(f"looks like a PLAN (it has '{found[0]}'), not a PROBLEM{swapped}; usage: supcoord check "
                         f"PROBLEM.json PLAN.json", value=found[0], where=problem_path) from None


def run(args: argparse.Namespace, console: Console) -> CommandResult:
    # the problems stack (numpy, scipy) is imported here, not at the top: every command's
    # parser imports this module, and `supcoord --help` or a mistyped option should not wait
    # a second for it
    from ..problems.plan import load_plan
    from ..problems.validate import RESOLUTION_RANGE, validate_plan

    lo, hi = RESOLUTION_RANGE
    if not lo <= args.resolution <= hi:
        raise InputError(f"must be a number of mm in [{lo:g}, {hi:g}], got {args.resolution}",
                         value=args.resolution, where="--resolution")
    jaeger = getattr(args, "jaeger", None)
    if args.plan is None and jaeger is None:
        raise InputError("give a PLAN.json or --jaeger PATHS.json", value=args.plan, where="check")
    if jaeger is not None:
        return _run_jaeger(args, console)
    figure_suffix(args.figure, [args.problem, args.plan])
    console.progress("load", {"file": args.problem})
    problem = _load_problem(args.problem, args.plan)
    console.progress("load", {"file": args.plan})
    plan = load_plan(args.plan, problem)
    for warning in problem.warnings:
        console.warn(warning)
    console.progress("validate", {"steps": max(len(plan.configurations) - 1, 0)})
    result = validate_plan(problem, plan, resolution=args.resolution)
    if args.figure:
        from ..figures.plan_figures import save_plan_figure

        drawn = dataclasses.replace(result, incidents=[i for i in result.incidents if len(i.positioners) == 2]
                                    if plan.configurations else [])
        with as_option("--figure"):
            save_plan_figure(problem, plan, args.figure, drawn, progress=console.progress)
    verdict = "VALID" if result.valid else "INVALID"
    lines = [f"{verdict}: {result.steps} steps, {result.collisions} collisions, "
             f"{result.at_target}/{problem.n} positioners at target"]
    if result.motion_time_s is not None:
        lines.append(f"motion time: {result.motion_time_s:.3f} s")
    if result.min_clearance is not None:
        lines.append(f"smallest clearance beyond the buffers: {result.min_clearance:.3f} mm")
    lines += [f"  - {p}" for p in result.problems]
    if args.figure:
        lines.append(f"figure written to {args.figure}")
    return CommandResult(payload=result.to_json(), text="\n".join(lines))


def _run_jaeger(args: argparse.Namespace, console: Console) -> CommandResult:
    """``check PROBLEM --jaeger PATHS.json``: :func:`supcoord.problems.validate_jaeger.check_jaeger`."""
    from ..problems.plan import load_plan
    from ..problems.problem import load_problem
    from ..problems.validate_jaeger import check_jaeger

    if args.figure:
        raise InputError("--figure draws plans; it is not available with --jaeger", value=args.figure,
                         where="--figure")
    problem = load_problem(args.problem)
    for warning in problem.warnings:
        console.warn(warning)
    if args.plan is not None:  # the plan's ends: a partial plan's robots off target end where their entries say
        from ..problems.validate_partial import partial_problem

        plan = load_plan(args.plan, problem)
        if plan.status == "partial":
            problem = partial_problem(problem, plan, [])
    try:
        res = check_jaeger(problem, args.jaeger, max_rpm=args.max_rpm, reverse=args.reverse,
                           resolution=args.resolution)
    except InputError as exc:
        raise InputError(exc.message, value=exc.value, where="--max-rpm" if exc.where == "max_rpm" else exc.where) \
            from None
    lines = [f"{'VALID' if res.valid else 'INVALID'}: {res.points} points, {res.collisions} collisions, motion "
             f"{res.motion_time_s:.3f} s, fastest joint {res.max_speed_deg_s:.4g} deg/s (limit "
             f"{res.speed_limit_deg_s:g})"]
    if res.first is not None:
        f = res.first
        what = (f"positioners {f['positioner_ids'][0]} and {f['positioner_ids'][1]} (robots {f['robots'][0]}, "
                f"{f['robots'][1]})" if "obstacle" not in f else
                f"positioner {f['positioner_ids'][0]} (robot {f['robots'][0]}) and obstacle {f['obstacle']}")
        lines.append(f"first collision: {what} at t = {f['time_s']:.3f} s, clearance {f['clearance_mm']:.3g} mm "
                     f"({f['distance_mm']:.6f} < {f['required_mm']:.6f} mm)")
    if res.min_clearance_mm is not None:
        lines.append(f"smallest clearance beyond the buffers: {res.min_clearance_mm:.4f} mm")
    lines += [f"  - {p}" for p in res.problems]
    return CommandResult(payload=res.to_json(), text="\n".join(lines))
