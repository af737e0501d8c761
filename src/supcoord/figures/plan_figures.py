"""Figures of plans: a strip of frames, an animated GIF, the collisions a validator found.

A plan ``c_0, …, c_T`` is drawn as the validator sees it: step ``k`` moves every joint
linearly in joint space, ``c_k + t·Δ_k`` for ``t ∈ [0, 1]`` (``Δ_k`` the short way round
where a joint wraps), and :func:`interpolate_plan` samples ``substeps`` poses per step.
Positioners that collide in a drawn pose (static check of :mod:`supcoord.geometry.collision`) are red,
so drawing an invalid plan shows where it fails.

- :func:`save_plan_strip`: up to ``max_frames`` evenly spaced configurations on a grid
  of panels (first and last included) with one legend;
- :func:`save_plan_gif`: an animated GIF written frame by frame with Pillow (the static
  layout drawn once and blitted, the arms updated in place; one shared palette without
  dithering, so unchanged pixels stay identical and each frame stores only what
  moved), the first and last frames held longer;
- :func:`save_incidents_figure`: one zoomed panel per collision incident of
  :func:`~supcoord.problems.validate.validate_plan` (the pose at the incident's time, the pair in red);
- :func:`save_plan_figure`: what ``supcoord solve/check --figure FILE`` writes (past
  :data:`~.wok.OVERVIEW_ABOVE` robots, the overview of :mod:`.wok` instead of the strip).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Callable

import numpy as np

from ..errors import InputError
from ..outputs import atomic_output
from ..problems.consistency import check_plan, check_problem
from ..problems.plan import Plan
from ..problems.problem import Problem
from ..problems.refine import at_lattice
from ..problems.validate import ValidationResult
from .problem_figures import (
    COLORS,
    FIGURE_SUFFIXES,
    _figsize,
    add_legend,
    arms,
    capsules,
    draw_layout,
    new_figure,
    plot_configuration,
    plot_problem,
    plot_target,
    plt,
    save_figure,
)
from .wok_overview import OVERVIEW_ABOVE, plan_title, save_plan_overview

__all__ = ["interpolate_plan", "save_plan_strip", "save_plan_gif", "save_incidents_figure", "save_plan_figure",
           "MAX_GIF_FRAMES"]

#: an animation longer than this samples fewer substeps per step (at least one)
MAX_GIF_FRAMES = 600


def _steps(problem: Problem, plan: Plan) -> list[tuple[np.ndarray, np.ndarray]]:
    """``(c_k, Δ_k)`` per step, ``Δ`` the short way round, clipped to one step per joint."""
    kin = problem.kinematics
    confs = plan.configurations
    return [(np.asarray(confs[k], float), np.clip(kin.signed_delta(confs[k], confs[k + 1]), -1, 1))
            for k in range(len(confs) - 1)]


def interpolate_plan(problem: Problem, plan: Plan, substeps: int = 4) -> list[np.ndarray]:
    """Float configurations along the plan, ``substeps`` per step (joint-space interpolation)."""
    if not plan.configurations:
        return [problem.start.astype(float)]
    if substeps < 1:
        raise InputError(f"substeps must be >= 1, got {substeps}", value=substeps)
    out = [c + delta * (s / substeps) for c, delta in _steps(problem, plan) for s in range(substeps)]
    out.append(np.asarray(plan.configurations[-1], float))
    return out


def _colliding(problem: Problem, q: np.ndarray) -> set[int]:
    return {p for a, b, _ in problem.collisions(q) for p in (a, b)}


def checked(problem: Problem, plan: Plan) -> None:
    """Refuse (:class:`InputError`) an inconsistent problem, or a plan that is malformed or of another problem."""
    check_problem(problem)
    if not isinstance(plan, Plan):
        raise InputError(f"plan must be a Plan, got {type(plan).__name__}", value=None, where="plan")
    check_plan(plan, problem)


def save_plan_strip(problem: Problem, plan: Plan, path: str | Path, max_frames: int = 8, dpi: int = 100,
                    columns: int = 4, progress: Callable[[str, dict], None] | None = None) -> Path:
    """Evenly spaced configurations of the plan (first and last included), ``columns`` panels a
    row, under a title naming the instrument and the plan; ``progress`` hears of each panel."""
    checked(problem, plan)
    confs = plan.configurations or [problem.start]
    idx = np.unique(np.linspace(0, len(confs) - 1, min(max_frames, len(confs))).round().astype(int))
    cols = min(columns, len(idx))
    rows = math.ceil(len(idx) / cols)
    w, h = _figsize(problem, 2.6)
    w, h = min(w, 4.5), min(h, 4.5)
    fig, axes = plt.subplots(rows, cols, figsize=(w * cols, h * rows + 1.0), squeeze=False)
    hit_any = False
    for i, (ax, k) in enumerate(zip(axes.ravel(), idx)):
        if progress is not None:
            progress("figure", {"done": i, "total": len(idx), "file": str(path)})
        q = np.asarray(confs[k])
        hits = _colliding(problem, q)
        hit_any |= bool(hits)
        draw_layout(ax, problem, f"step {k} of {len(confs) - 1}", numbers=problem.n <= 40)
        plot_target(ax, problem)
        plot_configuration(ax, problem, q, highlight=hits)
        if i % cols:  # mm labels on the first column and the last row only
            ax.set_ylabel("")
        if i < len(idx) - cols:
            ax.set_xlabel("")
    for ax in axes.ravel()[len(idx):]:
        ax.set_axis_off()
    fig.suptitle(plan_title(problem, plan), fontsize=10)
    fig.tight_layout(rect=(0, 0.45 / fig.get_figheight(), 1, 1))  # the legend's row at the bottom
    add_legend(fig, problem.kinematics.kind, ["collision"] if hit_any else [], problem, loc="lower center", ncol=9,
               frameon=False)
    return save_figure(fig, path, dpi, tight=False)


def save_plan_gif(problem: Problem, plan: Plan, path: str | Path, substeps: int = 4, fps: int = 10,
                  dpi: int = 80, hold: float = 0.8, progress: Callable[[str, dict], None] | None = None) -> Path:
    """An animated GIF of the plan, ``substeps`` interpolated frames a step (module docstring).

    Positioners colliding in a frame are red.  ``hold`` seconds on the first and the last
    frame.  Plans longer than :data:`MAX_GIF_FRAMES` frames get fewer substeps.  ``progress``
    hears of each frame drawn.
    """
    checked(problem, plan)
    from PIL import Image

    if Path(path).suffix.lower() != ".gif":
        raise InputError(f"an animation is written as .gif, got {path}", value=str(path))
    if not 1 <= fps <= 100:
        raise InputError(f"fps must be in [1, 100], got {fps}", value=fps)
    steps = max(1, len(plan.configurations) - 1)
    substeps = max(1, min(substeps, MAX_GIF_FRAMES // steps))
    frames = interpolate_plan(problem, plan, substeps)
    kin, bases = problem.kinematics, problem.bases
    fig, ax = new_figure(problem, 4.0, legend_width=1.6)
    draw_layout(ax, problem, numbers=problem.n <= 60)
    plot_target(ax, problem)
    art = plot_configuration(ax, problem, frames[0])
    box = ax.get_position()
    title = fig.text((box.x0 + box.x1) / 2, box.y1 + 0.01, " ", ha="center", va="bottom", fontsize=9)
    add_legend(ax, kin.kind, ["collision"], problem, loc="upper left", bbox_to_anchor=(1.02, 1.0),
               borderaxespad=0.0, fontsize=6)
    fig.text(0.01, 0.995, plan_title(problem, plan), ha="left", va="top", fontsize=8)
    dynamic = [a for a in (art.get("links"), art["capsules"], art["segments"], art["fibres"], title) if a is not None]

    def render(q: np.ndarray, label: str, red: set[int] | None = None) -> Image.Image:
        links, seg = arms(kin, bases, q)
        hits = _colliding(problem, q) if red is None else red
        colors = [COLORS["collision"] if p in hits else COLORS["arm"] for p in range(problem.n)]
        if "links" in art:
            art["links"].set_segments(links)
        art["capsules"].set_verts(capsules(problem, seg))
        art["capsules"].set_facecolor(colors)
        art["capsules"].set_edgecolor(colors)
        art["segments"].set_segments(seg)
        art["segments"].set_color(colors)
        art["fibres"].set_offsets(seg[:, 1])
        art["fibres"].set_color(colors)
        title.set_text(label)
        fig.canvas.restore_region(background)  # blitting: the static layout is drawn once
        for a in dynamic:
            fig.draw_artist(a)
        return Image.fromarray(np.array(fig.canvas.buffer_rgba())[..., :3])

    for a in dynamic:
        a.set_visible(False)
    fig.canvas.draw()
    background = fig.canvas.copy_from_bbox(fig.bbox)
    for a in dynamic:
        a.set_visible(True)
    # one palette for every frame (the first pose, blue and all red), so unchanged pixels stay
    # identical from frame to frame and the GIF stores only the changed rectangles
    first, red = render(frames[0], ""), render(frames[0], "", set(range(problem.n)))
    swatch = Image.new("RGB", (first.width * 2, first.height))
    swatch.paste(first, (0, 0))
    swatch.paste(red, (first.width, 0))
    palette = swatch.quantize(colors=96, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE)
    total = (len(frames) - 1) / substeps
    images = []
    for i, q in enumerate(frames):
        if progress is not None:
            progress("figure", {"done": i, "total": len(frames), "file": str(path)})
        images.append(render(q, f"step {i / substeps:.2f} of {total:g}").quantize(palette=palette,
                                                                                 dither=Image.Dither.NONE))
    plt.close(fig)
    ms = int(round(1000 / fps))
    durations = [ms] * len(images)
    durations[0] = durations[-1] = max(ms, int(hold * 1000))
    with atomic_output(path) as tmp:
        images[0].save(tmp, format="GIF", save_all=True, append_images=images[1:], duration=durations, loop=0)
    return Path(path)


def save_incidents_figure(problem: Problem, plan: Plan, result: ValidationResult, path: str | Path,
                          max_panels: int = 6, dpi: int = 110) -> Path:
    """One panel per collision incident of the validator's ``result`` (zoomed on the pair).

    At most ``max_panels``: the first incident of every colliding pair before repeats.
    """
    checked(problem, plan)
    listed = list(result.incidents)
    # the first incident of each pair first (a pair often collides over several steps), then the rest
    seen: set[tuple[int, int]] = set()
    first = [i for i, inc in enumerate(listed)
             if tuple(inc.positioners) not in seen and not seen.add(tuple(inc.positioners))]
    order = first + [i for i in range(len(listed)) if i not in set(first)]
    incidents = [listed[i] for i in sorted(order[:max_panels])]
    if not incidents:
        raise InputError("the validation found no collision to draw", value=result.collisions)
    steps = _steps(problem, plan)
    cols = min(3, len(incidents))
    rows = math.ceil(len(incidents) / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(3.8 * cols, 3.8 * rows + 0.5), squeeze=False)
    for ax, inc in zip(axes.ravel(), incidents):
        k, (a, b), t = int(inc.step), inc.positioners, float(inc.t)
        c, delta = steps[k] if k < len(steps) else (np.asarray(plan.configurations[k], float), 0.0)
        q = c + t * delta
        where = f"step {k}->{k + 1}, t = {t:.2f}" if steps else "configuration 0"
        draw_layout(ax, problem, f"{where}: {a} & {b}\n{inc.distance:.2f} mm < {inc.required:.2f} mm",
                    numbers=True, focus=[a, b])
        plot_target(ax, problem)
        plot_configuration(ax, problem, q, highlight={a: COLORS["collision"], b: COLORS["collision"]})
    for ax in axes.ravel()[len(incidents):]:
        ax.set_axis_off()
    more = result.collisions - len(incidents)
    fig.suptitle(f"{result.collisions} collision incident(s)" + (f", first {len(incidents)} shown"
                                                                          if more > 0 else ""), fontsize=10)
    fig.tight_layout(rect=(0, 0.45 / fig.get_figheight(), 1, 1))  # the legend's row at the bottom
    add_legend(fig, problem.kinematics.kind, ["collision"], loc="lower center", ncol=7, frameon=False)
    return save_figure(fig, path, dpi, tight=False)


def save_plan_figure(problem: Problem, plan: Plan, path: str | Path, result: ValidationResult | None = None,
                     progress: Callable[[str, dict], None] | None = None) -> Path:
    """The ``--figure`` of ``supcoord solve``/``check``, by extension and by what there is to show.

    ``.gif``: the animation (a plan with configurations); otherwise a strip of frames, or
    — given a validator ``result`` with collisions — the incidents.  A plan without
    configurations (infeasible, unknown) draws the problem, the positioners of an
    infeasibility certificate (``stats["certificate"]``) in orange.  Past
    :data:`~.wok.OVERVIEW_ABOVE` robots a still figure is the overview
    (:func:`~.wok.save_plan_overview`) instead of the strip.  ``progress(stage, info)`` hears
    how far the drawing is (``done`` of ``total`` frames or panels).
    """
    checked(problem, plan)
    suffix = Path(path).suffix.lower()
    if suffix not in FIGURE_SUFFIXES:
        raise InputError(f"--figure must end in {', '.join(FIGURE_SUFFIXES)}, got {path}", value=str(path))
    if not plan.configurations:
        cert = [int(p) for p in (plan.stats or {}).get("certificate", []) if isinstance(p, int)]
        title = (f"{plan.status}: positioners {', '.join(map(str, cert))} cannot all reach their targets"
                 if cert else f"plan {plan.status}: start and target")
        ax = plot_problem(problem, highlight={p: COLORS["certificate"] for p in cert}, title=title)
        return save_figure(ax.figure, path, tight=False)
    if plan.lattice is not None and tuple(plan.lattice) != problem.kinematics.shape:
        problem = at_lattice(problem, plan.lattice)  # planned on a finer lattice (supcoord.problems.refine)
    if suffix == ".gif":
        return save_plan_gif(problem, plan, path, progress=progress)
    if result is not None and result.incidents:
        return save_incidents_figure(problem, plan, result, path)
    if problem.n > OVERVIEW_ABOVE:
        return save_plan_overview(problem, plan, path, progress=progress)
    return save_plan_strip(problem, plan, path, progress=progress)
