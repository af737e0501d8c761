"""Figures of a study's results (matplotlib), one figure per question.

- :func:`figure_metric` — how do time (``seconds``), memory (``peak_rss_mb``) and BDD
  size (``bdd_nodes``) grow with the number of positioners (or the family size)?  One
  panel per group of series (the paper's literal model, its coupled model, each
  kinematics or instrument of geometric coordination, the synthesis families …), one
  line per series (route, model, family) through the median over seeds at each size,
  drawn in order of its x, every seed as a faint point, the growth fitted on all its
  sizes (:func:`.fit.series_growth`: power law, linear or exponential) in the legend under
  the panel; y on a log axis where the values span a decade or more, x on a log axis where
  most fits are power laws and the sizes span a decade, a linear axis otherwise (so an
  exponential is a straight line); log axes label 1-2-5 steps or decades, never crowded.  Cases
  that ran out of time are drawn as ▲ at their time limit (their time is at least that),
  out of memory as ✕;
- :func:`figure_verdicts` — what did each case answer?  Per series and size, the count
  of each verdict and failure, coloured (green: all positive answers, yellow: some
  negative answers, red: failures, grey: not run);
- :func:`figure_quality` — how good are the plans?  Makespan over its lower bound
  against positioners, per series of ``solve``.

Every panel has data or says why it has none.  :func:`study_figures` writes the five
figures of a database to a folder.
"""

from __future__ import annotations

import math
import os
import statistics
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..errors import InputError
from ..outputs import atomic_output, check_output
from .fit import series_growth, series_medians

__all__ = ["METRICS", "figure_metric", "figure_quality", "figure_verdicts", "group_of", "study_figures", "x_of"]

#: metric column -> (figure name, axis label, title)
METRICS = {"seconds": ("time", "seconds", "time of the computation (start-up excluded)"),
           "peak_rss_mb": ("memory", "peak RSS (MB)", "peak memory of the case's process (resident set)"),
           "bdd_nodes": ("nodes", "BDD nodes", "BDD nodes (peak live, or the supervisor's)")}
POSITIVE = {"forcible", "complete", "nonempty", "ok"}
#: the short codes of the answers in the verdicts figure
CODES = {"complete": "C", "infeasible": "I", "forcible": "F", "not forcible": "NF", "nonempty": "N", "empty": "E",
         "ok": "ok", "timeout": "T", "out-of-memory": "M", "crashed": "X", "error": "err", "lost": "L", "skipped": "–"}
NEGATIVE = {"not forcible", "infeasible", "empty"}
def x_of(row: dict[str, Any]) -> int | None:
    """The x of a row: its positioners, else its size (a family's size parameter)."""
    return row.get("positioners") if row.get("positioners") is not None else row.get("size")


def group_of(row: dict[str, Any]) -> str:
    """The panel a row is drawn in: ``paper literal``, ``solve rotary``, ``supcon`` …"""
    words = (row.get("series") or row.get("kind") or "?").split()
    return " ".join(words[:2]) if words[0] in ("paper", "solve") else words[0]


def _groups(rows: list[dict[str, Any]]) -> dict[str, list[dict[str, Any]]]:
    out: dict[str, list[dict[str, Any]]] = {}
    for r in rows:
        out.setdefault(group_of(r), []).append(r)
    return out


def _unit(rows: list[dict[str, Any]]) -> str:
    return "positioner" if any(r.get("positioners") is not None for r in rows) else "size step"


def _xlabel(rows: list[dict[str, Any]]) -> str:
    return "positioners" if _unit(rows) == "positioner" else "size (the family's parameter)"


def _panels(n: int, width: float = 4.6, height: float = 3.8):
    import matplotlib.pyplot as plt

    cols = min(n, 3)
    rows = (n + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(width * cols, height * rows), squeeze=False,
                             layout="constrained")  # makes room for the legends under the panels
    flat = list(axes.ravel())
    for ax in flat[n:]:
        ax.set_visible(False)
    return fig, flat[:n]


def _empty(ax, message: str) -> None:
    ax.text(0.5, 0.5, message, ha="center", va="center", transform=ax.transAxes, fontsize=9, wrap=True, color="0.35")
    ax.set_xticks([])
    ax.set_yticks([])


