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
- The alphabet (``NameSet::DoRead``): names, each with its controllability flags (an
  option with ``C`` sets the controllable bit, one with ``c`` clears it; ``0x…`` sets
  it from bit ``0x01``; ``<Controllable value=…/>``), or ``<Event name=…>`` elements.
- The XML layout (``XReadStateSet``/``XReadTransRel``): ``<Alphabet>`` with
  ``<Event>`` elements, ``<StateSet>`` with ``<State id= name=>`` (``<Initial/>``,
  ``<Marked/>``) and ``<Consecutive from= to=/>``, ``<TransitionRelation>`` with
  ``<Transition x1= event= x2=/>`` (a transition listed twice is an error); each
  section is found by ``ReadBegin``, searching once more from the start of
  ``<Generator>`` (so the sections may come in any order).
- The older ``<cGenerator>`` layout: a ``<Controllable>`` section after
  ``</Generator>`` (also inside ``<EventAttributes>``).

The large native sections are first offered to the fast path of :mod:`.gen_build`,
which reads plain text a column at a time with the same result and hands back
(:class:`~.gen_build.Fallback`) whatever it cannot decide.

References
----------
- T. Moor, K. Schmidt et al., libFAUDES reference, "CoreFaudes - Generators"
  (``cfl_generator.cpp``: ``DoRead``, ``ReadStates``, ``ReadStateSet``, ``ReadTransRel``,
  ``XReadStateSet``, ``XReadTransRel``; ``cfl_nameset.cpp``; ``cfl_attributes.cpp``:
  ``AttributeCFlags``), https://fgdes.tf.fau.de/faudes
