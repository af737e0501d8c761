"""A budget that ends the settled route's search for the rank after a checked forcing string
proved "forcible": the verdict, the string and the rank's bounds, against the explicit
Dijkstra twin's exact rank.  The budget is ended from the progress callback, at a chosen
report, as the command's watchdog ends it anywhere."""

from __future__ import annotations

import pytest
from coupled_cases import random_coupled_models

from supcoord.bdd.context import Context
from supcoord.cli.cmd_paper import _text
from supcoord.errors import BudgetExceeded
from supcoord.paper.coupled import CoupledModel
from supcoord.paper.run import coupled_instance, run_paper
from supcoord.paper.settled import settled_ccc, settled_ccc_naive
from supcoord.paper.settled_bound import PatternBound
from supcoord.paper.settled_graph import settle
from supcoord.paper.settled_witness import greedy_witness, replay


def _stop(stage: str, at: int) -> Context:
    """A context whose budget ends at the ``at``-th (0-based) report of ``stage``."""
    seen = []

    def progress(name: str, info: dict) -> None:
        if name == stage:
            seen.append(info)
            if len(seen) > at:
                raise BudgetExceeded(f"time budget exceeded in {name}", stats=info)

    return Context(progress=progress)


@pytest.mark.timeout(120)
def test_a_budget_in_the_astar_answers_the_verdict_with_bounds_that_hold_the_exact_rank():
    """Stopped at every report of the A* in turn: ``lower ≤ rank ≤ upper`` each time, the
    string forces the target, and the last stops are tight enough to meet the rank (so a
    lower bound one too high would fail here)."""
    tight = stops = 0
    for model in random_coupled_models(seed=6, count=12, sizes=(3, 4, 4), steps=(5, 6)):
        forcible, rank = settled_ccc_naive(model)
        if not forcible or greedy_witness(model, PatternBound(model)) is None:
            continue
        for at in range(200):
            c = settled_ccc(model, _stop("settled", at))
            bounds = c.stats.get("rank_bounds")
            if bounds is None:  # the A* finished before its report number ``at``, or its bound met the string
                assert c.rank == rank == replay(model, c.witness)
                if c.stats.get("rank_proved_by") == "lower bound":
                    stops += 1
                    tight += 1
                    continue
                break
            stops += 1
            assert c.forcible and c.rank is None
            assert bounds.lower <= rank <= bounds.upper <= replay(model, c.witness), (model.inst, at)
            assert bounds.stopped == "time budget exceeded in settled"
            tight += bounds.lower == rank
    assert stops >= 10 and tight >= 1, (stops, tight)


def test_a_budget_while_the_relations_are_built_keeps_the_proved_verdict():
    model = CoupledModel(coupled_instance(5, 8, 0))
    found = greedy_witness(model, PatternBound(model))
    c = settled_ccc(model, _stop("settled relations", 0))
    _, cost = settle(model, tuple(model.inst.start), (0,) * model.inst.size)
    assert c.forcible and c.rank is None and list(c.witness) == list(found.witness)
    assert c.stats["rank_bounds"].lower == cost + PatternBound(model).value(tuple(model.inst.start))
    assert c.stats["rank_bounds"].upper == found.length == replay(model, c.witness)


def test_the_relations_reports_carry_the_proved_verdict():
    model = CoupledModel(coupled_instance(5, 8, 0))
    reports = []
    settled_ccc(model, Context(progress=lambda stage, info: reports.append((stage, info))))
    building = [info for stage, info in reports if stage == "settled relations"]
    assert building and all(info["forcible"] is True and info["upper_bound"] > 0 for info in building)


def test_a_budget_before_any_proof_still_stops_the_run():
    model = CoupledModel(coupled_instance(5, 8, 0))
    with pytest.raises(BudgetExceeded):  # no greedy string: the refinement is stopped, nothing proved
        settled_ccc(model, _stop("settled refinement", 0), greedy_limit=1, certificate_size=1)


def test_run_paper_labels_the_bounded_rank_in_its_json_and_its_line():
    run = run_paper(5, 8, "coupled", 0, ctx=_stop("settled", 0))
    out = run.to_json()
    assert out["status"] == "ok" and out["ccc"] is True and out["rank"] is None
    bounds = out["rank_bounds"]
    assert bounds["proved"] is False and bounds["lower"] <= bounds["upper"] == out["witness_length"]
    assert replay(CoupledModel(run.instance), out["witness"]) == out["witness_length"]
    line = _text(run, out)
    assert f"rank in [{bounds['lower']}, {bounds['upper']}] (not proved minimal: time budget exceeded" in line
    assert "rank_bounds" not in run_paper(5, 8, "coupled", 0).to_json()  # a proved rank has no bounds
