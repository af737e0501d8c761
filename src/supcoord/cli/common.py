"""What every command shares: options, console output, progress, budgets, JSON."""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import math
import os
import sys
import time
from dataclasses import dataclass
from pathlib import Path
from collections.abc import Iterator
from typing import Any, Mapping

from ..bdd.budget import MAX_TIMEOUT, current_rss
from ..bdd.context import Budget
from ..errors import InputError

__all__ = ["CommandResult", "Console", "command_parser", "add_common_options", "add_problem_argument", "to_jsonable",
           "budget_from_args", "existing_file", "parse_size", "as_option_error", "options_named"]


@dataclass
class CommandResult:
    """What a command returns: the JSON object, the human report, the exit status."""

    payload: dict[str, Any]
    text: str = ""
    exit_code: int = 0


def command_parser(subparsers: argparse._SubParsersAction, name: str, *, help: str, description: str,
                   example: str) -> argparse.ArgumentParser:
    """The parser of one command: its one-line help, its description and its examples as the epilog."""
    return subparsers.add_parser(name, help=help, description=description, epilog=example,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)


def add_problem_argument(p: argparse.ArgumentParser) -> None:
    """The positional ``PROBLEM.json`` of ``solve`` and ``check``."""
    p.add_argument("problem", metavar="PROBLEM.json", help="the coordination problem")


def add_common_options(p: argparse.ArgumentParser, *, budgets: bool = True) -> None:
    """``--json``, ``--quiet``/``--verbose`` and (for long runs) ``--max-nodes``/``--timeout``."""
    p.add_argument("--json", action="store_true", help="print exactly one JSON object on stdout")
    g = p.add_mutually_exclusive_group()
    g.add_argument("-q", "--quiet", action="store_true", help="no progress bar or log on stderr (errors still)")
    g.add_argument("-v", "--verbose", action="count", default=0,
                   help="log fixpoint progress on stderr (stage start/end, every 2 s); -vv: every iteration")
    if budgets:
        p.add_argument("--max-nodes", type=int, metavar="N",
                       help="stop cleanly (exit 3) beyond N live BDD nodes (default: what fits in 80%% of "
                            "the memory available at start, at 80 bytes per node)")
        p.add_argument("--timeout", type=float, metavar="SECONDS", help="stop cleanly (exit 3) after SECONDS")
        p.add_argument("--max-memory", metavar="SIZE",
                       help="stop cleanly (exit 3) when the process's resident memory passes SIZE (bytes, or "
                            "with a unit: 500M, 8G; default: 90%% of the memory available at start)")
        p.add_argument("--backend", choices=["auto", "cudd", "autoref"], default="auto", help="BDD backend (default: CUDD if available)")


#: bytes of memory per live BDD node assumed by the default node budget: measured 78 B
#: per node (peak RSS / live nodes) at 12.6 million nodes with CUDD through dd, node,
#: unique-table and computed-table growth included (docs/cli.md, "Budgets")
BYTES_PER_NODE = 80
#: share of the memory available at start that the default node budget may fill
MEMORY_SHARE = 0.8


def available_memory() -> int | None:
    """``MemAvailable`` of ``/proc/meminfo`` in bytes (None where there is none)."""
    try:
        with open("/proc/meminfo", encoding="ascii") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        return None
    return None


def default_max_nodes() -> int | None:
    """The node budget when ``--max-nodes`` is not given: what fits in 80 % of the memory
    available at start, so a run that would be killed by the kernel's out-of-memory
    killer (no JSON, exit 137) stops at a fixpoint iteration with exit 3 instead."""
    mem = available_memory()
    return None if mem is None else max(1, int(mem * MEMORY_SHARE / BYTES_PER_NODE))


#: share of the memory available at start that the default memory budget lets the process hold
RSS_SHARE = 0.9
_UNITS = {"": 1, "K": 2**10, "M": 2**20, "G": 2**30, "T": 2**40}


