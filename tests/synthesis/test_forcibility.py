"""Forcibility layers: symbolic fixpoint vs the explicit twin, BFA, CCC, and the two
cautionary examples of docs/forcibility.md (decomposition; the literal paper model)."""

from collections import Counter

import pytest
from hypothesis import given
from hypothesis import strategies as st
from strategies import alphabets, generators

from supcoord.bdd import Budget, Context
from supcoord.des import explicit_ops as X
from supcoord.des import symbolic_ops as S
from supcoord.des.generator import Event, Generator
from supcoord.des.symbolic import from_explicit
from supcoord.errors import BudgetExceeded, InputError
from supcoord.synthesis import bfa, ccc, forcible_layers, forcible_layers_naive, forcing_paths, witness
from supcoord.synthesis.forcibility import (as_single_state, as_states, bfa_naive, force, forced_naive, rank_naive,
                                           uncontrollable_enabled)

SEMANTICS = ["preemptive", "standard"]


def state_sets(G, layers, n):
    """The symbolic layers of a one-variable generator as sets of state numbers."""
    false = G.ctx.false
    return [{q for q in range(n) if as_states(G, q) & layer != false} for layer in layers]


def target_bdd(G, target):
    out = G.ctx.false
    for q in target:
        out |= as_states(G, q)
    return out


