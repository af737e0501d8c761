"""Explicit vs symbolic generators: conversion, sync, meet, allevents, selfloop agree."""

import pytest
from hypothesis import given
from hypothesis import strategies as st
from strategies import alphabets, generators

from supcoord.bdd import Context
from supcoord.des import explicit_ops as X
from supcoord.des import symbolic_ops as S
from supcoord.des.generator import Event, Generator, tct_event
from supcoord.des.symbolic import from_explicit, to_explicit
from supcoord.errors import AlphabetError, InputError, NondeterminismError


@st.composite
def components(draw, k_max=3):
    alphabet = draw(alphabets())
    k = draw(st.integers(1, k_max))
    return [draw(generators(alphabet, 5, f"G{i}")) for i in range(k)]


@pytest.mark.slow  # 200 random products of up to three generators: seconds
@given(components())
def test_symbolic_sync_equals_explicit(gens):
    ctx = Context()
    product = S.sync(*[from_explicit(ctx, g) for g in gens])
    assert to_explicit(product).same_as(X.sync(*gens))


@pytest.mark.slow  # 200 random generators through the symbolic form: seconds
@given(components(k_max=1))
def test_round_trip(gens):
    (g,) = gens
    ctx = Context()
    sg = from_explicit(ctx, g)
    back = to_explicit(sg)
    assert back.same_as(g)
    reach = X.accessible_states(g)
    assert back.n_states == len(reach)


@pytest.mark.slow  # 200 random pairs of generators: seconds
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


def test_meet_needs_equal_alphabets(bdd_backend):
    a = Generator(1, [Event("a", True)], [])
    b = Generator(1, [Event("b", True)], [])
    with pytest.raises(AlphabetError):
        X.meet(a, b)
    ctx = Context(bdd_backend)
    with pytest.raises(AlphabetError):
        S.meet(from_explicit(ctx, a), from_explicit(ctx, b))


def test_exact_count_beyond_double_precision(bdd_backend):
    ctx = Context(bdd_backend)
    names = [ctx.add_variable(f"y{i}", 3).name for i in range(120)]
    assert ctx.count(ctx.domain(names), names) == 3**120


@st.composite
def random_predicates(draw):
    """A random Boolean function over the bits of a few finite-domain variables, given
    as a union of random partial assignments (cubes), and a care set containing its support."""
    sizes = draw(st.lists(st.integers(1, 7), min_size=1, max_size=4))
    cubes = draw(st.lists(st.lists(st.tuples(st.integers(0, len(sizes) - 1), st.integers(0, 8)), max_size=3),
                          max_size=6))
    negate = draw(st.booleans())
    return sizes, cubes, negate


@given(random_predicates())
def test_count_in_c_equals_python_walk(case):
    """CUDD's arbitrary-precision count (through the validated C layout) == the pure
    Python DAG walk, for unions of cubes, their complements and several care sets."""
    from supcoord.bdd.context import exact_count

    sizes, cubes, negate = case
    ctx = Context()
    names = [ctx.add_variable(f"v{i}", n).name for i, n in enumerate(sizes)]
    assert ctx.fast_count  # dd 0.6.0: the C path is active (a dd with another layout must fail here, not slow down silently)
    u = ctx.false
    for cube in cubes:
        values = {names[i]: x % sizes[i] for i, x in cube}
        u |= ctx.assignment(values)
    if negate:
        u = ~u & ctx.domain(names)
    care = ctx.bits(names)
    assert ctx.count(u, names) == exact_count(ctx.bdd, u, care)
    brute = sum(1 for _ in ctx.enumerate(u, names))
    assert ctx.count(u, names) == brute


def test_count_in_c_with_unused_declared_bits_and_primes():
    ctx = Context()
    ctx.add_variable("a", 5)
    ctx.add_variable("b", 300)
    ctx.add_variable("unused", 1000)
    u = ctx.less_than("a", 3) & ctx.less_than("b", 290, primed=True)
    assert ctx.fast_count
    assert ctx.count(u, ["a"], ["b"]) == 3 * 290 * 2 ** 0
    assert ctx.count(u, ["a", "unused"], ["b"]) == 3 * 290 * 2**10
    assert ctx.count(ctx.true, ["a"]) == 8 and ctx.count(ctx.false, ["a"]) == 0
    assert ctx.count(ctx.less_than("a", 3), ["a", "a"]) == 3  # a variable named twice counts once
    big = [ctx.add_variable(f"y{i}", 3).name for i in range(400)]
    assert ctx.count(ctx.domain(big), big) == 3**400


def test_live_nodes_in_c_equal_dd_statistics():
    ctx = Context()
    names = [ctx.add_variable(f"x{i}", 7).name for i in range(12)]
    keep = ctx.domain(names) & ~ctx.eq("x3", 2)
    assert ctx.fast_count and ctx.live_nodes() == ctx.statistics()["n_nodes"] > ctx.node_count(keep)
    slow = Context("autoref")
    slow.add_variable("y", 5)
    assert not slow.fast_count and slow.live_nodes() == len(slow.bdd)
