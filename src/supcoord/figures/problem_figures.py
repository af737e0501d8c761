"""Figures (matplotlib, no network): layouts, configurations, plans, collisions.

The Agg backend is selected on import (files only, no display needed), except inside
a Jupyter kernel, whose inline backend shows the figures :func:`plot_problem` returns.

Every drawing uses the same visual language, explained by a legend:

- base ``+`` with its number, patrol disc (grey circle of radius ``reach``);
- the colliding segment (rotary arm, or alpha-beta's beta arm) drawn as the *capsule*
  ``{x : dist(x, S) ≤ r}`` of its buffer ``r``, so two capsules overlap exactly when the
  two positioners collide; alpha-beta's alpha arm as a thin dark line;
- the target as a dashed green arm and a green ``×`` at the target fibre position;
- positioners in collision in red, positioners named by an infeasibility certificate in
  orange.

:func:`plot_problem` / :func:`save_problem_figure` draw a problem (start and target);
:mod:`supcoord.figures.plan_figures` draws plans (strip of frames, animated GIF, collision
incidents); :mod:`supcoord.figures` exports both.
"""

from __future__ import annotations

import io
import sys
from pathlib import Path
from typing import Any, Iterable

import matplotlib

if "ipykernel" not in sys.modules:  # headless everywhere but in Jupyter, which keeps its inline backend
    matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import LineCollection, PatchCollection, PolyCollection  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.patches import Circle  # noqa: E402

from ..errors import InputError  # noqa: E402
from ..geometry.collision import placed_segments  # noqa: E402
from ..geometry.kinematics import Kinematics  # noqa: E402
from ..outputs import atomic_output  # noqa: E402
from ..problems.consistency import check_problem  # noqa: E402
from ..problems.problem import Problem  # noqa: E402

__all__ = ["capsule", "capsules", "arms", "plot_configuration", "plot_target", "plot_problem", "save_problem_figure", "draw_layout", "add_legend",
           "save_figure", "new_figure", "draw_obstacles", "obstacle_handles", "FIGURE_SUFFIXES", "COLORS"]

#: the colours of the visual language (module docstring)
COLORS = {"arm": "C0", "target": "C2", "collision": "C3", "certificate": "C1", "alpha": "0.25", "disc": "0.82"}
#: file types a figure can be written to (``.gif``: an animation where that makes sense)
FIGURE_SUFFIXES = (".png", ".pdf", ".svg", ".jpg", ".gif")
#: positioner numbers are drawn up to this many positioners
MAX_NUMBERED = 200
#: obstacle colours: fiducials (points) and guide cameras (segments)
OBSTACLE = {"fiducial": "0.15", "gfa": "0.45"}


def capsule(p0: Any, p1: Any, radius: float, n: int = 12) -> np.ndarray:
    """Outline ``(2n + 2, 2)`` of the points within ``radius`` of the segment ``[p0, p1]``."""
    p0, p1 = np.asarray(p0, float), np.asarray(p1, float)
    d = p1 - p0
    phi = np.arctan2(d[1], d[0]) if np.any(d) else 0.0
    a1 = phi - np.pi / 2 + np.linspace(0, np.pi, n + 1)  # around p1
    a0 = phi + np.pi / 2 + np.linspace(0, np.pi, n + 1)  # around p0
    return np.concatenate([p1 + radius * np.c_[np.cos(a1), np.sin(a1)], p0 + radius * np.c_[np.cos(a0), np.sin(a0)]])


def arms(kin: Kinematics, bases: np.ndarray, q: Any) -> tuple[np.ndarray, np.ndarray]:
    """(alpha links base → elbow, colliding segments) in the focal plane for positions ``q`` (N, J)."""
    seg = placed_segments(kin, bases, np.asarray(q, float))
    if kin.kind == "alpha-beta":
        return np.stack([bases, seg[:, 0]], axis=1), seg
    return np.zeros((0, 2, 2)), seg


def capsules(problem: Problem, seg: np.ndarray) -> list[np.ndarray]:
    """The buffer capsule outline of every colliding segment ``seg`` (N, 2, 2)."""
    return [capsule(s[0], s[1], problem.buffers[p]) for p, s in enumerate(seg)]


def _colors(n: int, color: str, highlight: Any) -> list[str]:
    """Per-positioner colours: ``highlight`` is a set of indices (collision red) or a dict index → colour."""
    out = [color] * n
    items = highlight.items() if isinstance(highlight, dict) else ((int(h), COLORS["collision"]) for h in highlight)
    for p, c in items:
        if 0 <= int(p) < n:
            out[int(p)] = c
    return out


