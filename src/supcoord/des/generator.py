"""Explicit (TCT-like) generators: numbered states, events with a controllable flag.

A generator is ``G = (Q, Σ, δ, q0, Qm)`` with ``Q = {0, …, n-1}``, ``Σ = Σc ⊎ Σu``,
a deterministic partial ``δ : Q × Σ → Q``, an initial state ``q0`` (``None`` for the
empty generator, ``n = 0``) and marked states ``Qm ⊆ Q``.  This is the explicit
reference representation: every symbolic algorithm has a twin over it.

TCT numbers events with integers, odd meaning controllable; :func:`tct_event` and
:meth:`Generator.from_tct` follow that convention.

References
----------
- W. M. Wonham, K. Cai, *Supervisory Control of Discrete-Event Systems*, Springer 2019, ch. 2–3.
"""

from __future__ import annotations

import numbers

from dataclasses import dataclass
from typing import Iterable, Iterator, Mapping, Sequence

from ..errors import AlphabetError, InputError, NondeterminismError

__all__ = ["Event", "Generator", "tct_event", "merge_alphabets", "check_equal_alphabets", "check_new_events", "event_key",
           "MAX_STATES"]


@dataclass(frozen=True, order=True)
class Event:
    """An event label and whether a supervisor may disable it."""

    name: str
    controllable: bool


#: most states of an explicit generator (each becomes Python objects, then a BDD minterm)
MAX_STATES = 10_000_000


def tct_event(label: int | str) -> Event:
    """TCT's convention: an integer label, odd = controllable (``tct_event(71)``)."""
    if isinstance(label, bool) or not (isinstance(label, numbers.Integral)
                                       or (isinstance(label, str) and label.strip().isdigit())):
        raise InputError(f"TCT event labels are non-negative integers (or their digits), got {label!r}", value=label)
    number = int(label)
    if number < 0:
        raise InputError(f"TCT event labels are non-negative, got {number}", value=label)
    return Event(str(number), number % 2 == 1)


def event_key(name: str) -> tuple[int, int, str]:
    """Deterministic order of event names: TCT numbers numerically, then other names.

    >>> sorted(["9", "10", "b", "a"], key=event_key)
    ['9', '10', 'a', 'b']
    """
    return (0, int(name), "") if name.isdigit() else (1, 0, name)


def merge_alphabets(alphabets: Iterable[Iterable[Event]]) -> dict[str, Event]:
    """The union of several alphabets, in first-seen order.

    Raises :class:`AlphabetError` if one name is controllable in one alphabet and
    uncontrollable in another.
    """
    merged: dict[str, Event] = {}
    for alphabet in alphabets:
        for e in alphabet:
            old = merged.get(e.name)
            if old is None:
                merged[e.name] = e
            elif old.controllable != e.controllable:
                raise AlphabetError(
                    f"event {e.name!r} is controllable in one component and uncontrollable in another",
                    value=e.name,
                )
    return merged


def check_equal_alphabets(gens: Sequence) -> None:
    """Raise :class:`AlphabetError` unless all generators (explicit or symbolic) have
    the same event names, as TCT's ``meet`` requires."""
    if gens:
        first = set(gens[0].events)
        for g in gens[1:]:
            if set(g.events) != first:
                diff = sorted(first.symmetric_difference(g.events))
                raise AlphabetError(f"meet needs equal alphabets; {g.name!r} differs in {diff}", value=diff)


def check_new_events(g, events: Sequence[Event]) -> None:
    """Raise :class:`AlphabetError` if some of ``events`` are in the alphabet of ``g``
    (explicit or symbolic), as TCT's ``selfloop`` requires."""
    clash = [e.name for e in events if e.name in g.events]
    if clash:
        raise AlphabetError(f"selfloop: events already in the alphabet of {g.name!r}: {clash}", value=clash)


Transition = tuple[int, str, int]


