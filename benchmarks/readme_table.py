"""The README's performance table and figures, generated from the study's database.

Reads ``results/readme.sqlite`` (the results of ``benchmarks/studies/readme.toml``, run by
``supcoord study run benchmarks/studies/readme.toml``) and writes

- ``results/readme.md``: the table in the README's layout (what, size, supcoord, comparison),
  every number taken from the database, then the per-series summary of
  ``supcoord study show`` and the machines, loads and code versions the rows were measured with;
- ``results/readme-figures/``: the study's figures (time, memory, BDD nodes, verdicts, plan
  quality; ``supcoord.study.plots``).

    python benchmarks/readme_table.py
    python benchmarks/readme_table.py --db other.sqlite --out /tmp/t.md --figures /tmp/fig
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
from typing import Any

HERE = os.path.dirname(os.path.abspath(__file__))


def _pick(rows: list[dict], series: str, size: int | None = None) -> list[dict]:
    return [r for r in rows if r["series"] == series and (size is None or r["size"] == size)]


def _s(x: float | None) -> str:
    if x is None:
        return "?"
    return f"{x:.3f} s" if x < 1 else f"{x:.1f} s" if x < 100 else f"{x:.0f} s"


def _states(r: dict) -> str:
    if r.get("states") and len(r["states"]) <= 9:
        return f"{int(r['states']):,} states"
    if not r.get("states_log10"):
        return "? states"
    exponent = int(r["states_log10"])
    mantissa = 10 ** (r["states_log10"] - exponent)
    return f"10^{r['states_log10']:.0f} states" if exponent > 300 else f"{mantissa:.1f} × 10^{exponent} states"


def _first_failure(rows: list[dict], series: str) -> str:
    ok = sorted((r for r in _pick(rows, series) if r["status"] == "ok"), key=lambda r: r["size"])
    bad = sorted((r for r in _pick(rows, series) if r["status"] in ("timeout", "out-of-memory")), key=lambda r: r["size"])
    parts = []
    if ok:
        parts.append(f"{_s(ok[-1]['seconds'])} at {ok[-1]['size']}")
    if bad:
        limit = bad[0]["time_limit"] if bad[0]["status"] == "timeout" else None
        parts.append(f">{limit:g} s at {bad[0]['size']}" if limit else f"out of memory at {bad[0]['size']}")
    return ", ".join(parts) or "not run"


def _supcon(rows: list[dict], family: str, size: int, label: str) -> list[str]:
    rs = _pick(rows, f"supcon {family}", size)
    if not rs or rs[0]["status"] != "ok":
        return [f"| supcon, {label} | {size} | {rs[0]['status'] if rs else 'not run'} | — |"]
    return [f"| supcon, {label} | {size} ({_states(rs[0])}) | {_s(rs[0]['seconds'])}, {rs[0]['bdd_nodes']:,} BDD nodes | — |"]


def _solve(rows: list[dict], kind: str, size: int) -> str:
    rs = _pick(rows, f"solve {kind} local", size)
    if not rs:
        return f"| geometric coordination, {kind} | {size} | not run | — |"
    ok = [r for r in rs if r["status"] == "ok"]
    verdicts = {v: sum(r["verdict"] == v for r in ok) for v in ("complete", "infeasible")}
    failed = len(rs) - len(ok)
    secs = [r["seconds"] for r in ok]
    mono = _first_failure(rows, f"solve {kind} monolithic")
    ratio = [r["makespan"] / r["lower_bound"] for r in ok if r.get("makespan") and r.get("lower_bound")]
    what = f"{len(rs)} seeds: {verdicts['complete']} plans, {verdicts['infeasible']} certificate(s) of infeasibility" + (
        f", {failed} failed" if failed else "")
    return (f"| geometric coordination, {kind} | {size} positioners, {what} | median {_s(statistics.median(secs))} "
            f"(max {_s(max(secs))}, {max(r['peak_rss_mb'] for r in ok):.0f} MB); makespan / lower bound median "
            f"{statistics.median(ratio):.2f} | monolithic: {mono} |")


def table(rows: list[dict[str, Any]]) -> list[str]:
    out = ["| what | size | supcoord | comparison |", "|---|---|---|---|"]
    out += _supcon(rows, "dining_philosophers", 10, "dining philosophers")
    out += _supcon(rows, "machine_line", 11, "machine line")
    out += _supcon(rows, "transfer_line_chain", 3, "chain of transfer lines")
    out += _supcon(rows, "small_factories", 4, "small factories")
    out += _supcon(rows, "coupled_factories", 4, "coupled factories")
    out += _supcon(rows, "small_factories", 30, "small factories")
    for family in ("dining_philosophers", "machine_line"):
        rs = [r for r in _pick(rows, f"force {family} preemptive", 16) if r["status"] == "ok"]
        if rs:
            out.append(f"| forcibility (every state's rank + a witness), {family.replace('_', ' ')} | 16 "
                       f"({_states(rs[0])}, {rs[0]['extra'].get('layers')} layers) | {_s(rs[0]['seconds'])} | — |")
    for size in (5000,):
        rs = [r for r in _pick(rows, "paper literal modular", size) if r["status"] == "ok"]
        if rs:
            out.append(f"| the paper's literal model, modular route | {size} positioners ({_states(rs[0])}) | "
                       f"{_s(rs[0]['seconds'])}, {rs[0]['bdd_nodes']:,} BDD nodes, {rs[0]['peak_rss_mb']:.0f} MB | "
                       f"monolithic: {_first_failure(rows, 'paper literal monolithic')} |")
    ok = sorted((r for r in _pick(rows, "paper coupled monolithic") if r["status"] == "ok"), key=lambda r: r["size"])
    if ok:
        out.append(f"| the paper's coupled model | {ok[-1]['size']} positioners ({_states(ok[-1])}) | "
                   f"{_s(ok[-1]['seconds'])} | {_first_failure(rows, 'paper coupled monolithic').split(', ')[-1]} |")
    out.append(_solve(rows, "rotary", 127))
    out.append(_solve(rows, "rotary", 547))
    out.append(_solve(rows, "alpha-beta", 127))
    return out


def provenance(rows: list[dict[str, Any]]) -> list[str]:
    ran = [r for r in rows if r.get("cpu")]
    loads = [r["load"] for r in ran if r.get("load") is not None]
    counts = {s: sum(r["status"] == s for r in rows) for s in sorted({r["status"] for r in rows})}
    return [f"- cases: {len(rows)} ({', '.join(f'{n} {s}' for s, n in counts.items())})",
            f"- machines: {', '.join(sorted({r['cpu'] for r in ran}))}",
            f"- code versions: {', '.join(sorted({r['version'] for r in ran}))}",
            f"- started between {min(r['started'] for r in ran)} and {max(r['started'] for r in ran)} (UTC)",
            (f"- load average (1 min) at the start of a case: median {statistics.median(loads):.1f}, "
            f"max {max(loads):.1f} (the machine is shared: seconds are noisy, compare within the table)")]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--db", default=os.path.join(HERE, "results", "readme.sqlite"))
    ap.add_argument("--out", default=os.path.join(HERE, "results", "readme.md"))
    ap.add_argument("--figures", default=os.path.join(HERE, "results", "readme-figures"))
    args = ap.parse_args(argv)
    import matplotlib

    matplotlib.use("Agg")
    from supcoord.study.plots import study_figures
    from supcoord.study.report import markdown_table, summary_rows
    from supcoord.study.results import results_rows

    rows = results_rows(args.db)
    lines = ["# The README's performance table, from the study's database", "",
             ("Generated by `python benchmarks/readme_table.py` from `results/readme.sqlite`, the results of "
             "`supcoord study run benchmarks/studies/readme.toml`. Seconds are the computation alone (no "
             "interpreter start, no imports; `solve` without the validator), each case in a fresh process."), "",
             *provenance(rows), "", *table(rows), "", "## Every series and size", "",
             markdown_table(summary_rows(rows)), ""]
    with open(args.out, "w") as f:
        f.write("\n".join(lines))
    paths = study_figures(rows, args.figures)
    print(f"wrote {args.out} and {len(paths)} figures in {args.figures}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
