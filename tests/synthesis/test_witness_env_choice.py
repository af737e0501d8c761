"""The environment's choice in a witness, where the three rules disagree.

State 0 has only uncontrollable events (under preemptive semantics the environment acts
there): ``u1`` and ``u3`` lead into the target at once, ``u2`` to state 1, from which the
controller forces ``c`` into the target.  So the smallest name gives ``[u1]``, the largest
``[u3]`` and the worst case (highest rank reached, ties by name) ``[u2, c]``; the symbolic
witness and its explicit twin must both say so, with the documented defaults (preemptive,
smallest) when nothing is asked.
"""

from __future__ import annotations

import pytest

from supcoord.bdd import Context
from supcoord.des.generator import Event, Generator
from supcoord.des.symbolic import from_explicit
from supcoord.synthesis import forcible_layers, forcible_layers_naive, witness
from supcoord.synthesis.forcibility import as_states
from supcoord.synthesis.witness import witness_naive

EVENTS = [Event("u1", False), Event("u2", False), Event("u3", False), Event("c", True)]
G3 = Generator(3, EVENTS, [(0, "u1", 2), (0, "u2", 1), (0, "u3", 2), (1, "c", 2)], 0, [2], "env")
WANT = {"smallest": ["u1"], "largest": ["u3"], "worst": ["u2", "c"]}


@pytest.mark.parametrize("env_choice", sorted(WANT))
def test_each_environment_choice_picks_its_event(env_choice):
    semantics = "preemptive"
    G = from_explicit(Context(), G3)
    layers = forcible_layers(G, as_states(G, 2), semantics=semantics)
    naive = forcible_layers_naive(G3, [2], semantics)
    assert witness(G, layers, 0, env_choice=env_choice) == WANT[env_choice]
    assert witness_naive(G3, naive, 0, semantics, env_choice) == WANT[env_choice]


def test_the_defaults_are_preemptive_and_the_smallest_name():
    G = from_explicit(Context(), G3)
    assert witness(G, forcible_layers(G, as_states(G, 2)), 0) == ["u1"]
    assert witness_naive(G3, forcible_layers_naive(G3, [2]), 0) == ["u1"]
