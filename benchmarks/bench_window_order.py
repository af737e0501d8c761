"""The costliest window search of a run: its images and its members' variable order.

Solves ``supcoord.preset_problem("sdss-v", rings, seed, alpha_steps=A, beta_steps=B)``
(``improve=0``) and keeps the window search that took longest (on SDSS-V's 127 robots at
36 × 19 positions: a 5-robot window, at most 2 members displaced, 42 moves).  On it:

1. **images**, side by side on the last layers of both sides, alternating so that CUDD's
   cache favours neither: ``entry`` = :func:`supcoord.planning.search.image` (the
   invariant conjoined into each event's first conjunct, :meth:`GuardedSystem.pre`),
   ``after`` = the invariant conjoined once after the union of the pre-images (the code
   before);
2. **orders**: the window rebuilt in every order of its members (up to 6 members), its
   forward layers computed ``--layers`` deep; reports the seconds and nodes of each order,
   and the rank of the order the windows use (least cutwidth,
   :func:`supcoord.planning.graph_order.cutwidth_order`) among them.

Writes ``results/window_order.md`` with the command, machine and load.

    python benchmarks/bench_window_order.py
    python benchmarks/bench_window_order.py --steps 36x19 --layers 14 --repeat 2
"""

from __future__ import annotations

import argparse
import itertools
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", default="36x19", help="AxB positions")
    ap.add_argument("--rings", type=int, default=6, help="hex rings (6: 127 robots)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--layers", type=int, default=14, help="forward layers per member order")
    ap.add_argument("--repeat", type=int, default=2, help="rounds of the image comparison")
    ap.add_argument("--out", default=str(HERE / "results" / "window_order.md"))
    args = ap.parse_args()
    sys.path.insert(0, str(ROOT / "src"))
    import supcoord
    from supcoord.planning import search as search_mod
    from supcoord.planning import windows
    from supcoord.planning.graph_order import cutwidth_order
    from supcoord.planning.model import CoordinationModel
    from supcoord.study.machine import code_version, cpu_model, load, machine

    load_before = load()
    a, b = (int(v) for v in args.steps.lower().split("x"))
    problem = supcoord.preset_problem("sdss-v", rings=args.rings, seed=args.seed, alpha_steps=a, beta_steps=b)
    slowest: dict = {"seconds": -1.0}
    context: dict = {}
    real_search, real_few = windows.search, windows._Windows._few_displaced

    def few(win, wm, S, goal, p, members, c, cap):  # noqa: PLR0913 (the wrapped signature)
        context.update(p=p, c=c.copy(), base=S)
        return real_few(win, wm, S, goal, p, members, c, cap)

    def timed(S, goal, max_nodes=None, mode="bidirectional"):
        t0 = time.perf_counter()
        res = real_search(S, goal, max_nodes=max_nodes, mode=mode)
        seconds = time.perf_counter() - t0
        if seconds > slowest["seconds"] and context.get("base") is not None:
            slowest.update(seconds=seconds, S=S, res=res, p=context["p"], c=context["c"], base=context["base"])
        return res

    windows.search, windows._Windows._few_displaced = timed, few
    t0 = time.perf_counter()
    plan = supcoord.solve(problem, improve=0)
    solve_seconds = time.perf_counter() - t0
    windows.search, windows._Windows._few_displaced = real_search, real_few
    S, res = slowest["S"], slowest["res"]
    members, p, c = list(S.members), slowest["p"], slowest["c"]
    others = [q for q in members if q != p]
    base = slowest["base"]
    bound = next(k for k in range(len(others) + 1)
                 if S.invariant == base.invariant & S.model.displaced_at_most(others, c, k))
    ctx = S.model.ctx

    def after(x):  # the invariant once, after the union (the code before)
        parts, primed = [], {}
        for e, mv in S.moves.items():
            xp = primed.get(mv.var)
            if xp is None:
                xp = primed[mv.var] = S.prime(x, mv.var)
            first, *rest = S.relation(e)
            out = ctx.and_exist(first, xp, ctx.bits([mv.var], primed=True))
            for g in rest:
                out &= g
            parts.append(out)
        while len(parts) > 1:
            parts = [parts[i] | parts[i + 1] if i + 1 < len(parts) else parts[i] for i in range(0, len(parts), 2)]
        return parts[0] & S.invariant

    layers = res.fwd[-6:] + res.bwd[-6:]
    image_seconds = {"entry": 0.0, "after": 0.0}
    for _ in range(args.repeat):
        for name, fn in (("entry", lambda x: search_mod.image(S, x)), ("after", after)):
            t0 = time.perf_counter()
            outs = [fn(x) for x in layers]
            image_seconds[name] += time.perf_counter() - t0
            if name == "entry":
                reference = outs
            elif outs != reference:
                raise SystemExit("the two images differ")

    def forward(order):
        wm = CoordinationModel(problem, order=order, members=members)
        R = wm.system(members, c, init=c, merged=True)
        R = R.restricted(wm.displaced_at_most(others, c, bound))
        t0 = time.perf_counter()
        frontier = wall = R.init & R.invariant
        for _ in range(args.layers):
            frontier = search_mod.image(R, frontier) & ~wall
            wall |= frontier
        return time.perf_counter() - t0, len(frontier), len(wall)

    rows = []
    if len(members) <= 6:
        for order in itertools.permutations(members):
            rows.append((*forward(list(order)), list(order)))
    rows.sort()
    picks = {"least cutwidth (the windows' order)": cutwidth_order(problem, members)}

    header = f"python benchmarks/bench_window_order.py {' '.join(sys.argv[1:])}".strip()
    lines = [f"# The costliest window search: SDSS-V preset, {args.rings} rings, seed {args.seed}, {args.steps}", "",
             f"Command: `{header}`; supcoord {code_version()}.", "",
             f"Machine: {machine()}, {cpu_model()}; load {load_before} before, {load()} after; "
             f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}.", "",
             f"The run: {plan.status} in {solve_seconds:.1f} s (`improve=0`).  Its longest window search: "
             f"{slowest['seconds']:.2f} s, members {members} (robot {p} to its target, at most {bound} others "
             f"displaced), distance {res.distance}, {len(res.fwd) - 1} forward and {len(res.bwd) - 1} backward "
             f"layers, the largest {max(len(x) for x in res.fwd + res.bwd):,} nodes.", "",
             f"## Images of its last {len(layers)} layers ({args.repeat} rounds, alternating)", "",
             "| invariant | s | ratio |", "|---|---|---|",
             f"| in each event's first conjunct (now) | {image_seconds['entry']:.2f} | 1.00 |",
             f"| once after the union (before) | {image_seconds['after']:.2f} | "
             f"{image_seconds['after'] / image_seconds['entry']:.2f} |", ""]
    if rows:
        lines += [f"## Its {len(rows)} member orders, {args.layers} forward layers each", "",
                  "| order | s | rank | last layer nodes | reached nodes |", "|---|---|---|---|---|"]
        rank = {tuple(r[3]): i + 1 for i, r in enumerate(rows)}
        by_order = {tuple(r[3]): r for r in rows}
        for name, order in picks.items():
            r = by_order[tuple(order)]
            lines.append(f"| {name} {order} | {r[0]:.2f} | {rank[tuple(order)]} | {r[1]:,} | {r[2]:,} |")
        for label, r in (("fastest", rows[0]), ("median", rows[len(rows) // 2]), ("slowest", rows[-1])):
            lines.append(f"| {label} {r[3]} | {r[0]:.2f} | {rank[tuple(r[3])]} | {r[1]:,} | {r[2]:,} |")
    Path(args.out).write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
