"""Writing libFAUDES ``.gen`` files: the text of ``faudes.System.Write()``.

States are written by index (``<Consecutive>``) or, when the generator has valid and
unique state names, by name; names libFAUDES would misread (``true``, names
starting with a digit …) are quoted; controllable events get ``+C+``.  Beyond
:data:`NAMES_IN_TRANSITIONS_UP_TO` transitions, ``<TransRel>``, ``<InitStates>`` and
``<MarkedStates>`` refer to named states by index (libFAUDES reads both).  The
transitions are listed by source state, then event name.

The text is produced from a :class:`~supcoord.des.flat.FlatGenerator`; transitions by
index are laid out as bytes with array operations (digits placed column by column,
event names event by event), so a supervisor of millions of transitions is written
in seconds.  Files are written to a temporary file in the target directory and moved
into place.

References
----------
- T. Moor, K. Schmidt et al., libFAUDES reference, "CoreFaudes - Generators"
  (``vGenerator::DoWrite``), https://fgdes.tf.fau.de/faudes
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterable, Iterator

import numpy as np

from ...errors import InputError
from ..flat import FlatGenerator, from_generator
from ..flat_ops import successor_table
from ..generator import Generator
from .files import write_atomic
from .gen_tokens import valid_symbol

__all__ = ["format_gen", "write_gen", "write_gen_flat", "gen_chunks", "NAMES_IN_TRANSITIONS_UP_TO"]

#: above this many transitions, transitions and state sets refer to named states by index
NAMES_IN_TRANSITIONS_UP_TO = 10_000

_RESERVED = {"true", "false", "True", "False", "inf", "+inf", "-inf"}
_COLUMNS = 6
_WIDTH = 15
_ROWS_PER_CHUNK = 1 << 20


_SPECIAL = re.compile(r'[&<>"]')
_HEX = re.compile(r"0x[0-9a-fA-F]+")


def _escape(name: str) -> str:
    if _SPECIAL.search(name) is None:
        return name
    return name.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;").replace('"', "&quot;")


def _symbol(name: str) -> str:
    body = _escape(name)
    bare = name[0].isalpha() and name not in _RESERVED and _HEX.fullmatch(name) is None
    return body if bare else f'"{body}"'


def _rows(items: Iterable[str]) -> list[str]:
    items = list(items)
    lines = []
    for k in range(0, len(items), _COLUMNS):
        lines.append("".join(s.ljust(_WIDTH - 1) + " " for s in items[k:k + _COLUMNS]).rstrip())
    return lines


def format_gen(g: Generator, *, names_in_transitions: bool | None = None) -> str:
    """The text of ``g`` as a libFAUDES ``System`` file (readable by ``faudes.System``).

    Named states are listed by name in ``<States>`` (each gets the index of its
    position); ``<TransRel>``, ``<InitStates>`` and ``<MarkedStates>`` repeat the names
    (as ``faudes.Generator.Write()`` does) when ``names_in_transitions`` is true, and
    refer to the states by those indices otherwise (libFAUDES reads both).  The
    default repeats names up to :data:`NAMES_IN_TRANSITIONS_UP_TO` transitions:
    supervisors exported from large products have long names (one ``var=value`` per
    component), and repeating them three times per transition made a 59,047-state
    dining-philosophers supervisor a 175 MB file."""
    return "".join(c.decode("latin-1") if isinstance(c, bytes) else c
                   for c in gen_chunks(from_generator(g), names_in_transitions=names_in_transitions))


def write_gen(g: Generator, path: str | os.PathLike, *, names_in_transitions: bool | None = None) -> None:
    """Write ``g`` as a libFAUDES ``System`` ``.gen`` file (see :func:`format_gen`)."""
    write_gen_flat(from_generator(g), path, names_in_transitions=names_in_transitions)


def write_gen_flat(fg: FlatGenerator, path: str | os.PathLike, *, names_in_transitions: bool | None = None) -> None:
    """Write a :class:`FlatGenerator` as :func:`write_gen` writes the same generator."""
    write_atomic(path, gen_chunks(fg, names_in_transitions=names_in_transitions), "latin-1")


def gen_chunks(fg: FlatGenerator, *, names_in_transitions: bool | None = None) -> Iterator[str | bytes]:
    """The text of :func:`format_gen`, a part at a time (transitions by index as Latin-1 bytes)."""
    bad = [e.name for e in fg.events if not valid_symbol(e.name)]
    if bad:
        raise InputError(
            f"event names {bad[:5]} are not valid libFAUDES symbols (printable ASCII without blanks, '\"' or '#')",
            value=bad,
        )
    names = fg.state_names
    if names is not None and (len(set(names)) != len(names) or not _all_symbols(names)):
        names = None
    if names_in_transitions is None:
        names_in_transitions = fg.n_transitions <= NAMES_IN_TRANSITIONS_UP_TO
    n = fg.n_states
    labels = _labels(names) if names else None

    def ref(q: int) -> str:  # a state in <TransRel>, <InitStates>, <MarkedStates>
        return labels[q] if labels and names_in_transitions else str(q + 1)

    out = [f'<Generator name="{_escape(fg.name)}" ftype="System">', ""]
    out += [(f"% written by supcoord: {n} states, {len(fg.events)} events, "
             f"{fg.n_transitions} transitions, {len(fg.marked)} marked"), ""]
    alpha = []
    for e in fg.events:
        alpha.append(_symbol(e.name))
        if e.controllable:
            alpha.append("+C+")
    out += ["<Alphabet>", *_rows(alpha), "</Alphabet>", "", "<States>"]
    if labels:
        out += _rows(labels)
    elif n:
        out += ["<Consecutive>", *_rows(["1", str(n)]), "</Consecutive>"]
    out += ["</States>", "", "<TransRel>", ""]
    yield "\n".join(out)
    src, ev, dst = _by_source_and_name(fg)
    symbols = [_symbol(e.name) for e in fg.events]
    if labels and names_in_transitions:
        yield "".join(" ".join(s.ljust(_WIDTH - 1) for s in (labels[a], symbols[e], labels[b])).rstrip() + "\n"
                      for a, e, b in zip(src.tolist(), ev.tolist(), dst.tolist()))
    else:
        for k in range(0, len(src), _ROWS_PER_CHUNK):
            yield _index_lines(src[k:k + _ROWS_PER_CHUNK], ev[k:k + _ROWS_PER_CHUNK], dst[k:k + _ROWS_PER_CHUNK],
                               symbols)
    out = ["</TransRel>", "", "<InitStates>"]
    if fg.init is not None:
        out += _rows([ref(fg.init)])
    out += ["</InitStates>", "", "<MarkedStates>", *_rows(ref(q) for q in fg.marked.tolist()), "</MarkedStates>", "",
            "</Generator>", ""]
    yield "\n".join(out)


def _all_symbols(names: list[str]) -> bool:
    """Whether every name is a valid libFAUDES symbol (one pass over all of them)."""
    return all(names) and valid_symbol("".join(names))


def _labels(names: list[str]) -> list[str]:
    """The tokens of state names: quoted where libFAUDES would misread them bare, a
    state named after its own index (as unnamed states read) as that index."""
    if _SPECIAL.search("".join(names)) is not None:
        out = [_symbol(nm) for nm in names]
    else:  # no name needs escaping: only the quoting rule
        out = [nm if nm[0].isalpha() and nm not in _RESERVED else f'"{nm}"' for nm in names]
    digits = [q for q, nm in enumerate(names) if nm[0].isdigit() and nm == str(q + 1)]
    for q in digits:
        out[q] = names[q]
    return out


def _by_source_and_name(fg: FlatGenerator) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The transitions sorted by source state, then event name."""
    by_name = np.array(sorted(range(len(fg.events)), key=lambda k: fg.events[k].name), dtype=np.int64)
    table = successor_table(fg.n_states, len(fg.events), fg.src, fg.ev, fg.dst, columns=by_name)
    if table is None:
        rank = np.empty(len(by_name), dtype=np.int64)
        rank[by_name] = np.arange(len(by_name))
        order = np.lexsort((rank[fg.ev], fg.src))
        return fg.src[order], fg.ev[order], fg.dst[order]
    q, j = np.nonzero(table >= 0)
    return q.astype(np.int64), by_name[j], table[q, j].astype(np.int64)


