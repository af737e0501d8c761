"""Exact model counting in C: CUDD's arbitrary-precision ``Cudd_ApaCountMinterm``.

``|{a ∈ {0,1}^care : u(a)}|`` for a BDD ``u`` whose support lies in ``care`` is
``ApaCount(u, |care|)``: CUDD counts the minterms of ``u`` regarded as a function of
``n ≥ |support(u)|`` variables, starting from ``2^n`` at the constant one and halving
at each node on the way up (``count(f) = (count(f_hi) + count(f_lo)) / 2``, the
complement edge as ``2^n − count``), in base-2^32 digits: every intermediate value is an
integer, so the result is exact.

``dd.cudd`` (0.6) wraps ``Cudd_CountMinterm`` only, whose ``double`` is exact below
2^53 and overflows beyond 2^1024; it does not expose the manager or node pointers
either.  :func:`apa_counter` reads them from the Cython objects' C layout (``BDD``:
``PyObject_HEAD``, vtable, ``DdManager *``; ``Function``: ``PyObject_HEAD``, vtable,
``__weakref__``, ``BDD *``, ``DdManager *``, ``DdNode *``) and *validates* that layout
on a probe node: the ``BDD *`` field must be the Python object ``u.bdd``, the node
pointer must match ``int(u)`` (``dd``'s documented ``pointer + 2`` encoding) for a
plain and a complemented node, the two manager fields must agree, and the count of
the probe must equal the pure-Python count.  Any mismatch (another ``dd`` build or
version) disables the fast path and :func:`supcoord.bdd.counting.exact_count`
(a Python walk of the DAG, ~4 µs per node) is used instead.  The tests assert that
both paths agree and that the fast path is active with ``dd`` 0.6.0.

References
----------
- F. Somenzi, CUDD: CU Decision Diagram Package, release 3.0 (``cuddApa.c``).
"""

from __future__ import annotations

import ctypes
from typing import Any, Callable, Sequence

__all__ = ["apa_counter", "live_node_reader", "manager_pointer"]

_BDD_MANAGER = 24  # offsetof(struct __pyx_obj_2dd_4cudd_BDD, manager) on 64-bit CPython
_FN_BDD, _FN_MANAGER, _FN_NODE = 32, 40, 48  # offsets in struct __pyx_obj_2dd_4cudd_Function


def _pointer(obj: Any, offset: int) -> int:
    return ctypes.c_void_p.from_address(id(obj) + offset).value or 0


def manager_pointer(bdd: Any) -> int:
    """The ``DdManager *`` of a ``dd.cudd.BDD``, read from its C layout (module
    docstring; 0 for a manager without one).  Only for a ``dd.cudd`` manager."""
    return _pointer(bdd, _BDD_MANAGER)


def _library(module: Any):
    lib = ctypes.CDLL(module.__file__)
    count = lib.Cudd_ApaCountMinterm
    count.restype = ctypes.POINTER(ctypes.c_uint32)
    count.argtypes = [ctypes.c_void_p, ctypes.c_void_p, ctypes.c_int, ctypes.POINTER(ctypes.c_int)]
    free = lib.Cudd_FreeApaNumber
    free.restype = None
    free.argtypes = [ctypes.POINTER(ctypes.c_uint32)]
    keys, dead = lib.Cudd_ReadKeys, lib.Cudd_ReadDead
    for fn in (keys, dead):
        fn.restype = ctypes.c_uint
        fn.argtypes = [ctypes.c_void_p]
    return count, free, (keys, dead)


def live_node_reader(bdd: Any, counter: Callable[[Any, int], int] | None, module: Any) -> Callable[[], int] | None:
    """``keys − dead`` of ``bdd``'s manager (``Cudd_ReadKeys``, ``Cudd_ReadDead``): what
    ``dd``'s ``statistics()["n_nodes"]`` reports, without the dozen other statistics
    that make that call cost milliseconds; only once :func:`apa_counter` has validated
    the layout (``counter`` not ``None``)."""
    if counter is None:
        return None
    _, _, (keys, dead) = _library(module)
    manager = manager_pointer(bdd)
    return lambda: int(keys(manager)) - int(dead(manager))


def apa_counter(bdd: Any, module: Any, reference: Callable[[Any, Any, Sequence[str]], int]) -> Callable[[Any, int], int] | None:
    """A function ``count(u, n_care)`` counting ``u`` exactly over ``n_care`` care bits
    (``u``'s support must lie in them) with CUDD's C code, or ``None`` when the backend
    is not ``dd.cudd``, no variable is declared yet (nothing to probe) or the layout
    check fails.  ``reference`` is the pure-Python counter the probe is checked against."""
    try:
        if ctypes.sizeof(ctypes.c_void_p) != 8 or not module.__name__.endswith("cudd") or not bdd.vars:
            return None
        if type(bdd).__basicsize__ < _BDD_MANAGER + 8 or type(bdd.true).__basicsize__ < _FN_NODE + 8:
            return None
        return _validated(bdd, module, reference)
    except (AttributeError, OSError, ValueError, TypeError):  # no such symbol, library or layout
        return None


def _validated(bdd: Any, module: Any, reference) -> Callable[[Any, int], int] | None:
    count_fn, free_fn, _ = _library(module)
    manager = manager_pointer(bdd)
    if not manager:
        return None

    def node_of(u: Any) -> int:
        return _pointer(u, _FN_NODE)

    def count(u: Any, n_care: int) -> int:
        if _pointer(u, _FN_MANAGER) != manager:
            raise ValueError("count: the BDD belongs to another manager")
        if u == bdd.false:
            return 0
        if u == bdd.true:
            return 1 << n_care
        digits = ctypes.c_int()
        number = count_fn(manager, node_of(u), n_care, ctypes.byref(digits))
        if not number:
            raise MemoryError("CUDD could not allocate an arbitrary-precision count")
        try:
            value = 0
            for i in range(digits.value):  # most significant digit first
                value = (value << 32) | number[i]
        finally:
            free_fn(number)
        return value

    # validate the layout on a probe: a plain node and its complement, pointers and counts
    care = sorted(bdd.vars, key=bdd.level_of_var)[:3]
    u = bdd.var(care[0])
    for extra in care[1:]:
        u = u | ~bdd.var(extra)
    for f in (u, ~u):
        if _pointer(f, _FN_BDD) != id(f.bdd) or _pointer(f, _FN_MANAGER) != manager:
            return None
        if node_of(f) != int(f) - 2:  # dd.cudd: int(u) = pointer + 2
            return None
        if count(f, len(care)) != reference(bdd, f, care):
            return None
    return count
