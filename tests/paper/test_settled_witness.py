"""The greedy forcing string of the coupled model against the explicit Dijkstra twin, and
its replay check against strings that do not force the target."""

from __future__ import annotations

import pytest
from coupled_cases import random_coupled_models

from supcoord.errors import InputError, ModelError
from supcoord.paper.coupled import CoupledModel
from supcoord.paper.run import coupled_instance
from supcoord.paper.settled import settled_ccc, settled_ccc_naive
from supcoord.paper.settled_bound import PatternBound
from supcoord.paper.settled_graph import successor_events, target_in_zone
from supcoord.paper.settled_witness import greedy_witness, replay


def _random_models(seed: int, count: int):
    return random_coupled_models(seed, count, (2, 3, 3, 4), (4, 5, 6))


@pytest.mark.timeout(120)
def test_the_greedy_string_exists_exactly_where_the_explicit_twin_finds_the_target_forcible():
    kinds = {"forcible": 0, "not forcible": 0}
    for model in _random_models(seed=38, count=40):
        forcible, rank = settled_ccc_naive(model)
        found = greedy_witness(model, PatternBound(model), limit=10 ** 6)  # the whole settled graph fits
        assert (found is not None) == forcible, model.inst
        kinds["forcible" if forcible else "not forcible"] += 1
        if found is not None:
            assert replay(model, found.witness) == found.length == len(found.witness)
            assert found.length >= rank, model.inst
    assert min(kinds.values()) >= 2, kinds


@pytest.mark.timeout(240)
@pytest.mark.parametrize("size, seed", [(5, 0), pytest.param(6, 0, marks=pytest.mark.slow),
                                        pytest.param(7, 0, marks=pytest.mark.slow)])
def test_the_greedy_string_bounds_the_rank_of_the_benchmark_instances(size, seed):
    model = CoupledModel(coupled_instance(size, 8, seed))
    exact = settled_ccc(model)
    found = greedy_witness(model, PatternBound(model))
    assert exact.forcible and found is not None
    assert replay(model, exact.witness) == exact.rank  # the A*'s witness passes the same check
    assert found.length >= exact.rank


def test_replay_refuses_strings_that_do_not_force_the_target():
    model = CoupledModel(coupled_instance(6, 8, 0))
    witness = list(settled_ccc(model).witness)
    assert replay(model, witness) == len(witness)
    with pytest.raises(ModelError, match="does not end at the target"):
        replay(model, witness[:-1])
    with pytest.raises(ModelError):
        replay(model, witness[1:])
    with pytest.raises(ModelError):
        replay(model, witness + witness[-1:])
    # an uncontrollable event (even number) fired after a controllable one it must preempt
    k = next(i for i, e in enumerate(witness) if int(e) % 2 == 0 and i > 0 and int(witness[i - 1]) % 2 == 1)
    swapped = witness[:k - 1] + [witness[k], witness[k - 1]] + witness[k + 1:]
    with pytest.raises(ModelError):
        replay(model, swapped)
    state = (tuple(model.inst.start), (0,) * model.inst.size)
    for name in witness[:k]:
        state = dict(successor_events(model, state, False) or successor_events(model, state, True))[name]
    defined = [name for name, _ in successor_events(model, state, controllable=True)]  # defined, but preempted
    assert defined
    with pytest.raises(ModelError, match=f"step {k + 1} of the witness cannot fire: an uncontrollable event is "
                                         f"pending"):
        replay(model, witness[:k] + defined[:1])


def test_the_greedy_search_refuses_a_bad_limit_and_gives_up_at_its_limit():
    model = CoupledModel(coupled_instance(6, 8, 0))
    bound = PatternBound(model)
    for bad in (0, -1, True, 2.5):
        with pytest.raises(InputError):
            greedy_witness(model, bound, limit=bad)
    assert greedy_witness(model, bound, limit=1) is None


def test_a_budget_that_ends_the_search_for_the_rank_keeps_the_proved_verdict():
    """Once the greedy string proves "forcible", every report of the A* carries the verdict and
    the string, so a budget that stops the search for the rank still answers with both
    (``BudgetExceeded.stats`` are the last report's)."""
    from supcoord.bdd.context import Context

    model = CoupledModel(coupled_instance(5, 8, 0))
    found = greedy_witness(model, PatternBound(model))
    reports = []
    ctx = Context(progress=lambda stage, info: reports.append((stage, info)))
    settled_ccc(model, ctx)
    searching = [info for stage, info in reports if stage == "settled"]
    assert found is not None and searching
    for info in searching:
        assert info["forcible"] is True and info["upper_bound"] == found.length
        assert replay(model, info["witness"]) == found.length


def test_settling_near_the_mover_equals_settling_every_positioner():
    """The greedy search settles only the mover and its neighbours after a controllable
    event at a settled state; on every such step of random crowded instances that is the
    whole settling (levels and ``D``), and every case of ``D`` is met."""
    from supcoord.paper.events import decode_label
    from supcoord.paper.settled_graph import settle

    costs = set()
    for model in _random_models(seed=41, count=30):
        size = model.inst.size
        q0 = tuple(model.inst.start)
        start = (q0, settle(model, q0, (0,) * size)[0])
        seen, stack = {start}, [start]
        while stack:
            y = stack.pop()
            for name, z in successor_events(model, y, controllable=True):
                whole = settle(model, *z)
                assert settle(model, *z, near=decode_label(name)[0] - 1) == whole, (model.inst, y, name)
                costs.add(whole[1])
                if (z[0], whole[0]) not in seen:
                    seen.add((z[0], whole[0]))
                    stack.append((z[0], whole[0]))
    assert {0, 1, 2, 3} <= costs, costs
