"""The coupled reading of the paper's model (``supcoord paper --model coupled``): where the time goes.

For each number of positioners ``N`` (``coupled_instance(N, 8, seed)``: the first ``N``
hex sites, seeded starts and targets outside each other's safety zone) and each
variable order of :func:`supcoord.paper.coupled.positioner_order` — ``layout`` (the
hex grid's order) and ``auto`` (Cuthill–McKee on the neighbour graph where it
lowers the bandwidth) — one fresh subprocess with a time limit and a 6 GiB memory limit
builds ``G`` and ``allevents(G) || S``, runs ``supcon`` and ``ccc(full=False)`` (what
``supcoord paper --model coupled`` runs) and reports:

- seconds per stage: ``build``; inside supcon ``reach`` (``Reach(P)``), ``coreach``
  (the nonblocking and controllability fixpoints) and the rest (``B0``, exact counts);
  ``ccc`` (forcibility layers up to ``q0``, witness);
- the profile of the images (:class:`supcoord.synthesis.reachability.ImageProfile`):
  how many, seconds inside them, the largest operand and result (nodes: the intermediate
  sets, which the final sizes do not show), and the saturation clusters (how many; one
  cluster means saturation degenerates into chaining);
- peak live BDD nodes (CUDD), peak RSS, the reachable set's and ``V``'s BDD nodes;
- the results, which must not depend on the order: states, transitions, marked, CCC,
  rank, witness length.

Each point runs under one variant (``--variants``): ``new`` (default saturation: write
groups fired by their local transitive closure,
:data:`supcoord.synthesis.reachability.LOCAL_CLOSURES`), ``old`` (saturation over the
plain event steps, the code before that change), ``whole`` (``supcoord paper --model
coupled --route monolithic``: ``supcon(..., accessible=False)``, the supervisor on the
whole state space without ``Reach``, and CCC on it; the trim supervisor's sizes are then
counted, column ``count``, only up to ``AUTO_COUNT_COUPLED`` positioners) and
``settled`` (what ``supcoord paper --model coupled`` runs: CCC on the settled states,
:mod:`supcoord.paper.settled`, no supervisor built; ``settled-plain``: the same with the
A* bounded by the plain sum of ring distances instead of the pattern databases), so one run compares them on the
same machine and load; CCC, rank and witness must be equal under every variant and
order, and the sizes wherever they are counted.

``--rev REV`` also runs every variant with the code of an older git revision (its ``src``
and ``benchmarks`` exported by ``git archive``), next to this checkout's, labelled
``variant@REV``: a change measured against the code before it in the same run.

``--cpu SECONDS`` limits each worker's CPU time as well (``RLIMIT_CPU``: on a shared
machine the wall clock says little); ``--jobs K`` runs K points at once.  A settled point
stopped by a limit after its greedy search found a forcing string reports the verdict
(``yes``, proved by the checked string) and the string's length, an upper bound on the rank.
``--answer-cpu SECONDS`` ends each worker's budget at its first progress report past that
much CPU (as ``supcoord paper --timeout`` ends it on the wall clock): a settled point that
had proved "forcible" then answers with its string and the rank's bounds ``[lower, upper]``
(column ``rank``), not proved minimal.

A point that runs out of time reports the stage it was in; larger ``N`` are then not run
for that order (``--all`` runs them anyway, to show where each stops).  With ``--check`` (``N ≤ 4``) the worker also runs the explicit twin
(``supcon_naive``) and libFAUDES's ``SupCon`` and compares state and transition counts.

Usage::

    python benchmarks/bench_coupled.py --orders auto --variants whole settled --sizes 3 4 5 6 7 8 9 10 12 19 37 --all --check
    python benchmarks/bench_coupled.py --all --check --nodes   # N = 3..8, 19, 37, every variant
    python benchmarks/bench_coupled.py --orders auto --variants old new --all --check --nodes
    python benchmarks/bench_coupled.py --sizes 3 4 5 --timeout 60 --check
    python benchmarks/bench_coupled.py --orders auto --variants settled --sizes 6 8 10 12 --rev ae0fe25
    python benchmarks/bench_coupled.py --orders auto --variants settled --sizes 19 --seeds 0 1 2 --cpu 60 --timeout 900 --jobs 2 --all
    python benchmarks/bench_coupled.py --quick          # N = 3, 4; 30 s; prints, writes nothing
"""

