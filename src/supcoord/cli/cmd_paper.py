"""``supcoord paper --positioners N --steps n [--model literal|coupled] [--seed S] [--json]``.

Scaling runs of the seed paper's model: ``N`` positioners on the hex grid with seeded
random starts and targets (start ≠ target), priorities = indices; builds ``G`` and
``allevents(G) || S``, synthesizes ``V`` symbolically and runs CCC (preemptive).
JSON: ``{"status", "positioners", "steps", "model", "supervisor_states", "bdd_nodes",
"ccc", "witness_length", "seconds"}`` (plus a per-stage ``timings`` object).
"""

from __future__ import annotations

import argparse
import time

from ..errors import InputError
from .common import CommandResult, Console, add_common_options, budget_from_args

__all__ = ["register", "run", "solve_paper"]

EXAMPLE = """examples:
  supcoord paper --positioners 500 --steps 12 --json
  supcoord paper --positioners 7 --steps 12 --model coupled --seed 3"""


def register(subparsers: argparse._SubParsersAction) -> argparse.ArgumentParser:
    p = subparsers.add_parser(
        "paper",
        help="the seed paper's model for N positioners (scaling runs)",
        description="Build the seed paper's positioner model for N positioners (literal or coupled reading), "
                    "synthesize V = supcon(G, allevents(G) || S) with BDDs and run the CCC.",
        epilog=EXAMPLE,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--positioners", type=int, required=True, metavar="N", help="number of positioners (>= 1)")
    p.add_argument("--steps", type=int, required=True, metavar="n", help="positions per positioner (>= 2)")
    p.add_argument("--model", choices=["literal", "coupled"], default="literal", help="reading of the model (default literal)")
    p.add_argument("--seed", type=int, default=0, metavar="S", help="seed of the random starts/targets (default 0)")
    p.add_argument("--semantics", choices=["preemptive", "standard"], default="preemptive", help="forcibility semantics")
    add_common_options(p)
    p.set_defaults(func=run)
    return p


def solve_paper(positioners: int, steps: int, model: str = "literal", seed: int = 0, semantics: str = "preemptive",
                ctx=None) -> dict:
    """Build, synthesize and check; the formats of ``supcoord paper --json``."""
    from ..positioners.coupled import CoupledModel, coupled_models
    from ..positioners.paper import literal_models, random_instance
    from ..symbolic.context import Context
    from ..synthesis import ccc, supcon

    if isinstance(positioners, bool) or not isinstance(positioners, int) or positioners < 1:
        raise InputError(f"--positioners must be an integer >= 1, got {positioners!r}", value=positioners, where="--positioners")
    if isinstance(steps, bool) or not isinstance(steps, int) or steps < 2:
        raise InputError(f"--steps must be an integer >= 2, got {steps!r}", value=steps, where="--steps")
    if model not in ("literal", "coupled"):
        raise InputError(f"--model must be literal or coupled, got {model!r}", value=model, where="--model")
    t0 = time.perf_counter()
    ctx = ctx or Context()
    if model == "literal":
        inst = random_instance(positioners, steps, seed)
        G, E = literal_models(inst, ctx)
    else:
        inst = _coupled_instance(positioners, steps, seed)
        G, E = coupled_models(CoupledModel(inst), ctx)
    t1 = time.perf_counter()
    res = supcon(G, E)
    t2 = time.perf_counter()
    c = ccc(res.supervisor, semantics, full=False)
    t3 = time.perf_counter()
    return {
        "status": "ok",
        "positioners": positioners,
        "steps": steps,
        "model": model,
        "seed": seed,
        "supervisor_states": res.stats["states"],
        "supervisor_transitions": res.stats["transitions"],
        "bdd_nodes": res.stats["bdd_nodes"],
        "ccc": c.forcible,
        "rank": c.rank,
        "witness_length": len(c.witness),
        "seconds": round(t3 - t0, 4),
        "timings": {"build": round(t1 - t0, 4), "supcon": round(t2 - t1, 4), "ccc": round(t3 - t2, 4),
                    "supcon_iterations": res.stats.get("iterations")},
    }


def _coupled_instance(positioners: int, steps: int, seed: int):
    """Random starts/targets whose configurations are free of hard collisions (rejection
    sampling per positioner, in layout order, against the ones already placed)."""
    import numpy as np

    from ..positioners.coupled import CoupledModel
    from ..positioners.paper import hex_neighbours, hex_sites, PaperInstance

    rng = np.random.default_rng(seed)
    xy = hex_sites(positioners)
    base = PaperInstance(steps, (0,) * positioners, (0,) * positioners, tuple(range(1, positioners + 1)), hex_neighbours(xy))
    model = CoupledModel(base)
    confs = []
    for _ in range(2):
        conf: list[int] = []
        for i in range(positioners):
            choices = [q for q in rng.permutation(steps)
                       if not any(model.zone[(i, j)][q, conf[j]] for j in model.neighbours[i] if j < i)]
            if not choices:
                raise InputError(f"could not place P{i + 1} without a collision (seed {seed})", value=seed, where="--seed")
            conf.append(int(choices[0]))
        confs.append(tuple(conf))
    return PaperInstance(steps, confs[0], confs[1], base.priority, base.neighbours)


def run(args: argparse.Namespace, console: Console) -> CommandResult:
    from ..symbolic.context import Context

    ctx = Context(args.backend, budget=budget_from_args(args), progress=console.progress)
    payload = solve_paper(args.positioners, args.steps, args.model, args.seed, args.semantics, ctx)
    text = (f"{payload['model']} model, {payload['positioners']} positioners, {payload['steps']} steps (seed {payload['seed']}): "
            f"V has {payload['supervisor_states']} states, {payload['bdd_nodes']} BDD nodes; "
            f"CCC {'forcible' if payload['ccc'] else 'NOT forcible'}"
            + (f", witness of {payload['witness_length']} events" if payload['ccc'] else "")
            + f"; {payload['seconds']} s (build {payload['timings']['build']}, supcon {payload['timings']['supcon']}, "
              f"ccc {payload['timings']['ccc']})")
    return CommandResult(payload, text)
