"""Fixpoints restricted to a set that couples components which share no event.

Saturation fires each cluster of events to its own fixpoint and re-fires only the clusters
that share variables with one that grew.  A ``within`` set can couple components that share
nothing (``|a − b| ≤ 1`` of two independent counters): after one counter has moved, the
other may move further although no variable of it changed, which only saturation's final
pass (every cluster whose images are not of the current set fires again) finds.  Each
method is compared with the explicit twin on the full product.
"""

from __future__ import annotations

import itertools

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from supcoord.bdd import Context
from supcoord.des import symbolic_ops as S
from supcoord.des.generator import Event, Generator
from supcoord.des.symbolic import from_explicit
from supcoord.synthesis import METHODS, coreachable, coreachable_naive, reachable, reachable_naive


def _counters(sizes):
    """Independent counters (own events ``up_i``, ``down_i``), their symbolic product, the
    full explicit product over every state tuple and the tuples in its order."""
    gens = []
    for i, n in enumerate(sizes):
        up, down = Event(f"up{i}", i % 2 == 0), Event(f"down{i}", True)
        trans = [(q, up.name, q + 1) for q in range(n - 1)] + [(q + 1, down.name, q) for q in range(n - 1)]
        gens.append(Generator(n, [up, down], trans, 0, [n - 1], f"C{i}"))
    tuples = list(itertools.product(*(range(n) for n in sizes)))
    index = {t: k for k, t in enumerate(tuples)}
    trans = []
    for t in tuples:
        for i, g in enumerate(gens):
            for e in g.events:
                d = g.successor(t[i], e)
                if d is not None:
                    trans.append((index[t], e, index[t[:i] + (d,) + t[i + 1:]]))
    events = [e for g in gens for e in g.alphabet]
    marked = [index[t] for t in tuples if all(q == n - 1 for q, n in zip(t, sizes))]
    full = Generator(len(tuples), events, trans, 0, marked, "FULL")
    return gens, full, tuples


def _encode(ctx, sgs, tuples, states):
    u = ctx.false
    for q in states:
        u |= ctx.assignment({sg.variables[0]: v for sg, v in zip(sgs, tuples[q])})
    return u


def _decode(ctx, sgs, tuples, u):
    return {q for q in range(len(tuples)) if _encode(ctx, sgs, tuples, [q]) & u != ctx.false}


def _compare(sizes, within, seeds=None, targets=None):
    gens, full, tuples = _counters(sizes)
    ctx = Context()
    sgs = [from_explicit(ctx, g) for g in gens]
    G = S.sync(*sgs)
    w = _encode(ctx, sgs, tuples, within)
    start = None if seeds is None else _encode(ctx, sgs, tuples, seeds)
    goal = None if targets is None else _encode(ctx, sgs, tuples, targets)
    want_f = reachable_naive(full, seeds, within)
    want_b = coreachable_naive(full, targets, within)
    for method in METHODS:
        assert _decode(ctx, sgs, tuples, reachable(G, start, w, method=method)) == want_f, method
        assert _decode(ctx, sgs, tuples, coreachable(G, goal, w, method=method)) == want_b, method
    return want_f, tuples


@pytest.mark.parametrize("sizes", [(5, 5), (4, 6, 3)])
def test_a_within_set_that_couples_independent_counters(sizes):
    within = [k for k, t in enumerate(itertools.product(*(range(n) for n in sizes)))
              if max(t) - min(t) <= 1]
    got, tuples = _compare(sizes, within)
    assert {tuples[q] for q in got} == {tuples[q] for q in within}  # the staircase is connected


@settings(max_examples=60, deadline=None)
@given(sizes=st.lists(st.integers(2, 4), min_size=2, max_size=3), data=st.data())
def test_independent_components_within_random_sets_equal_the_explicit_twin(sizes, data):
    n = 1
    for s in sizes:
        n *= s
    within = data.draw(st.lists(st.integers(0, n - 1), min_size=n // 3, max_size=n, unique=True))
    seeds = data.draw(st.one_of(st.none(), st.lists(st.integers(0, n - 1), min_size=1, max_size=3, unique=True)))
    targets = data.draw(st.one_of(st.none(), st.lists(st.integers(0, n - 1), min_size=1, max_size=3, unique=True)))
    _compare(sizes, within, None if seeds is None else set(seeds), None if targets is None else set(targets))
