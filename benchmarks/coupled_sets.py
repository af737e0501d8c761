"""The coupled paper model: which sets are hard, and what CCC's layers cost.

Reproduces the figures of docs/paper.md, section "The supervisor without its reachable
set", for the instances of ``bench_coupled.py`` (``coupled_instance(N, 8, seed)``, the
``auto`` order), one fresh subprocess per ``N``:

- BDD nodes of ``Reach(G × E)`` and of its projections on the positions and on the
  positions and collision levels; whether the positions it reaches are exactly the
  collision-free configurations;
- BDD nodes and seconds of the controllable nonblocking set over all states
  (``supcon(..., accessible=False)``);
- CCC's preemptive layers up to ``q0`` on that supervisor with every event relation as is
  and restricted to the sources where its kind counts (what ``forcible_layers`` does):
  seconds, rank, same witness;
- the verdict alone, ``W(∞)`` computed by alternating backward reachability through calm
  states (no uncontrollable event pending) with the uncontrollable step: a prototype of a
  route the package does not have (it gives no rank), timed against the layers.

Usage::

    python benchmarks/coupled_sets.py                      # N = 5, 6, 7; writes results/coupled_sets.md
    python benchmarks/coupled_sets.py --sizes 5 6 --out /tmp/x.md
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))


def worker(size: int, seed: int) -> dict:
    from dataclasses import replace

    import numpy as np

    from supcoord.bdd import Context
    from supcoord.des.symbolic import SymbolicGenerator
    from supcoord.geometry.collision import placed_segments, segment_distance
    from supcoord.paper.coupled import CoupledModel, coupled_models
    from supcoord.paper.run import coupled_instance
    from supcoord.synthesis import supcon
    from supcoord.synthesis.forcibility import clusters, force, uncontrollable_enabled
    from supcoord.synthesis.product import product
    from supcoord.synthesis.reachability import coreachable, reachable
    from supcoord.synthesis.witness import witness
    from supcoord.synthesis.layers import Layers

    model = CoupledModel(coupled_instance(size, 8, seed))
    ctx = Context()
    G, E = coupled_models(model, ctx)
    out: dict = {"size": size, "seed": seed}
    names = {k: [f"{k}{i + 1}" for i in range(size)] for k in ("pos", "lvl", "cnt")}

    t = time.perf_counter()
    r = reachable(product(G, E))
    out["reach_seconds"] = round(time.perf_counter() - t, 2)
    out["reach_nodes"] = ctx.node_count(r)
    pos_lvl = ctx.exist(names["cnt"], r)
    pos = ctx.exist(names["lvl"], pos_lvl)
    out["reach_pos_lvl_nodes"], out["reach_pos_nodes"] = ctx.node_count(pos_lvl), ctx.node_count(pos)
    steps = np.arange(8, dtype=float)[:, None]
    free = ctx.true  # collision-free configurations, from the arms' geometry at rest
    for i in range(size):
        for j in model.neighbours[i]:
            if i < j:
                a = placed_segments(model.kin, model.bases[i], steps)[:, None]
                b = placed_segments(model.kin, model.bases[j], steps)[None, :]
                close = segment_distance(a[..., 0, :], a[..., 1, :], b[..., 0, :], b[..., 1, :]) < 2 * model.geo.buffer
                free &= ~model._table_bdd(ctx, i, j, close)
    out["positions_are_the_collision_free_ones"] = pos == free

    t = time.perf_counter()
    V = supcon(G, E, accessible=False, count_transitions=False).supervisor
    out["whole_seconds"] = round(time.perf_counter() - t, 2)
    out["whole_nodes"] = ctx.node_count(V.invariant)

    Q = V.invariant
    env = uncontrollable_enabled(V)
    plain = clusters(V)
    restricted = [replace(g, relation=g.relation & Q & (~env if g.controllable else env)) for g in plain]
    for label, groups in (("plain", plain), ("restricted", restricted)):
        t = time.perf_counter()
        w, layers, cache = V.marked & Q, [V.marked & Q], {}
        while (V.init & ~w) != ctx.false:
            w2 = w | force(V, w, Q, env, "preemptive", groups, cache)
            if w2 == w:
                break
            layers.append(w2 & ~w)
            w = w2
        lay = Layers(V, layers, w, "preemptive", env, False, {})
        out[f"layers_{label}_seconds"] = round(time.perf_counter() - t, 2)
        out[f"layers_{label}_rank"] = lay.rank(V.init)
        out[f"layers_{label}_witness"] = witness(V, lay, V.init)

    t = time.perf_counter()  # the verdict alone: W(∞) by alternation
    calm = {n: replace(e, relation=e.relation & Q & ~env) for n, e in V.events.items() if e.event.controllable}
    Vc = SymbolicGenerator(ctx, "calm", V.variables, calm, V.init, V.marked, V.invariant)
    unc = [g for g in plain if not g.controllable]
    w, rounds = V.marked & Q, 0
    while (V.init & ~w) != ctx.false:
        rounds += 1
        w1 = coreachable(Vc, w)  # reach W by controllable moves at calm states
        bad = ctx.false  # pending states with an uncontrollable successor outside W
        for g in unc:
            w_p = ctx.and_exist(w1, g.ident, g.bits)
            inv_p = ctx.and_exist(Q, g.ident, g.bits)
            bad |= ctx.and_exist(g.relation & env, inv_p & ~w_p, g.primed_bits)
        w2 = w1 | (env & Q & ~bad)
        if w2 == w:
            break
        w = w2
    out["verdict_seconds"] = round(time.perf_counter() - t, 2)
    out["verdict_rounds"] = rounds
    out["verdict"] = (V.init & ~w) == ctx.false
    return out


def _machine() -> dict:
    sys.path.insert(0, HERE)
    from bench_coupled import _machine as machine

    return machine()


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[5, 6, 7])
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--timeout", type=float, default=900.0, help="seconds per size (default 900)")
    ap.add_argument("--out", default=os.path.join(HERE, "results", "coupled_sets.md"))
    ap.add_argument("--worker", nargs=2, type=int, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.worker:
        print("R", json.dumps(worker(*args.worker)), flush=True)
        return 0
    command = "python benchmarks/coupled_sets.py " + " ".join(argv if argv is not None else sys.argv[1:])
    machine, load = _machine(), os.getloadavg()
    rows = []
    for n in args.sizes:
        try:
            p = subprocess.run([sys.executable, os.path.abspath(__file__), "--worker", str(n), str(args.seed)],
                               capture_output=True, text=True, timeout=args.timeout, check=False)
            line = next((ln[2:] for ln in p.stdout.splitlines() if ln.startswith("R ")), None)
            row = json.loads(line) if line else {"size": n, "status": f"exit {p.returncode}"}
        except subprocess.TimeoutExpired:
            row = {"size": n, "status": f"> {args.timeout:g} s"}
        rows.append(row)
        print(json.dumps(row), file=sys.stderr, flush=True)
    head = ["N", "Reach nodes (s)", "positions / + levels", "positions = collision-free", "whole-space Z nodes (s)",
            "layers s: plain / restricted", "rank", "same witness", "verdict alone s (rounds)"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in rows:
        if "reach_nodes" not in r:
            lines.append(f"| {r['size']} | {r['status']} |" + " |" * (len(head) - 2))
            continue
        same = r["layers_plain_witness"] == r["layers_restricted_witness"] and \
            r["layers_plain_rank"] == r["layers_restricted_rank"]
        lines.append(f"| {r['size']} | {r['reach_nodes']:,} ({r['reach_seconds']}) | {r['reach_pos_nodes']:,} / "
                     f"{r['reach_pos_lvl_nodes']:,} | {'yes' if r['positions_are_the_collision_free_ones'] else 'NO'} | "
                     f"{r['whole_nodes']:,} ({r['whole_seconds']}) | {r['layers_plain_seconds']} / "
                     f"{r['layers_restricted_seconds']} | {r['layers_restricted_rank']} | {'yes' if same else 'NO'} | "
                     f"{r['verdict_seconds']} ({r['verdict_rounds']}, {'forcible' if r['verdict'] else 'not forcible'}) |")
    text = "\n".join(lines)
    print(text)
    body = (f"# The coupled paper model: hard sets and CCC's layers\n\nCommand: `{command.strip()}`  \n"
            f"Date: {machine['date']}; machine: {machine['uname']}, {machine['cpus']} CPUs, Python "
            f"{machine['python']}; code: `{machine['version']}`  \nLoad (1/5/15 min) before: "
            f"{', '.join(f'{x:.2f}' for x in load)}; the machine is shared, read ratios within a row.  \n"
            f"n = 8 steps, seed {args.seed}, the `auto` order; seconds inside the worker.\n\n{text}\n\n"
            "Raw rows (JSON):\n\n```\n" + "".join(json.dumps(r) + "\n" for r in rows) + "```\n")
    tmp = args.out + ".tmp"
    with open(tmp, "w") as f:
        f.write(body)
    os.replace(tmp, args.out)  # atomic: a reader never sees half a file
    print(f"written {args.out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
