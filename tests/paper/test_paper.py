"""The seed paper's model: numbering, the literal G^P/S^P (explicit twin, libFAUDES),
the modular route against the generic algorithms (Theorems 1 and 2 of
paper_modular), and the coupled reading's supervisor checked by libFAUDES."""

from __future__ import annotations

import itertools
from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from oracle import faudes_is_controllable, faudes_is_nonblocking, faudes_supcon
from strategies import generators

from supcoord.bdd import Budget, Context
from supcoord.cli.main import main
from supcoord.des import explicit_ops as XO
from supcoord.des import symbolic_ops as SO
from supcoord.des.generator import Event
from supcoord.des.symbolic import from_explicit, to_explicit
from supcoord.errors import BudgetExceeded, InputError
from supcoord.paper.coupled import CoupledModel, coupled_models, coupled_models_explicit
from supcoord.paper.literal import (
    KINDS,
    TABLE1,
    PaperInstance,
    decode_label,
    event_label,
    literal_models,
    literal_models_explicit,
    paper_example,
    plant_explicit,
    plant_symbolic,
    priority_event,
    random_instance,
    spec_explicit,
    spec_symbolic,
)
from supcoord.paper.modular import Templates, ccc_modular, literal_components, literal_modular, supcon_modular
from supcoord.paper.run import coupled_instance, json_count, log10_count, run_paper, solve_paper
from supcoord.synthesis import ccc, forcible_layers, forcible_layers_naive, supcon, supcon_naive
from supcoord.synthesis.forcibility import rank_naive

SEMANTICS = ["preemptive", "standard"]


# -- numbering and the priority rule ---------------------------------------------------


def test_table1_labels_and_tct_parity():
    for num, row in TABLE1.items():
        for kind in KINDS:
            assert event_label(num, kind) == str(row[kind])
    assert [event_label(1, k) for k in KINDS] == ["71", "73", "11", "13", "15", "10", "40"]
    for num in range(1, 400):
        for kind in KINDS:
            label = event_label(num, kind)
            assert (int(label) % 2 == 1) == (kind not in ("k", "e")), (num, kind, label)


def test_numbering_extension_is_injective_and_decodes():
    labels = {}
    for num in range(1, 3001):
        for kind in KINDS:
            label = event_label(num, kind)
            assert label not in labels, f"{label} given to {labels[label]} and {(num, kind)}"
            labels[label] = (num, kind)
            assert decode_label(label) == (num, kind)
    # Table 1's own arithmetic pattern would give P4 k = 40, which is P1's e
    assert event_label(4, "k") != event_label(1, "e") and decode_label("40") == (1, "e")


@pytest.mark.parametrize("bad", [("x", 1), ("v", 0), ("v", -3), ("v", True)])
def test_numbering_rejects_bad_arguments(bad):
    kind, num = bad
    with pytest.raises(InputError):
        event_label(num, kind)


@pytest.mark.parametrize("label", ["12", "399", "406", "abc", "404", "1710"])
def test_decode_rejects_labels_outside_the_scheme(label):
    with pytest.raises(InputError):
        decode_label(label)


def test_priority_rule_follows_the_example():
    """Smaller number = higher priority (the paper's example: P1 fires h); the one that
    outranks all colliding neighbours gets h, the one all outrank gets l, others m."""
    assert [priority_event(r, [x for x in (1, 2, 3) if x != r]) for r in (1, 2, 3)] == ["h", "m", "l"]
    assert priority_event(5, [7]) == "h" and priority_event(7, [5]) == "l"
    assert priority_event(4, [2, 9]) == "m" and priority_event(4, []) == "h"
    inst = paper_example()
    assert [inst.priority_kind(i) for i in range(3)] == ["h", "m", "l"]


@pytest.mark.parametrize("prio", ["l", "m", "h"])
def test_plant_defines_exactly_its_priority_event(prio):
    n = 5
    g = plant_explicit(2, n, 0, 3, prio)
    used = {e for _, e, _ in g.transitions()}
    lb = {k: event_label(2, k) for k in KINDS}
    assert {lb[k] for k in ("l", "m", "h")} & used == {lb[prio]}
    assert set(g.events) == set(lb.values())  # the alphabet is all seven (Definition "Positioner")
    assert g.n_states == 3 * n and g.successor(0, lb["w"]) == n - 1 and g.successor(n - 1, lb["v"]) == 0
    with pytest.raises(InputError):
        plant_explicit(2, n, 0, 3, "x")


