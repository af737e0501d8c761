"""reachable/coreachable: every method == the explicit twin, on products of random
components with random start/target/within sets and event subsets."""

import itertools

import pytest
from hypothesis import given
from hypothesis import strategies as st
from oracle import faudes_accessible, faudes_coaccessible, faudes_parallel, faudes_trim
from strategies import alphabets, generators

from supcoord.bdd import Context
from supcoord.des import explicit_ops as X
from supcoord.des import symbolic_ops as S
from supcoord.des.generator import Event, Generator
from supcoord.des.symbolic import from_explicit, to_explicit
from supcoord.errors import InputError
from supcoord.synthesis import (
    METHODS,
    coreachable,
    coreachable_naive,
    event_clusters,
    reachable,
    reachable_naive,
    trim,
    trim_naive,
)


def full_product(gens):
    """The synchronous product over *all* state tuples (not only the accessible ones),
    numbered in ``itertools.product`` order, so arbitrary state sets can be compared."""
    alphabet = {}
    for g in gens:
        for e in g.alphabet:
            alphabet.setdefault(e.name, e)
    tuples = list(itertools.product(*[range(g.n_states) for g in gens]))
    index = {t: i for i, t in enumerate(tuples)}
    trans = []
    for t in tuples:
        for e in alphabet:
            nxt = list(t)
            for i, g in enumerate(gens):
                if e in g.events:
                    d = g.successor(t[i], e)
                    if d is None:
                        break
                    nxt[i] = d
            else:
                trans.append((index[t], e, index[tuple(nxt)]))
    marked = [index[t] for t in tuples if all(q in g.marked for q, g in zip(t, gens))]
    return Generator(len(tuples), alphabet.values(), trans, 0, marked, "FULL"), tuples


