"""Where and with what code a case ran: the code version, the machine, its CPU and load.

- :func:`code_version`: the installed package's version, plus the git commit
  (``+g<12 hex digits>``, ``.dirty`` with uncommitted changes) when the package is
  imported from a git checkout; the version is part of a case's key, so results of
  another version are not taken for done;
- :func:`machine`: the host name; :func:`cpu_model`: the CPU's model name
  (``/proc/cpuinfo``), with the number of CPUs; :func:`load`: the one-minute load average.
"""

from __future__ import annotations

import functools
import os
import platform
import socket
import subprocess
from importlib import metadata
from pathlib import Path

__all__ = ["code_version", "cpu_model", "load", "machine", "memory_mb"]


@functools.lru_cache(maxsize=1)
def code_version() -> str:
    """``0.2.0+g3dfed15c0a12`` (checkout, clean), ``…\u200b.dirty`` (changed), ``0.2.0`` (installed)."""
    try:
        version = metadata.version("supcoord")
    except metadata.PackageNotFoundError:  # pragma: no cover (always installed in practice)
        version = "unknown"
    here = Path(__file__).resolve().parent
    root = next((p for p in here.parents if (p / ".git").exists()), None)
    if root is None or "site-packages" in here.parts:
        return version
    try:
        commit = subprocess.run(["git", "-C", str(root), "rev-parse", "--short=12", "HEAD"], capture_output=True,
                                text=True, timeout=10, check=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", str(root), "status", "--porcelain", "--untracked-files=no", "--", "src"],
                               capture_output=True, text=True, timeout=10, check=True).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return version
    return f"{version}+g{commit}" + (".dirty" if dirty else "")


def machine() -> str:
    return socket.gethostname() or platform.node() or "unknown"


@functools.lru_cache(maxsize=1)
def cpu_model() -> str:
    """``Intel(R) Xeon(R) CPU @ 2.20GHz × 2`` (model name and the number of CPUs)."""
    model = platform.processor() or platform.machine() or "unknown CPU"
    try:
        with open("/proc/cpuinfo", encoding="utf-8", errors="replace") as f:
            model = next(line.split(":", 1)[1].strip() for line in f if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    return f"{model} × {os.cpu_count()}"


def load() -> float | None:
    try:
        return round(os.getloadavg()[0], 2)
    except OSError:  # pragma: no cover (not on Linux)
        return None


def memory_mb() -> float | None:
    """The machine's physical memory in MB."""
    try:
        return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES") / 2**20
    except (ValueError, OSError, AttributeError):  # pragma: no cover
        return None
