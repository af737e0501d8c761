"""Figures: layout, strip of frames, animated GIF, collision incidents, infeasibility certificate.

The pictures are checked through their pixels: collisions are drawn in red (``C3``),
a certificate in orange (``C1``), so counting those hues tells whether a figure shows
what it should.
"""

import copy

import numpy as np
import pytest
from PIL import Image

from supcoord.errors import InputError
from supcoord.figures import (
    capsule,
    interpolate_plan,
    save_incidents_figure,
    save_plan_figure,
    save_plan_gif,
    save_plan_strip,
    save_problem_figure,
)
from supcoord.problems import Plan, parse_problem, preset_problem, random_problem, validate_plan
from supcoord.problems.plan import plan_from_moves

THREE = {
    "layout": {"kind": "points", "xy": [[0, 0], [22.4, 0], [44.8, 0]]},
    "kinematics": {"kind": "rotary", "arm": 15.0, "steps": 12},
    "collision": {"buffer": 2.0},
    "start": [0, 0, 0],
    "target": [6, 6, 6],
}


def _red(image):
    """Pixels of the collision red (C3, also half transparent on white): red clearly above green = blue."""
    r, g, b = np.moveaxis(np.asarray(image.convert("RGB"), float), -1, 0)
    return int(((r > 150) & (r - g > 40) & (np.abs(g - b) < 25)).sum())


def _orange(image):
    """Pixels of the certificate orange (C1): red high, green in between, blue well below green."""
    r, g, b = np.moveaxis(np.asarray(image.convert("RGB"), float), -1, 0)
    return int(((r > 200) & (g > 100) & (g < 215) & (g - b > 50) & (r - g > 25)).sum())


@pytest.fixture(scope="module")
def three():
    return parse_problem(copy.deepcopy(THREE))


def _colliding_plan(three):
    # 0 stands at +x while 1 turns backwards through pointing at 0; then everyone goes to target
    confs = [[0, -k % 12, 0] for k in range(7)] + [[k, 6, 0] for k in range(1, 7)] + [[6, 6, k] for k in range(1, 7)]
    return Plan("complete", [np.array(c).reshape(3, 1) for c in confs])


def _valid_plan(three):
    # 1 turns down out of the way, 2 and 0 turn round, 1 finishes: nobody meets
    moves = [(1, 0, 1)] * 3 + [(2, 0, 1)] * 6 + [(0, 0, 1)] * 6 + [(1, 0, 1)] * 3
    plan = plan_from_moves(three, moves, compact=False)
    assert validate_plan(three, plan).valid
    return plan


def test_layout_png(tmp_path):
    p = preset_problem("sdss-v", rings=2, seed=0, alpha_steps=12, beta_steps=7)
    out = save_problem_figure(p, tmp_path / "layout.png")
    img = Image.open(out)
    assert img.format == "PNG" and out.stat().st_size > 1000
    assert _red(img) == 0 and _orange(img) == 0  # nothing flagged


def test_interpolation_follows_the_short_way_round(three):
    plan = Plan("complete", [np.array([[11], [0], [0]]), np.array([[0], [0], [0]])])
    frames = interpolate_plan(three, plan, substeps=4)
    assert [round(float(f[0, 0]), 2) for f in frames] == [11.0, 11.25, 11.5, 11.75, 0.0]
    with pytest.raises(InputError, match="substeps"):
        interpolate_plan(three, plan, substeps=0)


@pytest.mark.slow  # renders two 55-frame animations: seconds
def test_gif_is_smooth_small_and_shows_collisions_in_red(tmp_path, three):
    good = save_plan_gif(three, _valid_plan(three), tmp_path / "good.gif", substeps=3)
    bad = save_plan_gif(three, _colliding_plan(three), tmp_path / "bad.gif", substeps=3)
    g, b = Image.open(good), Image.open(bad)
    assert g.format == b.format == "GIF" and g.n_frames == b.n_frames == 18 * 3 + 1
    assert good.stat().st_size < 400_000
    reds = []
    for k in range(b.n_frames):
        b.seek(k)
        reds.append(_red(b))
    g.seek(0)
    legend = _red(g)  # the legend's "in collision" swatch
    assert legend > 0
    for k in range(0, g.n_frames, 6):
        g.seek(k)
        assert _red(g) == legend
    assert reds[0] == legend and max(reds) > legend + 50  # the colliding frames have red arms
    with pytest.raises(InputError, match=".gif"):
        save_plan_gif(three, _valid_plan(three), tmp_path / "x.png")


@pytest.mark.slow
def test_strip_is_a_grid_of_readable_panels(tmp_path, three):
    out = save_plan_strip(three, _valid_plan(three), tmp_path / "strip.png", max_frames=8)
    w, h = Image.open(out).size
    assert 1.0 < w / h < 3.5  # two rows of four, not one unreadable ribbon
    bad = save_plan_strip(three, _colliding_plan(three), tmp_path / "bad.png", max_frames=10)
    assert _red(Image.open(bad)) > _red(Image.open(out)) + 200


