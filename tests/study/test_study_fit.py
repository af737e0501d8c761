"""The fitted growth of a study's series: the right model and rate on known curves, the
direction of the data, one fit shared by the legends and tables, readable axes."""

from __future__ import annotations

import math

import matplotlib
import pytest

from supcoord.study.fit import fit_growth, series_growth
from supcoord.study.plots import figure_metric

matplotlib.use("Agg")

SIZES = [7, 19, 37, 61, 91, 127, 169, 271, 397, 547]


def test_a_power_law_is_recovered_with_its_exponent():
    g = fit_growth(SIZES, [0.01 * n**1.5 for n in SIZES])
    assert g.model == "power" and g.rate == pytest.approx(1.5, abs=1e-9)
    assert g.label("positioner") == "∝ N^1.50"


def test_an_exponential_is_recovered_with_its_factor():
    ns = list(range(2, 12))
    g = fit_growth(ns, [0.001 * 2.0**n for n in ns])
    assert g.model == "exponential" and g.rate == pytest.approx(2.0, rel=1e-9)
    assert g.label("positioner") == "×2 per positioner"


def test_a_fixed_cost_plus_a_cost_per_positioner_is_linear():
    # a process's memory: 65 MB of interpreter, then 0.19 MB per positioner
    ns = [1, 10, 30, 100, 300, 1000, 3000, 5000]
    g = fit_growth(ns, [65 + 0.19 * n for n in ns])
    assert g.model == "linear" and g.rate == pytest.approx(0.19, rel=1e-6)
    assert g.label("positioner") == "linear, +0.19 per positioner"


def test_a_rising_series_never_gets_a_falling_fit():
    # the README study's alpha-beta times: rising overall, falling over the last four sizes,
    # which the old fit (largest four sizes only) labelled ∝ N^-0.68
    seconds = [0.78, 5.64, 7.31, 11.84, 17.91, 26.7, 93.71, 49.21, 32.46, 46.97]
    rows = [{"series": "solve alpha-beta local", "status": "ok", "positioners": n, "seconds": s}
            for n, s in zip(SIZES, seconds)]
    g = series_growth(rows, "seconds")["solve alpha-beta local"]
    assert g.model == "power" and g.rate > 0
    for k in range(3, 12):  # every monotone rising series, of each shape
        for ys in ([n**0.3 for n in range(1, k + 1)], [math.exp(n) for n in range(k)], [5 + n for n in range(k)],
                   [1, 1, 1] + [2] * (k - 3)):
            g = fit_growth(list(range(1, k + 1)), ys)
            rate = math.log(g.rate) if g.model == "exponential" else g.rate
            assert rate >= 0, (ys, g)


def test_the_legend_shows_the_fit_of_series_growth():
    rows = [{"series": "s", "status": "ok", "positioners": n, "seconds": 0.01 * n**1.5, "kind": "solve"}
            for n in SIZES]
    fig = figure_metric(rows, "seconds")
    ax = fig.axes[0]
    texts = [t.get_text() for t in ax.get_legend().get_texts()]
    assert texts == [f"s: {series_growth(rows, 'seconds')['s'].label()}"]
    # the legend sits below the panel, outside the data
    assert ax.get_legend()._loc != 0 and ax.get_legend().get_bbox_to_anchor().y0 < ax.get_window_extent().y0
    # log axes carry no minor labels (they collided with the major ones)
    fig.canvas.draw()
    for axis in (ax.xaxis, ax.yaxis):
        assert not [t for t in axis.get_minorticklabels() if t.get_text()]
    labels = [t for t in ax.yaxis.get_majorticklabels() if t.get_text() and t.get_visible()]
    boxes = sorted((t.get_window_extent() for t in labels), key=lambda b: b.y0)
    assert all(a.y1 <= b.y0 for a, b in zip(boxes, boxes[1:])), "tick labels overlap"


def test_study_show_reports_the_same_fit_as_the_legend():
    from supcoord.cli.cmd_study import _growth

    rows = [{"series": "solve rotary local", "status": "ok", "positioners": n, "seconds": 0.01 * n**1.5,
             "peak_rss_mb": 65 + 0.19 * n, "bdd_nodes": None} for n in SIZES]
    payload: dict = {}
    lines = _growth(rows, payload)
    fit = series_growth(rows, "seconds")["solve rotary local"]
    assert payload["growth"]["seconds"]["solve rotary local"]["label"] == fit.label() == "∝ N^1.50"
    assert payload["growth"]["peak_rss_mb"]["solve rotary local"]["model"] == "linear"
    assert "  solve rotary local: ∝ N^1.50 (r² 1.00, 10 sizes)" in lines
    assert payload["growth"]["bdd_nodes"] == {}
