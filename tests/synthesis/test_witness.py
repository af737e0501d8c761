"""Witness strings, forcible paths and strategies read from the forcibility layers:
checked by replaying them in the explicit generator and against the explicit twins."""

import itertools

import pytest
from hypothesis import given
from hypothesis import strategies as st
from strategies import alphabets, generators

from supcoord.bdd import Context
from supcoord.des import symbolic_ops as S
from supcoord.des.generator import Event, Generator
from supcoord.des.symbolic import from_explicit
from supcoord.errors import InputError
from supcoord.synthesis import forcible_layers, forcible_layers_naive, forcing_paths, strategy, witness
from supcoord.synthesis.forcibility import as_states, rank_naive
from supcoord.synthesis.witness import forcing_paths_naive, strategy_naive, witness_naive

SEMANTICS = ["preemptive", "standard"]


def has_u(g, q):
    return any(not g.events[e].controllable for e in g.enabled(q))


@st.composite
def instance(draw, max_states=6):
    g = draw(generators(draw(alphabets(mixed=True)), max_states, density=draw(st.sampled_from([0.4, 0.6, 0.8])),
                        min_states=2, connected=True))
    target = draw(st.sets(st.integers(0, g.n_states - 1), min_size=1, max_size=max(1, g.n_states // 2)))
    source = draw(st.integers(0, g.n_states - 1))
    return g, sorted(target), source


def symbolic(g, target):
    G = from_explicit(Context(), g)
    T = G.ctx.false
    for q in target:
        T |= as_states(G, q)
    return G, T


def check_path(g, naive, semantics, source, path):
    """Replay ``path``: every step allowed by the semantics and rank-decreasing, ending
    in the target (layer 0) the first time it gets there."""
    q, k = source, rank_naive(naive, source)
    for e in path:
        assert k is not None and k > 0
        if semantics == "preemptive":
            assert g.events[e].controllable != has_u(g, q), "preemption violated"
        d = g.successor(q, e)
        assert d is not None
        j = rank_naive(naive, d)
        assert j is not None and j < k
        q, k = d, j
    assert k == 0 and q in naive[0]
    return q


@given(instance(), st.sampled_from(SEMANTICS), st.sampled_from(["smallest", "largest", "worst"]))
def test_witness_replays_and_is_bounded_by_rank(inst, semantics, env_choice):
    g, target, source = inst
    G, T = symbolic(g, target)
    lay = forcible_layers(G, T, semantics=semantics)
    naive = forcible_layers_naive(g, target, semantics)
    k = rank_naive(naive, source)
    if k is None:
        with pytest.raises(InputError):
            witness(G, lay, source)
        return
    w = witness(G, lay, source, env_choice=env_choice)
    assert w == witness_naive(g, naive, source, semantics, env_choice)
    assert g.run(w, start=source) in set(target)
    check_path(g, naive, semantics, source, w)
    assert len(w) <= k
    if semantics == "standard":  # the controller forces every step: no waiting for the environment
        assert all(g.events[e].controllable for e in w)
    # exact when no state on the way has an uncontrollable event
    visited = list(itertools.accumulate(w, lambda q, e: g.successor(q, e), initial=source))[:-1]
    if not any(has_u(g, q) for q in visited):
        assert len(w) == k


@given(instance(), st.sampled_from(SEMANTICS))
def test_forcing_paths_valid_sorted_and_complete(inst, semantics):
    g, target, source = inst
    G, T = symbolic(g, target)
    lay = forcible_layers(G, T, semantics=semantics)
    naive = forcible_layers_naive(g, target, semantics)
    if rank_naive(naive, source) is None:
        with pytest.raises(InputError):
            list(forcing_paths(G, lay, source))
        return
    paths = list(forcing_paths(G, lay, source))
    assert paths == forcing_paths_naive(g, naive, source, semantics)
    assert paths == sorted(paths, key=lambda p: (len(p), p))
    for p in paths:
        check_path(g, naive, semantics, source, p)
    assert witness(G, lay, source) in paths
    assert list(forcing_paths(G, lay, source, limit=2)) == paths[:2]
    assert list(forcing_paths(G, lay, source, max_length=1)) == [p for p in paths if len(p) <= 1]


@given(instance(), st.sampled_from(SEMANTICS))
def test_strategy_matches_its_definition(inst, semantics):
    g, target, _ = inst
    G, T = symbolic(g, target)
    lay = forcible_layers(G, T, semantics=semantics)
    naive = forcible_layers_naive(g, target, semantics)
    plan = strategy(G, lay)
    assert len(plan) == len(naive) and plan[0] == {}
    false = G.ctx.false
    expected_plan = strategy_naive(g, naive, semantics)
    for k in range(1, len(naive)):
        for c in sorted(g.controllable):
            got = {q for q in range(g.n_states) if c in plan[k] and as_states(G, q) & plan[k][c] != false}
            assert got == expected_plan[k].get(c, set())
        assert sorted(plan[k]) == sorted(expected_plan[k])
        # every state where the controller acts has a move (that is why it is ranked)
        acting = {q for q in naive[k] if not (semantics == "preemptive" and has_u(g, q))}
        covered = {q for q in acting if any(as_states(G, q) & s != false for s in plan[k].values())}
        assert covered == acting


def test_witness_on_a_product_and_from_component_states(bdd_backend):
    """A 3 x 3 x 3 product of counters: the witness has length rank = 6 and reads
    ascending-name moves; the source may be given by its component states."""
    ctx = Context(bdd_backend)
    comps = []
    for i in range(3):
        g = Generator(3, [Event(f"c{i}", True)], [(0, f"c{i}", 1), (1, f"c{i}", 2)], 0, [2], f"K{i}")
        comps.append(from_explicit(ctx, g, f"k{i}"))
    P = S.sync(*comps)
    lay = forcible_layers(P, P.marked)
    assert lay.sizes() == [1, 3, 6, 7, 6, 3, 1]
    assert witness(P, lay) == ["c0", "c0", "c1", "c1", "c2", "c2"]
    # witness extraction stays symbolic: no state of a layer is enumerated or counted
    def refuse(*args, **kwargs):
        raise AssertionError("a layer was enumerated or counted")

    ctx.enumerate = ctx.count = refuse
    assert witness(P, lay) == ["c0", "c0", "c1", "c1", "c2", "c2"]
    del ctx.enumerate, ctx.count
    src = [{"k0": 1}, {"k1": 2}, {"k2": 0}]
    assert lay.rank(src) == 3
    assert witness(P, lay, src) == ["c0", "c2", "c2"]
    paths = list(forcing_paths(P, lay, src))
    assert len(paths) == 3 and all(len(p) == 3 for p in paths)
    with pytest.raises(InputError):
        witness(P, lay, env_choice="random")
    with pytest.raises(InputError):
        witness(P, lay, P.invariant)  # a set, not one state


def test_standard_witness_takes_the_lowest_ranked_controllable_successor(bdd_backend):
    """Standard semantics: rank(q) = 1 + max(min_c rank δ(q,c), max_u rank δ(q,u)), so a
    controllable successor can lie two layers down; the witness takes it (z, not a)."""
    ev = [Event("a", True), Event("z", True), Event("c", True), Event("u", False)]
    g = Generator(4, ev, [(0, "a", 2), (0, "z", 1), (0, "u", 3), (2, "c", 1), (3, "c", 1)], 0, [1])
    G = from_explicit(Context(bdd_backend), g)
    lay = forcible_layers(G, G.marked, semantics="standard")
    assert lay.rank(0) == 2
    assert witness(G, lay) == ["z"] == witness_naive(g, forcible_layers_naive(g, [1], "standard"), 0, "standard")
    assert list(forcing_paths(G, lay)) == [["z"], ["a", "c"], ["u", "c"]]
    plan = strategy(G, lay)
    assert sorted(plan[2]) == ["a", "z"]
    # preemptive: u is pending at 0, so the environment moves
    pre = forcible_layers(G, G.marked)
    assert witness(G, pre) == ["u", "c"]


def test_standard_witness_never_waits_for_the_environment(bdd_backend):
    """0 -c-> 1 -c-> 2 (target) and 0 -u-> 2: rank(0) = 2 under standard semantics; the
    uncontrollable shortcut u reaches the target in one event, but the controller cannot
    make it happen: the witness forces c, c (and u is still one of the forcible paths)."""
    ev = [Event("c", True), Event("u", False)]
    g = Generator(3, ev, [(0, "c", 1), (1, "c", 2), (0, "u", 2)], 0, [2])
    G = from_explicit(Context(bdd_backend), g)
    lay = forcible_layers(G, G.marked, semantics="standard")
    assert lay.rank(0) == 2
    assert witness(G, lay) == ["c", "c"] == witness_naive(g, forcible_layers_naive(g, [2], "standard"), 0, "standard")
    assert list(forcing_paths(G, lay)) == [["u"], ["c", "c"]]
