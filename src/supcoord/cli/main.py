"""The ``supcoord`` command line: a thin shell over the library.

Each command lives in its own module ``supcoord.cli.cmd_<name>`` exposing ``HELP``,
``DESCRIPTION``, ``EXAMPLE``, ``BUDGETS``, ``add_arguments(parser)`` and
``run(args) -> CommandResult``; :func:`build_parser` adds its parser.  This module owns what every command shares
(``docs/formats.md``): ``--json`` prints exactly one JSON object on standard output;
a user error (:class:`~supcoord.errors.SupcoordError`) exits 2 with one line on
standard error; a budget that runs out exits 3 with ``"status": "unknown"``; any
other exception is a bug and exits 1.
"""

from __future__ import annotations

import argparse
import contextlib
import importlib
import json
import os
import signal
import sys
import threading
import time
from typing import Any, Callable, Iterator, Sequence

from .. import __version__
from ..errors import BudgetExceeded, SupcoordError
from ..bdd.budget import current_rss
from ..bdd.memory import RESERVE as CAP_RESERVE
from ..bdd.memory import MemoryCap
from . import guard
from .common import CommandResult, Console, add_common_options, budget_from_args, command_parser, to_jsonable

__all__ = ["main", "build_parser", "COMMANDS"]

#: command modules, in the order ``--help`` lists them
COMMANDS = ["demo", "paper", "supcon", "force", "solve", "check", "conflicts", "study"]


EPILOG = """examples:
  supcoord demo                                   the seed paper's example: report, V.gen, figure
  supcoord paper --positioners 500 --steps 12     the paper's model at scale
  supcoord supcon --plant M1.gen M2.gen --spec BUF.gen --export V.gen
  supcoord force V.gen --json                     CCC: forcible? rank, witness, layers
  supcoord solve problem.json --out plan.json --figure plan.gif
  supcoord check problem.json plan.json
  supcoord study run study.toml --workers 2       a declared grid of cases on Dask, results in a database

exit status: 0 an answer (also 'infeasible' or 'not forcible'); 2 a user error (one line on
stderr naming the file, field or option); 3 a budget (--timeout, --max-nodes) ran out
(JSON "status": "unknown" with the statistics so far); 1 a bug (please report it).
Progress goes to stderr: a status line on a terminal, a log with -v; --quiet for none.
Run 'supcoord COMMAND --help' for a command's options and an example; docs/cli.md has all."""


class UsageError(Exception):
    """A command line argparse rejects (unknown option, bad choice, wrong type)."""


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors: ``supcoord: error: argument --semantics: invalid
    choice: 'foo' (choose from 'preemptive', 'standard'); see 'supcoord force --help'``
    instead of the usage block and a second line (docs/formats.md: one clear line)."""

    def error(self, message: str):  # type: ignore[override]
        raise UsageError(f"{' '.join(message.split())}; see '{self.prog} --help'")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="supcoord",
        description=(
            "Coordinate robotic fiber positioners with supervisory control theory, "
            "computed symbolically with BDDs. Every command takes --json (one JSON object "
            "on stdout); user errors exit 2, budgets that run out exit 3."
        ),
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
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
        p = command_parser(sub, name, help=module.HELP, description=module.DESCRIPTION, example=module.EXAMPLE)
        module.add_arguments(p)
        add_common_options(p, budgets=module.BUDGETS)
        p.set_defaults(func=module.run)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``supcoord`` console script; returns the exit status."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # argparse: 0 after --help/--version
        return int(exc.code or 0)
    except UsageError as exc:
        print(f"supcoord: error: {exc}", file=sys.stderr)
        return 2
    if not getattr(args, "func", None):  # bare 'supcoord': the overview
        parser.print_help(sys.stderr)
        return 2
    console = Console.from_args(args)
    if hasattr(signal, "SIGXFSZ") and threading.current_thread() is threading.main_thread():
        # past a file-size limit (ulimit -f) a write fails with EFBIG, reported in one line, instead of
        # the signal killing the process halfway through a database write
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    max_memory = _memory_budget(args)
    if max_memory is not None and guard.can_fork():  # the work in a child the budget may end (guard)
        return guard.run_in_child(lambda: _work(args, console), max_memory,
                                  lambda reason, stats: _stopped(args, console, reason, stats),
                                  lambda message: (console.error(message), 1)[1])
    return _work(args, console)


def _memory_budget(args: argparse.Namespace) -> int | None:
    """The memory budget of a command that takes one (None: none, or options that
    :func:`_work` will refuse in one line)."""
    if not hasattr(args, "timeout"):
        return None
    try:
        return budget_from_args(args).max_memory
    except SupcoordError:
        return None


def _work(args: argparse.Namespace, console: Console) -> int:
    """The command's work, its output and its exit status (:func:`main`)."""
    restore = _interrupt_once()
    try:
        with _watchdog(args, console):
            result: CommandResult = args.func(args, console)
    except BudgetExceeded as exc:
        reason = exc.one_line()
        if reason.startswith("node budget") and getattr(args, "max_nodes", None) is None:
            reason += " (the default node budget, from the memory available; set it with --max-nodes)"
        return _stopped(args, console, reason, exc.stats)
    except SupcoordError as exc:
        console.error(exc.one_line())
        return 2
    except OSError as exc:  # a file the user named: missing directory, permissions, disk full
        console.error(_os_error(exc))
        return 2
    except (RuntimeError, ValueError, MemoryError) as exc:
        if not _out_of_memory(exc):
            raise
        return _stopped(args, console, _memory_reason(args, exc), {"stage": "memory"})
    except KeyboardInterrupt:
        console.error("interrupted")
        return 130
    finally:
        console.close()
        restore()
    try:
        if args.json:
            print(json.dumps(to_jsonable(result.payload)), flush=True)
        elif result.text:
            print(result.text, flush=True)
    except BrokenPipeError:  # `supcoord … | head`: the reader left; no traceback
        _silence_stdout()
        return 141
    return result.exit_code


