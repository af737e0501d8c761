"""``supcoord study run|show|export|plot STUDY.toml``: declared studies on Dask, results in a database.

- ``run``: run the cases of the study not yet done (same parameters and code version),
  on an embedded Dask ``LocalCluster`` of ``--workers`` processes (default 2, or the
  file's ``workers``), on an existing cluster (``--scheduler ADDRESS``), or one after
  another in this process (``--workers 0``); each case in a process of its own with its
  time and memory limits; one progress line per case on stderr; every finished case is
  committed to the database at once, so Ctrl-C (exit 130) loses nothing and ``run`` again
  resumes; a case that crashed (a bug, not a time-out, memory or infeasible answer) makes
  the run exit 1 after the others, with one ``supcoord: error:`` line naming the first.
  JSON: ``{"status": "finished"|"interrupted", "study", "database", "version",
  "total", "pending", "ran", "statuses", "failed", "left", "workers", "wall_seconds"}``.
- ``show``: how far the study is (cases done, failed, left) and, per series and size,
  the counts, verdicts, median and maximum seconds, memory and BDD nodes.
- ``export``: the rows to ``--out`` as ``--format csv|parquet`` (one row per case).
- ``plot``: the figures (time, memory, BDD nodes, verdicts, plan quality) to ``--out``.

``show``, ``export`` and ``plot`` read the rows of the study's cases from its database, or
every row of a results database (``.sqlite``) given instead of the study file.  The file format, the columns and running on a cluster: ``docs/study.md``.
"""

from __future__ import annotations

import argparse
import dataclasses
import re
from pathlib import Path

from .common import CommandResult, Console, options_named

__all__ = ["ACTIONS", "BUDGETS", "DESCRIPTION", "EXAMPLE", "HELP", "add_arguments", "run"]

ACTIONS = ("run", "show", "export", "plot")
DATABASE_SUFFIXES = (".sqlite", ".sqlite3", ".db")

EXAMPLE = """examples:
  supcoord study run benchmarks/studies/quick.toml --workers 2     run (or resume) a study
  supcoord study show benchmarks/studies/quick.toml                done / failed / left, per series
  supcoord study export benchmarks/studies/quick.toml --format csv --out quick.csv
  supcoord study plot benchmarks/studies/quick.toml --out figures/
  supcoord study run big.toml --scheduler tcp://10.0.0.5:8786      on an existing Dask cluster"""

HELP = "run a declared study (grid of paper/solve/supcon/force cases) on Dask; show, export, plot its results"
DESCRIPTION = ("Run the cases of a study file (TOML or JSON) not yet in its results database, each in a "
               "process of its own with time and memory limits, on Dask workers; show, export (CSV, "
               "Parquet) or plot the results.")
BUDGETS = False  # each case has its own limits, in the study file (or --time-limit/--memory-limit)


def add_arguments(p: argparse.ArgumentParser) -> None:
    """``supcoord study``'s own options (:func:`.main.build_parser` adds the common ones)."""
    p.add_argument("action", choices=ACTIONS, help="run the study, show its progress, export or plot its results")
    p.add_argument("study", metavar="STUDY.toml", help="the study file (.toml or .json); show/export/plot also "
                                                       "take its results database (.sqlite)")
    p.add_argument("--db", metavar="FILE.sqlite", help="the results database (default: the file's 'database', "
                                                       "else NAME.sqlite beside the study file)")
    p.add_argument("--workers", type=int, metavar="N", help="run: Dask worker processes of the embedded cluster "
                                                            "(default: the file's, else 2); 0: no Dask, one case after another")
    p.add_argument("--scheduler", metavar="ADDRESS", help="run: an existing Dask scheduler, e.g. tcp://host:8786")
    p.add_argument("--time-limit", type=float, metavar="SECONDS",
                   help="run/show: time limit of every case (replaces the file's)")
    p.add_argument("--memory-limit", metavar="SIZE",
                   help="run/show: memory limit of every case, e.g. '6 GiB' (replaces the file's)")
    p.add_argument("--retry", nargs="+", metavar="STATUS", default=[],
                   choices=["timeout", "out-of-memory", "error", "crashed", "lost"],
                   help="run: run the cases recorded with these statuses again (e.g. crashed, after a fix)")
    p.add_argument("--code-version", metavar="TEXT", help="run/show: the version recorded with each case and compared "
                                                          "to resume (default: the package version and git commit)")
    p.add_argument("--any-version", action="store_true",
                   help="run/show: a case recorded by any code version counts as done (resume a long study "
                        "across commits that did not change what it measures)")
    p.add_argument("--format", choices=["csv", "parquet"], help="export: the file format (default: from --out's suffix, else csv)")
    p.add_argument("--out", metavar="PATH", help="export: the file (default NAME.csv beside the database); "
                                                 "plot: the folder (default NAME-figures beside the database)")