# -- the literal model: explicit twin, symbolic, libFAUDES --------------------------------


@st.composite
def literal_instances(draw, max_steps=4, max_size=3):
    n = draw(st.integers(2, max_steps))
    size = draw(st.integers(1, max_size))
    start = tuple(draw(st.integers(0, n - 1)) for _ in range(size))
    target = tuple(draw(st.integers(0, n - 1)) for _ in range(size))
    priority = tuple(draw(st.permutations(range(1, size + 1))))
    edges = {p for p in itertools.combinations(range(size), 2) if draw(st.booleans())}
    neighbours = tuple(tuple(j for j in range(size) if (min(i, j), max(i, j)) in edges) for i in range(size))
    return PaperInstance(n, start, target, priority, neighbours)


@settings(max_examples=40)
@given(st.integers(2, 6), st.data())
def test_positioner_symbolic_equals_explicit(n, data):
    s, t = data.draw(st.integers(0, n - 1)), data.draw(st.integers(0, n - 1))
    prio = data.draw(st.sampled_from("lmh"))
    ctx = Context()
    assert to_explicit(plant_symbolic(ctx, 3, n, s, t, prio)).same_as(plant_explicit(3, n, s, t, prio))
    for sees, absorbing in [(False, True), (True, False), (True, True)]:
        S = spec_symbolic(Context(), 3, n, s, t, sees_priority=sees, absorbing=absorbing)
        assert to_explicit(S).same_as(spec_explicit(3, n, s, t, sees_priority=sees, absorbing=absorbing)), (sees, absorbing)


def test_spec_counts_to_the_target_as_the_paper_numbers_it():
    """S^P from 6 to 1 on 8 positions: n_v = 3 forward steps, n_w = 5 backward; q0, the
    forward chain q1, q2, the backward chain q3..q6, q_m (no transition out of q_m)."""
    s = spec_explicit(1, 8, 6, 1)
    v, w = event_label(1, "v"), event_label(1, "w")
    assert s.n_states == 8 and s.marked == {7} and s.run([v] * 3) == 7 and s.run([w] * 5) == 7
    assert [s.run([v] * k) for k in range(3)] == [0, 1, 2] and [s.run([w] * k) for k in range(1, 5)] == [3, 4, 5, 6]
    assert s.enabled(7) == {}


@settings(max_examples=25)
@given(literal_instances(max_steps=3, max_size=2))
def test_literal_supcon_symbolic_naive_and_libfaudes_agree(inst):
    G, E = literal_models_explicit(inst)
    naive = supcon_naive(G, E)
    assert naive.same_as(faudes_supcon(G, E))
    Gs, Es = literal_models(inst, Context())
    r = supcon(Gs, Es)
    assert (r.stats["states"], r.stats["transitions"], r.stats["marked"]) == (
        naive.n_states, sum(1 for _ in naive.transitions()), len(naive.marked))
    if naive.n_states <= 200:
        assert to_explicit(r.supervisor).same_as(naive)


def test_literal_example_pair_matches_libfaudes_and_has_one_marked_state():
    # P1 and P2 of the example (all three: 884736 states, too many for a unit test)
    inst = PaperInstance(8, (0, 6), (1, 5), (1, 2), ((1,), (0,)))
    G, E = literal_models_explicit(inst)
    oracle = faudes_supcon(G, E)
    r = supcon(*literal_models(inst, Context()))
    assert r.stats["states"] == oracle.n_states and r.stats["marked"] == len(oracle.marked) == 1
    assert r.stats["transitions"] == sum(1 for _ in oracle.transitions())


# -- the k, e cycle: why the literal model is never forcible off target ------------------


@pytest.mark.parametrize("prio", ["l", "m", "h"])
@pytest.mark.parametrize("semantics", SEMANTICS)
def test_literal_positioner_is_forcible_only_at_its_target(prio, semantics):
    """One literal positioner, 6 positions, 0 -> 3: k and e are defined at every
    position, so the environment answers any move with k, e, k, e, ...; the winning
    set is the target plus at most the level-2 state next to it that h or l leaves (no
    uncontrollable event is defined at level 2), whatever the semantics."""
    G = plant_explicit(1, 6, 0, 3, prio)
    V = supcon_naive(G, XO.sync(XO.allevents(G), spec_explicit(1, 6, 0, 3)))
    layers = forcible_layers_naive(V, V.marked, semantics)
    won = [V.state_label(q) for layer in layers for q in layer]
    assert won == {"m": ["q3,0,qm"], "h": ["q3,0,qm", "q2^2,0,qm"], "l": ["q3,0,qm", "q4^2,0,qm"]}[prio]
    assert rank_naive(layers, V.init) is None
    # the environment's cycle at the start: k then e returns to q0
    k, e = event_label(1, "k"), event_label(1, "e")
    assert V.run([k, e]) == V.init