def _digits(n: np.ndarray) -> np.ndarray:
    """The number of decimal digits of each positive integer."""
    d = np.ones(len(n), dtype=np.int64)
    bound = 10
    while len(n) and bound <= n.max():
        d += n >= bound
        bound *= 10
    return d


def _index_lines(src: np.ndarray, ev: np.ndarray, dst: np.ndarray, symbols: list[str]) -> bytes:
    """Lines ``x1 event x2`` (indices ``q + 1``; the source in 14 columns and a blank, the
    event padded to the longest event name, at least 14 columns, and a blank), laid out as
    a byte matrix: source digits a place at a time, each line's event field in one block
    copy, target digits, newline; the rows are then cut after their newline."""
    a, b = src + 1, dst + 1
    width = max(_WIDTH - 1, max((len(s) for s in symbols), default=0)) + 1
    table = np.frombuffer(b"".join(s.ljust(width).encode("latin-1") for s in symbols), dtype=np.uint8)
    da, db = _digits(a), _digits(b)
    first = max(_WIDTH, int(da.max()) + 1 if len(a) else 0)  # the event field's column
    cols = first + width + int(db.max() if len(b) else 1) + 1
    m = np.full((len(a), cols), ord(" "), dtype=np.uint8)
    m[:, first:first + width] = table.reshape(len(symbols), width)[ev]
    rows = np.arange(len(a))
    for value, ndigits, offset in ((a, da, 0), (b, db, first + width)):
        rest = value.copy()
        for place in range(int(ndigits.max()) if len(value) else 0):
            live = ndigits > place
            m[rows[live], offset + ndigits[live] - 1 - place] = (48 + rest[live] % 10).astype(np.uint8)
            rest //= 10
    end = first + width + db
    m[rows, end] = ord("\n")
    return m[np.arange(cols)[None, :] <= end[:, None]].tobytes()
