"""Does a study go faster on Dask workers?  20 cases one after another, then on 2 workers.

Runs ``benchmarks/studies/parallel.toml`` (20 cases of a few seconds: the paper's literal
model, monolithic route, 40 positioners, 20 seeds) twice into fresh databases, in one
invocation: first with ``--workers 0`` (one case after another from this process, no
Dask), then on an embedded ``LocalCluster`` of 2 worker processes.  Both ways run every
case in a process of its own with the same limits; the wall-clock time of each run
includes everything (the cluster's start and stop included).  Writes
``results/study_parallel.md``: a row per invocation (the rows of earlier runs are kept)
with both times, their ratio, the load average before and after and the scheduling
priority, then the last run's details (the sums of the cases' own seconds and of their
processes' wall-clock seconds).

    python benchmarks/bench_study_parallel.py                    # writes results/study_parallel.md
    python benchmarks/bench_study_parallel.py --workers 4 --out /tmp/p.md
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from datetime import UTC, datetime

HERE = os.path.dirname(os.path.abspath(__file__))


def _history(path: str | None) -> list[str]:
    """The rows of the runs table of an earlier results file (kept, and this run added)."""
    if not path or not os.path.exists(path):
        return []
    with open(path) as f:
        return [line.rstrip("\n") for line in f if line.startswith("| 20")]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--study", default=os.path.join(HERE, "studies", "parallel.toml"))
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--out", default=os.path.join(HERE, "results", "study_parallel.md"))
    args = ap.parse_args(argv)
    from supcoord.study import load_study, results_rows, run_study
    from supcoord.study.machine import code_version, cpu_model

    study = load_study(args.study)
    load0 = os.getloadavg()
    measured = {}
    with tempfile.TemporaryDirectory() as tmp:
        for label, workers in (("one after another (--workers 0)", 0), (f"{args.workers} Dask workers", args.workers)):
            db = os.path.join(tmp, f"{workers}.sqlite")
            t0 = time.perf_counter()
            summary = run_study(study, db, workers=workers, progress=lambda s: print(s, file=sys.stderr))
            wall = time.perf_counter() - t0
            rows = results_rows(db)
            measured[label] = {"wall": wall, "cases": len(rows), "ok": summary.statuses.get("ok", 0),
                               "case_seconds": sum(r["seconds"] or 0 for r in rows),
                               "case_wall": sum(r["wall_seconds"] or 0 for r in rows)}
    load1 = os.getloadavg()
    (_serial_label, serial), (par_label, par) = measured.items()
    ratio = par["wall"] / serial["wall"]
    what = ", ".join(sorted({c.describe().rsplit(", seed=", 1)[0] for c in study.cases}))
    run = (f"| {datetime.now(UTC):%Y-%m-%d %H:%M} | {what} | {' / '.join(f'{x:.1f}' for x in load0)} → "
           f"{' / '.join(f'{x:.1f}' for x in load1)} | {os.nice(0)} | {serial['wall']:.1f} | {par['wall']:.1f} | "
           f"**{ratio:.2f}** |")
    history = _history(args.out) + [run]
    lines = ["# A study on Dask workers against one case after another (`benchmarks/bench_study_parallel.py`)", "",
             ("Each row is one invocation of `python benchmarks/bench_study_parallel.py`: the 20 cases of "
             "`benchmarks/studies/parallel.toml` run one after another (`--workers 0`), then on a `LocalCluster` of "
             f"{args.workers} worker processes, each into a fresh database, every case in a process of its own; the "
             "wall-clock seconds include everything (the cluster's start and stop). The machine (2 cores) is shared "
             "with other jobs: the load (1/5/15-minute averages at the start → at the end) and the scheduling "
             "priority (nice) are recorded; with other jobs taking the cores, two workers cannot get two of them."), "",
             "| date (UTC) | cases | load | nice | one after another s | 2 workers s | ratio |",
             "|---|---|---|---:|---:|---:|---:|", *history, "",
             f"## The last run (code {code_version()}, {cpu_model()})", "",
             "| run | cases ok | wall s | cases' own s | cases' processes' wall s |", "|---|---:|---:|---:|---:|"]
    for label, m in measured.items():
        lines.append(f"| {label} | {m['ok']}/{m['cases']} | {m['wall']:.1f} | {m['case_seconds']:.1f} | "
                     f"{m['case_wall']:.1f} |")
    lines += ["", (f"**{par_label}: {ratio:.2f}× the wall-clock time of one after another** "
                   f"({par['wall']:.1f} s against {serial['wall']:.1f} s).")]
    text = "\n".join(lines) + "\n"
    print(text)
    if args.out:
        with open(args.out, "w") as f:
            f.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
