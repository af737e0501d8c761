"""``supcon_flat`` and the display of a ``SupconResult``, against libFAUDES and values by hand.

Written because a uniform sample of ``supcon.py``'s mutants
(``benchmarks/mutation_run.py --sample 40 --seed 0 supcon``) had 22 of 40 mutants that no
test of the module's selection ran: ``supcon_flat`` (the explicit route of the command
line), ``SupconResult.summary``/``__repr__``/``_repr_html_`` and ``_short``.  The
supervisors are checked against libFAUDES's ``SupCon`` (``tests/helpers/oracle.py``), and
their numbering, names, statistics and iteration counts against values worked out by hand
in the comments.
"""

from __future__ import annotations

import time

from oracle import faudes_supcon

from supcoord.bdd import Context
from supcoord.des import explicit_ops as X
from supcoord.des.flat import from_generator
from supcoord.des.generator import Event, Generator
from supcoord.des.symbolic import from_explicit
from supcoord.synthesis.supcon import SupconResult, _short, supcon, supcon_flat

A1, U1, A2, U2, C = Event("a1", True), Event("u1", False), Event("a2", True), Event("u2", False), Event("c", True)
# two machines (start a_i controllable, finish u_i not) around a buffer of one place, and a
# one-state component with a self-loop (left out of the state names)
M1 = Generator(2, [A1, U1], [(0, "a1", 1), (1, "u1", 0)], 0, [0], "M1")
M2 = Generator(2, [A2, U2], [(0, "a2", 1), (1, "u2", 0)], 0, [0], "M2")
ONE = Generator(1, [C], [(0, "c", 0)], 0, [0], "ONE")
BUFFER = Generator(2, [U1, A2], [(0, "u1", 1), (1, "a2", 0)], 0, [0], "BUF")


def test_the_buffer_supervisor_is_libfaudes_numbered_breadth_first_and_named_by_component():
    calls = []
    before = time.perf_counter()
    V, stats = supcon_flat([from_generator(g) for g in (M1, ONE, M2)], [from_generator(BUFFER)],
                           check=lambda stage, **info: calls.append((stage, info)))
    took = time.perf_counter() - before
    g = V.to_generator()
    assert g.same_as(faudes_supcon(X.sync(M1, ONE, M2), BUFFER))
    # breadth first from (M1, M2, BUF) = (0, 0, 0), events in the order a1 u1 c a2 u2:
    # 0 -a1-> 1 = (1,0,0) -u1-> 2 = (0,0,1) -a2-> 3 = (0,1,0) -a1-> 4 = (1,1,0) -u1-> 5 = (0,1,1);
    # a1 at (0,0,1) would fill the full buffer by u1 (uncontrollable): disabled
    assert V.name == "V" and g.init == 0 and g.marked == frozenset({0})
    assert sorted(g.transitions()) == [
        (0, "a1", 1), (0, "c", 0), (1, "c", 1), (1, "u1", 2), (2, "a2", 3), (2, "c", 2), (3, "a1", 4), (3, "c", 3),
        (3, "u2", 0), (4, "c", 4), (4, "u1", 5), (4, "u2", 1), (5, "c", 5), (5, "u2", 2)]
    # default labels G0.. per component, plants then specifications; ONE (G1) has one state
    assert g.state_names == ["G0=0,G2=0,G3=0", "G0=1,G2=0,G3=0", "G0=0,G2=0,G3=1", "G0=0,G2=1,G3=0",
                             "G0=1,G2=1,G3=0", "G0=0,G2=1,G3=1"]
    assert {k: stats[k] for k in ("states", "transitions", "marked", "bdd_nodes", "set_nodes", "iterations")} == \
        {"states": 6, "transitions": 14, "marked": 1, "bdd_nodes": 0, "set_nodes": 0, "iterations": 1}
    assert 0 <= stats["seconds"] <= took
    assert calls[-1] == ("supcon", {"iteration": 1})


