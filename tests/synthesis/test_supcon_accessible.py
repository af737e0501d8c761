"""``accessible_part`` of a supervisor computed on the whole state space: the supervisor's
name, and its ``seconds`` the first run's plus the time the accessible part took (bounded
by the time measured around the call, not a speed assertion)."""

from __future__ import annotations

import time

import pytest

from supcoord.bdd import Context
from supcoord.des.generator import Event, Generator
from supcoord.des.symbolic import from_explicit
from supcoord.synthesis import METHODS, accessible_part, supcon

# a counter the specification caps at 2: 0 -a-> 1 -a-> 2 -a-> 3, every state -u-> 0 (u uncontrollable)
PLANT = Generator(4, [Event("a", True), Event("u", False)],
                  [(0, "a", 1), (1, "a", 2), (2, "a", 3)] + [(q, "u", 0) for q in range(4)], 0, [0], "P")
SPEC = Generator(3, [Event("a", True), Event("u", False)],
                 [(0, "a", 1), (1, "a", 2)] + [(q, "u", 0) for q in range(3)], 0, [0], "E")


@pytest.mark.parametrize("method", METHODS)
def test_the_accessible_part_keeps_the_name_and_adds_its_time(method):
    ctx = Context()
    whole = supcon(from_explicit(ctx, PLANT), from_explicit(ctx, SPEC), name="SUP", method=method, accessible=False)
    before = time.perf_counter()
    trim = accessible_part(whole, method=method)
    took = time.perf_counter() - before
    assert trim.supervisor.name == "SUP"
    assert trim.stats["states"] == 3 and trim.stats["accessible"] is True
    assert whole.stats["seconds"] < trim.stats["seconds"] <= whole.stats["seconds"] + took
