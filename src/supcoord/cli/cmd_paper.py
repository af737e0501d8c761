"""``supcoord paper --positioners N --steps n [--model literal|coupled] [--route modular|monolithic|settled] [--json]``.

Scaling runs of the seed paper's model: ``N`` positioners on the hex grid with seeded
random starts and targets (start ≠ target), priorities = indices; builds ``G`` and
``allevents(G) || S``, synthesizes ``V`` symbolically and runs CCC (preemptive).
The literal model defaults to the exact ``modular`` route (one small supcon per
distinct positioner, Theorems 1–2 of :mod:`supcoord.paper.modular`); the
coupled model under preemptive semantics to ``settled`` (CCC on its settled states,
:mod:`supcoord.paper.settled`: the same verdict, rank and witness, without building
``V``; ``"settled"`` reports the search), else to ``monolithic``, where ``V`` is
synthesized without its reachable set and its exact sizes are counted up to 6
positioners (``--count-states`` beyond, which also selects ``monolithic``; ``"counted"``
says whether they were).  The library function is
:func:`supcoord.paper.run.run_paper`; its :class:`~supcoord.paper.run.PaperRun`'s
``to_json()`` is the JSON (``solve_paper``, re-exported here, returns it).
JSON: ``{"status", "positioners", "steps", "model", "route", "supervisor_states" (null beyond
4000 digits: Python refuses longer integers), "supervisor_states_log10",
"supervisor_transitions", "counted", "bdd_nodes", "ccc", "rank", "witness_length", "witness",
"certificate", "seconds", "timings"}``.
"""

from __future__ import annotations

import argparse

from .common import CommandResult, Console, budget_from_args, options_named

__all__ = ["HELP", "DESCRIPTION", "EXAMPLE", "BUDGETS", "add_arguments", "run"]

EXAMPLE = """examples:
  supcoord paper --positioners 5000 --steps 12 --json          literal model, modular route
  supcoord paper --positioners 30 --steps 12 --route monolithic
  supcoord paper --positioners 7 --steps 8 --model coupled --seed 3
  supcoord paper --positioners 5 --steps 8 --model coupled --route monolithic --count-states"""


def __getattr__(name: str):  # solve_paper lives in supcoord.paper.run; kept importable from here
    if name == "solve_paper":
        from ..paper.run import solve_paper

        return solve_paper
    raise AttributeError(name)


HELP = "the seed paper's model for N positioners (scaling runs)"
DESCRIPTION = ("Build the seed paper's positioner model for N positioners (literal or coupled reading), "
              "synthesize V = supcon(G, allevents(G) || S) with BDDs and run the CCC.")
BUDGETS = True  # --max-nodes/--timeout/--backend


def add_arguments(p: argparse.ArgumentParser) -> None:
    """``supcoord paper``'s own options (:func:`.main.build_parser` adds the common ones)."""
    p.add_argument("--positioners", type=int, required=True, metavar="N", help="number of positioners (>= 1)")
    p.add_argument("--steps", type=int, required=True, metavar="n", help="positions per positioner (>= 2)")
    p.add_argument("--model", choices=["literal", "coupled"], default="literal", help="reading of the model (default literal)")
    p.add_argument("--route", choices=["modular", "monolithic", "settled"], default=None,
                   help="modular: exact decomposition, literal model only (its default); "
                        "settled: CCC on the coupled model's settled states without building V "
                        "(its default under preemptive semantics; same verdict, rank and witness); "
                        "monolithic: generic supcon and CCC on the whole product")
    p.add_argument("--seed", type=int, default=0, metavar="S", help="seed of the random starts/targets (default 0)")
    p.add_argument("--semantics", choices=["preemptive", "standard"], default="preemptive", help="forcibility semantics")
    p.add_argument("--count-transitions", action="store_true",
                   help="exact transition count on the monolithic route even beyond 256 events (slow)")
    p.add_argument("--rank-cpu", type=_rank_cpu, default=None, metavar="SECONDS|none",
                   help="coupled model, settled route: CPU seconds the search for the rank may take once a "
                        "checked forcing string proved 'forcible' (default 50, supcoord.paper.settled.RANK_CPU; "
                        "past them the rank is bounded); none: until it is proved or a budget ends")
    p.add_argument("--count-states", action="store_true",
                   help="coupled model: count the supervisor's reachable states even beyond 6 positioners "
                        "(a reachability that takes longer than synthesis and CCC together)")


