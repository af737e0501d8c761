"""The classic benchmarks: data files load, and libFAUDES and supcoord both reproduce the
published supervisor sizes (docs/references.md lists each with its source)."""

from __future__ import annotations

import faudes
import pytest

from supcoord.des import classic
from supcoord.des import explicit_ops as X
from supcoord.errors import InputError
from supcoord.synthesis import lift_spec, supcon_naive

from faudes_twin import faudes_supcon, symbolic_supcon

PUBLISHED = {
    "small_factory": (12, 24),
    "transfer_line": (28, 65),
    "agv": (4406, 11338),
    "cat_mouse": (6, 9),
    "dining_philosophers": (79, 244),
}


def test_names_and_published_table():
    assert classic.names() == sorted(PUBLISHED)
    for name, expected in PUBLISHED.items():
        assert classic.load(name).expected == expected
    with pytest.raises(InputError, match="unknown classic model"):
        classic.load("nope")


@pytest.mark.parametrize("name", sorted(PUBLISHED))
def test_libfaudes_reproduces_published_size(name, tmp_path):
    m = classic.load(name)
    assert faudes_supcon(m.plants, m.specs, tmp_path) == PUBLISHED[name]


@pytest.mark.parametrize("name", sorted(PUBLISHED))
def test_supcoord_symbolic_supcon_reproduces_published_size(name):
    m = classic.load(name)
    st = symbolic_supcon(m.plants, m.specs)
    assert (st["states"], st["transitions"]) == PUBLISHED[name]


@pytest.mark.parametrize("name", ["small_factory", "transfer_line", "cat_mouse", "dining_philosophers"])
def test_explicit_twin_agrees(name):
    m = classic.load(name)
    G = X.sync(*m.plants)
    E = lift_spec(G, X.sync(*m.specs)) if m.specs else X.allevents(G)
    V = supcon_naive(G, E)
    assert (V.n_states, V.n_transitions) == PUBLISHED[name]


def test_components_match_textbook_shape():
    agv = classic.load("agv")
    assert [g.n_states for g in agv.plants] == [4, 8, 4, 6, 4]
    assert len(agv.specs) == 8
    assert all(e.controllable == (int(e.name) % 2 == 1) for g in agv.plants for e in g.alphabet)
    cm = classic.load("cat_mouse")
    cat, mouse = cm.plants
    assert cat.uncontrollable == {"c7"} and not mouse.uncontrollable
    assert cat.state_label(cat.init) == "room2" and mouse.state_label(mouse.init) == "room4"


@pytest.mark.parametrize("name", ["small_factory", "transfer_line", "agv", "cat_mouse"])
def test_data_files_are_read_identically_by_libfaudes(name):
    from importlib import resources

    m = classic.load(name)
    folder = resources.files("supcoord") / "data" / "classic" / name
    for g in m.plants + m.specs:
        with resources.as_file(folder / f"{g.name}.gen") as path:
            s = faudes.System(str(path))
        assert (s.Size(), s.TransRelSize(), s.MarkedStatesSize()) == (g.n_states, g.n_transitions, len(g.marked))
        assert {s.EventName(e) for e in s.ControllableEvents()} == set(g.controllable)
        assert {s.EventName(e) for e in s.Alphabet()} == set(g.events)
