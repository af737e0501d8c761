"""Hypothesis strategies shared by the tests: random deterministic generators.

``generators(alphabet)`` draws an explicit generator over a subset of ``alphabet``
(at least one event), 1–``max_states`` states, a random partial deterministic
transition function, a random marking.  ``alphabets()`` draws events with mixed
controllability; ``systems()`` draws a few plant components and a few spec
components over one alphabet, as synthesis tests need, biased towards instances where
synthesis has work to do (components with marked states, both kinds of events), and
``describe_system`` classifies an instance so tests can assert that the cases they ran
cover what they claim (several components, mixed controllability, supervisors that are
nonempty and strictly smaller than the trim product).

``tight_route(clearance)`` is a constructed problem whose only plan passes one move with
exactly ``clearance`` mm to spare.  ``tight_problems()`` draws random tight geometric problems (PROBLEM.json dicts of
:func:`supcoord.testing.oracle.tight_problems.tight_problem`: rotary or alpha-beta, 2–6
positioners, about 40 % without a plan), for comparisons with the independent oracle.
"""

from __future__ import annotations

import math

from hypothesis import strategies as st

from supcoord.des.generator import Event, Generator
from supcoord.testing.oracle.tight_problems import tight_problem

EVENT_NAMES = ["a", "b", "c", "d", "e", "f", "g", "h"]


@st.composite
def alphabets(draw, min_size: int = 2, max_size: int = 6, mixed: bool = False) -> list[Event]:
    """``mixed=True``: at least one controllable and one uncontrollable event."""
    n = draw(st.integers(min_size, max_size))
    names = EVENT_NAMES[:n]
    flags = draw(st.lists(st.sampled_from([True, False, True]) if mixed else st.booleans(), min_size=n, max_size=n))
    if mixed and n >= 2 and len(set(flags)) < 2:
        flags[draw(st.integers(0, n - 1))] = not flags[0]
    return [Event(name, flag) for name, flag in zip(names, flags)]


@st.composite
def generators(draw, alphabet: list[Event], max_states: int = 5, name: str = "G", full_alphabet: bool = False,
               density: float | None = None, min_states: int = 1, min_marked: int = 0,
               u_density: float | None = None, split: bool = False, connected: bool = False) -> Generator:
    """``u_density``: the density of uncontrollable events' transitions (default
    ``density``); ``split``: every state is either the controller's (only controllable
    events leave it; ``q0`` is one) or the environment's (only uncontrollable ones), as
    in machine models (``start`` from idle, ``finish``/``break`` from working);
    ``connected``: every state is reachable from ``q0`` (a random spanning tree first)."""
    n = draw(st.integers(min_states, max(min_states, max_states)))
    if full_alphabet:
        events = list(alphabet)
    else:
        events = draw(st.lists(st.sampled_from(alphabet), min_size=1, max_size=len(alphabet), unique=True))
    p = density if density is not None else draw(st.sampled_from([0.3, 0.5, 0.8]))
    rnd = draw(st.randoms(use_true_random=False))  # uniform draws (st.floats favours 0.0 and 1.0)
    env = [False] + [rnd.random() < 0.5 for _ in range(n - 1)] if split else [None] * n
    used: dict[tuple[int, str], int] = {}
    if connected:
        for q in range(1, n):
            r = rnd.randrange(q)
            options = [e for e in events if env[r] is None or env[r] != e.controllable]
            free = [e for e in options if (r, e.name) not in used]
            if free:
                used[(r, rnd.choice(free).name)] = q
    for q in range(n):
        for e in events:
            if env[q] is not None and env[q] == e.controllable:
                continue
            if (q, e.name) not in used and rnd.random() < (p if e.controllable or u_density is None else u_density):
                used[(q, e.name)] = rnd.randrange(n)
    transitions = [(q, e, d) for (q, e), d in used.items()]
    marked = draw(st.lists(st.integers(0, n - 1), min_size=min(min_marked, n), max_size=n, unique=True))
    return Generator(n, events, transitions, 0, marked, name)


