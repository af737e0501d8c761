"""What every command shares: options, console output, progress, budgets, JSON."""

from __future__ import annotations

import argparse
import dataclasses
import math
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Mapping

from ..errors import InputError
from ..symbolic.context import Budget

__all__ = ["CommandResult", "Console", "add_common_options", "to_jsonable", "budget_from_args", "existing_file"]


@dataclass
class CommandResult:
    """What a command returns: the JSON object, the human report, the exit status."""

    payload: dict[str, Any]
    text: str = ""
    exit_code: int = 0


def add_common_options(p: argparse.ArgumentParser, *, budgets: bool = True) -> None:
    """``--json``, ``--quiet``/``--verbose`` and (for long runs) ``--max-nodes``/``--timeout``."""
    p.add_argument("--json", action="store_true", help="print exactly one JSON object on stdout")
    g = p.add_mutually_exclusive_group()
    g.add_argument("-q", "--quiet", action="store_true", help="no progress or log output on stderr")
    g.add_argument("-v", "--verbose", action="store_true", help="log each fixpoint iteration on stderr")
    if budgets:
        p.add_argument("--max-nodes", type=int, metavar="N", help="stop cleanly (exit 3) beyond N live BDD nodes")
        p.add_argument("--timeout", type=float, metavar="SECONDS", help="stop cleanly (exit 3) after SECONDS")
        p.add_argument("--backend", choices=["auto", "cudd", "autoref"], default="auto", help="BDD backend (default: CUDD if available)")


def budget_from_args(args: argparse.Namespace) -> Budget:
    max_nodes = getattr(args, "max_nodes", None)
    timeout = getattr(args, "timeout", None)
    if max_nodes is not None and max_nodes <= 0:
        raise InputError(f"--max-nodes must be positive, got {max_nodes}", value=max_nodes)
    if timeout is not None and not timeout > 0:
        raise InputError(f"--timeout must be positive, got {timeout}", value=timeout)
    return Budget(max_nodes=max_nodes, timeout=timeout)


def existing_file(path: str, what: str = "file") -> Path:
    p = Path(path)
    if not p.is_file():
        raise InputError(f"{what} not found: {path}", value=path, where=path)
    return p


class Console:
    """Progress and logs on standard error (never stdout, which carries the JSON).

    ``progress(stage, info)`` is the callback the library's fixpoints call through
    :meth:`supcoord.symbolic.Context.check_budget`; it drives one tqdm bar per stage.
    """

    def __init__(self, quiet: bool = False, verbose: bool = False):
        self.quiet = quiet
        self.verbose = verbose
        self._bar = None
        self._stage: str | None = None

    @classmethod
    def from_args(cls, args: argparse.Namespace) -> "Console":
        return cls(quiet=getattr(args, "quiet", False), verbose=getattr(args, "verbose", False))

    def log(self, message: str) -> None:
        if not self.quiet:
            self._clear()
            print(message, file=sys.stderr)

    def error(self, message: str) -> None:
        self._clear()
        print(f"supcoord: error: {message}", file=sys.stderr)

    def progress(self, stage: str, info: Mapping[str, Any]) -> None:
        if self.quiet:
            return
        if self.verbose:
            details = " ".join(f"{k}={v}" for k, v in info.items())
            print(f"[{stage}] {details}", file=sys.stderr)
            return
        if not sys.stderr.isatty():
            return
        from tqdm import tqdm

        if stage != self._stage:
            self._clear()
            self._bar = tqdm(desc=stage, unit="it", file=sys.stderr, leave=False)
            self._stage = stage
        self._bar.update(1)
        self._bar.set_postfix({k: v for k, v in info.items()}, refresh=False)

    def _clear(self) -> None:
        if self._bar is not None:
            self._bar.close()
            self._bar = None
            self._stage = None

    def close(self) -> None:
        self._clear()


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
