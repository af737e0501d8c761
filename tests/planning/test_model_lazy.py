"""The coordination model declares a positioner's variables when first used, at its place in the
order: every BDD is the one of a manager that declared all positioners up front."""

from __future__ import annotations

import pytest

from supcoord.errors import ModelError
from supcoord.planning.model import CoordinationModel
from supcoord.problems.presets import preset_problem

pytest.importorskip("dd.cudd", reason="lazy declaration inserts variables at a level, which CUDD offers")


def _problem():
    return preset_problem("desi", rings=3, seed=1, alpha_steps=13, beta_steps=7)


def _levels(model):
    bdd = model.ctx.bdd
    return sorted(model.ctx.vars, key=lambda v: bdd.level_of_var(model.ctx.vars[v].bits[0]))


def test_nothing_is_declared_until_used_and_then_in_the_models_order():
    p = _problem()
    lazy = CoordinationModel(p, backend="cudd")
    assert lazy.declared == 0 and not lazy.ctx.vars
    members = [lazy.order[5], lazy.order[1], lazy.order[3]]
    lazy.system(members, p.start)
    assert lazy.declared == 3
    declared = [q for q in lazy.order if q in members]
    assert _levels(lazy) == [f"{c}{q}" for q in declared for c in "ab"]
    assert lazy.ctx.bdd.var_levels == {b: i for i, b in enumerate(
        bit for v in _levels(lazy) for pair in zip(lazy.ctx.vars[v].bits, lazy.ctx.vars[v].primed_bits) for bit in pair)}


def test_guards_and_systems_equal_those_of_a_model_declaring_everything_up_front():
    p = _problem()
    lazy, eager = CoordinationModel(p, backend="cudd"), CoordinationModel(p, backend="cudd")
    for q in eager.order:
        eager.declare(q)
    assert eager.declared == p.n
    for q in reversed(lazy.order[::3]):  # declared in an order other than the model's
        lazy.declare(q)
    for pp in range(p.n):
        for k, q, side in lazy.adj[pp][:2]:
            g_lazy, g_eager = lazy.pair_guard(pp, 0, k, q, side), eager.pair_guard(pp, 0, k, q, side)
            assert len(g_lazy) == len(g_eager)
            assert lazy.ctx.bdd.to_expr(g_lazy) == eager.ctx.bdd.to_expr(g_eager)
    members = lazy.order[:4]
    s_lazy, s_eager = lazy.system(members, p.start), eager.system(members, p.start)
    assert s_lazy.variables == s_eager.variables
    for ev in s_lazy.moves:
        assert [len(g) for g in s_lazy.moves[ev].guards] == [len(g) for g in s_eager.moves[ev].guards]


def test_a_positioner_outside_a_window_model_is_refused():
    p = _problem()
    window = CoordinationModel(p, backend="cudd", members=[0, 1], order="cutwidth")
    with pytest.raises(ModelError):
        window.declare(5)
