"""What a chaining fixpoint reports to the context's progress hook, by hand.

Written for survivors of a uniform sample of ``reachability.py``'s mutants
(``benchmarks/mutation_run.py --sample 40 --seed 0 reachability``): no selected test read
the ``iteration`` and ``method`` a chaining fixpoint hands to ``Context.check_budget``
(the progress line and a budget's message show them)."""

from __future__ import annotations

from supcoord.bdd import Context
from supcoord.des.generator import Event, Generator
from supcoord.des.symbolic import from_explicit
from supcoord.synthesis.reachability import reachable


def test_chaining_reports_each_sweep_by_number_and_its_method():
    # one event along 0 -> 1 -> 2 -> 3: each sweep applies it once, so sweeps 1-3 add a
    # state each and sweep 4 adds nothing (the fixpoint)
    G = Generator(4, [Event("a", True)], [(0, "a", 1), (1, "a", 2), (2, "a", 3)], 0, [0], "G")
    ctx = Context()
    S = from_explicit(ctx, G)
    seen = []
    ctx.progress = lambda stage, info: seen.append((stage, info.get("iteration"), info.get("method")))
    r = reachable(S, method="chaining")
    assert ctx.count(r, S.variables) == 4
    assert seen == [("reachable", k, "chaining") for k in (1, 2, 3, 4)]
