"""Symbolic generators: state variables, one transition relation per event.

A :class:`SymbolicGenerator` over a :class:`~supcoord.bdd.Context` represents
``G = (Q, Σ, δ, q0, Qm)`` with

- ``Q = {x : invariant(x)}``, ``x`` an assignment to the finite-domain ``variables``;
- for each event ``σ`` an :class:`EventRelation` ``R_σ(x, x'_W)`` with its write set
  ``W_σ``: ``δ(x, σ) = y`` iff ``R_σ(x, y_W)``, ``y_v = x_v`` for every ``v ∉ W_σ`` (the
  frame is implicit), and both ``x`` and ``y`` satisfy the invariant.  A relation may
  read variables it does not write (guards);
- ``init(x)`` (at most one state: generators are deterministic) and ``marked(x)``.

Relations stay partitioned by event, each over the few variables it touches, so an
image costs one ``AndAbstract`` over those bits and a rename of the written ones:
``Post_σ(S) = (∃ x_W . S ∧ R_σ)[x'_W := x_W] ∧ inv`` and
``Pre_σ(T) = ∃ x'_W . R_σ ∧ (T ∧ inv)[x_W := x'_W]``, conjoined with ``inv``.
Restricting a generator to a state set (a supervisor is the plant product restricted
to its winning set) only conjoins the invariant: relations are never rebuilt.

References
----------
- J. R. Burch, E. M. Clarke, D. E. Long, Symbolic model checking with partitioned
  transition relations, VLSI 1991.
- W. M. Wonham, K. Cai, *Supervisory Control of Discrete-Event Systems*, 2019.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Iterable, Mapping

from ..bdd.context import BDD, Context
from ..errors import InputError
from ..progress import summary_html
from .generator import Event, Generator

__all__ = ["EventRelation", "SymbolicGenerator", "from_explicit", "to_explicit"]


@dataclass
class EventRelation:
    """``R_σ(x, x'_W)``: the transitions of one event; variables outside ``writes`` keep their value."""

    event: Event
    relation: BDD
    writes: tuple[str, ...] = ()


@dataclass
class SymbolicGenerator:
    """A deterministic generator whose states are assignments to BDD variables."""

    ctx: Context
    name: str
    variables: tuple[str, ...]
    events: dict[str, EventRelation]
    init: BDD
    marked: BDD
    invariant: BDD
    _bits: dict[str, tuple[list[str], list[str]]] = field(default_factory=dict, repr=False)

    # -- alphabet ------------------------------------------------------------

    @property
    def alphabet(self) -> list[Event]:
        return [r.event for r in self.events.values()]

    @property
    def controllable(self) -> list[str]:
        return [n for n, r in self.events.items() if r.event.controllable]

    @property
    def uncontrollable(self) -> list[str]:
        return [n for n, r in self.events.items() if not r.event.controllable]

    def relation(self, event: str) -> EventRelation:
        try:
            return self.events[event]
        except KeyError:
            raise InputError(f"event {event!r} is not in the alphabet of {self.name!r}", value=event) from None

    def _event_bits(self, event: str) -> tuple[list[str], list[str]]:
        cached = self._bits.get(event)
        if cached is None:
            writes = self.relation(event).writes
            cached = (self.ctx.bits(writes), self.ctx.bits(writes, primed=True))
            self._bits[event] = cached
        return cached

    # -- images --------------------------------------------------------------

    def post(self, states: BDD, event: str) -> BDD:
        """``{δ(x, σ) : x ∈ states}``."""
        r = self.relation(event)
        qbits, _ = self._event_bits(event)
        img = self.ctx.and_exist(states & self.invariant, r.relation, qbits)
        return self.ctx.unprime(img, r.writes) & self.invariant

    def pre(self, states: BDD, event: str) -> BDD:
        """``{x ∈ Q : δ(x, σ) ∈ states}``."""
        r = self.relation(event)
        _, pbits = self._event_bits(event)
        target = self.ctx.prime(states & self.invariant, r.writes)
        return self.ctx.and_exist(r.relation, target, pbits) & self.invariant

    def enabled(self, event: str) -> BDD:
        """``{x ∈ Q : δ(x, σ)!}``: the states where ``σ`` is defined."""
        return self.pre(self.invariant, event)

    def enabled_sets(self, events: Iterable[str] | None = None) -> dict[str, BDD]:
        """``{σ: Pre_σ(Q)}`` for the given events (default all), priming ``Q`` once per
        write set rather than once per event (``dd``'s ``let`` costs time in the number
        of declared variables, whatever the size of the BDD)."""
        primed: dict[tuple[str, ...], BDD] = {}
        out = {}
        for e in self.events if events is None else events:
            r = self.relation(e)
            target = primed.get(r.writes)
            if target is None:
                target = primed[r.writes] = self.ctx.prime(self.invariant, r.writes)
            _, pbits = self._event_bits(e)
            out[e] = self.ctx.and_exist(r.relation, target, pbits) & self.invariant  # ∃x'_W. R_σ ∧ Q[x_W := x'_W]
        return out

    # -- derived generators --------------------------------------------------

    def restrict(self, states: BDD, name: str | None = None) -> "SymbolicGenerator":
        """The sub-generator on ``Q ∩ states``: only the invariant changes."""
        inv = self.invariant & states
        return SymbolicGenerator(
            self.ctx, name or self.name, self.variables, dict(self.events), self.init & inv, self.marked & inv, inv
        )

    # -- measurements --------------------------------------------------------

    def count_states(self, states: BDD | None = None) -> int:
        """Exact ``|states ∩ Q|`` (all of ``Q`` by default)."""
        s = self.invariant if states is None else states & self.invariant
        return self.ctx.count(s, self.variables)

    def count_transitions(self, states: BDD | None = None) -> int:
        """Exact number of transitions leaving ``states ∩ Q`` (deterministic: one per
        state and enabled event): ``Σ_σ |states ∩ Pre_σ(Q)|``."""
        s = self.invariant if states is None else states & self.invariant
        return sum(self.ctx.count(s & en, self.variables) for en in self.enabled_sets().values())

    def node_count(self) -> int:
        """Nodes of the shared DAG of all relations, init, marked and invariant."""
        return self.ctx.node_count(self.init, self.marked, self.invariant, *(r.relation for r in self.events.values()))

    def state_of(self, values: Mapping[str, int]) -> BDD:
        """The BDD of one state given as ``{variable: value}`` (all variables)."""
        missing = [v for v in self.variables if v not in values]
        if missing:
            raise InputError(f"state of {self.name!r} lacks values for {missing}", value=missing)
        return self.ctx.assignment({v: values[v] for v in self.variables}) & self.invariant

    def pick(self, states: BDD) -> dict[str, int] | None:
        return self.ctx.pick(states & self.invariant, self.variables)

    def summary(self) -> dict[str, Any]:
        """What a notebook shows: name, numbers of variables and events (never a BDD)."""
        return {"name": self.name, "variables": len(self.variables), "events": len(self.events)}

    def __repr__(self) -> str:
        return f"SymbolicGenerator({self.name!r}, variables={len(self.variables)}, events={len(self.events)})"

    def _repr_html_(self) -> str:
        return summary_html("SymbolicGenerator", self.summary())


def from_explicit(ctx: Context, g: Generator, var: str | None = None) -> SymbolicGenerator:
    """Encode an explicit generator with one finite-domain variable (its state number).

    A one-state generator needs no variable: its relations are ``TRUE`` (selfloops)
    or absent, as for ``allevents``.
    """
    if g.n_states <= 1:
        marked = ctx.true if (g.n_states == 1 and 0 in g.marked) else ctx.false
        init = ctx.true if g.n_states == 1 else ctx.false
        events = {
            e.name: EventRelation(e, ctx.true if g.successor(0, e.name) is not None else ctx.false, ())
            for e in g.alphabet
        }
        inv = ctx.true if g.n_states == 1 else ctx.false
        return SymbolicGenerator(ctx, g.name, (), events, init, marked, inv)
    name = var or ctx.fresh_name(g.name)
    ctx.add_variable(name, g.n_states)
    state = [ctx.eq(name, q) for q in range(g.n_states)]
    by_event: dict[str, dict[int, BDD]] = {e: {} for e in g.events}
    for s, e, d in g.transitions():
        row = by_event[e]
        row[d] = row.get(d, ctx.false) | state[s]
    events = {}
    for e, ev in g.events.items():
        rel = ctx.false
        for d, sources in by_event[e].items():
            rel |= sources & ctx.eq(name, d, primed=True)
        events[e] = EventRelation(ev, rel, (name,))
    marked = ctx.false
    for q in g.marked:
        marked |= state[q]
    return SymbolicGenerator(ctx, g.name, (name,), events, state[g.init], marked, ctx.domain([name]))


def to_explicit(sg: SymbolicGenerator, max_states: int = 1_000_000, name: str | None = None,
                states: BDD | None = None) -> Generator:
    """The accessible part of ``sg`` as an explicit generator, numbered breadth-first
    from the initial state with events in alphabet order (deterministic).

    State names are the variable values, e.g. ``"G=3,E=0"``.  The states are
    enumerated in bulk (:func:`supcoord.des.symbolic_export.to_flat`); ``states``, when
    given, is a set holding the accessible states (a supervisor's state set), which
    spares computing them.  Raises :class:`InputError` beyond ``max_states`` states.
    """
    from .symbolic_export import to_flat

    return to_flat(sg, states, max_states, name).to_generator()
