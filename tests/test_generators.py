"""Explicit vs symbolic generators: conversion, sync, meet, allevents, selfloop agree."""

import pytest
from hypothesis import given
from hypothesis import strategies as st
from strategies import alphabets, generators

from supcoord.des import explicit_ops as X
from supcoord.des import symbolic_ops as S
from supcoord.des.generator import Event, Generator, tct_event
from supcoord.des.symbolic import from_explicit, to_explicit
from supcoord.errors import AlphabetError, InputError, NondeterminismError
from supcoord.symbolic import Context


@st.composite
def components(draw, k_max=3):
    alphabet = draw(alphabets())
    k = draw(st.integers(1, k_max))
    return [draw(generators(alphabet, 5, f"G{i}")) for i in range(k)]


@given(components())
def test_symbolic_sync_equals_explicit(gens):
    ctx = Context()
    product = S.sync(*[from_explicit(ctx, g) for g in gens])
    assert to_explicit(product).same_as(X.sync(*gens))


@given(components(k_max=1))
def test_round_trip(gens):
    (g,) = gens
    ctx = Context()
    sg = from_explicit(ctx, g)
    back = to_explicit(sg)
    assert back.same_as(g)
    reach = X.accessible_states(g)
    assert back.n_states == len(reach)


@given(components(k_max=2))
def test_allevents_and_selfloop(gens):
    ctx = Context()
    g = gens[0]
    extra = [Event("z", False)]
    looped = X.selfloop(g, extra)
    assert to_explicit(S.selfloop(from_explicit(ctx, g), extra)).same_as(looped)
    all_g = X.allevents(g)
    assert to_explicit(S.allevents(ctx, from_explicit(ctx, g))).same_as(all_g)
    assert all_g.n_states == 1 and all_g.n_transitions == len(g.events)


def test_nondeterminism_is_rejected_with_value():
    with pytest.raises(NondeterminismError) as info:
        Generator(2, [Event("a", True)], [(0, "a", 0), (0, "a", 1)])
    assert info.value.value == (0, "a", (0, 1))


def test_conflicting_controllability():
    a = Generator(1, [Event("a", True)], [])
    b = Generator(1, [Event("a", False)], [])
    with pytest.raises(AlphabetError):
        X.sync(a, b)


def test_tct_numbering():
    assert tct_event(71).controllable and not tct_event(10).controllable
    with pytest.raises(InputError):
        tct_event("x")


def test_meet_needs_equal_alphabets():
    a = Generator(1, [Event("a", True)], [])
    b = Generator(1, [Event("b", True)], [])
    with pytest.raises(AlphabetError):
        X.meet(a, b)
    ctx = Context()
    with pytest.raises(AlphabetError):
        S.meet(from_explicit(ctx, a), from_explicit(ctx, b))


@pytest.mark.parametrize("backend", ["cudd", "autoref"])
def test_exact_count_beyond_double_precision(backend):
    ctx = Context(backend)
    names = [ctx.add_variable(f"y{i}", 3).name for i in range(120)]
    assert ctx.count(ctx.domain(names), names) == 3**120
