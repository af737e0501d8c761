"""``supcoord supcon --plant A.gen [B.gen ...] --spec S.gen [T.gen ...] [--export V.gen] [--json]``.

``V = supcon(sync(plants), sync(specs))`` with libFAUDES's conventions: the
specifications are lifted to the plant alphabet by self-loops of the plant events
they lack (``InvProject``; the library function itself has TCT's meaning, see
``docs/synthesis.md``) and controllability is the plants' (a specification may carry
no flags; a flag that contradicts the plants' is a warning naming the event and the
file).  An event that only specifications have is an error, or with
``--spec-only-events selfloop`` a controllable self-loop added to the plant (what the
libFAUDES examples do by hand).  Without ``--spec`` the specification is ``allevents``
(the supremal nonblocking supervisor of the plant).

Two routes give the same supervisor: symbolic (BDDs, for products of many
components) and explicit (arrays, for flat problems: few components, one of them
large); ``--route auto`` picks explicit when a component has more than
:data:`LARGE_COMPONENT` states (its BDD encoding would cost more than the explicit
product) and the product of the component sizes is at most
:data:`~supcoord.des.flat_product.MAX_CODES`.

Prints ``{"status": "ok", "states", "transitions", "marked", "bdd_nodes", "seconds"}``
(``docs/formats.md``; ``bdd_nodes`` is 0 on the explicit route); an empty supervisor
is ``"ok"`` with 0 states.  ``--export`` writes the supervisor; a supervisor larger
than ``--export-limit`` is refused before any enumeration.  A missing or malformed
file or a refused event is a user error (exit 2); ``--max-nodes``/``--timeout``
running out gives exit 3, with the stage (``"export"`` during the export).
"""

from __future__ import annotations

import argparse
import time

from .common import CommandResult, Console, budget_from_args, existing_file

__all__ = ["HELP", "DESCRIPTION", "EXAMPLE", "BUDGETS", "add_arguments", "run", "LARGE_COMPONENT"]

EXAMPLE = """examples:
  supcoord supcon --plant MACH1.gen MACH2.gen --spec BUF.gen BR.gen --json
  -> {"status": "ok", "states": 12, "transitions": 24, "marked": 1, "bdd_nodes": 150, "seconds": 0.02}
  supcoord supcon --plant M*.gen --spec B*.gen --export V.gen --order force --timeout 60
  supcoord supcon --plant cell.gen --spec spec.gen --spec-only-events selfloop --export V.gen"""


HELP = "supremal controllable nonblocking supervisor of plants for specifications"
DESCRIPTION = ("Compute V = supcon(sync(plants), sync(specs)) with libFAUDES's conventions: the "
               "specifications are lifted to the plant alphabet by self-loops (InvProject) and "
               "controllability is taken from the plants. Symbolically with BDDs, or explicitly for "
               "small flat problems (--route). Files are libFAUDES .gen or supcoord .json generators.")
BUDGETS = True  # --max-nodes/--timeout/--backend

#: ``--route auto`` is explicit when some component has more states than this (its BDD
#: encoding would dominate: 0.1 s at 1,000 states, 0.8 s at 4,000, 5.5 s at 16,000)
LARGE_COMPONENT = 512


def add_arguments(p: argparse.ArgumentParser) -> None:
    """``supcoord supcon``'s own options (:func:`.main.build_parser` adds the common ones)."""
    from ..bdd.ordering import ORDERINGS
    from ..synthesis.reachability import DEFAULT_METHOD, METHODS

    p.add_argument("--plant", nargs="+", required=True, metavar="A.gen", help="plant component files")
    p.add_argument("--spec", nargs="*", default=[], metavar="S.gen",
                   help="specification component files (none: allevents, i.e. only nonblocking)")
    p.add_argument("--spec-only-events", choices=["error", "selfloop"], default="error",
                   help="events that only specifications have: an error (default), or controllable "
                        "self-loops added to the plant, as the libFAUDES examples do")
    p.add_argument("--export", metavar="V.gen", help="write the supervisor (.gen, .json or .dot)")
    p.add_argument("--export-limit", type=int, default=1_000_000, metavar="N",
                   help="refuse to export supervisors with more than N states (default 1000000)")
    p.add_argument("--route", choices=["auto", "symbolic", "explicit"], default="auto",
                   help="symbolic (BDDs) or explicit (arrays, for flat problems); auto (default) picks "
                        f"explicit when a component has more than {LARGE_COMPONENT} states and the product fits")
    p.add_argument("--method", choices=METHODS, default=DEFAULT_METHOD,
                   help=f"fixpoint schedule of the symbolic route (default {DEFAULT_METHOD})")
    p.add_argument("--order", choices=ORDERINGS, default="rcm",
                   help="declaration order of the components' BDD variables (default rcm: reverse "
                        "Cuthill-McKee on the components' shared events)")
    p.add_argument("--reorder", action="store_true", help="let CUDD reorder variables dynamically (sifting)")


