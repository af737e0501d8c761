"""Figures (matplotlib, Agg backend, no network): layouts, configurations, plans.

- :func:`plot_configuration`: bases, reach circles, the arms, and the colliding segment
  drawn as the capsule ``{x : dist(x, S) ≤ r}`` of its buffer ``r`` (so two capsules
  overlap exactly when the two positioners collide).
- :func:`plot_problem` / :func:`save_problem_figure`: start (solid) and target (dashed).
- :func:`save_plan_strip`: a strip of frames of a plan; :func:`save_plan_gif`: an
  animated GIF (``matplotlib.animation.PillowWriter``), each step interpolated in
  joint space as the validator does.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.animation import FuncAnimation, PillowWriter  # noqa: E402
from matplotlib.collections import LineCollection, PatchCollection  # noqa: E402
from matplotlib.patches import Circle, Polygon  # noqa: E402

from ..errors import InputError  # noqa: E402
from .kinematics import Kinematics  # noqa: E402
from .plan import Plan  # noqa: E402
from .problem import Problem  # noqa: E402

__all__ = ["capsule", "plot_configuration", "plot_problem", "save_problem_figure", "save_plan_strip",
           "save_plan_gif", "interpolate_plan"]


def capsule(p0: Any, p1: Any, radius: float, n: int = 12) -> np.ndarray:
    """Outline ``(2n + 2, 2)`` of the points within ``radius`` of the segment ``[p0, p1]``."""
    p0, p1 = np.asarray(p0, float), np.asarray(p1, float)
    d = p1 - p0
    phi = np.arctan2(d[1], d[0]) if np.any(d) else 0.0
    a1 = phi - np.pi / 2 + np.linspace(0, np.pi, n + 1)  # around p1
    a0 = phi + np.pi / 2 + np.linspace(0, np.pi, n + 1)  # around p0
    return np.concatenate([p1 + radius * np.c_[np.cos(a1), np.sin(a1)], p0 + radius * np.c_[np.cos(a0), np.sin(a0)]])


def _arms(kin: Kinematics, bases: np.ndarray, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(non-colliding links, colliding segments) in the focal plane for positions ``q`` (N, J)."""
    seg = kin.segments(q) + bases[:, None, :]
    if kin.kind == "alpha-beta":
        links = np.stack([bases, seg[:, 0]], axis=1)  # base → elbow
    else:
        links = np.zeros((0, 2, 2))
    return links, seg


def plot_configuration(ax: Any, problem: Problem, positions: Any, *, color: str = "C0", alpha: float = 0.35,
                       linestyle: str = "-", label: str | None = None, highlight: Any = ()) -> None:
    """Draw one configuration: arms, and each colliding segment with its buffer capsule."""
    kin, bases = problem.kinematics, problem.bases
    links, seg = _arms(kin, bases, np.asarray(positions, float))
    if len(links):
        ax.add_collection(LineCollection(links, colors="0.35", linewidths=1.0, linestyles=linestyle))
    hl = set(int(h) for h in highlight)
    patches = [Polygon(capsule(s[0], s[1], problem.buffers[p]), closed=True) for p, s in enumerate(seg)]
    colors = ["C3" if p in hl else color for p in range(len(seg))]
    ax.add_collection(PatchCollection(patches, facecolors=colors, edgecolors=colors, alpha=alpha,
                                      linestyles=linestyle, linewidths=0.8))
    ax.add_collection(LineCollection(seg, colors=colors, linewidths=1.2, linestyles=linestyle, label=label))
    ax.plot(seg[:, 1, 0], seg[:, 1, 1], "o", color=color, markersize=2.5)