def _silence_stdout() -> None:
    """After a broken pipe, point stdout at /dev/null so that the interpreter's final
    flush does not raise again (the recipe of Python's signal documentation)."""
    import os

    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError, AttributeError):  # not a real file (tests): nothing to do
        pass


#: seconds after a Ctrl-C within which the command must have stopped cleanly; past them
#: the process leaves with one line and exit 130 (an interrupt that landed in a ``__del__``
#: or a weakref callback is only printed, "Exception ignored", and the work would go on)
INTERRUPT_GRACE = 5.0


def _interrupt_once() -> Callable[[], None]:
    """While a command works, the first Ctrl-C raises ``KeyboardInterrupt`` (a clean stop,
    exit 130) and later ones are ignored, so a second interrupt during the clean-up
    cannot turn into a traceback; if the command has not stopped :data:`INTERRUPT_GRACE`
    seconds later, the process ends with one line and exit 130.  Returns the function
    that restores the previous handler (and calls off that deadline)."""
    if threading.current_thread() is not threading.main_thread():
        return lambda: None
    fired = []
    done = threading.Event()

    def deadline() -> None:
        if not done.wait(INTERRUPT_GRACE):
            os.write(2, b"supcoord: interrupted\n")
            os._exit(130)

    def handler(signum, frame):  # noqa: ARG001
        if not fired:
            fired.append(True)
            threading.Thread(target=deadline, name="supcoord-interrupt", daemon=True).start()
            raise KeyboardInterrupt

    previous = signal.signal(signal.SIGINT, handler)

    def restore() -> None:
        done.set()
        signal.signal(signal.SIGINT, previous)

    return restore


#: seconds past ``--timeout`` after which the watchdog interrupts code between fixpoint
#: iterations (model building, counting, export), where ``check_budget`` cannot
WATCHDOG_GRACE = 0.5
#: seconds between two looks of the watchdog at the clock and the resident memory
WATCHDOG_TICK = 0.25


@contextlib.contextmanager
def _watchdog(args: argparse.Namespace, console: Console) -> Iterator[None]:
    """Enforce ``--timeout`` and ``--max-memory`` also where no fixpoint checks them: a
    thread looks at the clock and the resident memory every :data:`WATCHDOG_TICK`
    seconds and, once the time passes ``timeout + WATCHDOG_GRACE`` or the memory passes
    the memory budget, interrupts the main thread (``signal.pthread_kill`` with
    ``SIGUSR2``, a real signal that also ends a sleep; its handler raises
    :class:`BudgetExceeded` with the last progress report as partial statistics).  No interval timer is used, so ``SIGALRM`` stays free for the
    caller (a test runner's own time limit).  A single BDD or numpy operation still runs
    to its end: the handler runs when the interpreter gets control back; for memory,
    :class:`~supcoord.bdd.memory.MemoryCap` makes the limit hard (an allocation past it
    fails, which is then reported like any out-of-memory error, exit 3).  Main thread only;
    elsewhere the fixpoints' own checks are the budget.  Bad values of the options are
    refused here, before any work."""
    if not getattr(args, "func", None) or not hasattr(args, "timeout"):
        yield
        return
    budget = budget_from_args(args)
    timeout, max_memory = budget.timeout, budget.max_memory
    with _sampling(console, timeout, max_memory):  # its thread first: the cap leaves no room for a stack
        with MemoryCap(max_memory) if max_memory is not None else contextlib.nullcontext():
            yield


