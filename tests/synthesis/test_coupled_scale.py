"""The coupled paper model at scale (issue 15): the positioners' variable order.

The order of the positioners' variable blocks changes BDD sizes and times only: every
result (states, transitions, marked, CCC verdict, rank, witness) must be the same under
every order, and equal to the explicit twin's and libFAUDES's where those finish.  The
bandwidth order must actually give saturation more than one event cluster (in layout
order every event's top level is the centre's, so saturation was chaining).  The local
closures of saturation (a positioner's write group fired by its transitive closure) must
give the plain steps' results too.  No timings here: benchmarks/bench_coupled.py
measures them.
"""

from __future__ import annotations

import pytest
from oracle import faudes_supcon

from supcoord.bdd import Context
from supcoord.bdd.ordering import bandwidth
from supcoord.errors import InputError
from supcoord.paper.coupled import (
    ORDERS,
    CoupledModel,
    coupled_models,
    coupled_models_explicit,
    positioner_order,
)
from supcoord.paper.literal import paper_example
from supcoord.paper.run import coupled_instance, run_paper
from supcoord.synthesis import ccc, event_clusters, supcon, supcon_naive
from supcoord.synthesis.image_step import event_steps
from supcoord.synthesis.product import product
from supcoord.synthesis.reachability import ImageProfile, coreachable, reachable


def _model(size: int, steps: int = 8, seed: int = 0) -> CoupledModel:
    return CoupledModel(coupled_instance(size, steps, seed))


@pytest.mark.parametrize("size", [1, 2, 3, 4, 5, 7, 12, 19, 37])
def test_orders_are_permutations_and_auto_never_widens_the_bandwidth(size):
    model = _model(size)
    layout = positioner_order(model, "layout")
    assert layout == list(range(size))
    for order in ORDERS:
        assert sorted(positioner_order(model, order)) == layout
    auto = positioner_order(model, "auto")
    assert bandwidth(model.neighbours, auto) <= bandwidth(model.neighbours, layout)
    if size >= 4:  # the centre and a partial ring: Cuthill–McKee is strictly narrower
        assert bandwidth(model.neighbours, auto) < bandwidth(model.neighbours, layout)
        assert auto == positioner_order(model, "bandwidth")


def test_auto_keeps_the_layout_order_where_every_order_is_as_narrow():
    """Three mutual neighbours (the paper's example): the layout order and its BDDs stay."""
    model = CoupledModel(paper_example())
    assert positioner_order(model) == [0, 1, 2]
    r = supcon(*coupled_models(model, Context()))
    assert r.stats["bdd_nodes"] == 1948  # docs/paper.md §4


def test_unknown_order_is_a_user_error():
    with pytest.raises(InputError) as e:
        positioner_order(_model(3), "spiral")
    assert e.value.value == "spiral"
    with pytest.raises(InputError):
        bandwidth([[1], [0]], [0, 0])


@pytest.mark.parametrize("size", [5, 7, 19])
def test_bandwidth_order_gives_saturation_more_than_one_cluster(size):
    """In layout order every event reads the centre (or a first-ring positioner declared
    near the top): one or a few clusters.  Cuthill–McKee spreads the events' top levels."""
    ctx_a, ctx_b = Context(), Context()
    model = _model(size)
    layout = event_clusters(product(*coupled_models(model, ctx_a, order="layout")))
    auto = event_clusters(product(*coupled_models(model, ctx_b, order="auto")))
    if size <= 7:
        assert len(layout) == 1  # the degenerate case issue 15 measured
    assert len(auto) > len(layout)
    assert sorted(e for c in auto for e in c) == sorted(e for c in layout for e in c)


def _results(model: CoupledModel, order: str) -> tuple:
    ctx = Context()
    G, E = coupled_models(model, ctx, order=order)
    r = supcon(G, E)
    c = ccc(r.supervisor, "preemptive", full=False)
    return (r.stats["states"], r.stats["transitions"], r.stats["marked"], c.forcible, c.rank, tuple(c.witness))


