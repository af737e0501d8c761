"""Safe output files: checked before the work, written atomically, never over an input.

Every file supcoord writes (plans, problems, generators, supervisors, figures, CSV and
Parquet exports, study plots) goes through :func:`atomic_output`, and the results
database is opened only after :func:`check_output`:

- :func:`check_output` refuses an output path that is one of the inputs of the same run
  or its database (compared by device and inode, so another spelling or a link of the
  same file is caught), a symbolic link or a file with other hard links (writing through
  either would change a file elsewhere), a directory, FIFO or device, or a file in a
  directory that is missing or not writable.  Commands call it before any work, so a
  refusal costs nothing;
- :func:`atomic_output` checks again, lets the writer fill a temporary file in the target
  directory, flushes it to disk (``fsync``) and renames it into place (``os.replace``,
  atomic on POSIX and Windows).  A full disk (``ENOSPC``, or ``EFBIG`` past a file-size
  limit such as ``ulimit -f``: ``SIGXFSZ`` is ignored while it writes), a read-only file
  system or an interrupt leaves the old file (or none), never a truncated one, and the
  temporary file is removed.  :func:`atomic_write_text` / :func:`atomic_write_bytes` are
  its shorthands for data held in memory.

Every refusal or failure is an :class:`~supcoord.errors.InputError` whose one-line message
names the option (or what the file is for) and the path; the command line prints it and
exits 2.
"""

from __future__ import annotations

import contextlib
import os
import signal
import stat
import tempfile
import threading
from pathlib import Path
from typing import Iterable, Iterator

from .errors import InputError

__all__ = ["check_output", "atomic_output", "atomic_write_text", "atomic_write_bytes"]


def _identity(path: str | os.PathLike) -> tuple[int, int] | None:
    """``(device, inode)`` of the file ``path`` names (links followed), or None if there is none."""
    try:
        st = os.stat(path)
    except (OSError, ValueError):
        return None
    return st.st_dev, st.st_ino


def _name(path: str | os.PathLike) -> str:
    text = os.fspath(path)
    return text if len(text) <= 200 else text[:200] + "…"


def check_output(path: str | os.PathLike, inputs: Iterable[str | os.PathLike | None] = (),
                 what: str = "output") -> Path:
    """``path`` as a :class:`Path` if supcoord may write it; otherwise a one-line :class:`InputError`.

    Parameters
    ----------
    path : str or os.PathLike
        The file to be written.
    inputs : iterable of str or os.PathLike
        The files the same run reads, and its database: writing over one of them is
        refused, also when the two names differ (hard or symbolic links, ``./``).
    what : str
        What the file is for (an option such as ``"--out"``), used in messages.

    Returns
    -------
    Path
        ``path``.
    """
    if not isinstance(path, (str, os.PathLike)) or not os.fspath(path) or "\0" in os.fspath(path):
        raise InputError(f"{what} must be a file name, got {path!r:.80}", value=path)
    p = Path(path)
    name = _name(path)
    try:
        link = p.is_symlink()
        st = None if link else (os.stat(p) if p.exists() else None)
        parent = p.absolute().parent
        parent_ok = parent.is_dir()
    except (OSError, ValueError) as exc:
        raise InputError(f"{what}: cannot use {name!r}: {getattr(exc, 'strerror', None) or exc}", value=name) from None
    if link:
        raise InputError(f"{what}: {name!r} is a symbolic link; give the path of the file itself", value=name)
    if st is not None:
        if stat.S_ISDIR(st.st_mode):
            raise InputError(f"{what}: {name!r} is a directory, not a file name", value=name)
        if not stat.S_ISREG(st.st_mode):
            raise InputError(f"{what}: {name!r} is not a regular file (a FIFO, socket or device); refusing to "
                             "write it", value=name)
        if st.st_nlink > 1:
            raise InputError(f"{what}: {name!r} has {st.st_nlink - 1} other hard link(s); writing it would change "
                             "another file too; choose another file name", value=name)
    mine = None if st is None else (st.st_dev, st.st_ino)
    for source in inputs:
        if source is None:
            continue
        same = (mine is not None and _identity(source) == mine) or (
            mine is None and Path(source).absolute().resolve() == p.absolute().resolve())
        if same:
            raise InputError(f"{what}: {name!r} is also an input of this run ({_name(source)}); choose another "
                             "file name", value=name)
    if not parent_ok:
        raise InputError(f"{what}: directory {_name(p.parent)!r} does not exist", value=name)
    if not os.access(parent, os.W_OK | os.X_OK):
        raise InputError(f"{what}: directory {_name(p.parent)!r} is not writable", value=name)
    if st is not None and not os.access(p, os.W_OK):
        raise InputError(f"{what}: {name!r} exists and is not writable", value=name)
    return p


