"""Benchmark: exactness — the independent oracle against ``solve`` on random tight problems.

Every problem is drawn by :func:`supcoord.testing.oracle.tight_problems.tight_problem` from its
seed alone (rotary or alpha-beta, 2–6 positioners, at most ``--max-product``
configurations, bases 0.45–1.2 reaches apart: about 40 % have no plan; a seed ending in 7
uses round numbers, arms touching at exactly the buffer sum).  It is solved by
:func:`supcoord.planning.solve` — half on the default route, half with the window route
**forced** (no small component solved whole, tiny window caps, with and without the
greedy descent) — and answered by :mod:`supcoord.testing.oracle` (its own geometry,
certified swept checks and breadth-first search, none of the planner's code):

- **verdict**: plan iff the oracle finds one (for a tie, the oracle's bounds: a plan if
  one exists even with the ties blocked, none if none exists even with them free);
- **plans**: every plan passes :func:`supcoord.problems.validate_plan` and has at least
  the oracle's number of single moves;
- **certificates**: the certified positioners, every other one removed, have no plan
  according to the oracle.

Writes ``results/exactness.md`` (the table by kinematics, size and route, the kinds of
route and certificate reached, every disagreement with its seed) and
``results/exactness.json`` (every case), both atomically.

    python benchmarks/exactness.py                 # 1,200 problems, 2 processes (≈ 10 min)
    python benchmarks/exactness.py --quick         # 60 problems, written to /tmp
    python benchmarks/exactness.py --seeds 209 27  # chosen seeds, printed
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import signal
import subprocess
import sys
import tempfile
import time
from collections import Counter, defaultdict
from multiprocessing import Pool

HERE = os.path.dirname(os.path.abspath(__file__))
#: the window route forced on half of the seeds: (levels, descent), every conflict component left to the windows
FORCED = {"windows A": ((18, 60, 200, None), "greedy"), "windows B": ((12, 40, 135, None), "none"),
          "windows C": ((30, 300, None), "greedy"), "windows D": ((30, 300, None), "none")}
SETTINGS = ["default", "windows A", "default", "windows B", "default", "windows C", "default", "windows D"]
CERTIFICATES = {"their conflict component": "conflict component", "this relaxed subproblem": "relaxed subproblem",
                "no other positioner restricts them": "no blocker"}
#: seconds a case may take before it is recorded as timed out
CASE_SECONDS = 300


def _observer(run: set):
    """A watcher of the window route (its public observer) that collects in ``run`` what a
    solve went through."""
    from supcoord.planning.windows import WindowObserver

    class Watch(WindowObserver):
        def descended(self, steps):
            if steps:
                run.add("descent moved")

        def window(self, out):
            run.add("window")
            if out.kind == "solved" and len(out.members) > 1:
                run.add("grown window solved")
            if out.kind == "gave_up":
                run.add("window cap hit")
            if "descent moved" in run:
                run.add("descent then windows")

        def whole_component(self, out):
            run.add(f"whole component {out.kind}")

    return Watch()


_RUN: set = set()
#: the workers' tight_problem(max_product=...), set by _init_worker
_MAX_PRODUCT = [200_000]


def _init_worker(memory_gib: float, max_product: int) -> None:
    _MAX_PRODUCT[0] = max_product
    limit = int(memory_gib * 2**30)
    resource.setrlimit(resource.RLIMIT_AS, (limit, limit))


def _alarm(signum, frame):
    raise TimeoutError(f"case over {CASE_SECONDS} s")


def run_case(seed: int) -> dict:
    """One seed: draw, solve, answer with the oracle, compare (module docstring)."""
    from supcoord.planning import Local, solve
    from supcoord.problems import parse_problem, validate_plan
    from supcoord.testing.oracle import oracle_bounds
    from supcoord.testing.oracle.bfs import Space
    from supcoord.testing.oracle.tight_problems import tight_problem
    from supcoord.testing.oracle.oracle_model import OracleProblem

    data = tight_problem(seed, max_product=_MAX_PRODUCT[0])
    kin = data["kinematics"]
    n = len(data["start"])
    positions = kin["steps"] if kin["kind"] == "rotary" else kin["alpha_steps"] * kin["beta_steps"]
    setting = SETTINGS[seed % len(SETTINGS)]
    shape = f"{kin['steps']} steps" if kin["kind"] == "rotary" else f"{kin['alpha_steps']}×{kin['beta_steps']}"
    row = {"seed": seed, "kind": kin["kind"], "positioners": n, "configurations": positions ** n,
           "discretisation": shape, "layout": data["name"].split()[-1], "route": setting, "ties": seed % 10 == 7}
    signal.signal(signal.SIGALRM, _alarm)
    signal.alarm(CASE_SECONDS)
    try:
        t0 = time.perf_counter()
        space = Space(OracleProblem.from_json(data))
        loose, strict = space.single_bounds()
        row["oracle_seconds"] = time.perf_counter() - t0
        row.update(oracle_lo=loose.distance, oracle_hi=strict.distance, undecided_read=strict.undecided,
                   undecided_entries=sum(t.counts["undecided"] for _, _, t in space.pairs),
                   critical_time_entries=sum(t.counts["critical_times"] for _, _, t in space.pairs))
        exact = loose.distance == strict.distance
        row["oracle"] = strict.distance if exact else "tie"
        p = parse_problem(data)
        _RUN.clear()
        t0 = time.perf_counter()
        if setting == "default":
            plan = solve(p, Local(observer=_observer(_RUN)))
        else:
            levels, descent = FORCED[setting]
            plan = solve(p, Local(levels=levels, descent=descent, small_component=0, observer=_observer(_RUN)))
        row["solve_seconds"] = time.perf_counter() - t0
        row["status"] = plan.status
        row["routes"] = sorted(_RUN)
        t0 = time.perf_counter()
        problems = []
        if plan.status == "complete":
            row["single_moves"] = plan.stats["single_moves"]
            row["makespan"] = plan.makespan
            result = validate_plan(p, plan)
            row["valid"] = bool(result.valid)
            if not result.valid:
                problems.append(f"invalid plan: {result.problems[:2]}")
            if loose.distance is None:
                problems.append("a plan, but the oracle has none")
                row["verdict_disagrees"] = True
            elif plan.stats["single_moves"] < loose.distance:
                problems.append(f"{plan.stats['single_moves']} single moves < the oracle's shortest {loose.distance}")
            if strict.distance is None and not exact:
                row["tie_verdict"] = "plan through ties"
        elif plan.status == "infeasible":
            cert = plan.stats["certificate"]
            how = next((k for h, k in CERTIFICATES.items() if h in plan.reason), "exhaustive")
            row.update(certificate=cert, certificate_kind=how)
            if strict.distance is not None:
                problems.append(f"certificate {cert}, but the oracle has a plan of {strict.distance} moves")
                row["verdict_disagrees"] = True
            sub = oracle_bounds(data, members=cert)
            row["certificate_confirmed"] = sub[1] is None
            row["certificate_exact"] = sub[0] is None
            if sub[1] is not None:
                problems.append(f"certificate {cert}: the oracle solves it alone in {sub[1]} moves")
        else:
            problems.append(f"status {plan.status}: {plan.reason}")
        row["check_seconds"] = time.perf_counter() - t0
        row["disagreement"] = "; ".join(problems)
    except Exception as exc:  # noqa: BLE001 -- recorded as a disagreement, never hidden
        row["error"] = f"{type(exc).__name__}: {exc}"[:400]
        row["status"] = row.get("status", "error")
        row["disagreement"] = row.get("disagreement", "") or f"error: {row['error']}"
    finally:
        signal.alarm(0)
    return row


def machine() -> str:
    cpu = "unknown CPU"
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next(line.split(":", 1)[1].strip() for line in f if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    return f"`{' '.join(platform.uname())}`; {cpu}; {os.cpu_count()} CPUs; Python {platform.python_version()}"


def version() -> str:
    try:
        return subprocess.run(["git", "describe", "--always", "--dirty"], cwd=HERE, capture_output=True, text=True,
                              check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def _write_atomically(path: str, text: str) -> None:
    with tempfile.NamedTemporaryFile("w", dir=os.path.dirname(os.path.abspath(path)), suffix=".tmp",
                                     delete=False) as tmp:
        tmp.write(text)
    os.chmod(tmp.name, 0o644)
    os.replace(tmp.name, path)  # an interrupted run leaves the old file


def table(rows: list[dict]) -> list[str]:
    """Per kinematics, size and route: the oracle's verdicts (plans counted with ties free),
    ``solve``'s answers, and what went wrong."""
    groups: dict[tuple, list[dict]] = defaultdict(list)
    for r in rows:
        groups[(r["kind"], r["positioners"], "default" if r["route"] == "default" else "windows forced")].append(r)
    out = [("| kinematics | positioners | route | problems | oracle: plan / none / tie | solve: plan / certificate "
            "/ error | verdict disagreements | invalid plans | certificates confirmed | undecided oracle entries "
            "(read) | seconds: solve / oracle |"),
           "|---|---|---|---|---|---|---|---|---|---|---|"]
    for key in sorted(groups):
        rs = groups[key]
        infeas = [r for r in rs if r.get("status") == "infeasible"]
        oracle = (sum(r.get("oracle") not in (None, "tie") for r in rs), sum(r.get("oracle_lo", 0) is None for r in rs),
                  sum(r.get("oracle") == "tie" for r in rs))
        out.append(
            f"| {key[0]} | {key[1]} | {key[2]} | {len(rs)} | {' / '.join(map(str, oracle))} | "
            f"{sum(r.get('status') == 'complete' for r in rs)} / {len(infeas)} / {sum('error' in r for r in rs)} | "
            f"{sum(bool(r.get('verdict_disagrees')) for r in rs)} | {sum(r.get('valid') is False for r in rs)} | "
            f"{sum(bool(r.get('certificate_confirmed')) for r in infeas)}/{len(infeas)} | "
            f"{sum(r.get('undecided_entries', 0) for r in rs)} ({sum(r.get('undecided_read', 0) for r in rs)}) | "
            f"{sum(r.get('solve_seconds', 0) for r in rs):.1f} / {sum(r.get('oracle_seconds', 0) for r in rs):.1f} |")
    return out