def _limit_value(row: dict[str, Any], metric: str) -> float | None:
    if metric == "seconds" and row["status"] == "timeout":
        return max(row.get("seconds") or 0.0, row.get("time_limit") or 0.0) or None
    if metric == "peak_rss_mb" and row["status"] == "out-of-memory" and row.get("memory_limit_mb"):
        return max(row.get("peak_rss_mb") or 0.0, row["memory_limit_mb"])
    return row.get(metric)


def _log_ticks(axis, values: list[float]) -> None:
    """Major ticks at 1-2-5, 1-3 or 1 of each decade (fewer as the decades grow) with plain
    labels, and no minor labels: labels that never run into each other."""
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

    lo, hi = min(values), max(values)
    decades = math.log10(hi / lo) if lo > 0 else 0.0
    subs = (1.0, 2.0, 5.0) if decades <= 2 else (1.0, 3.0) if decades <= 3.5 else (1.0,)
    axis.set_major_locator(LogLocator(base=10, subs=subs))
    axis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:,.10g}" if 1e-3 <= v < 1e5 else f"{v:.0e}"))
    axis.set_minor_formatter(NullFormatter())


def _legend_below(ax) -> None:
    """The legend under the panel (outside it), so it hides no marker."""
    handles, labels = ax.get_legend_handles_labels()
    if handles:
        ax.legend(handles, labels, fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=1,
                  frameon=False)


@dataclass
class _Drawn:
    """What a panel drew so far: its y values and x values (for the axes' scales), the
    growth fitted to each series drawn, and the failure labels already in the legend."""

    any: bool = False
    values: list[float] = field(default_factory=list)
    xs: list[float] = field(default_factory=list)
    growths: list[Any] = field(default_factory=list)
    failed_labels: set[str] = field(default_factory=set)


def _draw_medians(ax, rs: list[dict[str, Any]], metric: str, color: str, label: str, xs: list, med: list,
                  drawn: _Drawn) -> None:
    """A series' medians as a line, and its single cases where an x has several."""
    ax.plot(xs, med, "o-", color=color, label=label, ms=4, lw=1.4)
    by_x: dict[int, list[float]] = {}
    for r in rs:
        if r["status"] == "ok" and r.get(metric) is not None and x_of(r) is not None:
            by_x.setdefault(x_of(r), []).append(float(r[metric]))
    spread = [(x, v) for x in xs for v in by_x[x] if len(by_x[x]) > 1]
    if spread:
        ax.plot([p[0] for p in spread], [p[1] for p in spread], ".", color=color, alpha=0.35, ms=4)
    drawn.any = True
    drawn.values += med
    drawn.xs += xs


def _draw_failures(ax, name: str, rs: list[dict[str, Any]], metric: str, color: str, drawn: _Drawn) -> None:
    """A series' cases that ran out of time (▲) or memory (✕), at the value they reached."""
    where = "at its limit" if metric == "seconds" else "when it stopped"
    for status, marker, text in (("timeout", "^", f"{name}: ran out of time (▲ {where})"),
                                 ("out-of-memory", "X", f"{name}: ran out of memory (✕ {where})")):
        bad = [(x_of(r), _limit_value(r, metric)) for r in rs if r["status"] == status and x_of(r) is not None]
        bad = sorted((x, v) for x, v in bad if v)
        if bad:
            ax.plot([b[0] for b in bad], [b[1] for b in bad], marker, color=color, mfc="none", ms=8, mew=1.5,
                    label=text if text not in drawn.failed_labels else None)
            drawn.failed_labels.add(text)
            drawn.any = True
            drawn.values += [b[1] for b in bad]
            drawn.xs += [b[0] for b in bad]


def _scale_axes(ax, drawn: _Drawn) -> None:
    """Logarithmic axes where the values span a decade or more (x only where most fitted
    growths are powers)."""
    positive = [v for v in drawn.values if v and v > 0]
    if positive and max(positive) / min(positive) >= 10:
        ax.set_yscale("log")
        _log_ticks(ax.yaxis, positive)
    fitted = [g for g in drawn.growths if g is not None]
    powers = sum(g.model == "power" for g in fitted)
    xpos = [x for x in drawn.xs if x and x > 0]
    if xpos and max(xpos) / min(xpos) >= 10 and powers >= len(fitted) - powers:
        ax.set_xscale("log")
        _log_ticks(ax.xaxis, xpos)


