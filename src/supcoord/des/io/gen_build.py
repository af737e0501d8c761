"""The generator a ``.gen`` file describes, collected in libFAUDES's index space and
mapped to a :class:`~supcoord.des.flat.FlatGenerator`, and the fast filling of it from
the large sections of a file when their text is plain.

libFAUDES keeps states by index (``1, 2, …``, gaps allowed) with optional names;
:class:`GenBuilder` records them in the order they appear (the ``<States>`` section,
then the states a ``<TransRel>`` introduces) and numbers them ``0…n-1`` in that
order.  Unnamed states are named by their index as soon as some state is named or
the indices are not ``1…n`` in order.  Repeated transitions count once (libFAUDES's
transition set); two initial states, or two transitions on one event from one state,
raise :class:`~supcoord.errors.NondeterminismError` (supcoord generators are
deterministic); a generator without an initial state describes the empty language
and is the empty generator (no states, alphabet kept).

The parser (:mod:`.gen_parser`) fills the builder a token at a time.  For
``<States>``, ``<TransRel>``, ``<InitStates>`` and ``<MarkedStates>`` it first tries
:func:`bulk_states`, :func:`bulk_transrel` and :func:`bulk_state_set`, which fill it
a column at a time when the section's text is plain: names and indices separated by
blanks, no markup, option, comment, entity or control character, and no bare token
that libFAUDES would read as an attribute (``0x…``, ``true``/``false``, a negative
number).  Such text tokenizes by :meth:`str.split` (or one regular expression when
names are quoted), and a token's meaning is a dictionary look-up; the result is the
one of the token-by-token reading, which handles every other text (and every error,
so that errors name their line): the fast path raises :class:`Fallback` when it
cannot decide.

References
----------
- T. Moor, K. Schmidt et al., libFAUDES reference, "CoreFaudes - Generators"
  (``cfl_generator.cpp``: ``ReadStates``, ``ReadStateSet``, ``ReadTransRel``),
  https://fgdes.tf.fau.de/faudes
"""

from __future__ import annotations

import re
from array import array
from collections.abc import Callable, Iterator
from dataclasses import dataclass

import numpy as np

from ...errors import NondeterminismError
from ..flat import FlatGenerator, check_deterministic_arrays
from ..flat_ops import distinct
from ..generator import Event
from .gen_tokens import TokenReader, bare_kind, valid_symbol

__all__ = ["Fallback", "GenBuilder", "Introducing", "MAX_STATES", "bulk_state_set", "bulk_states", "bulk_transrel"]

MAX_STATES = 10_000_000  # an explicit generator beyond this is not meant to be read into Python


@dataclass
class Introducing:
    """What ``<TransRel>`` may still introduce that the sections before it lack: states
    by index until it introduces a named one, by name until it introduces an indexed
    one, and events only when there was no alphabet."""

    events: bool
    by_index: bool = True
    by_name: bool = True


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
        self.trans_pos: list[int] = []  # text position of each XML <Transition>, for error lines
        self._lookup_cache: tuple[int, dict[str, int], dict[str, int]] | None = None  # (states, bare, names) of _lookups
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


# -- the fast path: plain sections a column at a time -----------------------------------

# possessive: the three alternatives start differently, so nothing to backtrack into (with
# plain `\s+` inside `*`, an unterminated quote after a run of blanks took exponential time)
_QUOTED_OK = re.compile(rb'(?:\s++|"[^"\s]*+"(?=\s|\Z)|[^\s"]++(?=\s|\Z))*+')
_QUOTED_STR = re.compile(rb'"[^"]*"')
_TOKEN = re.compile(r'"([^"\s]*)"|([^\s"]+)', re.ASCII)
_DIGITS = re.compile(rb"[0-9\s]*")
_SPACE = re.compile(r"\s", re.ASCII)
#: what may be a number to libFAUDES (the rest is a string: most names fail this at once)
_NUMBERISH = re.compile(r"-?[0-9.]*|0x[0-9a-fA-F]*|[Tt]rue|[Ff]alse|-?inf")
_SPACES = b" \t\n\r\x0b\x0c"
#: bytes a plain section may hold: blanks, printable ASCII but ``& > ' + % = #``, Latin-1 letters
_PLAIN_BYTES = _SPACES + bytes(c for c in range(0x21, 0x7F) if chr(c) not in "&>'+%=#\"") + bytes(range(0x80, 0x100))
#: bare words that are no names to libFAUDES (attributes after an element, like ``-…`` and ``0x…``, or ``inf``)
_NOT_NAMES = frozenset(["true", "True", "false", "False", "inf"])
#: the bytes of valid libFAUDES symbols, blanks and quotes (names that need no check one by one)
_SYMBOL_BYTES = _SPACES + b'"' + bytes(c for c in range(0x21, 0x7F) if chr(c) not in '"#')
CHUNK = 1 << 23  # characters of section text tokenized at a time


