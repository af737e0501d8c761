"""The pattern databases restricted to the projection refinement's sets
(:mod:`supcoord.paper.settled_sets_bound`) against the exact ranks of an explicit oracle
written from the plant's rules (``coupled_cases.exact_ranks``): a lower bound on every
settled state the A* may expand, never below the plain bound, and above it somewhere; the
settled route that uses it gives the oracle's rank."""

from __future__ import annotations

import pytest
from coupled_cases import exact_ranks, random_coupled_models

from supcoord.bdd.context import Context
from supcoord.paper.settled import settled_ccc
from supcoord.paper.settled_bound import PatternBound
from supcoord.paper.settled_refine import refine
from supcoord.paper.settled_sets_bound import within_sets


def _models(seed: int, count: int):
    return random_coupled_models(seed, count, (3, 4, 4), (4, 5), pitches=(16.0, 18.0, 20.0))


@pytest.mark.timeout(120)
def test_the_bound_inside_the_sets_is_a_lower_bound_on_the_exact_rank_of_every_kept_settled_state():
    checked = raised = 0
    for model in _models(seed=380, count=12):
        rank = exact_ranks(model)
        start = (tuple(model.inst.start), (0,) * model.inst.size)
        back = refine(model, forward=False)
        if start not in rank or back.excluded is not None:
            continue
        both = refine(model, forward=True, within=back)
        for group_size in (2, 3):
            plain = PatternBound(model, group_size)
            for proj in (back, both):
                tight = within_sets(plain, proj)
                for (pos, lvl), r in rank.items():
                    if not proj.admits(pos) or not _settled(model, pos, lvl):
                        continue
                    h, h0 = tight.value(pos), plain.value(pos)
                    assert h is not None and h0 <= h <= r, (model.inst, pos, lvl, h0, h, r)
                    checked += 1
                    raised += h > h0
    assert checked >= 200 and raised >= 5, (checked, raised)


def _settled(model, pos, lvl) -> bool:
    """No collision event defined: every level is ``min(c, 2)``, or 2 over one arm."""
    for i, level in enumerate(lvl):
        c = sum(bool(model.zone[(i, j)][pos[i], pos[j]]) for j in model.neighbours[i])
        if not (level == min(c, 2) or (level == 2 and c == 1)):
            return False
    return True


@pytest.mark.slow
@pytest.mark.timeout(120)
def test_the_route_through_the_refinement_with_the_tighter_bound_gives_the_exact_rank():
    """The greedy search switched off, so the refinement's sets and its bound drive the A*."""
    seen = 0
    for model in _models(seed=381, count=12):
        rank = exact_ranks(model)
        start = (tuple(model.inst.start), (0,) * model.inst.size)
        c = settled_ccc(model, Context(), group_size=2, certificate_size=1, greedy_limit=1)
        assert c.forcible == (start in rank), model.inst
        if c.forcible:
            assert c.rank == rank[start], model.inst
            seen += 1
    assert seen >= 5, seen

