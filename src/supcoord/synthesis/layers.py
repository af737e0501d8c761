"""The forcibility layers as a value, and the states the forcing functions take.

:class:`Layers` holds the iterates of ``W(k+1) = W(k) ∪ Force(W(k))`` from a target
``T`` (:mod:`.forcibility`): the layers ``L(k) = W(k) \\ W(k-1)`` (``L(0) = T``) and
``rank(q) = min {k : q ∈ W(k)}``; :func:`rank_naive` is the rank read from explicit
layers.  :func:`as_states` reads a state or a set of states given as a BDD, a
``{variable: value}`` dict or a state number.

References
----------
- A. Macktoobian, W. M. Wonham, Automatic reconfiguration of untimed discrete-event
  systems, ICEEE 2017 (backtracking forcibility).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Mapping, Sequence, TypedDict

from ..bdd.context import BDD
from ..des.symbolic import SymbolicGenerator
from ..errors import InputError
from ..progress import summary_html, summary_repr

__all__ = ["SEMANTICS", "check_semantics", "Layers", "LayerStats", "rank_naive", "as_states", "as_single_state"]

SEMANTICS = ("preemptive", "standard")


def check_semantics(semantics: str) -> None:
    """Raise :class:`InputError` unless ``semantics`` is one of :data:`SEMANTICS`."""
    if semantics not in SEMANTICS:
        raise InputError(f"unknown forcibility semantics {semantics!r} (use preemptive or standard)", value=semantics)


class LayerStats(TypedDict, total=False):
    """The statistics of a forcibility fixpoint: ``iterations`` (layers computed),
    ``seconds`` (wall-clock, s), ``bdd_nodes`` (the layers' shared DAG, nodes),
    ``peak_nodes`` (the manager's peak, nodes); ``dag_nodes`` (nodes) after
    :func:`~.forcibility.bfa`."""

    iterations: int
    seconds: float
    bdd_nodes: int
    peak_nodes: int
    dag_nodes: int


@dataclass
class Layers:
    """The iterates of the forcibility fixpoint: ``layers[k] = L(k)``, ``winning = ⋃ L(k)``.

    ``complete`` is False when the iteration stopped early (``stop_at``), so ``winning``
    is then ``W(k)`` for the last ``k`` computed, not ``W(∞)``.  ``env_states`` is the set
    of states with ``U(q) ≠ ∅`` (where, under preemptive semantics, the environment acts).
    """

    generator: SymbolicGenerator
    layers: list[BDD]
    winning: BDD
    semantics: str
    env_states: BDD
    complete: bool = True
    stats: LayerStats = field(default_factory=LayerStats)

    def __len__(self) -> int:
        return len(self.layers)

    def summary(self) -> dict[str, Any]:
        """What a notebook shows: the generator, the semantics, how many layers, complete or not."""
        return {"generator": getattr(self.generator, "name", "?"), "semantics": self.semantics,
                "layers": len(self.layers), "complete": self.complete}

    def __repr__(self) -> str:
        return summary_repr("Layers", self.summary())

    def _repr_html_(self) -> str:
        return summary_html("Layers", self.summary())

    @property
    def target(self) -> BDD:
        return self.layers[0] if self.layers else self.generator.ctx.false

    def rank(self, state: Any) -> int | None:
        """Least ``k`` with ``state ⊆ W(k)`` (a single state: its rank), None if none.

        ``state`` is a BDD, a ``{variable: value}`` dict, a list of component dicts or
        (one-variable generators) a state number; see :func:`as_states`.
        """
        s = as_states(self.generator, state)
        false = self.generator.ctx.false
        if s == false:
            return None
        for k, layer in enumerate(self.layers):
            s = s & ~layer  # what is not yet in W(k)
            if s == false:
                return k
        return None

    def sizes(self) -> list[int]:
        """Exact number of states in each layer (arbitrary-precision integers)."""
        return [self.generator.count_states(layer) for layer in self.layers]

    def prefix(self, k: int) -> BDD:
        """``W(k) = L(0) ∪ … ∪ L(k)`` (``W(-1) = ∅``)."""
        w = self.generator.ctx.false
        for layer in self.layers[: max(0, k + 1)]:
            w |= layer
        return w

    def controller_states(self) -> BDD:
        """Where the controller chooses the next event: everywhere under standard
        semantics, only where ``U(q) = ∅`` under preemptive semantics."""
        if self.semantics == "preemptive":
            return self.generator.invariant & ~self.env_states
        return self.generator.invariant


def rank_naive(layers: Sequence[set[int]], q: int) -> int | None:
    """The explicit twin of :meth:`Layers.rank`: the first layer holding ``q``, or ``None``."""
    for k, layer in enumerate(layers):
        if q in layer:
            return k
    return None


# -- states given in several forms -------------------------------------------------


def as_states(G: SymbolicGenerator, x: Any) -> BDD:
    """A set of states of ``G`` from a BDD, a ``{variable: value}`` dict, a list of
    dicts (one per component of a product: merged), a tuple of component states (one
    value per variable, in ``G.variables`` order: for a product of explicit components
    encoded by :func:`~supcoord.des.symbolic.from_explicit`, their state numbers), a
    state number (generators with one variable), or ``None`` for the initial state.
    Conjoined with ``G.invariant``.
    """
    ctx = G.ctx
    if x is None:
        return G.init
    if getattr(x, "bdd", None) is ctx.bdd:
        return x & G.invariant
    if isinstance(x, Mapping):
        return G.state_of(x)
    if isinstance(x, bool):
        raise InputError(f"a state cannot be given as {x!r}", value=x)
    if isinstance(x, int):
        if len(G.variables) == 1:
            return G.state_of({G.variables[0]: x})
        if not G.variables and x == 0:
            return G.invariant
        raise InputError(f"state number {x} needs a one-variable generator; {G.name!r} has {len(G.variables)}", value=x)
    if isinstance(x, (list, tuple)) and all(isinstance(p, Mapping) for p in x):
        merged: dict[str, int] = {}
        for part in x:
            merged.update(part)
        return G.state_of(merged)
    if isinstance(x, tuple) and all(isinstance(p, int) and not isinstance(p, bool) for p in x):
        if len(x) != len(G.variables):
            raise InputError(
                f"a state of {G.name!r} as a tuple needs one value per variable {G.variables}, got {x!r}", value=x
            )
        return G.state_of(dict(zip(G.variables, x)))
    raise InputError(f"cannot read a state of {G.name!r} from {x!r}", value=x)


def as_single_state(G: SymbolicGenerator, x: Any) -> BDD:
    """Like :func:`as_states` but exactly one state (a cube), else :class:`InputError`."""
    s = as_states(G, x)
    values = G.pick(s)
    if values is None:
        raise InputError(f"no such state in {G.name!r}: {x!r}", value=x)
    cube = G.state_of(values) if G.variables else G.invariant
    if cube != s:
        raise InputError(f"expected one state of {G.name!r}, got a set of several", value=x)
    return cube