class Fallback(Exception):
    """The plain reading cannot decide: read the section token by token instead."""


def _plain(r: TokenReader, label: str) -> tuple[int, int, bool] | None:
    """``(start, end, quoted)`` of the section's text if it is plain."""
    span = r.section_text(label)
    if span is None:
        return None
    s, e = span
    raw = r.raw[s:e]
    rest = raw.translate(None, _PLAIN_BYTES)
    if rest.translate(None, b"'+%=\"") :  # entities, '#', '>', control characters: anywhere
        return None
    quoted = b'"' in rest
    if quoted:
        if not _QUOTED_OK.fullmatch(raw):
            return None
        raw = _QUOTED_STR.sub(b" ", raw)
        rest = raw.translate(None, _PLAIN_BYTES)
    if rest:
        return None
    return s, e, quoted


def _symbols_only(r: TokenReader, s: int, e: int) -> bool:
    """Whether every name in ``text[s:e]`` is a valid libFAUDES symbol (and none is empty)."""
    raw = r.raw[s:e]
    return not raw.translate(None, _SYMBOL_BYTES) and b'""' not in raw


def _chunks(text: str, s: int, e: int, quoted: bool) -> Iterator[list]:
    """The tokens of ``text[s:e]`` a chunk at a time: strings, or ``(quoted, bare)`` pairs."""
    while s < e:
        cut = min(e, s + CHUNK)
        if cut < e:
            m = _SPACE.search(text, cut, e)
            cut = e if m is None else m.start()
        piece = text[s:cut]
        yield _TOKEN.findall(piece) if quoted else piece.split()
        s = cut


def _items(tokens: list, quoted: bool) -> Iterator[tuple[str, bool]]:
    if quoted:
        for q, bare in tokens:
            yield (bare, False) if bare else (q, True)
    else:
        for t in tokens:
            yield t, False


def bulk_states(r: TokenReader, b: GenBuilder, label: str) -> bool:
    """``<States>`` in one pass; ``False`` when the text is not plain (nothing read)."""
    plain = _plain(r, label)
    if plain is None:
        return False
    s, e, quoted = plain
    r.jump(s, label)
    if not quoted and _DIGITS.fullmatch(r.raw, s, e):
        _add_indices(b, list(map(int, r.text[s:e].split())))
    elif _symbols_only(r, s, e) and (quoted or not re.search(rb"(?:^|\s)[0-9.]", r.raw[s:e])):
        # names only (a bare name starts with no digit or '.', special words are excluded)
        _add_names(b, _state_names(r.text, s, e, quoted))
    else:
        _add_mixed(b, r.text, s, e, quoted)
    r.pos = e
    r.end(label)
    return True


def _state_names(text: str, s: int, e: int, quoted: bool) -> list[str]:
    """The names of a ``<States>`` text of valid symbols (``Fallback`` on a special word)."""
    if quoted:
        pairs = _TOKEN.findall(text, s, e)
        if any(bare and (bare[0] in "0123456789.-" or bare in _NOT_NAMES) for _, bare in pairs):
            raise Fallback
        return [q or bare for q, bare in pairs]
    names = text[s:e].split()
    if not _NOT_NAMES.isdisjoint(names) or any(nm[0] == "-" for nm in names):
        raise Fallback
    return names


