"""Bounded reading of the JSON files users give (PROBLEM.json, PLAN.json).

:func:`read_json` checks a file before and while reading it: a regular file, at most a
given size, UTF-8, JSON, no repeated key in an object, no integer past Python's limit; every
failure is one :class:`~supcoord.errors.InputError` or :class:`~supcoord.errors.FormatError`
naming the file.
"""

from __future__ import annotations

import json
import os
import stat
from pathlib import Path
from typing import Any

from ..errors import FormatError, InputError
from ..geometry.layout import _short

__all__ = ["read_json"]


def read_json(path: str | Path, what: str, max_bytes: int) -> Any:
    """Decode a JSON file, bounded: refused (one-line :class:`InputError`/:class:`FormatError`
    with ``where = path``) when missing, not a regular file, over ``max_bytes``, not UTF-8,
    not JSON, nested too deeply, or holding an integer too long to convert (Python's limit of
    4,300 digits)."""
    if not isinstance(path, (str, os.PathLike)):
        raise InputError(f"a {what} file name must be a string or a path, got {_short(path)}", value=path,
                         where="path")
    where = str(path)
    if len(where) > 200:
        where = where[:200] + "…"
    p = Path(path)
    try:
        st = os.stat(p)
    except (OSError, ValueError) as exc:  # missing, a name too long, a NUL byte, no permission
        text = "file not found" if isinstance(exc, FileNotFoundError) else \
            f"file cannot be opened: {getattr(exc, 'strerror', None) or exc}"
        raise InputError(f"{what} {text}", value=where, where=where) from None
    if not stat.S_ISREG(st.st_mode):
        raise InputError(f"is not a regular file (a directory, FIFO or device), not a {what} file", value=where,
                         where=where)
    size = st.st_size
    if size > max_bytes:
        raise InputError(f"{what} file is {size} bytes, more than the {max_bytes} a {what} may have", value=size,
                         where=where)
    try:
        with open(p, "rb") as f:
            raw = f.read(max_bytes + 1)
        if len(raw) > max_bytes:
            raise InputError(f"{what} file is more than {max_bytes} bytes", value=len(raw), where=where)
        return json.loads(raw.decode("utf-8"), object_pairs_hook=_unique_keys)
    except InputError as exc:  # a repeated key (_unique_keys), a file that grew: with the file's name
        raise type(exc)(exc.message, value=exc.value, where=where) from None
    except UnicodeDecodeError as exc:
        raise FormatError(f"not a UTF-8 text file ({exc.reason})", value=where, where=where) from None
    except json.JSONDecodeError as exc:
        raise FormatError(f"not valid JSON: {exc.msg} at line {exc.lineno} column {exc.colno}",
                          value=where, where=where) from None
    except RecursionError:
        raise FormatError("JSON nested too deeply", value=where, where=where) from None
    except ValueError as exc:  # e.g. "Exceeds the limit (4300 digits) for integer string conversion"
        raise FormatError(f"a number is out of range: {str(exc).splitlines()[0]}", value=where, where=where) from None
    except OSError as exc:
        raise InputError(f"cannot be read: {exc.strerror or exc}", value=where, where=where) from None


def _unique_keys(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    """A JSON object whose keys are distinct (``json.loads`` would keep the last of a repeated
    key silently); :class:`FormatError` naming the repeated key."""
    out: dict[str, Any] = {}
    for key, value in pairs:
        if key in out:
            raise FormatError(f"the key {_short(key)} appears twice in one JSON object", value=key)
        out[key] = value
    return out