def _is_database(path: str) -> bool:
    return Path(path).suffix.lower() in DATABASE_SUFFIXES


def _study(args: argparse.Namespace):
    from ..errors import InputError
    from ..study.spec import load_study, parse_memory

    if _is_database(args.study):
        if args.action == "run":
            raise InputError("run needs the study file (.toml or .json), not its database", value=args.study,
                             where=args.study)
        return None, Path(args.db or args.study)
    study = load_study(args.study)
    if args.time_limit is not None or args.memory_limit is not None:
        changes = {}
        if args.time_limit is not None:
            if not args.time_limit > 0:
                raise InputError(f"must be a positive number of seconds, got {args.time_limit}",
                                 value=args.time_limit, where="--time-limit")
            changes["time_limit"] = float(args.time_limit)
        if args.memory_limit is not None:
            changes["memory_limit_mb"] = parse_memory(args.memory_limit, "--memory-limit")
        study.cases = [dataclasses.replace(c, **changes) for c in study.cases]
    return study, study.database_path(args.db)


def run(args: argparse.Namespace, console: Console) -> CommandResult:
    study, database = _study(args)
    action = {"run": _run, "show": _show, "export": _export, "plot": _plot}[args.action]
    return action(args, console, study, database)


#: parameters of :func:`~supcoord.study.execute.run_study` whose errors are shown as their options
RUN_OPTIONS = {"workers": "--workers", "scheduler": "--scheduler", "retry": "--retry"}


def _run(args, console, study, database) -> CommandResult:
    import sys

    from ..errors import InputError
    from ..study.execute import run_study

    if args.scheduler is not None and args.workers is not None:
        raise InputError("give --workers (an embedded cluster) or --scheduler (an existing one), not both",
                         value=args.workers, where="--workers")
    command = "supcoord study " + " ".join(sys.argv[2:]) if len(sys.argv) > 2 else ""

    def report(line: str) -> None:
        """Each case's line, and the status line's count (``[ 12/40] …``), which its
        heartbeat keeps alive while a long case runs."""
        console.log(line)
        counted = re.match(r"\[\s*(\d+)/(\d+)\]", line)
        console.progress("study", {"done": int(counted[1]), "total": int(counted[2])} if counted else {})

    with options_named(RUN_OPTIONS):  # the library names its parameters
        summary = run_study(study, database, workers=args.workers, scheduler=args.scheduler, progress=report,
                            version=args.code_version, retry=args.retry, any_version=args.any_version, command=command)
    payload = {"status": "interrupted" if summary.interrupted else "finished", **dataclasses.asdict(summary),
               "failed": summary.failed, "left": summary.left}
    text = (f"{study.name}: {summary.total} cases, {summary.total - summary.pending} done before this run, "
            f"{summary.ran} run now ({summary.failed} failed), {summary.left} left; results in {database}")
    crashed = summary.statuses.get("crashed", 0)
    if summary.interrupted:
        return CommandResult(payload, text, exit_code=130)
    if crashed:  # a bug (in supcoord or a called function), not an answer: exit 1 (docs/formats.md)
        console.error(f"{crashed} of {summary.ran} cases crashed (a bug: the first, {summary.first_crash}); "
                      f"the others' results are in {database}")
        return CommandResult(payload, text, exit_code=1)
    return CommandResult(payload, text)


