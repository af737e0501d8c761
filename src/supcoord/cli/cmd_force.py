"""``supcoord force V.gen [--target marked|STATE] [--semantics preemptive|standard] [--json]``.

Backtracking forcibility from the initial state of a generator (typically a
supervisor ``V``) to its marked states or to one state: the seed paper's CCC.  Prints
``{"status": "ok", "forcible", "witness", "rank", "layers"}`` (``docs/formats.md``).  Not
forcible is an answer (exit 0); a missing or malformed file or an unknown state is a
user error (exit 2); ``--max-nodes``/``--timeout`` running out gives exit 3.

``STATE`` is a state name of the file, else a state number: for ``.gen`` files the
libFAUDES index (states numbered 1, 2, … in the order of the file's ``<States>``, as
libFAUDES writes them; where the file's indices have gaps, as after libFAUDES deleted
states, only the indices written in the file), for ``.json`` files the JSON state
number (from 0).  Names are matched first.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from .common import CommandResult, Console, budget_from_args, existing_file

__all__ = ["HELP", "DESCRIPTION", "EXAMPLE", "BUDGETS", "add_arguments", "run", "resolve_state"]

EXAMPLE = """examples:
  supcoord force V.gen --json
  -> {"status": "ok", "forcible": true, "witness": ["73", "10", ...], "rank": 7, "layers": [1, 3, ...]}
  supcoord force V.gen --target 12 --semantics standard"""


HELP = "backtracking forcibility (CCC) from the initial state of a generator"
DESCRIPTION = ("Compute the forcibility layers W(0)=T, W(k+1)=W(k) ∪ Force(W(k)) symbolically, "
              "decide whether the initial state is forcible to the target and print a witness "
              "event string of length at most rank(q0).")
BUDGETS = True  # --max-nodes/--timeout/--backend


def add_arguments(p: argparse.ArgumentParser) -> None:
    """``supcoord force``'s own options (:func:`.main.build_parser` adds the common ones)."""
    p.add_argument("generator", metavar="V.gen", help="the generator (.gen or .json), e.g. a supervisor")
    p.add_argument("--target", default="marked", metavar="marked|STATE",
                   help="the marked states (default) or one state, by name or number")
    p.add_argument("--semantics", choices=["preemptive", "standard"], default="preemptive",
                   help="preemptive: pending uncontrollable events preempt (the paper's Remark, default); "
                        "standard: the controller forces an event, the environment may move first")


def resolve_state(g, text: str, path: str) -> int:
    """The state number of ``text`` in ``g`` (a name, else a file index), or InputError."""
    from ..errors import InputError

    if g.state_names is not None and text in g.state_names:
        return g.state_names.index(text)
    try:
        number = int(text)
    except ValueError:
        number = None
    gen = Path(path).suffix.lower() == ".gen"
    # in a .gen file whose indices have gaps (unnamed states are then named by their
    # index, see supcoord.des.io.gen_file), a number that is no state's index is no state
    gaps = gen and g.state_names is not None and any(
        n.isdigit() and int(n) != i + 1 for i, n in enumerate(g.state_names))
    if number is not None and not gaps:
        q = number - 1 if gen else number
        if 0 <= q < g.n_states:
            return q
    raise InputError(f"unknown state {text!r} in {path}", value=text, where="--target")


def run(args: argparse.Namespace, console: Console) -> CommandResult:
    from ..bdd.context import Context
    from ..des.io import read_generator
    from ..des.symbolic import from_explicit
    from ..synthesis.ccc import ccc
    from ..synthesis.effort import EffortMeter

    path = str(existing_file(args.generator, "generator file"))
    budget = budget_from_args(args)
    g = read_generator(path)
    ctx = Context(args.backend, budget=budget, progress=console.progress)
    V = from_explicit(ctx, g, "q")
    if args.target == "marked":
        target, shown = V.marked, "the marked states"
    else:
        q = resolve_state(g, args.target, path)
        target, shown = (V.state_of({"q": q}) if V.variables else V.invariant), f"state {args.target}"
    with EffortMeter(ctx) as meter:
        with meter.stage("ccc"):
            result = ccc(V, args.semantics, target=target)
    payload = result.to_json() | {"effort": meter.result().as_dict()}  # CUDD's counters, as supcon's
    lines = [f"{g.name}: {g.n_states} states, {g.n_transitions} transitions; target {shown}; "
             f"{args.semantics} semantics"]
    if result.forcible:
        lines.append(f"FORCIBLE: rank(q0) = {result.rank}; witness ({len(result.witness)} events): "
                     + (" ".join(result.witness) or "(empty: q0 is in the target)"))
    else:
        lines.append("NOT FORCIBLE from the initial state")
    lines.append(f"layers ({len(result.layers)}): {result.layers}")
    lines.append(f"{result.stats['seconds']:.3f} s, {result.stats['bdd_nodes']} BDD nodes")
    return CommandResult(payload=payload, text="\n".join(lines))
