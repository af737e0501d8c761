"""Flat explicit generators: the states, transitions and marking of one explicit
generator as arrays, for generators too large to hold as Python dictionaries.

A :class:`FlatGenerator` is ``G = (Q, Σ, δ, q0, Qm)`` with ``Q = {0, …, n-1}``,
``Σ`` a list of :class:`~supcoord.des.generator.Event` and ``δ`` given by three
integer arrays ``src``, ``ev`` (positions in ``Σ``), ``dst``: ``δ(src[k], Σ[ev[k]]) =
dst[k]``, deterministic (at most one ``k`` per ``(src, ev)``).  It has the meaning of
:class:`~supcoord.des.generator.Generator` (:meth:`FlatGenerator.to_generator`,
:func:`from_generator`); the file readers build it directly, the explicit route of
``supcoord supcon`` computes on it, and the writers write it without building
dictionaries.

The operations on these arrays (breadth-first numbering, look-ups of packed
states) are in :mod:`.flat_ops`.

References
----------
- W. M. Wonham, K. Cai, *Supervisory Control of Discrete-Event Systems*, Springer 2019, ch. 2.
"""

from __future__ import annotations

from dataclasses import dataclass
from collections.abc import Sequence

import numpy as np

from .generator import Event, Generator

__all__ = ["FlatGenerator", "from_generator", "check_deterministic_arrays", "renumber"]


@dataclass
class FlatGenerator:
    """An explicit deterministic generator held as arrays (see the module docstring)."""

    name: str
    events: list[Event]
    n_states: int
    src: np.ndarray
    ev: np.ndarray
    dst: np.ndarray
    init: int | None
    marked: np.ndarray  # state numbers, sorted, unique
    state_names: list[str] | None = None

    @property
    def n_transitions(self) -> int:
        return len(self.src)

    @property
    def event_names(self) -> list[str]:
        return [e.name for e in self.events]

    def to_generator(self) -> Generator:
        """The same generator as a :class:`Generator`."""
        names = self.event_names
        evs = [names[e] for e in self.ev.tolist()]
        return Generator(
            self.n_states, self.events, zip(self.src.tolist(), evs, self.dst.tolist()), self.init,
            self.marked.tolist(), self.name, self.state_names,
        )

    def __repr__(self) -> str:
        return (f"FlatGenerator({self.name!r}, states={self.n_states}, events={len(self.events)}, "
                f"transitions={self.n_transitions}, marked={len(self.marked)})")


def from_generator(g: Generator) -> FlatGenerator:
    """The arrays of an explicit :class:`Generator`."""
    position = {e: k for k, e in enumerate(g.events)}
    triples = [(s, position[e], d) for s, row in g.delta.items() for e, d in row.items()]
    arr = np.array(triples, dtype=np.int64).reshape(-1, 3)
    return FlatGenerator(g.name, g.alphabet, g.n_states, arr[:, 0].copy(), arr[:, 1].copy(), arr[:, 2].copy(),
                         g.init, np.array(sorted(g.marked), dtype=np.int64), g.state_names)


def check_deterministic_arrays(src: np.ndarray, ev: np.ndarray, dst: np.ndarray, n_events: int,
                               name: str = "G") -> tuple[np.ndarray, np.ndarray, np.ndarray, int | None]:
    """Drop repeated transitions; return ``(src, ev, dst, k)`` sorted by ``(src, ev)``
    where ``k`` is the position (in the input) of a transition that conflicts with an
    earlier one on the same ``(src, ev)``, or ``None`` when the arrays are deterministic."""
    if len(src) == 0:
        return src, ev, dst, None
    key = src.astype(np.int64) * max(n_events, 1) + ev
    ks = np.sort(key)
    if not (ks[1:] == ks[:-1]).any():
        return src, ev, dst, None
    order = np.lexsort((np.arange(len(src)), dst, key))
    key_s, dst_s = key[order], dst[order]
    same = (key_s[1:] == key_s[:-1])
    repeat = same & (dst_s[1:] == dst_s[:-1])
    clash = same & ~repeat
    if clash.any():
        k = int(np.argmax(clash)) + 1
        # the later of the two conflicting transitions in file order
        return src, ev, dst, int(max(order[k], order[k - 1]))
    keep = np.concatenate(([True], ~repeat))
    order = order[keep]
    return src[order], ev[order], dst[order], None


def renumber(fg: FlatGenerator, order: np.ndarray, name: str | None = None,
             state_names: Sequence[str] | None = None) -> FlatGenerator:
    """The sub-generator on the states ``order`` (``order[k]`` becomes state ``k``);
    transitions leaving that set are dropped."""
    new = np.full(fg.n_states, -1, dtype=np.int64)
    new[order] = np.arange(len(order), dtype=np.int64)
    s, d = new[fg.src], new[fg.dst]
    keep = (s >= 0) & (d >= 0)
    marked = new[fg.marked]
    marked = np.sort(marked[marked >= 0])
    init = None if fg.init is None or new[fg.init] < 0 else int(new[fg.init])
    if state_names is None and fg.state_names is not None:
        state_names = [fg.state_names[q] for q in order.tolist()]
    return FlatGenerator(name or fg.name, fg.events, len(order), s[keep], fg.ev[keep], d[keep], init, marked,
                         list(state_names) if state_names is not None else None)