def _umask() -> int:
    """The process's umask, read without changing it (``/proc/self/status``; else 022)."""
    try:
        with open("/proc/self/status", encoding="ascii") as f:
            for line in f:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except (OSError, ValueError, IndexError):
        pass
    return 0o022


@contextlib.contextmanager
def _file_size_errors() -> Iterator[None]:
    """Past a file-size limit, a write fails with ``EFBIG`` instead of killing the process
    (``SIGXFSZ``), so the temporary file is removed and the failure reported.  Only the main
    thread may change signal handlers; elsewhere the default stays."""
    sig = getattr(signal, "SIGXFSZ", None)
    if sig is None or threading.current_thread() is not threading.main_thread():
        yield
        return
    old = signal.signal(sig, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(sig, old)


def _fsync(path: str | os.PathLike, directory: bool = False) -> None:
    fd = os.open(path, os.O_RDONLY | (getattr(os, "O_DIRECTORY", 0) if directory else 0))
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


@contextlib.contextmanager
def atomic_output(path: str | os.PathLike, suffix: str | None = None, *,
                  inputs: Iterable[str | os.PathLike | None] = (), what: str = "output") -> Iterator[Path]:
    """Yield a temporary path in ``path``'s directory; on success it replaces ``path``.

    The one way supcoord writes a file (module docstring).  The writer fills the
    temporary file by name (``savefig``, an image's ``save``, ``open(tmp, "wb")``); when
    the block ends without an exception the file is flushed to disk and renamed to
    ``path``, otherwise removed.

    Parameters
    ----------
    path : str or os.PathLike
        The file to write (checked with :func:`check_output`).
    suffix : str, optional
        The temporary file's suffix (default: ``path``'s), so writers that choose the
        format by extension keep working.
    inputs : iterable of str or os.PathLike
        The files the run reads and its database, which ``path`` must not be.
    what : str
        What the file is for (an option such as ``"--out"``), used in messages.

    Yields
    ------
    Path
        The temporary file to write.

    Raises
    ------
    InputError
        ``path`` may not be written (:func:`check_output`), or writing failed (full
        disk, file-size limit, read-only file system): one line naming the file.
    """
    inputs = list(inputs)
    p = check_output(path, inputs, what)
    name = _name(path)
    tmp: str | None = None
    try:
        with _file_size_errors():
            fd, tmp = tempfile.mkstemp(prefix=f".{p.name[:100]}.", suffix=(p.suffix if suffix is None else suffix)[:20],
                                       dir=p.absolute().parent)
            os.close(fd)
            yield Path(tmp)
            _fsync(tmp)
            check_output(p, inputs, what)  # nothing has become a link or an input meanwhile
            # a temporary file is private (0600); the result gets the mode a plain open() would give
            os.chmod(tmp, stat.S_IMODE(p.stat().st_mode) if p.exists() else 0o666 & ~_umask())
            os.replace(tmp, p)
            tmp = None
            with contextlib.suppress(OSError):  # the rename itself on disk (not every system allows it)
                _fsync(p.absolute().parent, directory=True)
    except OSError as exc:
        raise InputError(f"{what}: cannot write {name!r}: {exc.strerror or exc}; nothing written",
                         value=name) from None
    finally:
        if tmp is not None:
            with contextlib.suppress(OSError):
                os.unlink(tmp)


def atomic_write_bytes(path: str | os.PathLike, data: bytes, *, inputs: Iterable[str | os.PathLike | None] = (),
                       what: str = "output") -> Path:
    """Write ``data`` to ``path`` with :func:`atomic_output` (same checks and errors); returns ``path``."""
    with atomic_output(path, inputs=inputs, what=what) as tmp:
        with open(tmp, "wb") as f:
            f.write(data)
    return Path(path)


def atomic_write_text(path: str | os.PathLike, text: str, encoding: str = "utf-8", *,
                      inputs: Iterable[str | os.PathLike | None] = (), what: str = "output") -> Path:
    """Write ``text`` to ``path`` with :func:`atomic_output` (same checks and errors); returns ``path``."""
    return atomic_write_bytes(path, text.encode(encoding), inputs=inputs, what=what)