class Generator:
    """An explicit deterministic generator.

    >>> g = Generator(2, [Event("a", True), Event("b", False)], [(0, "a", 1), (1, "b", 0)], marked=[0])
    >>> g.n_states, g.n_transitions, g.successor(0, "a")
    (2, 2, 1)
    """

    def __init__(
        self,
        states: int,
        events: Iterable[Event],
        transitions: Iterable[Transition],
        init: int | None = 0,
        marked: Iterable[int] = (),
        name: str = "G",
        state_names: Sequence[str] | None = None,
    ):
        if isinstance(states, bool) or not isinstance(states, int) or states < 0:
            raise InputError(f"number of states must be a non-negative integer, got {states!r}", value=states)
        if states > MAX_STATES:
            raise InputError(f"an explicit generator has at most {MAX_STATES} states, got {states}", value=states,
                             where="states")
        if init is not None and (isinstance(init, bool) or not isinstance(init, numbers.Integral)):
            raise InputError(f"the initial state must be an integer state index, got {init!r}", value=init)
        if not isinstance(name, str):
            raise InputError(f"a generator's name must be a string, got {name!r}", value=name)
        self.name = name
        self.n_states = states
        self.events: dict[str, Event] = merge_alphabets([list(events)])
        if states == 0:
            init = None
        elif init is None or not 0 <= init < states:
            raise InputError(f"initial state {init!r} outside 0..{states - 1}", value=init)
        self.init = init
        self.marked = frozenset(marked)
        for q in self.marked:
            self._check_state(q, "marked state")
        self.delta: dict[int, dict[str, int]] = {}
        count = 0
        for src, ev, dst in transitions:
            self._check_state(src, "transition source")
            self._check_state(dst, "transition target")
            if ev not in self.events:
                raise AlphabetError(f"transition ({src}, {ev!r}, {dst}) uses an event outside the alphabet", value=ev)
            row = self.delta.setdefault(src, {})
            old = row.get(ev)
            if old is not None and old != dst:
                raise NondeterminismError(
                    f"generator {name!r} is nondeterministic: state {src} has event {ev!r} to {old} and to {dst}",
                    value=(src, ev, (old, dst)),
                )
            if old is None:
                count += 1
            row[ev] = dst
        self.n_transitions = count
        if state_names is not None and len(state_names) != states:
            raise InputError(f"{len(state_names)} state names for {states} states", value=len(state_names))
        self.state_names = list(state_names) if state_names is not None else None

    def _check_state(self, q: int, what: str) -> None:
        if not isinstance(q, int) or not 0 <= q < self.n_states:
            raise InputError(f"{what} {q!r} outside 0..{self.n_states - 1} in generator {self.name!r}", value=q)

    # -- construction helpers ------------------------------------------------

    @classmethod
    def from_tct(
        cls,
        states: int,
        transitions: Iterable[tuple[int, int, int]],
        init: int = 0,
        marked: Iterable[int] = (),
        name: str = "G",
        extra_events: Iterable[int] = (),
    ) -> "Generator":
        """Build from TCT-style ``(src, label, dst)`` triples, odd labels controllable."""
        triples = [(s, str(int(e)), d) for s, e, d in transitions]
        labels = sorted({int(e) for _, e, _ in triples} | {int(e) for e in extra_events})
        return cls(states, [tct_event(x) for x in labels], triples, init, marked, name)

    # -- queries -------------------------------------------------------------

    @property
    def alphabet(self) -> list[Event]:
        return list(self.events.values())

    @property
    def controllable(self) -> frozenset[str]:
        return frozenset(n for n, e in self.events.items() if e.controllable)

    @property
    def uncontrollable(self) -> frozenset[str]:
        return frozenset(n for n, e in self.events.items() if not e.controllable)

    def successor(self, q: int, event: str) -> int | None:
        """``δ(q, event)`` or ``None`` where undefined."""
        return self.delta.get(q, {}).get(event)

    def enabled(self, q: int) -> dict[str, int]:
        """The events defined at ``q`` with their targets."""
        return self.delta.get(q, {})

    def transitions(self) -> Iterator[Transition]:
        """All transitions, sorted by source state then event name."""
        for src in sorted(self.delta):
            for ev in sorted(self.delta[src]):
                yield src, ev, self.delta[src][ev]

    def run(self, string: Iterable[str], start: int | None = None) -> int | None:
        """``δ(start, s)`` for a string of event names, ``None`` if it is undefined."""
        q = self.init if start is None else start
        for ev in string:
            if q is None:
                return None
            q = self.successor(q, ev)
        return q

    def state_label(self, q: int) -> str:
        return self.state_names[q] if self.state_names else str(q)

    def __repr__(self) -> str:
        return (
            f"Generator({self.name!r}, states={self.n_states}, events={len(self.events)}, "
            f"transitions={self.n_transitions}, marked={len(self.marked)})"
        )

    # -- comparison ----------------------------------------------------------

    def canonical(self) -> "Generator":
        """The accessible part renumbered by breadth-first search from ``q0`` (events
        in name order): two generators are isomorphic iff their canonical forms are equal."""
        if self.init is None:
            return Generator(0, self.alphabet, [], None, (), self.name)
        order = {self.init: 0}
        queue = [self.init]
        for q in queue:
            for ev in sorted(self.enabled(q)):
                d = self.delta[q][ev]
                if d not in order:
                    order[d] = len(order)
                    queue.append(d)
        trans = [(order[s], e, order[d]) for s, e, d in self.transitions() if s in order]
        names = [self.state_label(q) for q in queue] if self.state_names else None
        return Generator(
            len(order), self.alphabet, trans, 0, [order[q] for q in self.marked if q in order], self.name, names
        )

    def same_as(self, other: "Generator") -> bool:
        """Isomorphic accessible parts with equal alphabets (names and controllability)."""
        if self.events != other.events:
            return False
        a, b = self.canonical(), other.canonical()
        return (
            a.n_states == b.n_states
            and a.marked == b.marked
            and list(a.transitions()) == list(b.transitions())
        )

    def relabel_states(self, names: Mapping[int, str]) -> "Generator":
        """A copy with state names."""
        return Generator(
            self.n_states, self.alphabet, self.transitions(), self.init, self.marked, self.name,
            [names.get(q, str(q)) for q in range(self.n_states)],
        )