def _add_names(b: GenBuilder, names: list[str]) -> None:
    """Named states numbered by position (``Fallback`` on a repeated name or index)."""
    first = 1 + len(b.order)
    idx = range(first, first + len(names))
    if len(set(names)) != len(names) or b.by_name.keys() & set(names) or not b.known.isdisjoint(idx) \
            or len(b.order) + len(names) > MAX_STATES:
        raise Fallback
    b.by_name.update(zip(names, idx))
    b.names.update(zip(idx, names))
    b.known.update(idx)
    b.order.extend(idx)
    b.max_index = max(b.max_index, first + len(names) - 1)


def _add_mixed(b: GenBuilder, text: str, s: int, e: int, quoted: bool) -> None:
    """Indices and names mixed, one token at a time (a name's index is its position)."""
    symnext = 1 + len(b.order)
    for tokens in _chunks(text, s, e, quoted):
        for tok, is_quoted in _items(tokens, quoted):
            kind, value = ("string", None) if is_quoted else bare_kind(tok)
            if kind == "integer":
                _add_indices(b, [value])
            else:
                if kind != "string" or tok in b.by_name or symnext in b.known or not valid_symbol(tok):
                    raise Fallback
                b.add_state(symnext, tok, s)
            symnext += 1


def _add_indices(b: GenBuilder, values: list[int]) -> None:
    """Anonymous states by index (``Fallback`` on a repeated or non-positive one)."""
    fresh = set(values)
    if 0 in fresh or len(fresh) != len(values) or not b.known.isdisjoint(fresh) or \
            len(b.order) + len(values) > MAX_STATES:
        raise Fallback
    b.order.extend(values)
    b.known.update(fresh)
    b.max_index = max(b.max_index, max(values, default=0))


def _lookups(b: GenBuilder) -> tuple[dict[str, int], dict[str, int]]:
    """Bare token -> index (decimal indices and names libFAUDES reads as strings), quoted
    name -> index; kept on the builder while no state is added."""
    cached = b._lookup_cache
    if cached is not None and cached[0] == len(b.order):
        return cached[1], cached[2]
    bare = dict(zip(map(str, b.known), b.known))
    bare.update((nm, i) for nm, i in b.by_name.items() if _NUMBERISH.fullmatch(nm) is None or
                bare_kind(nm)[0] == "string")
    b._lookup_cache = (len(b.order), bare, b.by_name)
    return bare, b.by_name


def bulk_state_set(r: TokenReader, b: GenBuilder, label: str) -> list[int] | None:
    """``<InitStates>``/``<MarkedStates>`` in one pass, ``None`` when not plain."""
    plain = _plain(r, label)
    if plain is None:
        return None
    s, e, quoted = plain
    r.jump(s, label)
    out: list[int] = []
    for tokens in _chunks(r.text, s, e, quoted):
        for tok, is_quoted in _items(tokens, quoted):
            kind, value = ("string", None) if is_quoted else bare_kind(tok)
            if kind == "integer" and value in b.known:
                out.append(value)
            elif kind == "string" and tok in b.by_name:
                out.append(b.by_name[tok])
            else:
                raise Fallback
    r.pos = e
    r.end(label)
    return out