@st.composite
def systems(draw, max_plants: int = 3, max_specs: int = 2, max_states: int = 4):
    """``(alphabet, plants, specs)`` with every spec event somewhere in the plants, shaped
    like the classic benchmarks so that synthesis has work to do: each plant component
    has its own events (``c0``, ``u0``, … : at least one controllable and one
    uncontrollable, sometimes one shared with another component), 2–``max_states``
    states split between controller states (controllable events leave them) and
    environment states (uncontrollable ones), a marked state; each specification is
    either a random generator over a few plant events that mostly allows (a missing
    uncontrollable transition is what makes controllability bite) or a copy of a plant
    component with transitions deleted and its own marking."""
    k = draw(st.integers(1, max_plants))
    own: list[list[Event]] = []
    for i in range(k):
        flags = [True, False] + draw(st.lists(st.booleans(), max_size=1))
        own.append([Event(f"{'c' if f else 'u'}{i}{x}", f) for x, f in zip("xyz", flags)])
    alphabet = [e for events in own for e in events]
    plants = []
    for i in range(k):
        events = list(own[i])
        if k > 1 and draw(st.booleans()):  # share an event with another component
            j = draw(st.integers(0, k - 1).filter(lambda j, i=i: j != i))
            events.append(draw(st.sampled_from(own[j])))
        p = draw(st.sampled_from([0.5, 0.7, 0.9]))
        plants.append(draw(generators(events, max_states, f"P{i}", full_alphabet=True, density=p, min_states=2,
                                      min_marked=1, split=True, connected=True)))
    plant_events = [e for e in alphabet if any(e.name in g.events for g in plants)]
    specs = []
    for i in range(draw(st.integers(1, max_specs))):
        if draw(st.integers(0, 3)):
            base = plants[draw(st.integers(0, k - 1))]
            rnd = draw(st.randoms(use_true_random=False))
            kept = [t for t in base.transitions() if base.events[t[1]].controllable or rnd.random() < 0.5]
            marked = draw(st.lists(st.integers(0, base.n_states - 1), min_size=1, max_size=base.n_states, unique=True))
            specs.append(Generator(base.n_states, base.alphabet, kept, 0, marked, f"E{i}"))
        else:
            events = draw(st.lists(st.sampled_from(plant_events), min_size=1, max_size=4, unique=True))
            p = draw(st.sampled_from([0.75, 0.85, 0.95]))
            g = draw(generators(events, max_states, "E", full_alphabet=True, density=p, min_states=2, min_marked=1,
                                u_density=0.6))
            specs.append(Generator(g.n_states, g.alphabet, g.transitions(), 0, g.marked, f"E{i}"))
    return alphabet, plants, specs


def describe_system(plants: list[Generator], G: Generator, V: Generator, product_trim: Generator) -> set[str]:
    """Labels of one synthesis case, for coverage assertions: ``several_plants``,
    ``mixed`` (the plant has both kinds of events), ``nonempty`` (a supervisor),
    ``pruned`` (nonempty and strictly smaller than the trim ``G × E``: controllability
    removed states), ``emptied`` (the trim ``G × E`` is nonempty, the supervisor empty)."""
    labels = set()
    if len(plants) >= 2:
        labels.add("several_plants")
    if G.controllable and G.uncontrollable:
        labels.add("mixed")
    if V.n_states:
        labels.add("nonempty")
        if V.n_states < product_trim.n_states:
            labels.add("pruned")
    elif product_trim.n_states:
        labels.add("emptied")
    return labels


@st.composite
def tight_problems(draw, min_n: int = 2, max_n: int = 4, max_product: int = 50_000, ties: bool = False) -> dict:
    """A random tight problem as PROBLEM.json (module docstring), seeded by the draw;
    ``ties=False`` leaves out the seeds with round numbers (arms touching at exactly the
    buffer sum, where the oracle answers with bounds rather than one distance)."""
    seed = draw(st.integers(0, 10**6).filter(lambda s: ties or s % 10 != 7))
    n = draw(st.integers(min_n, max_n))
    return tight_problem(seed, n=n, max_product=max_product)


def tight_route(clearance: float, angle_deg: float = -15.0) -> dict:
    """Rotary ``a`` (arm 10, 12 steps) must turn 0 → 3 clockwise: the way round is shut by
    ``c``'s base at (0, 13) (3 mm from ``a``'s tip at 90°, buffers 2 + 2).  ``b``'s base
    stands ``10 + 4 + clearance`` from ``a``'s base at ``angle_deg`` (mid-step 0 → 1 for
    −15°) with its arm pointing away, so whatever ``b`` does, the move 0 → 1 passes it with
    exactly ``clearance`` to spare: the problem has a 3-move plan iff that move is free."""
    rb = 14.0 + clearance
    b = rb * complex(math.cos(math.radians(angle_deg)), math.sin(math.radians(angle_deg)))
    return {"layout": {"kind": "points", "xy": [[0.0, 0.0], [b.real, b.imag], [0.0, 13.0]]},
            "kinematics": {"kind": "rotary", "arm": 10.0, "steps": 12}, "collision": {"buffer": 2.0},
            "start": [0, 0, 9], "target": [3, 0, 9]}
