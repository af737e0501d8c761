"""The generator a ``.gen`` file describes, collected in libFAUDES's index space and
mapped to a :class:`~supcoord.des.flat.FlatGenerator`.

libFAUDES keeps states by index (``1, 2, …``, gaps allowed) with optional names;
:class:`GenBuilder` records them in the order they appear (the ``<States>`` section,
then the states a ``<TransRel>`` introduces) and numbers them ``0…n-1`` in that
order.  Unnamed states are named by their index as soon as some state is named or
the indices are not ``1…n`` in order.  Repeated transitions count once (libFAUDES's
transition set); two initial states, or two transitions on one event from one state,
raise :class:`~supcoord.errors.NondeterminismError` (supcoord generators are
deterministic); a generator without an initial state describes the empty language
and is the empty generator (no states, alphabet kept).

References
----------
- T. Moor, K. Schmidt et al., libFAUDES reference, "CoreFaudes - Generators"
  (``cfl_generator.cpp``), https://fgdes.tf.fau.de/faudes
"""

from __future__ import annotations

from array import array
from collections.abc import Callable

import numpy as np

from ...errors import NondeterminismError
from ..flat import FlatGenerator, check_deterministic_arrays
from ..flat_ops import distinct
from ..generator import Event
from .gen_tokens import TokenReader, valid_symbol

__all__ = ["GenBuilder", "MAX_STATES"]

MAX_STATES = 10_000_000  # an explicit generator beyond this is not meant to be read into Python


class GenBuilder:
    """The sections of one ``<Generator>``, collected in libFAUDES's index space."""

    def __init__(self, r: TokenReader):
        self.r = r
        self.events: dict[str, bool] = {}
        self.event_pos: dict[str, int] = {}
        self.order: list[int] = []  # libFAUDES state indices in order of appearance
        self.names: dict[int, str] = {}  # index -> name, named states only
        self.by_name: dict[str, int] = {}
        self.known: set[int] = set()
        self.max_index = 0
        self.x1, self.ev, self.x2 = array("q"), array("q"), array("q")  # transitions read one by one
        self.chunks: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []  # ... and a column at a time
        self.trans_section: tuple[int, int] | None = None  # text span of <TransRel>, for error lines
        self._lookup_cache: tuple | None = None  # (states, bare look-up, name look-up) of gen_bulk
        self.init: list[int] = []
        self.marked: list[int] = []

    # -- states and events --------------------------------------------------------

    def add_event(self, name: str, controllable: bool, pos: int) -> None:
        if not valid_symbol(name):
            raise self.r.error(pos, f"invalid event name {name!r}", name)
        if name not in self.event_pos:
            self.event_pos[name] = len(self.event_pos)
        self.events[name] = controllable

    def add_state(self, idx: int, name: str | None, pos: int) -> None:
        if idx < 1 or idx > 2**63 - 1:
            raise self.r.error(pos, f"state index {idx} is not a positive integer (libFAUDES reserves 0 "
                                    f"for 'no state')", idx)
        if idx in self.known or (name is not None and name in self.by_name):
            raise self.r.error(pos, f"state {name or idx} appears twice in the state set", name or idx)
        if len(self.order) >= MAX_STATES:
            raise self.r.error(pos, f"more than {MAX_STATES} states", MAX_STATES)
        if name is not None:
            if not valid_symbol(name):
                raise self.r.error(pos, f"invalid state name {name!r}", name)
            self.by_name[name] = idx
            self.names[idx] = name
        self.known.add(idx)
        self.order.append(idx)
        self.max_index = max(self.max_index, idx)

    def add_range(self, first: int, last: int, pos: int) -> None:
        """``<Consecutive> first last </Consecutive>``: anonymous states ``first…last``."""
        if last - first >= MAX_STATES or len(self.order) + last - first >= MAX_STATES:
            raise self.r.error(pos, f"range {first}..{last} makes more than {MAX_STATES} states", (first, last))
        if first < 1:
            raise self.r.error(pos, f"invalid range of consecutive states {first}..{last}", (first, last))
        new = range(first, last + 1)
        if self.known and not self.known.isdisjoint(new):
            clash = next(i for i in new if i in self.known)
            raise self.r.error(pos, f"state {clash} appears twice in the state set", clash)
        self.known.update(new)
        self.order.extend(new)
        self.max_index = max(self.max_index, last)

    # -- the result -----------------------------------------------------------------

    def build(self, name: str, locate: Callable[[int], int] | None = None) -> FlatGenerator:
        """The :class:`FlatGenerator`; ``locate(k)`` gives the line of transition ``k``."""
        where = self.r.where
        events = [Event(e, c) for e, c in self.events.items()]
        inits = list(dict.fromkeys(self.init))
        label = lambda q: self.names.get(q) or str(q)
        if len(inits) > 1:
            shown = [label(q) for q in inits[:5]]
            raise NondeterminismError(
                f"{len(inits)} initial states {shown}: supcoord generators are deterministic (one initial state)",
                value=shown, where=where,
            )
        empty = np.zeros(0, dtype=np.int64)
        if not inits:
            return FlatGenerator(name, events, 0, empty, empty, empty, None, empty, None)
        n = len(self.order)
        to_number = self._numbering()
        x1, ev, x2 = (np.concatenate([np.frombuffer(a, dtype=np.int64) if len(a) else empty] +
                                     [c[k] for c in self.chunks]) for k, a in enumerate((self.x1, self.ev, self.x2)))
        src, evs, dst, clash = check_deterministic_arrays(x1, ev, x2, len(events))
        if clash is not None:
            first = int(np.flatnonzero((x1 == x1[clash]) & (ev == ev[clash]) & (x2 != x2[clash]))[0])
            line = f"line {locate(clash)}: " if locate is not None else ""
            e = events[int(ev[clash])].name
            a, b1, b2 = label(int(x1[clash])), label(int(x2[first])), label(int(x2[clash]))
            first_line = f" (line {locate(first)})" if locate is not None else ""
            raise NondeterminismError(
                f"{line}state {a} has two transitions on {e!r}, to {b1}{first_line} and to {b2}",
                value=(a, e, (b1, b2)), where=where,
            )
        marked = distinct(to_number(np.array(self.marked, dtype=np.int64))) if self.marked else empty
        named = bool(self.names) or self.order != list(range(1, n + 1))
        state_names = [self.names.get(q) or str(q) for q in self.order] if named else None
        init = int(to_number(np.array(inits, dtype=np.int64))[0])
        return FlatGenerator(name, events, n, to_number(src), evs, to_number(dst), init, marked, state_names)

    def _numbering(self) -> Callable[[np.ndarray], np.ndarray]:
        """libFAUDES index -> state number (position in ``order``), vectorised."""
        n = len(self.order)
        if self.order == list(range(1, n + 1)):
            return lambda a: a - 1
        idx = np.array(self.order, dtype=np.int64)
        if self.max_index <= 4 * n + 1024:
            table = np.full(self.max_index + 1, -1, dtype=np.int64)
            table[idx] = np.arange(n, dtype=np.int64)
            return lambda a: table[a]
        perm = np.argsort(idx, kind="stable")
        sorted_idx = idx[perm]
        return lambda a: perm[np.searchsorted(sorted_idx, a)]