def report(rows: list[dict], command: str, started: str, load0, load1, wall: float, processes: int) -> str:
    bad = [r for r in rows if r.get("disagreement")]
    kinds = Counter(k for r in rows for k in r.get("routes", []))
    kinds.update(f"certificate: {r['certificate_kind']}" for r in rows if r.get("certificate_kind"))
    ties = [r for r in rows if r.get("oracle") == "tie"]
    lines = [
        "# Exactness: the independent oracle against `solve` (`benchmarks/exactness.py`)", "",
        f"Command: `{command}`  ", f"Date: {started} (UTC)  ", f"Machine: {machine()}  ",
        f"Code: `{version()}`  ",
        (f"Load (`os.getloadavg()`): {' / '.join(f'{x:.2f}' for x in load0)} at the start, "
         f"{' / '.join(f'{x:.2f}' for x in load1)} at the end; {processes} processes, {wall:.0f} s wall."), "",
        (f"**{len(rows)} problems: {sum(r.get('status') == 'complete' for r in rows)} plans, "
         f"{sum(r.get('status') == 'infeasible' for r in rows)} certificates; "
         f"{sum(bool(r.get('verdict_disagrees')) for r in rows)} verdict disagreements, "
         f"{sum(r.get('valid') is False for r in rows)} invalid plans, {sum('error' in r for r in rows)} solve errors, "
         f"{sum(bool(r.get('certificate_confirmed')) for r in rows)} of "
         f"{sum(r.get('status') == 'infeasible' for r in rows)} certificates confirmed by the oracle.**"), "",
        ("Random tight problems of `supcoord.testing.oracle.tight_problems.tight_problem(seed)` (module docstring of "
        "this script); half on the default route, half with the window route forced "
        "(`SMALL_COMPONENT = 0`, levels (18, 60, 200, None) / (12, 40, 135, None) / (30, 300, None), greedy "
        "descent on and off). *Ties*: seeds ending in 7 use round numbers (arms of 15 mm, bases 19 mm apart, "
        "buffers 2 mm), where arms touch at exactly the buffer sum and rounding decides; the oracle then "
        "answers with bounds (ties free / ties blocked) and the verdict is checked against both. *Undecided "
        "oracle entries*: swept entries the oracle could not decide (ties within 1e-10 mm; several joints "
        "moving within 1e-9 mm of the buffer sum), and in parentheses how often its searches read one."), "",
        *table(rows), "",
        "## Routes and certificates reached", "",
        "| kind | problems |", "|---|---|",
        *[f"| {k} | {v} |" for k, v in sorted(kinds.items())], "",
        "## Ties", "",
        (f"{len(ties)} problems whose oracle answer depends on touches at exactly the buffer sum: "
         f"{sum(r.get('status') == 'complete' for r in ties)} plans, "
         f"{sum(r.get('status') == 'infeasible' for r in ties)} certificates, all within the oracle's bounds "
         "unless listed below."), "",
        "## Disagreements and errors", "",
    ]
    if not bad:
        lines.append("None.")
    for r in bad:
        lines.append(f"- seed {r['seed']} ({r['kind']} {r['discretisation']}, {r['positioners']} positioners, "
                     f"{r['layout']}, "
                     f"{r['route']}): oracle {r.get('oracle')} (bounds {r.get('oracle_lo')}–{r.get('oracle_hi')}), "
                     f"solve {r.get('status')}: {r['disagreement']}")
    lines += ["", "Every case: [`exactness.json`](exactness.json).", ""]
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--problems", type=int, default=1200)
    ap.add_argument("--seeds", type=int, nargs="*", help="run these seeds only (printed, nothing written)")
    ap.add_argument("--processes", type=int, default=2)
    ap.add_argument("--max-product", type=int, default=200_000,
                    help="largest number of configurations of a problem (tight_problem's max_product)")
    ap.add_argument("--memory", type=float, default=6.0, help="GiB of address space per process")
    ap.add_argument("--quick", action="store_true", help="60 problems, written to /tmp/supcoord-exactness")
    ap.add_argument("--out-dir", default=os.path.join(HERE, "results"))
    args = ap.parse_args()
    command = " ".join(["python benchmarks/exactness.py", *sys.argv[1:]])
    if args.quick:
        args.problems = 60
        if args.out_dir == ap.get_default("out_dir"):
            args.out_dir = "/tmp/supcoord-exactness"
    seeds = args.seeds if args.seeds else list(range(args.problems))
    started = time.strftime("%Y-%m-%d %H:%M", time.gmtime())
    load0, t0 = os.getloadavg(), time.perf_counter()
    rows = []
    with Pool(args.processes, initializer=_init_worker, initargs=(args.memory, args.max_product)) as pool:
        for i, row in enumerate(pool.imap_unordered(run_case, seeds, chunksize=4)):
            rows.append(row)
            flag = f"  DISAGREEMENT: {row['disagreement']}" if row.get("disagreement") else ""
            print(f"[{i + 1}/{len(seeds)}] seed {row['seed']:5d} {row['kind']:10s} {row['positioners']} "
                  f"{row['route']:9s} oracle {row.get('oracle')!s:5s} {row.get('status', '-'):10s}{flag}",
                  file=sys.stderr, flush=True)
    rows.sort(key=lambda r: r["seed"])
    load1, wall = os.getloadavg(), time.perf_counter() - t0
    text = report(rows, command, started, load0, load1, wall, args.processes)
    if args.seeds:
        print(text)
        return
    os.makedirs(args.out_dir, exist_ok=True)
    _write_atomically(os.path.join(args.out_dir, "exactness.json"), json.dumps(rows, indent=1, default=str) + "\n")
    _write_atomically(os.path.join(args.out_dir, "exactness.md"), text)
    print(f"written {args.out_dir}/exactness.md and exactness.json ({wall:.0f} s)", file=sys.stderr)


if __name__ == "__main__":
    main()
