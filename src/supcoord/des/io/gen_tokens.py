"""libFAUDES token text: the tokens of a ``.gen`` file and a cursor that reads them as
libFAUDES's ``TokenReader`` does.

A token is a begin tag ``<Label a="v">`` (XML attributes allowed; ``<Label/>`` is a
begin and an end), an end tag ``</Label>``, a string (``"quoted"``, ``'quoted'`` or
bare) or an option ``+…+``.  ``%`` starts a comment running to the end of the line
(between tokens only); ``&lt; &gt; &amp; &quot; &apos;`` are decoded in names;
``<?xml…?>``, ``<!DOCTYPE…>`` and ``<!-- … -->`` are skipped and
``<![CDATA[…]]>`` is a quoted string.  Binary (base64) tokens are not supported.

A bare string also has libFAUDES's numeric reading (``Token::InterpretNumber``, as
the libFAUDES 2.34 binaries behave): decimal digits (also ``1.5``, read as 1) are an
*integer*, ``0x…`` a hexadecimal *integer16*, ``true``/``false`` a *boolean* (1/0),
a negative number a *float*; everything else, and every quoted string, is a
*string*.  The readers use these kinds as libFAUDES does: an integer where a state is
expected is a state index, and after an element the tokens that are neither strings
nor integers are its attribute (``AttrType::Skip``: ``0x01``, ``+C+``, ``true``, a
section ``<Tag>…</Tag>``).  :func:`valid_symbol` is libFAUDES's rule for the names
of events and states (``SymbolTable::ValidSymbol``).  Errors raise :class:`~supcoord.errors.FormatError` naming
the line; lines are counted only when an error needs one.

References
----------
- T. Moor, K. Schmidt et al., libFAUDES reference, "Token IO" (``cfl_token.cpp``,
  ``cfl_tokenreader.cpp``, ``cfl_types.cpp``) and ``cfl_symboltable.cpp``,
  https://fgdes.tf.fau.de/faudes
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from ...errors import FormatError

__all__ = ["IDX_MAX", "Mark", "Token", "TokenReader", "bare_kind", "tokenize", "valid_symbol"]

_DECIMAL_RE = re.compile(r"(\d*)(?:\.(\d*))?")
_HEX_RE = re.compile(r"0x([0-9a-fA-F]*)")
_NEGATIVE_RE = re.compile(r"-(\d*)(?:\.\d*)?")

_WORDS = frozenset(["true", "True", "false", "False", "inf"])
#: libFAUDES's ``Idx`` maximum, the value of ``inf``
IDX_MAX = 2**32 - 1


def bare_kind(text: str) -> tuple[str, int | None]:
    """libFAUDES's reading of a bare (unquoted) string: ``(kind, value)``.

    >>> [bare_kind(s) for s in ("12", "007", "0x0b", "true", "-3", "1.5", "a1")]
    [('integer', 12), ('integer', 7), ('integer16', 11), ('boolean', 1), ('float', None), ('integer', 1), ('string', None)]
    """
    c = text[:1]
    if c.isalpha() and text not in _WORDS:
        return "string", None
    if text.isdigit() and text.isascii():
        digits = text.lstrip("0")
        # beyond any index libFAUDES accepts; not converted (Python refuses 4,300+ digits)
        return "integer", int(digits or "0") if len(digits) <= 30 else 10**30
    if text in ("true", "True"):
        return "boolean", 1
    if text in ("false", "False"):
        return "boolean", 0
    if text == "inf":
        return "integer", IDX_MAX
    if text == "-inf":
        return "integer", -IDX_MAX
    m = _DECIMAL_RE.fullmatch(text)
    if m and (m.group(1) or m.group(2)):
        return "integer", int(m.group(1) or "0")
    m = _HEX_RE.fullmatch(text)
    if m:
        return "integer16", int(m.group(1) or "0", 16)
    m = _NEGATIVE_RE.fullmatch(text)
    if m and text.strip("-."):
        return "float", None
    return "string", None


_SYMBOL_RE = re.compile(r'[\x21\x24-\x7e]+')  # printable ASCII without blank, '"' (0x22) and '#' (0x23)


def valid_symbol(name: str) -> bool:
    """libFAUDES's ``SymbolTable::ValidSymbol``: printable ASCII, no blank, ``"`` or ``#``."""
    return _SYMBOL_RE.fullmatch(name) is not None