def plot_configuration(ax: Any, problem: Problem, positions: Any, *, color: str = COLORS["arm"], alpha: float = 0.35,
                       linestyle: str = "-", label: str | None = None, highlight: Any = ()) -> dict[str, Any]:
    """Draw one configuration: alpha links, each colliding segment with its buffer capsule, fibres.

    ``highlight``: indices drawn in red (collisions), or a dict ``{index: colour}``.
    Returns the artists (``links``, ``capsules``, ``segments``, ``fibres``) so that an
    animation can update them in place.
    """
    kin, bases = problem.kinematics, problem.bases
    links, seg = arms(kin, bases, positions)
    colors = _colors(problem.n, color, highlight)
    out: dict[str, Any] = {}
    if kin.kind == "alpha-beta":
        out["links"] = ax.add_collection(LineCollection(links, colors=COLORS["alpha"], linewidths=1.0,
                                                        linestyles=linestyle))
    out["capsules"] = ax.add_collection(PolyCollection(capsules(problem, seg), facecolors=colors, edgecolors=colors,
                                                       alpha=alpha, linestyles=linestyle, linewidths=0.8))
    out["segments"] = ax.add_collection(LineCollection(seg, colors=colors, linewidths=1.2, linestyles=linestyle,
                                                       label=label))
    out["fibres"] = ax.scatter(seg[:, 1, 0], seg[:, 1, 1], s=6, c=colors, zorder=3)
    return out


def draw_layout(ax: Any, problem: Problem, title: str | None = None, numbers: bool | None = None,
                focus: Any = None) -> None:
    """Patrol discs, bases and their numbers, fixed obstacles (:func:`draw_obstacles`), equal
    axes in mm; ``focus`` = indices to zoom on."""
    bases, reach = problem.bases, problem.kinematics.reach
    ax.add_collection(PatchCollection([Circle(b, reach) for b in bases], facecolors="none",
                                      edgecolors=COLORS["disc"], linewidths=0.6))
    ax.plot(bases[:, 0], bases[:, 1], "k+", markersize=4)
    pad = reach + float(problem.buffers.max(initial=0.0)) + 1.0
    shown = bases if focus is None or len(focus) == 0 else bases[np.asarray(list(focus), int)]
    lo, hi = shown.min(axis=0) - pad, shown.max(axis=0) + pad
    obs = np.asarray(problem.obstacles, float).reshape(-1, 2)
    if (focus is None or len(focus) == 0) and len(obs):  # the whole layout: its obstacles in view too
        margin = float(np.max(problem.obstacle_buffers, initial=0.0)) + 1.0
        lo, hi = np.minimum(lo, obs.min(axis=0) - margin), np.maximum(hi, obs.max(axis=0) + margin)
    if numbers is None:
        numbers = problem.n <= MAX_NUMBERED
    if numbers:
        inside = np.all((bases >= lo - pad) & (bases <= hi + pad), axis=1)
        for p in np.nonzero(inside)[0]:
            ax.annotate(str(p), bases[p], textcoords="offset points", xytext=(2, -8), fontsize=6, color="0.3")
    draw_obstacles(ax, problem)
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_aspect("equal")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    if title:
        ax.set_title(title, fontsize=9)


def _kinds(problem: Problem) -> tuple[np.ndarray, np.ndarray]:
    """Masks of the point obstacles (fiducials) and segment obstacles (guide cameras)."""
    obs = np.asarray(problem.obstacles, float).reshape(-1, 2, 2)
    points = np.all(np.isclose(obs[:, 0], obs[:, 1]), axis=1)
    return points, ~points


def draw_obstacles(ax: Any, problem: Problem) -> dict[str, Any]:
    """Draw the fixed obstacles with their buffers (module docstring); the artists by kind."""
    obs = np.asarray(problem.obstacles, float).reshape(-1, 2, 2)
    if not len(obs):
        return {}
    buffers = np.asarray(problem.obstacle_buffers, float)
    points, segments = _kinds(problem)
    out: dict[str, Any] = {}
    if points.any():
        out["fiducials"] = ax.add_collection(PatchCollection(
            [Circle(o[0], r) for o, r in zip(obs[points], buffers[points])], facecolors="0.85",
            edgecolors=OBSTACLE["fiducial"], linewidths=0.5, zorder=1, label="fiducial"))
        ax.plot(obs[points, 0, 0], obs[points, 0, 1], ".", color=OBSTACLE["fiducial"], ms=2.5, zorder=2)
    if segments.any():
        out["gfas"] = ax.add_collection(PolyCollection(
            [capsule(o[0], o[1], r) for o, r in zip(obs[segments], buffers[segments])], facecolors="0.7",
            edgecolors=OBSTACLE["gfa"], linewidths=0.8, zorder=1, label="guide camera (GFA)"))
    return out


def obstacle_handles(problem: Problem) -> list[Line2D]:
    """Legend entries for the obstacles the problem has."""
    points, segments = _kinds(problem)
    out = []
    if points.any():
        out.append(Line2D([], [], color=OBSTACLE["fiducial"], marker="o", mfc="0.85", ls="", label="fiducial"))
    if segments.any():
        out.append(Line2D([], [], color="0.7", lw=5, solid_capstyle="round", label="guide camera (GFA)"))
    return out


def plot_target(ax: Any, problem: Problem) -> None:
    """The target: dashed faint arms and capsules, and a green × at each target fibre position."""
    plot_configuration(ax, problem, problem.target, color=COLORS["target"], linestyle="--", alpha=0.12)
    fibres = problem.kinematics.fibre(problem.target.astype(float)) + problem.bases
    ax.plot(fibres[:, 0], fibres[:, 1], "x", color=COLORS["target"], markersize=5, mew=1.2, zorder=4)


