"""The coupled paper model over many seeds: which instances the fast answers settle.

For each seed, ``coupled_instance(N, 8, seed)`` and, in CPU seconds of one process:

- ``h(q0)``: the A*'s lower bound (:mod:`supcoord.paper.settled_bound`, groups of 6);
- the blocked-group certificate (groups of up to 5 around each positioner): "not
  forcible", exact, with the group;
- else the greedy forcing string (:func:`supcoord.paper.settled_witness.greedy_witness`,
  at most ``--limit`` settled states), checked by replay: "forcible", exact, with the
  string's length, an upper bound on the rank;
- else projection refinement (:mod:`supcoord.paper.settled_refine`) backward from the
  target: "not forcible" where the start's projection is excluded; else a greedy search
  on configurations pruned by it (:func:`supcoord.paper.settled_witness.position_witness`);
  else the forward refinement inside it and the search again (what
  :func:`supcoord.paper.settled.settled_ccc` runs before its A*);
- else "open": the A* of :func:`supcoord.paper.settled.settled_ccc` must answer.

No A* runs here (``bench_coupled.py --variants settled`` times it).

Usage::

    python benchmarks/survey_coupled.py --size 19 --seeds 0 1 2 --limit 5000 --jobs 2 --out survey.md
"""

from __future__ import annotations

import argparse
import concurrent.futures
import datetime
import os
import time


def point(size: int, seed: int, limit: int) -> dict:
    """One seed: the bound, the certificate or the greedy string, CPU seconds of each."""
    from supcoord.paper.coupled import CoupledModel
    from supcoord.paper.run import coupled_instance
    from supcoord.paper.settled_bound import PatternBound
    from supcoord.paper.settled_witness import greedy_witness

    t0 = time.process_time()
    model = CoupledModel(coupled_instance(size, 8, seed))
    bound = PatternBound(model)
    group = bound.blocked_group(tuple(model.inst.start))
    t1 = time.process_time()
    row = {"seed": seed, "h": bound.value(tuple(model.inst.start)), "certificate_cpu": round(t1 - t0, 2)}
    if group is not None:
        return dict(row, answer="not forcible", group=[i + 1 for i in group])
    found = greedy_witness(model, bound, limit)
    t2 = time.process_time()
    row["greedy_cpu"] = round(t2 - t1, 2)
    if found is None:
        from supcoord.paper.settled import refined_answer

        proj, found = refined_answer(model, bound, None)
        row.update(refine_cpu=round(time.process_time() - t2, 2), kept=proj.sizes())
        if proj.excluded is not None:
            return dict(row, answer="not forcible", group=[i + 1 for i in proj.excluded],
                        how="forward" if proj.forward else "backward")
        if found is None:
            return dict(row, answer="open")
    return dict(row, answer="forcible", length=found.length, expanded=found.expanded)


def table(rows: list[dict]) -> str:
    out = ["| seed | h(q0) | answer | blocked group / string length | CPU s: bound + certificate | CPU s: greedy "
           "(states) | CPU s: refinement + search (how) |", "|---|---|---|---|---|---|---|"]
    for r in rows:
        what = ", ".join(f"P{i}" for i in r["group"]) if "group" in r else r.get("length", "")
        greedy = f"{r['greedy_cpu']} ({r.get('expanded', 'none found')})" if "greedy_cpu" in r else ""
        refined = f"{r['refine_cpu']} ({r.get('how', 'search')})" if "refine_cpu" in r else ""
        out.append(f"| {r['seed']} | {r['h'] if r['h'] is not None else '∞'} | {r['answer']} | {what} | "
                   f"{r['certificate_cpu']} | {greedy} | {refined} |")
    return "\n".join(out)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=int, default=19)
    ap.add_argument("--seeds", type=int, nargs="+", default=list(range(30)))
    ap.add_argument("--limit", type=int, default=5000, help="settled states the greedy search expands at most")
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--out", default=None, help="write the table here (markdown) as well")
    args = ap.parse_args()
    load = os.getloadavg()
    with concurrent.futures.ProcessPoolExecutor(args.jobs) as pool:
        rows = list(pool.map(point, [args.size] * len(args.seeds), args.seeds, [args.limit] * len(args.seeds)))
    text = table(rows)
    print(text)
    if args.out:
        date = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
        with open(args.out, "w") as f:
            f.write(f"# The coupled model at {args.size} positioners: certificate, greedy string or open\n\n")
            f.write(f"Command: `python benchmarks/survey_coupled.py --size {args.size} --seeds "
                    f"{' '.join(map(str, args.seeds))} --limit {args.limit} --jobs {args.jobs}`  \n")
            f.write(f"Date: {date}; {os.cpu_count()} CPUs; load (1/5/15 min) before: "
                    f"{', '.join(f'{x:.2f}' for x in load)}, after: "
                    f"{', '.join(f'{x:.2f}' for x in os.getloadavg())}. CPU seconds of each seed's process.\n\n")
            f.write(text + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
