"""The default fixpoint schedule is never far from the best one (issue 38).

Measured in CUDD's computed-table lookups (``SupconResult.effort.work``: the main
manager's and the local closures' scratch manager's), which count the recursive steps of
the BDD operations and are the same on every machine: the default ``supcon`` may take at
most ``MAX_RATIO`` × the work of the best of ``bfs``, ``chaining`` and saturation over
the plain steps, on every small instance of the benchmark families (in the declaration
order of ``families.to_symbolic``, where ``machine_line(8)``'s closure once took 120
million lookups) and the classic models.  ``benchmarks/bench_default_vs_best.py`` runs
the same comparison in seconds on larger sizes.
"""

from __future__ import annotations

import pytest

from supcoord.bdd import Context
from supcoord.des import classic, families, symbolic_ops
from supcoord.synthesis import reachability as R
from supcoord.synthesis.closures import _closures, local_closures, work_done
from supcoord.synthesis.effort import EffortMeter
from supcoord.synthesis.image_step import event_steps
from supcoord.synthesis.product import product
from supcoord.synthesis.supcon import lift_spec, supcon

MAX_RATIO = 3
SMALL = [("machine_line", n) for n in range(1, 10)] + [
    ("transfer_line_chain", 1), ("transfer_line_chain", 2), ("dining_philosophers", 3), ("dining_philosophers", 5),
    ("small_factories", 2), ("coupled_factories", 2), ("coupled_factories", 3)]


def _models(ctx: Context, plants, specs):
    G, E = families.to_symbolic(ctx, plants, specs)
    return G, (lift_spec(G, E) if E is not None else symbolic_ops.allevents(ctx, G))


def _work(plants, specs, method: str, monkeypatch) -> tuple[int, int]:
    """``(states, lookups)`` of one supcon; ``plain`` is saturation without local closures."""
    monkeypatch.setattr(R, "LOCAL_CLOSURES", method != "plain")
    ctx = Context()
    G, E = _models(ctx, plants, specs)
    res = supcon(G, E, method="saturation" if method in ("plain", "default") else method, count_transitions=False)
    assert res.effort.work is not None  # CUDD's counters are read
    return res.stats["states"], res.effort.work


def _check(plants, specs, monkeypatch) -> None:
    work = {m: _work(plants, specs, m, monkeypatch) for m in ("bfs", "chaining", "plain", "default")}
    assert len({states for states, _ in work.values()}) == 1  # every schedule: the same supervisor
    best = min(w for _, w in work.values())
    assert work["default"][1] <= MAX_RATIO * best, {m: w for m, (_, w) in work.items()}


def _whole_relation(ctx: Context, P):
    """The written bits of all of ``P``'s steps and their one relation ``⋁_σ R_σ ∧ I_{W \\ W_σ}``."""
    steps = event_steps(P, None, True)
    writes = sorted(frozenset().union(*(s.writes for s in steps)))
    rel = ctx.false
    for s in steps:
        rel |= s.relation & ctx.identity(sorted(set(writes) - s.writes))
    return writes, rel


@pytest.mark.parametrize("family,size", SMALL)
def test_default_within_three_times_the_best_work(family, size, monkeypatch):
    _check(*families.FAMILIES[family](size), monkeypatch)


@pytest.mark.parametrize("name", ["small_factory", "transfer_line", "cat_mouse",
                                  pytest.param("agv", marks=pytest.mark.slow)])  # agv: ~10 s
def test_default_within_three_times_the_best_work_on_classic_models(name, monkeypatch):
    m = classic.load(name)
    _check(m.plants, m.specs, monkeypatch)


def test_closure_work_limit_abandons_and_reports():
    """A closure over its work bound is abandoned (``None``: the plain steps), reported to
    the effort meter, and the closure within the bound is the same as unbounded."""
    ctx = Context()
    P = product(*_models(ctx, *families.machine_line(7)))
    writes, rel = _whole_relation(ctx, P)
    bits = ctx.bits(writes)
    with EffortMeter(ctx) as meter:
        free = _closures(ctx, [(bits, rel)])
    used = meter.result().closure_lookups
    with EffortMeter(ctx) as meter:
        bounded = _closures(ctx, [(bits, rel)], max_work=used // 100)
    effort = meter.result()
    assert free[0] is not None and bounded == [None]
    assert effort.closures_built == 0 and effort.closures_abandoned == 1
    assert used // 100 < effort.closure_lookups < used // 2  # stopped soon after its bound
    roomy = _closures(ctx, [(bits, rel)], max_work=2 * used)  # (the count varies a little with CUDD's GC)
    assert roomy[0] == free[0]


def test_single_write_group_keeps_its_steps():
    """One write group holding every step (a machine line): no closure is attempted."""
    ctx = Context()
    P = product(*_models(ctx, *families.machine_line(5)))
    steps = event_steps(P, None, True)
    before = work_done(ctx)
    with EffortMeter(ctx) as meter:
        out = local_closures(ctx, steps, P.invariant)
    assert [s.event for s in out] == [s.event for s in steps]
    assert meter.result().closures_built == 0 and work_done(ctx) >= before


def test_no_scratch_manager_means_the_plain_steps(monkeypatch):
    """Under a memory cap a second CUDD manager may not be had (``RuntimeError`` from
    ``dd.cudd.BDD``): every closure is abandoned, reported, and the reachable set is the same."""
    import dd.cudd

    ctx = Context()
    P = product(*_models(ctx, *families.machine_line(4)))
    writes, rel = _whole_relation(ctx, P)
    expected = R.reachable(P, method="saturation")

    def no_manager(*args, **kwargs):
        raise RuntimeError("failed to initialize CUDD DdManager")

    monkeypatch.setattr(dd.cudd, "BDD", no_manager)
    with EffortMeter(ctx) as meter:
        assert _closures(ctx, [(ctx.bits(writes), rel), (ctx.bits(writes), rel)]) == [None, None]
    assert meter.result().closures_abandoned == 2
    assert R.reachable(P, method="saturation") == expected
