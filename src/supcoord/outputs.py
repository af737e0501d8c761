"""Safe output files: checked before the work, written atomically, never over an input.

Every file supcoord writes (plans, supervisors, figures, reports) goes through here:

- :func:`check_output` refuses, before any work is done, an output path that names one
  of the inputs (the same file, also through links), a symbolic link (writing through
  it would replace a file elsewhere), a directory, FIFO or device, or a file in a
  directory that is missing or not writable;
- :func:`atomic_write_text` / :func:`atomic_write_bytes` / :func:`atomic_output` write to
  a temporary file in the target directory and rename it into place (``os.replace``,
  atomic on POSIX and Windows), so a full disk or an interrupt leaves the old file (or
  nothing), never a truncated one; a failure names the file.

Refusals are :class:`~supcoord.errors.InputError` whose message names the option (or
what the file is for) and the path (the command line prints one line and exits 2).
"""

from __future__ import annotations

import contextlib
import os
import stat
import tempfile
from pathlib import Path
from typing import Iterable, Iterator

from .errors import InputError

__all__ = ["check_output", "atomic_output", "atomic_write_text", "atomic_write_bytes"]


def _same_file(a: Path, b: Path) -> bool:
    try:
        return a.exists() and b.exists() and os.path.samefile(a, b)
    except OSError:
        return False


def check_output(path: str | os.PathLike, inputs: Iterable[str | os.PathLike] = (), what: str = "output") -> Path:
    """``path`` as a :class:`Path` if supcoord may write it; otherwise a one-line :class:`InputError`.

    ``inputs`` are the files the same run reads: writing over one of them is refused,
    also when the two names differ (links, ``./``, another spelling of the path).
    """
    if not isinstance(path, (str, os.PathLike)) or str(path) == "":
        raise InputError(f"{what} must be a file name, got {path!r}", value=path)
    p = Path(path)
    name = str(path)
    if p.is_symlink():
        raise InputError(f"{what}: {name!r} is a symbolic link; give the path of the file itself", value=name)
    if p.exists():
        mode = p.stat().st_mode
        if stat.S_ISDIR(mode):
            raise InputError(f"{what}: {name!r} is a directory, not a file name", value=name)
        if not stat.S_ISREG(mode):
            raise InputError(f"{what}: {name!r} is not a regular file (a FIFO, socket or device); refusing to "
                             "write it", value=name)
    for source in inputs:
        src = Path(source)
        if _same_file(p, src) or (not p.exists() and p.resolve() == src.resolve()):
            raise InputError(f"{what}: {name!r} is also an input of this run ({source}); choose another file name",
                             value=name)
    parent = p.resolve().parent
    if not parent.is_dir():
        raise InputError(f"{what}: directory {str(p.parent)!r} does not exist", value=name)
    if not os.access(parent, os.W_OK | os.X_OK):
        raise InputError(f"{what}: directory {str(p.parent)!r} is not writable", value=name)
    if p.exists() and not os.access(p, os.W_OK):
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
def atomic_output(path: str | os.PathLike, suffix: str | None = None) -> Iterator[Path]:
    """Yield a temporary path in ``path``'s directory; on success rename it to ``path``.

    For writers that want a file name (matplotlib's ``savefig``, GIF writers): they write
    the temporary file, which replaces ``path`` only when the block ends without an
    exception; otherwise it is removed.  ``suffix`` (default: ``path``'s) keeps format
    detection by extension working.
    """
    p = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{p.name}.", suffix=suffix if suffix is not None else p.suffix,
                               dir=p.resolve().parent)
    os.close(fd)
    try:
        yield Path(tmp)
        # a temporary file is private (0600); the result gets the mode a plain open() would give
        os.chmod(tmp, stat.S_IMODE(p.stat().st_mode) if p.exists() else 0o666 & ~_umask())
        os.replace(tmp, p)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def atomic_write_bytes(path: str | os.PathLike, data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically (module docstring); errors name the file."""
    p = Path(path)
    try:
        with atomic_output(p) as tmp:
            with open(tmp, "wb") as f:
                f.write(data)
                f.flush()
                os.fsync(f.fileno())
    except OSError as exc:
        raise InputError(f"cannot write: {exc.strerror or exc}", value=str(path), where=str(path)) from exc
    return p


def atomic_write_text(path: str | os.PathLike, text: str, encoding: str = "utf-8") -> Path:
    """Write ``text`` to ``path`` atomically (module docstring); errors name the file."""
    return atomic_write_bytes(path, text.encode(encoding))