def parse_size(text: str, where: str = "--max-memory") -> int:
    """``"8G"`` → bytes (units K, M, G, T in powers of 1024, optional ``B``/``iB``);
    anything else is a one-line :class:`InputError` naming the option."""
    t = str(text).strip().upper().removesuffix("IB").removesuffix("B")
    unit = t[-1:] if t[-1:] in _UNITS and t[-1:] else ""
    number = t[: len(t) - len(unit)]
    try:
        value = float(number) * _UNITS[unit]
    except ValueError:
        raise InputError(f"must be a size such as 500M or 8G, got {text!r}", value=text, where=where) from None
    if not (value >= 2**20 and math.isfinite(value) and value <= 2**60):
        raise InputError(f"must be between 1M and 1024P, got {text!r}", value=text, where=where)
    return int(value)


def default_max_memory() -> int | None:
    """The memory budget when ``--max-memory`` is not given: the resident size now plus 90 %
    of the memory available at start, so the run stops with exit 3 before the kernel's
    out-of-memory killer ends it (no JSON, exit 137)."""
    mem = available_memory()
    return None if mem is None else current_rss() + int(mem * RSS_SHARE)


def budget_from_args(args: argparse.Namespace) -> Budget:
    """The :class:`Budget` of ``--max-nodes``/``--timeout``/``--max-memory`` (defaults:
    :func:`default_max_nodes`, no time limit, :func:`default_max_memory`); bad values are a
    one-line user error naming the option."""
    max_nodes = getattr(args, "max_nodes", None)
    timeout = getattr(args, "timeout", None)
    size = getattr(args, "max_memory", None)
    if max_nodes is not None and max_nodes <= 0:
        raise InputError(f"must be a positive number of nodes, got {max_nodes}", value=max_nodes, where="--max-nodes")
    if timeout is not None and not (timeout > 0 and math.isfinite(timeout) and timeout <= MAX_TIMEOUT):
        raise InputError(f"must be a positive number of seconds up to {MAX_TIMEOUT:.0f} (a year), got {timeout}",
                         value=timeout, where="--timeout")
    max_memory = parse_size(size) if size is not None else default_max_memory()
    if max_nodes is None:
        max_nodes = default_max_nodes()
    return Budget(max_nodes=max_nodes, timeout=timeout, max_memory=max_memory)


def as_option_error(exc: InputError, options: Mapping[str, str]) -> InputError:
    """The library's error about one of its parameters, told with the command's options.

    The library names its parameters (``where="workers"``, "... or use workers=0",
    "out: 'x' is a directory"); the command line shows the options instead
    (``--workers``, "... or use --workers 0", "--out: 'x' is a directory").  ``options``
    maps a parameter to its option; an error that names none of them is returned as it is.

    >>> as_option_error(InputError("must be >= 0, got -1", value=-1, where="workers"), {"workers": "--workers"})
    InputError('--workers: must be >= 0, got -1')
    >>> as_option_error(InputError("out: 'x' is a directory, not a file name"), {"out": "--out"})
    InputError("--out: 'x' is a directory, not a file name")
    """
    message = exc.message
    for name, option in options.items():
        message = message.replace(f"use {name}=", f"use {option} ").replace(f"use {name} ", f"use {option} ")
        if message.startswith((f"{name}: ", f"{name} ")):
            message = option + message[len(name):]
    where = options.get(exc.where, exc.where)
    if (message, where) == (exc.message, exc.where):
        return exc
    return InputError(message, value=exc.value, where=where)


@contextlib.contextmanager
def options_named(options: Mapping[str, str]) -> Iterator[None]:
    """Within the block, a library error that names a parameter of ``options`` is told with
    its option (:func:`as_option_error`); any other error passes unchanged."""
    try:
        yield
    except InputError as exc:
        told = as_option_error(exc, options)
        if told is exc:
            raise
        raise told from None


def existing_file(path: str, what: str = "file") -> Path:
    """``path`` as a :class:`Path` if it is a readable file, else a one-line
    :class:`InputError` naming it (missing, a directory, or unreadable)."""
    p = Path(path)
    if not p.exists():
        raise InputError(f"{what} not found", value=path, where=path)
    if p.is_dir():
        raise InputError(f"is a directory, not a {what}", value=path, where=path)
    if not os.access(p, os.R_OK):
        raise InputError(f"{what} cannot be read (permission denied)", value=path, where=path)
    return p


