"""Figures at the scale of a real wok: titles and a plan overview (the fixed obstacles,
fiducials and guide cameras, are drawn by :func:`.problem.draw_layout` in every figure).

- :func:`instrument_name` and :func:`plan_title`: what a title names (the instrument or
  layout, the plan's status, steps and motion time);
- :func:`save_plan_overview`: one readable figure of a large plan, what ``--figure`` draws
  past :data:`OVERVIEW_ABOVE` robots instead of a strip of 500-arm panels: on the left the
  wok at the target, each robot coloured by the number of steps it moves (grey: never),
  its start fibre joined to its target fibre; on the right a per-robot timeline (one row
  a robot, in order of its first move; a blue cell a step in which it moves) under the
  count of robots moving in each step.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Callable

import numpy as np
from matplotlib.collections import LineCollection
from matplotlib.colors import ListedColormap
from matplotlib.lines import Line2D

from ..problems.plan import Plan
from ..problems.problem import Problem
from .problem_figures import arms, draw_layout, draw_obstacles, obstacle_handles, plot_configuration, plt, save_figure

__all__ = ["OVERVIEW_ABOVE", "instrument_name", "plan_title", "save_plan_overview"]

#: above this many robots, ``--figure`` draws :func:`save_plan_overview` instead of a strip
OVERVIEW_ABOVE = 60


def instrument_name(problem: Problem) -> str:
    """``sdss-v-apo`` for an instrument layout, ``hex`` (or the preset) for the others."""
    layout = problem.layout if isinstance(problem.layout, dict) else {}
    preset = (problem.extra or {}).get("preset") if isinstance(problem.extra, dict) else None
    return str(layout.get("name") or preset or layout.get("kind") or "layout")


def plan_title(problem: Problem, plan: Plan) -> str:
    """``sdss-v-apo, 500 robots: plan complete, 22 steps (lower bound 12), motion 54.0 s``."""
    text = f"{instrument_name(problem)}, {problem.n} robots: plan {plan.status}"
    if plan.makespan is not None:
        text += f", {plan.makespan} steps"
        if plan.lower_bound is not None:
            text += f" (lower bound {plan.lower_bound})"
    if plan.motion_time_s is not None:
        text += f", motion {plan.motion_time_s:.1f} s"
    return text


def _moving(problem: Problem, plan: Plan) -> np.ndarray:
    """``(N, T)`` booleans: robot ``p`` moves in step ``k``."""
    confs = [np.asarray(c) for c in plan.configurations]
    if len(confs) < 2:
        return np.zeros((problem.n, 0), bool)
    return np.stack([np.any(b != a, axis=1) for a, b in zip(confs, confs[1:])], axis=1)


def save_plan_overview(problem: Problem, plan: Plan, path: str | Path, dpi: int = 110,
                       progress: Callable[[str, dict], None] | None = None) -> Path:
    """One figure of a large plan: the wok and a per-robot motion timeline (module docstring)."""
    def report(done: int) -> None:
        if progress is not None:
            progress("figure", {"done": done, "total": 3, "file": str(path)})

    report(0)
    moving = _moving(problem, plan)
    steps_moved = moving.sum(axis=1)
    fig = plt.figure(figsize=(15, 8.2))
    grid = fig.add_gridspec(2, 2, width_ratios=(1.15, 1), height_ratios=(1, 3.2), wspace=0.18, hspace=0.08,
                            left=0.06, right=0.97, bottom=0.1, top=0.9)
    ax = fig.add_subplot(grid[:, 0])
    draw_layout(ax, problem, "the wok at the target; colour: steps in motion", numbers=False)
    draw_obstacles(ax, problem)
    end = plan.configurations[-1] if plan.configurations else problem.target
    cmap = plt.get_cmap("viridis")
    top = max(int(steps_moved.max(initial=0)), 1)
    colors = [cmap(s / top) if s else (0.6, 0.6, 0.6, 1.0) for s in steps_moved]
    plot_configuration(ax, problem, end, color="C0", alpha=0.5, highlight=dict(enumerate(colors)))
    start_fibre = arms(problem.kinematics, problem.bases, np.asarray(problem.start, float))[1][:, 1]
    end_fibre = arms(problem.kinematics, problem.bases, np.asarray(end, float))[1][:, 1]
    ax.add_collection(LineCollection(np.stack([start_fibre, end_fibre], axis=1), colors="0.35", linewidths=0.5,
                                     linestyles=":"))
    ax.plot(start_fibre[:, 0], start_fibre[:, 1], "o", ms=1.5, color="0.35")
    report(1)
    sm = plt.cm.ScalarMappable(cmap=cmap, norm=plt.Normalize(0, top))
    fig.colorbar(sm, ax=ax, shrink=0.6, pad=0.01, label="steps in which the robot moves")
    handles = [Line2D([], [], color=cmap(0.6), lw=5, alpha=0.6, solid_capstyle="round", label="beta arm at the end"),
               Line2D([], [], color="0.6", lw=5, alpha=0.6, solid_capstyle="round", label="never moves"),
               Line2D([], [], color="0.35", ls=":", marker="o", ms=2, label="start fibre → end fibre"),
               *obstacle_handles(problem)]
    ax.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, -0.07), ncol=3, fontsize=7, frameon=False)
    count = fig.add_subplot(grid[0, 1])
    line = fig.add_subplot(grid[1, 1], sharex=count)
    T = moving.shape[1]
    count.bar(np.arange(T) + 0.5, moving.sum(axis=0), width=0.9, color="C0")
    count.set_ylabel("robots\nmoving")
    count.tick_params(labelbottom=False)
    count.set_title("per-robot motion timeline", fontsize=9)
    first = np.where(moving.any(axis=1), moving.argmax(axis=1), T)
    order = np.lexsort((-steps_moved, first))
    if T:
        line.imshow(moving[order], aspect="auto", interpolation="nearest", cmap=ListedColormap(["white", "C0"]),
                    extent=(0, T, len(order), 0))
    line.set_xlim(0, max(T, 1))
    line.set_xlabel("step")
    line.set_ylabel(f"robot (in order of its first move; {int(moving.any(axis=1).sum())} of {problem.n} move)")
    report(2)
    fig.suptitle(plan_title(problem, plan), fontsize=12)
    out = save_figure(fig, path, dpi, tight=False)
    report(3)
    return out