def _draw_metric(ax, rows: list[dict[str, Any]], metric: str, title: str) -> None:
    """One panel: each series' medians against x with its fitted growth, and its failures."""
    medians = series_medians(rows, metric)
    growth_of = series_growth(rows, metric)
    series: dict[str, list[dict[str, Any]]] = {}
    for r in rows:
        series.setdefault(r["series"], []).append(r)
    drawn = _Drawn()
    for i, (name, rs) in enumerate(sorted(series.items())):
        color = f"C{i % 10}"
        xs, med = medians.get(name, ([], []))  # every series in order of its x
        growth = growth_of.get(name)
        if xs:
            label = name + (f": {growth.label(_unit(rs))}" if growth else "")
            _draw_medians(ax, rs, metric, color, label, xs, med, drawn)
            drawn.growths.append(growth)
        _draw_failures(ax, name, rs, metric, color, drawn)
    ax.set_title(title, fontsize=10)
    if not drawn.any:
        statuses = sorted({r["status"] for r in rows})
        _empty(ax, f"no {METRICS[metric][0]} measured in this group\n({len(rows)} cases: {', '.join(statuses)})")
        return
    _scale_axes(ax, drawn)
    ax.set_xlabel(_xlabel(rows))
    ax.set_ylabel(METRICS[metric][1])
    ax.grid(alpha=0.3, which="both")
    _legend_below(ax)


def figure_metric(rows: list[dict[str, Any]], metric: str = "seconds"):
    """One panel per group of series (module docstring); returns the figure."""
    if metric not in METRICS:
        raise ValueError(f"metric must be one of {', '.join(METRICS)}, got {metric!r}")
    groups = _groups(rows)
    fig, axes = _panels(max(1, len(groups)))
    if not groups:
        _empty(axes[0], "the database holds no case yet")
    for ax, (title, rs) in zip(axes, sorted(groups.items())):
        _draw_metric(ax, rs, metric, title)
    fig.suptitle(f"{METRICS[metric][2]} against size, per route and model; ▲ ran out of time, ✕ out of memory",
                 fontsize=11)
    return fig


def _outcome(row: dict[str, Any]) -> str:
    return (row.get("verdict") or "ok") if row["status"] == "ok" else row["status"]


def figure_verdicts(rows: list[dict[str, Any]]):
    """Counts of each answer per series and size (module docstring)."""
    from matplotlib.patches import Rectangle

    groups = _groups(rows)
    fig, axes = _panels(max(1, len(groups)), width=5.2, height=3.0)
    if not groups:
        _empty(axes[0], "the database holds no case yet")
    for ax, (title, rs) in zip(axes, sorted(groups.items())):
        names = sorted({r["series"] for r in rs})
        sizes = sorted({x_of(r) for r in rs if x_of(r) is not None})
        cells: dict[tuple[str, Any], dict[str, int]] = {}
        for r in rs:
            cell = cells.setdefault((r["series"], x_of(r)), {})
            cell[_outcome(r)] = cell.get(_outcome(r), 0) + 1
        cols = sizes + ([None] if any(x_of(r) is None for r in rs) else [])
        for (name, x), counts in cells.items():
            i, j = names.index(name), cols.index(x)
            outcomes = set(counts)
            color = ("#f4a6a6" if outcomes - POSITIVE - NEGATIVE - {"skipped"} else
                     "#dddddd" if outcomes == {"skipped"} else "#f7e08f" if outcomes & NEGATIVE else "#a8dba8")
            ax.add_patch(Rectangle((j - 0.48, i - 0.45), 0.96, 0.9, color=color))
            text = "\n".join(f"{n}{CODES.get(o, o)}" for o, n in sorted(counts.items()))
            ax.text(j, i, text, ha="center", va="center", fontsize=6)
        ax.set_xlim(-0.5, len(cols) - 0.5)
        ax.set_ylim(len(names) - 0.5, -0.5)
        ax.set_xticks(range(len(cols)), ["?" if c is None else str(c) for c in cols], fontsize=7)
        ax.set_yticks(range(len(names)), [n.split(" ", 1)[-1] if n.count(" ") else n for n in names], fontsize=7)
        ax.set_xlabel(_xlabel(rs))
        ax.set_title(title, fontsize=10)
    used = sorted({_outcome(r) for r in rows})
    fig.suptitle("cases per answer, series and size — green: all positive, yellow: some negative, red: failures, "
                 "grey: not run\n" + ", ".join(f"{CODES.get(o, o)} {o}" for o in used), fontsize=9)
    return fig


