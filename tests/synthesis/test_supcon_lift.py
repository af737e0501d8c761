"""``lift_spec``: the specification's name kept or replaced as asked, and a refusal of
what is not a generator that names its type and carries it."""

from __future__ import annotations

import pytest

from supcoord.bdd import Context
from supcoord.des.generator import Event, Generator
from supcoord.des.symbolic import from_explicit
from supcoord.errors import InputError
from supcoord.synthesis import lift_spec

PLANT = Generator(2, [Event("a", True), Event("u", False)], [(0, "a", 1), (1, "u", 0)], 0, [0], "P")
SPEC = Generator(1, [Event("a", True)], [(0, "a", 0)], 0, [0], "E")


@pytest.mark.parametrize("symbolic", [False, True])
def test_the_lifted_spec_keeps_its_name_unless_given_one(symbolic):
    ctx = Context()
    plant, spec = (from_explicit(ctx, PLANT), from_explicit(ctx, SPEC)) if symbolic else (PLANT, SPEC)
    kept = lift_spec(plant, spec)
    assert kept.name == "E" and set(kept.events) >= {"a", "u"}
    assert lift_spec(plant, spec, "lifted").name == "lifted"
    assert type(kept) is type(spec)


@pytest.mark.parametrize("bad", ["E", 3, None])
def test_lift_spec_refuses_what_is_not_a_generator(bad):
    with pytest.raises(InputError) as info:
        lift_spec(PLANT, bad)
    assert f"got {type(bad).__name__}" in str(info.value)
    assert info.value.value is bad
