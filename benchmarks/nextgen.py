"""Benchmark: next-generation focal planes, 469 ... 32,137 robots (the study ``studies/nextgen.toml``).

Runs the study's cases that are not done (``--no-run``: none), then writes from its database
``results/nextgen.md`` (one row per case: verdict, seconds, CPU seconds, peak resident memory,
makespan, the load of the machine when it started; the fitted growth of each series' time,
memory and motion time, :func:`supcoord.study.fit.series_growth`) and ``results/nextgen.png``
(time, peak memory and makespan against robots, one curve per series, the fit in the legend).

    python benchmarks/nextgen.py                 # run what is missing (2 workers), write the results
    python benchmarks/nextgen.py --no-run        # only rewrite the results from the database
"""

from __future__ import annotations

import argparse
import os

HERE = os.path.dirname(os.path.abspath(__file__))
STUDY = os.path.join(HERE, "studies", "nextgen.toml")
RESULTS = os.path.join(HERE, "results")
#: what is fitted and drawn: column, title, unit
METRICS = (("seconds", "time to answer", "s"), ("cpu_seconds", "CPU time", "s"),
           ("peak_rss_mb", "peak resident memory", "MB"),
           ("makespan", "motion time (makespan)", "steps"))


def table(rows: list[dict]) -> list[str]:
    """The Markdown table of every case, by series then robots."""
    out = ["| series | robots | status | verdict | seconds | CPU s | peak RSS (MB) | makespan | load |",
           "|---|---|---|---|---|---|---|---|---|"]
    for r in sorted(rows, key=lambda r: (r["series"], r["positioners"] or 0)):
        def num(key: str, fmt: str = "{:.1f}") -> str:
            return "" if r.get(key) is None else fmt.format(r[key])
        out.append(f"| {r['series']} | {r['positioners']} | {r['status']} | {r.get('verdict') or ''} | "
                   f"{num('seconds')} | {num('cpu_seconds')} | {num('peak_rss_mb', '{:.0f}')} | "
                   f"{num('makespan', '{:.0f}')} | {num('load')} |")
    return out


def growths(rows: list[dict]) -> list[str]:
    """One line per series and metric: the fitted growth over the sizes that answered."""
    from supcoord.study.fit import series_growth

    out = ["| series | " + " | ".join(title for _, title, _ in METRICS) + " |", "|---" * (len(METRICS) + 1) + "|"]
    fits = {m: series_growth(rows, m) for m, _, _ in METRICS}
    for name in sorted({r["series"] for r in rows}):
        cells = []
        for m, _, _ in METRICS:
            g = fits[m].get(name)
            cells.append("fewer than 3 sizes" if g is None else f"{g.label('positioner')} (R² {g.r2:.3f})")
        out.append(f"| {name} | " + " | ".join(cells) + " |")
    return out


def figure(rows: list[dict], path: str) -> None:
    """Time, memory and makespan against robots, log-log, one curve per series."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from supcoord.study.fit import series_growth, series_medians

    fig, axes = plt.subplots(1, len(METRICS), figsize=(4.6 * len(METRICS), 4.4))
    for ax, (metric, title, unit) in zip(axes, METRICS):
        medians, fits = series_medians(rows, metric), series_growth(rows, metric)
        for name, (xs, ys) in sorted(medians.items()):
            g = fits.get(name)
            ax.plot(xs, ys, "o-", label=name + ("" if g is None else f": {g.label('positioner')}"))
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("robots")
        ax.set_ylabel(unit)
        ax.set_title(title)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def provenance(rows: list[dict]) -> list[str]:
    """Which machine, code version and dates the rows come from, and how to read their seconds."""
    def distinct(key: str) -> str:
        return ", ".join(sorted({str(r[key]) for r in rows if r.get(key)})) or "unknown"
    started = sorted(r["started"] for r in rows if r.get("started"))
    when = f"{started[0]} to {started[-1]}" if started else "unknown"
    return [f"Machine: {distinct('machine')} ({distinct('cpu')}); code version {distinct('version')}; "
            f"cases started {when}. `seconds` is wall-clock time under the load average of the last "
            "column (a shared machine): compare CPU seconds.", ""]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--no-run", action="store_true", help="only write the results from the database")
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    from supcoord.study import load_study, results_rows, run_study

    study = load_study(STUDY)
    database = os.path.join(RESULTS, "nextgen.sqlite")
    if not args.no_run:
        run_study(study, database, workers=args.workers)
    rows = [r for r in results_rows(database) if r["positioners"]]
    answered = [r for r in rows if r["status"] == "ok"]
    pooled = [dict(r, series="all series, improve=0") for r in answered if "improve=0" in r["series"]]
    lines = ["# Next-generation focal planes: 469 to 32,137 robots", "",
             "Written by `python benchmarks/nextgen.py` from the study `benchmarks/studies/nextgen.toml`",
             "(each case in a process of its own, under its time and memory limits; 2 workers).", ""] + provenance(rows) + [
             "## Cases", ""] + table(rows) + ["", "## Fitted growth (cases that answered)", ""] + growths(answered + pooled)
    with open(os.path.join(RESULTS, "nextgen.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    figure(answered + pooled, os.path.join(RESULTS, "nextgen.png"))


if __name__ == "__main__":
    main()