def add_legend(target: Any, kind: str, extra: Iterable[str] = (), problem: Problem | None = None,
               **kwargs: Any) -> Any:
    """Legend of the visual language on an axes or a figure; ``extra`` ⊆ {"collision", "certificate"};
    with ``problem``, its kinds of fixed obstacles too."""
    beta = "beta arm" if kind == "alpha-beta" else "arm"
    handles = [Line2D([], [], color=COLORS["arm"], lw=5, alpha=0.45, solid_capstyle="round",
                      label=f"{beta} + buffer (capsule)")]
    if kind == "alpha-beta":
        handles.append(Line2D([], [], color=COLORS["alpha"], lw=1, label="alpha arm"))
    handles += [Line2D([], [], color=COLORS["target"], lw=1.2, ls="--", label="target arm"),
                Line2D([], [], color=COLORS["target"], marker="x", ls="", label="target fibre"),
                Line2D([], [], color="k", marker="+", ls="", label="base"),
                Line2D([], [], color=COLORS["disc"], marker="o", mfc="none", ls="", markersize=9, label="patrol disc")]
    names = {"collision": "in collision", "certificate": "cannot all reach target"}
    for key in extra:
        handles.append(Line2D([], [], color=COLORS[key], lw=5, alpha=0.6, solid_capstyle="round", label=names[key]))
    if problem is not None:
        handles += obstacle_handles(problem)
    kwargs.setdefault("fontsize", 7)
    return target.legend(handles=handles, **kwargs)


def _figsize(problem: Problem, base: float = 5.0) -> tuple[float, float]:
    span = np.ptp(problem.bases, axis=0) + 2 * problem.kinematics.reach if problem.n else np.ones(2)
    side = min(12.0, base + 0.35 * np.sqrt(problem.n))
    ratio = float(np.clip(span[1] / max(span[0], 1e-9), 0.5, 2.0))
    return (side, side * ratio)


def new_figure(problem: Problem, base: float = 5.0, legend_width: float = 1.9) -> tuple[Any, Any]:
    """A figure with one axes sized to the layout and ``legend_width`` inches on its right for the legend.

    The axes is placed explicitly (margins in inches for the labels and the title), so
    the geometry does not change between frames of an animation.
    """
    w, h = _figsize(problem, base)
    left, bottom, top, right = 0.75, 0.55, 0.4, legend_width + 0.15
    fig = plt.figure(figsize=(w + left + right, h + bottom + top))
    ax = fig.add_axes((left / (w + left + right), bottom / (h + bottom + top), w / (w + left + right),
                       h / (h + bottom + top)))
    return fig, ax


def plot_problem(problem: Problem, ax: Any = None, *, show_target: bool = True, highlight: Any = (),
                 title: str | None = None, legend: bool = True) -> Any:
    """Layout with patrol discs and numbers, the start (solid), the target (dashed, ×), a legend.

    ``highlight``: indices in red, or a dict ``{index: colour}`` (e.g. an infeasibility
    certificate in ``COLORS["certificate"]``).
    """
    check_problem(problem)
    if ax is None:
        _, ax = new_figure(problem)
    name = (problem.layout or {}).get("name") if isinstance(problem.layout, dict) else None
    draw_layout(ax, problem, title or f"{name + ', ' if name else ''}{problem.n} positioners, "
                f"{problem.kinematics.kind}: start and target")
    if show_target:
        plot_target(ax, problem)
    plot_configuration(ax, problem, problem.start, highlight=highlight)
    if legend:
        values = highlight.values() if isinstance(highlight, dict) else [COLORS["collision"]] * len(list(highlight))
        extra = [k for k in ("collision", "certificate") if COLORS[k] in set(values)]
        add_legend(ax, problem.kinematics.kind, extra, problem, loc="upper left", bbox_to_anchor=(1.02, 1.0),
                   borderaxespad=0.0)
    return ax


def save_figure(fig: Any, path: str | Path, dpi: int = 120, tight: bool = True) -> Path:
    """Write ``fig`` by extension (``.gif`` through Pillow, as one frame) and close it."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in FIGURE_SUFFIXES:
        plt.close(fig)
        raise InputError(f"a figure is written as {', '.join(FIGURE_SUFFIXES)}, got {path}", value=str(path))
    if tight:
        fig.tight_layout()
    try:
        with atomic_output(path) as tmp:
            if suffix == ".gif":
                from PIL import Image

                buf = io.BytesIO()
                fig.savefig(buf, format="png", dpi=dpi)
                Image.open(buf).convert("RGB").quantize(colors=128).save(tmp, format="GIF")
            else:
                fig.savefig(tmp, dpi=dpi, format=suffix[1:])
    finally:
        plt.close(fig)
    return path


def save_problem_figure(problem: Problem, path: str | Path, dpi: int = 120, **kwargs: Any) -> Path:
    """Write :func:`plot_problem` to ``path`` (PNG, SVG, PDF, JPG or a one-frame GIF by extension)."""
    ax = plot_problem(problem, **kwargs)
    return save_figure(ax.figure, path, dpi, tight=False)