def figure_quality(rows: list[dict[str, Any]]):
    """Makespan / lower bound against positioners for the ``solve`` series."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 4.6), layout="constrained")
    plans = [r for r in rows if r.get("makespan") is not None and r.get("lower_bound") and x_of(r) is not None]
    if not plans:
        solves = sum(r.get("kind") == "solve" for r in rows)
        _empty(ax, "no plan with a makespan in this study" + (f" ({solves} solve cases, none complete)" if solves
                                                             else " (it has no solve case)"))
        return fig
    series: dict[str, list[dict[str, Any]]] = {}
    for r in plans:
        series.setdefault(r["series"], []).append(r)
    for i, (name, rs) in enumerate(sorted(series.items())):
        by_x: dict[int, list[float]] = {}
        for r in rs:
            by_x.setdefault(x_of(r), []).append(r["makespan"] / r["lower_bound"])
        xs = sorted(by_x)
        ax.plot(xs, [statistics.median(by_x[x]) for x in xs], "o-", color=f"C{i % 10}", ms=4, label=f"{name} (median)")
        pts = [(x, v) for x in xs for v in by_x[x]]
        ax.plot([p[0] for p in pts], [p[1] for p in pts], ".", color=f"C{i % 10}", alpha=0.35)
    ax.axhline(1, color="grey", lw=0.8, ls=":")
    xs_all = [x_of(r) for r in plans]
    if max(xs_all) / max(1, min(xs_all)) >= 10:
        ax.set_xscale("log")
        _log_ticks(ax.xaxis, [x for x in xs_all if x > 0])
    ax.set(xlabel="positioners", ylabel="makespan / lower bound", title="plan quality (1 = provably optimal)")
    ax.grid(alpha=0.3)
    _legend_below(ax)
    return fig


def study_figures(rows: list[dict[str, Any]], out_dir: str | Path, fmt: str = "png", dpi: int = 110,
                  inputs: Iterable[str | Path | None] = ()) -> list[Path]:
    """Write ``time``, ``memory``, ``nodes``, ``verdicts`` and ``quality`` figures of
    ``rows`` (:func:`~supcoord.study.results.results_rows`) to ``out_dir``; their paths.

    Each figure is written atomically and never over one of ``inputs`` (the database, the
    study file) nor through a link (:func:`supcoord.outputs.atomic_output`)."""
    import matplotlib.pyplot as plt

    out = check_output_dir(out_dir)
    inputs = list(inputs)
    names = [METRICS[m][0] for m in METRICS] + ["verdicts", "quality"]
    for name in names:  # every file checked before any is drawn
        check_output(out / f"{name}.{fmt}", inputs, "out")
    figures = [(METRICS[m][0], lambda m=m: figure_metric(rows, m)) for m in METRICS]
    figures += [("verdicts", lambda: figure_verdicts(rows)), ("quality", lambda: figure_quality(rows))]
    paths = []
    for name, draw in figures:
        path = out / f"{name}.{fmt}"
        fig = draw()
        try:
            with atomic_output(path, inputs=inputs, what="out") as tmp:
                fig.savefig(tmp, dpi=dpi, format=fmt)
        finally:
            plt.close(fig)
        paths.append(path)
    return paths


def check_output_dir(out_dir: str | Path) -> Path:
    """``out_dir`` created if missing; an :class:`InputError` if it is a link or not a directory."""
    if not isinstance(out_dir, (str, os.PathLike)) or not os.fspath(out_dir):
        raise InputError(f"must be a folder name, got {out_dir!r:.80}", value=out_dir, where="out")
    out = Path(out_dir)
    if out.is_symlink() or (out.exists() and not out.is_dir()):
        raise InputError(f"{str(out)!r} is not a folder (a file or a link)", value=str(out), where="out")
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"cannot create the folder {str(out)!r}: {exc.strerror or exc}", value=str(out),
                         where="out") from None
    return out