def _show(args, console, study, database) -> CommandResult:
    from ..study.resume import is_done, records
    from ..study.machine import code_version
    from ..study.report import markdown_table, summary_rows
    from ..study.results import results_rows
    from ..study.store import ResultStore

    rows = [] if study is not None and not database.is_file() else results_rows(_existing(database), study=study)
    statuses: dict[str, int] = {}
    for r in rows:
        statuses[r["status"]] = statuses.get(r["status"], 0) + 1
    payload = {"study": study.name if study else None, "database": str(database), "rows": len(rows),
               "statuses": statuses, "series": summary_rows(rows)}
    lines = [f"{database}: {len(rows)} cases recorded ({', '.join(f'{n} {s}' for s, n in sorted(statuses.items())) or 'none'})"]
    if study is not None:
        version = args.code_version or code_version()
        found = {}
        if database.is_file():
            with ResultStore(database, create=False) as store:
                found = records(study, store, version, args.any_version)
        done = sum(is_done(found.get(c.params_key), c) for c in study.cases)
        skipped = sum((found.get(c.params_key) or ("",))[0] == "skipped" for c in study.cases)
        payload.update(total=len(study.cases), done=done, left=len(study.cases) - done, skipped=skipped,
                       version=version)
        lines.insert(0, f"{study.name}: {done} of {len(study.cases)} cases done for "
                        f"{'any version' if args.any_version else 'version ' + version}, "
                        f"{len(study.cases) - done} left" + (f" ({skipped} skipped by skip_larger)" if skipped else ""))
    if rows:
        lines += ["", markdown_table(payload["series"])]
        lines += _growth(rows, payload)
    return CommandResult(payload, "\n".join(lines))


def _growth(rows: list[dict], payload: dict) -> list[str]:
    """The fitted growth of each series (the figures' legends: ``series_growth``), as lines
    and as ``payload["growth"][metric][series]``."""
    from ..study.fit import series_growth
    from ..study.plots import METRICS

    lines, payload["growth"] = [], {}
    for metric, (_, label, _) in METRICS.items():
        fits = {name: g for name, g in series_growth(rows, metric).items() if g is not None}
        payload["growth"][metric] = {name: {**dataclasses.asdict(g), "label": g.label(_unit(name))}
                                     for name, g in fits.items()}
        if fits:
            lines += ["", f"fitted growth of {label} (every size of a series):"]
            lines += [f"  {name}: {g.label(_unit(name))} (r² {g.r2:.2f}, {g.points} sizes)" for name, g in fits.items()]
    return lines


def _unit(series: str) -> str:
    return "positioner" if series.startswith(("paper", "solve")) else "size step"


def _export(args, console, study, database) -> CommandResult:
    from ..study.results import export_results

    from ..outputs import check_output

    fmt = args.format or (Path(args.out).suffix.lstrip(".").lower() if args.out else "csv") or "csv"
    out = Path(args.out) if args.out else database.with_suffix(f".{fmt}")
    check_output(out, [database, args.study], "--out")  # never over the database or the study file
    with options_named({"out": "--out"}):
        n = export_results(_existing(database), out, fmt, study=study)
    return CommandResult({"status": "ok", "rows": n, "format": fmt, "out": str(out)}, f"{n} rows written to {out}")


def _plot(args, console, study, database) -> CommandResult:
    import matplotlib

    matplotlib.use("Agg")
    from ..study.plots import study_figures
    from ..study.results import results_rows

    from ..study.plots import check_output_dir

    out = Path(args.out) if args.out else database.with_name(database.stem + "-figures")
    with options_named({"out": "--out"}):
        check_output_dir(out)
        paths = study_figures(results_rows(_existing(database), study=study), out, inputs=[database, args.study])
    return CommandResult({"status": "ok", "figures": [str(p) for p in paths]},
                         "figures written: " + ", ".join(str(p) for p in paths))


def _existing(database: Path) -> Path:
    from ..errors import InputError

    if not database.is_file():
        raise InputError("no results database here yet (run the study first)", value=str(database), where=str(database))
    return database
