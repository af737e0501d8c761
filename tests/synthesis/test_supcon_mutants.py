"""The statistics ``supcon`` documents, read back, and the explicit twin's default name.

Written for survivors of a uniform sample of ``supcon.py``'s mutants
(``benchmarks/mutation_run.py --sample 40 --seed 0 supcon``): no test read ``set_nodes``,
``seconds`` of ``supcon`` itself or ``effort`` from the stats, nor called ``supcon_naive``
without a name.  ``seconds`` is bounded by the time measured around the call (not a speed
assertion)."""

from __future__ import annotations

import time

from supcoord.bdd import Context
from supcoord.des.generator import Event, Generator
from supcoord.des.symbolic import from_explicit
from supcoord.synthesis import supcon
from supcoord.synthesis.supcon import supcon_naive

# a counter the specification caps at 2: 0 -a-> 1 -a-> 2 -a-> 3, every state -u-> 0 (u uncontrollable)
PLANT = Generator(4, [Event("a", True), Event("u", False)],
                  [(0, "a", 1), (1, "a", 2), (2, "a", 3)] + [(q, "u", 0) for q in range(4)], 0, [0], "P")
SPEC = Generator(3, [Event("a", True), Event("u", False)],
                 [(0, "a", 1), (1, "a", 2)] + [(q, "u", 0) for q in range(3)], 0, [0], "E")


def test_supcon_stats_are_the_documented_ones():
    ctx = Context()
    before = time.perf_counter()
    res = supcon(from_explicit(ctx, PLANT), from_explicit(ctx, SPEC))
    took = time.perf_counter() - before
    V = res.supervisor
    assert res.stats["set_nodes"] == ctx.node_count(V.invariant)
    assert 0 <= res.stats["seconds"] <= took
    assert res.stats["effort"] == res.effort.as_dict() and "stage_seconds" in res.stats["effort"]


def test_supcon_naive_names_its_supervisor_v_by_default():
    V = supcon_naive(PLANT, SPEC)
    assert V.name == "V" and V.n_states == 3


def test_supcon_effort_names_the_stages_docs_synthesis_lists():
    # docs/synthesis.md ("where the effort goes"): the stages in the order they run
    ctx = Context()
    res = supcon(from_explicit(ctx, PLANT), from_explicit(ctx, SPEC))
    assert list(res.stats["effort"]["stage_seconds"]) == ["product", "reachable", "nonblocking", "controllable",
                                                          "accessible", "counts"]
