"""Hypothesis strategies shared by the tests: random deterministic generators.

``generators(alphabet)`` draws an explicit generator over a subset of ``alphabet``
(at least one event), 1–``max_states`` states, a random partial deterministic
transition function, a random marking.  ``alphabets()`` draws events with mixed
controllability; ``systems()`` draws a few plant components and a few spec
components over one alphabet, as synthesis tests need.
"""

from __future__ import annotations

from hypothesis import strategies as st

from supcoord.des.generator import Event, Generator

EVENT_NAMES = ["a", "b", "c", "d", "e", "f", "g", "h"]


@st.composite
def alphabets(draw, min_size: int = 2, max_size: int = 6) -> list[Event]:
    n = draw(st.integers(min_size, max_size))
    names = EVENT_NAMES[:n]
    flags = draw(st.lists(st.booleans(), min_size=n, max_size=n))
    return [Event(name, flag) for name, flag in zip(names, flags)]


@st.composite
def generators(draw, alphabet: list[Event], max_states: int = 5, name: str = "G", full_alphabet: bool = False,
               density: float | None = None) -> Generator:
    n = draw(st.integers(1, max_states))
    if full_alphabet:
        events = list(alphabet)
    else:
        events = draw(st.lists(st.sampled_from(alphabet), min_size=1, max_size=len(alphabet), unique=True))
    p = density if density is not None else draw(st.sampled_from([0.3, 0.5, 0.8]))
    transitions = []
    for q in range(n):
        for e in events:
            if draw(st.floats(0, 1)) < p:
                transitions.append((q, e.name, draw(st.integers(0, n - 1))))
    marked = draw(st.lists(st.integers(0, n - 1), max_size=n, unique=True))
    return Generator(n, events, transitions, 0, marked, name)


@st.composite
def systems(draw, max_plants: int = 3, max_specs: int = 2, max_states: int = 4):
    """``(alphabet, plants, specs)`` with every spec event somewhere in the plants."""
    alphabet = draw(alphabets())
    plants = draw(st.lists(generators(alphabet, max_states, "P"), min_size=1, max_size=max_plants))
    plant_events = [e for e in alphabet if any(e.name in p.events for p in plants)]
    specs = draw(st.lists(generators(plant_events, max_states, "E"), min_size=1, max_size=max_specs))
    plants = [Generator(p.n_states, p.alphabet, p.transitions(), p.init, p.marked, f"P{i}") for i, p in enumerate(plants)]
    specs = [Generator(s.n_states, s.alphabet, s.transitions(), s.init, s.marked, f"E{i}") for i, s in enumerate(specs)]
    return alphabet, plants, specs