def test_labels_and_name_are_used():
    V, _ = supcon_flat([from_generator(M1), from_generator(M2)], [from_generator(BUFFER)], name="S",
                       labels=["m1", "m2", "buf"])
    assert V.name == "S" and V.to_generator().state_names[:3] == ["m1=0,m2=0,buf=0", "m1=1,m2=0,buf=0",
                                                                  "m1=0,m2=0,buf=1"]


def test_each_pass_of_the_loop_is_counted_and_offered_to_the_check():
    # 0 marked; 1 -u-> 2, where the specification disables v (B0 = {2}); 3 reaches 0 only
    # through 1; 4 -w-> 3 (w uncontrollable).  Pass 1: CoReach = {0, 1, 3, 4}, 1 removed (u);
    # pass 2: 3 blocks now, 4 removed (w); pass 3 removes nothing: the supervisor is {0}.
    a, b, c, d, e, f = (Event(x, True) for x in "abcdef")
    u, v, w = (Event(x, False) for x in "uvw")
    G = Generator(6, [a, b, c, d, e, f, u, v, w], [(0, "a", 1), (1, "b", 0), (1, "u", 2), (2, "v", 5), (0, "c", 3),
                                                  (3, "d", 1), (0, "e", 4), (4, "f", 0), (4, "w", 3)], 0, [0], "G")
    E = Generator(1, [v], [], 0, [0], "E")
    calls = []
    V, stats = supcon_flat([from_generator(G)], [from_generator(E)],
                           check=lambda stage, **info: calls.append((stage, info)))
    assert V.to_generator().same_as(faudes_supcon(G, E))
    assert (V.n_states, V.n_transitions, V.marked.tolist(), stats["iterations"]) == (1, 0, [0], 3)
    assert [c for c in calls if c[0] == "supcon"] == [("supcon", {"iteration": i}) for i in (1, 2, 3)]


def test_an_initial_state_the_specification_cannot_keep_gives_the_empty_supervisor():
    u = Event("u", False)
    G = Generator(2, [u], [(0, "u", 1)], 0, [0, 1], "G")
    V, stats = supcon_flat([from_generator(G)], [from_generator(Generator(1, [u], [], 0, [0], "E"))])
    assert (V.n_states, V.n_transitions, len(V.marked), V.state_names) == (0, 0, 0, None)
    assert (stats["states"], stats["transitions"], stats["marked"]) == (0, 0, 0)


def test_the_summary_repr_and_html_show_the_numbers_short():
    ctx = Context()
    res = supcon(from_explicit(ctx, M1), from_explicit(
        ctx, Generator(2, [A1, U1], [(0, "a1", 0), (0, "u1", 1), (1, "a1", 1)], 0, [0, 1], "E")))
    # M1 with u1 allowed once: (0,0) -a1-> (1,0) -u1-> (0,1) -a1-> (1,1), where u1 is disabled: removed, so
    # (0,1) keeps no a1: 3 states, 2 transitions, 2 marked
    s = res.summary()
    assert list(s) == ["supervisor", "states", "marked", "transitions", "bdd_nodes", "iterations", "seconds"]
    assert (s["supervisor"], s["states"], s["marked"], s["transitions"]) == ("V", 3, 2, 2)
    assert s["seconds"] == round(res.stats["seconds"], 3)
    big = SupconResult(res.supervisor, {"states": 2 ** 60, "marked": 2 ** 1000, "transitions": 2 ** 50 - 1,
                                        "seconds": 1.23456, "other": 7})
    assert big.summary() == {"supervisor": "V", "states": "~1.15e+18", "marked": "~10^301",
                             "transitions": 2 ** 50 - 1, "seconds": 1.235}
    assert repr(big) == ("SupconResult(supervisor='V', states='~1.15e+18', marked='~10^301', "
                         f"transitions={2 ** 50 - 1}, seconds=1.235)")
    html = big._repr_html_()
    assert "<b>SupconResult</b>" in html and "~10^301" in html and "other" not in html
    assert _short(True) is True and _short(2 ** 51) == "~2.25e+15" and _short("x") == "x"
