"""The verdict of the coupled model is a reachability question on positions alone.

On a settled state a positioner's move is enabled by the positions only (``v``/``w``:
its zone empty; ``h``/``l``: everyone in its zone outranked / outranking), the stale
bits change weights and never enable a move, and the target (zone-free) has every
stale bit 0.  So ``q0`` is forcible exactly when the target configuration is reachable
from the start in the graph of configurations where arm ``i`` turns one step if the
swept move is free of its neighbours and every neighbour in its zone lets it go that
way (docs/paper.md, "What decides the verdict").  The twin below is a brute-force BFS on
tuples written here from the geometry tables alone; the reference is supcon and the
forcibility layers on ``V`` (the generic route)."""

from __future__ import annotations

from collections import Counter

import pytest
from coupled_cases import random_coupled_models, target_reachable

from supcoord.bdd import Context
from supcoord.paper.coupled import coupled_models
from supcoord.paper.settled_bound import PatternBound
from supcoord.synthesis import ccc, supcon


def _random_models(seed: int, count: int):
    return random_coupled_models(seed, count, (2, 3, 3, 4, 4), (4, 5, 6, 8))


@pytest.mark.timeout(600)
@pytest.mark.slow
def test_forcible_exactly_when_the_target_configuration_is_reachable():
    kinds = Counter()
    for model in _random_models(seed=38, count=150):
        G, E = coupled_models(model, Context())
        forcible = ccc(supcon(G, E, accessible=False).supervisor, "preemptive", full=False).forcible
        assert target_reachable(model) == forcible, model.inst
        # at most GROUP_SIZE arms are one group of every arm: the blocked-group certificate is exact
        blocked = PatternBound(model).blocked_group(tuple(model.inst.start)) is not None
        assert blocked == (not forcible), model.inst
        kinds["forcible" if forcible else "not forcible"] += 1
        kinds["zone at start"] += any(model.in_zone(i, tuple(model.inst.start)) for i in range(model.inst.size))
    for kind in ("forcible", "not forcible", "zone at start"):
        assert kinds[kind] >= 3, kinds
