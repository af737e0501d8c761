"""Quantification in a manager of many bits: kept cubes give the same sets as ``dd``'s own cubes.

:meth:`Context.and_exist` and :meth:`Context.exist` build the quantifier's cube once from the
bits' own nodes when the manager holds more than :data:`MANY_BITS` bits (``dd`` rebuilds it
from an array over every declared bit at each call).  Both ways must give the same BDD.
"""

import numpy as np
import pytest

import supcoord.bdd.context as context_module
from supcoord.bdd.context import Context


def _random_set(ctx: Context, rng: np.random.Generator, names: list[str], size: int):
    u = ctx.false
    for _ in range(int(rng.integers(1, 8))):
        term = ctx.true
        for n in rng.choice(names, size=int(rng.integers(1, 4)), replace=False):
            term &= ctx.eq(str(n), int(rng.integers(size)))
        u |= term
    return u


@pytest.mark.timeout(60)
def test_kept_cubes_quantify_like_dd(monkeypatch, bdd_backend):
    rng = np.random.default_rng(5)
    names = [f"x{i}" for i in range(8)]
    ctx = Context(bdd_backend)
    for n in names:
        ctx.add_variable(n, 6)
    for _ in range(200):
        u, v = _random_set(ctx, rng, names, 6), _random_set(ctx, rng, names, 6)
        q = [str(n) for n in rng.choice(names, size=int(rng.integers(1, 4)), replace=False)]
        monkeypatch.setattr(context_module, "MANY_BITS", 10**9)
        want = (ctx.and_exist(u, v, ctx.bits(q)), ctx.exist(q, u))
        monkeypatch.setattr(context_module, "MANY_BITS", 0)
        got = (ctx.and_exist(u, v, ctx.bits(q)), ctx.exist(q, u))
        assert got == want
        assert ctx.and_exist(u, v, ctx.bits(q)) == ctx.exist(q, u & v)