@st.composite
def generator_and_target(draw, max_states=6):
    """A connected generator (every state reachable from 0) over both kinds of events and
    a nonempty target of at most half its states: layers several deep are common
    (``test_random_cases_have_deep_layers`` checks it)."""
    density = draw(st.sampled_from([0.4, 0.6, 0.8]))
    g = draw(generators(draw(alphabets(mixed=True)), max_states, density=density, min_states=2, connected=True))
    target = draw(st.sets(st.integers(0, g.n_states - 1), min_size=1, max_size=max(1, g.n_states // 2)))
    return g, sorted(target)


def test_random_cases_have_deep_layers():
    """The random instances the layer tests run on are not trivial: for a good share of
    them a state is won in two or more steps, and states where the environment acts are
    won (the cases where the two semantics differ)."""
    seen: Counter = Counter()

    @given(generator_and_target())
    def count(gt):
        g, target = gt
        seen["cases"] += 1
        for semantics in SEMANTICS:
            layers = forcible_layers_naive(g, target, semantics)
            seen[semantics, "deep"] += len(layers) >= 3
            seen[semantics, "env"] += any(any(not g.events[e].controllable for e in g.enabled(q))
                                          for layer in layers[1:] for q in layer)

    count()
    n = seen["cases"]
    assert n >= 20, seen
    assert seen["preemptive", "deep"] >= n // 20 and seen["standard", "deep"] >= n // 40, seen
    assert seen["preemptive", "env"] >= n // 10, seen


@given(generator_and_target(), st.sampled_from(SEMANTICS))
def test_symbolic_layers_equal_naive(gt, semantics):
    g, target = gt
    G = from_explicit(Context(), g)
    lay = forcible_layers(G, target_bdd(G, target), semantics=semantics)
    naive = forcible_layers_naive(g, target, semantics)
    assert state_sets(G, lay.layers, g.n_states) == naive
    assert lay.sizes() == [len(x) for x in naive]
    assert lay.complete
    for q in range(g.n_states):
        assert lay.rank(q) == rank_naive(naive, q)


@given(generator_and_target(), st.sampled_from(SEMANTICS))
def test_one_force_step_on_the_whole_relations_equals_the_definition(gt, semantics):
    """``force`` called as its docstring does (no pre-restricted relations): under the
    preemptive semantics a state with an uncontrollable event pending is won only when
    every such event leads into W, whatever its controllable events do."""
    g, target = gt
    G = from_explicit(Context(), g)
    W = set(target)
    got = force(G, target_bdd(G, target), G.invariant, uncontrollable_enabled(G), semantics)
    assert state_sets(G, [got], g.n_states)[0] == {q for q in range(g.n_states) if forced_naive(g, q, W, semantics)}


@given(generator_and_target(), st.sampled_from(SEMANTICS), st.data())
def test_within_equals_naive(gt, semantics, data):
    g, target = gt
    inside = data.draw(st.sets(st.integers(0, g.n_states - 1)))
    G = from_explicit(Context(), g)
    lay = forcible_layers(G, target_bdd(G, target), semantics=semantics, within=target_bdd(G, inside))
    naive = forcible_layers_naive(g, target, semantics, within=inside)
    assert state_sets(G, lay.layers, g.n_states) == naive


@st.composite
def products(draw):
    alphabet = draw(alphabets(mixed=True))
    k = draw(st.integers(2, 3))
    return [draw(generators(alphabet, 3, f"G{i}", min_states=2, connected=True, min_marked=1)) for i in range(k)]


@given(products(), st.sampled_from(SEMANTICS))
def test_product_layers_equal_naive_on_accessible_part(gens, semantics):
    """On a symbolic product (no pruning) the layers restricted to the accessible
    states equal the explicit layers of the accessible product (target = marked)."""
    ctx = Context()
    comps = [from_explicit(ctx, g) for g in gens]
    P = S.sync(*comps)
    xp = X.sync(*gens)
    lay = forcible_layers(P, P.marked, semantics=semantics)
    naive = forcible_layers_naive(xp, xp.marked, semantics)

    def values(i):
        parts = [int(x) for x in xp.state_label(i).split(",")]
        return [{c.variables[0]: q} for c, q in zip(comps, parts) if c.variables]

    assert len(lay.layers) >= len(naive)
    for q in range(xp.n_states):
        assert lay.rank(values(q)) == rank_naive(naive, q)


def test_decomposition_counterexample_design_md(bdd_backend):
    """Component 1: a -u-> b -u2-> a, target a; component 2: s -c-> t, target t.
    The product's winning set is not the product of the components' winning sets."""
    c1 = Generator(2, [Event("u", False), Event("u2", False)], [(0, "u", 1), (1, "u2", 0)], 0, [0], "C1")
    c2 = Generator(2, [Event("c", True)], [(0, "c", 1)], 0, [1], "C2")
    ctx = Context(bdd_backend)
    a, b = from_explicit(ctx, c1, "x1"), from_explicit(ctx, c2, "x2")
    P = S.sync(a, b)
    expected = {"preemptive": (2, 2, 4, 2), "standard": (1, 2, 2, 1)}
    for semantics, (w1, w2, prod_of_w, w_of_prod) in expected.items():
        W1 = forcible_layers(a, a.marked, semantics=semantics).winning
        W2 = forcible_layers(b, b.marked, semantics=semantics).winning
        WP = forcible_layers(P, P.marked, semantics=semantics).winning
        assert (a.count_states(W1), b.count_states(W2)) == (w1, w2)
        assert P.count_states(W1 & W2) == prod_of_w
        assert P.count_states(WP) == w_of_prod
        assert WP != W1 & W2
        # and the explicit twin agrees on the product
        xp = X.sync(c1, c2)
        assert sum(len(x) for x in forcible_layers_naive(xp, xp.marked, semantics)) == w_of_prod
    # preemptive: (a,s) and (b,s) cycle on u, u2 forever and the controller never acts
    lay = forcible_layers(P, P.marked)
    assert lay.rank({"x1": 0, "x2": 0}) is None and lay.rank([{"x1": 1}, {"x2": 1}]) == 1


def paper_positioner(prone, coupled=False, n=4, start=0, target=2):
    """One positioner of the seed paper (priority event h only), literal reading.

    States ``q_j = j``, ``q_j^1 = n + j``, ``q_j^2 = 2n + j``; ``v``/``w`` move with
    wrap-around; at collision-prone positions ``k: q_j → q_j^1 → q_j^2``,
    ``e: q_j^1 → q_j``, ``h: q_j^1, q_j^2 → q_{j+1}``.  ``coupled=True`` lets ``e`` lead
    to a copy ``3n + j`` of ``q_j`` where ``k`` is not pending (the neighbour has left).
    """
    ev = [Event("v", True), Event("w", True), Event("h", True), Event("k", False), Event("e", False)]
    t = []
    for j in range(n):
        for base in (0, 3 * n) if coupled else (0,):
            t += [(base + j, "v", (j + 1) % n), (base + j, "w", (j - 1) % n)]
        if j in prone:
            t += [(j, "k", n + j), (n + j, "k", 2 * n + j), (n + j, "e", 3 * n + j if coupled else j)]
            t += [(n + j, "h", (j + 1) % n), (2 * n + j, "h", (j + 1) % n)]
    return Generator(4 * n if coupled else 3 * n, ev, t, start, [target], "P")


@pytest.mark.parametrize("semantics", SEMANTICS)
def test_literal_paper_model_k_e_cycle_blocks_forcibility(semantics, bdd_backend):
    """Literal model: k and e may fire whenever the generator allows, so the environment
    can cycle k, e, k, e, … at a collision-prone position: with every route from q_0 to
    q_2 crossing one (positions 1 and 3), q_0 is not forcible under either semantics;
    leaving one route free (only 1 prone) makes it forcible, via w, w."""
    for prone, expect in [({1, 3}, None), ({1}, ["w", "w"])]:
        g = paper_positioner(prone)
        naive = forcible_layers_naive(g, g.marked, semantics)
        G = from_explicit(Context(bdd_backend), g)
        r = ccc(G, semantics)
        assert r.rank == rank_naive(naive, 0)
        assert (r.witness if r.forcible else None) == expect
        # q_1 and q_1^1 lie on the k, e cycle: never won, whatever the other routes
        assert r.fixpoint.rank(1) is None and r.fixpoint.rank(4 + 1) is None


@pytest.mark.parametrize("semantics", SEMANTICS)
def test_coupled_variant_is_forcible(semantics):
    """Once e means "the neighbour has left" (k no longer pending), the same positioner
    is forcible: the k, e, k, e cycle is gone."""
    g = paper_positioner({1, 3}, coupled=True)
    G = from_explicit(Context(), g)
    r = ccc(G, semantics)
    assert r.forcible
    assert r.rank == rank_naive(forcible_layers_naive(g, g.marked, semantics), 0)
    assert g.run(r.witness) in g.marked


@given(generator_and_target(), st.sampled_from(SEMANTICS), st.data())
def test_bfa_is_the_reachable_part_of_the_layers(gt, semantics, data):
    g, target = gt
    source = data.draw(st.integers(0, g.n_states - 1))
    G = from_explicit(Context(), g)
    T = target_bdd(G, target)
    full = forcible_layers_naive(g, target, semantics)
    dag = bfa(G, source, T, semantics=semantics)
    k0 = rank_naive(full, source)
    expected = bfa_naive(g, source, target, semantics)
    if k0 is None:
        assert dag.layers == [] == expected and dag.rank(source) is None
        return
    assert state_sets(G, dag.layers, g.n_states) == expected
    assert dag.rank(source) == k0
    # the DAG carries every forcible path from the source, and the same witness
    whole = forcible_layers(G, T, semantics=semantics)
    assert list(forcing_paths(G, dag, source, limit=50)) == list(forcing_paths(G, whole, source, limit=50))
    assert witness(G, dag, source) == witness(G, whole, source)


def test_stop_at_within_and_rank_forms():
    # a chain 0 -c-> 1 -c-> 2 -c-> 3, target 3
    g = Generator(4, [Event("c", True)], [(0, "c", 1), (1, "c", 2), (2, "c", 3)], 0, [3])
    G = from_explicit(Context(), g, "x")
    lay = forcible_layers(G, G.marked, stop_at={"x": 2})
    assert not lay.complete and lay.sizes() == [1, 1]
    full = forcible_layers(G, G.marked)
    assert full.complete and full.sizes() == [1, 1, 1, 1]
    assert full.rank(None) == full.rank(0) == full.rank({"x": 0}) == full.rank(G.init) == 3
    assert full.rank(G.invariant) == 3  # a set: the least k containing all of it
    cut = forcible_layers(G, G.marked, within=~G.ctx.eq("x", 1))
    assert cut.sizes() == [1, 1] and cut.rank(0) is None
    with pytest.raises(InputError):
        forcible_layers(G, G.marked, semantics="angelic")
    with pytest.raises(InputError):
        as_single_state(G, G.invariant)
    with pytest.raises(InputError):
        as_states(G, "zero")
    with pytest.raises(InputError):
        full.rank({"y": 0})


def test_budget_stops_the_fixpoint():
    g = Generator(4, [Event("c", True)], [(0, "c", 1), (1, "c", 2), (2, "c", 3)], 0, [3])
    seen = []
    ctx = Context(budget=Budget(max_nodes=1), progress=lambda stage, info: seen.append((stage, info["iteration"])))
    G = from_explicit(ctx, g)
    with pytest.raises(BudgetExceeded) as info:
        forcible_layers(G, G.marked)
    assert info.value.stats["stage"] == "force" and seen == [("force", 0)]


def test_ccc_on_empty_and_trivial_generators():
    ctx = Context()
    empty = from_explicit(ctx, Generator(0, [Event("a", True)], []))
    r = ccc(empty)
    assert (r.forcible, r.rank, r.witness) == (False, None, [])
    one = from_explicit(ctx, Generator(1, [Event("a", True)], [(0, "a", 0)], 0, [0]))
    r = ccc(one)
    assert (r.forcible, r.rank, r.witness, r.layers) == (True, 0, [], [1])
    assert r.to_json() == {"status": "ok", "forcible": True, "witness": [], "rank": 0, "layers": [1]}


def test_ccc_early_stop_and_bfa_by_component_states():
    ctx = Context()
    comps = []
    for i in range(2):
        g = Generator(3, [Event(f"c{i}", True)], [(0, f"c{i}", 1), (1, f"c{i}", 2)], 0, [2], f"K{i}")
        comps.append(from_explicit(ctx, g, f"k{i}"))
    P = S.sync(*comps)
    full, early = ccc(P), ccc(P, full=False)
    assert full.layers == [1, 2, 3, 2, 1] and full.stats["complete"]
    assert (early.rank, early.witness, early.layers) == (4, full.witness, [1, 2, 3, 2, 1])
    from_mid = ccc(P, target=[{"k0": 1}, {"k1": 1}])
    assert (from_mid.rank, from_mid.witness) == (2, ["c0", "c1"])
    dag = bfa(P, [{"k0": 1}, {"k1": 0}], {"k0": 2, "k1": 2})
    assert [P.count_states(x) for x in dag.layers] == [1, 2, 2, 1]
    by_tuple = bfa(P, (1, 0), (2, 2))  # component states, in P.variables order
    assert by_tuple.layers == dag.layers and by_tuple.rank((1, 0)) == 3
    with pytest.raises(InputError):
        bfa(P, (1,), (2, 2))
    assert dag.rank({"k0": 1, "k1": 0}) == 3 and dag.rank({"k0": 0, "k1": 0}) is None


def test_both_backends_agree_with_the_twin(bdd_backend):
    g = paper_positioner({1, 3}, coupled=True)
    G = from_explicit(Context(bdd_backend), g)
    for semantics in SEMANTICS:
        lay = forcible_layers(G, G.marked, semantics=semantics)
        assert state_sets(G, lay.layers, g.n_states) == forcible_layers_naive(g, g.marked, semantics)
