"""libFAUDES's reading of bare tokens and its rule for symbols.

- :func:`bare_kind`: what ``Token::InterpretNumber`` makes of an unquoted string, as
  the libFAUDES 2.34 binaries behave: decimal digits (also ``1.5``, read as 1) are an
  *integer*, ``0x…`` a hexadecimal *integer16*, ``true``/``false`` a *boolean* (1/0),
  ``inf`` the largest index, a negative number a *float*; everything else a *string*.
- :func:`valid_symbol`: ``SymbolTable::ValidSymbol``, the names of events and states.

References
----------
- T. Moor, K. Schmidt et al., libFAUDES reference, "Token IO" (``cfl_token.cpp``) and
  ``cfl_symboltable.cpp``, https://fgdes.tf.fau.de/faudes
"""

from __future__ import annotations

import re

__all__ = ["IDX_MAX", "bare_kind", "valid_symbol"]

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
