"""The settled route's search for the rank once a checked string proved "forcible": ``h``'s
partition built only up to the string's bound, and the default CPU allowance
(``rank_cpu``), against the exact ranks of an explicit oracle written from the plant's
rules (``coupled_cases.exact_ranks``, no code shared with the route)."""

from __future__ import annotations

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
    seen = 0
    for model, rank, _ in _forcible_with_string(seed=3802, count=4, group_size=2):
        reports = []
        ctx = Context(progress=lambda stage, info: reports.append(stage))
        mine = ctx.progress
        c = settled_ccc(model, ctx, group_size=2, rank_cpu=1e-9)
        bounds = c.stats["rank_bounds"]
        assert c.forcible and c.rank is None and replay(model, c.witness) == bounds.upper
        assert bounds.lower <= rank <= bounds.upper, (model.inst, bounds, rank)
        assert bounds.stopped.startswith("the rank's CPU allowance of 1e-09 s ran out in ")
        assert ctx.progress is mine and reports  # the caller's callback heard the reports, and is back
        seen += 1
    assert seen >= 2, seen


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
        position_witness(model, bound, lambda pos: True, 500, check=check)
    check, seen = _raise_after(10**6)
    refine(model, forward=False, check=check)
    assert len(seen) > len(refine(model, forward=False).groups)  # within a group's recomputation too
