"""CCC of the coupled model on its settled states (supcoord.paper.settled) against the
generic route: supcon of the whole product and forcibility layers on V (their own code),
and the explicit Dijkstra twin.

The random instances vary the pitch (so starts lie inside safety zones and collisions
are frequent), steps, priorities and sizes, so that every branch is reached: forcible
and not, settled and unsettled starts, start = target, stale levels (two neighbours in
the zone, one leaves).  No timings here: benchmarks/bench_coupled.py measures them."""

from __future__ import annotations

import random
from collections import Counter

import pytest
from coupled_cases import random_coupled_models

from supcoord.bdd import Context
from supcoord.cli.main import main
from supcoord.errors import InputError
from supcoord.paper.coupled import CoupledModel, Geometry, coupled_models
from supcoord.paper.literal import PaperInstance, hex_neighbours, hex_sites, paper_example
from supcoord.paper.run import coupled_instance, run_paper
from supcoord.paper.settled import SettledGraph, settle, settled_ccc, settled_ccc_naive, target_in_zone
from supcoord.synthesis import ccc, supcon


def _generic(model: CoupledModel) -> tuple:
    G, E = coupled_models(model, Context())
    c = ccc(supcon(G, E, accessible=False).supervisor, "preemptive", full=False)
    return c.forcible, c.rank, c.witness


def _random_models(seed: int, count: int):
    return random_coupled_models(seed, count, (2, 2, 3, 3, 4), (4, 5, 6, 8))


def _visits_a_stale_level(model: CoupledModel) -> bool:
    """Some settled state reachable from the start has a level 2 with one neighbour in the zone."""
    size = model.inst.size
    start = (tuple(model.inst.start), settle(model, tuple(model.inst.start), (0,) * size)[0])
    seen, stack = {start}, [start]
    while stack:
        pos, lvl = stack.pop()
        if any(l == 2 and model.count(i, pos) == 1 for i, l in enumerate(lvl)):
            return True
        for i in range(size):
            for kind, (p, level) in model.successors(i, pos, lvl).items():
                nxt = pos[:i] + (p,) + pos[i + 1:]
                state = (nxt, settle(model, nxt, lvl[:i] + (level,) + lvl[i + 1:])[0])
                if state not in seen:
                    seen.add(state)
                    stack.append(state)
    return False


@pytest.mark.timeout(240)
@pytest.mark.slow
def test_settled_ccc_equals_the_generic_route_and_the_explicit_twin_on_random_instances():
    kinds = Counter()
    for model in _random_models(seed=11, count=160):
        generic = _generic(model)
        fast = settled_ccc(model)
        assert (fast.forcible, fast.rank, fast.witness) == generic, model.inst
        assert settled_ccc_naive(model) == generic[:2], model.inst
        size = model.inst.size
        kinds["forcible" if generic[0] else "not forcible"] += 1
        kinds["unsettled start"] += settle(model, tuple(model.inst.start), (0,) * size)[1] > 0
        kinds["start = target"] += model.inst.start == model.inst.target
        kinds["environment in the witness"] += any(int(e) % 2 == 0 for e in generic[2])
        kinds["stale level"] += _visits_a_stale_level(model)
    # every route of the reduction is reached, not only the easy one
    for kind in ("forcible", "not forcible", "unsettled start", "start = target", "environment in the witness",
                 "stale level"):
        assert kinds[kind] >= 3, kinds


@pytest.mark.timeout(120)
@pytest.mark.parametrize("size, steps, seed", [(3, 8, 0), (4, 6, 1), (5, 6, 0),
                                                  pytest.param(6, 8, 0, marks=pytest.mark.slow)])
def test_settled_ccc_equals_the_generic_route_on_the_benchmark_instances(size, steps, seed):
    model = CoupledModel(coupled_instance(size, steps, seed))
    fast = settled_ccc(model)
    assert (fast.forcible, fast.rank, fast.witness) == _generic(model)
    assert fast.stats["distance"] == fast.rank - SettledGraph(model).start_cost


def test_the_papers_example_starts_in_a_collision_and_keeps_its_witness():
    """P1 and P2 start inside each other's zone: the witness opens with their k events."""
    model = CoupledModel(paper_example())
    r = settled_ccc(model)
    assert (r.forcible, r.rank, r.witness) == (True, 6, ["10", "20", "15", "50", "83", "93"])
    assert SettledGraph(model).start_cost == 2


