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


def _guard_problems():
    from supcoord.geometry import AlphaBeta, Rotary
    from supcoord.problems.problem import parse_problem
    from supcoord.problems.random import random_problem

    rotary = Rotary(10.0, 9)
    yield random_problem({"kind": "hex", "rings": 2, "pitch": 15.0}, rotary, buffer=1.5, seed=3)
    ab = AlphaBeta(7.4, 15.0, 8, 5, (0.0, 180.0))
    yield random_problem({"kind": "hex", "rings": 2, "pitch": 22.4}, ab, buffer=2.0, seed=1)
    # every robot its own lattice (exact angles): pairs of equal offset differ in geometry
    bases = [[0.0, 0.0], [22.4, 0.0], [11.2, 19.4], [33.6, 19.4]]
    kin = {"kind": "alpha-beta", "alpha": 7.4, "beta": 15.0, "alpha_steps": 8, "beta_steps": 5, "beta_range": [0, 180]}
    yield parse_problem({"layout": {"kind": "points", "xy": bases}, "kinematics": kin, "collision": {"buffer": 2.0},
                         "start": {"alpha_beta_deg": [[10.0, 170.0]] * 4},
                         "target": {"alpha_beta_deg": [[200.0, 100.0], [300.0, 40.0], [95.0, 60.0], [5.0, 30.0]]}},
                        "p.json")


@pytest.mark.timeout(120)
@pytest.mark.parametrize("rename", [True, False])
def test_pair_guards_renamed_by_geometry_equal_their_own_tables(rename, monkeypatch):
    """``CoordinationModel.pair_guard`` builds one BDD per (pair geometry, side, move) and,
    on fine lattices (forced here), renames it for the other pairs of that geometry: each
    must equal the BDD of its own blocked table, in both relative orders of the two robots'
    variables."""
    from supcoord.planning import model as model_module
    from supcoord.planning.guards import blocked_table, conflict_graph, var_names
    from supcoord.planning.model import CoordinationModel

    monkeypatch.setattr(model_module, "RENAME_MIN_ENTRIES", 0 if rename else 2**62)

    for problem in _guard_problems():
        adj = conflict_graph(problem)
        shape = problem.kinematics.shape
        for order in ("rcm", "hex"):
            model = CoordinationModel(problem, order=order)
            seen_orders, renamed = set(), 0
            for p in range(problem.n):
                for k, q, side in adj[p]:
                    for m in range(len(model.moves)):
                        before = len(model._guard_by_geometry)
                        g = model.pair_guard(p, m, k, q, side)
                        renamed += len(model._guard_by_geometry) == before
                        table = ~blocked_table(problem, k, side)[m].reshape(shape + shape)
                        names = var_names(problem, p) + var_names(problem, q)
                        assert g == table_bdd(model.ctx, table, names), (p, q, m, side)
                    seen_orders.add(model.order.index(p) < model.order.index(q))
            assert seen_orders == {True, False}
            if problem.robot_kinematics is None and rename:
                assert renamed > len(model._guard_by_geometry)  # the renaming route was taken
            assert bool(model._guard_by_geometry) == rename
            # a window's own manager: the first guard of a geometry copied, the others renamed
            members = sorted({p for p in range(problem.n) if adj[p]})[:5]
            window = CoordinationModel(problem, order="cutwidth", members=members, guards_from=model)
            for p in members:
                for k, q, side in adj[p]:
                    if q in members:
                        for m in range(len(window.moves)):
                            table = ~blocked_table(problem, k, side)[m].reshape(shape + shape)
                            names = var_names(problem, p) + var_names(problem, q)
                            assert window.pair_guard(p, m, k, q, side) == table_bdd(window.ctx, table, names)
