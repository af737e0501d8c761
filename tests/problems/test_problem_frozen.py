"""A parsed Problem is immutable: assignment is refused, arrays are read-only, replace makes a copy."""

import dataclasses

import numpy as np
import pytest

from supcoord.problems import parse_problem
from supcoord.problems.plan import exchanged

ROTARY = {
    "layout": {"kind": "hex", "rings": 1, "pitch": 22.4},
    "kinematics": {"kind": "rotary", "arm": 15.0, "steps": 12},
    "collision": {"buffer": 2.0},
    "start": [0, 0, 0, 0, 0, 0, 0],
    "target": [6, 6, 6, 6, 6, 6, 6],
}


@pytest.mark.parametrize("name, value", [("target", np.zeros((7, 1), int)), ("kinematics", None),
                                         ("priority", [7, 6, 5, 4, 3, 2, 1]), ("warnings", []), ("margin", 1.0),
                                         ("_tables", None), ("something_new", 1)])
def test_setting_an_attribute_on_a_parsed_problem_raises(name, value):
    p = parse_problem(ROTARY)
    before = p.to_json()
    with pytest.raises(dataclasses.FrozenInstanceError, match=f"immutable: cannot set '{name}'"):
        setattr(p, name, value)
    with pytest.raises(dataclasses.FrozenInstanceError):
        delattr(p, "target")
    assert p.to_json() == before and not hasattr(p, "something_new")


def test_arrays_are_read_only_and_replace_makes_a_changed_copy():
    p = parse_problem(ROTARY)
    with pytest.raises(ValueError, match="read-only"):
        p.start[0, 0] = 3
    q = dataclasses.replace(p, target=np.full((7, 1), 3))
    assert q.target[0, 0] == 3 and p.target[0, 0] == 6 and not q.target.flags.writeable
    with pytest.raises(dataclasses.FrozenInstanceError):
        q.start = p.target


def test_lazy_tables_are_still_computed_once_and_exchange_keeps_them():
    p = parse_problem(ROTARY)
    assert p.tables() is p.tables() and p.pairs is p.pairs and p.unary() is p.unary()
    back = exchanged(p)
    assert np.array_equal(back.start, p.target) and np.array_equal(back.target, p.start)
    assert back.tables() is p.tables() and np.array_equal(p.start, np.zeros((7, 1)))
    with pytest.raises(dataclasses.FrozenInstanceError):
        back.target = p.target