@contextlib.contextmanager
def _sampling(console: Console, timeout: float | None, max_memory: int | None) -> Iterator[None]:
    """The watchdog's thread (:func:`_watchdog`)."""
    usable = ((timeout is not None or max_memory is not None) and hasattr(signal, "pthread_kill")
              and threading.current_thread() is threading.main_thread())
    if not usable:
        yield
        return
    started = time.perf_counter()
    reason: list[tuple[str, dict, Any]] = []

    def where_and_stats() -> tuple[str, dict]:
        if console.last is None:
            return "before any fixpoint reported (setting up)", {"stage": "setup"}
        stage, info = console.last
        stats = {"stage": stage, **{k: v for k, v in info.items() if k != "nodes"}, "bdd_nodes": info.get("nodes")}
        return f"after the last report of {stage}", stats

    def watch() -> None:
        while not stop.wait(WATCHDOG_TICK):
            elapsed = time.perf_counter() - started
            if timeout is not None and elapsed > timeout + WATCHDOG_GRACE:
                where, stats = where_and_stats()
                reason.append((f"time budget exceeded {where}: {elapsed:.1f} s > {timeout} s",
                               {**stats, "seconds": elapsed, "watchdog": True}, timeout))
            elif max_memory is not None and (rss := current_rss()) > max_memory - CAP_RESERVE - 2**20:
                # (at the hard limit's ceiling: past it allocations fail, and CUDD may go on collecting garbage)
                where, stats = where_and_stats()
                reason.append((f"memory budget exceeded {where}: {rss / 2**20:.0f} MiB resident, at the "
                               f"budget of {max_memory / 2**20:.0f} MiB",
                               {**stats, "seconds": elapsed, "rss_bytes": rss, "watchdog": True}, max_memory))
            if reason:
                signal.pthread_kill(main_thread, signal.SIGUSR2)  # a real signal: it also ends a sleep
                return

    def expire(signum, frame):  # noqa: ARG001
        if reason:
            message, stats, value = reason[0]
            raise BudgetExceeded(message, stats=stats, value=value)

    previous = signal.signal(signal.SIGUSR2, expire)
    main_thread = threading.main_thread().ident
    stop = threading.Event()
    watcher = threading.Thread(target=watch, name="supcoord-watchdog", daemon=True)
    watcher.start()
    try:
        yield
    finally:
        stop.set()
        watcher.join()
        signal.signal(signal.SIGUSR2, previous)


def _os_error(exc: OSError) -> str:
    """``/nonexistent/V.gen: No such file or directory`` (the file, then the reason)."""
    reason = exc.strerror or _first_line(exc)
    return f"{exc.filename}: {reason}" if exc.filename else reason


def _first_line(exc: BaseException) -> str:
    text = str(exc).strip().splitlines()
    return text[0] if text else type(exc).__name__


def _out_of_memory(exc: BaseException) -> bool:
    """CUDD's allocation failures as dd reports them (``RuntimeError('CUDD appears to have
    run out of memory …')`` from operators, ``ValueError('`DdNode *node` is `NULL`
    pointer.')`` from constructors, a manager that cannot be initialised), and Python's own
    :class:`MemoryError`."""
    if isinstance(exc, MemoryError):
        return True
    text = str(exc)
    return ("run out of memory" in text or "out of memory" in text.lower() or "`NULL` pointer" in text
            or "failed to initialize CUDD DdManager" in text)


def _memory_reason(args: argparse.Namespace, exc: BaseException) -> str:
    """Why an allocation failed: the memory budget (``--max-memory``, or its default) that
    :class:`~supcoord.bdd.memory.MemoryCap` enforces, and what failed."""
    size = getattr(args, "max_memory", None)
    budget = f"the memory budget of {size}" if size is not None else "the default memory budget (set it with --max-memory)"
    return (f"memory budget exceeded (out of memory): an allocation failed at {budget} "
            f"({type(exc).__name__}: {_first_line(exc)})")


def _stopped(args: argparse.Namespace, console: Console, reason: str, stats: dict) -> int:
    """A budget ran out: exit 3, ``"status": "unknown"`` with the statistics so far."""
    stats = {k: round(v, 4) if isinstance(v, float) else v for k, v in to_jsonable(stats).items()}
    shown = ", ".join(f"{k} {v}" for k, v in stats.items() if k != "stage" and not isinstance(v, (dict, list)))
    console.stopped(reason + (f" (so far: {shown})" if shown else ""))
    if args.json:
        print(json.dumps({"status": "unknown", "command": args.command, "reason": reason, "stats": stats}))
    return 3


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
