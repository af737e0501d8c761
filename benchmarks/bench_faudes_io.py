#!/usr/bin/env python
"""libFAUDES files and large supervisors: supcoord against libFAUDES where libFAUDES is
at home (flat explicit generators) and on the export of large supervisors.

Every measurement runs in a fresh subprocess with a timeout (seconds exclude the
interpreter start and the imports, for both tools):

- **flat**: a plant of ``10^k`` states (the product of ``k`` ten-state machines, built
  and *written by libFAUDES* as one flat ``System`` file) and a two-state buffer
  specification written by libFAUDES as a plain ``Generator`` (no controllability
  flags: the plant's are used).  supcoord = ``supcoord supcon --plant P.gen --spec
  B.gen`` run in-process (``main([...])``: reading, the explicit route, and with
  ``--export`` writing the supervisor); libFAUDES = ``System(P.gen)``,
  ``Generator(B.gen)``, ``InvProject``, ``SupCon`` and ``Write`` of the supervisor.
- **export**: symbolic supervisors of the scalable families (up to 1.6 million
  states): supcoord = synthesis (symbolic), enumeration (``to_flat``) and writing
  (``write_gen_flat``), timed apart; libFAUDES = ``Parallel`` of the components,
  ``InvProject``, ``SupCon`` and ``Write`` (not run on larger sizes of a family after a
  timeout).

The ratio column is supcoord seconds / libFAUDES seconds (below 1: supcoord is faster).

Usage::

    python benchmarks/bench_faudes_io.py              # writes benchmarks/results/faudes_io.md
    python benchmarks/bench_faudes_io.py --quick      # small sizes, no file written
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import os
import platform
import resource
import subprocess
import sys
import tempfile
import time
from datetime import datetime, timezone

FLAT_SIZES = [3, 4, 5, 6]  # 10^k plant states
EXPORT_CASES = [("dining_philosophers", 10), ("transfer_line_chain", 3), ("coupled_factories", 4),
                ("dining_philosophers", 12), ("dining_philosophers", 13)]
QUICK_FLAT, QUICK_EXPORT = [3, 4], [("dining_philosophers", 8), ("transfer_line_chain", 2)]
MEMORY_LIMIT = 12 * 2**30
REPEAT = 3  # runs of the small flat cases, the best one counts (for both tools)


def _peak_rss_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


# -- workers (each in a fresh subprocess) ----------------------------------------------------


def prepare(k: int, directory: str) -> dict:
    """The flat plant (``k`` ten-state machines, composed and written by libFAUDES) and the buffer."""
    import faudes

    def machine(i: int):
        s = faudes.System()
        s.Name(f"M{i}")
        x = [s.InsState() for _ in range(10)]
        s.SetInitState(x[0])
        s.SetMarkedState(x[0])
        for j in range(10):
            ev = f"m{i}_{j}"
            e = s.InsControllableEvent(ev) if j % 2 == 0 else s.InsUncontrollableEvent(ev)
            s.SetTransition(x[j], e, x[(j + 1) % 10])
        return s

    plant = machine(0)
    for i in range(1, k):
        out = faudes.System()
        faudes.Parallel(plant, machine(i), out)
        plant = out
    plant.Name(f"plant{k}")
    plant.Write(os.path.join(directory, f"P{k}.gen"))
    buf = faudes.Generator()  # a plain generator: no controllability flags
    buf.Name("BUF")
    a, b = buf.InsEvent("m0_9"), buf.InsEvent("m1_0")
    x, y = buf.InsState(), buf.InsState()
    buf.SetInitState(x)
    buf.SetMarkedState(x)
    buf.SetTransition(x, a, y)
    buf.SetTransition(y, b, x)
    buf.Write(os.path.join(directory, "BUF.gen"))
    return {"plant_states": plant.Size(), "plant_transitions": plant.TransRelSize()}


def flat_supcoord(k: int, directory: str, export: bool) -> dict:
    from supcoord.cli.main import main

    buf = os.path.join(directory, "BUF.gen")
    argv = ["supcon", "--plant", os.path.join(directory, f"P{k}.gen"), "--spec", buf, "--json", "--quiet"]
    if export:
        argv += ["--export", os.path.join(directory, f"V{k}_supcoord.gen"), "--export-limit", "10000000"]
    out = io.StringIO()
    with contextlib.redirect_stdout(out):  # imports are not timed: a first run on the two-state buffer
        main(["supcon", "--plant", buf, "--spec", buf, "--route", "explicit", "--quiet", "--export",
              os.path.join(directory, "warm-up.gen")])
    best = float("inf")
    for _ in range(REPEAT if k <= 4 else 1):  # small runs: the best of a few (a shared machine)
        out = io.StringIO()
        t0 = time.perf_counter()
        with contextlib.redirect_stdout(out):
            code = main(argv)
        best = min(best, time.perf_counter() - t0)
        if code != 0:
            raise RuntimeError(f"supcoord supcon exited {code}")
    payload = json.loads(out.getvalue())
    return {"states": payload["states"], "transitions": payload["transitions"], "seconds": best,
            "peak_rss_mb": _peak_rss_mb()}


def flat_faudes(k: int, directory: str) -> dict:
    import faudes

    times = []
    for _ in range(REPEAT if k <= 4 else 1):  # small runs: the best of a few (a shared machine)
        t0 = time.perf_counter()
        P = faudes.System(os.path.join(directory, f"P{k}.gen"))
        S = faudes.Generator(os.path.join(directory, "BUF.gen"))
        t1 = time.perf_counter()
        faudes.InvProject(S, P.Alphabet())
        R = faudes.System()
        faudes.SupCon(P, S, R)
        t2 = time.perf_counter()
        R.Write(os.path.join(directory, f"V{k}_faudes.gen"))
        t3 = time.perf_counter()
        times.append((t2 - t0, t1 - t0, t3 - t2))
    seconds, read, write = min(times)
    return {"states": R.Size(), "transitions": R.TransRelSize(), "read_seconds": read,
            "seconds": seconds, "write_seconds": write, "peak_rss_mb": _peak_rss_mb()}


def _components(family: str, size: int):
    from supcoord.des import families

    return families.FAMILIES[family](size)


def export_supcoord(family: str, size: int, directory: str) -> dict:
    from supcoord.bdd import Context
    from supcoord.bdd.context import load_backend
    from supcoord.des import families
    from supcoord.des import symbolic_ops as S
    from supcoord.des.io.gen_write import write_gen_flat
    from supcoord.des.symbolic_export import to_flat
    from supcoord.synthesis import lift_spec, supcon

    plants, specs = _components(family, size)
    load_backend()
    import supcoord.bdd.cudd_count  # noqa: F401
    t0 = time.perf_counter()
    ctx = Context()
    G, E = families.to_symbolic(ctx, plants, specs)
    E = lift_spec(G, E) if E is not None else S.allevents(ctx, G)
    result = supcon(G, E)
    t1 = time.perf_counter()
    V = result.supervisor
    flat = to_flat(V, V.invariant, max_states=10**7, name="V")
    t2 = time.perf_counter()
    write_gen_flat(flat, os.path.join(directory, f"{family}{size}.gen"))
    t3 = time.perf_counter()
    return {"states": result.stats["states"], "transitions": result.stats["transitions"],
            "bits": len(ctx.bits(V.variables)), "synthesis_seconds": t1 - t0, "enumerate_seconds": t2 - t1,
            "write_seconds": t3 - t2, "seconds": t3 - t0, "peak_rss_mb": _peak_rss_mb()}


def export_faudes(family: str, size: int, directory: str) -> dict:
    import faudes

    from supcoord.des.io.gen_file import write_gen

    plants, specs = _components(family, size)

    def load(g, tag):
        path = os.path.join(directory, f"{tag}.gen")
        write_gen(g, path)
        return faudes.System(path)

    P_parts = [load(g, f"p{i}") for i, g in enumerate(plants)]
    S_parts = [load(g, f"s{i}") for i, g in enumerate(specs)]
    t0 = time.perf_counter()
    P = P_parts[0]
    for g in P_parts[1:]:
        out = faudes.System()
        faudes.Parallel(P, g, out)
        P = out
    if S_parts:
        S = S_parts[0]
        for g in S_parts[1:]:
            out = faudes.System()
            faudes.Parallel(S, g, out)
            S = out
        faudes.InvProject(S, P.Alphabet())
    else:
        S = faudes.System()  # allevents: the supremal nonblocking supervisor
        S.InsEvents(P.Alphabet())
        q = S.InsState()
        S.SetInitState(q)
        S.SetMarkedState(q)
        for e in P.Alphabet():
            S.SetTransition(q, e, q)
    R = faudes.System()
    faudes.SupCon(P, S, R)
    t1 = time.perf_counter()
    R.Write(os.path.join(directory, f"{family}{size}_faudes.gen"))
    t2 = time.perf_counter()
    return {"states": R.Size(), "transitions": R.TransRelSize(), "synthesis_seconds": t1 - t0,
            "write_seconds": t2 - t1, "seconds": t2 - t0, "peak_rss_mb": _peak_rss_mb()}


WORKERS = {"prepare": prepare, "flat_supcoord": flat_supcoord, "flat_faudes": flat_faudes,
           "export_supcoord": export_supcoord, "export_faudes": export_faudes}


def run_worker(name: str, args: list, timeout: float) -> dict:
    """One measurement in a fresh interpreter: ``{"status": "ok"|"timeout"|"error", ...}``."""
    cmd = [sys.executable, os.path.abspath(__file__), "--worker", name, json.dumps(args)]
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, check=False)
    except subprocess.TimeoutExpired:
        return {"status": "timeout", "limit": timeout}
    if proc.returncode != 0:
        tail = (proc.stderr.strip().splitlines() or ["?"])[-1]
        return {"status": "error", "error": tail[:200]}
    return {"status": "ok", **json.loads(proc.stdout.strip().splitlines()[-1])}


# -- driver --------------------------------------------------------------------------------------


def machine() -> dict:
    import faudes

    cpu = "?"
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next(line.split(":", 1)[1].strip() for line in f if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    return {"uname": " ".join(platform.uname()), "nproc": os.cpu_count(), "cpu": cpu,
            "python": platform.python_version(), "faudes": faudes.Version()}


def fmt(x, digits: int = 2) -> str:
    if x is None:
        return "–"
    if isinstance(x, float):
        return f"{x:.{digits}f}" if x < 100 else f"{x:.0f}"
    return f"{x:,}" if isinstance(x, int) else str(x)


def status(r: dict) -> str:
    return r["status"] + (f" (>{r['limit']:.0f} s)" if r["status"] == "timeout" else "") + \
        (f": {r['error']}" if r["status"] == "error" else "")


def ratio(a: dict, b: dict, key: str = "seconds") -> str:
    if a.get("status") == "ok" and b.get("status") == "ok" and b[key] > 0:
        return f"{a[key] / b[key]:.3g}"
    if a.get("status") == "ok" and b.get("status") == "timeout":
        return f"< {a[key] / b['limit']:.3g}"
    return "–"


def flat_table(sizes: list[int], directory: str, timeout: float) -> tuple[list[str], list[str]]:
    lines = ["| plant states | plant transitions | supervisor states | supcoord s (read + synthesis) "
             "| libFAUDES s (read + SupCon) | ratio | supcoord s (+ export) | libFAUDES s (+ Write) | ratio "
             "| supcoord / libFAUDES peak RSS MB |",
             "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    notes = []
    for k in sizes:
        made = run_worker("prepare", [k, directory], timeout)
        if made["status"] != "ok":
            notes.append(f"- 10^{k}: the plant could not be made: {status(made)}")
            break
        ours = run_worker("flat_supcoord", [k, directory, False], timeout)
        ours_x = run_worker("flat_supcoord", [k, directory, True], timeout)
        theirs = run_worker("flat_faudes", [k, directory], timeout)
        if ours["status"] == theirs["status"] == "ok" and \
                (ours["states"], ours["transitions"]) != (theirs["states"], theirs["transitions"]):
            theirs = {"status": f"MISMATCH {theirs['states']}/{theirs['transitions']}"}
        total = dict(theirs, seconds=theirs["seconds"] + theirs["write_seconds"]) if theirs["status"] == "ok" else theirs
        line = "| " + " | ".join([
            fmt(made["plant_states"]), fmt(made["plant_transitions"]),
            fmt(ours.get("states")) if ours["status"] == "ok" else status(ours),
            fmt(ours.get("seconds"), 3) if ours["status"] == "ok" else "–",
            fmt(theirs.get("seconds"), 3) if theirs["status"] == "ok" else status(theirs), ratio(ours, theirs),
            fmt(ours_x.get("seconds"), 3) if ours_x["status"] == "ok" else status(ours_x),
            fmt(total.get("seconds"), 3) if theirs["status"] == "ok" else "–", ratio(ours_x, total),
            f"{fmt(ours_x.get('peak_rss_mb'), 0)} / {fmt(theirs.get('peak_rss_mb'), 0)}",
        ]) + " |"
        print(line, flush=True)
        lines.append(line)
        if theirs["status"] == "ok":
            notes.append(f"- 10^{k} plant states: libFAUDES reads the two files in {theirs['read_seconds']:.2f} s "
                         f"and writes the supervisor in {theirs['write_seconds']:.2f} s.")
    return lines, notes


def export_table(cases: list[tuple[str, int]], directory: str, timeout: float,
                 faudes_timeout: float) -> tuple[list[str], list[str]]:
    lines = ["| family | size | supervisor states | transitions | state bits | supcoord synthesis s "
             "| enumeration s | writing s | export / synthesis | supcoord total s | libFAUDES s (SupCon + Write) "
             "| ratio | supcoord peak RSS MB |",
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    notes, dead = [], set()
    for family, size in cases:
        ours = run_worker("export_supcoord", [family, size, directory], timeout)
        theirs = {"status": "not run"} if family in dead else run_worker("export_faudes", [family, size, directory],
                                                                           faudes_timeout)
        if theirs["status"] == "timeout":
            dead.add(family)
        if ours["status"] != "ok":
            lines.append(f"| {family} | {size} | {status(ours)} |" + " |" * 10)
            print(lines[-1], flush=True)
            continue
        if theirs["status"] == "ok" and (ours["states"], ours["transitions"]) != (theirs["states"], theirs["transitions"]):
            theirs = {"status": f"MISMATCH {theirs['states']}/{theirs['transitions']}"}
        export = ours["enumerate_seconds"] + ours["write_seconds"]
        line = "| " + " | ".join([
            family, str(size), fmt(ours["states"]), fmt(ours["transitions"]), str(ours["bits"]),
            fmt(ours["synthesis_seconds"], 3), fmt(ours["enumerate_seconds"], 3), fmt(ours["write_seconds"], 3),
            f"{export / max(ours['synthesis_seconds'], 1e-9):.3g}", fmt(ours["seconds"], 3),
            fmt(theirs["seconds"], 3) if theirs["status"] == "ok" else status(theirs), ratio(ours, theirs),
            fmt(ours["peak_rss_mb"], 0),
        ]) + " |"
        print(line, flush=True)
        lines.append(line)
        if ours["states"] >= 10**6:
            notes.append(f"- {family} {size}: a supervisor of {ours['states']:,} states and {ours['transitions']:,} "
                         f"transitions enumerated and written in {export:.1f} s.")
    return lines, notes


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="small sizes; writes no results file")
    ap.add_argument("--timeout", type=float, default=900.0, help="seconds per run (default 900)")
    ap.add_argument("--faudes-export-timeout", type=float, default=300.0,
                    help="seconds per libFAUDES run of the export part (default 300; larger sizes of a family "
                         "are not run after a timeout)")
    ap.add_argument("--out", default=None, help="results file (default benchmarks/results/faudes_io.md)")
    ap.add_argument("--worker", nargs=2, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.worker:
        resource.setrlimit(resource.RLIMIT_AS, (MEMORY_LIMIT, MEMORY_LIMIT))
        print(json.dumps(WORKERS[args.worker[0]](*json.loads(args.worker[1]))))
        return 0
    command = "python benchmarks/bench_faudes_io.py " + " ".join(argv if argv is not None else sys.argv[1:])
    started = datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    load_start = os.getloadavg()
    info = machine()
    with tempfile.TemporaryDirectory() as directory:
        flat, flat_notes = flat_table(QUICK_FLAT if args.quick else FLAT_SIZES, directory, args.timeout)
        exported, export_notes = export_table(QUICK_EXPORT if args.quick else EXPORT_CASES, directory, args.timeout,
                                              args.faudes_export_timeout)
    load_end = os.getloadavg()
    if args.quick and not args.out:
        return 0
    out = args.out or os.path.join(os.path.dirname(os.path.abspath(__file__)), "results", "faudes_io.md")
    text = [
        "# libFAUDES files and large supervisors: supcoord vs libFAUDES", "",
        f"- command: `{command.strip()}`", f"- date: {started}",
        f"- machine: `{info['uname']}`; {info['nproc']} CPUs ({info['cpu']})",
        f"- load (`os.getloadavg()`, 1/5/15 minutes): {' / '.join(f'{x:.2f}' for x in load_start)} at the start, "
        f"{' / '.join(f'{x:.2f}' for x in load_end)} at the end (a shared machine: wall-clock seconds are noisy, "
        "both tools ran minutes apart under the same load)",
        f"- versions: Python {info['python']}, {info['faudes']}",
        f"- every run in a fresh subprocess, {args.timeout:.0f} s timeout ({args.faudes_export_timeout:.0f} s for "
        f"libFAUDES in the export part), address space {MEMORY_LIMIT // 2**30} GiB; the flat cases up to 10^4 "
        f"states: the best of {REPEAT} runs for both tools; "
        "seconds exclude the interpreter start and imports; ratio = supcoord seconds / libFAUDES seconds; "
        "the supervisor sizes of both tools are checked equal wherever both finish", "",
        "## Flat generators written by libFAUDES", "",
        "The plant is one flat `System` file of 10^k states written by libFAUDES (the product of k "
        "ten-state machines); the specification a two-state buffer written as a plain `Generator` "
        "(controllability from the plant). supcoord: `supcoord supcon --plant P.gen --spec BUF.gen "
        "[--export V.gen]` in-process (the explicit route, chosen automatically).", "",
        *flat, "", *flat_notes, "",
        "## Export of large supervisors", "",
        "Symbolic supervisors of the scalable families; supcoord's seconds split into synthesis, "
        "enumeration (`to_flat`: the state set, one relation per event, numbering) and writing the `.gen` "
        "file; libFAUDES: Parallel + InvProject + SupCon + Write.", "",
        *exported, "", *export_notes, "",
    ]
    os.makedirs(os.path.dirname(out), exist_ok=True)
    with open(out, "w", encoding="utf-8") as f:
        f.write("\n".join(text))
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
