"""Exporting supervisors in bulk: :func:`to_explicit` enumerates a symbolic generator
with array operations and gives exactly what enumerating it one state and one event at a
time gives (numbering, names, marking); the pieces (assignments, packed-key look-ups,
breadth-first numbering, the ``.gen`` writer) against their definitions; and the explicit
supcon route against the symbolic one."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from strategies import alphabets, generators, systems

from supcoord.bdd import Context
from supcoord.bdd.budget import Budget
from supcoord.des import explicit_ops as X
from supcoord.des import symbolic_ops as S
from supcoord.des.flat import from_generator
from supcoord.des.flat_ops import KeyIndex, bfs_order
from supcoord.des.generator import Generator
from supcoord.des.io.gen_file import format_gen, parse_gen
from supcoord.des.io.gen_write import write_gen_flat
from supcoord.des.symbolic import from_explicit, to_explicit
from supcoord.des.symbolic_export import assignments, to_flat
from supcoord.errors import BudgetExceeded, InputError
from supcoord.synthesis.supcon import lift_spec, supcon, supcon_flat

SOME = settings(max_examples=40, deadline=None, suppress_health_check=list(HealthCheck))


def to_explicit_one_by_one(sg, name=None) -> Generator:
    """The definition: breadth-first from the initial state, one image per state and event."""
    ctx, variables = sg.ctx, sg.variables
    init = sg.pick(sg.init)
    if init is None:
        return Generator(0, sg.alphabet, [], None, (), name or sg.name)
    key = lambda d: tuple(d[v] for v in variables)
    index, queue, transitions = {key(init): 0}, [init], []
    for values in queue:
        here = ctx.assignment(values) if variables else ctx.true
        for e in sg.events:
            nxt = sg.post(here, e)
            if nxt == ctx.false:
                continue
            d = ctx.pick(nxt, variables) if variables else {}
            if key(d) not in index:
                index[key(d)] = len(queue)
                queue.append(d)
            transitions.append((index[key(values)], e, index[key(d)]))
    cube = lambda v: ctx.assignment(v) if variables else ctx.true
    marked = [i for i, v in enumerate(queue) if cube(v) & sg.marked != ctx.false]
    names = [",".join(f"{v}={d[v]}" for v in variables) or "0" for d in queue]
    return Generator(len(queue), sg.alphabet, transitions, 0, marked, name or sg.name, names)


def identical(a: Generator, b: Generator) -> bool:
    return (a.n_states, a.alphabet, list(a.transitions()), a.init, a.marked, a.state_names) == \
        (b.n_states, b.alphabet, list(b.transitions()), b.init, b.marked, b.state_names)


@SOME
@given(st.data())
def test_bulk_export_equals_the_state_by_state_definition(data):
    alphabet = data.draw(alphabets())
    gens = [data.draw(generators(alphabet, 5, f"G{i}")) for i in range(data.draw(st.integers(1, 3)))]
    ctx = Context()
    product = S.sync(*[from_explicit(ctx, g) for g in gens])
    assert identical(to_explicit(product), to_explicit_one_by_one(product))


@SOME
@given(systems())
def test_supervisor_export_with_its_state_set_equals_the_definition(system):
    _, plants, specs = system
    ctx = Context()
    G = S.sync(*[from_explicit(ctx, g) for g in plants])
    E = S.sync(*[from_explicit(ctx, g) for g in specs])
    V = supcon(G, lift_spec(G, E)).supervisor
    assert identical(to_explicit(V, states=V.invariant), to_explicit_one_by_one(V))


def test_keys_wider_than_one_word_and_assignments():
    ctx = Context()
    names = [f"v{i}" for i in range(12)]
    for n in names:
        ctx.add_variable(n, 37)  # 6 bits each: 72 bits, two words
    u = ctx.false
    rows = [[(i * 7 + j * 3 + i * j) % 37 for j in range(12)] for i in range(30)]
    for r in rows:
        u |= ctx.assignment(dict(zip(names, r)))
    got = assignments(ctx, u, names)
    assert sorted(map(tuple, got.tolist())) == sorted(map(tuple, rows)) and len(got) == ctx.count(u, names)
    keys = np.array([[sum(x << (6 * k) for k, x in enumerate(r[:10])), r[10] * 37 + r[11]] for r in rows],
                    dtype=np.uint64)
    index = KeyIndex(keys)
    assert (index.find(keys[::-1]) == np.arange(30)[::-1]).all()
    assert (index.find(keys[:3] + np.uint64(1)) == -1).all()


def test_breadth_first_numbering_past_the_layer_limit_is_the_same():
    rng = np.random.default_rng(3)
    n = 300
    src = np.concatenate([np.arange(n - 1), rng.integers(0, n, 400)])
    dst = np.concatenate([np.arange(1, n), rng.integers(0, n, 400)])
    ev = rng.integers(0, 4, len(src))
    keep = np.unique(src * 4 + ev, return_index=True)[1]  # deterministic
    src, dst, ev = src[keep], dst[keep], ev[keep]
    assert (bfs_order(n, src, ev, dst, 0) == bfs_order(n, src, ev, dst, 0, layers=3)).all()


def test_export_limit_and_budget_stage():
    g = Generator.from_tct(3, [(0, 1, 1), (1, 3, 2), (2, 5, 0)], 0, [0])
    ctx = Context()
    sg = from_explicit(ctx, g)
    with pytest.raises(InputError, match="3 states to enumerate, more than 2"):
        to_flat(sg, max_states=2)
    ctx.budget = Budget(timeout=1e-9)
    with pytest.raises(BudgetExceeded) as info:
        to_flat(sg)
    assert info.value.stats["stage"] == "export"


@SOME
@given(alphabets().flatmap(lambda a: generators(a, 6)), st.booleans())
def test_the_array_writer_writes_what_the_generator_writer_wrote(tmp_path_factory, g, by_index):
    text = format_gen(g, names_in_transitions=not by_index)
    path = tmp_path_factory.mktemp("w") / "g.gen"
    write_gen_flat(from_generator(g), path, names_in_transitions=not by_index)
    assert path.read_text(encoding="latin-1") == text
    back = parse_gen(text)
    assert back.same_as(g) and (back.n_states, back.n_transitions) == (g.n_states, g.n_transitions)
    lines = text.split("<TransRel>\n")[1].split("</TransRel>")[0].splitlines()
    expected = [" ".join(s.ljust(14) for s in (str(a + 1), e if e[0].isalpha() else f'"{e}"', str(b + 1))).rstrip()
                for a, e, b in g.transitions()] if by_index else lines
    assert lines == expected


@SOME
@given(systems())
def test_explicit_route_equals_symbolic_route(system):
    _, plants, specs = system
    labels = [f"P{i}_{g.name}" for i, g in enumerate(plants)] + [f"S{j}_{g.name}" for j, g in enumerate(specs)]
    ctx = Context()
    G = S.sync(*[from_explicit(ctx, g, var=labels[i]) for i, g in enumerate(plants)], name="G")
    E = S.sync(*[from_explicit(ctx, g, var=labels[len(plants) + j]) for j, g in enumerate(specs)], name="E")
    result = supcon(G, lift_spec(G, E), name="V")
    V, stats = supcon_flat([from_generator(g) for g in plants], [from_generator(g) for g in specs], labels=labels)
    assert {k: stats[k] for k in ("states", "transitions", "marked")} == \
        {k: result.stats[k] for k in ("states", "transitions", "marked")}
    assert identical(V.to_generator(), to_explicit(result.supervisor, name="V"))
    assert V.to_generator().same_as(X.trim(V.to_generator()) if V.n_states else V.to_generator())
