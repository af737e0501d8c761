"""``guards.table_bdd`` against the plain definition: the OR of one cube per TRUE entry.

The tables of at least ``ROW_SPLIT_BITS`` bits are reduced row by row (distinct rows of the
upper half once each); both routes, and both relative orders of the two variables'
blocks, must give the very BDD of the definition.
"""

import numpy as np
import pytest

from supcoord.bdd.context import Context
from supcoord.planning import guards
from supcoord.planning.guards import table_bdd


def _by_cubes(ctx, table, names):
    out = ctx.false
    for idx in zip(*np.nonzero(table)):
        out |= ctx.assignment({n: int(v) for n, v in zip(names, idx)})
    return out


@pytest.mark.timeout(120)
@pytest.mark.parametrize("split", [guards.ROW_SPLIT_BITS, 99])
def test_table_bdd_is_the_or_of_its_true_entries(split, monkeypatch):
    monkeypatch.setattr(guards, "ROW_SPLIT_BITS", split)
    rng = np.random.default_rng(split)
    shape = (9, 7, 9, 7)  # 4 + 3 + 4 + 3 bits: the row split applies from 12
    for order in (("a0", "b0", "a1", "b1"), ("a1", "b1", "a0", "b0"), ("a0", "a1", "b0", "b1")):
        ctx = Context("auto")
        for name in order:
            ctx.add_variable(name, 9 if name.startswith("a") else 7)
        names = ["a0", "b0", "a1", "b1"]
        for density in (0.0, 0.05, 0.5, 0.97, 1.0):
            table = rng.random(shape) < density
            if density == 0.5:  # repeated rows, as in a pair guard
                table[1] = table[0]
                table[4, 2] = table[7, 6]
            assert table_bdd(ctx, table, names) == _by_cubes(ctx, table, names), (order, density)
        # one variable, and a table smaller than its codes
        small = rng.random((9,)) < 0.5
        assert table_bdd(ctx, small, ["a0"]) == _by_cubes(ctx, small, ["a0"])
        part = rng.random((5, 7, 9, 2)) < 0.5
        assert table_bdd(ctx, part, names) == _by_cubes(ctx, part, names)