# -- the modular route = the generic route (Theorems 1 and 2) ---------------------------


def _generic_and_modular(inst, semantics):
    ctx = Context()
    comps = literal_components(inst, ctx)
    G = SO.sync(*[g for g, _ in comps], name="G")
    E = SO.sync(*[e for _, e in comps], name="ALLxS")
    generic = supcon(G, E)
    _, _, modular, verdict = literal_modular(inst, ctx, semantics, components=comps, full=True)
    return generic, modular, verdict


@settings(max_examples=40)
@given(literal_instances(max_steps=4, max_size=3), st.sampled_from(SEMANTICS))
def test_literal_modular_equals_generic(inst, semantics):
    generic, modular, verdict = _generic_and_modular(inst, semantics)
    assert modular.supervisor.invariant == generic.supervisor.invariant  # the same state set, as a BDD
    assert modular.supervisor.init == generic.supervisor.init
    for key in ("states", "transitions", "marked", "bdd_nodes", "set_nodes"):
        assert modular.stats[key] == generic.stats[key], key
    reference = ccc(generic.supervisor, semantics)
    assert verdict.forcible == reference.forcible
    if verdict.stats.get("certificate"):  # Theorem 2's certificate never contradicts the generic ccc
        assert not reference.forcible
    else:
        assert (verdict.rank, verdict.witness) == (reference.rank, reference.witness)


@pytest.mark.parametrize("semantics", SEMANTICS)
def test_literal_modular_all_on_target_is_forcible_with_the_empty_witness(semantics):
    inst = PaperInstance(5, (1, 4, 0), (1, 4, 0), (1, 2, 3), ((1,), (0, 2), (1,)))
    generic, modular, verdict = _generic_and_modular(inst, semantics)
    assert modular.supervisor.invariant == generic.supervisor.invariant
    assert verdict.forcible and verdict.rank == 0 and verdict.witness == [] and "certificate" not in verdict.stats


@st.composite
def disjoint_components(draw, max_components=3):
    """``[(plant, spec)]`` with pairwise disjoint alphabets (events ``a0, b0, …``)."""
    out = []
    for i in range(draw(st.integers(1, max_components))):
        names = [f"{c}{i}" for c in "abc"]
        alphabet = [Event(n, draw(st.booleans())) for n in names]
        g = draw(generators(alphabet, 3, f"G{i}", full_alphabet=True))
        e = draw(generators(alphabet, 3, f"E{i}"))
        out.append((g, e))
    return out


@settings(max_examples=60)
@given(disjoint_components())
def test_theorem1_supcon_of_disjoint_components_is_the_product(components):
    ctx = Context()
    comps = [(from_explicit(ctx, g, f"g{i}"), from_explicit(ctx, e, f"e{i}")) for i, (g, e) in enumerate(components)]
    modular, parts = supcon_modular(comps)
    generic = supcon(SO.sync(*[g for g, _ in comps]), SO.sync(*[e for _, e in comps]))
    assert modular.supervisor.invariant == generic.supervisor.invariant
    for key in ("states", "transitions", "marked"):
        assert modular.stats[key] == generic.stats[key], key


@settings(max_examples=60)
@given(disjoint_components(), st.sampled_from(SEMANTICS))
def test_theorem2_product_winning_set_within_product_of_winning_sets(components, semantics):
    ctx = Context()
    Vs = [from_explicit(ctx, g, f"g{i}") for i, (g, _) in enumerate(components)]
    V = SO.sync(*Vs)
    W = forcible_layers(V, V.marked, semantics=semantics).winning
    bound = ctx.true
    for Vi in Vs:
        bound &= forcible_layers(Vi, Vi.marked, semantics=semantics).winning
    assert W & ~bound == ctx.false  # W(V) ⊆ ∏ W(V_i)
    # ccc_modular's negative verdicts (certificates) never contradict the generic ccc
    parts = [SimpleNamespace(supervisor=Vi) for Vi in Vs]  # what ccc_modular reads of a SupconResult
    verdict, reference = ccc_modular(V, parts, semantics), ccc(V, semantics)
    assert verdict.forcible == reference.forcible


