"""The seed paper's model at scale: N positioners, four routes side by side.

A thin wrapper over the study ``benchmarks/studies/paper.toml`` (``docs/study.md``).  For
each model and number of positioners ``N`` (seeded random starts and targets on the hex
grid, priorities = indices; ``supcoord paper``'s instances) each route is one case of the
study — a ``call`` of :func:`study_case` — run in a fresh process with a time limit (60 s)
and a 6 GiB memory limit; a route runs its sizes in order and, once one runs out of time
or memory, not on larger ``N`` ("not run"):

- ``modular`` (literal model only): :func:`supcoord.paper.modular.literal_modular`
  — one supcon per distinct positioner, ``V`` = the product restricted to ``∏ Z_i``
  (Theorem 1), CCC by Theorem 2's certificate;
- ``monolithic``: the generic symbolic ``supcon`` and ``ccc`` on the whole product;
- ``explicit``: the explicit twin (``literal_models_explicit``/``coupled_models_explicit``,
  ``supcon_naive``, ``forcible_layers_naive``);
- ``libFAUDES``: ``Parallel`` of the plant components and of the specifications,
  ``InvProject`` (= ``allevents(G) || S``), ``SupCon`` (no forcibility in libFAUDES).

Seconds are measured inside the case (build + supcon + CCC; the interpreter start and
imports are not included; ``wall s`` is the whole case process); peak RSS is the case
process's ``ru_maxrss`` (CUDD's and libFAUDES's C++ allocations included).  Every
route's supervisor size (state count, exactly, as a residue mod 2^61 − 1 plus its
log10), BDD node count (symbolic routes) and CCC verdict are compared on each ``N``
where more than one finishes.  The results database is ``results/paper.sqlite``; the
tables ``results/paper.md`` and ``results/paper.csv`` are written from it.

Usage::

    python benchmarks/bench_paper.py            # run what is missing, write results/paper.md and paper.csv
    python benchmarks/bench_paper.py --no-run   # only rewrite the tables from the database
    python benchmarks/bench_paper.py --quick    # small sizes, 20 s limit, to /tmp, prints the tables
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import math
import os
import platform
import resource
import statistics
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
LITERAL_SIZES = [1, 2, 3, 10, 30, 100, 300, 500, 1000, 3000, 5000]
COUPLED_SIZES = [2, 3, 4, 5, 6, 7, 12, 19]
QUICK = {"literal": [1, 2, 10, 100], "coupled": [2, 3]}
STEPS = {"literal": 12, "coupled": 8}
ROUTES = {"literal": ["modular", "monolithic", "explicit", "faudes"], "coupled": ["monolithic", "explicit", "faudes"]}
RESIDUE = 2**61 - 1


# -- workers (one measurement, in a fresh subprocess) -----------------------------------------


def _instance(model: str, size: int, steps: int, seed: int):
    from supcoord.paper.literal import random_instance
    from supcoord.paper.run import coupled_instance

    return random_instance(size, steps, seed) if model == "literal" else coupled_instance(size, steps, seed)


def _peak_rss_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024  # kB on Linux


def _count(states: int) -> dict:
    return {"states_residue": states % RESIDUE, "states_log10": round(math.log10(states), 4) if states else None,
            "states": states if states < 10**15 else None}


def worker_symbolic(model: str, route: str, size: int, steps: int, seed: int) -> dict:
    from supcoord.bdd import Context
    from supcoord.paper.run import run_paper

    inst = _instance(model, size, steps, seed)
    Context()  # load dd.cudd before timing
    t0 = time.perf_counter()
    r = run_paper(model=model, route=route, instance=inst, ctx=Context(), count_transitions=False)
    seconds = time.perf_counter() - t0
    st = r.supcon.stats
    return {**_count(st["states"]), "bdd_nodes": st["bdd_nodes"], "ccc": r.ccc.forcible, "rank": r.ccc.rank,
            "seconds": seconds, "timings": r.payload["timings"], "peak_rss_mb": _peak_rss_mb(),
            "certificate": bool(r.ccc.stats.get("certificate"))}


def worker_explicit(model: str, size: int, steps: int, seed: int) -> dict:
    from supcoord.paper.coupled import CoupledModel, coupled_models_explicit
    from supcoord.paper.literal import literal_models_explicit
    from supcoord.synthesis import forcible_layers_naive, supcon_naive
    from supcoord.synthesis.forcibility import rank_naive

    inst = _instance(model, size, steps, seed)
    t0 = time.perf_counter()
    G, E = literal_models_explicit(inst) if model == "literal" else coupled_models_explicit(CoupledModel(inst))
    V = supcon_naive(G, E)
    t1 = time.perf_counter()
    rank = rank_naive(forcible_layers_naive(V, V.marked, "preemptive"), V.init) if V.init is not None else None
    t2 = time.perf_counter()
    return {**_count(V.n_states), "ccc": rank is not None, "rank": rank, "seconds": t2 - t0,
            "timings": {"supcon": t1 - t0, "ccc": t2 - t1}, "peak_rss_mb": _peak_rss_mb()}


def worker_faudes(model: str, size: int, steps: int, seed: int) -> dict:
    import tempfile

    import faudes

    from supcoord.des.io.gen_file import write_gen
    from supcoord.paper.coupled import CoupledModel
    from supcoord.paper.coupled import plant_explicit as coupled_plant
    from supcoord.paper.literal import plant_explicit, spec_explicit

    inst = _instance(model, size, steps, seed)
    if model == "literal":
        plants = [plant_explicit(inst.number(i), steps, inst.start[i], inst.target[i], inst.priority_kind(i))
                  for i in range(size)]
        specs = [spec_explicit(inst.number(i), steps, inst.start[i], inst.target[i]) for i in range(size)]
    else:  # the coupled plant is not a product of components: enumerate it (timed)
        plants = None
        specs = [spec_explicit(i + 1, steps, inst.start[i], inst.target[i], sees_priority=True, absorbing=False)
                 for i in range(size)]
    with tempfile.TemporaryDirectory() as tmp:
        def load(g, name):
            path = os.path.join(tmp, f"{name}.gen")
            write_gen(g, path)
            return faudes.System(path)

        S_parts = [load(g, f"s{i}") for i, g in enumerate(specs)]
        t0 = time.perf_counter()
        P_parts = [load(g, f"p{i}") for i, g in enumerate(plants)] if plants else [load(coupled_plant(CoupledModel(inst)), "G")]
    t_load = time.perf_counter() - t0 if plants is None else 0.0
    t0 = time.perf_counter()

    def parallel(parts):
        out = parts[0]
        for g in parts[1:]:
            nxt = faudes.System()
            faudes.Parallel(out, g, nxt)
            out = nxt
        return out

    P, S = parallel(P_parts), parallel(S_parts)
    faudes.InvProject(S, P.Alphabet())  # = allevents(G) || S
    R = faudes.System()
    faudes.SupCon(P, S, R)
    seconds = time.perf_counter() - t0 + t_load
    return {**_count(R.Size()), "ccc": None, "seconds": seconds, "peak_rss_mb": _peak_rss_mb(),
            "plant_states": P.Size()}


def worker(route: str, model: str, size: int, steps: int, seed: int) -> dict:
    if route in ("modular", "monolithic"):
        return worker_symbolic(model, route, size, steps, seed)
    if route == "explicit":
        return worker_explicit(model, size, steps, seed)
    return worker_faudes(model, size, steps, seed)


def study_case(route: str, model: str, positioners: int, steps: int, seed: int = 0) -> dict:
    """One route on one instance, as a ``call`` case of the study: :func:`worker`'s
    measurement with the study's names (``verdict``: the CCC's, none for libFAUDES)."""
    r = worker(route, model, positioners, steps, seed)
    out = {k: v for k, v in r.items() if k != "peak_rss_mb"}
    if r.get("ccc") is not None:
        out["verdict"] = "forcible" if r["ccc"] else "not forcible"
    if out.get("states") is not None:
        out["states"] = str(out["states"])
    return out


# -- driver ------------------------------------------------------------------------------------


def machine() -> dict:
    cpu, ram = "?", "?"
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next(line.split(":", 1)[1].strip() for line in f if line.startswith("model name"))
        with open("/proc/meminfo") as f:
            ram = f"{int(next(line.split()[1] for line in f if line.startswith('MemTotal'))) / 2**20:.1f} GiB"
    except (OSError, StopIteration):
        pass
    import dd
    import faudes

    return {"nproc": os.cpu_count(), "cpu": cpu, "ram": ram, "python": platform.python_version(),
            "dd": getattr(dd, "__version__", "?"), "faudes": faudes.Version(), "platform": platform.platform()}


def load() -> str:
    return " / ".join(f"{x:.2f}" for x in os.getloadavg())


def cell(r: dict | None, key: str, digits: int = 2) -> str:
    if r is None:
        return "not run"
    if r["status"] != "ok":
        return {"timeout": "timeout", "memory": "out of memory"}.get(r["status"], "error")
    x = r.get(key)
    if x is None:
        return "–"
    if isinstance(x, bool):
        return "yes" if x else "no"
    if isinstance(x, float):
        return f"{x:.{digits}f}" if x < 100 else f"{x:.0f}"
    return f"{x:,}" if isinstance(x, int) else str(x)


def states_cell(results: dict) -> str:
    for r in results.values():
        if r and r["status"] == "ok":
            if r.get("states") is not None:
                return f"{r['states']:,}"
            return f"10^{r['states_log10']:.1f}"
    return "?"


def agreement(results: dict) -> str:
    ok = {k: r for k, r in results.items() if r and r["status"] == "ok"}
    if len(ok) < 2:
        return "–"
    problems = []
    if len({r["states_residue"] for r in ok.values()}) > 1:
        problems.append("states " + ", ".join(f"{k}={r.get('states') or r['states_log10']}" for k, r in ok.items()))
    nodes = {r["bdd_nodes"] for r in ok.values() if "bdd_nodes" in r}
    if len(nodes) > 1:
        problems.append(f"BDD nodes {sorted(nodes)}")
    verdicts = {r["ccc"] for r in ok.values() if r.get("ccc") is not None}
    if len(verdicts) > 1:
        problems.append("CCC verdicts differ")
    return "MISMATCH: " + "; ".join(problems) if problems else f"yes ({len(ok)})"


def table(model: str, rows: list[dict]) -> list[str]:
    routes = ROUTES[model]
    names = {"modular": "modular", "monolithic": "monolithic", "explicit": "explicit twin", "faudes": "libFAUDES"}
    head = ["positioners", "V states"]
    for r in routes:
        head += [f"{names[r]} s", f"{names[r]} wall s"]
        if r in ("modular", "monolithic"):
            head.append(f"{names[r]} BDD nodes")
        head.append(f"{names[r]} peak RSS MB")
    head += ["CCC", "routes agree"]
    out = ["| " + " | ".join(head) + " |", "|" + "---:|" * (len(head) - 1) + "---|"]
    for row in rows:
        res = row["results"]
        cells = [str(row["positioners"]), row["states"]]
        for r in routes:
            cells += [cell(res[r], "seconds", 3), cell(res[r], "wall")]
            if r in ("modular", "monolithic"):
                cells.append(cell(res[r], "bdd_nodes"))
            cells.append(cell(res[r], "peak_rss_mb", 0))
        verdict = next((x["ccc"] for x in res.values() if x and x["status"] == "ok" and x.get("ccc") is not None), None)
        cells += ["forcible" if verdict else ("not forcible" if verdict is False else "?"), row["agree"]]
        out.append("| " + " | ".join(cells) + " |")
    return out


def write_csv(path: str, rows: list[dict]) -> None:
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["model", "positioners", "steps", "route", "status", "seconds", "wall_seconds", "bdd_nodes",
                    "states_log10", "peak_rss_mb", "ccc", "load"])
        for row in rows:
            for route, r in row["results"].items():
                if r is None:
                    w.writerow([row["model"], row["positioners"], row["steps"], route, "not run"] + [""] * 6 + [row["load"]])
                    continue
                w.writerow([row["model"], row["positioners"], row["steps"], route, r["status"], r.get("seconds", ""),
                            r.get("wall", ""), r.get("bdd_nodes", ""), r.get("states_log10", ""),
                            r.get("peak_rss_mb", ""), r.get("ccc", ""), row["load"]])


def from_database(db_rows: list[dict], model: str, sizes: list[int]) -> list[dict]:
    """The rows of :func:`table` (one per size, the routes side by side) from the study's rows."""
    rows = []
    for size in sizes:
        results: dict[str, dict | None] = {}
        for route in ROUTES[model]:
            r = next((x for x in db_rows if x["series"] == f"{model} {route}" and x["positioners"] == size), None)
            if r is None or r["status"] == "skipped":
                results[route] = None
                continue
            extra = r.get("extra") or {}
            status = {"ok": "ok", "timeout": "timeout", "out-of-memory": "memory"}.get(r["status"], "error")
            results[route] = {**extra, "status": status, "seconds": r["seconds"], "wall": r["wall_seconds"],
                              "bdd_nodes": r["bdd_nodes"], "peak_rss_mb": r["peak_rss_mb"],
                              "states": int(r["states"]) if r.get("states") else None,
                              "states_log10": r["states_log10"], "error": r["message"], "load": r["load"]}
            if r["bdd_nodes"] is None:
                results[route].pop("bdd_nodes")
        loads = [x["load"] for x in results.values() if x and x.get("load") is not None]
        rows.append({"model": model, "positioners": size, "steps": STEPS[model], "results": results,
                     "states": states_cell(results), "agree": agreement(results),
                     "load": f"{max(loads):.2f}" if loads else ""})
    return rows


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--study", default=os.path.join(HERE, "studies", "paper.toml"))
    ap.add_argument("--db", help="results database (default: the study's)")
    ap.add_argument("--workers", type=int, help="Dask worker processes (default: the study's, 2)")
    ap.add_argument("--no-run", action="store_true", help="only write the tables from the database")
    ap.add_argument("--any-version", action="store_true", help="cases run by any code version count as done")
    ap.add_argument("--quick", action="store_true", help="small sizes, 20 s limit, database in /tmp, print only")
    ap.add_argument("--out", default=None, help="markdown results file (default results/paper.md; quick: none)")
    args = ap.parse_args(argv)
    from supcoord.study import load_study, results_rows, run_study

    study = load_study(args.study)
    db = args.db
    sizes = {m: (QUICK[m] if args.quick else LITERAL_SIZES if m == "literal" else COUPLED_SIZES) for m in ROUTES}
    if args.quick:
        study.cases = [dataclasses.replace(c, time_limit=20.0) for c in study.cases
                       if c.params["positioners"] in sizes[c.params["kwargs"]["model"]]]
        db = db or "/tmp/supcoord-paper.sqlite"
    out = args.out or (None if args.quick else os.path.join(HERE, "results", "paper.md"))
    db = str(study.database_path(db))
    log = lambda s: print(s, file=sys.stderr, flush=True)
    command = "python benchmarks/bench_paper.py" + " ".join([""] + (argv if argv is not None else sys.argv[1:]))
    if not args.no_run:
        run_study(study, db, workers=args.workers, progress=log, any_version=args.any_version, command=command)
    db_rows = results_rows(db, study=study)
    ran = [r for r in db_rows if r.get("cpu")]
    m = machine()
    loads = [r["load"] for r in ran if r.get("load") is not None]
    limits = sorted({f"{r['time_limit']:g} s" for r in ran})
    lines = [
        "# The seed paper's model at scale: modular vs monolithic (symbolic) vs explicit twin vs libFAUDES",
        "",
        f"- command: `{command.strip()}` (the study `benchmarks/studies/paper.toml`; database `results/paper.sqlite`)",
        (f"- cases started between {min(r['started'] for r in ran)} and {max(r['started'] for r in ran)} UTC; "
        f"code {', '.join(sorted({r['version'] for r in ran}))}"),
        f"- machine: {', '.join(sorted({r['cpu'] for r in ran}))}, RAM {m['ram']}, {m['platform']}",
        (f"- load (1 min) at the start of a case: median {statistics.median(loads):.1f}, max {max(loads):.1f} "
        "(the machine is shared with other agents: seconds are noisy; compare routes within a row)"),
        f"- versions: Python {m['python']}, dd {m['dd']} (CUDD), {m['faudes']}",
        (f"- instances: `supcoord paper`'s (seed 0; literal n = {STEPS['literal']}, coupled n = {STEPS['coupled']}); "
        "each run a case of the study in a fresh process with a time limit of "
        f"{', '.join(limits)} and 6 GiB of address space, on 2 Dask "
        "workers; after a time-out a route is not run on larger N"),
        ("- seconds: inside the case (build + supcon + CCC, imports excluded); wall s: the whole case process "
        "(interpreter start and imports included). Peak RSS: the case process's `ru_maxrss`."),
        ("- routes agree: supervisor state counts equal (exactly, mod 2^61 − 1), BDD nodes equal between the two "
        "symbolic routes, CCC verdicts equal (libFAUDES has no forcibility); the count of routes compared in parentheses"),
        "",
    ]
    rows = []
    for model in ROUTES:
        mr = from_database(db_rows, model, sizes[model])
        rows += mr
        lines += [f"## {model} model, n = {STEPS[model]}", ""] + table(model, mr) + [""]
    text = "\n".join(lines)
    print(text)
    if out:
        with open(out, "w") as f:
            f.write(text)
        write_csv(os.path.splitext(out)[0] + ".csv", rows)
        log(f"wrote {out} and {os.path.splitext(out)[0]}.csv")
    return 0


if __name__ == "__main__":
    sys.exit(main())
