"""Reading a generator file's bytes, with the project's error for an unreadable file,
and writing a file atomically (a temporary file in the target directory, then
:func:`os.replace`), so that a reader never sees half a file."""

from __future__ import annotations

import os
from collections.abc import Iterable

from ...errors import FormatError
from ...outputs import atomic_output

__all__ = ["read_bytes", "write_atomic"]


def read_bytes(path: str | os.PathLike) -> bytes:
    """The contents of ``path``; :class:`FormatError` (``where`` = the path) if it cannot be read."""
    where = os.fspath(path)
    try:
        with open(path, "rb") as f:
            return f.read()
    except OSError as exc:
        raise FormatError(f"cannot read generator file: {exc.strerror or exc}", value=where, where=where) from None


def write_atomic(path: str | os.PathLike, chunks: Iterable[str | bytes], encoding: str = "utf-8") -> None:
    """Write the text ``chunks`` (strings, encoded with ``encoding``, or bytes as they
    are) to ``path`` through a temporary file in the same directory, moved into place
    once complete (:func:`supcoord.outputs.atomic_output`); :class:`InputError` naming the
    path if it cannot be written
    (also for a file with other hard links, or a symbolic link)."""
    with atomic_output(path) as tmp:
        with open(tmp, "wb") as f:
            for chunk in chunks:
                f.write(chunk if isinstance(chunk, bytes) else chunk.encode(encoding))