def test_a_target_inside_a_safety_zone_takes_the_monolithic_route():
    """There supcon may remove the target itself (a pending k leads to a blocking state),
    so the settled states do not decide CCC: the settled route refuses, the default
    route is monolithic, and they would disagree on this instance."""
    inst = PaperInstance(8, (2, 2, 7), (1, 2, 6), (3, 2, 1), hex_neighbours(hex_sites(3)))
    geometry = Geometry(pitch=16.0)
    model = CoupledModel(inst, geometry)
    assert target_in_zone(model) is not None
    with pytest.raises(InputError) as e:
        settled_ccc(model)
    assert e.value.where == "target"
    run = run_paper(instance=inst, model="coupled", geometry=geometry)
    assert run.route == "monolithic" and run.payload["ccc"] is False
    with pytest.raises(InputError):
        run_paper(instance=inst, model="coupled", geometry=geometry, route="settled")


def test_default_routes_and_refusals():
    r = run_paper(4, 6, model="coupled", seed=1)
    assert r.route == "settled" and r.supervisor is None and r.payload["supervisor_states"] is None
    assert r.payload["counted"] is False and r.payload["settled"]["distance"] <= r.payload["rank"]
    mono = run_paper(4, 6, model="coupled", seed=1, route="monolithic")
    assert [mono.payload[k] for k in ("ccc", "rank", "witness")] == [r.payload[k] for k in ("ccc", "rank", "witness")]
    assert run_paper(4, 6, model="coupled", seed=1, semantics="standard").route == "monolithic"
    assert run_paper(4, 6, model="coupled", seed=1, count_states=True).route == "monolithic"
    for options, where in (({"semantics": "standard"}, "semantics"), ({"count_states": True}, "route")):  # library names
        with pytest.raises(InputError) as e:
            run_paper(4, 6, model="coupled", seed=1, route="settled", **options)
        assert e.value.where == where
    with pytest.raises(InputError):
        run_paper(4, 6, model="literal", route="settled")


