"""Figures: layout PNG, plan strip PNG and animated GIF are written and non-empty."""

import numpy as np
from PIL import Image

from supcoord.positioners import Plan, preset_problem, random_problem
from supcoord.positioners.figures import capsule, save_plan_gif, save_plan_strip, save_problem_figure


def _plan(problem):
    mid = problem.start.copy()
    return Plan("complete", [problem.start, mid, problem.target])


def test_layout_png(tmp_path):
    p = preset_problem("sdss-v", rings=2, seed=0)
    out = save_problem_figure(p, tmp_path / "layout.png")
    assert out.stat().st_size > 1000
    assert Image.open(out).format == "PNG"


def test_rotary_layout_and_plan_figures(tmp_path):
    p = random_problem({"kind": "hex", "rings": 1, "pitch": 22.4}, {"kind": "rotary", "arm": 15.0, "steps": 12}, 2.0, 0)
    assert save_problem_figure(p, tmp_path / "rot.png").stat().st_size > 1000
    strip = save_plan_strip(p, _plan(p), tmp_path / "strip.png")
    assert strip.stat().st_size > 1000 and Image.open(strip).format == "PNG"
    gif = save_plan_gif(p, _plan(p), tmp_path / "plan.gif", substeps=2)
    img = Image.open(gif)
    assert img.format == "GIF" and img.n_frames >= 3


def test_capsule_outline_is_at_buffer_distance():
    outline = capsule([0, 0], [10, 0], 2.0)
    # every outline point is exactly 2 mm from the segment
    x = np.clip(outline[:, 0], 0, 10)
    assert np.allclose(np.hypot(outline[:, 0] - x, outline[:, 1]), 2.0)
