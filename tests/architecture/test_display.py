"""What a notebook shows: short reprs and HTML tables whatever the size, and a top-level
``dir`` that lists the API only."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import supcoord as sc
from supcoord.problems import parse_problem
from supcoord.problems.plan import Plan
from supcoord.study.execute import RunSummary
from supcoord.study.spec import load_study

EXAMPLES = Path(__file__).resolve().parents[2] / "docs" / "examples"
#: a repr is one short line, whatever the size of the object
MAX_REPR = 300


@pytest.fixture(scope="module")
def apo():
    """The APO wok: 500 robots, 66 fiducials and guide cameras, folded at start and target."""
    folded = {"alpha_beta_deg": [[10, 170]] * 500}
    return parse_problem({"layout": {"kind": "instrument", "name": "sdss-v-apo"}, "start": folded,
                          "target": folded}, "apo wok")


@pytest.mark.slow
def test_a_wok_problem_and_plan_have_short_reprs_and_html(apo):
    for text in (repr(apo), apo._repr_html_()):
        assert "500" in text and "sdss-v-apo" in text and len(text) < 3 * MAX_REPR
    assert len(repr(apo)) < MAX_REPR
    steps = [apo.start.copy() for _ in range(40)]
    plan = Plan("complete", steps, lower_bound=30, events=["a1+"] * 4000, motion_time_s=54.03,
                angles_deg=[np.zeros((500, 2))] * 40, stats={"seconds": 12.3})
    assert repr(plan) == ("Plan(status='complete', positioners=500, makespan=39, lower_bound=30, "
                          "motion_time_s=54.03, single_moves=4000, seconds=12.3)")
    assert "<table>" in plan._repr_html_() and "motion_time_s" in plan._repr_html_()


def test_every_result_has_a_short_repr_and_html():
    inst = sc.paper_example()
    ctx = sc.Context()
    G, E = sc.coupled_models(sc.CoupledModel(inst), ctx)
    result = sc.supcon(G, E)
    verdict = sc.ccc(result.supervisor)
    run = sc.run_paper(30, 8)
    problem = sc.load_problem(EXAMPLES / "three_rotary.json")
    summary = RunSummary("quick", "quick.sqlite", "v", total=40, pending=12, ran=12, statuses={"ok": 11, "timeout": 1})
    study = load_study(Path(__file__).resolve().parents[2] / "benchmarks" / "studies" / "readme.toml")
    assert len(repr(study.cases[0])) < MAX_REPR
    objects = [study, sc.random_instance(1000, 8), G, result, verdict, verdict.fixpoint, run, problem, sc.solve(problem), summary]
    for obj in objects:
        text = repr(obj)
        assert len(text) < MAX_REPR and "\n" not in text, text
        html = obj._repr_html_()
        assert html.startswith("<table>") and type(obj).__name__ in html
    assert "forcible=True" in repr(verdict) and "rank=6" in repr(verdict)
    assert "states=4128" in repr(result) and "positioners=30" in repr(run)


def test_dir_of_the_package_is_its_api():
    shown = dir(sc)
    assert shown == sorted(sc.__all__)
    for helper in ("Any", "TYPE_CHECKING", "annotations", "importlib", "_compat", "errors"):
        assert helper not in shown
    assert {"solve", "Problem", "Plan", "supcon", "ccc", "SupcoordError"} <= set(shown)