def test_literal_bdd_is_the_sum_of_its_blocks():
    """Linear in N: the supervisor's state set is a conjunction of blocks on consecutive
    variables, so its BDD has the blocks' nodes, give or take one per block (with
    complemented edges a block's TRUE becomes the next block's root, which may split
    a node shared with its complement)."""
    inst = random_instance(60, 12, seed=5)
    tpl = Templates(12)
    _, _, res, _ = literal_modular(inst, Context(), templates=tpl)
    blocks = [tpl.get(inst.start[i], inst.target[i], inst.priority_kind(i))["z"] for i in range(inst.size)]
    sizes = [tpl.ctx.node_count(z) for z in blocks]
    assert sum(sizes) - inst.size + 1 <= res.stats["set_nodes"] <= sum(sizes) + 1
    assert res.stats["distinct_components"] == len(tpl) < inst.size


def test_templates_reject_another_step_count():
    with pytest.raises(InputError):
        literal_modular(random_instance(3, 6), Context(), templates=Templates(8))


# -- the coupled reading: V checked by libFAUDES, the witness replayed --------------------


@pytest.fixture(scope="module")
def coupled_example():
    model = CoupledModel(paper_example())
    Gx, Ex = coupled_models_explicit(model)
    r = supcon(*coupled_models(model, Context()))
    return model, Gx, Ex, r, to_explicit(r.supervisor, name="V")


def test_coupled_geometry_is_the_rotary_kinematics():
    """The coupled model's arms are Rotary's; its hard collisions are colliding_pairs'."""
    from supcoord.geometry.collision import colliding_pairs
    from supcoord.geometry.kinematics import Rotary

    inst = paper_example()
    model = CoupledModel(inst)
    kin = Rotary(model.geo.arm, inst.steps)
    for i in range(inst.size):
        for q in range(inst.steps):
            assert np.array_equal(model.fibre(i, q), kin.fibre([q]) + model.bases[i])
    for pos in itertools.product(range(inst.steps), repeat=inst.size):
        pairs = colliding_pairs(kin, model.bases, model.geo.buffer, np.array(pos)[:, None])
        assert model.hard_collisions(pos) == [(a, b) for a, b, _ in pairs]
    assert model._next[1][inst.steps - 1] == 0 and model._next[-1][0] == inst.steps - 1


def test_coupled_supervisor_is_controllable_nonblocking_with_one_marked_state(coupled_example):
    """The paper's Theorem (i), checked independently by libFAUDES."""
    _, Gx, Ex, r, Vx = coupled_example
    assert faudes_is_controllable(Gx, Vx)
    assert faudes_is_nonblocking(Vx)
    assert len(Vx.marked) == 1 == r.stats["marked"]
    assert Vx.same_as(faudes_supcon(Gx, Ex)) and Vx.same_as(supcon_naive(Gx, Ex))
    assert (Vx.n_states, sum(1 for _ in Vx.transitions())) == (r.stats["states"], r.stats["transitions"])


def test_coupled_witness_replays_to_the_marked_state(coupled_example):
    _, _, _, r, Vx = coupled_example
    c = ccc(r.supervisor, "preemptive")
    assert c.forcible and Vx.run(c.witness) in Vx.marked
    assert c.rank == rank_naive(forcible_layers_naive(Vx, Vx.marked, "preemptive"), Vx.init) == len(c.witness)
    assert c.witness == ["10", "20", "15", "50", "83", "93"]  # docs/paper.md explains it event by event
    assert [decode_label(x)[1] for x in c.witness] == ["k", "k", "h", "e", "w", "w"]
    assert not ccc(r.supervisor, "standard").forcible  # without preemption the k at q0 cannot be waited for


def test_the_papers_path_is_not_a_path_of_either_reading(coupled_example):
    _, _, _, _, Vx = coupled_example
    paper = ["73", "10", "30", "15", "31", "81", "20"]
    # 73 is in V, but preempted: P1 and P2 start in each other's zone, so k is pending at q0
    assert Vx.run(paper[:1]) is not None and {"10", "20"} <= set(Vx.enabled(Vx.init))
    assert Vx.run(paper[:2]) is None  # after 73 nobody is in P1's zone: 10 is not defined
    V = supcon(*literal_models(paper_example(), Context())).supervisor  # 884736 states: symbolically
    q = V.init
    for event in paper:
        q = V.post(q, event)
        assert q != V.ctx.false, event  # every event is defined in the literal V ...
    assert q & V.marked == V.ctx.false  # ... but the path ends in collision mode (20 = k), not marked