#: ``--rank-cpu none``: the search for the rank has no CPU allowance
NO_LIMIT = "none"


def _rank_cpu(text: str) -> float | str:
    """``--rank-cpu``: positive seconds, or :data:`NO_LIMIT`."""
    if text.strip().lower() == NO_LIMIT:
        return NO_LIMIT
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be positive seconds or 'none', got {text!r}") from None
    if not 0 < value < float("inf"):
        raise argparse.ArgumentTypeError(f"must be positive seconds or 'none', got {text!r}")
    return value


def _magnitude(count: int | None, log10: float | None) -> str:
    """``68024448`` as is, a huge count as ``10^7812.4`` (exact integers overflow floats)."""
    if count is not None and count < 10**12:
        return str(count)
    return "0" if log10 is None else f"10^{log10:.1f}"


#: parameters of :func:`~supcoord.paper.run.run_paper` whose errors are shown as the options of the same name
OPTIONS = {name: "--" + name.replace("_", "-")
           for name in ("positioners", "steps", "model", "seed", "semantics", "route", "count_states", "rank_cpu")}


def run(args: argparse.Namespace, console: Console) -> CommandResult:
    from ..bdd.context import Context
    from ..paper.run import run_paper

    ctx = Context(args.backend, budget=budget_from_args(args), progress=console.progress)
    # without --rank-cpu the library's allowance applies (RANK_CPU); "none" lifts it
    rank = {} if args.rank_cpu is None else {"rank_cpu": None if args.rank_cpu == NO_LIMIT else args.rank_cpu}
    with options_named(OPTIONS):  # the library names its parameters
        paper = run_paper(args.positioners, args.steps, args.model, args.seed, args.semantics, ctx,
                          route=args.route, count_transitions=True if args.count_transitions else None,
                          count_states=True if args.count_states else None, **rank)
    payload = paper.to_json()
    return CommandResult(payload, _text(paper, payload))


def _text(paper, payload: dict) -> str:
    """The one-line report of a :class:`~supcoord.paper.run.PaperRun` (``payload``: its JSON)."""
    t = payload["timings"]
    verdict = "forcible" if paper.forcible else "NOT forcible"
    if paper.forcible:
        verdict += f", witness of {payload['witness_length']} events"
    if paper.rank_bounds is not None:  # the verdict is proved, the rank only bounded
        b = paper.rank_bounds
        verdict += f", rank in [{b.lower}, {b.upper}] (not proved minimal: {b.stopped})"
    if paper.certificate:
        verdict += f" ({paper.certificate})"
    if paper.settled is not None:
        states = f"V not built (CCC on the settled states, {paper.settled.relations} relations)"
    elif paper.sizes.counted:
        states = (f"V has {_magnitude(payload['supervisor_states'], payload['supervisor_states_log10'])} states, "
                  f"{paper.sizes.bdd_nodes} BDD nodes")
    else:
        states = f"V's states not counted (--count-states), {paper.sizes.bdd_nodes} BDD nodes"
    return (f"{paper.model} model, {paper.route} route, {payload['positioners']} positioners, "
            f"{payload['steps']} steps (seed {payload['seed']}): {states}; CCC {verdict}; {payload['seconds']} s "
            f"(build {t['build']}, supcon {t['supcon']}, ccc {t['ccc']}"
            + (f", count {t['count']})" if t.get("count") else ")"))