@pytest.mark.parametrize("size, steps, seed", [(2, 8, 1), (3, 8, 0), (3, 6, 2), (4, 4, 0)])
def test_every_order_gives_the_explicit_twins_and_libfaudes_supervisor(size, steps, seed):
    model = _model(size, steps, seed)
    results = {order: _results(model, order) for order in ("layout", "bandwidth")}
    assert results["layout"] == results["bandwidth"]
    Gx, Ex = coupled_models_explicit(model)
    naive, oracle = supcon_naive(Gx, Ex), faudes_supcon(Gx, Ex)
    states, transitions, marked = results["layout"][:3]
    assert (naive.n_states, naive.n_transitions, len(naive.marked)) == (states, transitions, marked)
    assert (oracle.n_states, sum(1 for _ in oracle.transitions()), len(oracle.marked)) == (states, transitions, marked)
    forcible, rank, witness = results["layout"][3:]
    if forcible:
        assert oracle.run(list(witness)) in oracle.marked and len(witness) == rank


@pytest.mark.slow
def test_every_order_gives_the_same_results_on_five_positioners():
    """Beyond the explicit twin's reach (5 positioners, 6 steps): the orders agree."""
    model = _model(5, 6, 0)
    assert _results(model, "layout") == _results(model, "auto")


def test_run_paper_coupled_uses_the_bandwidth_order_and_the_same_answers():
    r = run_paper(4, 6, model="coupled", seed=0, route="monolithic")
    assert next(v for v in r.G.ctx.vars if v.startswith("pos")) == f"pos{positioner_order(_model(4, 6))[0] + 1}"
    assert r.payload["supervisor_states"] == _results(_model(4, 6), "layout")[0]


@pytest.mark.parametrize("size, seed", [(3, 0), (4, 1), pytest.param(5, 0, marks=pytest.mark.slow)])
def test_run_paper_coupled_decides_without_the_reachable_set(size, seed, monkeypatch):
    """The coupled route synthesizes V without Reach and runs CCC on it: the verdict,
    rank and witness of the trim supervisor; its sizes are counted up to
    AUTO_COUNT_COUPLED positioners (or on request) and equal the trim supervisor's."""
    import supcoord.paper.paper_routes as routes

    counted = run_paper(size, 6, model="coupled", seed=seed, route="monolithic")
    trim = _results(_model(size, 6, seed), "auto")
    assert counted.payload["counted"] is True and counted.supcon.stats["accessible"] is True
    assert (counted.payload["supervisor_states"], counted.payload["supervisor_transitions"],
            counted.payload["supervisor_marked"]) == trim[:3]
    assert (counted.payload["ccc"], counted.payload["rank"], tuple(counted.payload["witness"])) == trim[3:]
    assert counted.supervisor.count_states() == trim[0]
    monkeypatch.setattr(routes, "AUTO_COUNT_COUPLED", size - 1)
    quick = run_paper(size, 6, model="coupled", seed=seed, route="monolithic")
    assert quick.payload["counted"] is False and quick.payload["supervisor_states"] is None
    assert quick.payload["supervisor_states_log10"] is None and quick.payload["timings"]["count"] == 0
    assert (quick.payload["ccc"], quick.payload["rank"], quick.payload["witness"]) == (
        counted.payload["ccc"], counted.payload["rank"], counted.payload["witness"])
    assert quick.supervisor.count_states() >= trim[0]  # unreachable states kept
    asked = run_paper(size, 6, model="coupled", seed=seed, count_states=True)
    assert asked.payload["supervisor_states"] == trim[0]


def test_image_profile_counts_the_images_and_changes_nothing():
    model = _model(4, 6)
    ctx = Context()
    G, E = coupled_models(model, ctx)
    P = product(G, E)
    plain = reachable(P)
    with ImageProfile(nodes=True) as outer, ImageProfile() as inner:
        profiled = reachable(P)
    assert profiled == plain
    assert outer.images == inner.images > 0
    assert sum(n for n, _ in outer.by_event.values()) == outer.images
    assert outer.max_operand >= ctx.node_count(plain) > 0 and outer.max_result > 0
    assert set(outer.as_dict()) == {"images", "image_seconds", "max_operand_nodes", "max_result_nodes"}
    assert set(inner.as_dict()) == {"images", "image_seconds"}
    before = outer.images
    reachable(P)  # inactive again: nothing recorded
    assert outer.images == before


