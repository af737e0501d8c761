"""Figures (matplotlib, Agg backend outside Jupyter): problems, plans, animations, collisions.

:mod:`.problem_figures` draws a layout with start and target arms; :mod:`.plan_figures` draws plans (a
strip of frames, an animated GIF, the collision incidents a validator found).  Importing
this package imports matplotlib.
"""

from .plan_figures import interpolate_plan, save_incidents_figure, save_plan_figure, save_plan_gif, save_plan_strip
from .wok_overview import plan_title, save_plan_overview
from .problem_figures import (
    add_legend,
    arms,
    capsule,
    capsules,
    draw_layout,
    plot_configuration,
    plot_problem,
    plot_target,
    save_problem_figure,
)

__all__ = [
    "add_legend",
    "arms",
    "capsule",
    "capsules",
    "draw_layout",
    "interpolate_plan",
    "plot_configuration",
    "plot_problem",
    "plan_title",
    "plot_target",
    "save_incidents_figure",
    "save_plan_figure",
    "save_plan_gif",
    "save_plan_overview",
    "save_plan_strip",
    "save_problem_figure",
]
