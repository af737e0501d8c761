"""Elements and layouts of libFAUDES ``.gen`` files shared by :mod:`.gen_parser`: the
alphabet with its controllability flags, the XML layout, the ``<cGenerator>`` wrapper.

- :func:`read_alphabet` and :func:`cflags`: ``NameSet::DoRead`` and
  ``AttributeCFlags::DoRead``: names, each with its flags (an option with ``C`` sets
  the controllable bit, one with ``c`` clears it; ``0x…`` sets it from bit ``0x01``;
  ``<Controllable value=…/>``), or ``<Event name=…>`` elements;
- :func:`find`: libFAUDES's ``ReadBegin`` inside a section: the next ``<label>`` at
  this level, searching once more from the section's start when the section ends (so
  the XML sections may come in any order);
- :func:`read_xml`: ``XReadStateSet``/``XReadTransRel``: ``<Alphabet>`` with
  ``<Event>`` elements, ``<StateSet>`` with ``<State id= name=>`` (``<Initial/>``,
  ``<Marked/>``) and ``<Consecutive from= to=/>``, ``<TransitionRelation>`` with
  ``<Transition x1= event= x2=/>`` (a transition listed twice is an error);
- :func:`controllable_section`: the older ``<cGenerator>`` layout's
  ``<Controllable>`` section after ``</Generator>``.

References
----------
- T. Moor, K. Schmidt et al., libFAUDES reference, "CoreFaudes - Generators"
  (``cfl_generator.cpp``: ``XReadStateSet``, ``XReadTransRel``; ``cfl_nameset.cpp``;
  ``cfl_attributes.cpp``: ``AttributeCFlags``), https://fgdes.tf.fau.de/faudes
"""

from __future__ import annotations

from .gen_build import GenBuilder
from .gen_tokens import Token, TokenReader, bare_kind

__all__ = ["cflags", "int_attr", "read_alphabet", "find", "read_xml", "controllable_section"]


def cflags(r: TokenReader) -> bool:
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
        value = int_attr(u, "value")
        if u.text == "Flags" and value is not None:
            controllable = bool(value & 0x01)
        elif u.text == "Controllable":
            controllable = value is None or value != 0
        r.end(u.text)
    return controllable


def int_attr(t: Token, key: str) -> int | None:
    if key not in t.attrs:
        return None
    kind, value = bare_kind(t.attrs[key])
    return value if kind in ("integer", "integer16", "boolean") else None


def read_alphabet(r: TokenReader, b: GenBuilder, label: str) -> None:
    """libFAUDES's ``NameSet::DoRead``: names (each with its attribute) or ``<Event>`` elements."""
    r.begin(label)
    while not r.is_end(label):
        t = r.peek()
        if t is None:
            raise r.error(len(r.text), f"missing </{label}>", label)
        if t.is_string:
            r.get()
            controllable = cflags(r)
            r.skip_attributes()
            b.add_event(t.name, controllable, t.pos)
        elif t.kind == "begin" and t.text == "Event":
            r.get()
            controllable = cflags(r)
            r.end("Event")
            b.add_event(t.attrs.get("name", ""), controllable, t.pos)
        else:
            raise r.error(t, f"unexpected {t.show()} in <{label}>", t.text)
    r.get()


def find(r: TokenReader, label: str, start) -> bool:
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


def read_xml(r: TokenReader, b: GenBuilder, start) -> None:
    """The XML layout of ``XWrite()``: ``<Alphabet>`` with ``<Event>`` elements,
    ``<StateSet>`` with ``<State id= name=>`` (``<Initial/>``, ``<Marked/>``) and
    ``<Consecutive from= to=/>``, ``<TransitionRelation>`` with ``<Transition x1= event= x2=/>``."""
    if not find(r, "Alphabet", start):
        raise r.error(r.pos, "missing <Alphabet> section", "Alphabet")
    read_alphabet(r, b, "Alphabet")
    find(r, "StateSet", start)
    r.begin("StateSet")
    while not r.is_end("StateSet"):
        t = r.get()
        if t.kind == "begin" and t.text == "Consecutive":
            first, last = int_attr(t, "from") or 0, int_attr(t, "to") or 0
            if first < 1 or last < first:
                raise r.error(t, f"invalid range of consecutive states {first}..{last}", (first, last))
            b.add_range(first, last, t.pos)
            r.end("Consecutive")
        elif t.kind == "begin" and t.text == "State":
            idx = int_attr(t, "id") or b.by_name.get(t.attrs.get("name", ""))
            if not idx:
                raise r.error(t, f"<State> needs a positive integer id, got {t.attrs.get('id')!r}", t.attrs)
            b.add_state(idx, t.attrs.get("name") or None, t.pos)
            while r.is_begin("Initial", "Marked"):
                u = r.get()
                if int_attr(u, "value") != 0:
                    (b.init.append if u.text == "Initial" else b.marked.append)(idx)
                r.end(u.text)
            r.end("State")
        elif t.kind == "begin":
            r.end(t.text)
    r.get()
    if not find(r, "TransitionRelation", start):
        raise r.error(r.pos, "missing <TransitionRelation> section", "TransitionRelation")
    r.begin("TransitionRelation")
    seen = set()
    while not r.is_end("TransitionRelation"):
        t = r.get()
        if t.kind != "begin":
            continue
        r.end(t.text)
        if t.text != "Transition":
            continue
        ends = [int_attr(t, k) or b.by_name.get(t.attrs.get(k, "")) for k in ("x1", "x2")]
        ev = b.event_pos.get(t.attrs.get("event", ""))
        if None in ends or ev is None or any(x not in b.known for x in ends):
            raise r.error(t, f"invalid transition {t.attrs}", t.attrs)
        if (ends[0], ev, ends[1]) in seen:
            raise r.error(t, f"transition {t.attrs} appears twice", t.attrs)
        seen.add((ends[0], ev, ends[1]))
        b.x1.append(ends[0])
        b.ev.append(ev)
        b.x2.append(ends[1])
    r.get()


def controllable_section(r: TokenReader, b: GenBuilder) -> None:
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