from __future__ import annotations

import argparse
import concurrent.futures
import datetime
import json
import os
import platform
import resource
import signal
import subprocess
import sys
import tarfile
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
SIZES = [3, 4, 5, 6, 7, 8, 19, 37]
ORDERS = ["layout", "auto"]
VARIANTS = ["old", "new", "whole", "settled", "settled-plain"]
STEPS = 8
MEMORY = 6 * 2**30


def _rss_mb() -> float:
    return round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, 1)


def _emit(kind: str, data: dict) -> None:
    print(kind, json.dumps(data), flush=True)


def worker(size: int, steps: int, seed: int, order: str, check: bool, nodes: bool, variant: str = "new",
           answer_cpu: float | None = None) -> None:
    """One point; prints ``P {...}`` progress lines and a final ``R {...}`` line.  ``answer_cpu``:
    CPU seconds after which the next progress report ends the budget (``BudgetExceeded``, as
    ``--timeout`` ends it on the wall clock), so the settled route answers with what it proved."""
    from supcoord.bdd import Context
    from supcoord.errors import BudgetExceeded
    from supcoord.paper.coupled import CoupledModel, coupled_models, positioner_order
    from supcoord.paper.run import AUTO_COUNT_COUPLED, coupled_instance
    from supcoord.synthesis import accessible_part, ccc, supcon
    from supcoord.synthesis import reachability as R
    from supcoord.synthesis.product import product

    R.LOCAL_CLOSURES = variant != "old"  # "old": saturation over the plain event steps
    Context()  # load dd.cudd before timing
    t0 = time.perf_counter()
    last = {"stage": "build"}

    def progress(stage: str, info: dict) -> None:
        if stage != last.get("stage") or time.perf_counter() - last.get("t", 0.0) > 5:
            last.update(stage=stage, t=time.perf_counter())
            _emit("P", {"stage": stage, "at": round(time.perf_counter() - t0, 2), "nodes": info.get("nodes"),
                        "rss_mb": _rss_mb(), "cpu": round(time.process_time(), 2),
                        **({"upper_bound": info["upper_bound"]} if "upper_bound" in info else {})})
        if answer_cpu is not None and time.process_time() > answer_cpu:
            raise BudgetExceeded(f"CPU budget of {answer_cpu:g} s exceeded in {stage}", stats=info)

    ctx = Context(progress=progress)
    inst = coupled_instance(size, steps, seed)
    model = CoupledModel(inst)
    model.check()
    if variant.startswith("settled"):
        _settled(model, ctx, order, t0, seed, variant)
        return
    G, E = coupled_models(model, ctx, order=order)
    t1 = time.perf_counter()
    clusters = [len(c) for c in R.event_clusters(product(G, E))]
    fix = {"reach": 0.0, "coreach": 0.0}
    sizes = {}
    original = R._fixpoint

    def timed(G_, seeds, within, method, events, forward):  # instrumentation only
        t = time.perf_counter()
        out = original(G_, seeds, within, method, events, forward)
        key = "reach" if forward and within is None else "coreach" if not forward else "reach_within"
        fix[key] = fix.get(key, 0.0) + time.perf_counter() - t
        if key == "reach":
            sizes["reach_nodes"] = ctx.node_count(out)
        return out

    R._fixpoint = timed
    with R.ImageProfile(nodes=nodes) as prof:
        res = supcon(G, E, count_transitions=True, accessible=variant != "whole")
        t2 = time.perf_counter()
        images_supcon = prof.as_dict()
        _emit("P", {"stage": "ccc", "at": round(t2 - t0, 2), "rss_mb": _rss_mb()})
        c = ccc(res.supervisor, "preemptive", full=False)
    t3 = time.perf_counter()
    if variant == "whole" and size <= AUTO_COUNT_COUPLED:
        _emit("P", {"stage": "count", "at": round(t3 - t0, 2), "rss_mb": _rss_mb()})
        res = accessible_part(res)
    R._fixpoint = original
    t4 = time.perf_counter()
    st = res.stats
    out = {
        "size": size, "steps": steps, "seed": seed, "order": order, "variant": variant, "positioner_order": positioner_order(model, order),
        "states": st["states"], "transitions": st["transitions"], "marked": st["marked"], "ccc": c.forcible,
        "rank": c.rank, "witness_length": len(c.witness), "witness": c.witness,
        "seconds": round(t4 - t0, 3), "build": round(t1 - t0, 3), "supcon": round(t2 - t1, 3),
        "count": round(t4 - t3, 3) if variant == "whole" else None,
        "reach": round(fix["reach"], 3), "coreach": round(fix["coreach"] + fix.get("reach_within", 0.0), 3),
        "ccc_seconds": round(t3 - t2, 3), "ccc_layers": c.stats.get("iterations"),
        "clusters": clusters, "profile_supcon": images_supcon,
        "reach_nodes": sizes.get("reach_nodes"), "bdd_nodes": st["bdd_nodes"],
        "peak_nodes": ctx.peak_nodes(), "rss_mb": _rss_mb(),
    }
    if check and size <= 4:
        out.update(_check(model, st))
    _emit("R", out)


