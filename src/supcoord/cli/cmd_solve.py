"""``supcoord solve PROBLEM.json [--out PLAN.json] [--figure FILE] [--json]``: plan a problem.

Prints the PLAN.json object (``formats.md``): ``complete`` with a validated plan,
``infeasible`` with a ``reason`` naming the positioners (exit 0: an answer), or — when
``--max-nodes``/``--timeout`` run out — ``unknown`` with the statistics so far (exit 3).
A missing or malformed problem, or a start/target that itself collides, exits 2.
"""

from __future__ import annotations

import argparse

from .common import CommandResult, Console, add_common_options, budget_from_args

__all__ = ["register", "run"]

EXAMPLE = """examples:
  supcoord solve problem.json --out plan.json --figure plan.gif
  supcoord solve problem.json --json --timeout 60
  -> {"status": "complete", "configurations": [...], "makespan": 9, "lower_bound": 6, ...}
  supcoord solve problem.json --route monolithic     # the plain whole-grid method"""


def register(subparsers: argparse._SubParsersAction) -> argparse.ArgumentParser:
    p = subparsers.add_parser(
        "solve",
        help="plan collision-free moves from start to target (or prove none exists)",
        description="Solve a geometric coordination problem symbolically: a validated plan, "
                    "or 'infeasible' with the positioners involved.",
        epilog=EXAMPLE,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("problem", metavar="PROBLEM.json", help="the coordination problem")
    p.add_argument("--out", metavar="PLAN.json", help="write the plan here")
    p.add_argument("--figure", metavar="FILE", help="draw the plan: .gif animates it, other extensions get a strip")
    p.add_argument("--route", choices=["local", "monolithic"], default="local",
                   help="local: exact windows with certificates (default); monolithic: one model of the whole grid")
    p.add_argument("--order", choices=["rcm", "hex"], help="variable order (default: rcm for local, hex for monolithic)")
    add_common_options(p)
    p.set_defaults(func=run)
    return p


def run(args: argparse.Namespace, console: Console) -> CommandResult:
    from ..errors import InputError
    from ..positioners.planner import solve
    from ..positioners.problem import load_problem

    budget = budget_from_args(args)
    problem = load_problem(args.problem)
    if args.figure and not str(args.figure).lower().endswith((".gif", ".png", ".pdf", ".svg", ".jpg")):
        raise InputError(f"--figure must end in .gif, .png, .pdf, .svg or .jpg, got {args.figure}", value=args.figure)
    plan = solve(problem, route=args.route, order=args.order, backend=args.backend, budget=budget,
                 progress=console.progress)
    kin = problem.kinematics
    if args.out:
        plan.dump(args.out, kin)
    if args.figure and plan.status == "complete":
        from ..positioners.figures import save_plan_gif, save_plan_strip

        if str(args.figure).lower().endswith(".gif"):
            save_plan_gif(problem, plan, args.figure)
        else:
            save_plan_strip(problem, plan, args.figure)
    s = plan.stats
    if plan.status == "complete":
        text = (f"COMPLETE: {problem.n} positioners, makespan {plan.makespan} (lower bound {plan.lower_bound}), "
                f"{s.get('single_moves')} single moves, {s.get('windows')} symbolic solve(s), "
                f"{s.get('seconds', 0):.2f} s, peak {s.get('bdd_nodes')} BDD nodes")
    else:
        text = f"INFEASIBLE: {plan.reason}"
    if args.out:
        text += f"\nplan written to {args.out}"
    return CommandResult(payload=plan.to_json(kin), text=text)
