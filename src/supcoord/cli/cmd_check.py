"""``supcoord check PROBLEM.json PLAN.json [--json]``: independent validation of a plan.

Prints ``{"valid", "collisions", "at_target", "problems", ...}`` (``formats.md``).
An invalid plan is an answer (exit 0); a missing or malformed file, or a problem whose
start or target itself collides, is a user error (exit 2, one line on stderr).
"""

from __future__ import annotations

import argparse

from ..positioners.plan import load_plan
from ..positioners.problem import load_problem
from ..positioners.validate import validate_plan
from .common import CommandResult, Console, add_common_options

__all__ = ["register", "run"]

EXAMPLE = """example:
  supcoord check problem.json plan.json --json
  -> {"valid": true, "collisions": 0, "at_target": 19, "problems": [], ...}"""


def register(subparsers: argparse._SubParsersAction) -> argparse.ArgumentParser:
    p = subparsers.add_parser(
        "check",
        help="validate a plan geometrically, independently of the planner",
        description="Check a PLAN.json against a PROBLEM.json: start and target, one step per joint "
                    "per configuration, and no collision during any step (finely interpolated).",
        epilog=EXAMPLE,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("problem", metavar="PROBLEM.json", help="the coordination problem")
    p.add_argument("plan", metavar="PLAN.json", help="the plan to check")
    p.add_argument("--resolution", type=float, default=0.05, metavar="MM",
                   help="largest sampling error of the interpolated motion, in mm (default 0.05)")
    add_common_options(p, budgets=False)
    p.set_defaults(func=run)
    return p


def run(args: argparse.Namespace, console: Console) -> CommandResult:
    from ..errors import InputError

    if not args.resolution > 0:
        raise InputError(f"--resolution must be positive, got {args.resolution}", value=args.resolution)
    problem = load_problem(args.problem)
    plan = load_plan(args.plan, problem)
    result = validate_plan(problem, plan, resolution=args.resolution)
    verdict = "VALID" if result["valid"] else "INVALID"
    lines = [f"{verdict}: {result['steps']} steps, {result['collisions']} collisions, "
             f"{result['at_target']}/{problem.n} positioners at target"]
    if result["min_clearance"] is not None:
        lines.append(f"smallest clearance beyond the buffers: {result['min_clearance']:.3f} mm")
    lines += [f"  - {p}" for p in result["problems"]]
    return CommandResult(payload=result, text="\n".join(lines))