_ENTITIES = {"&amp;": "&", "&quot;": '"', "&apos;": "'", "&lt;": "<", "&gt;": ">"}
_ENTITY_RE = re.compile(r"&[^;\s&]*;")
_CTRL_RE = re.compile(r"[\x00-\x1f\x7f]+")
_SPACE_RE = re.compile(r"(?:[\x00-\x20\x7f]+|%[^\n\r]*[\n\r]?)*")
_BARE_RE = re.compile(r"[^\x00-\x20\x7f<>]+")
_DQ_RE = re.compile(r'"([^"<>]*)"')
_SQ_RE = re.compile(r"'([^'<>]*)'")
_OPT_RE = re.compile(r"\+([^+<>]*)\+")
_ATTR_RE = re.compile(r"""[\x00-\x20]*([^\x00-\x20=/>]+)[\x00-\x20]*=[\x00-\x20]*("[^"<>]*"|'[^'<>]*'|[^\x00-\x20"'<>/]+)""")
_TAG_RE = re.compile(r"[A-Za-z_:][^\x00-\x20/>]*")


@dataclass
class Token:
    """One libFAUDES token: ``begin``/``end`` markup, ``string`` (quoted or bare) or ``option``."""

    kind: str
    text: str
    pos: int
    quoted: bool = False
    attrs: dict[str, str] = field(default_factory=dict)
    _number: tuple[str, int | None] | None = field(default=None, repr=False, compare=False)

    def _kind(self) -> tuple[str, int | None]:
        if self._number is None:
            self._number = bare_kind(self.text) if self.kind == "string" and not self.quoted else (self.kind, None)
        return self._number

    @property
    def ftype(self) -> str:
        """libFAUDES's ``Token::Type()``: begin, end, option, string, integer, integer16, boolean, float."""
        return self._kind()[0]

    @property
    def is_string(self) -> bool:
        """libFAUDES's ``IsString()``: every string and option token."""
        return self.kind in ("string", "option")

    @property
    def index(self) -> int | None:
        """The integer of a bare token libFAUDES reads as one (``IsInteger()``), else ``None``."""
        kind, value = self._kind()
        return value if kind in ("integer", "integer16", "boolean") else None

    @property
    def name(self) -> str:
        """The string value (an option's text without its ``+`` signs)."""
        return self.text

    @property
    def is_hex(self) -> bool:
        return self._kind()[0] == "integer16"

    def show(self) -> str:
        if self.kind == "begin":
            return f"<{self.text}>"
        if self.kind == "end":
            return f"</{self.text}>"
        if self.kind == "option":
            return f"'+{self.text}+'"
        return repr(self.text)


def _decode(raw: str) -> str:
    if "&" not in raw and not _CTRL_RE.search(raw):
        return raw
    raw = _CTRL_RE.sub(" ", raw)
    return _ENTITY_RE.sub(lambda m: _ENTITIES.get(m.group(0), m.group(0)), raw)


#: a reader's position, to come back to: ``(pos, open sections, tokens read ahead)``
Mark = tuple[int, list[str], list[Token]]


