"""Reading and writing generators by file suffix.

========  ======  ======  =========================================
suffix    read    write   format
========  ======  ======  =========================================
``.gen``  yes     yes     libFAUDES token format (:mod:`.gen_file`)
``.json`` yes     yes     ``docs/formats.md`` JSON (:mod:`.json_file`)
``.dot``  no      yes     Graphviz (:mod:`.dot_file`)
========  ======  ======  =========================================

Unknown suffixes raise :class:`~supcoord.errors.FormatError` naming the file.
:func:`read_generator_flat` and :func:`write_generator_flat` do the same with
:class:`~supcoord.des.flat.FlatGenerator` arrays (``.gen`` files are read and written
without building dictionaries: the route for generators of millions of states).
"""

from __future__ import annotations

import os
from pathlib import Path

from ...errors import FormatError, InputError
from ..flat import FlatGenerator, from_generator
from ..generator import Generator
from .dot_file import DOT_MAX_STATES, write_dot
from .gen_file import read_gen, read_gen_flat, write_gen, write_gen_flat
from .json_file import read_json, write_json

__all__ = ["read_generator", "write_generator", "read_generator_flat", "write_generator_flat"]

_READERS = {".gen": read_gen, ".json": read_json}
_WRITERS = {".gen": write_gen, ".json": write_json, ".dot": write_dot}


def _suffix(path: str | os.PathLike, table: dict, what: str) -> str:
    suffix = Path(path).suffix.lower()
    if suffix not in table:
        raise FormatError(f"unknown generator file type {suffix or '(none)'!r}; use {what}", value=suffix,
                          where=os.fspath(path))
    return suffix


def read_generator_flat(path: str | os.PathLike) -> FlatGenerator:
    """Read a ``.gen`` or ``.json`` generator as a :class:`FlatGenerator`."""
    if _suffix(path, _READERS, ".gen or .json") == ".gen":
        return read_gen_flat(path)
    return from_generator(read_json(path))


def write_generator_flat(fg: FlatGenerator, path: str | os.PathLike) -> None:
    """Write a :class:`FlatGenerator` to a ``.gen``, ``.json`` or ``.dot`` file (by suffix)."""
    suffix = _suffix(path, _WRITERS, ".gen, .json or .dot")
    if suffix == ".gen":
        write_gen_flat(fg, path)
    elif suffix == ".dot" and fg.n_states > DOT_MAX_STATES:
        raise InputError(f"{fg.name!r} has {fg.n_states} states; DOT export is for at most {DOT_MAX_STATES}",
                         value=fg.n_states, where=os.fspath(path))
    else:
        _WRITERS[Path(path).suffix.lower()](fg.to_generator(), path)


def read_generator(path: str | os.PathLike) -> Generator:
    """Read a generator from a ``.gen`` or ``.json`` file."""
    suffix = Path(path).suffix.lower()
    reader = _READERS.get(suffix)
    if reader is None:
        raise FormatError(
            f"unknown generator file type {suffix or '(none)'!r}; use .gen or .json", value=suffix, where=os.fspath(path)
        )
    return reader(path)


def write_generator(g: Generator, path: str | os.PathLike) -> None:
    """Write ``g`` to a ``.gen``, ``.json`` or ``.dot`` file (chosen by suffix)."""
    suffix = Path(path).suffix.lower()
    writer = _WRITERS.get(suffix)
    if writer is None:
        raise FormatError(
            f"unknown generator file type {suffix or '(none)'!r}; use .gen, .json or .dot",
            value=suffix, where=os.fspath(path),
        )
    writer(g, path)
