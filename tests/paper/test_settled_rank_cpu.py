"""The settled route's search for the rank once a checked string proved "forcible": ``h``'s
partition built only up to the string's bound, and the default CPU allowance
(``rank_cpu``), against the exact ranks of an explicit oracle written from the plant's
rules (``coupled_cases.exact_ranks``, no code shared with the route)."""

from __future__ import annotations

import json

import pytest
from coupled_cases import exact_ranks, random_coupled_models

from supcoord.bdd.context import Context
from supcoord.errors import BudgetExceeded, InputError
from supcoord.paper.coupled import CoupledModel
from supcoord.paper.run import coupled_instance
from supcoord.paper.settled import RANK_CPU, settled_ccc
from supcoord.paper.settled_bound import PatternBound
from supcoord.paper.settled_refine import refine
from supcoord.paper.settled_witness import greedy_witness, position_witness, replay


def _forcible_with_string(seed: int, count: int, group_size: int):
    """``(model, exact rank of q0, the greedy string's length)`` where a string is found."""
    for model in random_coupled_models(seed, count, (3, 4), (4,), pitches=(16.0, 18.0, 20.0)):
        rank = exact_ranks(model).get((tuple(model.inst.start), (0,) * model.inst.size))
        found = greedy_witness(model, PatternBound(model, group_size))
        if rank is not None and found is not None:
            yield model, rank, found.length


def test_the_astar_bounded_by_the_string_gives_the_exact_rank_and_a_shortest_witness():
    """The partition stops at the string's length: where that is the rank itself (the
    tightest cap) and where it is above, the rank and a witness of that length."""
    tight = loose = 0
    for model, rank, upper in _forcible_with_string(seed=3801, count=12, group_size=1):
        c = settled_ccc(model, Context(), group_size=1, rank_cpu=None)
        assert c.forcible and c.rank == rank, (model.inst, c.rank, rank)
        assert c.stats["upper_bound"] == upper and replay(model, c.witness) == rank
        tight += upper == rank
        loose += upper > rank
    assert tight >= 1 and loose >= 1, (tight, loose)


@pytest.mark.timeout(60)
def test_the_cpu_allowance_ends_the_rank_search_with_bounds_that_hold_the_exact_rank():
    """Bounds that hold the oracle's rank; where the lower bound already meets the string's
    length, the rank itself (the string is a shortest one)."""
    bounded = exact = 0
    for model, rank, _ in _forcible_with_string(seed=3802, count=16, group_size=2):
        reports = []
        ctx = Context(progress=lambda stage, info: reports.append(stage))
        mine = ctx.progress
        c = settled_ccc(model, ctx, group_size=2, rank_cpu=1e-9)
        assert ctx.progress is mine and reports  # the caller's callback heard the reports, and is back
        assert c.forcible
        if c.rank is not None:
            assert "rank_bounds" not in c.stats and c.stats["rank_proved_by"] == "lower bound"
            assert c.rank == rank == replay(model, c.witness), (model.inst, c.rank, rank)
            exact += 1
            continue
        bounds = c.stats["rank_bounds"]
        assert replay(model, c.witness) == bounds.upper
        assert bounds.lower <= rank <= bounds.upper and bounds.lower < bounds.upper, (model.inst, bounds, rank)
        assert bounds.stopped.startswith("the rank's CPU allowance of 1e-09 s ran out in ")
        bounded += 1
    assert bounded >= 2 and exact >= 1, (bounded, exact)


@pytest.mark.parametrize("bad", [0, -1.0, float("inf"), True, "5"])
def test_a_wrong_allowance_is_refused(bad):
    with pytest.raises(InputError, match="rank_cpu"):
        settled_ccc(CoupledModel(coupled_instance(3, 8, 0)), rank_cpu=bad)


def test_the_default_allowance_is_a_minute_or_less():
    assert 0 < RANK_CPU <= 55


def _raise_after(calls: int):
    seen = []

    def check() -> None:
        seen.append(1)
        if len(seen) > calls:
            raise BudgetExceeded("time budget exceeded in test")

    return check, seen


def test_the_explicit_searches_check_their_budget_as_they_go():
    """The string searches call ``check`` while they expand (a budget ends them there)."""
    model = CoupledModel(coupled_instance(5, 8, 0))
    bound = PatternBound(model)
    check, seen = _raise_after(0)
    with pytest.raises(BudgetExceeded):
        greedy_witness(model, bound, 500, check=check)
    check, seen = _raise_after(0)
    with pytest.raises(BudgetExceeded):
        position_witness(model, bound, lambda pos, moved: True, 500, check=check)
    check, seen = _raise_after(10**6)
    refine(model, forward=False, check=check)
    assert len(seen) > len(refine(model, forward=False).groups)  # within a group's recomputation too


def test_the_command_line_sets_and_lifts_the_allowance(capsys):
    """``supcoord paper --rank-cpu``: seconds pass to the route, ``none`` lifts the limit,
    anything else is one line naming the option (exit 2)."""
    from supcoord.cli.main import main

    argv = ["paper", "--positioners", "5", "--steps", "8", "--model", "coupled", "--seed", "0", "--json"]
    free = json.loads((main(argv + ["--rank-cpu", "none"]), capsys.readouterr())[1].out)
    assert free["ccc"] and free["rank"] == free["witness_length"] and free.get("rank_bounds") is None
    code, out = main(argv + ["--rank-cpu", "1e-9"]), capsys.readouterr()
    cut = json.loads(out.out)  # seed 0's string (14 events) is longer than its bound (13) at the first report
    assert code == 0 and cut["ccc"] and cut["rank"] is None and cut["witness_length"] == 14
    assert cut["rank_bounds"]["lower"] <= free["rank"] <= cut["rank_bounds"]["upper"]
    assert "allowance of 1e-09 s" in cut["rank_bounds"]["stopped"]
    for bad in ("0", "-3", "inf", "soon"):
        code, err = main(argv + ["--rank-cpu", bad]), capsys.readouterr().err
        assert code == 2 and len(err.strip().splitlines()) == 1 and "--rank-cpu" in err, (bad, err)


def test_the_option_help_states_the_librarys_default():
    """``--rank-cpu``'s help names the default without importing the route (the parser stays
    light): the number it states is :data:`RANK_CPU`."""
    import argparse

    from supcoord.cli.cmd_paper import add_arguments

    parser = argparse.ArgumentParser()
    add_arguments(parser)
    option = next(a for a in parser._actions if "--rank-cpu" in a.option_strings)
    assert f"default {RANK_CPU:g}, supcoord.paper.settled.RANK_CPU" in option.help
