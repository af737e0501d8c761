"""CUDD's operation counts, and a bound on the work of one manager.

CUDD counts the lookups of its computed table (``Cudd_ReadCacheLookUps``): every
recursive step of an operation (``And``, ``AndAbstract``, ``ITE``, …) that is not a
terminal case looks its operands up once, so the count measures the *work* of the
operations, independent of the machine and its load.  :func:`cache_lookups` reads it;
:class:`WorkLimit` makes every operation of a manager give up (return ``NULL``, which
``dd`` raises as ``ValueError``) once the manager's count has grown by more than a given
number of lookups since the limit was set.  It uses CUDD's termination callback
(``Cudd_RegisterTerminationCallback``), which CUDD polls from inside its recursions
(every few thousand cache misses), so even a single operation that would run for
minutes is stopped within a few thousand lookups of the limit.

``dd.cudd`` (0.6) exposes neither the callback nor the manager pointer: the pointer is
read from the ``BDD`` object's C layout, which :mod:`.cudd_count` validates on first
use; where it is not validated (another ``dd`` build, the pure-Python backend) the
functions here report ``None`` and the caller does without a bound.

References
----------
- F. Somenzi, CUDD: CU Decision Diagram Package, release 3.0 (``cuddAPI.c``:
  ``Cudd_ReadCacheLookUps``, ``Cudd_RegisterTerminationCallback``).
"""

from __future__ import annotations

import ctypes
from functools import lru_cache
from typing import Any

from .cudd_count import manager_pointer

__all__ = ["cache_lookups", "WorkLimit"]

_CALLBACK = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_void_p)


@lru_cache(maxsize=None)
def _functions(path: str):
    lib = ctypes.CDLL(path)
    lookups = lib.Cudd_ReadCacheLookUps
    lookups.restype, lookups.argtypes = ctypes.c_double, [ctypes.c_void_p]
    register = lib.Cudd_RegisterTerminationCallback
    register.restype, register.argtypes = None, [ctypes.c_void_p, _CALLBACK, ctypes.c_void_p]
    unregister = lib.Cudd_UnregisterTerminationCallback
    unregister.restype, unregister.argtypes = None, [ctypes.c_void_p]
    return lookups, register, unregister


def _manager(bdd: Any, module: Any) -> int:
    return manager_pointer(bdd) if module.__name__.endswith("cudd") else 0


def cache_lookups(bdd: Any, module: Any) -> int | None:
    """The computed-table lookups of ``bdd``'s CUDD manager so far (CUDD's count of
    recursive operation steps), or ``None`` without a validated CUDD layout.  Call only
    after :attr:`supcoord.bdd.Context.fast_count` is true for a manager of this module."""
    manager = _manager(bdd, module)
    if not manager:
        return None
    return int(_functions(module.__file__)[0](manager))


class WorkLimit:
    """``with WorkLimit(bdd, module, lookups):`` every operation of ``bdd``'s manager
    gives up once the manager has taken more than ``lookups`` further computed-table
    lookups; :attr:`exceeded` then says so.  The manager's results after that are
    ``NULL`` (``dd`` raises ``ValueError``): use a manager that can be thrown away.
    ``lookups=None`` sets no limit (and touches nothing)."""

    def __init__(self, bdd: Any, module: Any, lookups: int | None) -> None:
        self.bdd, self.manager = bdd, (_manager(bdd, module) if lookups is not None else 0)
        self.functions = _functions(module.__file__) if self.manager else None
        self.limit = lookups
        self.exceeded = False
        self._start = 0
        self._callback = None

    def used(self) -> int:
        """Lookups taken since the limit was set (0 without a CUDD layout)."""
        if not self.manager:
            return 0
        return int(self.functions[0](self.manager)) - self._start

    def __enter__(self) -> WorkLimit:
        if not self.manager:
            return self
        read, register, _ = self.functions
        self._start = int(read(self.manager))
        stop_at = self._start + self.limit

        def give_up(_arg: Any) -> int:
            if read(self.manager) > stop_at:
                self.exceeded = True
                return 1
            return 0

        self._callback = _CALLBACK(give_up)  # kept alive while registered
        register(self.manager, self._callback, None)
        return self

    def __exit__(self, *exc: object) -> None:
        if self.manager:
            self.functions[2](self.manager)
        self._callback = None
