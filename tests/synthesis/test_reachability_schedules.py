"""Saturation's schedule on products whose events write different components, its budget
stop inside a ``within`` set, and the explicit twins' event subsets, checked by hand.

Saturation merges the events of a cluster that write the same variables into one image;
a shared event (writing two components) and a private one (writing one) that fall into
one cluster must stay apart, or the image of the private event lets the other component
move too.  Two chains sharing one event show it: four of the nine state pairs are
reachable, whatever the component order.
"""

from __future__ import annotations

import pytest

from supcoord.bdd import Budget, Context
from supcoord.des import explicit_ops as X
from supcoord.des import symbolic_ops as S
from supcoord.des.generator import Event, Generator
from supcoord.des.symbolic import from_explicit
from supcoord.errors import BudgetExceeded
from supcoord.synthesis import METHODS, coreachable, coreachable_naive, reachable, reachable_naive, trim_naive

SHARED, OWN_A, OWN_B = Event("s", True), Event("a", True), Event("b", False)
# A: 0 -a-> 1 -s-> 2,  B: 0 -s-> 1 -b-> 2; the product runs (0,0) a (1,0) s (2,1) b (2,2)
CHAIN_A = Generator(3, [SHARED, OWN_A], [(0, "a", 1), (1, "s", 2)], 0, [2], "A")
CHAIN_B = Generator(3, [SHARED, OWN_B], [(0, "s", 1), (1, "b", 2)], 0, [2], "B")
RUN = [(0, 0), (1, 0), (2, 1), (2, 2)]


def _pairs(ctx, sgs, u):
    """The state pairs of ``u`` (component states in the order of ``sgs``)."""
    out = set()
    for p in range(3):
        for q in range(3):
            if ctx.assignment({sgs[0].variables[0]: p, sgs[1].variables[0]: q}) & u != ctx.false:
                out.add((p, q))
    return out


@pytest.mark.parametrize("order", ["AB", "BA"])
@pytest.mark.parametrize("method", METHODS)
def test_a_shared_and_a_private_event_of_one_cluster_stay_apart(order, method):
    ctx = Context()
    gens = [CHAIN_A, CHAIN_B] if order == "AB" else [CHAIN_B, CHAIN_A]
    sgs = [from_explicit(ctx, g) for g in gens]
    G = S.sync(*sgs)
    want = set(RUN) if order == "AB" else {(q, p) for p, q in RUN}
    assert _pairs(ctx, sgs, reachable(G, method=method)) == want
    everything = ctx.true
    assert _pairs(ctx, sgs, reachable(G, within=everything, method=method)) == want
    # every pair of the run can finish; (0, 1), reached by no run, cannot (B needs s, A needs a first)
    back = _pairs(ctx, sgs, coreachable(G, method=method))
    assert set(want) <= back and ((0, 1) if order == "AB" else (1, 0)) not in back
    assert len(reachable_naive(X.sync(*gens))) == len(RUN)  # the explicit product agrees with the hand run


@pytest.mark.parametrize("forward", [True, False])
def test_saturation_inside_a_within_set_stops_at_its_node_budget(forward):
    ring = [Generator(8, [Event(f"a{i}", True)], [(q, f"a{i}", (q + 1) % 8) for q in range(8)], 0, [0], f"R{i}")
            for i in range(3)]
    ctx = Context(budget=Budget(max_nodes=1))
    G = S.sync(*[from_explicit(ctx, g) for g in ring])
    fixpoint = reachable if forward else coreachable
    with pytest.raises(BudgetExceeded) as caught:
        fixpoint(G, within=G.invariant, method="saturation")
    stats = caught.value.stats
    del caught, G  # the traceback holds BDD nodes: free them before their manager
    assert stats["stage"] == ("reachable" if forward else "coreachable")
    assert stats["method"] == "saturation"


def test_the_explicit_twins_follow_the_events_and_name_given():
    chain = Generator(3, [OWN_A, OWN_B], [(0, "a", 1), (1, "b", 2)], 0, [2], "chain")
    assert reachable_naive(chain) == {0, 1, 2}
    assert reachable_naive(chain, events=["a"]) == {0, 1}
    assert reachable_naive(chain, events=["b"]) == {0}
    assert coreachable_naive(chain) == {0, 1, 2}
    assert coreachable_naive(chain, events=["b"]) == {1, 2}
    assert coreachable_naive(chain, events=["a"]) == {2}
    assert trim_naive(chain, "kept").name == "kept"


@pytest.mark.parametrize("within", [False, True])
@pytest.mark.parametrize("method", METHODS)
def test_a_budget_spent_by_the_first_image_stops_at_iteration_one(method, within):
    ring = [Generator(8, [Event(f"a{i}", True)], [(q, f"a{i}", (q + 1) % 8) for q in range(8)], 0, [0], f"R{i}")
            for i in range(3)]
    ctx = Context(budget=Budget(max_nodes=1))
    G = S.sync(*[from_explicit(ctx, g) for g in ring])
    with pytest.raises(BudgetExceeded) as caught:
        reachable(G, within=G.invariant if within else None, method=method)
    stats = caught.value.stats
    del caught, G  # the traceback holds BDD nodes: free them before their manager
    assert stats["iteration"] == 1


@pytest.mark.parametrize("forward", [True, False])
@pytest.mark.parametrize("method", METHODS)
def test_a_fixpoint_longer_than_saturations_plain_phase_is_complete(method, forward):
    """Two independent 300-state chains: the deeper chain's local fixpoint alone takes 300
    images, more than saturation's plain phase before the local closures take over; the
    fixpoint must go on to the other chain (300 × 300 states)."""
    n = 300
    ctx = Context()
    chains = [from_explicit(ctx, Generator(n, [Event(f"a{i}", True)], [(q, f"a{i}", q + 1) for q in range(n - 1)],
                                           0, [n - 1], f"C{i}")) for i in range(2)]
    G = S.sync(*chains)
    got = reachable(G, method=method) if forward else coreachable(G, method=method)
    assert G.count_states(got) == n * n