@st.composite
def scenario(draw):
    alphabet = draw(alphabets())
    k = draw(st.integers(1, 4))
    gens = [draw(generators(alphabet, 4, f"G{i}")) for i in range(k)]
    full, tuples = full_product(gens)
    n = full.n_states
    subset = st.lists(st.integers(0, n - 1), max_size=n, unique=True).map(set)
    seeds = draw(st.one_of(st.none(), subset))
    within = draw(st.one_of(st.none(), st.lists(st.integers(0, n - 1), min_size=n // 2, max_size=n, unique=True).map(set)))
    names = sorted(full.events)
    events = draw(st.one_of(st.none(), st.lists(st.sampled_from(names), unique=True)))
    return gens, full, tuples, seeds, within, events


def encode(ctx, sgs, tuples, states):
    u = ctx.false
    for q in states:
        values = {}
        for sg, v in zip(sgs, tuples[q]):
            if sg.variables:
                values[sg.variables[0]] = v
        u |= ctx.assignment(values) if values else ctx.true
    return u


def decode(ctx, sgs, tuples, u):
    return {q for q, t in enumerate(tuples) if encode(ctx, sgs, tuples, [q]) & u != ctx.false}


@given(scenario(), st.sampled_from(METHODS))
def test_reachable_equals_naive(case, method):
    gens, full, tuples, seeds, within, events = case
    ctx = Context()
    sgs = [from_explicit(ctx, g) for g in gens]
    G = S.sync(*sgs)
    start = None if seeds is None else encode(ctx, sgs, tuples, seeds)
    w = None if within is None else encode(ctx, sgs, tuples, within)
    got = reachable(G, start, w, method=method, events=events)
    assert decode(ctx, sgs, tuples, got) == reachable_naive(full, seeds, within, events)


@given(scenario(), st.sampled_from(METHODS))
def test_coreachable_equals_naive(case, method):
    gens, full, tuples, targets, within, events = case
    ctx = Context()
    sgs = [from_explicit(ctx, g) for g in gens]
    G = S.sync(*sgs)
    target = None if targets is None else encode(ctx, sgs, tuples, targets)
    w = None if within is None else encode(ctx, sgs, tuples, within)
    got = coreachable(G, target, w, method=method, events=events)
    assert decode(ctx, sgs, tuples, got) == coreachable_naive(full, targets, within, events)


@given(st.data())
def test_naive_twins_agree_with_libfaudes(data):
    alphabet = data.draw(alphabets())
    g = data.draw(generators(alphabet, 6, "G"))
    assert faudes_accessible(g) == reachable_naive(g)
    assert faudes_coaccessible(g) == coreachable_naive(g)


def test_methods_on_a_product_of_independent_counters(bdd_backend):
    """Eight independent 5-state counters: 5^8 reachable states by every method."""
    ctx = Context(bdd_backend)
    gens = []
    for i in range(8):
        ev = Event(f"up{i}", i % 2 == 0)
        g = Generator(5, [ev], [(q, ev.name, q + 1) for q in range(4)], 0, [4], f"C{i}")
        gens.append(from_explicit(ctx, g))
    G = S.sync(*gens)
    results = {m: reachable(G, method=m) for m in METHODS}
    assert len(set(results.values())) == 1
    assert G.count_states(results["saturation"]) == 5**8
    back = coreachable(G)  # every state can finish
    assert G.count_states(back) == 5**8
    clusters = event_clusters(G)
    assert len(clusters) == 8 and all(len(c) == 1 for c in clusters)
    # bottom-up: the last declared component's cluster comes first
    assert clusters[0] == ["up7"] and clusters[-1] == ["up0"]


def test_unknown_method_is_refused(bdd_backend):
    ctx = Context(bdd_backend)
    G = from_explicit(ctx, Generator(2, [Event("a", True)], [(0, "a", 1)], 0, [1]))
    try:
        reachable(G, method="dfs")
    except InputError as exc:
        exc.__traceback__ = None
        assert exc.value == "dfs"
    else:
        pytest.fail("no InputError")


@st.composite
def several_components(draw):
    alphabet = draw(alphabets(min_size=3))
    k = draw(st.integers(2, 4))
    return [draw(generators(alphabet, 4, f"G{i}")) for i in range(k)]


@given(several_components(), st.sampled_from(METHODS))
def test_products_agree_with_libfaudes(gens, method):
    """On the full product of 2-4 random components (every state tuple, so libFAUDES
    sees unreachable and blocking states too): symbolic sync == libFAUDES Parallel,
    reachable == Accessible, coreachable == Coaccessible, trim == Trim."""
    full, tuples = full_product(gens)
    ctx = Context()
    sgs = [from_explicit(ctx, g) for g in gens]
    P = S.sync(*sgs)
    assert to_explicit(P).same_as(faudes_parallel(*gens)) and X.sync(*gens).same_as(faudes_parallel(*gens))
    assert decode(ctx, sgs, tuples, reachable(P, method=method)) == faudes_accessible(full)
    assert decode(ctx, sgs, tuples, coreachable(P, method=method)) == faudes_coaccessible(full)
    kept = faudes_trim(full)
    T = trim(P, method=method)
    assert decode(ctx, sgs, tuples, T.invariant) == kept
    assert to_explicit(T).same_as(trim_naive(X.sync(*gens)))
    assert (T.init == ctx.false) == (not kept)


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("forward", [True, False])
def test_every_method_stops_at_its_node_budget(method, forward):
    # a ring of 3 counters: every fixpoint iterates, and each must check its budget
    from supcoord.bdd import Budget
    from supcoord.errors import BudgetExceeded

    ring = [Generator(8, [Event(f"a{i}", True)], [(q, f"a{i}", (q + 1) % 8) for q in range(8)], 0, [0], f"R{i}")
            for i in range(3)]
    ctx = Context(budget=Budget(max_nodes=1))
    G = S.sync(*[from_explicit(ctx, g) for g in ring])
    fixpoint = reachable if forward else coreachable
    with pytest.raises(BudgetExceeded) as caught:
        fixpoint(G, method=method)
    stats = caught.value.stats
    del caught, G  # the traceback holds BDD nodes: free them before their manager
    assert stats["stage"] == ("reachable" if forward else "coreachable")
    assert stats["method"] == method
