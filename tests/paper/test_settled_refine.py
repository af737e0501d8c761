"""Projection refinement (:mod:`supcoord.paper.settled_refine`) and the search on
configurations (:func:`~supcoord.paper.settled_witness.position_witness`) against brute
force on tuples written from the geometry tables alone (``tests/helpers/coupled_cases.py``)
and the explicit Dijkstra twin on the settled states."""

from __future__ import annotations

from collections import Counter

import numpy as np
import pytest
from coupled_cases import configuration_sets, random_coupled_models

from supcoord.bdd import Context
from supcoord.paper.coupled import CoupledModel
from supcoord.paper.run import coupled_instance
from supcoord.paper.settled import settled_ccc, settled_ccc_naive
from supcoord.paper.settled_bound import PatternBound
from supcoord.paper.settled_refine import neighbourhood_groups, proj_bdd, refine
from supcoord.paper.settled_witness import position_witness, replay


def _models(seed: int, count: int):
    """4 to 7 positioners: neighbourhoods that leave neighbours outside, so every branch of
    the refinement (neighbours inside the group, outside it, a home group) is taken."""
    return random_coupled_models(seed, count, (4, 5, 6, 7), (4,), (16.0, 18.0, 22.4))


@pytest.mark.timeout(600)
@pytest.mark.slow
def test_the_sets_hold_every_reachable_and_co_reachable_configuration():
    kinds = Counter()
    for model in random_coupled_models(7, 20, (4, 5, 6, 7), (4,), (16.0, 18.0)):  # crowded: refuted often
        reach, coreach = configuration_sets(model)
        forcible = tuple(model.inst.target) in reach
        fwd, back = refine(model), refine(model, forward=False)
        both = refine(model, forward=True, within=back)
        for proj, configurations in ((fwd, reach), (back, coreach), (both, reach & coreach)):
            if proj.excluded is None:  # a certificate stops the sweeps early: its sets are sound then too
                assert all(proj.admits(x) for x in configurations), model.inst
            if forcible:
                assert proj.excluded is None, model.inst
        if not forcible:
            kinds["refuted" if both.excluded is not None else "missed"] += 1
            kinds["back refuted"] += back.excluded is not None
        kinds["forcible" if forcible else "not forcible"] += 1
        kinds["proper subsets"] += any(s.sum() < s.size for s in fwd.sets)
    assert kinds["forcible"] >= 5 and kinds["refuted"] >= 3 and kinds["back refuted"] >= 1, kinds
    assert kinds["proper subsets"] >= 10, kinds


@pytest.mark.timeout(600)
def test_the_sets_exclude_what_the_plain_reachable_set_excludes_on_a_fixpoint():
    """At the fixpoint, the sets are the projections of a superset of the reachable set:
    each set holds at least the reachable projections and is not trivially everything."""
    model = next(m for m in _models(seed=3, count=40) if len(m.inst.start) >= 6)
    reach, _ = configuration_sets(model)
    fwd = refine(model)
    assert fwd.fixpoint or fwd.excluded is not None
    for group, values in zip(fwd.groups, fwd.sets):
        exact = np.zeros_like(values)
        for x in reach:
            exact[tuple(x[i] for i in group)] = True
        assert not (exact & ~values).any()
    assert neighbourhood_groups(model) == fwd.groups


@pytest.mark.timeout(600)
@pytest.mark.slow
def test_the_search_on_configurations_finds_a_string_exactly_where_the_target_is_reachable():
    kinds = Counter()
    for model in _models(seed=11, count=15):
        reach, coreach = configuration_sets(model)
        forcible, rank = settled_ccc_naive(model)
        assert forcible == (tuple(model.inst.target) in reach)
        back = refine(model, forward=False)
        for admits in (lambda pos, moved: True, back.admits):
            found = position_witness(model, PatternBound(model), admits, limit=10 ** 6)
            assert (found is not None) == forcible, model.inst
            if found is not None:
                assert replay(model, found.witness) == found.length >= rank
        kinds[forcible] += 1
    assert min(kinds.values()) >= 3, kinds


@pytest.mark.timeout(600)
@pytest.mark.slow
def test_settled_ccc_through_the_refinement_equals_the_explicit_twin():
    """No blocked group and no settled greedy string (groups of one, limits of 1): every answer comes from
    the refinement's certificate, or its search and the A* restricted to its sets."""
    kinds = Counter()
    for model in _models(seed=19, count=15):
        forcible, rank = settled_ccc_naive(model)
        c = settled_ccc(model, Context(), group_size=1, certificate_size=1, greedy_limit=1)
        assert (c.forcible, c.rank) == (forcible, rank), model.inst
        if forcible:
            assert replay(model, c.witness) == rank
        else:
            kinds["certificate" if c.stats.get("certificate") else "search"] += 1
        kinds[forcible] += 1
    assert kinds[True] >= 3 and kinds["certificate"] >= 3, kinds


def test_the_bdd_of_the_sets_holds_the_configurations_they_admit():
    model = CoupledModel(coupled_instance(4, 5, 1))
    proj = refine(model, forward=False)
    ctx = Context()
    for i in range(model.inst.size):
        ctx.add_variable(f"pos{i + 1}", model.inst.steps)
    u = proj_bdd(proj, ctx, lambda i: f"pos{i + 1}")
    for x in np.ndindex(*(model.inst.steps,) * model.inst.size):
        inside = u & ctx.assignment({f"pos{i + 1}": int(p) for i, p in enumerate(x)}) != ctx.false
        assert inside == proj.admits(tuple(int(p) for p in x))

