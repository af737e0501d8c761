"""``bfa`` and its explicit twin on a state where only the environment acts: forcible under
preemptive semantics (the default), not under standard semantics (the controller has no
event there)."""

from __future__ import annotations

import pytest

from supcoord.bdd import Context
from supcoord.des.generator import Event, Generator
from supcoord.des.symbolic import from_explicit
from supcoord.synthesis import bfa
from supcoord.synthesis.forcibility import as_states, bfa_naive

# 0 -u1-> 2, 0 -u2-> 1, 1 -c-> 2 (target 2): from 0 the environment moves, then the controller
EVENTS = [Event("u1", False), Event("u2", False), Event("c", True)]
G3 = Generator(3, EVENTS, [(0, "u1", 2), (0, "u2", 1), (1, "c", 2)], 0, [2], "env")
LAYERS = [{2}, {1}, {0}]


def test_the_default_semantics_is_preemptive_in_both():
    assert bfa_naive(G3, 0, [2]) == LAYERS == bfa_naive(G3, 0, [2], "preemptive")
    G = from_explicit(Context(), G3)
    dag = bfa(G, 0, as_states(G, 2))
    assert dag.rank(0) == 2


def test_under_standard_semantics_the_environments_state_is_not_forcible():
    assert bfa_naive(G3, 0, [2], "standard") == []
    assert bfa_naive(G3, 1, [2], "standard") == [{2}, {1}]
    G = from_explicit(Context(), G3)
    assert bfa(G, 0, as_states(G, 2), semantics="standard").layers == []


@pytest.mark.parametrize("order", [0, 1])
def test_every_branch_is_followed_past_a_target_state(order):
    """0 -u1-> 2 (target), 0 -u2-> 1 -c-> 3 (target): both targets are on the DAG, whichever
    of the environment's events is listed first."""
    events = [Event("u1", False), Event("u2", False), Event("c", True)]
    trans = [(0, "u1", 2), (0, "u2", 1), (1, "c", 3)]
    if order:
        events, trans = events[::-1], trans[::-1]
    g = Generator(4, events, trans, 0, [2, 3], "branches")
    assert bfa_naive(g, 0, [2, 3]) == [{2, 3}, {1}, {0}]
    G = from_explicit(Context(), g)
    dag = bfa(G, 0, as_states(G, 2) | as_states(G, 3))
    assert dag.rank(0) == 2 and dag.rank(3) == 0 and dag.rank(1) == 1
