"""Seeded random coupled paper instances for the tests of :mod:`supcoord.paper`: small hex
layouts whose start and target are collision-free and whose target has no arm in another's
safety zone (the settled route's condition).  The pitch varies so that starts lie inside
safety zones and moves collide."""

from __future__ import annotations

import random
from collections import deque
from collections.abc import Iterator, Sequence

from supcoord.paper.coupled import CoupledModel, Geometry
from supcoord.paper.literal import PaperInstance, hex_neighbours, hex_sites
from supcoord.paper.settled_graph import target_in_zone

PITCHES = (16.0, 18.0, 20.0, 22.4)


def random_coupled_models(seed: int, count: int, sizes: Sequence[int], steps: Sequence[int],
                          pitches: Sequence[float] = PITCHES) -> Iterator[CoupledModel]:
    """``count`` instances drawn with ``random.Random(seed)``: positioners from ``sizes``,
    steps per turn from ``steps``, pitch (mm) from ``pitches``, then start, target and a
    shuffled priority; instances that fail the conditions above are drawn again."""
    rng = random.Random(seed)
    while count:
        size = rng.choice(list(sizes))
        n = rng.choice(list(steps))
        pitch = rng.choice(list(pitches))
        start = tuple(rng.randrange(n) for _ in range(size))
        target = tuple(rng.randrange(n) for _ in range(size))
        priority = list(range(1, size + 1))
        rng.shuffle(priority)
        inst = PaperInstance(n, start, target, tuple(priority), hex_neighbours(hex_sites(size)))
        model = CoupledModel(inst, Geometry(pitch=pitch))
        if model.start_collisions or model.target_collisions or target_in_zone(model):
            continue
        count -= 1
        yield model


def target_reachable(model: CoupledModel) -> bool:
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


def configuration_sets(model: CoupledModel) -> tuple[set, set]:
    """``(reachable, co_reachable)``: the configurations reachable from the start, and those
    from which the target is reachable, by brute force on tuples from the geometry tables
    alone (the rule of :func:`target_reachable`; backward: a step is taken back where the
    configuration before it allows it)."""
    inst = model.inst
    n, r = inst.steps, inst.priority

    def allowed(pos: tuple, i: int, sign: int) -> bool:
        for j in model.neighbours[i]:
            if model.swept[(i, j, sign)][pos[i], pos[j]]:
                return False
            if model.zone[(i, j)][pos[i], pos[j]] and not (r[i] < r[j] if sign > 0 else r[i] > r[j]):
                return False
        return True

    def closure(seed: tuple, backward: bool) -> set:
        seen, queue = {seed}, deque([seed])
        while queue:
            pos = queue.popleft()
            for i in range(inst.size):
                for sign in (1, -1):
                    other = pos[:i] + ((pos[i] - sign if backward else pos[i] + sign) % n,) + pos[i + 1:]
                    if allowed(other if backward else pos, i, sign) and other not in seen:
                        seen.add(other)
                        queue.append(other)
        return seen

    return closure(tuple(inst.start), False), closure(tuple(inst.target), True)