def bulk_transrel(r: TokenReader, b: GenBuilder, label: str) -> bool:
    """``<TransRel>`` a column at a time; ``False`` when the text is not plain.  States
    and events the section introduces (see :mod:`.gen_parser`) are added in file order."""
    plain = _plain(r, label)
    if plain is None:
        return False
    s, e, quoted = plain
    r.jump(s, label)
    b.trans_section = (s, e)
    events = b.event_pos
    intro = Introducing(events=not b.events)
    table = _known_table(b)
    carry: list = []
    for tokens in _chunks(r.text, s, e, quoted):
        if carry:
            tokens = carry + tokens
        cut = len(tokens) - len(tokens) % 3
        carry = tokens[cut:]
        if not quoted:
            colev = list(map(events.get, tokens[1:cut:3]))
            n1 = _int_column(tokens[0:cut:3], table)
            n2 = _int_column(tokens[2:cut:3], table) if n1 is not None else None
            if n2 is not None and None not in colev:
                b.chunks.append((n1, np.array(colev, dtype=np.int64), n2))
                continue
        bare, names = _lookups(b)
        if quoted:
            col1 = [names.get(q) if not bb else bare.get(bb) for q, bb in tokens[0:cut:3]]
            colev = [events.get(q or bb) for q, bb in tokens[1:cut:3]]
            col2 = [names.get(q) if not bb else bare.get(bb) for q, bb in tokens[2:cut:3]]
        else:
            col1 = list(map(bare.get, tokens[0:cut:3]))
            col2 = list(map(bare.get, tokens[2:cut:3]))
        if None in col1 or None in colev or None in col2:
            _misses(b, tokens, cut, quoted, col1, colev, col2, bare, names, intro)
            table = _known_table(b)
        b.chunks.append(tuple(np.array(c, dtype=np.int64) for c in (col1, colev, col2)))
    if carry:
        raise Fallback  # an incomplete transition: the token reading names its line
    r.pos = e
    r.end(label)
    return True


def _known_table(b: GenBuilder) -> np.ndarray | None:
    """``table[i]``: whether index ``i`` is a state (``None`` when indices are too sparse)."""
    if b.max_index > 4 * len(b.order) + 1024:
        return None
    table = np.zeros(b.max_index + 1, dtype=bool)
    if b.order:
        table[np.array(b.order, dtype=np.int64)] = True
    return table


def _int_column(col: list[str], table: np.ndarray | None) -> np.ndarray | None:
    """The column as state indices if it is all decimal digits naming states, else ``None``."""
    joined = "".join(col)
    if table is None or not (joined.isdigit() and joined.isascii()):
        return None if joined or table is None else np.zeros(0, dtype=np.int64)
    if max(map(len, col)) > 18:  # beyond int64: a state no table holds
        return None
    values = np.fromiter(map(int, col), dtype=np.int64, count=len(col))
    if len(values) and (values.max() >= len(table) or not table[values].all()):
        return None
    return values


def _misses(b: GenBuilder, tokens: list, cut: int, quoted: bool, col1: list, colev: list, col2: list,
            bare: dict[str, int], names: dict[str, int], intro: Introducing) -> None:
    """Resolve the tokens the look-ups missed, in file order, introducing states and
    events as libFAUDES does (``Fallback`` for anything else)."""

    def item(k: int) -> tuple[str, bool]:
        t = tokens[k]
        if quoted:
            return (t[1], False) if t[1] else (t[0], True)
        return t, False

    def state(k: int) -> int:
        tok, is_quoted = item(k)
        idx = names.get(tok) if is_quoted else bare.get(tok)
        if idx is not None:
            return idx
        kind, value = ("string", None) if is_quoted else bare_kind(tok)
        if kind not in ("string", "integer"):
            raise Fallback  # an attribute libFAUDES skips, or a state by a special number
        if kind == "integer":
            if value in b.known:
                return value
            if not intro.by_index or not 0 < value < 2**63 or len(b.order) >= MAX_STATES:
                raise Fallback  # refused: the token reading names the transition's line
            b.add_state(value, None, 0)
            bare[str(value)] = value
            intro.by_name = False
            return value
        if kind != "string" or not intro.by_name or not valid_symbol(tok) or len(b.order) >= MAX_STATES:
            raise Fallback
        idx = b.max_index + 1
        b.add_state(idx, tok, 0)
        names[tok] = idx
        bare.setdefault(str(idx), idx)
        if not is_quoted:
            bare[tok] = idx
        intro.by_index = False
        return idx

    for j in range(cut // 3):
        if col1[j] is None:
            col1[j] = state(3 * j)
        if colev[j] is None:
            name = item(3 * j + 1)[0]
            if name in b.event_pos:
                colev[j] = b.event_pos[name]
            elif intro.events and valid_symbol(name):
                b.add_event(name, False, 0)
                colev[j] = b.event_pos[name]
            else:
                raise Fallback
        if col2[j] is None:
            col2[j] = state(3 * j + 2)
