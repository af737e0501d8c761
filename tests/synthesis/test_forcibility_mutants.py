"""The result of ``bfa`` in full (its winning set and whether it is complete), and the
explicit witness twin's default semantics, against the explicit twins and hand-written values.

Written for survivors of a uniform sample of ``forcibility.py``/``witness.py``'s mutants
(``benchmarks/mutation_run.py --sample 40 --seed 0 forcibility``): the tests of ``bfa`` read
its layers and ranks only, never ``winning`` or ``complete``; no test called
``forcing_paths_naive`` without naming the semantics."""

from __future__ import annotations

import pytest

from supcoord.bdd import Context
from supcoord.des.generator import Event, Generator
from supcoord.des.symbolic import from_explicit
from supcoord.synthesis import bfa
from supcoord.synthesis.forcibility import as_states, bfa_naive
from supcoord.synthesis.witness import forcing_paths_naive

# 0 -u1-> 2, 0 -u2-> 1, 1 -c-> 2 (target 2): from 0 the environment moves, then the controller
G3 = Generator(3, [Event("u1", False), Event("u2", False), Event("c", True)],
               [(0, "u1", 2), (0, "u2", 1), (1, "c", 2)], 0, [2], "env")


def _states(G, u) -> set[int]:
    return {q for q in range(3) if G.ctx.eq("env", q) & u != G.ctx.false}


@pytest.mark.parametrize("semantics,source", [("preemptive", 0), ("standard", 1), ("preemptive", 1)])
def test_bfa_of_a_forcible_source_is_complete_and_wins_its_layers(semantics, source):
    G = from_explicit(Context(), G3)
    res = bfa(G, source, as_states(G, 2), semantics=semantics)
    want = bfa_naive(G3, source, [2], semantics)
    assert [_states(G, layer) for layer in res.layers] == want
    assert res.complete is True
    assert _states(G, res.winning) == set().union(*want)


def test_bfa_of_a_source_that_is_not_forcible_is_complete_and_wins_nothing():
    G = from_explicit(Context(), G3)
    res = bfa(G, 0, as_states(G, 2), semantics="standard")
    assert bfa_naive(G3, 0, [2], "standard") == [] and res.layers == []
    assert res.complete is True  # the fixpoint ran to its end without meeting the source
    assert res.winning == G.ctx.false


def test_forcing_paths_naive_defaults_to_the_preemptive_semantics():
    layers = bfa_naive(G3, 0, [2])
    assert forcing_paths_naive(G3, layers, 0) == forcing_paths_naive(G3, layers, 0, "preemptive")
    assert forcing_paths_naive(G3, layers, 0) == [["u1"], ["u2", "c"]]
