"""libFAUDES ``.gen`` files: every layout libFAUDES's token reader reads as a generator.

The first ``<Generator>`` section of the file is read, at any depth: what precedes it
(stray tokens, comments, a ``<cGenerator>`` or ``<aGenerator>`` wrapper, foreign
sections) and what follows its end are skipped, except the ``<Controllable>`` section
of a ``<cGenerator>`` wrapper (directly or inside ``<EventAttributes>``), which marks
its events controllable.  Inside, in this order:

- the name: ``<Generator name="N" ftype="System">`` or a string ``<Generator> "N"``;
- ``<Alphabet>`` (or ``<A>``), optional: event names, each followed by its attribute:
  an option with ``C`` sets the controllable flag and one with ``c`` clears it
  (``+C+``, ``+CF+`` controllable; ``+c+``, ``+Cc+`` not), hexadecimal flags set it
  with bit ``0x01`` (``0x0b`` controllable, ``0x0a`` not), as does ``<Controllable/>``
  in an ``<Event name=…>`` element; no attribute: uncontrollable;
- ``<States>`` (or ``<S>``), optional: indices, names (a name's index is its
  position, or the ``name#index`` suffix: all names or none), ``<Consecutive> a b
  </Consecutive>`` ranges, each element followed by an attribute libFAUDES skips
  (``0x01``, ``+P+``, ``true``, a negative number, a ``<Section>…</Section>``);
- ``<TransRel>`` (or ``<T>``), required: triples ``x1 event x2`` (states by index or
  name, each triple followed by an attribute as above).  States it uses that
  ``<States>`` lacks are added: by index until it adds a named one, by name (the
  next index) until it adds an indexed one; events only when there was no alphabet;
- ``<InitStates>`` (``<I>``) and ``<MarkedStates>`` (``<M>``), optional, in this
  order: states of the state set by index, name or range;
- anything after these up to ``</Generator>`` is skipped.

A bare token that is a number is an index where a state is expected (``007`` is 7,
``true`` is 1); quoted tokens are names.  ``%`` starts a comment to the end of the
line (in the text libFAUDES skips, before ``<Generator>`` and in skipped sections, it
must not hold ``<`` or ``>``); ``"…"`` and ``'…'`` quote
names; ``&lt; &gt; &amp; &quot; &apos;`` are decoded; ``<?xml…?>``, ``<!DOCTYPE…>``
and ``<!-- … -->`` are skipped.  When ``<TransRel>`` is not where it belongs and the
name was no string token, the XML layout of ``faudes.Generator.XWrite()`` is read
(``<Alphabet>`` with ``<Event>`` elements, ``<StateSet>`` with ``<State id= name=>``,
``<Initial/>``, ``<Marked/>``, ``<TransitionRelation>`` with ``<Transition x1= event=
x2=/>``, in any order).

The result is what libFAUDES reads, with these differences: supcoord generators are
deterministic (two initial states, or two transitions on one event from one state,
raise :class:`~supcoord.errors.NondeterminismError`); a file without an initial state
describes the empty language and reads as the empty generator (0 states, alphabet
kept); a state index 0 (libFAUDES's "no state") is refused; a file whose native
layout breaks (sections out of order, stray tokens between them), which libFAUDES
reads as an empty generator, is refused naming the token where it broke.  Everything
libFAUDES refuses is refused: :class:`~supcoord.errors.FormatError` with ``where`` =
the file and a message naming the line and the token.

States are numbered ``0…n-1`` in the order they appear (the state set, then the states
the transitions add); names are kept, and unnamed states are named by their libFAUDES
index as soon as some state is named or the indices are not ``1…n`` in order.  An
empty alphabet is legal here (the synthesis layer rejects it).

The writer (:mod:`.gen_write`) writes what ``faudes.System.Write()`` writes.  The
reader is :mod:`.gen_tokens` (text to tokens, libFAUDES's cursor and its rules for
numbers and symbols), :mod:`.gen_parser` (the sections of both layouts) and
:mod:`.gen_build` (the generator in libFAUDES's index space, and the fast path that
fills it from large plain sections a column at a time).

References
----------
- T. Moor, K. Schmidt et al., libFAUDES reference, "CoreFaudes - Generators" and
  "Token IO" (``cfl_generator.cpp``, ``cfl_tokenreader.cpp``, ``cfl_token.cpp``,
  ``cfl_attributes.cpp``), https://fgdes.tf.fau.de/faudes
"""

from __future__ import annotations

import os

from ..flat import FlatGenerator
from ..generator import Generator
from .files import read_bytes
from .gen_parser import MAX_STATES, parse_text  # noqa: F401  (MAX_STATES: importable from here too)
from .gen_tokens import Token, TokenReader, tokenize, valid_symbol  # noqa: F401  (Token: likewise)
from .gen_write import NAMES_IN_TRANSITIONS_UP_TO, format_gen, write_gen, write_gen_flat  # noqa: F401

__all__ = ["read_gen", "write_gen", "parse_gen", "format_gen", "valid_symbol", "read_gen_flat", "write_gen_flat"]


def parse_gen(text: str, where: str = "<string>") -> Generator:
    """Parse the text of a ``.gen`` file into a :class:`Generator`."""
    return parse_text(text, where).to_generator()


def read_gen(path: str | os.PathLike) -> Generator:
    """Read a libFAUDES ``.gen`` file (see the module docstring for the accepted forms)."""
    return read_gen_flat(path).to_generator()


def read_gen_flat(path: str | os.PathLike) -> FlatGenerator:
    """Read a libFAUDES ``.gen`` file into a :class:`~supcoord.des.flat.FlatGenerator`
    (the same generator as :func:`read_gen`, held as arrays)."""
    raw = read_bytes(path)
    return parse_text(raw.decode("latin-1"), os.fspath(path), raw=raw)