def _frame(ax: Any, problem: Problem, title: str | None = None, numbers: bool = True) -> None:
    bases, reach = problem.bases, problem.kinematics.reach
    ax.add_collection(PatchCollection([Circle(b, reach) for b in bases], facecolors="none", edgecolors="0.8",
                                      linewidths=0.6))
    ax.plot(bases[:, 0], bases[:, 1], "k+", markersize=4)
    if numbers and problem.n <= 100:
        for p, (x, y) in enumerate(bases):
            ax.annotate(str(p), (x, y), textcoords="offset points", xytext=(2, -8), fontsize=6, color="0.3")
    pad = reach + float(problem.buffers.max(initial=0.0)) + 1.0
    ax.set_xlim(bases[:, 0].min() - pad, bases[:, 0].max() + pad)
    ax.set_ylim(bases[:, 1].min() - pad, bases[:, 1].max() + pad)
    ax.set_aspect("equal")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    if title:
        ax.set_title(title, fontsize=9)


def plot_problem(problem: Problem, ax: Any = None, *, show_target: bool = True) -> Any:
    """Layout with reach circles, the start (solid, blue) and the target (dashed, green)."""
    if ax is None:
        size = min(12.0, 4.0 + 0.25 * np.sqrt(problem.n) * 2)
        _, ax = plt.subplots(figsize=(size, size))
    _frame(ax, problem, f"{problem.n} positioners, {problem.kinematics.kind}: start (solid), target (dashed)")
    plot_configuration(ax, problem, problem.start, color="C0", label="start")
    if show_target:
        plot_configuration(ax, problem, problem.target, color="C2", linestyle="--", alpha=0.15, label="target")
    return ax


def save_problem_figure(problem: Problem, path: str | Path, dpi: int = 120) -> Path:
    """Write :func:`plot_problem` to ``path`` (PNG, SVG or PDF by extension)."""
    ax = plot_problem(problem)
    fig = ax.figure
    fig.tight_layout()
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
    return Path(path)


def interpolate_plan(problem: Problem, plan: Plan, substeps: int = 4) -> list[np.ndarray]:
    """Float configurations along the plan, ``substeps`` per step (joint-space interpolation)."""
    if not plan.configurations:
        return [problem.start.astype(float)]
    kin = problem.kinematics
    out = []
    confs = plan.configurations
    for k in range(len(confs) - 1):
        delta = kin.signed_delta(confs[k], confs[k + 1])
        for s in range(substeps):
            out.append(confs[k] + delta * (s / substeps))
    out.append(np.asarray(confs[-1], float))
    return out


def save_plan_strip(problem: Problem, plan: Plan, path: str | Path, max_frames: int = 8, dpi: int = 100) -> Path:
    """A row of frames (evenly spaced configurations of the plan, first and last included)."""
    confs = plan.configurations or [problem.start]
    idx = np.unique(np.linspace(0, len(confs) - 1, min(max_frames, len(confs))).round().astype(int))
    fig, axes = plt.subplots(1, len(idx), figsize=(3.2 * len(idx), 3.4), squeeze=False)
    for ax, k in zip(axes[0], idx):
        _frame(ax, problem, f"step {k}/{len(confs) - 1}", numbers=False)
        plot_configuration(ax, problem, problem.target, color="C2", linestyle="--", alpha=0.1)
        plot_configuration(ax, problem, confs[k], color="C0")
        ax.set_xlabel("")
        ax.set_ylabel("")
    fig.tight_layout()
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
    return Path(path)


def save_plan_gif(problem: Problem, plan: Plan, path: str | Path, substeps: int = 3, fps: int = 8,
                  dpi: int = 80) -> Path:
    """An animated GIF of the plan (Pillow), each step in ``substeps`` interpolated frames."""
    if str(path).lower().endswith(".gif") is False:
        raise InputError(f"an animation is written as .gif, got {path}", value=str(path))
    frames = interpolate_plan(problem, plan, substeps)
    fig, ax = plt.subplots(figsize=(5, 5))

    def draw(i: int) -> None:
        ax.clear()
        _frame(ax, problem, f"t = {i / substeps:.2f} / {len(frames) // substeps}", numbers=False)
        plot_configuration(ax, problem, problem.target, color="C2", linestyle="--", alpha=0.1)
        plot_configuration(ax, problem, frames[i], color="C0")

    anim = FuncAnimation(fig, draw, frames=len(frames), interval=1000 // fps)
    anim.save(str(path), writer=PillowWriter(fps=fps), dpi=dpi)
    plt.close(fig)
    return Path(path)
