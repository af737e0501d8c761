"""``supcoord demo [--json] [--out DIR]``: the seed paper's example end to end (the main job).

Builds the 3-positioner example in the literal and the coupled reading, synthesizes
``V = supcon(G, allevents(G) || S)``, runs CCC (preemptive), explains the shortest
forcing path in Table-1 labels, replays the paper's path, and writes the coupled
reading's ``G.gen``, ``S.gen``, ``V.gen`` and ``demo.png`` into ``DIR``.
"""

from __future__ import annotations

import argparse

from .common import CommandResult, Console, options_named

__all__ = ["HELP", "DESCRIPTION", "EXAMPLE", "BUDGETS", "add_arguments", "run"]

EXAMPLE = """examples:
  supcoord demo                      report on stdout, files in ./supcoord-demo
  supcoord demo --json --out /tmp/d  -> {"supervisor": {"states": ..}, "ccc": {..}, "witness": [..], "literal": {..}}
  supcoord demo --no-files"""


HELP = "the seed paper's 3-positioner example end to end (models, V, CCC, forcing path, figure)"
DESCRIPTION = ("Solve the seed paper's example (P1-P3 starting at [0], [6], [6]) in the literal reading "
              "of its model and in the coupled reading (collisions driven by the arms' geometry): "
              "supervisor V, complete coordination check, shortest forcing path in Table-1 labels.")
BUDGETS = False  # no --max-nodes/--timeout/--backend


def add_arguments(p: argparse.ArgumentParser) -> None:
    """``supcoord demo``'s own options (:func:`.main.build_parser` adds the common ones)."""
    p.add_argument("--out", default="supcoord-demo", metavar="DIR",
                   help="directory for G.gen, S.gen, V.gen and demo.png (default ./supcoord-demo)")
    p.add_argument("--no-files", action="store_true", help="write nothing, only report")


def run(args: argparse.Namespace, console: Console) -> CommandResult:
    from ..paper.demo import run_demo

    with options_named({"out": "--out"}):  # the library names its parameter out
        result = run_demo(None if args.no_files else args.out)
    return CommandResult(result.payload, result.text)