def _settled(model, ctx, order: str, t0: float, seed: int, variant: str) -> None:
    """The settled route (supcoord.paper.settled, what ``supcoord paper --model coupled``
    runs): no supervisor, so no sizes; CCC, rank and witness to compare.  ``settled-plain``
    bounds the A* by the plain sum of ring distances (pattern groups of one positioner)."""
    from supcoord.paper.coupled import positioner_order
    from supcoord.paper.settled import GROUP_SIZE, settled_ccc

    c = settled_ccc(model, ctx, order=order, group_size=1 if variant == "settled-plain" else GROUP_SIZE)
    st = c.stats
    _emit("R", {
        "size": model.inst.size, "steps": model.inst.steps, "seed": seed, "order": order, "variant": variant,
        "positioner_order": positioner_order(model, order), "states": None, "transitions": None, "marked": None,
        "ccc": c.forcible, "rank": c.rank, "witness_length": len(c.witness), "witness": c.witness,
        "seconds": round(time.perf_counter() - t0, 3), "build": st["build_seconds"], "supcon": None,
        "ccc_seconds": round(st["search_seconds"] + st["witness_seconds"], 3), "relations": st["relations"],
        "buckets": st["buckets"], "max_layer_nodes": st["max_layer_nodes"], "bdd_nodes": None,
        "blocked_group": st.get("blocked_group"), "upper_bound": st.get("upper_bound"),
        "greedy_expanded": st.get("greedy_expanded"), "cpu": round(time.process_time(), 2),
        "rank_bounds": None if st.get("rank_bounds") is None else [st["rank_bounds"].lower, st["rank_bounds"].upper],
        "peak_nodes": ctx.peak_nodes(), "rss_mb": _rss_mb()})


def _check(model, st: dict) -> dict:
    """The explicit twin and libFAUDES on the same instance: equal counts?"""
    sys.path.insert(0, os.path.join(HERE, "..", "tests"))
    from oracle import faudes_supcon  # the tests' libFAUDES bridge

    from supcoord.paper.coupled import coupled_models_explicit
    from supcoord.synthesis import supcon_naive

    t = time.perf_counter()
    Gx, Ex = coupled_models_explicit(model)
    V = supcon_naive(Gx, Ex)
    t_naive = time.perf_counter() - t
    t = time.perf_counter()
    F = faudes_supcon(Gx, Ex)
    t_faudes = time.perf_counter() - t
    counts = (st["states"], st["transitions"], st["marked"])
    return {"explicit_equal": (V.n_states, V.n_transitions, len(V.marked)) == counts,
            "faudes_equal": (F.n_states, sum(1 for _ in F.transitions()), len(F.marked)) == counts,
            "explicit_seconds": round(t_naive, 2), "faudes_seconds": round(t_faudes, 2)}


# -- driver -------------------------------------------------------------------------------


def _limiter(cpu: float | None):
    def limit() -> None:
        resource.setrlimit(resource.RLIMIT_AS, (MEMORY, MEMORY))
        if cpu is not None:
            resource.setrlimit(resource.RLIMIT_CPU, (int(cpu), int(cpu) + 5))
    return limit


def export_revision(rev: str, into: str) -> str:
    """``src`` and ``benchmarks`` of git revision ``rev`` under ``into``; returns the directory."""
    root = os.path.dirname(HERE)
    archive = os.path.join(into, f"{rev}.tar")
    subprocess.run(["git", "-C", root, "archive", "-o", archive, rev, "src", "benchmarks"], check=True)
    with tarfile.open(archive) as tar:
        tar.extractall(os.path.join(into, rev), filter="data")
    return os.path.join(into, rev)


