"""Fast reading of the large sections of a ``.gen`` file (``<States>``, ``<TransRel>``,
``<InitStates>``, ``<MarkedStates>``) when their text is plain.

Plain text is names and indices separated by blanks: no markup, option, comment,
entity or control character, and no bare token that libFAUDES would read as an
attribute (``0x…``, ``true``/``false``, a negative number).  Such text tokenizes by
:meth:`str.split` (or one regular expression when names are quoted), and a token's
meaning is a dictionary look-up, a column of the section at a time; the result is
the one of the token-by-token reading of :mod:`.gen_parser`, which handles every
other text (and every error, so that errors name their line).

References
----------
- T. Moor, K. Schmidt et al., libFAUDES reference, "CoreFaudes - Generators"
  (``cfl_generator.cpp``: ``ReadStates``, ``ReadStateSet``, ``ReadTransRel``),
  https://fgdes.tf.fau.de/faudes
"""

from __future__ import annotations

import re
from collections.abc import Iterator

import numpy as np

from .gen_build import MAX_STATES, GenBuilder
from .gen_tokens import TokenReader, bare_kind, valid_symbol

__all__ = ["Fallback", "bulk_states", "bulk_state_set", "bulk_transrel"]

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
    raw, text = r.raw, r.text
    if not quoted and _DIGITS.fullmatch(raw, s, e):
        _add_indices(b, list(map(int, text[s:e].split())))
    elif _symbols_only(r, s, e) and (quoted or not re.search(rb"(?:^|\s)[0-9.]", raw[s:e])):
        # names only (a bare name starts with no digit or '.', special words are excluded)
        if quoted:
            pairs = _TOKEN.findall(text, s, e)
            if any(bare and (bare[0] in "0123456789.-" or bare in _NOT_NAMES) for _, bare in pairs):
                raise Fallback
            names = [q or bare for q, bare in pairs]
        else:
            names = text[s:e].split()
            if not _NOT_NAMES.isdisjoint(names) or any(nm[0] == "-" for nm in names):
                raise Fallback
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
    else:
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
    r.pos = e
    r.end(label)
    return True


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
    cached = getattr(b, "_lookup_cache", None)
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
    flags = {"isx": True, "isn": True, "ien": not b.events}
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
            _misses(b, tokens, cut, quoted, col1, colev, col2, bare, names, flags)
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
    values = np.fromiter(map(int, col), dtype=np.int64, count=len(col))
    if len(values) and (values.max() >= len(table) or not table[values].all()):
        return None
    return values


def _misses(b: GenBuilder, tokens: list, cut: int, quoted: bool, col1: list, colev: list, col2: list,
            bare: dict[str, int], names: dict[str, int], flags: dict[str, bool]) -> None:
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
            if not flags["isx"]:
                raise Fallback
            b.add_state(value, None, 0)
            bare[str(value)] = value
            flags["isn"] = False
            return value
        if kind != "string" or not flags["isn"] or not valid_symbol(tok):
            raise Fallback
        idx = b.max_index + 1
        b.add_state(idx, tok, 0)
        names[tok] = idx
        bare.setdefault(str(idx), idx)
        if not is_quoted:
            bare[tok] = idx
        flags["isx"] = False
        return idx

    for j in range(cut // 3):
        if col1[j] is None:
            col1[j] = state(3 * j)
        if colev[j] is None:
            name = item(3 * j + 1)[0]
            if name in b.event_pos:
                colev[j] = b.event_pos[name]
            elif flags["ien"] and valid_symbol(name):
                b.add_event(name, False, 0)
                colev[j] = b.event_pos[name]
            else:
                raise Fallback
        if col2[j] is None:
            col2[j] = state(3 * j + 2)