def _plant_flags(plants, specs, spec_paths, args, console):
    """The specifications with the plants' controllability, and the plant component of
    the specification-only events (``None`` if there are none)."""
    from ..des.flat import FlatGenerator
    from ..des.generator import Event, merge_alphabets
    from ..errors import AlphabetError

    plant = merge_alphabets(g.events for g in plants)
    extra: dict[str, Event] = {}
    fixed = []
    for path, g in zip(spec_paths, specs):
        unknown = [e.name for e in g.events if e.name not in plant]
        if unknown and args.spec_only_events == "error":
            raise AlphabetError(
                f"specification uses event(s) {', '.join(map(repr, unknown))} that no plant has (with "
                f"--spec-only-events selfloop they become controllable self-loops of the plant)",
                value=unknown[0], where=path)
        extra.update((n, Event(n, True)) for n in unknown)
        flagged = any(e.controllable for e in g.events)  # a specification without flags says nothing
        wrong = [e.name for e in g.events if e.name in plant and flagged and e.controllable != plant[e.name].controllable]
        if wrong:
            shown = ", ".join(f"{n!r} ({'un' if not plant[n].controllable else ''}controllable in the plant)"
                              for n in wrong[:5])
            console.warn(f"{path}: the plant's controllability is used for {shown}"
                         + (f" and {len(wrong) - 5} more" if len(wrong) > 5 else ""))
        events = [plant.get(e.name) or extra[e.name] for e in g.events]
        fixed.append(FlatGenerator(g.name, events, g.n_states, g.src, g.ev, g.dst, g.init, g.marked, g.state_names))
    if not extra:
        return fixed, None
    import numpy as np

    loops = np.arange(len(extra), dtype=np.int64)
    zero = np.zeros(len(extra), dtype=np.int64)
    return fixed, FlatGenerator("SPEC_ONLY", list(extra.values()), 1, zero, loops, zero, 0,
                                np.zeros(1, dtype=np.int64), None)


def _route(args, components) -> str:
    from ..des.flat_product import MAX_CODES

    if args.route != "auto":
        return args.route
    bound = 1.0
    for g in components:
        bound *= max(g.n_states, 1)
    largest = max((g.n_states for g in components), default=0)
    return "explicit" if largest > LARGE_COMPONENT and bound <= MAX_CODES else "symbolic"


def _inputs(args: argparse.Namespace, console: Console):
    """The plants (with the specification-only events' component last, or None) and the
    specifications, read and checked before any work; ``(plants, specs, extra)``."""
    from ..des.io import read_generator_flat
    from ..errors import InputError

    if args.export_limit < 1:
        raise InputError(f"must be at least 1, got {args.export_limit}", value=args.export_limit,
                         where="--export-limit")
    plant_paths = [str(existing_file(p, "plant file")) for p in args.plant]
    spec_paths = [str(existing_file(p, "specification file")) for p in args.spec]
    if args.export:  # before any work: never over an input, a link, a FIFO; a writable directory
        from ..outputs import check_output

        check_output(args.export, plant_paths + spec_paths, what="--export")
    plants = [read_generator_flat(p) for p in plant_paths]
    specs = [read_generator_flat(p) for p in spec_paths]
    specs, extra = _plant_flags(plants, specs, spec_paths, args, console)
    return plants + ([extra] if extra is not None else []), specs, extra