def run_point(size: int, order: str, timeout: float, seed: int, check: bool, nodes: bool,
              variant: str = "new", source: tuple[str, str] | None = None, cpu: float | None = None,
              answer_cpu: float | None = None) -> dict:
    """One point in a fresh subprocess; ``source`` = ``(rev, dir)``: the worker of an older
    revision exported by :func:`export_revision` (its ``src`` first on ``sys.path``)."""
    script = os.path.abspath(__file__) if source is None else os.path.join(source[1], "benchmarks", "bench_coupled.py")
    env = None if source is None else dict(os.environ, PYTHONPATH=os.path.join(source[1], "src"))
    cmd = [sys.executable, script, "--worker", str(size), order, str(seed), variant]
    cmd += ["--check"] if check else []
    cmd += ["--nodes"] if nodes else []
    cmd += ["--answer-cpu", str(answer_cpu)] if answer_cpu is not None else []
    t = time.perf_counter()
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, preexec_fn=_limiter(cpu),
                           check=False, env=env)
        text, status = p.stdout, ("ok" if p.returncode == 0 else f"> {cpu:g} s CPU"
                                  if cpu is not None and p.returncode == -signal.SIGXCPU else f"exit {p.returncode}")
        err = p.stderr.strip().splitlines()[-1:] if p.returncode else []
    except subprocess.TimeoutExpired as exc:
        text = exc.stdout.decode() if isinstance(exc.stdout, bytes) else (exc.stdout or "")
        status, err = f"> {timeout:g} s", []
    wall = time.perf_counter() - t
    lines = [ln.split(" ", 1) for ln in text.splitlines() if ln[:2] in ("P ", "R ")]
    result = next((json.loads(j) for k, j in lines if k == "R"), None)
    progress = [json.loads(j) for k, j in lines if k == "P"]
    row = result or {"size": size, "seed": seed, "order": order, "variant": variant}
    row.update(status=status, wall=round(wall, 2))
    if source is not None:
        row["variant"] = f"{variant}@{source[0]}"
    if result is None:
        row["last_stage"] = progress[-1] if progress else None
        proved = [p["upper_bound"] for p in progress if "upper_bound" in p]  # the greedy string, before the A*
        if proved:
            row["last_stage"]["upper_bound"] = proved[0]
        row["error"] = err[0] if err else None
    return row


def _fmt(v) -> str:
    if v is None:
        return ""
    if isinstance(v, float):
        return f"{v:.2f}"
    if isinstance(v, int) and abs(v) >= 10000:
        return f"{v:,}"
    return str(v)


def table(rows: list[dict]) -> str:
    head = ["N", "seed", "order", "variant", "status", "CCC", "CPU s", "s (worker)", "build", "reach", "coreach", "supcon", "ccc", "count", "images",
            "image s", "max operand", "clusters", "reach nodes", "V nodes", "peak nodes", "RSS MB", "states",
            "transitions", "rank", "settled: buckets / max layer nodes", "equal to explicit / libFAUDES"]
    out = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in rows:
        prof = r.get("profile_supcon") or {}
        last = r.get("last_stage")
        status = r["status"] if "rank" in r else f"{r['status']} (in {last['stage']} at {last['at']} s, " \
            f"{_fmt(last.get('nodes'))} nodes)" if last else r["status"]
        eq = ""
        if "explicit_equal" in r:
            eq = f"{'yes' if r['explicit_equal'] else 'NO'} ({r['explicit_seconds']} s) / " \
                 f"{'yes' if r['faudes_equal'] else 'NO'} ({r['faudes_seconds']} s)"
        verdict = None if "rank" not in r else "yes" if r["ccc"] else "no"
        if verdict is None and last and last.get("upper_bound"):
            verdict = f"yes (checked witness of {last['upper_bound']} events; rank not proved)"
        elif r.get("rank_bounds"):
            verdict += f" (checked witness of {r['witness_length']} events; rank bounded)"
        elif r.get("upper_bound"):
            verdict += f" (greedy witness: {r['upper_bound']} events)"
        if r.get("blocked_group"):
            verdict += " (blocked: " + ", ".join(f"P{i}" for i in r["blocked_group"]) + ")"
        cpu = r.get("cpu", last.get("cpu") if last else None)
        cells = [r["size"], r.get("seed"), r["order"], r.get("variant", "new"), status, verdict, cpu, r.get("seconds"), r.get("build"), r.get("reach"), r.get("coreach"),
                 r.get("supcon"), r.get("ccc_seconds"), r.get("count"), prof.get("images"), prof.get("image_seconds"),
                 prof.get("max_operand_nodes"), len(r["clusters"]) if "clusters" in r else None,
                 r.get("reach_nodes"), r.get("bdd_nodes"), r.get("peak_nodes"), r.get("rss_mb"), r.get("states"),
                 r.get("transitions"),
                 f"[{r['rank_bounds'][0]}, {r['rank_bounds'][1]}]" if r.get("rank_bounds") else r.get("rank"),
                 f"{r['buckets']} / {_fmt(r['max_layer_nodes'])}" if "buckets" in r else None, eq]
        out.append("| " + " | ".join(_fmt(c) for c in cells) + " |")
    return "\n".join(out)


