"""The ``<Generator>`` grammar of libFAUDES ``.gen`` files, read as libFAUDES's
``vGenerator::DoRead`` reads it (:mod:`.gen_file` states the accepted forms).

- The first ``<Generator>`` at any depth is read (``SeekBegin``): what precedes it
  (a wrapper such as ``<cGenerator>`` or ``<aGenerator>``, stray text, comments) and
  what follows its end are skipped; the ``<Controllable>`` section of a
  ``<cGenerator>`` wrapper marks its events controllable.
- The native layout: an optional name, then in this order ``<Alphabet>``,
  ``<States>``, ``<TransRel>`` (required), ``<InitStates>``, ``<MarkedStates>``;
  anything after these inside ``<Generator>`` is skipped.  When ``<TransRel>`` is not
  where it belongs, the XML layout is read (``<Alphabet>``, ``<StateSet>``,
  ``<TransitionRelation>`` in any order) unless the name was a string token;
  libFAUDES reads such a file as an empty generator (or refuses it when it has no
  ``<StateSet>``), supcoord refuses it, naming where the native layout broke.
- An element (event or state) is followed by its attribute: for events the
  controllability flags (``+C+``, ``0x…`` with bit 1, ``<Controllable/>``), for
  others anything libFAUDES's ``AttrType::Skip`` skips.
- ``<TransRel>`` introduces states it uses but ``<States>`` lacks: integer ones until
  it introduces a named one and named ones until it introduces an integer one (the
  next index after the largest); events only when there was no alphabet.

References
----------
- T. Moor, K. Schmidt et al., libFAUDES reference, "CoreFaudes - Generators"
  (``cfl_generator.cpp``, ``cfl_nameset.cpp``, ``cfl_attributes.cpp``),
  https://fgdes.tf.fau.de/faudes
"""

from __future__ import annotations

from ...errors import FormatError
from ..flat import FlatGenerator
from .gen_build import MAX_STATES, GenBuilder
from .gen_bulk import Fallback, bulk_state_set, bulk_states, bulk_transrel
from .gen_tokens import Token, TokenReader
from .gen_xml import controllable_section, find, int_attr, read_alphabet, read_xml

__all__ = ["MAX_STATES", "parse_text"]

_ORDER = "the native sections come in the order <Alphabet>, <States>, <TransRel>, <InitStates>, <MarkedStates>"


def parse_text(text: str, where: str = "<string>", *, raw: bytes | None = None, fast: bool = True) -> FlatGenerator:
    """The generator of the first ``<Generator>`` section of libFAUDES token text
    (``raw``: the same text as Latin-1 bytes, when at hand)."""
    try:
        return _parse(text, where, raw, fast)
    except Fallback:
        return _parse(text, where, raw, False)


def _parse(text: str, where: str, raw: bytes | None, fast: bool) -> FlatGenerator:
    r = TokenReader(text, where, raw)
    if not text or text.isspace():
        raise r.error(0, "empty file: expected <Generator>")
    btag = r.seek_begin("Generator")
    parent = r.stack[-2] if len(r.stack) > 1 else None
    name = btag.attrs.get("name", "Generator")
    t = r.peek()
    native_name = t is not None and t.is_string  # libFAUDES then reads no XML
    if native_name:
        name = r.get().name
    start = r.mark()
    b = GenBuilder(r)
    broke = _native(r, b, fast)
    if broke is not None:
        r.reset(start)
        b = GenBuilder(r)
        if native_name or not find(r, "StateSet", start):
            if broke.kind == "end" and broke.text == "Generator":
                raise r.error(broke, "missing <TransRel> section", "TransRel")
            raise r.error(broke, f"expected <TransRel>, found {broke.show()} ({_ORDER})", broke.text)
        r.reset(start)
        name = btag.attrs.get("name", "generator")
        read_xml(r, b, start)
    r.end("Generator")
    if parent == "cGenerator":
        try:
            controllable_section(r, b)
        except FormatError:  # libFAUDES reads nothing after </Generator>: a bad tail is no error
            pass
    return b.build(name, lambda k: _locate(r, b, k))


# -- native layout ----------------------------------------------------------------------


def _native(r: TokenReader, b: GenBuilder, fast: bool) -> Token | None:
    """Read the native sections; the token where ``<TransRel>`` was expected if absent."""
    if r.is_begin("Alphabet", "A"):
        read_alphabet(r, b, r.peek().text)
    if r.is_begin("States", "S"):
        label = r.peek().text
        if not (fast and bulk_states(r, b, label)):
            _states(r, b, label)
    t = r.peek()
    if t is None:
        raise r.error(len(r.text), "missing </Generator>", "Generator")
    if not r.is_begin("TransRel", "T"):
        return t
    if not (fast and bulk_transrel(r, b, t.text)):
        _transrel(r, b, t.text)
    for labels, target in ((("InitStates", "I"), b.init), (("MarkedStates", "M"), b.marked)):
        if r.is_begin(*labels):
            label = r.peek().text
            found = bulk_state_set(r, b, label) if fast else None
            target.extend(found if found is not None else _state_set(r, b, label))
    return None