@pytest.mark.parametrize("size, steps, seed", [(2, 8, 0), (2, 8, 3), (3, 8, 1)])
def test_coupled_random_instances_agree_with_the_explicit_twin(size, steps, seed):
    inst = coupled_instance(size, steps, seed)
    model = CoupledModel(inst)
    Gx, Ex = coupled_models_explicit(model)
    G, E = coupled_models(model, Context())
    if size == 2:  # to_explicit walks state by state: seconds for the 4128 states of 3 positioners
        assert to_explicit(G).same_as(Gx)
    r = supcon(G, E)
    oracle = faudes_supcon(Gx, Ex)
    assert (r.stats["states"], r.stats["transitions"], r.stats["marked"]) == (
        oracle.n_states, sum(1 for _ in oracle.transitions()), len(oracle.marked))
    c = ccc(r.supervisor)
    if c.forcible:
        assert oracle.run(c.witness) in oracle.marked


# -- solve_paper and supcoord paper -------------------------------------------------------


def test_routes_agree_on_the_literal_model():
    a = solve_paper(8, 6, seed=4, route="modular")
    b = solve_paper(8, 6, seed=4, route="monolithic", count_transitions=True)
    for key in ("supervisor_states", "supervisor_transitions", "supervisor_marked", "bdd_nodes", "ccc", "rank"):
        assert a[key] == b[key], key
    assert a["route"] == "modular" and a["certificate"] and b["certificate"] is None


def test_run_paper_takes_an_instance_and_keeps_the_results():
    inst = PaperInstance(4, (0, 2), (0, 2), (1, 2), ((1,), (0,)))
    r = run_paper(instance=inst)
    assert r.payload["positioners"] == 2 and r.payload["seed"] is None and r.payload["ccc"] is True
    assert r.supervisor.count_states() == r.payload["supervisor_states"]
    assert r.payload["supervisor_states_log10"] == pytest.approx(__import__("math").log10(r.payload["supervisor_states"]), abs=1e-4)


def test_huge_counts_stay_readable_json():
    r = solve_paper(300, 12)  # ~10^467 states, exact
    assert isinstance(r["supervisor_states"], int) and r["supervisor_states_log10"] > 400
    assert json_count(10 ** 5000) is None and json_count(10 ** 100) == 10 ** 100  # Python's 4300-digit limit
    assert log10_count(10 ** 5000) == 5000 and log10_count(0) is None


@pytest.mark.parametrize("kwargs, where", [
    ({"model": "coupled", "route": "modular"}, "route"),
    ({"route": "sideways"}, "route"),
    ({"model": "quantum"}, "model"),
])
def test_bad_route_or_model_is_a_user_error(kwargs, where):
    """The library names its parameters (the command line translates them to --route, --model)."""
    with pytest.raises(InputError) as info:
        solve_paper(3, 6, **kwargs)
    assert info.value.where == where


@pytest.mark.parametrize("route", ["modular", "monolithic"])
def test_budgets_end_cleanly(route, capsys):
    code = main(["paper", "--positioners", "40", "--steps", "12", "--route", route, "--timeout", "0.001", "--json"])
    out = capsys.readouterr().out
    assert code == 3 and '"status": "unknown"' in out
    with pytest.raises(BudgetExceeded):
        solve_paper(40, 12, ctx=Context(budget=Budget(max_nodes=10)), route=route)


def test_cli_coupled_modular_is_one_line_exit_2(capsys):
    assert main(["paper", "--positioners", "3", "--steps", "8", "--model", "coupled", "--route", "modular"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--route" in err[0]


@pytest.mark.parametrize("model", ["literal", "coupled"])
def test_negative_seed_is_a_user_error_naming_the_parameter(model):
    with pytest.raises(InputError) as info:
        solve_paper(3, 8, model, seed=-1)
    assert info.value.where == "seed"  # the library's parameter; the command line says --seed
    with pytest.raises(InputError):
        random_instance(3, 8, seed=-1)