def _machine() -> dict:
    try:
        version = subprocess.run(["git", "describe", "--always", "--dirty"], capture_output=True, text=True,
                                 cwd=HERE, check=False).stdout.strip()
    except OSError:
        version = "?"
    return {"date": datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC"),
            "uname": " ".join(platform.uname()[:3] + (platform.uname()[4],)), "cpus": os.cpu_count(),
            "python": platform.python_version(), "version": version}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=SIZES)
    ap.add_argument("--orders", nargs="+", default=ORDERS, choices=["layout", "auto", "bandwidth"])
    ap.add_argument("--variants", nargs="+", default=VARIANTS, choices=VARIANTS,
                    help="variants to compare (old: plain event steps; new: local closures; whole: supervisor "
                         "without Reach, as supcoord paper runs)")
    ap.add_argument("--timeout", type=float, default=120.0, help="seconds per point (default 120)")
    ap.add_argument("--cpu", type=float, default=None, help="CPU seconds per point (default: no limit)")
    ap.add_argument("--answer-cpu", type=float, default=None,
                    help="CPU seconds after which a point's budget ends at its next progress report: a settled "
                         "point that proved 'forcible' then answers with its string and the rank's bounds")
    ap.add_argument("--jobs", type=int, default=1, help="points run at once (more than 1: every size runs)")
    ap.add_argument("--seeds", "--seed", dest="seeds", type=int, nargs="+", default=[0],
                    help="seeds of the random instances, each size run on each (default 0)")
    ap.add_argument("--check", action="store_true", help="compare with the explicit twin and libFAUDES (N <= 4)")
    ap.add_argument("--nodes", action="store_true", help="measure every image's operand (slower)")
    ap.add_argument("--all", action="store_true", help="run every size even after one ran out of time")
    ap.add_argument("--quick", action="store_true", help="N = 3, 4, 30 s, print only")
    ap.add_argument("--out", default=os.path.join(HERE, "results", "coupled.md"))
    ap.add_argument("--rev", action="append", default=[],
                    help="also run every variant at this older git revision, side by side (repeatable)")
    ap.add_argument("--worker", nargs=4, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.worker:
        size, order, seed, variant = args.worker
        worker(int(size), STEPS, int(seed), order, args.check, args.nodes, variant, args.answer_cpu)
        return 0
    if args.quick:
        args.sizes, args.timeout = [3, 4], 30.0
    command = "python benchmarks/bench_coupled.py " + " ".join(argv if argv is not None else sys.argv[1:])
    machine = _machine()
    load_before = os.getloadavg()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        sources = [None] + [(rev, export_revision(rev, tmp)) for rev in args.rev]
        if args.jobs > 1:
            points = [(size, order, seed, variant, source) for order in args.orders for size in sorted(args.sizes)
                      for seed in args.seeds for variant in args.variants for source in sources]
            with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
                futures = [pool.submit(run_point, size, order, args.timeout, seed, args.check, args.nodes, variant,
                                       source, args.cpu, args.answer_cpu) for size, order, seed, variant, source in points]
                for future in futures:
                    rows.append(future.result())
                    print(table(rows[-1:]).splitlines()[-1], file=sys.stderr, flush=True)
        for order in args.orders if args.jobs == 1 else ():
            for size in sorted(args.sizes):
                stop = True
                for seed in args.seeds:
                    for variant in args.variants:  # side by side: same size, same load
                        for source in sources:
                            row = run_point(size, order, args.timeout, seed, args.check, args.nodes, variant,
                                            source, args.cpu, args.answer_cpu)
                            rows.append(row)
                            print(table([row]).splitlines()[-1], file=sys.stderr, flush=True)
                            stop &= "rank" not in row
                if stop and not args.all:
                    break  # larger N would not finish either
    load_after = os.getloadavg()
    text = table(rows)
    print(text)
    agree = _agreement(rows)
    print(agree)
    if args.quick:
        return 0
    with open(args.out, "w") as f:
        f.write("# The coupled paper model: where the time goes\n\n")
        f.write(f"Command: `{command.strip()}`  \n")
        f.write(f"Date: {machine['date']}; machine: {machine['uname']}, {machine['cpus']} CPUs, Python "
                f"{machine['python']}; code: `{machine['version']}`  \n")
        f.write(f"Load (1/5/15 min) before: {', '.join(f'{x:.2f}' for x in load_before)}; after: "
                f"{', '.join(f'{x:.2f}' for x in load_after)} — the machine is shared, read ratios within a run.  \n")
        cpu = "" if args.cpu is None else f", {args.cpu:g} s of CPU"
        cpu += "" if args.answer_cpu is None else f" (the budget ended after {args.answer_cpu:g} s of CPU)"
        f.write(f"Each point: a fresh subprocess, {args.timeout:g} s{cpu} and 6 GiB at most; n = {STEPS} steps, "
                f"seeds {', '.join(map(str, args.seeds))}.\n\n")
        f.write(text + "\n\n" + agree + "\n\n")
        f.write("Columns: `variant` = `old` (saturation over the plain event steps, the code before the local "
                "closures), `new` (write groups fired by their local transitive closure, closures computed "
                "inside `reach`) or `whole` (`new`, with the supervisor computed on the whole state space "
                "without `Reach` and CCC on it: `supcoord paper --model coupled --route monolithic`) or `settled` "
                "(CCC on the settled states without `V`, `supcoord.paper.settled`: what `supcoord paper --model "
                "coupled` runs; `ccc` = its A* and witness, `build` its relations; last column: the A*'s "
                "buckets and largest distance layer); `CCC` = the verdict, with the group of positioners whose relaxation cannot reach its targets where that answered it before any search (`blocked`); seconds are inside "
                "the worker (imports excluded): `build` = instance, geometry "
                "tables and relations; `reach` = `Reach(G × E)`; `coreach` = the nonblocking and controllability "
                "fixpoints; `supcon` = all of supcon including exact counts; `ccc` = forcibility layers up to "
                "`q0` and the witness; `count` (`whole` only) = the trim supervisor and its exact sizes, computed "
                "after CCC up to 6 positioners.  `images`, `image s`, `max operand` profile the images of supcon's "
                "fixpoints (`ImageProfile`; `max operand` only with `--nodes`).  `clusters` = saturation's "
                "event clusters of the plain steps (1 = saturation degenerates into chaining).  `reach nodes` = BDD of the "
                "reachable set; `V nodes` = supervisor (relations included); `peak nodes` = CUDD's peak of "
                "live nodes.\n\nRaw rows (JSON):\n\n```\n")
        for r in rows:
            f.write(json.dumps(r) + "\n")
        f.write("```\n")
    print(f"written {args.out}", file=sys.stderr)
    return 0


def _agreement(rows: list[dict]) -> str:
    """Where several orders or variants finish, every result must be equal."""
    keys = ("states", "transitions", "marked", "ccc", "rank", "witness")
    by = {}
    for r in rows:
        if "rank" in r:
            by.setdefault((r["size"], r.get("seed")), []).append(r)
    lines = []
    for (size, seed), rs in sorted(by.items()):
        if len(rs) > 1:  # (a supervisor left uncounted has sizes None: compared where both counted)
            same = all(all(r[k] == rs[0][k] for k in keys if r[k] is not None and rs[0][k] is not None)
                       for r in rs[1:])
            counted = all(r["states"] is not None for r in rs)
            what = "states, transitions, marked, CCC, rank and witness" if counted else \
                "CCC, rank and witness (sizes where counted)"
            lines.append(f"N = {size}, seed {seed}: {' and '.join(r['order'] + '/' + r.get('variant', 'new') for r in rs)} give "
                         f"{'the same' if same else 'DIFFERENT'} {what}")
    return "\n".join(lines) or "no size finished under two orders"


if __name__ == "__main__":
    sys.exit(main())