def test_cli_settled_route(capsys):
    assert main(["paper", "--positioners", "4", "--steps", "8", "--model", "coupled", "--seed", "3"]) == 0
    out = capsys.readouterr().out
    assert "settled route" in out and "V not built" in out and "CCC forcible" in out
    assert main(["paper", "--positioners", "4", "--steps", "8", "--model", "coupled", "--route", "settled",
                 "--semantics", "standard"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "preemptive" in err[0]


def _settled_edges(model: CoupledModel):
    """Every edge ``(y, weight, y')`` of the settled graph reachable from the start."""
    size = model.inst.size
    q0 = tuple(model.inst.start)
    start = (q0, settle(model, q0, (0,) * size)[0])
    seen, stack = {start}, [start]
    while stack:
        y = stack.pop()
        pos, lvl = y
        for i in range(size):
            for kind, (p, level) in model.successors(i, pos, lvl).items():
                if kind in ("k", "e"):
                    raise AssertionError(f"an uncontrollable event at a settled state: {y}")
                nxt = pos[:i] + (p,) + pos[i + 1:]
                levels, d = settle(model, nxt, lvl[:i] + (level,) + lvl[i + 1:])
                z = (nxt, levels)
                yield y, 1 + d, z
                if z not in seen:
                    seen.add(z)
                    stack.append(z)


@pytest.mark.timeout(120)
@pytest.mark.parametrize("group_size", [1, 2, 3, 6])
@pytest.mark.slow
def test_the_pattern_bound_is_consistent_and_its_bdds_are_its_values(group_size):
    """h(y) ≤ w + h(y') on every edge, h = 0 on the target, finite wherever the target is
    reachable, and H[b] holds exactly the configurations of value b."""
    from supcoord.paper.settled_bound import PatternBound, neighbour_groups

    checked = 0
    for model in _random_models(seed=5, count=25):
        bound = PatternBound(model, group_size)
        groups = neighbour_groups(model, group_size)
        assert sorted(i for g in groups for i in g) == list(range(model.inst.size))
        assert all(len(g) <= group_size for g in groups)
        assert bound.value(tuple(model.inst.target)) == 0
        forcible, rank = settled_ccc_naive(model)
        h0 = bound.value(tuple(model.inst.start))
        assert (h0 is None) <= (not forcible) and (not forcible or h0 <= rank)
        for y, w, z in _settled_edges(model):
            hy, hz = bound.value(y[0]), bound.value(z[0])
            if hy is not None:
                assert hz is None or hy <= w + hz, (model.inst, y, z)
                checked += 1
        graph = SettledGraph(model, group_size=group_size)
        H = graph.distance_exact()
        for pos in {tuple(model.inst.start), tuple(model.inst.target)}:
            cube = graph.ctx.assignment({graph.pos(i): p for i, p in enumerate(pos)})
            values = [b for b, u in enumerate(H) if u & cube != graph.ctx.false]
            assert values == ([] if bound.value(pos) is None else [bound.value(pos)])
    assert checked > 500


def test_groups_are_refused_when_their_database_would_not_fit():
    from supcoord.paper.settled_bound import PatternBound

    model = CoupledModel(coupled_instance(19, 8, 0))
    with pytest.raises(InputError):
        PatternBound(model, 0)
    with pytest.raises(InputError):
        PatternBound(model, 9)  # 8^9 entries


@pytest.mark.timeout(120)
def test_each_pattern_database_is_the_least_cost_of_its_relaxation():
    """Every entry of every group's database equals a Dijkstra (heap, one configuration at a
    time) over the group's relaxed graph, written here from the definition: a move of
    ``P_i`` free of the group's swept arms and, where an arm it may not escape from is in
    its zone, refused; cost 1 + min(arms of the group in ``P_i``'s zone after it, 2), plus 1
    for each other positioner of the group next to ``P_i`` whose neighbours are all in the
    group and whose zone goes from empty to occupied or back.  A 7-positioner hex (the
    default geometry), where moves ending with 0, 1, 2 and 3 group arms in the zone and
    moves charged 0 and 1 such zone changes occur."""
    import heapq
    import itertools

    import numpy as np

    from supcoord.paper.settled_bound import UNREACHABLE, PatternBound

    inst = PaperInstance(6, (0, 1, 2, 3, 4, 5, 0), (3, 4, 5, 0, 1, 2, 3), (4, 1, 7, 2, 6, 3, 5),
                         hex_neighbours(hex_sites(7)))
    model = CoupledModel(inst)
    bound = PatternBound(model, 5)
    n, prio = model.inst.steps, model.inst.priority
    zones_seen, changes_seen = Counter(), Counter()
    for group, table in zip(bound.groups, bound.tables):
        into: dict[tuple, list[tuple[int, tuple]]] = {}  # y -> [(cost, x)] for every move x -> y
        whole = [c for c, j in enumerate(group) if all(k in group for k in model.neighbours[j])]

        def busy(c, conf):  # group[c]'s zone holds an arm (all its neighbours are in the group)
            j = group[c]
            return any(model.zone[(j, k)][conf[c], conf[group.index(k)]] for k in model.neighbours[j])

        for x in itertools.product(range(n), repeat=len(group)):
            for a, i in enumerate(group):
                for sign in (1, -1):
                    others = [(b, j) for b, j in enumerate(group) if j != i and j in model.neighbours[i]]
                    if any(model.swept[(i, j, sign)][x[a], x[b]] for b, j in others):
                        continue
                    may_escape = lambda j: prio[i] < prio[j] if sign > 0 else prio[i] > prio[j]  # noqa: E731
                    if any(model.zone[(i, j)][x[a], x[b]] and not may_escape(j) for b, j in others):
                        continue
                    y = x[:a] + (model._next[sign][x[a]],) + x[a + 1:]
                    in_zone = sum(bool(model.zone[(i, j)][y[a], y[b]]) for b, j in others)
                    zones_seen[in_zone] += 1
                    changes = sum(busy(c, x) != busy(c, y) for c in whole if c != a and group[c] in model.neighbours[i])
                    changes_seen[changes] += 1
                    into.setdefault(y, []).append((1 + min(in_zone, 2) + changes, x))
        target = tuple(model.inst.target[i] for i in group)
        dist, queue = {target: 0}, [(0, target)]
        while queue:
            d, y = heapq.heappop(queue)
            if d > dist[y]:
                continue
            for w, x in into.get(y, []):
                if d + w < dist.get(x, d + w + 1):
                    dist[x] = d + w
                    heapq.heappush(queue, (d + w, x))
        expected = np.full(table.shape, UNREACHABLE, dtype=table.dtype)
        for x, d in dist.items():
            expected[x] = d
        assert np.array_equal(table, expected), group
    assert all(zones_seen[c] for c in (0, 1, 2, 3)), zones_seen
    assert all(changes_seen[c] for c in (0, 1)), changes_seen


@pytest.mark.timeout(240)
@pytest.mark.slow
def test_a_blocked_group_answers_as_the_explicit_twin_does():
    """Groups of one in the bound (they never block) and certificate groups of two or three
    on crowded instances of 4-5 positioners: every "not forcible" answered by a blocked
    group is also the explicit Dijkstra's answer, and every other instance still gets
    the search's verdict and rank (and, up to 4 positioners, the generic route's witness)."""
    rng = random.Random(23)
    seen = Counter()
    while sum(seen.values()) < 40:
        size, steps = rng.choice([4, 4, 5]), rng.choice([4, 5])
        inst = PaperInstance(steps, tuple(rng.randrange(steps) for _ in range(size)),
                             tuple(rng.randrange(steps) for _ in range(size)), tuple(rng.sample(range(1, size + 1), size)),
                             hex_neighbours(hex_sites(size)))
        model = CoupledModel(inst, Geometry(pitch=rng.choice([16.0, 18.0])))
        if model.start_collisions or model.target_collisions or target_in_zone(model):
            continue
        certificate = rng.choice([2, 3])
        fast = settled_ccc(model, group_size=1, certificate_size=certificate)
        assert (fast.forcible, fast.rank) == settled_ccc_naive(model), inst
        if size <= 4:
            assert (fast.forcible, fast.rank, fast.witness) == _generic(model), inst
        if "blocked_group" in fast.stats and "refinement" not in fast.stats:  # not the neighbourhoods' certificate
            assert 2 <= len(fast.stats["blocked_group"]) <= certificate and not fast.forcible
            seen["blocked"] += 1
        else:
            seen["searched, forcible" if fast.forcible else "searched, not forcible"] += 1
    assert all(seen[k] >= 3 for k in ("blocked", "searched, forcible", "searched, not forcible")), seen


@pytest.mark.timeout(120)
@pytest.mark.slow
def test_the_19_positioner_benchmark_instance_is_blocked():
    """``supcoord paper --positioners 19 --steps 8 --model coupled`` (seed 0) answers "not
    forcible" from a group of 5; a breadth-first search written here from the definition
    (only the group's arms: a move free of their swept arms, and with one of them in the
    mover's zone only the way its priority allows) confirms that the group's targets are
    unreachable from its starts, over a non-trivial set of configurations."""
    from supcoord.paper.settled_bound import PatternBound

    model = CoupledModel(coupled_instance(19, 8, 0))
    start, target, prio = model.inst.start, model.inst.target, model.inst.priority
    group = PatternBound(model).blocked_group(tuple(start))
    assert group is not None and len(group) == 5
    seen = {tuple(start[i] for i in group)}
    frontier = list(seen)
    while frontier:
        nxt = []
        for x in frontier:
            for a, i in enumerate(group):
                others = [(b, j) for b, j in enumerate(group) if j in model.neighbours[i]]
                for sign in (1, -1):
                    if any(model.swept[(i, j, sign)][x[a], x[b]] for b, j in others):
                        continue
                    if any(model.zone[(i, j)][x[a], x[b]] and not (prio[i] < prio[j] if sign > 0 else prio[i] > prio[j])
                           for b, j in others):
                        continue
                    y = x[:a] + ((x[a] + sign) % model.inst.steps,) + x[a + 1:]
                    if y not in seen:
                        seen.add(y)
                        nxt.append(y)
        frontier = nxt
    assert tuple(target[i] for i in group) not in seen
    assert len(seen) > 10_000, len(seen)  # 15,428 of 8^5
    answer = run_paper(19, 8, "coupled", 0).payload
    assert answer["ccc"] is False and answer["rank"] is None and answer["witness"] == []
    assert answer["certificate"].startswith(", ".join(f"P{i + 1}" for i in group[:-1]))