def run(args: argparse.Namespace, console: Console) -> CommandResult:
    from ..des.io import write_generator_flat
    from ..errors import InputError
    from ..synthesis.product import check_alphabets

    t0 = time.perf_counter()
    budget = budget_from_args(args)
    plants, specs, extra = _inputs(args, console)
    labels = [f"P{i}_{g.name}" for i, g in enumerate(plants)] + [f"S{j}_{g.name}" for j, g in enumerate(specs)]
    check_alphabets([e for g in plants for e in g.events], [], "G")
    route = _route(args, plants + specs)
    if route == "explicit":
        V, st = _explicit(plants, specs, labels, budget, console)
    else:
        V, st = _symbolic(args, plants, specs, labels, budget, console)
    if args.export:
        if st["states"] > args.export_limit:
            raise InputError(f"the supervisor has {st['states']} states, more than --export-limit "
                             f"{args.export_limit}; nothing written", value=st["states"], where=args.export)
        write_generator_flat(V() if callable(V) else V, args.export)
    seconds = time.perf_counter() - t0
    payload = {
        "status": "ok",
        "states": st["states"],
        "transitions": st["transitions"],
        "marked": st["marked"],
        "bdd_nodes": st["bdd_nodes"],
        "seconds": round(seconds, 6),
    }
    if "effort" in st:  # the symbolic route: seconds per stage, CUDD's counters
        payload["effort"] = st["effort"]
    return CommandResult(payload=payload, text=_text(args, plants, specs, extra, st, route, seconds))


def _text(args, plants, specs, extra, st, route: str, seconds: float) -> str:
    """The human report: the components, the supervisor's sizes, the effort."""
    names = [g.name for g in plants if g is not extra]
    lines = [
        f"plants: {', '.join(names)}; specifications: {', '.join(g.name for g in specs) or '(none)'}"
        + (f"; {len(extra.events)} specification-only event(s) as plant self-loops" if extra is not None else ""),
        f"supervisor V: {st['states']} states, {st['transitions']} transitions, {st['marked']} marked"
        + (" (empty: no controllable nonblocking behaviour)" if st["states"] == 0 else ""),
        f"{st['iterations']} iterations, "
        + (f"{st['bdd_nodes']} BDD nodes, {seconds:.3f} s ({args.method}, {args.order} order)" if route == "symbolic"
           else f"{seconds:.3f} s (explicit route)"),
    ]
    if args.export:
        lines.append(f"written to {args.export}")
    return "\n".join(lines)


def _explicit(plants, specs, labels, budget, console):
    from ..synthesis.supcon import supcon_flat

    def check(stage: str, **info) -> None:
        console.progress(stage, {"nodes": 0, **info})
        budget.check(stage, 0, info)

    return supcon_flat(plants, specs, name="V", labels=labels, check=check)


def _symbolic(args, plants, specs, labels, budget, console):
    """The symbolic route: the supervisor (exported on demand: a function) and its statistics."""
    from ..bdd.context import Context
    from ..bdd.ordering import order_components
    from ..des import symbolic_ops as S
    from ..des.symbolic import from_explicit
    from ..des.symbolic_export import to_flat
    from ..synthesis.supcon import lift_spec, supcon

    components = plants + specs
    is_spec = [False] * len(plants) + [True] * len(specs)
    order = order_components([{e.name for e in g.events} for g in components], args.order, is_spec)
    ctx = Context(args.backend, reordering=args.reorder, budget=budget, progress=console.progress)
    symbolic = {}
    for i in order:
        symbolic[i] = from_explicit(ctx, components[i].to_generator(), var=ctx.fresh_name(labels[i]))
    G = S.sync(*(symbolic[i] for i in range(len(plants))), name="G")
    E = S.sync(*(symbolic[i] for i in range(len(plants), len(components))), name="E") if specs else S.allevents(ctx, [])
    result = supcon(G, lift_spec(G, E), name="V", method=args.method)
    V = result.supervisor

    def export():
        return to_flat(V, V.invariant, max_states=args.export_limit, name="V")

    return export, result.stats
