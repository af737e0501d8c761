"""``supcoord conflicts PROBLEM.json [--out PAIRS.csv] [--max-groups N] [--json]``: targets not reachable together.

For a field, the pairs of targets whose robots collide when both are at target, the targets
colliding with a fixed obstacle or a held robot, and small groups whose robots alone have no
plan (:mod:`supcoord.planning.conflicts`), written as a CSV a target-assignment program reads
as forbidden pairs and groups.  A command of its own rather than a ``solve`` option: it
answers a question about the targets before any plan is wanted, and takes a field whose
targets collide, which ``solve`` refuses.
"""

from __future__ import annotations

import argparse

from .common import CommandResult, Console, add_problem_argument, budget_from_args

__all__ = ["HELP", "DESCRIPTION", "EXAMPLE", "BUDGETS", "add_arguments", "run"]

EXAMPLE = """examples:
  supcoord conflicts field.json --out pairs.csv
  supcoord conflicts field.json --json --max-groups 0     # static pairs only
  -> {"conflicts": [{"kind": "static-pair", "robots": [3, 4], ...}], "searched": "max_groups", ...}"""

HELP = "targets that cannot be reached together: forbidden pairs and groups for target assignment"
DESCRIPTION = ("List the targets of a field that cannot be reached together: pairs whose robots collide at "
               "target, targets colliding with an obstacle or a held robot, and groups of robots that alone "
               "have no plan. --out writes them as CSV (kind,size,robots,targets,reason).")
BUDGETS = True


def add_arguments(p: argparse.ArgumentParser) -> None:
    """``supcoord conflicts``'s own options (:func:`.main.build_parser` adds the common ones)."""
    add_problem_argument(p)
    p.add_argument("--out", metavar="PAIRS.csv", help="write the conflicts as CSV: kind,size,robots,targets,reason")
    p.add_argument("--max-groups", type=int, default=8, metavar="N",
                   help="most planned groups looked for (default 8; 0: the static conflicts only)")


def run(args: argparse.Namespace, console: Console) -> CommandResult:
    """``supcoord conflicts``: check the output first, find the conflicts, write, say what was found."""
    from ..errors import InputError
    from ..outputs import atomic_write_text
    from ..planning.conflicts import conflicts_csv, find_conflicts
    from ..problems.problem import load_problem
    from .cmd_solve import writable

    if not 0 <= args.max_groups <= 10_000:
        raise InputError(f"must be a number of groups in [0, 10000], got {args.max_groups}", value=args.max_groups,
                         where="--max-groups")
    writable(args.out, "--out", [args.problem])
    console.progress("load", {"file": args.problem})
    problem = load_problem(args.problem, check_collisions=False)
    for warning in problem.warnings:
        console.warn(warning)
    report = find_conflicts(problem, args.max_groups, budget_from_args(args))
    if args.out:
        atomic_write_text(args.out, conflicts_csv(report.conflicts), inputs=[args.problem], what="--out")
    kinds = {k: sum(c.kind == k for c in report.conflicts) for k in dict.fromkeys(c.kind for c in report.conflicts)}
    text = (f"{len(report.conflicts)} conflicts" + (f" ({', '.join(f'{v} {k}' for k, v in kinds.items())})"
                                                     if kinds else "")
            + f"; search for planned groups: {report.searched}")
    text += "".join(f"\n  {c.kind}: robots {' '.join(map(str, c.robots))}: {c.reason}" for c in report.conflicts[:20])
    if len(report.conflicts) > 20:
        text += f"\n  ... and {len(report.conflicts) - 20} more"
    if args.out:
        text += f"\nconflicts written to {args.out}"
    payload = {"conflicts": [{"kind": c.kind, "robots": list(c.robots), "targets": list(c.targets),
                              "reason": c.reason} for c in report.conflicts],
               "searched": report.searched, "positioners": problem.n}
    return CommandResult(payload=payload, text=text)
