"""The coupled paper model at scale (issue 15): the positioners' variable order.

The order of the positioners' variable blocks changes BDD sizes and times only: every
result (states, transitions, marked, CCC verdict, rank, witness) must be the same under
every order, and equal to the explicit twin's and libFAUDES's where those finish.  The
bandwidth order must actually give saturation more than one event cluster (in layout
order every event's top level is the centre's, so saturation was chaining).  No timings
here: benchmarks/bench_coupled.py measures them.
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
from supcoord.synthesis.product import product
from supcoord.synthesis.reachability import ImageProfile, reachable


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


def test_every_order_gives_the_same_results_on_five_positioners():
    """Beyond the explicit twin's reach (5 positioners, 6 steps): the orders agree."""
    model = _model(5, 6, 0)
    assert _results(model, "layout") == _results(model, "auto")


def test_run_paper_coupled_uses_the_bandwidth_order_and_the_same_answers():
    r = run_paper(4, 6, model="coupled", seed=0)
    assert next(v for v in r.G.ctx.vars if v.startswith("pos")) == f"pos{positioner_order(_model(4, 6))[0] + 1}"
    assert r.payload["supervisor_states"] == _results(_model(4, 6), "layout")[0]


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