"""

from __future__ import annotations

from ...errors import FormatError
from ..flat import FlatGenerator
from .gen_build import MAX_STATES, Fallback, GenBuilder, Introducing, bulk_state_set, bulk_states, bulk_transrel
from .gen_tokens import Mark, Token, TokenReader, bare_kind

__all__ = ["MAX_STATES", "parse_text", "parse_text_by_token"]

_ORDER = "the native sections come in the order <Alphabet>, <States>, <TransRel>, <InitStates>, <MarkedStates>"


class _Bulk:
    """The column-at-a-time readers of :mod:`.gen_build` offered the large native sections
    first; each declines (False or None) what it cannot decide, or raises :class:`Fallback`."""

    states = staticmethod(bulk_states)
    transrel = staticmethod(bulk_transrel)
    state_set = staticmethod(bulk_state_set)


def parse_text(text: str, where: str = "<string>", *, raw: bytes | None = None) -> FlatGenerator:
    """The generator of the first ``<Generator>`` section of libFAUDES token text
    (``raw``: the same text as Latin-1 bytes, when at hand): the large native sections a
    column at a time where :mod:`.gen_build` can, the rest (and everything, after a
    :class:`Fallback`) as :func:`parse_text_by_token` reads it, with the same result."""
    try:
        return _parse(text, where, raw, _Bulk())
    except Fallback:
        return _parse(text, where, raw, None)


def parse_text_by_token(text: str, where: str = "<string>", *, raw: bytes | None = None) -> FlatGenerator:
    """The generator of the first ``<Generator>`` section of libFAUDES token text, read token
    by token only: the reference reading that :func:`parse_text` equals (and slower on
    large sections)."""
    return _parse(text, where, raw, None)


def _parse(text: str, where: str, raw: bytes | None, bulk: _Bulk | None) -> FlatGenerator:
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
    broke = _native(r, b, bulk)
    if broke is not None:
        r.reset(start)
        b = GenBuilder(r)
        if native_name or not _find(r, "StateSet", start):
            if broke.kind == "end" and broke.text == "Generator":
                raise r.error(broke, "missing <TransRel> section", "TransRel")
            raise r.error(broke, f"expected <TransRel>, found {broke.show()} ({_ORDER})", broke.text)
        r.reset(start)
        name = btag.attrs.get("name", "generator")
        _read_xml(r, b, start)
    r.end("Generator")
    if parent == "cGenerator":
        try:
            _controllable_section(r, b)
        except FormatError:  # libFAUDES reads nothing after </Generator>: a bad tail is no error
            pass
    return b.build(name, lambda k: _locate(r, b, k))


# -- native layout ----------------------------------------------------------------------


def _native(r: TokenReader, b: GenBuilder, bulk: _Bulk | None) -> Token | None:
    """Read the native sections (the large ones offered to ``bulk`` first, when given); the
    token where ``<TransRel>`` was expected if absent."""
    if r.is_begin("Alphabet", "A"):
        _read_alphabet(r, b, r.peek().text)
    if r.is_begin("States", "S"):
        label = r.peek().text
        if not (bulk and bulk.states(r, b, label)):
            _states(r, b, label)
    t = r.peek()
    if t is None:
        raise r.error(len(r.text), "missing </Generator>", "Generator")
    if not r.is_begin("TransRel", "T"):
        return t
    if not (bulk and bulk.transrel(r, b, t.text)):
        _transrel(r, b, t.text)
    for labels, target in ((("InitStates", "I"), b.init), (("MarkedStates", "M"), b.marked)):
        if r.is_begin(*labels):
            label = r.peek().text
            found = bulk.state_set(r, b, label) if bulk else None
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
        r.get()
        if t.index is not None or t.is_string:
            out.append(_member(r, b, label, t))
            r.skip_attributes()
        elif t.kind == "begin" and t.text == "State":
            idx = _int_attr(t, "id") or b.by_name.get(t.attrs.get("name", ""))
            if idx is None or idx not in b.known:
                raise r.error(t, f"cannot find the state of {t.show()} {t.attrs}", t.attrs)
            out.append(idx)
            r.end("State")
        elif t.kind == "begin" and t.text == "Consecutive":
            out.extend(_member_range(r, b, t))
        else:
            raise r.error(t, f"unexpected {t.show()} in <{label}>", t.text)
    r.get()
    return out


def _member(r: TokenReader, b: GenBuilder, label: str, t: Token) -> int:
    """The state a token of a state set names, by index or name (no ``#index`` suffix)."""
    if t.index is None and "#" in t.name:
        raise r.error(t, f"index suffix not allowed in <{label}>: {t.name!r}", t.name)
    idx = t.index if t.index is not None else b.by_name.get(t.name)
    if idx is None or idx not in b.known:
        raise r.error(t, f"state {t.name!r} is not in the state set", t.name)
    return idx


def _member_range(r: TokenReader, b: GenBuilder, t: Token) -> range:
    """``<Consecutive> a b </Consecutive>`` or ``<Consecutive from= to=/>`` in a state set:
    states of the state set, read up to the end tag."""
    if r.is_end("Consecutive"):
        first, last = _int_attr(t, "from") or 0, _int_attr(t, "to") or 0
    else:
        t1, t2 = r.get(), r.get()
        first, last = t1.index or 0, t2.index or 0
    if first < 1 or last < first:
        raise r.error(t, f"invalid range of consecutive states {first}..{last}", (first, last))
    if last - first >= MAX_STATES or any(i not in b.known for i in range(first, last + 1)):
        raise r.error(t, f"range {first}..{last} is not in the state set", (first, last))
    r.end("Consecutive")
    return range(first, last + 1)


def _transrel(r: TokenReader, b: GenBuilder, label: str) -> None:
    """libFAUDES's ``ReadTransRel``: triples ``x1 event x2``, each followed by its attribute."""
    r.begin(label)
    b.trans_section = (r.pos, -1)
    intro = Introducing(events=not b.events)

    def state(t: Token) -> int | None:
        if t.index is not None:
            if t.index not in b.known and intro.by_index:
                b.add_state(t.index, None, t.pos)
                intro.by_name = False
            return t.index
        if t.is_string:
            idx = b.by_name.get(t.name)
            if idx is None and intro.by_name:
                idx = b.max_index + 1
                b.add_state(idx, t.name, t.pos)
                intro.by_index = False
            return idx
        raise r.error(t, f"incomplete transition before {t.show()} in <{label}>", t.text)

    while not r.is_end(label):
        t1 = r.get()
        x1 = state(t1)
        te = r.get()
        if not te.is_string:
            raise r.error(te, f"incomplete transition before {te.show()} in <{label}>", te.text)
        if te.name not in b.event_pos and intro.events:
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
    """The line of the ``k``-th transition (for error messages): of ``<TransRel>``, or the
    ``<Transition>`` element of the XML layout's ``<TransitionRelation>``."""
    if b.trans_section is None:
        return r.line_at(b.trans_pos[k])
    s = TokenReader(r.text, r.where)
    s.pos = b.trans_section[0]
    for _ in range(k):
        s.get(), s.get(), s.get()
        s.skip_attributes()
    t = s.peek()
    return s.line_at(t.pos if t is not None else s.pos)


# -- elements shared by the layouts, the XML layout, the <cGenerator> wrapper -----------


def _cflags(r: TokenReader) -> bool:
    """libFAUDES's ``AttributeCFlags::DoRead``: the controllable bit of an event attribute."""
    t = r.peek()
    if t is not None and t.is_hex:
        return bool(r.get().index & 0x01)
    if t is not None and t.kind == "option":
        text = r.get().text
        return "C" in text and "c" not in text
    controllable = False
    while r.is_begin("Flags", "Controllable", "Observable", "Forcible", "Preemptible"):
        u = r.get()
        value = _int_attr(u, "value")
        if u.text == "Flags" and value is not None:
            controllable = bool(value & 0x01)
        elif u.text == "Controllable":
            controllable = value is None or value != 0
        r.end(u.text)
    return controllable


def _int_attr(t: Token, key: str) -> int | None:
    if key not in t.attrs:
        return None
    kind, value = bare_kind(t.attrs[key])
    return value if kind in ("integer", "integer16", "boolean") else None


def _read_alphabet(r: TokenReader, b: GenBuilder, label: str) -> None:
    """libFAUDES's ``NameSet::DoRead``: names (each with its attribute) or ``<Event>`` elements."""
    r.begin(label)
    while not r.is_end(label):
        t = r.peek()
        if t is None:
            raise r.error(len(r.text), f"missing </{label}>", label)
        if t.is_string:
            r.get()
            controllable = _cflags(r)
            r.skip_attributes()
            b.add_event(t.name, controllable, t.pos)
        elif t.kind == "begin" and t.text == "Event":
            r.get()
            controllable = _cflags(r)
            r.end("Event")
            b.add_event(t.attrs.get("name", ""), controllable, t.pos)
        else:
            raise r.error(t, f"unexpected {t.show()} in <{label}>", t.text)
    r.get()


def _find(r: TokenReader, label: str, start: Mark) -> bool:
    """libFAUDES's ``ReadBegin`` inside ``<Generator>``: the next ``<label>`` at this
    level, searching once more from the section's start when the section ends."""
    level, here = len(r.stack), r.mark()
    for _ in range(2):
        while True:
            t = r.peek()
            if t is None:
                return False
            if len(r.stack) == level and t.kind == "begin" and t.text == label:
                return True
            if len(r.stack) == level and t.kind == "end":
                break
            r.get()
        r.reset(start)
        if start[0] >= here[0]:
            return False
    return False


def _read_xml(r: TokenReader, b: GenBuilder, start: Mark) -> None:
    """The XML layout of ``XWrite()``: ``<Alphabet>`` with ``<Event>`` elements,
    ``<StateSet>`` with ``<State id= name=>`` (``<Initial/>``, ``<Marked/>``) and
    ``<Consecutive from= to=/>``, ``<TransitionRelation>`` with ``<Transition x1= event= x2=/>``."""
    if not _find(r, "Alphabet", start):
        raise r.error(r.pos, "missing <Alphabet> section", "Alphabet")
    _read_alphabet(r, b, "Alphabet")
    _find(r, "StateSet", start)
    _xml_states(r, b)
    if not _find(r, "TransitionRelation", start):
        raise r.error(r.pos, "missing <TransitionRelation> section", "TransitionRelation")
    _xml_transitions(r, b)


def _xml_states(r: TokenReader, b: GenBuilder) -> None:
    """``XReadStateSet``: ``<StateSet>`` of ``<State>`` and ``<Consecutive>`` elements."""
    r.begin("StateSet")
    while not r.is_end("StateSet"):
        t = r.get()
        if t.kind == "begin" and t.text == "Consecutive":
            first, last = _int_attr(t, "from") or 0, _int_attr(t, "to") or 0
            if first < 1 or last < first:
                raise r.error(t, f"invalid range of consecutive states {first}..{last}", (first, last))
            b.add_range(first, last, t.pos)
            r.end("Consecutive")
        elif t.kind == "begin" and t.text == "State":
            idx = _int_attr(t, "id") or b.by_name.get(t.attrs.get("name", ""))
            if not idx:
                raise r.error(t, f"<State> needs a positive integer id, got {t.attrs.get('id')!r}", t.attrs)
            b.add_state(idx, t.attrs.get("name") or None, t.pos)
            while r.is_begin("Initial", "Marked"):
                u = r.get()
                if _int_attr(u, "value") != 0:
                    (b.init.append if u.text == "Initial" else b.marked.append)(idx)
                r.end(u.text)
            r.end("State")
        elif t.kind == "begin":
            r.end(t.text)
    r.get()


def _xml_transitions(r: TokenReader, b: GenBuilder) -> None:
    """``XReadTransRel``: ``<TransitionRelation>`` of ``<Transition x1= event= x2=/>``
    (a transition listed twice is an error)."""
    r.begin("TransitionRelation")
    seen = set()
    while not r.is_end("TransitionRelation"):
        t = r.get()
        if t.kind != "begin":
            continue
        r.end(t.text)
        if t.text != "Transition":
            continue
        ends = [_int_attr(t, k) or b.by_name.get(t.attrs.get(k, "")) for k in ("x1", "x2")]
        ev = b.event_pos.get(t.attrs.get("event", ""))
        if None in ends or ev is None or any(x not in b.known for x in ends):
            raise r.error(t, f"invalid transition {t.attrs}", t.attrs)
        if (ends[0], ev, ends[1]) in seen:
            raise r.error(t, f"transition {t.attrs} appears twice", t.attrs)
        seen.add((ends[0], ev, ends[1]))
        b.x1.append(ends[0])
        b.ev.append(ev)
        b.x2.append(ends[1])
        b.trans_pos.append(t.pos)
    r.get()


def _controllable_section(r: TokenReader, b: GenBuilder) -> None:
    """The older ``<cGenerator>`` layout: ``<Controllable> names </Controllable>`` after
    ``</Generator>`` (also inside ``<EventAttributes>``) marks those events of the
    alphabet controllable (other names are ignored)."""
    level = len(r.stack)
    while len(r.stack) >= level:
        t = r.peek()
        if t is None or (t.kind == "end" and len(r.stack) == level):
            return
        r.get()
        if t.kind == "begin" and t.text == "Controllable":
            while not r.is_end("Controllable"):
                u = r.get()
                if u.kind == "begin":
                    r.end(u.text)
                    continue
                if u.is_string and u.name in b.events:  # (libFAUDES reads none of this section)
                    b.events[u.name] = True
            r.get()