class Console:
    """Progress and logs on standard error (never stdout, which carries the JSON).

    ``progress(stage, info)`` is the callback the library's fixpoints call through
    :meth:`supcoord.bdd.Context.check_budget`:

    - on a terminal, one live status line (:class:`supcoord.progress.ProgressBar`:
      stage, iteration or layer, live and peak BDD nodes, elapsed time), erased when
      the command ends, so the report or JSON follows on a clean screen;
    - ``--verbose`` adds a log line (:class:`supcoord.progress.ProgressLog`) when a
      stage starts and ends and at most every 2 s in between; ``-vv`` logs every
      iteration.  Without a terminal (pipes, CI, files) only the log is written, and
      only with ``--verbose``;
    - ``--quiet``: nothing but the one error line of a failure.
    """

    def __init__(self, quiet: bool = False, verbose: int | bool = False, *, stream: Any = None,
                 tty: bool | None = None):
        self.quiet = quiet
        self.verbose = int(verbose)
        self._stream = stream
        self.tty = tty
        self._bar: Any = None
        self._log: Any = None
        self.started = time.perf_counter()
        #: the last progress report ``(stage, info)``, for partial statistics
        self.last: tuple[str, dict[str, Any]] | None = None

    @property
    def stream(self) -> Any:
        return self._stream if self._stream is not None else sys.stderr

    def _is_tty(self) -> bool:
        if self.tty is not None:
            return self.tty
        try:
            return bool(self.stream.isatty())
        except (AttributeError, ValueError):
            return False

    @classmethod
    def from_args(cls, args: argparse.Namespace) -> "Console":
        return cls(quiet=getattr(args, "quiet", False), verbose=getattr(args, "verbose", 0) or 0)

    def _print(self, message: str) -> None:
        if self._bar is not None:
            self._bar.write(message)
        else:
            print(message, file=self.stream, flush=True)

    def log(self, message: str) -> None:
        """An informational line (not with ``--quiet``)."""
        if not self.quiet:
            self._print(message)

    def warn(self, message: str) -> None:
        """A problem the run went past: ``supcoord: warning: …`` (not with ``--quiet``)."""
        self.log(f"supcoord: warning: {message}")

    def error(self, message: str) -> None:
        """The one line of a failure: ``supcoord: error: …`` (also with ``--quiet``)."""
        self.close()
        print(f"supcoord: error: {message}", file=self.stream, flush=True)

    def stopped(self, message: str) -> None:
        """The one line of a budget that ran out: ``supcoord: stopped: …``."""
        self.close()
        print(f"supcoord: stopped: {message}", file=self.stream, flush=True)

    def progress(self, stage: str, info: Mapping[str, Any]) -> None:
        self.last = (stage, dict(info))
        if self.quiet:
            return
        if self.verbose:
            if self._log is None:
                from ..progress import ProgressLog

                self._log = ProgressLog(interval=0 if self.verbose > 1 else 2.0, write=self._print,
                                        started=self.started)
            self._log(stage, info)
        if self._is_tty():
            if self._bar is None:
                from ..progress import ProgressBar

                self._bar = ProgressBar(file=self.stream, auto=False, leave=False, started=self.started)
            self._bar(stage, info)

    def close(self) -> None:
        """Flush the log's last line and erase the status line."""
        if self._log is not None:
            self._log.close()
            self._log = None
        if self._bar is not None:
            self._bar.close()
            self._bar = None


def to_jsonable(obj: Any) -> Any:
    """Plain JSON types: dataclasses, paths, tuples, sets, numpy scalars; NaN → null."""
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return to_jsonable(dataclasses.asdict(obj))
    if isinstance(obj, Mapping):
        return {str(k): to_jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple, set, frozenset)):
        items = sorted(obj) if isinstance(obj, (set, frozenset)) else obj
        return [to_jsonable(v) for v in items]
    if isinstance(obj, Path):
        return str(obj)
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    if hasattr(obj, "item") and callable(obj.item):  # numpy scalar
        return obj.item()
    return obj