class TokenReader:
    """A lazy cursor over libFAUDES token text, tracking nested sections as libFAUDES does."""

    def __init__(self, text: str, where: str = "<string>", raw: bytes | None = None):
        self.text, self.where = text, where
        #: the text as bytes, one per character (Latin-1), for the checks of the fast path in :mod:`.gen_build`
        self.raw = raw if raw is not None else text.encode("latin-1", errors="replace")
        self.pos = 0  # where the next token starts scanning
        self.stack: list[str] = []  # labels of the open sections
        self._peeked: list[Token] = []  # scanned, not yet consumed (an empty tag gives two)

    # -- positions and errors --------------------------------------------------

    def line_at(self, pos: int) -> int:
        return self.text.count("\n", 0, pos) + 1

    def error(self, where: int | Token, msg: str, value=None) -> FormatError:
        """A :class:`FormatError` at a token or text position: ``line N: msg``."""
        pos = where.pos if isinstance(where, Token) else where
        return FormatError(f"line {self.line_at(pos)}: {msg}", value=value if value is not None else msg,
                           where=self.where)

    def mark(self) -> Mark:
        return self.pos, list(self.stack), list(self._peeked)

    def reset(self, mark: Mark) -> None:
        self.pos, self.stack, self._peeked = mark[0], list(mark[1]), list(mark[2])

    # -- scanning ---------------------------------------------------------------

    def _scan(self) -> list[Token]:
        """The next token(s) at ``self.pos`` (``[]`` at the end of the text)."""
        text = self.text
        while True:
            i = _SPACE_RE.match(text, self.pos).end()
            self.pos = i
            if i >= len(text):
                return []
            c = text[i]
            if c == "<":
                out = self._markup(i)
                if out:
                    return out
                continue  # a comment, declaration or processing instruction
            if c == '"' or c == "'":
                m = (_DQ_RE if c == '"' else _SQ_RE).match(text, i)
                if m is None:
                    raise self.error(i, f"unterminated quoted name starting {text[i:i + 20]!r}")
                self.pos = m.end()
                return [Token("string", _decode(m.group(1)), i, quoted=True)]
            if c == "+":
                m = _OPT_RE.match(text, i)
                if m is None:
                    raise self.error(i, f"unterminated option starting {text[i:i + 20]!r}")
                self.pos = m.end()
                return [Token("option", m.group(1), i)]
            if c == ">":
                raise self.error(i, "stray '>'")
            if c == "=":
                raise self.error(i, "binary (base64) tokens are not supported in generator files")
            m = _BARE_RE.match(text, i)
            self.pos = m.end()
            return [Token("string", _decode(m.group(0)), i)]

    def _markup(self, i: int) -> list[Token]:
        """The construct ``<…>`` at ``text[i]``: tokens, or ``[]`` for one to skip."""
        text = self.text
        if text.startswith("<!--", i):
            j = text.find("-->", i + 4)
            if j < 0:
                raise self.error(i, "unterminated XML comment")
            self.pos = j + 3
            return []
        if text.startswith("<![CDATA[", i):
            j = text.find("]]>", i)
            if j < 0:
                raise self.error(i, "unterminated CDATA section")
            self.pos = j + 3
            return [Token("string", text[i + 9:j], i, quoted=True)]
        j = text.find(">", i)
        if j < 0 or "<" in text[i + 1:j]:
            raise self.error(i, f"unterminated markup {text[i:i + 20]!r}")
        self.pos = j + 1
        body = text[i + 1:j]
        if body[:1] in ("?", "!"):
            return []
        if body.startswith("/"):
            name = body[1:].rstrip()
            if not name or any(ch <= " " for ch in name):
                raise self.error(i, f"malformed end tag <{body}>")
            return [Token("end", name, i)]
        empty = body.endswith("/")
        if empty:
            body = body[:-1]
        m = _TAG_RE.match(body)
        if not m:
            raise self.error(i, f"malformed tag <{body}>")
        attrs: dict[str, str] = {}
        rest, pos = body[m.end():], 0
        while rest[pos:].strip():
            a = _ATTR_RE.match(rest, pos)
            if not a:
                raise self.error(i, f"malformed attribute in <{body}>")
            value = a.group(2)
            attrs[a.group(1)] = _decode(value[1:-1] if value[0] in "\"'" else value)
            pos = a.end()
        begin = Token("begin", m.group(0), i, attrs=attrs)
        return [begin, Token("end", m.group(0), i)] if empty else [begin]

    # -- the cursor -------------------------------------------------------------

    def peek(self) -> Token | None:
        if not self._peeked:
            self._peeked = self._scan()
        return self._peeked[0] if self._peeked else None

    def get(self) -> Token:
        t = self.peek()
        if t is None:
            raise self.error(len(self.text), "unexpected end of file")
        self._peeked.pop(0)
        if t.kind == "begin":
            self.stack.append(t.text)
        elif t.kind == "end":
            if not self.stack:
                raise self.error(t, f"unbalanced end tag {t.show()}", t.text)
            self.stack.pop()
        return t

    def is_end(self, label: str) -> bool:
        """libFAUDES's ``Eos(label)``."""
        t = self.peek()
        return t is not None and t.kind == "end" and t.text == label

    def is_begin(self, *labels: str) -> bool:
        t = self.peek()
        return t is not None and t.kind == "begin" and t.text in labels

    def begin(self, *labels: str) -> Token:
        t = self.peek()
        if t is None or t.kind != "begin" or t.text not in labels:
            found = "the end of the file" if t is None else t.show()
            raise self.error(len(self.text) if t is None else t, f"expected <{labels[0]}>, found {found}",
                             None if t is None else t.text)
        return self.get()

    def end(self, label: str) -> None:
        """libFAUDES's ``ReadEnd(label)``: skip to the end of the current section (text
        that is not markup is skipped as character data, see :meth:`skip_text`)."""
        level = len(self.stack)
        while True:
            if not self._peeked or self._peeked[0].kind not in ("begin", "end"):
                self.skip_text()
            t = self.peek()
            if t is None:
                raise self.error(len(self.text), f"missing </{label}>", label)
            if t.kind == "end" and t.text == label and len(self.stack) == level:
                self.get()
                return
            if t.kind == "end" and len(self.stack) == level:
                raise self.error(t, f"expected </{label}>, found {t.show()}", t.text)
            self.get()

    def skip_section(self) -> None:
        """Skip a begin tag and everything up to its matching end tag."""
        t = self.get()
        self.end(t.text)

    def skip_attributes(self) -> None:
        """libFAUDES's ``AttrType::Skip``: drop what follows an element up to the next
        string, integer, end tag or ``<Consecutive>`` (options, ``0x…``, booleans,
        negative numbers, foreign sections)."""
        while True:
            t = self.peek()
            if t is None or t.kind == "end" or (t.kind == "begin" and t.text == "Consecutive"):
                return
            if t.kind == "string" and t.ftype in ("string", "integer"):
                return
            if t.kind == "begin":
                self.skip_section()
            else:
                self.get()

    def seek_begin(self, label: str) -> Token:
        """libFAUDES's ``SeekBegin(label)``: the first ``<label>`` at any depth; text
        that is not markup is skipped, other sections are entered and left."""
        text, start = self.text, len(self.stack)
        self._peeked = []
        while True:
            self.skip_text()
            i = self.pos
            if i >= len(text):
                raise self.error(len(text), f"expected <{label}>, found no <{label}> section", label)
            tokens = self._markup(i)
            for t in tokens:
                if t.kind == "begin" and t.text == label:
                    self._peeked = tokens[tokens.index(t):]
                    return self.get()
                if t.kind == "end" and len(self.stack) <= start:
                    raise self.error(t, f"expected <{label}>, found {t.show()}", t.text)
                self._peeked = [t]
                self.get()

    def skip_text(self) -> None:
        """libFAUDES's ``ReadCharacterData``: drop a peeked string and the text up to the
        next ``<``; a ``%`` comment in that text must not hold ``<`` or ``>``."""
        self._peeked = [t for t in self._peeked if t.kind in ("begin", "end")]
        if self._peeked:
            return
        text, i = self.text, self.pos
        j = text.find("<", i)
        j = len(text) if j < 0 else j
        k = text.find("%", i, j)
        while k >= 0:
            eol = text.find("\n", k)
            eol = len(text) if eol < 0 else eol
            bad = min((x for x in (text.find("<", k, eol), text.find(">", k, eol)) if x >= 0), default=-1)
            if bad >= 0:
                raise self.error(bad, f"'{text[bad]}' in a '%' comment outside a section", text[bad])
            j = text.find("<", eol)
            j = len(text) if j < 0 else j
            k = text.find("%", eol, j)
        self.pos = j

    def section_text(self, label: str) -> tuple[int, int] | None:
        """``(start, end)`` of the text of the section that begins with the peeked
        ``<label>`` when that text holds no markup, else ``None``; nothing is consumed."""
        t = self.peek()
        if t is None or t.kind != "begin" or t.text != label or len(self._peeked) != 1:
            return None
        j = self.text.find("<", self.pos)
        if j < 0 or not self.text.startswith("</" + label, j):
            return None
        k = self.text.find(">", j)
        if k < 0 or self.text[j + 2:k].rstrip() != label:
            return None
        return self.pos, j

    def jump(self, pos: int, label: str) -> None:
        """Consume the peeked ``<label>`` and its text up to ``pos`` (``</label>`` is next)."""
        self.get()
        self.pos = pos
        self._peeked = []


def tokenize(text: str, where: str = "<string>") -> list[Token]:
    """Every token of ``text`` (for tests and tools; the readers scan lazily)."""
    r = TokenReader(text, where)
    out = []
    while True:
        batch = r._scan()
        if not batch:
            return out
        out.extend(batch)
