"""The ``supcoord`` command line: a thin shell over the library.

Each command lives in its own module ``supcoord.cli.cmd_<name>`` exposing
``register(subparsers)``; the parser it adds sets ``func`` to a callable
``run(args) -> CommandResult``.  This module owns what every command shares
(``formats.md``): ``--json`` prints exactly one JSON object on standard output;
a user error (:class:`~supcoord.errors.SupcoordError`) exits 2 with one line on
standard error; a budget that runs out exits 3 with ``"status": "unknown"``; any
other exception is a bug and exits 1.
"""

from __future__ import annotations

import argparse
import importlib
import json
import sys
from typing import Sequence

from .. import __version__
from ..errors import BudgetExceeded, SupcoordError
from .common import CommandResult, Console, to_jsonable

__all__ = ["main", "build_parser", "COMMANDS"]

#: command modules, in the order ``--help`` lists them
COMMANDS = ["demo", "paper", "supcon", "force", "solve", "check"]


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="supcoord",
        description=(
            "Coordinate robotic fiber positioners with supervisory control theory, "
            "computed symbolically with BDDs. Every command takes --json (one JSON object "
            "on stdout); user errors exit 2, budgets that run out exit 3."
        ),
        epilog="Run 'supcoord COMMAND --help' for a command's options and an example.",
    )
    parser.add_argument("--version", action="version", version=f"supcoord {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name in COMMANDS:
        try:
            module = importlib.import_module(f"supcoord.cli.cmd_{name}")
        except ModuleNotFoundError as exc:  # a command not built yet is simply absent
            if exc.name == f"supcoord.cli.cmd_{name}":
                continue
            raise
        module.register(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``supcoord`` console script; returns the exit status."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # argparse: 2 on bad usage, 0 on --help
        return int(exc.code or 0)
    if not getattr(args, "func", None):
        parser.print_help(sys.stderr)
        return 2
    console = Console.from_args(args)
    try:
        result: CommandResult = args.func(args, console)
    except BudgetExceeded as exc:
        payload = {"status": "unknown", "reason": exc.one_line(), "stats": to_jsonable(exc.stats)}
        console.error(exc.one_line())
        if args.json:
            print(json.dumps(to_jsonable(payload)))
        return 3
    except SupcoordError as exc:
        console.error(exc.one_line())
        return 2
    except KeyboardInterrupt:
        console.error("interrupted")
        return 130
    finally:
        console.close()
    if args.json:
        print(json.dumps(to_jsonable(result.payload)))
    elif result.text:
        print(result.text)
    return result.exit_code

if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
