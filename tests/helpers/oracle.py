"""libFAUDES as the independent oracle: conversions and the operations tests compare to.

``to_faudes(g)`` builds a ``faudes.System`` (controllable events marked as libFAUDES
does), ``from_faudes(sys)`` reads any libFAUDES generator back (initial state first,
then the others in libFAUDES's order), and the wrappers call libFAUDES the way it is
meant to be used: ``faudes_supcon(plant, spec)`` lifts the specification to the plant
alphabet with ``InvProject`` and then calls ``faudes.SupCon(plant, spec, result)``.

``import faudes`` is required: the oracle never skips.
"""

from __future__ import annotations

import faudes

from supcoord.des.generator import Event, Generator

__all__ = [
    "to_faudes",
    "from_faudes",
    "faudes_supcon",
    "faudes_parallel",
    "faudes_accessible",
    "faudes_coaccessible",
    "faudes_trim",
    "faudes_is_controllable",
    "faudes_is_nonblocking",
]

if hasattr(faudes, "Verbosity"):
    try:
        faudes.Verbosity(0)
    except Exception:  # pragma: no cover - older bindings
        pass


def to_faudes(g: Generator) -> "faudes.System":
    """A libFAUDES System with ``g``'s states (named ``q<i>`` or by ``state_names``),
    events (``+C+`` where controllable), transitions, initial and marked states."""
    s = faudes.System()
    s.Name(g.name)
    ev = {}
    for e in g.alphabet:
        ev[e.name] = s.InsControllableEvent(e.name) if e.controllable else s.InsUncontrollableEvent(e.name)
    idx = [s.InsState(f"q{q}") for q in range(g.n_states)]
    if g.init is not None:
        s.SetInitState(idx[g.init])
    for q in g.marked:
        s.SetMarkedState(idx[q])
    for src, e, dst in g.transitions():
        s.SetTransition(idx[src], ev[e], idx[dst])
    return s


def from_faudes(sys: "faudes.Generator", name: str | None = None) -> Generator:
    """An explicit generator from a libFAUDES one (deterministic, at most one initial state)."""
    lists = sys.ToLists()
    if len(lists) == 6:
        states, sigma, sigma_c, delta, init, marked = lists
    else:  # a plain Generator: no controllability attribute
        states, sigma, delta, init, marked = lists
        sigma_c = []
    if len(init) > 1:
        raise ValueError(f"libFAUDES generator with {len(init)} initial states")
    order = list(init) + [q for q in states if q not in set(init)]
    number = {q: i for i, q in enumerate(order)}
    controllable = set(sigma_c)
    events = [Event(str(e), e in controllable) for e in sigma]
    trans = [(number[s], str(e), number[d]) for s, e, d in delta]
    return Generator(
        len(order), events, trans, 0 if init else None, [number[q] for q in marked], name or sys.Name() or "F"
    )


def _faudes_names(events) -> "faudes.EventSet":
    out = faudes.EventSet()
    for e in events:
        out.Insert(e)
    return out


def faudes_parallel(*gens: Generator) -> Generator:
    """libFAUDES ``Parallel`` (accessible synchronous product)."""
    res = to_faudes(gens[0])
    for g in gens[1:]:
        out = faudes.System()
        faudes.Parallel(res, to_faudes(g), out)
        res = out
    # Parallel keeps the alphabet but not the controllability attributes of plain Generators
    g = from_faudes(res)
    flags = {e.name: e.controllable for x in gens for e in x.alphabet}
    return Generator(g.n_states, [Event(n, flags[n]) for n in g.events], g.transitions(), g.init, g.marked, g.name)


def faudes_accessible(g: Generator) -> set[int]:
    """The states of ``g`` that libFAUDES ``Accessible`` keeps (as ``g``'s numbers)."""
    s = to_faudes(g)
    faudes.Accessible(s)
    return _kept(s)


def faudes_coaccessible(g: Generator) -> set[int]:
    """The states of ``g`` that libFAUDES ``Coaccessible`` keeps (as ``g``'s numbers)."""
    s = to_faudes(g)
    faudes.Coaccessible(s)
    return _kept(s)


def faudes_trim(g: Generator) -> set[int]:
    """The states of ``g`` that libFAUDES ``Trim`` keeps (as ``g``'s numbers)."""
    s = to_faudes(g)
    faudes.Trim(s)
    return _kept(s)


def _kept(s) -> set[int]:
    return {int(str(name)[1:]) for name in s.ToLists()[0]}


def _with_flags(h: Generator, like: Generator) -> Generator:
    return Generator(h.n_states, [like.events[n] for n in h.events], h.transitions(), h.init, h.marked, h.name)


def faudes_supcon(plant: Generator, spec: Generator) -> Generator:
    """libFAUDES's supcon: spec lifted by ``InvProject`` to the plant alphabet, then
    ``SupCon(System plant, Generator spec, Generator result)``."""
    p = to_faudes(plant)
    s = to_faudes(spec)
    faudes.InvProject(s, p.Alphabet())
    result = faudes.System()
    faudes.SupCon(p, s, result)
    h = from_faudes(result, "V")
    # the result's alphabet is the plant's; restore controllability flags
    return Generator(h.n_states, plant.alphabet, h.transitions(), h.init, h.marked, "V")


def faudes_is_controllable(plant: Generator, candidate: Generator) -> bool:
    """``faudes.IsControllable(System plant, Generator candidate)`` with TCT's meaning:
    plant events the candidate lacks join its alphabet without transitions (disabled)."""
    missing = [e for e in plant.alphabet if e.name not in candidate.events]
    c = Generator(candidate.n_states, candidate.alphabet + missing, candidate.transitions(), candidate.init,
                  candidate.marked, candidate.name)
    return bool(faudes.IsControllable(to_faudes(plant), to_faudes(c)))


def faudes_is_nonblocking(g: Generator) -> bool:
    return bool(faudes.IsNonblocking(to_faudes(g)))