def test_incidents_figure_draws_each_collision(tmp_path, three):
    plan = _colliding_plan(three)
    result = validate_plan(three, plan)
    assert result.incidents
    out = save_plan_figure(three, plan, tmp_path / "incidents.png", result)
    assert _red(Image.open(out)) > 1000
    with pytest.raises(InputError, match="no collision"):
        save_incidents_figure(three, _valid_plan(three), validate_plan(three, _valid_plan(three)), tmp_path / "x.png")


def test_infeasible_answer_draws_its_certificate(tmp_path):
    p = random_problem(np.array([[0, 0], [18, 0], [9, 15]], float), THREE["kinematics"], 2.0, seed=1)
    plan = Plan("infeasible", [], reason="positioners 0, 1 ...", stats={"certificate": [0, 1]})
    out = save_plan_figure(p, plan, tmp_path / "why.png")
    assert _orange(Image.open(out)) > 1000
    assert _orange(Image.open(save_plan_figure(p, Plan("infeasible", []), tmp_path / "plain.png"))) == 0
    gif = save_plan_figure(p, plan, tmp_path / "why.gif")
    assert Image.open(gif).format == "GIF"
    with pytest.raises(InputError, match="--figure must end in"):
        save_plan_figure(p, plan, tmp_path / "why.txt")


def test_capsule_outline_is_at_buffer_distance():
    outline = capsule([0, 0], [10, 0], 2.0)
    # every outline point is exactly 2 mm from the segment
    x = np.clip(outline[:, 0], 0, 10)
    assert np.allclose(np.hypot(outline[:, 0] - x, outline[:, 1]), 2.0)


# -- wok scale: obstacles, titles, mm axes, the overview of a large plan -----------------------

def _with_obstacles(problem_json):
    data = copy.deepcopy(problem_json)
    data["layout"]["obstacles"] = [{"xy": [0.0, 40.0], "buffer": 2.0},
                                   {"segment": [[-30.0, -45.0], [30.0, -45.0]], "buffer": 3.0}]
    return parse_problem(data)


def test_fiducials_and_guide_cameras_are_drawn_and_named(tmp_path):
    import matplotlib.pyplot as plt

    from supcoord.figures.problem_figures import plot_problem

    problem = _with_obstacles(THREE)
    ax = plot_problem(problem)
    labels = {c.get_label() for c in ax.collections}
    assert {"fiducial", "guide camera (GFA)"} <= labels
    legend = {t.get_text() for t in ax.get_legend().get_texts()}
    assert {"fiducial", "guide camera (GFA)"} <= legend
    assert ax.get_xlabel() == "x (mm)" and ax.get_ylabel() == "y (mm)"
    assert ax.get_ylim()[0] < -45 - 3  # the guide camera is in view
    plt.close(ax.figure)


def test_the_strip_names_the_plan_and_labels_mm(tmp_path, three, monkeypatch):
    import matplotlib.figure

    seen = []
    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", lambda fig, *a, **k: seen.append(fig))
    plan = _valid_plan(three)
    save_plan_strip(three, plan, tmp_path / "s.png")
    fig = seen[0]
    title = fig._suptitle.get_text()
    assert title.startswith("points, 3 robots: plan complete") and f"{plan.makespan} steps" in title
    shown = [ax for ax in fig.axes if ax.get_visible() and ax.axison]
    assert shown[0].get_ylabel() == "y (mm)" and shown[-1].get_xlabel() == "x (mm)"


def test_a_large_plan_gets_one_overview_with_a_timeline(tmp_path, monkeypatch):
    import matplotlib.figure

    from supcoord.figures.plan_figures import save_plan_figure
    from supcoord.figures.wok_overview import OVERVIEW_ABOVE

    seen = []
    original = matplotlib.figure.Figure.savefig
    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", lambda fig, *a, **k: (seen.append(fig),
                                                                                    original(fig, *a, **k)))
    problem = preset_problem("sdss-v", rings=5, start="folded")
    assert problem.n > OVERVIEW_ABOVE
    confs = [problem.start.copy() for _ in range(4)]
    confs[1][:10, 0] += 1  # robots 0-9 move in step 1, robots 10-19 in step 2, nobody in step 3
    confs[2][:20, 0] += 1
    confs[3] = confs[2].copy()
    plan = Plan("complete", confs, lower_bound=2, motion_time_s=4.5)
    reports = []
    save_plan_figure(problem, plan, tmp_path / "o.png", progress=lambda stage, info: reports.append(info["done"]))
    fig = seen[0]
    assert fig._suptitle.get_text() == f"sdss-v, {problem.n} robots: plan complete, 3 steps (lower bound 2), motion 4.5 s"
    wok, counts, timeline = fig.axes[0], fig.axes[2], fig.axes[3]
    assert wok.get_xlabel() == "x (mm)" and timeline.get_xlabel() == "step"
    assert [round(p.get_height()) for p in counts.patches] == [10, 10, 0]
    assert reports == [0, 1, 2, 3]
    assert Image.open(tmp_path / "o.png").size[0] >= 1200