# -- local closures (issue 15): the accelerated saturation against the plain steps ----------


def _results_with(model: CoupledModel, closures: bool, monkeypatch) -> tuple:
    from supcoord.synthesis import reachability as R

    monkeypatch.setattr(R, "LOCAL_CLOSURES", closures)
    return _results(model, "auto")


@pytest.mark.timeout(120)
@pytest.mark.parametrize("size, seed", [(3, 0), (3, 1), (4, 0), (4, 1)])
def test_local_closures_give_the_plain_steps_supervisor_and_ccc(size, seed, monkeypatch):
    """States, transitions, marked, CCC verdict, rank and witness: equal with and without
    the local closures (N = 3, 4; two seeds); N = 3 also equal to the explicit twin."""
    model = _model(size, 8, seed)
    new = _results_with(model, True, monkeypatch)
    assert new == _results_with(model, False, monkeypatch)
    if size == 3:
        naive = supcon_naive(*coupled_models_explicit(model))
        assert (naive.n_states, naive.n_transitions, len(naive.marked)) == new[:3]


@pytest.mark.timeout(60)
def test_local_closures_fire_one_step_per_positioner_and_fewer_images():
    """Each positioner's events and its specification's (``pos, lvl, cnt``) form one write
    group, fired by its closure; the reachable set is the same with fewer images."""
    from supcoord.synthesis import reachability as R

    model = _model(4, 8, 0)
    ctx = Context()
    P = product(*coupled_models(model, ctx))
    plain = event_steps(P, None, True)
    steps = R.local_closures(ctx, plain, P.invariant)
    assert len(steps) == 4 and all(not s.clip for s in steps)
    assert sorted(sorted(s.writes) for s in steps) == [[f"cnt{i}", f"lvl{i}", f"pos{i}"] for i in range(1, 5)]
    assert sorted(e for s in steps for e in s.event.split("|")) == sorted(s.event for s in plain)
    try:
        R.LOCAL_CLOSURES = False
        with ImageProfile() as old:
            before = reachable(P)
    finally:
        R.LOCAL_CLOSURES = True
    with ImageProfile() as new:
        after = reachable(P)
    assert after == before
    assert new.images < old.images


@pytest.mark.timeout(30)
def test_a_group_leaving_the_invariant_keeps_its_plain_steps():
    """``0 → 3`` leaves ``Q = {0, 1, 2}`` and ``3 → 1`` comes back: a closure through the
    invalid code would reach ``1``; the guard ``Img(Q) ⊆ Q`` keeps the plain steps."""
    from supcoord.des.generator import Event
    from supcoord.des.symbolic import EventRelation, SymbolicGenerator
    from supcoord.synthesis import reachability as R

    ctx = Context()
    ctx.add_variable("x", 3)  # two bits, code 3 invalid
    three, three_p = ctx.cube({"x_1": True, "x_0": True}), ctx.cube({"x_1'": True, "x_0'": True})
    rel = (ctx.eq("x", 0) & three_p) | (three & ctx.eq("x", 1, primed=True))
    rel2 = ctx.eq("x", 1) & ctx.eq("x", 2, primed=True)
    events = {"a": EventRelation(Event("a", True), rel, ("x",)), "b": EventRelation(Event("b", True), rel2, ("x",))}
    G = SymbolicGenerator(ctx, "G", ("x",), events, ctx.eq("x", 0), ctx.eq("x", 2), ctx.domain(["x"]))
    assert reachable(G) == ctx.eq("x", 0)
    assert coreachable(G) == ctx.eq("x", 2) | ctx.eq("x", 1)
    steps = R.local_closures(ctx, event_steps(G, None, True), G.invariant)
    assert [s.event for s in steps] == ["a", "b"] and steps[0].clip and not steps[1].clip
