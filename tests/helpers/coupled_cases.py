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


def exact_ranks(model: CoupledModel) -> dict[tuple, int]:
    """``{(pos, lvl): rank}`` of every plant state reachable from the start from which the
    target is forcible under preemptive semantics, by the definition alone: the plant's
    events written from the geometry tables (collision ``k``/``e`` uncontrollable, moves
    ``v``/``w``/``h``/``l`` and ``m`` controllable), the attractor built layer by layer
    (a state with an uncontrollable event defined joins when all of its uncontrollable
    successors are in, any other when one controllable successor is)."""
    inst = model.inst
    n, r, size = inst.steps, inst.priority, inst.size

    def events(state: tuple) -> tuple[list, list]:
        pos, lvl = state
        unc, con = [], []
        for i in range(size):
            zone = [j for j in model.neighbours[i] if model.zone[(i, j)][pos[i], pos[j]]]
            c, level = len(zone), lvl[i]
            free = {s: not any(model.swept[(i, j, s)][pos[i], pos[j]] for j in model.neighbours[i]) for s in (1, -1)}

            def put(p: int, lv: int) -> tuple:
                return pos[:i] + (p % n,) + pos[i + 1:], lvl[:i] + (lv,) + lvl[i + 1:]

            if level < min(c, 2):
                unc.append(put(pos[i], level + 1))
            if level >= 1 and c == 0:
                unc.append(put(pos[i], 0))
            for s in (1, -1):
                if free[s] and (level == 0 or (c >= 1 and all((r[i] < r[j]) if s > 0 else (r[i] > r[j])
                                                              for j in zone))):
                    con.append(put(pos[i] + s, 0))
            if level == 2 and c <= 1:
                con.append(put(pos[i], 1))
        return unc, con

    start = (tuple(inst.start), (0,) * size)
    moves, queue = {start: events(start)}, deque([start])
    while queue:
        unc, con = moves[queue.popleft()]
        for nxt in unc + con:
            if nxt not in moves:
                moves[nxt] = events(nxt)
                queue.append(nxt)
    target = (tuple(inst.target), (0,) * size)
    before: dict[tuple, list[tuple]] = {}
    for x, (unc, con) in moves.items():
        for y in set(unc) | set(con):
            before.setdefault(y, []).append(x)
    waiting = {x: len(set(unc)) for x, (unc, con) in moves.items() if unc}  # uncontrollable successors not in
    rank = {target: 0} if target in moves else {}
    frontier, layer = list(rank), 0
    while frontier:
        layer += 1
        new = []
        for y in frontier:
            for x in before.get(y, ()):
                if x in rank:
                    continue
                if x in waiting:
                    if y in moves[x][0]:
                        waiting[x] -= 1
                        if waiting[x] == 0:
                            new.append(x)
                elif y in moves[x][1]:
                    new.append(x)
        new = list(dict.fromkeys(new))
        rank.update(dict.fromkeys(new, layer))
        frontier = new
    return rank
