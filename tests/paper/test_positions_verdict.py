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

import random
from collections import Counter, deque

import pytest

from supcoord.bdd import Context
from supcoord.paper.coupled import CoupledModel, Geometry, coupled_models
from supcoord.paper.literal import PaperInstance, hex_neighbours, hex_sites
from supcoord.paper.settled import target_in_zone
from supcoord.paper.settled_bound import PatternBound
from supcoord.synthesis import ccc, supcon


def _target_reachable(model: CoupledModel) -> bool:
    """BFS over configurations: one arm turns one step when the move is free and the arms
    in its zone let it go that way."""
    inst = model.inst
    n, r = inst.steps, inst.priority
    start, target = tuple(inst.start), tuple(inst.target)
    seen, queue = {start}, deque([start])
    while queue:
        pos = queue.popleft()
        if pos == target:
            return True
        for i in range(inst.size):
            for sign in (1, -1):
                ok = True
                for j in model.neighbours[i]:
                    if model.swept[(i, j, sign)][pos[i], pos[j]]:
                        ok = False
                    elif model.zone[(i, j)][pos[i], pos[j]] and not (r[i] < r[j] if sign > 0 else r[i] > r[j]):
                        ok = False
                if ok:
                    nxt = pos[:i] + ((pos[i] + sign) % n,) + pos[i + 1:]
                    if nxt not in seen:
                        seen.add(nxt)
                        queue.append(nxt)
    return False


def _random_models(seed: int, count: int):
    rng = random.Random(seed)
    while count:
        size = rng.choice([2, 3, 3, 4, 4])
        steps = rng.choice([4, 5, 6, 8])
        pitch = rng.choice([16.0, 18.0, 20.0, 22.4])
        start = tuple(rng.randrange(steps) for _ in range(size))
        target = tuple(rng.randrange(steps) for _ in range(size))
        priority = list(range(1, size + 1))
        rng.shuffle(priority)
        inst = PaperInstance(steps, start, target, tuple(priority), hex_neighbours(hex_sites(size)))
        model = CoupledModel(inst, Geometry(pitch=pitch))
        if model.start_collisions or model.target_collisions or target_in_zone(model):
            continue
        count -= 1
        yield model


@pytest.mark.timeout(600)
@pytest.mark.slow
def test_forcible_exactly_when_the_target_configuration_is_reachable():
    kinds = Counter()
    for model in _random_models(seed=38, count=150):
        G, E = coupled_models(model, Context())
        forcible = ccc(supcon(G, E, accessible=False).supervisor, "preemptive", full=False).forcible
        assert _target_reachable(model) == forcible, model.inst
        # at most GROUP_SIZE arms are one group of every arm: the blocked-group certificate is exact
        blocked = PatternBound(model).blocked_group(tuple(model.inst.start)) is not None
        assert blocked == (not forcible), model.inst
        kinds["forcible" if forcible else "not forcible"] += 1
        kinds["zone at start"] += any(model.in_zone(i, tuple(model.inst.start)) for i in range(model.inst.size))
    for kind in ("forcible", "not forcible", "zone at start"):
        assert kinds[kind] >= 3, kinds