def _states(r: TokenReader, b: GenBuilder, label: str) -> None:
    """libFAUDES's ``ReadStates``: indices, names (index = position or ``name#index``), ranges."""
    r.begin(label)
    symnext, implicit, explicit = 1, False, False
    while not r.is_end(label):
        t = r.peek()
        if t is None:
            raise r.error(len(r.text), f"missing </{label}>", label)
        if t.index is not None:
            r.get()
            b.add_state(t.index, None, t.pos)
            r.skip_attributes()
        elif t.is_string:
            r.get()
            name, sep, suffix = t.name.partition("#")
            idx = symnext
            if sep:
                explicit = True
                if suffix:
                    if not (suffix.isdigit() and suffix.isascii()):
                        raise r.error(t, f"invalid index suffix in state {t.name!r}", t.name)
                    idx = int(suffix)
                else:
                    name = t.name
            else:
                implicit = True
            b.add_state(idx, name, t.pos)
            r.skip_attributes()
        elif t.kind == "begin" and t.text == "Consecutive":
            r.get()
            t1, t2 = r.get(), r.get()
            if t1.index is None or t2.index is None:
                raise r.error(t1, f"invalid range of consecutive states {t1.show()}..{t2.show()}", (t1.text, t2.text))
            b.add_range(t1.index, t2.index, t1.pos)
            symnext += max(0, t2.index - t1.index + 1) - 1
            r.end("Consecutive")
        else:
            raise r.error(t, f"unexpected {t.show()} in <{label}>", t.text)
        symnext += 1
    r.get()
    if implicit and explicit:
        raise r.error(r.pos, "states with and without an explicit '#index' suffix", label)


def _state_set(r: TokenReader, b: GenBuilder, label: str) -> list[int]:
    """libFAUDES's ``ReadStateSet``: states of the state set by index, name, range or element."""
    r.begin(label)
    out: list[int] = []
    while not r.is_end(label):
        t = r.peek()
        if t is None:
            raise r.error(len(r.text), f"missing </{label}>", label)
        if t.index is not None or t.is_string:
            r.get()
            if t.index is None and "#" in t.name:
                raise r.error(t, f"index suffix not allowed in <{label}>: {t.name!r}", t.name)
            idx = t.index if t.index is not None else b.by_name.get(t.name)
            if idx is None or idx not in b.known:
                raise r.error(t, f"state {t.name!r} is not in the state set", t.name)
            out.append(idx)
            r.skip_attributes()
        elif t.kind == "begin" and t.text == "State":
            r.get()
            idx = int_attr(t, "id") or b.by_name.get(t.attrs.get("name", ""))
            if idx is None or idx not in b.known:
                raise r.error(t, f"cannot find the state of {t.show()} {t.attrs}", t.attrs)
            out.append(idx)
            r.end("State")
        elif t.kind == "begin" and t.text == "Consecutive":
            r.get()
            if r.is_end("Consecutive"):
                first, last = int_attr(t, "from") or 0, int_attr(t, "to") or 0
            else:
                t1, t2 = r.get(), r.get()
                first, last = t1.index or 0, t2.index or 0
            if first < 1 or last < first:
                raise r.error(t, f"invalid range of consecutive states {first}..{last}", (first, last))
            if last - first >= MAX_STATES or any(i not in b.known for i in range(first, last + 1)):
                raise r.error(t, f"range {first}..{last} is not in the state set", (first, last))
            out.extend(range(first, last + 1))
            r.end("Consecutive")
        else:
            raise r.error(t, f"unexpected {t.show()} in <{label}>", t.text)
    r.get()
    return out


def _transrel(r: TokenReader, b: GenBuilder, label: str) -> None:
    """libFAUDES's ``ReadTransRel``: triples ``x1 event x2``, each followed by its attribute."""
    r.begin(label)
    b.trans_section = (r.pos, -1)
    isx, isn, ien = True, True, not b.events

    def state(t: Token) -> int | None:
        nonlocal isx, isn
        if t.index is not None:
            if t.index not in b.known and isx:
                b.add_state(t.index, None, t.pos)
                isn = False
            return t.index
        if t.is_string:
            idx = b.by_name.get(t.name)
            if idx is None and isn:
                idx = b.max_index + 1
                b.add_state(idx, t.name, t.pos)
                isx = False
            return idx
        raise r.error(t, f"incomplete transition before {t.show()} in <{label}>", t.text)

    while not r.is_end(label):
        t1 = r.get()
        x1 = state(t1)
        te = r.get()
        if not te.is_string:
            raise r.error(te, f"incomplete transition before {te.show()} in <{label}>", te.text)
        if te.name not in b.event_pos and ien:
            b.add_event(te.name, False, te.pos)
        t2 = r.get()
        x2 = state(t2)
        r.skip_attributes()
        for t, x in ((t1, x1), (t2, x2)):
            if x is None or x not in b.known:
                raise r.error(t, f"state {t.name!r} is not in the state set", t.name)
        if te.name not in b.event_pos:
            raise r.error(te, f"event {te.name!r} is not in the alphabet", te.name)
        b.x1.append(x1)
        b.ev.append(b.event_pos[te.name])
        b.x2.append(x2)
    r.get()


def _locate(r: TokenReader, b: GenBuilder, k: int) -> int:
    """The line of the ``k``-th transition of ``<TransRel>`` (for error messages)."""
    if b.trans_section is None:
        return 0
    s = TokenReader(r.text, r.where)
    s.pos = b.trans_section[0]
    for _ in range(k):
        s.get(), s.get(), s.get()
        s.skip_attributes()
    t = s.peek()
    return s.line_at(t.pos if t is not None else s.pos)
